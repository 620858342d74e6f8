#!/usr/bin/env bash
# The shape of one build's real-time factor on this machine over minutes (docs/performance.md,
# "Session 35"): many short `sercon bench` runs, spread over time, summed up as quantiles, a
# histogram and a median per minute.
#
# One run's figure on a shared virtual machine is not the build's speed: this VM runs a build
# at one steady speed most of the time and, in bursts of 0.1-1 s that nothing on the VM causes,
# at a half to three quarters of it, now and then a quarter (session 35: 17-21 % of the ring-8
# runs). A few long runs land
# in a burst or not by chance; many short ones show both modes and how often each comes.
#
# Usage: scripts/rtf-spread.sh [-s SCENARIO] [-m SIM_MS] [-d SECONDS] [-t TARGET] [-o FILE] [BINARY]
#   -s  bench scenario (default ring-8)
#   -m  simulated milliseconds per run (default 500: ≈ 5 ms of wall time for ring-8)
#   -d  how long to go on, in wall seconds (default 300)
#   -t  the target real-time factor, for the share of runs below it (default 100)
#   -o  also write every run to FILE ("UNIX-SECONDS RTF" a line)
#   BINARY  a `sercon` binary (default: target/release/sercon; build it with
#           `cargo build --release -p sercon-cli`)
# Each run warms up for 5 wall ms (`--warm-up-ms`); after every 5 runs the script pauses
# 0.2 s, so that the runs sample the minutes rather than one stretch.
set -euo pipefail
scenario=ring-8 sim_ms=500 seconds=300 target=100 keep=""
# The usage lines of the header; `usage 0` (for -h) on standard output, otherwise an error.
usage() {
  local text
  text=$(sed -n '/^# Usage:/,/^# Each run/p' "$0" | sed 's/^# \{0,1\}//' | sed '$d')
  if [ "$1" = 0 ]; then echo "$text"; else echo "$text" >&2; fi
  exit "$1"
}
while getopts "s:m:d:t:o:h" o; do
  case $o in
    s) scenario=$OPTARG ;;
    m) sim_ms=$OPTARG ;;
    d) seconds=$OPTARG ;;
    t) target=$OPTARG ;;
    o) keep=$OPTARG ;;
    h) usage 0 ;;
    *) usage 2 ;;
  esac
done
shift $((OPTIND - 1))
[ $# -le 1 ] || usage 2
# Whole numbers of at most nine digits (no overflow in shell arithmetic), read as decimal.
for v in "$sim_ms" "$seconds" "$target"; do
  [[ $v =~ ^[0-9]{1,9}$ ]] && [ $((10#$v)) -gt 0 ] ||
    { echo "rtf-spread: not a positive whole number below 10^9: $v" >&2; exit 2; }
done
sim_ms=$((10#$sim_ms)) seconds=$((10#$seconds)) target=$((10#$target))
bin=${1:-${CARGO_TARGET_DIR:-target}/release/sercon}
[ -x "$bin" ] || { echo "rtf-spread: no sercon binary at $bin (cargo build --release -p sercon-cli)" >&2; exit 2; }
if [ -n "$keep" ] && ! : >"$keep"; then
  echo "rtf-spread: cannot write $keep" >&2
  exit 2
fi
command -v python3 >/dev/null || { echo "rtf-spread: python3 is needed" >&2; exit 2; }
# One run first: a wrong scenario name or an old binary stops here, with its own message.
"$bin" bench --json --scenario "$scenario" --sim-ms "$sim_ms" --warm-up-ms 5 >/dev/null
runs=$(mktemp)
trap 'rm -f "$runs"' EXIT
end=$((SECONDS + seconds))
n=0
# Ctrl-C or a failed run ends the runs early; what was measured is still summed up.
stop=0
trap 'stop=1' INT
while [ $SECONDS -lt $end ] && [ $stop = 0 ]; do
  for _ in 1 2 3 4 5; do
    # Read with sed, not python: a reader starting while the run goes on (a pipe) slows it.
    out=$("$bin" bench --json --scenario "$scenario" --sim-ms "$sim_ms" --warm-up-ms 5) || out=""
    r=$(sed -n 's/.*"rtf":\([0-9.]*\).*/\1/p' <<<"$out")
    if [ $stop = 1 ] || [ -z "$r" ]; then
      [ $stop = 1 ] || echo "rtf-spread: a run gave no rtf (${out:-no output}); stopping" >&2
      stop=1
      break
    fi
    echo "$(date +%s) $r" >>"$runs"
    n=$((n + 1))
  done
  printf '\rrtf-spread: %d runs, %d s to go ' "$n" $((end - SECONDS > 0 ? end - SECONDS : 0)) >&2
  [ $stop = 1 ] || sleep 0.2
done
trap - INT
echo >&2
[ "$n" -gt 0 ] || { echo "rtf-spread: no run finished" >&2; exit 1; }
if [ -n "$keep" ]; then
  cp "$runs" "$keep"
fi
python3 - "$runs" "$scenario" "$sim_ms" "$target" <<'PY'
import statistics, sys
from collections import defaultdict

path, scenario, sim_ms, target = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
runs = [(int(t), float(r)) for t, r in (line.split() for line in open(path))]
rtf = sorted(r for _, r in runs)

def q(p):
    return rtf[min(len(rtf) - 1, int(p * len(rtf)))]

print(f"{scenario}, {len(rtf)} runs of {sim_ms} simulated ms over "
      f"{(runs[-1][0] - runs[0][0]) / 60:.1f} min")
print(f"  real-time factor: p10 {q(0.1):.1f}  p25 {q(0.25):.1f}  median {statistics.median(rtf):.1f}"
      f"  p75 {q(0.75):.1f}  p90 {q(0.9):.1f}  best {rtf[-1]:.1f}")
below = sum(r < target for r in rtf)
print(f"  below {target:g}x: {below} runs ({100 * below / len(rtf):.0f} %)")
print("  histogram (5x bins):")
bins = defaultdict(int)
for r in rtf:
    bins[int(r // 5) * 5] += 1
top = max(bins.values())
for b in sorted(bins):
    print(f"    {b:4d}-{b + 5:<4d} {bins[b]:5d} {'#' * max(1, round(40 * bins[b] / top))}")
print("  per minute (median, runs below the target):")
minutes = defaultdict(list)
t0 = runs[0][0]
for t, r in runs:
    minutes[(t - t0) // 60].append(r)
for m in sorted(minutes):
    v = minutes[m]
    print(f"    min {m:3d}: {len(v):4d} runs, median {statistics.median(v):6.1f}x, "
          f"{100 * sum(r < target for r in v) / len(v):3.0f} % below")
PY
