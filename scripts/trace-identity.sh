#!/usr/bin/env bash
# Checks that two `sercon` builds write byte-identical traces: four `sercon ring` runs (8
# drives; 3 drives with a fibre break, bit errors and a power cycle; 20 drives at 4 Mbit/s;
# the 410B), each with telegram log, VCD, transcript, pcap and JSON report, five files each.
# Usage: scripts/trace-identity.sh SERCON_A SERCON_B [WORK_DIR]
# B_EXTRA (environment): options added to side B's runs (scripts/reference-identity.sh sets
# --reference to compare one build's fast and reference paths).
# Prints "same" or "DIFF" per file (20 lines) and exits 1 if any differs.
set -uo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 SERCON_A SERCON_B [WORK_DIR]" >&2
  exit 2
fi
a=$(realpath "$1") b=$(realpath "$2")
dir=${3:-$(mktemp -d)}
i=0 diff=0
run() {
  i=$((i + 1))
  for side in A B; do
    bin=$a extra=()
    if [ "$side" = B ]; then
      bin=$b
      read -r -a extra <<<"${B_EXTRA:-}"
    fi
    d=$dir/$side/$i
    rm -rf "$d" && mkdir -p "$d"
    (cd "$d" && "$bin" ring "$@" "${extra[@]}" --log l.jsonl --vcd v.vcd --transcript t.jsonl --pcap p.pcap \
      --json >report.json 2>err.txt) || echo "$side run $i exited $?"
  done
  for f in l.jsonl v.vcd t.jsonl p.pcap report.json; do
    if cmp -s "$dir/A/$i/$f" "$dir/B/$i/$f"; then
      echo "same $i $f"
    else
      echo "DIFF $i $f"
      diff=1
    fi
  done
}
run --drives 8 --seconds 0.3
run --drives 3 --seconds 2.5 --fault break:2@1s..1.5s --fault ber:1e-5 --fault power:1@0.5s..0.7s
run --drives 20 --seconds 0.2 --baud 4 --cycle-us 2000
run --drives 8 --seconds 0.3 --variant 410b --baud 4 --cycle-us 1000
exit $diff
