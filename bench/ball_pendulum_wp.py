#!/usr/bin/env python3
"""Work-precision of the seed's ball and pendulum: the exact impact against MapleSim's penalty force.

Closed form (tests/physics/ball_pendulum_test.cc): just after the impact, for e = 1 and equal
masses, A = (2*sqrt(3)/5, 1/5) v0 and B = (-2*sqrt(3)/5, 0) v0, v0 = sqrt(2 g (L - sqrt(3) r)).
The error of a run is the largest of the four post-impact velocity components' errors, divided by
v0 (so 1e-3 is 0.1 % of the impact speed).

- models/ball_pendulum_impact.yaml at rtol = 1e-4 ... 1e-10 (atol = rtol): the velocities on the
  right-limit row of the impact.
- models/ball_pendulum.yaml with the penalty force F = 1e3 ... 1e6 N at rtol 1e-8: the velocities
  on the first output row after the force stops (touching.y back to 0; output interval 1e-5 s
  for this, the model's 1e-3 s for the timing).

Prints a Markdown table with the median wall time of --repeat whole CLI runs (process start, load,
build, simulate, CSV). A benchmark, not a test: it asserts nothing.
Usage: bench/ball_pendulum_wp.py [--momenta build/app/momenta] [--repeat 5]
"""
import argparse, csv, math, statistics, subprocess, tempfile, time, os

G, L, R = 9.81, 3.5, 0.5
S3 = math.sqrt(3.0)
EXACT = (2 * S3 / 5, 0.2, -2 * S3 / 5, 0.0)


def run(momenta, model, args, out):
    t0 = time.perf_counter()
    subprocess.run([momenta, "simulate", model, *args, "-o", out, "-q"], check=True)
    return time.perf_counter() - t0


def read(path):
    with open(path) as f:
        r = list(csv.reader(f))
    h = r[0]
    return {name: i for i, name in enumerate(h)}, [[float(x) for x in row] for row in r[1:]]


def error(before, after, c):
    v0 = math.hypot(before[c["A.v[1]"]], before[c["A.v[2]"]])
    got = [after[c[k]] / v0 for k in ("A.v[1]", "A.v[2]", "B.v[1]", "B.v[2]")]
    return max(abs(g - x) for g, x in zip(got, EXACT)), v0


def exact_error(path):
    c, rows = read(path)
    for k in range(1, len(rows)):
        if rows[k][0] == rows[k - 1][0]:
            return error(rows[k - 1], rows[k], c)
    raise RuntimeError("no impact")


def penalty_error(path):
    c, rows = read(path)
    on = [k for k, row in enumerate(rows) if row[c["touching.y"]] > 0.5]
    return error(rows[on[0] - 1], rows[on[-1] + 1], c) + (rows[on[-1] + 1][0] - rows[on[0]][0],)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--momenta", default="build/app/momenta")
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args()
    tmp = tempfile.mkdtemp()
    out = os.path.join(tmp, "out.csv")
    print("| exact impact, rtol | error / v0 | time [ms] |")
    print("|---|---|---|")
    for rtol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]:
        args = ["--rtol", str(rtol), "--atol", str(rtol)]
        times = [run(a.momenta, "models/ball_pendulum_impact.yaml", args, out) for _ in range(a.repeat)]
        err, _ = exact_error(out)
        print(f"| {rtol:.0e} | {err:.2e} | {1e3 * statistics.median(times):.1f} |")
    print()
    print("| penalty force F [N], rtol 1e-8 | error / v0 | contact time [ms] | time [ms] |")
    print("|---|---|---|---|")
    for force in [1e3, 1e4, 1e5, 1e6]:
        # Timed at the model's own output interval (1e-3 s); the error is read from a run that
        # writes every 1e-5 s, to see the contact's end.
        times = [run(a.momenta, "models/ball_pendulum.yaml", ["-p", f"F={force}"], out) for _ in range(a.repeat)]
        run(a.momenta, "models/ball_pendulum.yaml", ["-p", f"F={force}", "--interval", "1e-5"], out)
        err, _, contact = penalty_error(out)
        print(f"| {force:.0e} | {err:.2e} | {1e3 * contact:.3f} | {1e3 * statistics.median(times):.1f} |")


if __name__ == "__main__":
    main()
