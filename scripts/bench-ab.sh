#!/usr/bin/env bash
# Compares `sercon` builds side by side (docs/performance.md: this VM's speed changes within
# seconds, so only alternating, repeated runs say anything).
# Usage: scripts/bench-ab.sh [--cpu-time] SCENARIO SIM_MS ROUNDS BINARY...
# Runs `BINARY bench --json --scenario SCENARIO --sim-ms SIM_MS` for each binary in turn,
# ROUNDS times, and prints each binary's best and median real-time factor.
# --cpu-time: measures each run's CPU time instead (`perf stat -e task-clock`, the whole
# process: set-up and run) and prints the least and median; over 10 simulated seconds and
# 20-40 rounds in both orders it separates 1 % differences where wall figures on a shared VM
# do not (docs/performance.md, sessions 32 and 33).
# Every binary runs without `sercon bench`'s warm-up (`--warm-up-ms=0` where it has the
# option), so that builds before and after it do the same work.
set -euo pipefail
cpu=0
if [ "${1:-}" = --cpu-time ]; then
  cpu=1
  shift
  command -v perf >/dev/null || { echo "perf is needed (apt-get install -y linux-perf)" >&2; exit 2; }
fi
if [ $# -lt 4 ]; then
  echo "usage: $0 [--cpu-time] SCENARIO SIM_MS ROUNDS BINARY..." >&2
  exit 2
fi
sc=$1 ms=$2 rounds=$3
shift 3
results=$(mktemp)
trap 'rm -f "$results"' EXIT
# The same work from every binary: builds with `--warm-up-ms` (session 34 on) run without the
# extra warm-up, as the builds before it do (its wall time would count in CPU time, and its
# warm runs are not what an older build measures).
declare -A warm
for b in "$@"; do
  warm[$b]=""
  if "$b" bench --help 2>/dev/null | grep -q -- --warm-up-ms; then
    warm[$b]="--warm-up-ms=0"
  fi
done
for _ in $(seq "$rounds"); do
  for b in "$@"; do
    if [ "$cpu" = 1 ]; then
      v=$(perf stat -x, -e task-clock "$b" bench --json --scenario "$sc" --sim-ms "$ms" ${warm[$b]} 2>&1 >/dev/null |
        awk -F, '/task-clock/ {print $1}')
      [ -n "$v" ] || { echo "no task-clock figure from $b (is perf allowed here?)" >&2; exit 1; }
    else
      v=$("$b" bench --json --scenario "$sc" --sim-ms "$ms" ${warm[$b]} |
        python3 -c 'import sys, json; print(json.loads(sys.stdin.readline())["rtf"])')
    fi
    echo "$b $v" >>"$results"
  done
done
python3 - "$results" "$sc" "$ms" "$cpu" <<'PY'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    b, v = line.rsplit(" ", 1)
    runs.setdefault(b, []).append(float(v))
sc, ms, cpu = sys.argv[2], float(sys.argv[3]), sys.argv[4] == "1"
for b, v in runs.items():
    if cpu:
        lo, med = min(v), statistics.median(v)
        print(f"{sc} {b}: least {lo:.2f} ms median {med:.2f} ms CPU (≈ {ms / lo:.1f}x / {ms / med:.1f}x, {len(v)} runs)")
    else:
        print(f"{sc} {b}: best {max(v):.1f}x median {statistics.median(v):.1f}x ({len(v)} runs)")
PY
