#!/usr/bin/env bash
# Interleaved wall-time comparison of two builds (or programs), for before/after measurements on
# a noisy machine: runs A and B alternately N times each and prints the minimum and median wall
# time (ms, from `date +%s%N`) of each. Every argument that is a file is read once before each
# run, so that it is in the page cache (this machine's cache drops large files within a minute).
#
#   bench/ab.sh N PROGRAM_A PROGRAM_B ARGS...
#   e.g. bench/ab.sh 21 /tmp/objmodel-before target/release/objmodel learn /tmp/tum/box_1000000.tum --json
set -euo pipefail
N=$1; A=$2; B=$3; shift 3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for _ in $(seq "$N"); do
  for x in A B; do
    bin=$A; [ "$x" = B ] && bin=$B
    for f in "$@"; do [ -f "$f" ] && cat "$f" >/dev/null; done
    t0=$(date +%s%N); "$bin" "$@" >/dev/null; t1=$(date +%s%N)
    echo $(( (t1 - t0) / 100000 )) >> "$dir/$x"
  done
done
for x in A B; do
  sort -n "$dir/$x" | awk -v x="$x" '{a[NR]=$1} END {printf "%s: min %.1f ms, median %.1f ms   ", x, a[1]/10, a[int((NR+1)/2)]/10}'
done
echo
