#!/usr/bin/env bash
# Compares `sercon` builds side by side (docs/performance.md: this VM's speed changes within
# seconds, so only alternating, repeated runs say anything).
# Usage: scripts/bench-ab.sh SCENARIO SIM_MS ROUNDS BINARY...
# Runs `BINARY bench --json --scenario SCENARIO --sim-ms SIM_MS` for each binary in turn,
# ROUNDS times, and prints each binary's best and median real-time factor.
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: $0 SCENARIO SIM_MS ROUNDS BINARY..." >&2
  exit 2
fi
sc=$1 ms=$2 rounds=$3
shift 3
results=$(mktemp)
trap 'rm -f "$results"' EXIT
for _ in $(seq "$rounds"); do
  for b in "$@"; do
    rtf=$("$b" bench --json --scenario "$sc" --sim-ms "$ms" |
      python3 -c 'import sys, json; print(json.loads(sys.stdin.readline())["rtf"])')
    echo "$b $rtf" >>"$results"
  done
done
python3 - "$results" "$sc" <<'PY'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    b, v = line.rsplit(" ", 1)
    runs.setdefault(b, []).append(float(v))
for b, v in runs.items():
    print(f"{sys.argv[2]} {b}: best {max(v):.1f}x median {statistics.median(v):.1f}x ({len(v)} runs)")
PY
