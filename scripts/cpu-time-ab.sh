#!/usr/bin/env bash
# Compares the CPU time of `sercon` builds, alternating (docs/performance.md, sessions 32 and
# 33: on this shared VM `perf stat -e task-clock` over 10 simulated seconds, 20-40 rounds in
# both orders, separates 1 % differences where wall-clock figures do not).
# Usage: scripts/cpu-time-ab.sh SCENARIO SIM_MS ROUNDS BINARY...
# Runs `perf stat -e task-clock BINARY bench --json --scenario SCENARIO --sim-ms SIM_MS` for
# each binary in turn, ROUNDS times, and prints each binary's least and median CPU time (the
# whole process: set-up and run) with the real-time factors they give.
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: $0 SCENARIO SIM_MS ROUNDS BINARY..." >&2
  exit 2
fi
command -v perf >/dev/null || { echo "perf is needed (apt-get install -y linux-perf)" >&2; exit 2; }
sc=$1 ms=$2 rounds=$3
shift 3
results=$(mktemp)
trap 'rm -f "$results"' EXIT
for _ in $(seq "$rounds"); do
  for b in "$@"; do
    t=$(perf stat -x, -e task-clock "$b" bench --json --scenario "$sc" --sim-ms "$ms" 2>&1 >/dev/null |
      awk -F, '/task-clock/ {print $1}')
    if [ -z "$t" ]; then
      echo "no task-clock figure from $b (is perf allowed here?)" >&2
      exit 1
    fi
    echo "$b $t" >>"$results"
  done
done
python3 - "$results" "$ms" <<'PY'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    b, v = line.rsplit(" ", 1)
    runs.setdefault(b, []).append(float(v))
ms = float(sys.argv[2])
for b, v in runs.items():
    lo, med = min(v), statistics.median(v)
    print(f"{b}: least {lo:.2f} ms, median {med:.2f} ms CPU (≈ {ms / lo:.1f}× / {ms / med:.1f}×)")
PY
