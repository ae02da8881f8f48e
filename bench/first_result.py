#!/usr/bin/env python3
"""Time to a first result: the whole `momenta simulate` process against a hand-written IDA program.

Runs each pair (momenta, baseline) alternately K times (paired runs, so that a change in the
machine's load touches both), and prints a Markdown table of the medians: CPU time of the process
(user + system, from wait4; what a shared machine's waiting does not inflate) and wall time.

  bench/first_result.py [--build build] [--repeat 21] [--momenta PATH] [--also PATH] [--only TEXT]

--also runs a second momenta binary (another commit's) in the same series, each of its runs next
to the first binary's and the baseline's, and adds its median and ratio to each row.

The pairs: the seed examples (models/carrier_collision*.yaml, models/ball_pendulum*.yaml) against
bench/handwritten_carrier and bench/handwritten_ball_pendulum [--impact] (the MapleSim variant of
the carrier has no program of its own: `-` as baseline, its figure stands alone), the RC ladder at
n = 1000 against handwritten_rc at the same settings (rtol = atol = 1e-6, interval 0.01, stop 10),
and `momenta --help` (the bare start-up: loading, static initialisers) against /bin/true.
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time


def run(cmd):
    """Wall and CPU seconds of one run of `cmd` (its output thrown away)."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    err = p.stderr.read().decode(errors="replace")
    p.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"failed ({os.waitstatus_to_exitcode(status)}): {' '.join(cmd)}\n{err}")
    return wall, usage.ru_utime + usage.ru_stime


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--momenta", default=None, help="the momenta binary (default BUILD/app/momenta)")
    ap.add_argument("--also", default=None, help="a second momenta binary, run in the same pairs")
    ap.add_argument("--repeat", type=int, default=21)
    ap.add_argument("--only", default=None, help="run only the rows whose name contains this text")
    a = ap.parse_args()
    momenta = a.momenta or f"{a.build}/app/momenta"
    out = tempfile.mkdtemp(prefix="momenta-first-")
    hw = f"{a.build}/bench"
    rc = ["--n", "1000", "--stop", "10", "--rtol", "1e-6", "--atol", "1e-6", "--interval", "0.01",
          "--repeat", "1"]
    pairs = [("start-up (`--help`)", [momenta, "--help"], ["/bin/true"])]
    baselines = {"carrier_collision": [f"{hw}/handwritten_carrier", f"{out}/hw.csv"],
                 "ball_pendulum_impact": [f"{hw}/handwritten_ball_pendulum", "--impact", f"{out}/hw.csv"],
                 "ball_pendulum": [f"{hw}/handwritten_ball_pendulum", f"{out}/hw.csv"]}
    for m in ("carrier_collision", "carrier_collision_maplesim", "ball_pendulum_impact", "ball_pendulum"):
        base = baselines.get(m)
        pairs.append((f"`{m}`", [momenta, "simulate", f"models/{m}.yaml", "-o", f"{out}/{m}.csv"], base))
    pairs.append(("RC ladder n = 1000", [momenta, "simulate", "models/rc_ladder.yaml", "-p", "n=1000", "-o",
                                         f"{out}/rc.csv"], [f"{hw}/handwritten_rc"] + rc))
    also = f" {a.also} CPU (ms) | its ratio |" if a.also else ""
    print(f"| run | momenta CPU (ms) | hand-written CPU (ms) | **ratio** | momenta wall (ms) | hand-written wall (ms) |{also}")
    print("|---|---:|---:|---:|---:|---:|" + ("---:|---:|" if a.also else ""))
    for name, cmd, base in pairs:
        if a.only and a.only not in name:
            continue
        ours, theirs, others = [], [], []
        for _ in range(a.repeat):
            ours.append(run(cmd))
            if a.also:
                others.append(run([a.also] + cmd[1:]))
            if base:
                theirs.append(run(base))
        med = lambda runs, i: statistics.median(r[i] for r in runs) * 1e3
        other = ""
        if a.also:
            other = f" {med(others, 1):.1f} | " + (f"{med(others, 1) / med(theirs, 1):.2f} |" if base else "- |")
        if base:
            print(f"| {name} | {med(ours, 1):.1f} | {med(theirs, 1):.1f} | **{med(ours, 1) / med(theirs, 1):.2f}** | "
                  f"{med(ours, 0):.1f} | {med(theirs, 0):.1f} |{other}")
        else:
            print(f"| {name} | {med(ours, 1):.1f} | - | - | {med(ours, 0):.1f} | - |{other}")


if __name__ == "__main__":
    main()
