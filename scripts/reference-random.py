#!/usr/bin/env python3
"""Random `sercon ring` runs on the simulator's fast path and its reference path, compared.

Each run picks a ring (1-16 drives, 2-16 Mbit/s, 500-2000 µs cycle, SERCON816 or 410B, a
telegram type now and then), a seed, up to three faults (break, power, bit errors, a burst,
clock drift, distortion) and now and then a VCD, a pcap of a fibre, a log of one fibre or the
service transcript at random, runs it twice (`sercon ring …` and `sercon ring …
--reference`) with a JSON log, and prints "same" or "DIFF" with the command line. The two
must give the same report, log and traces (spec-notes "Fast path = reference path"); a fast run that
met telegrams at a repeater it cannot follow runs again on the reference path by itself, and
its report then says so (the field `fast_path_collisions`), which shows here as DIFF too.

`sercon ring` runs a ring with a fault other than drift on the reference path either way
(session 17), so those runs check the CLI; the fast path is checked by the fault-free and
drift runs (and by the property tests in crates/sercos-sim/tests).

Usage: scripts/reference-random.py SERCON [SEED] [RUNS]
Session 16 found with it that the runner's schedule drifted with the path (fixed).
"""

import json
import os
import random
import subprocess
import sys
import tempfile


def ring_args(rng):
    drives = rng.randint(1, 16)
    args = ["ring", "--drives", str(drives), "--baud", str(rng.choice([2, 4, 8, 16])),
            "--seconds", rng.choice(["0.06", "0.2"]),
            "--cycle-us", rng.choice(["500", "1000", "2000"]),
            "--seed", str(rng.randint(1, 99))]
    for _ in range(rng.randint(0, 3)):
        kind = rng.choice(["break", "power", "ber", "burst", "drift", "distort"])
        d = rng.randint(1, drives)
        t1 = rng.randint(0, 40)
        t2 = t1 + rng.randint(1, 30)
        args += ["--fault", {
            "break": f"break:{d}@{t1}ms..{t2}ms",
            "power": f"power:{d}@{t1}ms..{t2}ms",
            "ber": f"ber:{rng.choice(['1e-3', '1e-4', '1e-5'])}:{d}@{t1}ms..{t2}ms",
            "burst": f"burst:{d}:{rng.randint(1, 40)}@{t1}ms",
            "drift": f"drift:{d}:{rng.randint(-3000, 3000)}@{t1}ms",
            "distort": f"distort:{d}@{t1}ms..{t2}ms",
        }[kind]]
    if rng.random() < 0.3:
        args[4] = rng.choice(["2", "4"])
        args += ["--variant", "410b"]
    if rng.random() < 0.3:
        args += ["--telegram-type", str(rng.randint(0, 7))]
    # Traces: a traced chip or fibre takes other paths through the simulator (a VCD keeps its
    # chips from running ahead; a traced fibre splits telegrams from their filler).
    if rng.random() < 0.25:
        args += ["--vcd", "v.vcd"]
        if rng.random() < 0.5:
            # Other pins (IDLE, REACTN and the others traced are events of the chip, not
            # quiet: another path again), of some nodes. A drive's REACTN runs on the
            # reference path either way (spec-notes "A VCD of chosen pins of chosen nodes"),
            # so it is asked of the master only.
            pins = rng.sample(["INT0", "INT1", "CON_CLK", "DIV_CLK", "WDOGN", "IDLE",
                               "L_ERRN", "DMAREQR", "DMAREQT", "TxD"], rng.randint(1, 4))
            nodes = rng.sample(["master"] + [str(a) for a in range(1, drives + 1)],
                               rng.randint(1, min(3, drives + 1)))
            if nodes == ["master"] and rng.random() < 0.5:
                pins.append("REACTN")
            args += ["--vcd-pins", ",".join(pins), "--vcd-nodes", ",".join(nodes)]
    if rng.random() < 0.25:
        args += ["--pcap", "p.pcap", "--pcap-segment", str(rng.randint(0, drives))]
    if rng.random() < 0.2:
        args += ["--log-segment", str(rng.randint(0, drives))]
    if rng.random() < 0.2:
        args += ["--transcript", "t.jsonl"]
    return args


def run(sercon, args):
    """Exit code, report and every file the run wrote (the log and the traces asked for)."""
    with tempfile.TemporaryDirectory() as d:
        r = subprocess.run([sercon] + args + ["--log", "l.jsonl", "--json"], cwd=d,
                           capture_output=True, text=True, timeout=600)
        files = {}
        for name in sorted(os.listdir(d)):
            with open(os.path.join(d, name), "rb") as f:
                files[name] = f.read()
    return r.returncode, r.stdout, files


def main():
    if len(sys.argv) < 2:
        print(__doc__.strip().splitlines()[-2], file=sys.stderr)
        sys.exit(2)
    sercon = os.path.realpath(sys.argv[1])
    rng = random.Random(int(sys.argv[2]) if len(sys.argv) > 2 else 1)
    runs = int(sys.argv[3]) if len(sys.argv) > 3 else 20
    differ = 0
    for i in range(runs):
        args = ring_args(rng)
        fast, reference = run(sercon, args), run(sercon, args + ["--reference"])
        same = fast == reference
        differ += not same
        print(i, "same" if same else "DIFF", " ".join(args), "exit", fast[0], reference[0],
              flush=True)
        if not same and fast[1] and reference[1]:
            a, b = json.loads(fast[1]), json.loads(reference[1])
            keys = [k for k in a if a.get(k) != b.get(k)]
            print("   report fields that differ:", keys, flush=True)
        if not same:
            names = sorted(set(fast[2]) | set(reference[2]))
            print("   files that differ:",
                  [n for n in names if fast[2].get(n) != reference[2].get(n)], flush=True)
    sys.exit(1 if differ else 0)


if __name__ == "__main__":
    main()
