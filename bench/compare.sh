#!/usr/bin/env bash
# Side-by-side benchmark of `objmodel learn` against the numpy baseline of the same screw
# pipeline (../shared/bench/screw_numpy.py), whole processes, on files from gen_tum.py.
#
#   bench/compare.sh [SIZES...]        default: 1000000 10000000
#
# Needs python3 with numpy, scipy (and pandas, which the baseline prefers for parsing).
# Writes bench/results.md. Timings are wall clock and peak RSS from /usr/bin/time.
set -euo pipefail
cd "$(dirname "$0")/.."
SHARED=${SHARED:-../shared/bench}
DATA=${DATA:-/tmp/tum}
SIZES=${*:-1000000 10000000}
REPS=${REPS:-3}
mkdir -p "$DATA"
cargo build --release -q -p objmodel-cli
BIN=target/release/objmodel

measure() { # prints "wall_s rss_mb" (median wall of $REPS runs, max RSS)
  local walls=() rss=0 out
  for _ in $(seq "$REPS"); do
    /usr/bin/time -o "$DATA/.time" -f "%e %M" "$@" >/dev/null 2>&1
    out=$(tail -1 "$DATA/.time")
    walls+=("${out% *}")
    local r=${out#* }; (( r > rss )) && rss=$r
  done
  local med; med=$(printf '%s\n' "${walls[@]}" | sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}')
  echo "$med $((rss / 1024))"
}

{
  echo "| poses | file MB | program | wall s | peak RSS MB | speed-up vs numpy |"
  echo "|---|---|---|---|---|---|"
  for n in $SIZES; do
    f="$DATA/box_$n.tum"
    [ -f "$f" ] || python3 "$SHARED/gen_tum.py" "$n" "$f"
    mb=$(du -m "$f" | cut -f1)
    read -r np_w np_m < <(measure python3 "$SHARED/screw_numpy.py" "$f" --json)
    read -r pa_w pa_m < <(measure "$BIN" learn "$f" --method paper --json)
    read -r ro_w ro_m < <(measure "$BIN" learn "$f" --json)
    echo "| $n | $mb | numpy baseline (screw_numpy.py) | $np_w | $np_m | 1.0 |"
    echo "| $n | $mb | objmodel learn --method paper | $pa_w | $pa_m | $(echo "$np_w / $pa_w" | bc -l | xargs printf '%.1f') |"
    echo "| $n | $mb | objmodel learn (robust, default) | $ro_w | $ro_m | $(echo "$np_w / $ro_w" | bc -l | xargs printf '%.1f') |"
  done
} | tee bench/results.md
