#!/usr/bin/env python3
"""Sweep scaling: runs per second of `momenta sweep` against threads and MPI ranks.

The spring-damper chain with n = 50 masses (models/spring_damper_chain.yaml: 100 unknowns, all
states, KLU; about 2 200 steps to t = 10 s), swept over the sine force's amplitude
(`-p n=50 -p sine.amplitude=5:15:RUNS`): about 45 ms per run on one core, so one message per run
and MPI's start-up are small against the work. Configurations:
  threads 1, 2                            momenta sweep -j T
  ranks 1, 2 (one thread each)            mpirun -n R momenta sweep -j 1
  2 ranks x 2 threads                     mpirun -n 2 momenta sweep -j 2 (oversubscribed on 2 cores)
Each is run --repeat times, interleaved (round r runs every configuration once) so that a noisy
spell on the shared machine hits all of them alike; the table gives medians of
  - runs/s as momenta reports it (the runs only: after every rank has built the model), and
  - the whole command's wall time (process start-up, MPI start-up, build, runs, writing).
Every configuration's summary is checked to be byte-identical to the first one's.

Usage: bench/sweep_scaling.py [--momenta build/app/momenta] [--mpirun mpirun] [--runs 48]
[--repeat 5]. A benchmark, not a test: it prints figures and asserts only that the tables agree.
"""
import argparse, os, re, statistics, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--momenta", default=os.path.join(REPO, "build", "app", "momenta"))
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--runs", type=int, default=48)
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args()
    model = os.path.join(REPO, "models", "spring_damper_chain.yaml")
    mpi = [a.mpirun, "--allow-run-as-root", "--oversubscribe", "-n"]
    configs = [
        ("threads", "1 thread", [], 1),
        ("threads", "2 threads", [], 2),
        ("ranks", "1 rank x 1 thread", mpi + ["1"], 1),
        ("ranks", "2 ranks x 1 thread", mpi + ["2"], 1),
        ("ranks", "2 ranks x 2 threads (oversubscribed: 4 threads on 2 cores)", mpi + ["2"], 2),
    ]
    rates = {c[1]: [] for c in configs}
    walls = {c[1]: [] for c in configs}
    reference = None
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(a.repeat):
            for kind, label, launcher, jobs in configs:
                out = os.path.join(tmp, "s.csv")
                cmd = launcher + [a.momenta, "sweep", model, "-p", "n=50", "-p",
                                  "sine.amplitude=5:15:%d" % a.runs, "-j", str(jobs), "-o", out]
                t0 = time.perf_counter()
                p = subprocess.run(cmd, capture_output=True, text=True)
                wall = time.perf_counter() - t0
                if p.returncode != 0:
                    sys.exit("%s failed (%d):\n%s%s" % (" ".join(cmd), p.returncode, p.stdout, p.stderr))
                m = re.search(r"\(([0-9.e+]+) runs/s\)", p.stdout)
                rates[label].append(float(m.group(1)))
                walls[label].append(wall)
                text = open(out).read()
                if reference is None:
                    reference = text
                elif text != reference:
                    sys.exit("the summary of '%s' differs from the first configuration's" % label)
            print("round %d of %d done" % (r + 1, a.repeat), file=sys.stderr)
    load = os.getloadavg()
    print("%d runs (`-p n=50 -p sine.amplitude=5:15:%d`), medians of %d interleaved rounds; load "
          "average %.1f at the end; every summary byte-identical.\n" % (a.runs, a.runs, a.repeat, load[0]))
    print("| configuration | runs/s (runs only) | range | speed-up | whole command, wall |")
    print("|---|---:|---:|---:|---:|")
    base = statistics.median(rates[configs[0][1]])
    for kind, label, launcher, jobs in configs:
        med = statistics.median(rates[label])
        print("| %s | %.1f | %.1f–%.1f | %.2f | %.2f s |" % (label, med, min(rates[label]), max(rates[label]),
                                                            med / base, statistics.median(walls[label])))


if __name__ == "__main__":
    main()
