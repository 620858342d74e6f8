#!/usr/bin/env python3
"""Per-instruction costs per cycle, joined with the inlined frames and the disassembly.

Where `callgrind-per-cycle.py lines` is flat (one big function with everything inlined into
it, e.g. `Chip::advance_to`), the instruction-level costs show what each inlined function
and each call's entry and exit cost. Run the program twice with `--dump-instr=yes`
(optionally `--toggle-collect` to one caller, e.g. a `split-profile` build's
`*split::slave_advance*`, scripts/chip-split.sh):

    valgrind --tool=callgrind --dump-instr=yes --callgrind-out-file=/tmp/a.out ring_profile ring-8 500
    valgrind --tool=callgrind --dump-instr=yes --callgrind-out-file=/tmp/b.out ring_profile ring-8 1500

then

    scripts/callgrind-instr.py /tmp/a.out /tmp/b.out 1000 'Chip::advance_to$' BINARY frames
        # cost per cycle by the outermost inlined frame (what the function called, inlined)
    scripts/callgrind-instr.py /tmp/a.out /tmp/b.out 1000 'Chip::advance_to$' BINARY inner
        # by the innermost frame outside the standard library (file:line)
    scripts/callgrind-instr.py /tmp/a.out /tmp/b.out 1000 'load_rx$' BINARY asm
        # every executed instruction: cost per cycle, disassembly, innermost frame

The cost of a call instruction's callee is not counted (self costs only). Needs binutils
(addr2line, objdump) and a binary with debug info (the release profile has it).
"""

import argparse
import collections
import re
import signal
import subprocess

# Frames from the standard library are told by their path (the toolchain's sources: `/rustc/…`
# or a `rustlib` source directory), not by their file name: `mod.rs` is also the project's.
STD_PATHS = ("/rustc/", "/rustlib/", "/library/core/", "/library/alloc/", "/library/std/")


def costs(path, pattern):
    """Self cost per instruction address inside functions matching `pattern`."""
    names, fn, addr, after_call = {}, None, 0, False
    out = collections.Counter()
    with open(path) as f:
        for raw in f:
            line = raw.rstrip("\n")
            m = re.match(r"(c?)fn=\((\d+)\)(?: (.*))?", line)
            if m:
                if m.group(3):
                    names[m.group(2)] = m.group(3)
                if not m.group(1):
                    fn = names.get(m.group(2))
                continue
            if line.startswith("calls="):
                after_call = True
                continue
            m = re.match(r"^(0x[0-9a-f]+|[+-]\d+|\*)\s+\S+\s+(\d+)", line)
            if m:
                p = m.group(1)
                if p.startswith("0x"):
                    addr = int(p, 16)
                elif p[0] in "+-":
                    addr += int(p)
                if after_call:
                    # The cost line of a call is the callee's inclusive cost.
                    after_call = False
                    continue
                if fn and re.search(pattern, fn):
                    out[addr] += int(m.group(2))
    return out


def frames(binary, addrs):
    """Inlined frames per address, innermost first, as `function@file:line`."""
    res = subprocess.run(["addr2line", "-a", "-i", "-f", "-C", "-e", binary]
                         + [hex(a) for a in addrs], capture_output=True, text=True, check=True)
    out, cur, pending = {}, None, None
    for line in res.stdout.splitlines():
        if line.startswith("0x"):
            cur = int(line, 16)
            out[cur] = []
            pending = None
        elif cur is not None:
            if pending is None:
                pending = line.split("(")[0].split("::")[-1]
            else:
                path = line.split(" ")[0]
                # Standard-library frames are marked `STD/`; the project's keep their
                # directory, so that `telegram_processor/mod.rs` is not any `mod.rs`.
                where = ("STD/" + path.split("/")[-1] if any(s in path for s in STD_PATHS)
                         else "/".join(path.split("/")[-2:]))
                out[cur].append(f"{pending}@{where}")
                pending = None
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("short")
    p.add_argument("long")
    p.add_argument("cycles", type=float)
    p.add_argument("pattern", help="function-name regex")
    p.add_argument("binary")
    p.add_argument("what", choices=["frames", "inner", "asm"])
    p.add_argument("--top", type=int, default=50)
    a = p.parse_args()
    short, long_ = costs(a.short, a.pattern), costs(a.long, a.pattern)
    per = {k: (v - short.get(k, 0)) / a.cycles for k, v in long_.items() if v > short.get(k, 0)}
    fr = frames(a.binary, sorted(per))
    print(f"total {sum(per.values()):.0f} per cycle")
    if a.what == "asm":
        lo, hi = min(per), max(per) + 16
        dis = subprocess.run(["objdump", "-d", "--no-show-raw-insn", "-C", a.binary,
                              f"--start-address={lo:#x}", f"--stop-address={hi:#x}"],
                             capture_output=True, text=True, check=True).stdout
        for line in dis.splitlines():
            m = re.match(r"\s*([0-9a-f]+):\t(.*)", line)
            if m and int(m.group(1), 16) in per:
                k = int(m.group(1), 16)
                inner = (fr.get(k) or ["?"])[0]
                print(f"{per[k]:7.1f} {k:#x} {m.group(2)[:60]:60s} {inner}")
        return
    agg = collections.Counter()
    for k, v in per.items():
        chain = fr.get(k) or ["?"]
        if a.what == "frames":
            key = chain[-2] if len(chain) >= 2 else chain[-1] + " (itself)"
            key = key.split("@")[0]
        else:
            key = next((x for x in chain if not x.split("@")[-1].startswith("STD/")), chain[0])
        agg[key] += v
    for key, v in agg.most_common(a.top):
        print(f"{v:8.1f} {key}")


if __name__ == "__main__":
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # `| head` ends quietly
    main()
