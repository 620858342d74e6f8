#!/usr/bin/env python3
"""Splits a callgrind profile's instructions by the source crate of each (inlined) line.

Usage: scripts/callgrind-by-crate.py callgrind.out...
(e.g. `valgrind --tool=callgrind --callgrind-out-file=cg.out \\
 target/release/examples/ring_profile ring-8 2000`). Code inlined from the standard library
is counted as `std:sim` when the function it was inlined into is the simulator's, else as
`std:model`. docs/performance.md, "Session 6".
"""
import re
import subprocess
import sys

CRATES = ["sercon-model", "sercon-regs", "sercos-wire", "sercos-sim", "sercdrv", "sercos-drive", "sercon-cli"]

for path in sys.argv[1:]:
    out = subprocess.run(
        ["callgrind_annotate", "--threshold=100", path], capture_output=True, text=True, check=True
    ).stdout
    share, total = {}, 0
    for line in out.splitlines():
        m = re.match(r"^\s*([\d,]+) \(\s*[\d.]+%\)\s+(\S+?):(.*)$", line)
        if not m or "PROGRAM TOTALS" in line:
            continue
        count, src, func = int(m.group(1).replace(",", "")), m.group(2), m.group(3)
        crate = next((c for c in CRATES if f"/{c}/" in src), None)
        # The standard library's sources: `/rustc/<hash>/library/…` or, with the rust-src
        # component, `…/rustlib/src/rust/library/…`.
        if crate is None and ("/rustc/" in src or "/rustlib/src/" in src):
            crate = "std:sim" if "sercos_sim::" in func.split("[")[0] else "std:model"
        crate = crate or "other"
        share[crate] = share.get(crate, 0) + count
        total += count
    parts = sorted(share.items(), key=lambda kv: -kv[1])
    print(path, " ".join(f"{k} {100 * v / max(total, 1):.1f}%" for k, v in parts))
