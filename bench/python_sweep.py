#!/usr/bin/env python3
"""A run from Python against a `momenta simulate` process: what one more run of a model costs.

The carrier collision (models/carrier_collision.yaml: 0 to 0.5 s, two impacts, 105 rows of 10
outputs) by default. Measured, each --repeat times, interleaved so that a noisy spell on the
shared machine hits both alike:
  - `momenta simulate MODEL -q -o FILE.csv`, a process: load, build, simulate, write the CSV;
    its CPU time (user + system, from the children's rusage) and its wall time;
  - `m.simulate()` on a model that momenta.load built once: CPU time of this process (every
    thread) and wall time, the numpy arrays made;
and once, momenta.load's own cost and a sweep of --sweep values of eC on 1 and 2 threads (per
run). Medians; the ratio is the process's CPU time over the Python run's.

Usage: PYTHONPATH=build/python bench/python_sweep.py [--momenta build/app/momenta]
[--model models/carrier_collision.yaml] [--repeat 21] [--sweep 200]. A benchmark, not a test:
it prints figures and checks only that both ways end at the same B.v.
"""
import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def ms(seconds):
    return "%.3g ms" % (seconds * 1e3)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--momenta", default=os.path.join(REPO, "build", "app", "momenta"))
    ap.add_argument("--model", default=os.path.join(REPO, "models", "carrier_collision.yaml"))
    ap.add_argument("--repeat", type=int, default=21)
    ap.add_argument("--sweep", type=int, default=200)
    a = ap.parse_args()
    try:
        import numpy as np
        import momenta
    except ImportError as e:
        sys.exit("cannot import momenta (%s): build it and run with PYTHONPATH=build/python" % e)

    # Loading and building, once.
    c0, w0 = time.process_time(), time.perf_counter()
    m = momenta.load(a.model)
    load_cpu, load_wall = time.process_time() - c0, time.perf_counter() - w0
    m.simulate()  # the first run's one-time costs (numpy's, the threads') out of the medians

    proc_cpu, proc_wall, py_cpu, py_wall = [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "run.csv")
        cmd = [a.momenta, "simulate", a.model, "-q", "-o", out]
        for _ in range(a.repeat):
            # A momenta simulate process.
            c0, w0 = children_cpu(), time.perf_counter()
            p = subprocess.run(cmd, capture_output=True, text=True)
            proc_wall.append(time.perf_counter() - w0)
            proc_cpu.append(children_cpu() - c0)
            if p.returncode != 0:
                sys.exit("%s failed (%d):\n%s%s" % (" ".join(cmd), p.returncode, p.stdout, p.stderr))
            # A run of the built model from Python.
            c0, w0 = time.process_time(), time.perf_counter()
            r = m.simulate()
            py_wall.append(time.perf_counter() - w0)
            py_cpu.append(time.process_time() - c0)
        # Both end at the same value.
        with open(out) as f:
            lines = f.read().splitlines()
        header, last = lines[0].split(","), lines[-1].split(",")
        name = m.outputs[min(1, len(m.outputs) - 1)]
        cli_final = float(last[header.index(name)])
        if abs(cli_final - r[name][-1]) > 1e-12 * max(1.0, abs(cli_final)):
            sys.exit("the two disagree: %s = %r (process) and %r (Python)" % (name, cli_final, r[name][-1]))

    # A sweep of eC (the carrier's) or of the model's first parameter, on 1 and 2 threads.
    pname = "eC" if "eC" in m.parameters else next(iter(m.parameters))
    p0 = m.parameters[pname].value
    values = np.linspace(0.5 * p0, p0, a.sweep) if p0 else np.linspace(0, 1, a.sweep)
    sweeps = []
    for jobs in (1, 2):
        c0, w0 = time.process_time(), time.perf_counter()
        s = m.sweep({pname: values}, jobs=jobs)
        sweeps.append((jobs, time.process_time() - c0, time.perf_counter() - w0, len(s.errors)))

    med = statistics.median
    print("model: %s (%s), %d rows x %d outputs a run; codegen: %s" % (m.name, os.path.relpath(a.model, REPO),
                                                                     len(r.time), len(m.outputs), m.codegen))
    print("momenta.load (load + build, once): %s CPU, %s wall" % (ms(load_cpu), ms(load_wall)))
    print("median of %d:                       CPU          wall" % a.repeat)
    print("  momenta simulate process        %10s  %10s" % (ms(med(proc_cpu)), ms(med(proc_wall))))
    print("  Model.simulate from Python      %10s  %10s" % (ms(med(py_cpu)), ms(med(py_wall))))
    print("  ratio (process / Python)        %9.1fx  %9.1fx" % (med(proc_cpu) / med(py_cpu),
                                                              med(proc_wall) / med(py_wall)))
    for jobs, cpu, wall, failed in sweeps:
        print("sweep of %d values of %s on %d thread%s: %s CPU and %s wall per run (%.0f runs/s)%s" % (
            a.sweep, pname, jobs, "" if jobs == 1 else "s", ms(cpu / a.sweep), ms(wall / a.sweep), a.sweep / wall,
            ", %d failed" % failed if failed else ""))


if __name__ == "__main__":
    main()
