#!/usr/bin/env bash
# Side-by-side benchmark of `objmodel learn` against the numpy baseline of the same screw
# pipeline (../shared/bench/screw_numpy.py), whole processes, on files from gen_tum.py.
#
#   bench/compare.sh [SIZES...]        default: 1000000 10000000
#
# Needs python3 with numpy, scipy (and pandas, which the baseline prefers for parsing).
# Writes bench/results.md. Wall clock from `date +%s%N` around each run (ms resolution), CPU
# (user + sys) and peak RSS from /usr/bin/time. Each run starts with the input file read once
# (`cat > /dev/null`): this machine's page cache drops a third of a 100 MB file within half a
# minute (measured with `fincore`), and the baseline's numbers are for files in the cache.
set -euo pipefail
cd "$(dirname "$0")/.."
SHARED=${SHARED:-../shared/bench}
DATA=${DATA:-/tmp/tum}
SIZES=${*:-1000000 10000000}
REPS=${REPS:-3}
mkdir -p "$DATA"
cargo build --release -q -p objmodel-cli
BIN=target/release/objmodel

measure() { # measure FILE CMD...: prints "wall_s cpu_s rss_mb" (medians of $REPS runs of CMD,
  # FILE read into the page cache before each; CPU = user + sys; max RSS)
  local walls=() cpus=() rss=0 w u s r file=$1
  shift
  for _ in $(seq "$REPS"); do
    local t0 t1
    cat "$file" >/dev/null
    t0=$(date +%s%N)
    /usr/bin/time -o "$DATA/.time" -f "%e %U %S %M" "$@" >/dev/null 2>&1
    t1=$(date +%s%N)
    read -r w u s r < <(tail -1 "$DATA/.time")
    # Wall clock to the millisecond (GNU time's %e has 10 ms steps).
    w=$(echo "($t1 - $t0) / 1000000000" | bc -l | xargs printf "%.3f")
    walls+=("$w")
    cpus+=("$(echo "$u + $s" | bc -l | xargs printf "%.2f")")
    (( r > rss )) && rss=$r
  done
  median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'; }
  echo "$(median "${walls[@]}") $(median "${cpus[@]}") $((rss / 1024))"
}

{
  echo "| poses | file MB | program | wall s | CPU s | peak RSS MB | speed-up vs numpy (wall) |"
  echo "|---|---|---|---|---|---|---|"
  for n in $SIZES; do
    f="$DATA/box_$n.tum"
    [ -f "$f" ] || python3 "$SHARED/gen_tum.py" "$n" "$f"
    mb=$(du -m "$f" | cut -f1)
    read -r np_w np_c np_m < <(measure "$f" python3 "$SHARED/screw_numpy.py" "$f" --json)
    read -r pa_w pa_c pa_m < <(measure "$f" "$BIN" learn "$f" --method paper --json)
    read -r ro_w ro_c ro_m < <(measure "$f" "$BIN" learn "$f" --json)
    ratio() { echo "$np_w / $1" | bc -l | xargs printf '%.1f'; }
    echo "| $n | $mb | numpy baseline (screw_numpy.py) | $np_w | $np_c | $np_m | 1.0 |"
    echo "| $n | $mb | objmodel learn --method paper | $pa_w | $pa_c | $pa_m | $(ratio "$pa_w") |"
    echo "| $n | $mb | objmodel learn (robust, default) | $ro_w | $ro_c | $ro_m | $(ratio "$ro_w") |"
  done
} | tee bench/results.md
