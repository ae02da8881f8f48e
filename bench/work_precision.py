#!/usr/bin/env python3
"""Work-precision of momenta's exact impacts: error against the closed form vs run time.

For rtol = 1e-3 ... 1e-10 (atol = rtol), runs the CLI on
  - models/carrier_collision.yaml: |B.v - 2.9045454545...| and |S.v - 4.2545454545...| at the end;
  - models/bouncing_ball.yaml: |t_10 - t_10 exact| (10th impact time) and |v after it - e^10 v0|,
and prints a Markdown table with the median wall time of `--repeat` runs (whole CLI process:
load, build, simulate, write). Usage: bench/work_precision.py [--momenta build/app/momenta]
[--repeat 5]. A benchmark, not a test: it asserts nothing.
"""
import argparse, csv, math, os, statistics, subprocess, sys, tempfile, time

G, H, E = 9.81, 1.0, 0.8
V0 = math.sqrt(2 * G * H)


def run(momenta, model, rtol, out):
    t0 = time.perf_counter()
    subprocess.run([momenta, "simulate", model, "--rtol", str(rtol), "--atol", str(rtol), "-o", out, "-q"],
                   check=True)
    return time.perf_counter() - t0


def rows(path):
    with open(path) as f:
        r = list(csv.reader(f))
    header = r[0]
    return header, [[float(x) for x in row] for row in r[1:]]


def carrier_errors(path):
    header, data = rows(path)
    last = data[-1]
    vb2 = (40 * 4.5 - 15 * 0.3 * 4.5) / 55
    vs2 = (40 * 4.5 + 40 * 0.3 * 4.5) / 55
    return abs(last[header.index("B.v")] - vb2), abs(last[header.index("S.v")] - vs2)


def ball_errors(path):
    header, data = rows(path)
    iv = header.index("ball.v")
    events = [k for k in range(len(data) - 1) if data[k][0] == data[k + 1][0] and data[k + 1][iv] > 0]
    t1 = math.sqrt(2 * H / G)
    tk, vk = t1, V0
    for _ in range(9):
        vk *= E
        tk += 2 * vk / G
    k = events[9]
    return abs(data[k][0] - tk), abs(data[k + 1][iv] - E ** 10 * V0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--momenta", default="build/app/momenta")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    tmp = tempfile.mkdtemp()
    print("| rtol | carrier: error B.v | error S.v | time [ms] | ball: error t_10 [s] | error v_10 | time [ms] |")
    print("|---|---|---|---|---|---|---|")
    for rtol in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]:
        c_out, b_out = os.path.join(tmp, "c.csv"), os.path.join(tmp, "b.csv")
        c_times = [run(args.momenta, "models/carrier_collision.yaml", rtol, c_out) for _ in range(args.repeat)]
        b_times = [run(args.momenta, "models/bouncing_ball.yaml", rtol, b_out) for _ in range(args.repeat)]
        eb, es = carrier_errors(c_out)
        et, ev = ball_errors(b_out)
        print(f"| {rtol:.0e} | {eb:.2e} | {es:.2e} | {1e3 * statistics.median(c_times):.1f} | "
              f"{et:.2e} | {ev:.2e} | {1e3 * statistics.median(b_times):.1f} |")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
