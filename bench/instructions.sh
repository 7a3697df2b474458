#!/usr/bin/env bash
# Instructions executed by two builds (or programs) on the same input, counted by valgrind's
# callgrind: a comparison that the machine's noise does not reach (wall times on this 2-core
# virtual machine vary by 20-40% from hour to hour, and `bench/ab.sh` needs 20+ interleaved
# rounds to see a 5% change; instruction counts repeat to a few parts in a million). It does
# not see what instructions cost (cache misses, page faults, the two threads' balance): a
# change it finds must still be confirmed in wall time with `bench/ab.sh`.
#
#   bench/instructions.sh PROGRAM_A PROGRAM_B ARGS...
#   e.g. bench/instructions.sh /tmp/objmodel-before target/release/objmodel learn /tmp/tum/box_1000000.tum --json
#
# Prints the total for each program and the functions whose own instructions (exclusive,
# summed over their inlined code) differ most. Needs valgrind (apt-get install valgrind) and
# python3; about 7 s per program for 10^6 poses. A function renamed between the builds shows as
# one removed and one added.
set -euo pipefail
A=$1; B=$2; shift 2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for x in A B; do
  bin=$A; [ "$x" = B ] && bin=$B
  valgrind --tool=callgrind --callgrind-out-file="$dir/$x.out" "$bin" "$@" >/dev/null 2>"$dir/$x.log" || {
    echo "callgrind failed on $bin:"; tail -5 "$dir/$x.log"; exit 1; }
  callgrind_annotate --auto=no --threshold=100 "$dir/$x.out" > "$dir/$x.txt"
done
python3 - "$dir/A.txt" "$dir/B.txt" "$A" "$B" <<'EOF'
import re, sys
from collections import Counter
def functions(path):
    """Exclusive instructions per function name (file and object dropped)."""
    c = Counter()
    for line in open(path):
        m = re.match(r"\s*([\d,]+) \(\s*[\d.]+%\)\s+(.*)", line)
        if not m or "PROGRAM TOTALS" in line:
            continue
        name = re.sub(r" \[.*\]$", "", m.group(2))
        c[name.split(":", 1)[1] if ":" in name else name] += int(m.group(1).replace(",", ""))
    return c
a, b = functions(sys.argv[1]), functions(sys.argv[2])
ta, tb = sum(a.values()), sum(b.values())
print(f"A {sys.argv[3]}: {ta / 1e6:.1f} M instructions")
print(f"B {sys.argv[4]}: {tb / 1e6:.1f} M instructions ({100 * (tb - ta) / ta:+.1f}%)")
print("\n| function | A (M) | B (M) | B - A (M) |\n|---|---|---|---|")
keys = sorted(set(a) | set(b), key=lambda k: -abs(b[k] - a[k]))
for k in keys[:15]:
    if abs(b[k] - a[k]) < 0.5e6:
        break
    print(f"| `{k[:90]}` | {a[k] / 1e6:.1f} | {b[k] / 1e6:.1f} | {(b[k] - a[k]) / 1e6:+.1f} |")
EOF
