#!/usr/bin/env python3
"""Per-cycle costs from two callgrind runs of different length (the set-up cancels).

Run the same program twice, e.g.

    valgrind --tool=callgrind --callgrind-out-file=/tmp/a.out ring_profile ring-8 500
    valgrind --tool=callgrind --callgrind-out-file=/tmp/b.out ring_profile ring-8 1500

then divide the difference by the extra cycles (here 1000):

    scripts/callgrind-per-cycle.py self      /tmp/a.out /tmp/b.out 1000   # self cost per function
    scripts/callgrind-per-cycle.py inclusive /tmp/a.out /tmp/b.out 1000   # inclusive cost
    scripts/callgrind-per-cycle.py calls     /tmp/a.out /tmp/b.out 1000   # calls per function
    scripts/callgrind-per-cycle.py lines     /tmp/a.out /tmp/b.out 1000 'Chip::advance_to$'
        # self cost per source line inside the functions matching the regex (inlined code
        # counted where its source is), with the line's text when found under --src

docs/performance.md names these as the per-function and per-line figures of each session.
"""

import argparse
import collections
import glob
import os
import re
import subprocess
import sys

ANNOTATED = re.compile(r"^\s*([\d,]+) \(\s*[\d.]+%\)\s+(\S+?):(.*?)( \[.*)?$")


def annotated(path, inclusive):
    """Cost per function name from callgrind_annotate."""
    out = subprocess.run(
        ["callgrind_annotate", "--threshold=100", f"--inclusive={'yes' if inclusive else 'no'}", path],
        capture_output=True, text=True, check=True,
    ).stdout
    costs = collections.Counter()
    for line in out.splitlines():
        m = ANNOTATED.match(line)
        if m and "PROGRAM" not in line:
            cost = int(m.group(1).replace(",", ""))
            name = m.group(3)
            # Inclusive costs of a recursive function would add up: keep the largest.
            costs[name] = max(costs[name], cost) if inclusive else costs[name] + cost
    return costs


def calls(path):
    """Calls per callee name, from the raw callgrind file (names are compressed: `(id) name`)."""
    names, counts, callee = {}, collections.Counter(), None
    with open(path) as f:
        for line in f:
            m = re.match(r"c?fn=\((\d+)\)(?: (.*))?", line)
            if m:
                if m.group(2):
                    names[m.group(1)] = m.group(2).rstrip("\n")
                if line.startswith("cfn"):
                    callee = m.group(1)
                continue
            m = re.match(r"calls=(\d+)", line)
            if m and callee:
                counts[callee] += int(m.group(1))
    return collections.Counter({names.get(k, k): v for k, v in counts.items()})


def lines(path, pattern):
    """Self cost per (source file, line) inside functions whose name matches `pattern`."""
    files, fns, costs = {}, {}, collections.Counter()
    cur_file = in_file = cur_fn = None
    line_no, after_call = 0, False
    with open(path) as f:
        for raw in f:
            line = raw.rstrip("\n")
            m = re.match(r"(fl|fi|fe)=\((\d+)\)(?: (.*))?", line)
            if m:
                if m.group(3):
                    files[m.group(2)] = m.group(3)
                name = files.get(m.group(2), m.group(2))
                if m.group(1) == "fl":
                    cur_file = name
                in_file = name
                continue
            m = re.match(r"fn=\((\d+)\)(?: (.*))?", line)
            if m:
                if m.group(2):
                    fns[m.group(1)] = m.group(2)
                cur_fn, in_file = fns.get(m.group(1)), cur_file
                continue
            m = re.match(r"cfn=\((\d+)\)(?: (.*))?", line)
            if m:
                if m.group(2):
                    fns[m.group(1)] = m.group(2)
                continue
            m = re.match(r"cf[il]=\((\d+)\)(?: (.*))?", line)
            if m:
                if m.group(2):
                    files[m.group(1)] = m.group(2)
                continue
            if line.startswith("calls="):
                after_call = True
                continue
            m = re.match(r"^([+-]?\d+|\*)\s+(\d+)", line)
            if m:
                pos = m.group(1)
                if pos[0] in "+-":
                    line_no += int(pos)
                elif pos != "*":
                    line_no = int(pos)
                if after_call:
                    # The cost line of a call is the callee's inclusive cost: not this line's.
                    after_call = False
                    continue
                if cur_fn and in_file and re.search(pattern, cur_fn):
                    costs[(in_file.split("/src/")[-1], line_no)] += int(m.group(2))
    return costs


def source_text(roots, rel, line_no):
    for root in roots:
        for p in glob.glob(os.path.join(root, rel)):
            try:
                with open(p) as f:
                    text = f.read().split("\n")
                return text[line_no - 1].strip()[:90] if 0 < line_no <= len(text) else ""
            except OSError:
                pass
    return ""


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("what", choices=["self", "inclusive", "calls", "lines"])
    p.add_argument("short", help="callgrind output of the shorter run")
    p.add_argument("long", help="callgrind output of the longer run")
    p.add_argument("cycles", type=float, help="extra cycles of the longer run")
    p.add_argument("pattern", nargs="?", help="function-name regex (for `lines`)")
    p.add_argument("--top", type=int, default=40, help="rows to print (default 40)")
    p.add_argument("--src", action="append", default=None,
                   help="glob of source roots for `lines` (default: crates/*/src/ and the toolchain's library sources)")
    a = p.parse_args()
    if a.cycles <= 0:
        p.error("cycles must be positive")
    if a.what == "lines":
        if not a.pattern:
            p.error("`lines` needs a function-name regex")
        short, long_ = lines(a.short, a.pattern), lines(a.long, a.pattern)
    elif a.what == "calls":
        short, long_ = calls(a.short), calls(a.long)
    else:
        short, long_ = annotated(a.short, a.what == "inclusive"), annotated(a.long, a.what == "inclusive")
    rows = sorted((((long_[k] - short.get(k, 0)) / a.cycles, k) for k in long_), reverse=True)
    if a.what == "lines":
        print(f"total {sum(v for v, _ in rows):.0f} per cycle in the matching functions")
    roots = a.src or [
        "crates/*/src/",
        os.path.expanduser("~/.rustup/toolchains/*/lib/rustlib/src/rust/library/*/src/"),
    ]
    for v, k in rows[: a.top]:
        if a.what == "lines":
            print(f"{v:8.0f} {k[0][-34:]:34s}:{k[1]:<5d} {source_text(roots, k[0], k[1])}")
        elif v > 0 or a.what != "calls":
            print(f"{v:8.0f} {k[:150]}" if a.what != "calls" else f"{v:8.2f} {k[:150]}")


if __name__ == "__main__":
    try:
        main()
    except (OSError, subprocess.CalledProcessError) as e:
        sys.exit(f"callgrind-per-cycle: {e}")
