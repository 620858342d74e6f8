#!/usr/bin/env bash
# Checks that one `sercon` build gives the same run on the simulator's fast path and on its
# reference path (`sercon ring --reference`): the four runs of scripts/trace-identity.sh (side
# A fast, side B reference), each with telegram log, VCD, transcript, pcap and JSON report.
# Usage: scripts/reference-identity.sh SERCON [WORK_DIR]
# Prints "same" or "DIFF" per file (20 lines) and exits 1 if any differs.
set -uo pipefail
if [ $# -lt 1 ]; then
  echo "usage: $0 SERCON [WORK_DIR]" >&2
  exit 2
fi
B_EXTRA=--reference exec "$(dirname "$0")/trace-identity.sh" "$1" "$1" "${@:2}"
