#!/usr/bin/env bash
# Instructions per simulated cycle of the two bench rings, from callgrind (deterministic, unlike
# wall time on a shared VM; docs/performance.md "Ring simulation").
# Usage: scripts/instructions-per-cycle.sh [RING_PROFILE_BINARY]
#   default binary: the release build of crates/sercos-sim/examples/ring_profile.rs
#   (`cargo build --release -p sercos-sim --example ring_profile`).
# Each ring runs twice with different lengths; the difference divided by the extra cycles
# cancels the set-up: ring-8 1500 − 500 cycles, ring-254 60 − 20 cycles.
# With SPLIT=1 it also runs ring-8 with one slave (`ring-8x1`) and splits ring-8's cycle into a
# part per slave ((ring-8 − ring-8x1) / 7: the slave's chip, its deliveries, the master's
# work for its AT) and a fixed part (the rest: the master's cycle, MST and MDT, the loop).
set -euo pipefail
bin=${1:-${CARGO_TARGET_DIR:-target}/release/examples/ring_profile}
if [ ! -x "$bin" ]; then
  echo "no ring_profile binary at $bin (build it: cargo build --release -p sercos-sim --example ring_profile)" >&2
  exit 2
fi
command -v valgrind >/dev/null || { echo "valgrind is needed (apt-get install -y valgrind)" >&2; exit 2; }
refs() {
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" "$1" "$2" 2>&1 |
    awk '/refs/ {gsub(",", "", $4); print $4}'
}
a=$(refs ring-8 500); b=$(refs ring-8 1500)
ring8=$(( (b - a) / 1000 ))
echo "ring-8: $ring8 instructions per cycle"
if [ "${SPLIT:-0}" = 1 ]; then
  a=$(refs ring-8x1 500); b=$(refs ring-8x1 1500)
  one=$(( (b - a) / 1000 ))
  per=$(( (ring8 - one) / 7 ))
  echo "ring-8x1: $one instructions per cycle; ring-8: $per per slave, $(( one - per )) fixed"
fi
a=$(refs ring-254 20); b=$(refs ring-254 60)
echo "ring-254: $(( (b - a) / 40 )) instructions per cycle"
