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

# One timed run: `run FILE CMD...` prints "wall_s cpu_s rss_kb" (FILE read into the page cache
# first; CPU = user + sys).
run() {
  local file=$1 t0 t1 w u s r
  shift
  cat "$file" >/dev/null
  t0=$(date +%s%N)
  /usr/bin/time -o "$DATA/.time" -f "%e %U %S %M" "$@" >/dev/null 2>&1
  t1=$(date +%s%N)
  read -r w u s r < <(tail -1 "$DATA/.time")
  # Wall clock to the millisecond (GNU time's %e has 10 ms steps).
  echo "$(echo "($t1 - $t0) / 1000000000" | bc -l | xargs printf "%.3f") $(echo "$u + $s" | bc -l | xargs printf "%.2f") $r"
}

median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'; }

# The three programs take turns, REPS rounds (numpy, paper, robust, numpy, ...), so that a
# slow spell of the machine hits all of them; besides the ratio of the medians, the median of
# the rounds' own ratios (numpy's wall over objmodel's in the same round) is reported.
{
  echo "| poses | file MB | program | wall s | CPU s | peak RSS MB | speed-up vs numpy (wall) | median of per-round speed-ups |"
  echo "|---|---|---|---|---|---|---|---|"
  for n in $SIZES; do
    f="$DATA/box_$n.tum"
    [ -f "$f" ] || python3 "$SHARED/gen_tum.py" "$n" "$f"
    mb=$(du -m "$f" | cut -f1)
    declare -A wall=() cpu=() rss=([np]=0 [pa]=0 [ro]=0) per=()
    for i in $(seq "$REPS"); do
      for p in np pa ro; do
        case $p in
          np) cmd=(python3 "$SHARED/screw_numpy.py" "$f" --json) ;;
          pa) cmd=("$BIN" learn "$f" --method paper --json) ;;
          ro) cmd=("$BIN" learn "$f" --json) ;;
        esac
        read -r w c r < <(run "$f" "${cmd[@]}")
        wall[$p]+="$w " cpu[$p]+="$c "
        (( r > rss[$p] )) && rss[$p]=$r
        [ "$p" = np ] && np_round=$w
        [ "$p" != np ] && per[$p]+="$(echo "$np_round / $w" | bc -l | xargs printf '%.1f') "
      done
    done
    # shellcheck disable=SC2086
    for p in np pa ro; do
      eval "${p}_w=$(median ${wall[$p]}) ${p}_c=$(median ${cpu[$p]}) ${p}_m=$(( rss[$p] / 1024 ))"
    done
    ratio() { echo "$np_w / $1" | bc -l | xargs printf '%.1f'; }
    # shellcheck disable=SC2086,SC2154
    {
      echo "| $n | $mb | numpy baseline (screw_numpy.py) | $np_w | $np_c | $np_m | 1.0 | |"
      echo "| $n | $mb | objmodel learn --method paper | $pa_w | $pa_c | $pa_m | $(ratio "$pa_w") | $(median ${per[pa]}) |"
      echo "| $n | $mb | objmodel learn (robust, default) | $ro_w | $ro_c | $ro_m | $(ratio "$ro_w") | $(median ${per[ro]}) |"
    }
  done
} | tee bench/results.md
