#!/usr/bin/env bash
# Splits a ring-8 cycle's instructions into the slaves' chips, the master's chip and the
# simulation itself (callgrind inclusive costs of the `split-profile` build's role-named chip
# calls, crates/sercos-sim/src/sim/chip_calls.rs; docs/performance.md, session 28).
# Usage: scripts/chip-split.sh [SCENARIO] (default ring-8; any ring_profile scenario name)
# Builds `ring_profile` with the feature into ${SPLIT_TARGET_DIR:-target/split-profile}.
# The wrappers add a call per chip call (≈ +2 % on ring-8): compare shares, not totals,
# with scripts/instructions-per-cycle.sh.
set -euo pipefail
scenario=${1:-ring-8}
dir=${SPLIT_TARGET_DIR:-target/split-profile}
command -v valgrind >/dev/null || { echo "valgrind is needed (apt-get install -y valgrind)" >&2; exit 2; }
CARGO_TARGET_DIR=$dir cargo build -q --release -p sercos-sim --features split-profile --example ring_profile
bin=$dir/release/examples/ring_profile
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
case $scenario in
  ring-254*|ring-n128*) short=20; long=60 ;;
  *) short=500; long=1500 ;;
esac
valgrind --tool=callgrind --callgrind-out-file="$tmp/a" "$bin" "$scenario" "$short" >/dev/null 2>&1
valgrind --tool=callgrind --callgrind-out-file="$tmp/b" "$bin" "$scenario" "$long" >/dev/null 2>&1
here=$(dirname "$0")
python3 "$here/callgrind-per-cycle.py" inclusive "$tmp/a" "$tmp/b" $((long - short)) --top 400 |
  python3 -c '
import re, sys
cost = {}
for line in sys.stdin:
    m = re.match(r"\s*(-?\d+)\s+(.*)$", line)
    if m:
        cost[m.group(2).strip()] = max(cost.get(m.group(2).strip(), 0), int(m.group(1)))
def get(name):
    return sum(v for k, v in cost.items() if k.endswith("chip_calls::split::" + name))
total = cost.get("sercos_sim::sim::Simulation::run_until", 0)
parts = [("slaves: receivers (line input)", get("slave_input")),
         ("slaves: advances (run-aheads, wakes)", get("slave_advance")),
         ("slaves: takes (their output)", get("slave_take")),
         ("master: receiver (line input)", get("master_input")),
         ("master: advances (wakes)", get("master_advance")),
         ("master: takes (its output)", get("master_take"))]
chips = sum(v for _, v in parts)
print(f"{sys.argv[1]}: {total} instructions per cycle (split-profile build)")
for name, v in parts:
    print(f"  {name:40} {v:8d}  {100 * v / max(total, 1):5.1f} %")
rest = ("the simulation (the rest)", total - chips)
print(f"  {rest[0]:40} {rest[1]:8d}  {100 * rest[1] / max(total, 1):5.1f} %")
' "$scenario"
