#!/usr/bin/env python3
"""How the spring-damper chain's step count depends on IDA's first step (issue 12, item 4).

IDA starts with a step of 0.001 of the distance to the first time it is asked for (less where
|y'| is large); momenta aims that first call one output interval ahead, as the hand-written
program's IDA_NORMAL loop aims it at its first output row, so both start with h0 = 0.001 * interval.
This script varies the output interval a little around the benchmark's 0.1 s (only h0 changes:
the stop time is the same and IDA's steps do not stop at output rows) and runs, per interval:

  hand-written   bench/handwritten_chain: absolute positions and velocities of every mass
  relative       momenta_bench on models/spring_damper_chain.yaml with --unit-nominals (the
                 benchmark's configuration: the library's states, sd[1] and sd[n]'s stretch and
                 relative velocity instead of mass[1] and mass[n]'s position and velocity)
  absolute       momenta_bench on the same chain with stateSelect: avoid on the spring-dampers
                 (bench/chain_states.py's variant): the hand-written program's states

all at rtol = atol = --tol, KLU, momenta with native code (compiled once into a temporary cache).
Errors are in mass[n].s and mass[n].v at t = 10 against the hand-written program at rtol = atol =
--ref-tol. Steps and errors are deterministic: one run each. CPU is the process's CPU time of the
simulation (momenta_bench's simulate_cpu_s; the hand-written program's set-up + solve), one run
per first step, so the medians over the first steps are also medians of that many runs.

--max-order Q caps IDA's BDF order at Q in every run but the reference (both programs).

Usage: bench/first_step.py [--build build] [--sizes 1000,10000] [--intervals 0.09,...,0.11]
       [--tol 1e-6] [--ref-tol 1e-10] [--max-order 5]
"""
import argparse, os, statistics, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import chain_states  # noqa: E402  (the state-choice variants of the chain)


def fields(text):
    """The key=value pairs of the first "run=1" line."""
    line = next(l for l in text.splitlines() if l.startswith("run=1 "))
    return dict(kv.split("=", 1) for kv in line.split())


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("%s failed:\n%s%s" % (" ".join(cmd), p.stdout, p.stderr))
    return fields(p.stdout)


def hand(build, n, tol, interval, max_order=5):
    f = run([os.path.join(build, "bench", "handwritten_chain"), "--n", str(n), "--stop", "10", "--rtol", str(tol),
             "--atol", str(tol), "--interval", repr(interval), "--linear-solver", "klu", "--repeat", "1",
             "--max-order", str(max_order)])
    return {"steps": int(f["steps"]), "res": int(f["res_evals"]), "s": float(f["s_n"]), "v": float(f["v_n"]),
            "cpu": float(f["setup_cpu_s"]) + float(f["solve_cpu_s"])}


def momenta(build, model, n, tol, interval, cache, max_order):
    os.environ["MOMENTA_CACHE_DIR"] = cache
    f = run([os.path.join(build, "bench", "momenta_bench"), "--model", model, "-p", "n=%d" % n, "--stop", "10",
             "--rtol", str(tol), "--atol", str(tol), "--interval", repr(interval), "--linear-solver", "klu",
             "--unit-nominals", "--codegen", "native", "--repeat", "1", "--max-order", str(max_order)])
    return {"steps": int(f["steps"]), "res": int(f["res_evals"]), "s": float(f["mass[n].s"]),
            "v": float(f["mass[n].v"]), "cpu": float(f["simulate_cpu_s"])}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(REPO, "build"))
    ap.add_argument("--sizes", default="1000,10000")
    ap.add_argument("--intervals", default="0.09,0.095,0.099,0.1,0.101,0.105,0.11")
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--ref-tol", type=float, default=1e-10)
    ap.add_argument("--max-order", type=int, default=5, help="IDA's highest BDF order for the runs (not the reference)")
    a = ap.parse_args()
    intervals = [float(x) for x in a.intervals.split(",")]
    lines = ["| n | run | " + " | ".join("%g" % iv for iv in intervals) + " | median steps | "
             "median error s_n | median error v_n | median CPU (s) |",
             "|---:|---|" + "---:|" * (len(intervals) + 4)]
    with tempfile.TemporaryDirectory() as tmp:
        for n in [int(s) for s in a.sizes.split(",")]:
            absolute = os.path.join(tmp, "absolute.yaml")
            open(absolute, "w").write(chain_states.variant_yaml("absolute", n))
            ref = hand(a.build, n, a.ref_tol, 0.1)
            runs = {
                "hand-written": lambda iv: hand(a.build, n, a.tol, iv, a.max_order),
                "momenta, relative (library)": lambda iv: momenta(
                    a.build, os.path.join(REPO, "models", "spring_damper_chain.yaml"), n, a.tol, iv, tmp, a.max_order),
                "momenta, absolute": lambda iv: momenta(a.build, absolute, n, a.tol, iv, tmp, a.max_order),
            }
            for name, fn in runs.items():
                rs = [fn(iv) for iv in intervals]
                es = [abs(r["s"] - ref["s"]) for r in rs]
                ev = [abs(r["v"] - ref["v"]) for r in rs]
                lines.append("| %d | %s | %s | %d | %.1e | %.1e | %.3g |" % (
                    n, name, " | ".join("%d" % r["steps"] for r in rs), statistics.median(r["steps"] for r in rs),
                    statistics.median(es), statistics.median(ev), statistics.median(r["cpu"] for r in rs)))
                print(lines[-1], file=sys.stderr)
                print("  n=%d %s: steps %s; res. evals %s; error s_n %s; error v_n %s; CPU %s" % (
                    n, name, [r["steps"] for r in rs], [r["res"] for r in rs], ["%.1e" % e for e in es],
                    ["%.1e" % e for e in ev], ["%.3g" % r["cpu"] for r in rs]), file=sys.stderr)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
