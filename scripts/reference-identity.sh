#!/usr/bin/env bash
# Checks that one `sercon` build gives the same run on the simulator's fast path and on its
# reference path (`sercon ring --reference`): the four runs of scripts/trace-identity.sh, each
# with telegram log, VCD, transcript, pcap and JSON report, compared file by file.
# Usage: scripts/reference-identity.sh SERCON [WORK_DIR]
# Prints "same" or "DIFF" per file (20 lines) and exits 1 if any differs.
set -uo pipefail
if [ $# -lt 1 ]; then
  echo "usage: $0 SERCON [WORK_DIR]" >&2
  exit 2
fi
bin=$(realpath "$1")
dir=${2:-$(mktemp -d)}
i=0 diff=0
run() {
  i=$((i + 1))
  for side in fast reference; do
    extra=()
    [ "$side" = reference ] && extra=(--reference)
    d=$dir/$side/$i
    rm -rf "$d" && mkdir -p "$d"
    (cd "$d" && "$bin" ring "$@" "${extra[@]}" --log l.jsonl --vcd v.vcd --transcript t.jsonl \
      --pcap p.pcap --json >report.json 2>err.txt) || echo "$side run $i exited $?"
  done
  for f in l.jsonl v.vcd t.jsonl p.pcap report.json; do
    if cmp -s "$dir/fast/$i/$f" "$dir/reference/$i/$f"; then
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
