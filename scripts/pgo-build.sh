#!/usr/bin/env bash
# Builds `sercon` with profile-guided optimisation (docs/performance.md, "PGO build").
#
# 1. an instrumented `sercon` runs the main job, `sercon ring` (master driver, emulated
#    drives, controllers, ring; phase-up and phase 4, with and without faults, both
#    controllers), and, unless PGO_TRAIN=job, `sercon bench --sim-ms 20` (the static rings
#    and the full stack, 20 ms each: the bench's own scenarios, so its figures from this
#    build are from a profile trained on them; docs/performance.md says which);
# 2. llvm-profdata merges the profiles;
# 3. `sercon` is built again with them.
#
# Needs the rustup component llvm-tools (`rustup component add llvm-tools`).
# Usage: scripts/pgo-build.sh [target-dir]   (default: target/pgo)
# Prints the path of the optimised binary on its last line.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
target=${1:-$root/target/pgo}
sysroot=$(rustc --print sysroot)
host=$(rustc -vV | sed -n 's/^host: //p')
profdata="$sysroot/lib/rustlib/$host/bin/llvm-profdata"
if [ ! -x "$profdata" ]; then
  echo "pgo-build: $profdata not found; run: rustup component add llvm-tools" >&2
  exit 1
fi
raw="$target/profraw"
rm -rf "$raw"
mkdir -p "$raw"

# RUSTFLAGS replaces the workspace's .cargo/config.toml flags: its block alignment and
# placement are added here (x86-64 only, as there).
align=""
if [ "$(uname -m)" = x86_64 ]; then
  align="-Cllvm-args=-align-all-nofallthru-blocks=5 -Cllvm-args=-enable-ext-tsp-block-placement=true"
fi

echo "pgo-build: 1/3 instrumented build" >&2
RUSTFLAGS="-Cprofile-generate=$raw $align" CARGO_TARGET_DIR="$target/gen" \
  cargo build --release --locked -p sercon-cli >&2
gen="$target/gen/release/sercon"

echo "pgo-build: 2/3 training runs (sercon ring)" >&2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(
  cd "$work"
  "$gen" ring --drives 8 --seconds 1 >/dev/null
  "$gen" ring --drives 32 --seconds 0.5 --log l.jsonl --pcap p.pcap >/dev/null
  "$gen" ring --drives 3 --seconds 2.5 --fault break:2@1s..1.5s --fault ber:1e-5 \
    --fault power:1@0.5s..0.7s >/dev/null
  "$gen" ring --drives 8 --seconds 0.5 --variant 410b --baud 4 --cycle-us 1000 \
    --vcd v.vcd >/dev/null
  if [ "${PGO_TRAIN:-all}" != job ]; then
    "$gen" bench --sim-ms 20 >/dev/null
  fi
)
"$profdata" merge -o "$target/sercon.profdata" "$raw"/*.profraw

echo "pgo-build: 3/3 optimised build" >&2
SERCON_PGO_BUILD=1 RUSTFLAGS="-Cprofile-use=$target/sercon.profdata $align" CARGO_TARGET_DIR="$target/use" \
  cargo build --release --locked -p sercon-cli >&2
echo "$target/use/release/sercon"
