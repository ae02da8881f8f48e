#!/usr/bin/env python3
"""The scalable suite: build, simulate and memory of models/scalable/ against their size N.

Models (after Casella et al.'s Modelica ScalableTestSuite, same equations, parameters and
experiments): CascadedFirstOrder, HarmonicOscillator, TransmissionLineEquations, HeatConduction.
Each is run as `momenta simulate MODEL -p N=n -o FILE` for n = 10, 100, 1 000, ... (the sizes
given by --sizes), each size's runs before the next:

  - medians of --repeat runs (3) while a run takes under --single seconds (10 s CPU), then 1 run;
  - the next size is skipped when the last one's CPU time, extrapolated with the exponent measured
    so far (at least linear), would exceed --per-size seconds (150 s), or when the model's whole
    time so far exceeds --budget seconds (240 s), or the last run failed or ran out of time.

Figures per run: `momenta check -p N=n` under /usr/bin/time gives the build's CPU time (load
through compilation, plus reading the built-in component library, about 0.1 s) and its maximum
resident set size; `momenta simulate` gives its printed per-pass times (wall clock; the raw
output has them all), `integrate` (initialisation + IDA, wall clock), the steps, and under
/usr/bin/time the whole run's CPU time (build + simulation + writing the CSV) and maximum RSS. On
a shared machine the CPU times are the steady figures; wall clock includes waiting for a core.

The table gives, per model and size: states, runs, build CPU, build wall (load + the passes, as
printed), the slowest pass, the build's max RSS, simulate CPU (the whole `simulate` process),
integrate wall, steps, the simulate process's max RSS and that per state, and scaling exponents
d log(CPU) / d log(n) between consecutive sizes for the build and the whole simulate run. A benchmark, not a test: it asserts nothing beyond each run succeeding.

Usage: bench/scalable.py [--momenta build/app/momenta] [--models A,B] [--sizes 10,100,...]
       [--repeat 3] [--budget 240] [--per-size 150] [--single 10] [--timeout 300]
       [--limit MODEL=N,...] [--raw FILE]
"""
import argparse, math, os, re, signal, statistics, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
MODELS = ["CascadedFirstOrder", "HarmonicOscillator", "TransmissionLineEquations", "HeatConduction"]
SIZES = [10, 100, 1000, 10000, 100000, 1000000]


def ms(text):
    """'644 ms' -> 0.644 (seconds)."""
    return float(text) / 1e3


def parse_summary(out):
    """The figures `momenta simulate` prints."""
    build = re.search(r"build ([0-9.e+-]+) ms \(load ([0-9.e+-]+) ms(.*?)\); initialise ([0-9.e+-]+) ms; "
                      r"integrate ([0-9.e+-]+) ms", out)
    solver = re.search(r"(\d+) unknowns \((\d+) states\), IDA with (\w+) LU.*?: (\d+) steps, (\d+) residual "
                       r"evaluations, (\d+) Jacobians", out)
    if not build or not solver:
        raise ValueError("unexpected summary:\n" + out)
    passes = dict((name.strip(), ms(v)) for name, v in re.findall(r", ([a-z ]+) ([0-9.e+-]+) ms", build.group(3)))
    return {
        "build": ms(build.group(1)), "load": ms(build.group(2)), "passes": passes,
        "initialise": ms(build.group(4)), "integrate": ms(build.group(5)),
        "unknowns": int(solver.group(1)), "states": int(solver.group(2)), "linear_solver": solver.group(3),
        "steps": int(solver.group(4)), "residuals": int(solver.group(5)), "jacobians": int(solver.group(6)),
    }


def timed(args, tmp, timeout):
    """Runs args under /usr/bin/time in a session of its own (so that a timeout ends momenta too,
    not only /usr/bin/time): (stdout, CPU seconds (user + system), maximum RSS in bytes, wall
    seconds), or an error message."""
    usage = os.path.join(tmp, "usage")
    cmd = ["/usr/bin/time", "-f", "%U %S %M", "-o", usage] + args
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        stdout, stderr = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        return "no result within %d s" % timeout
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        return "exit %d: %s" % (p.returncode, " ".join((stderr or stdout).strip().splitlines()[-1:]))
    user, system, rss_kb = open(usage).read().split()[-3:]
    return stdout, float(user) + float(system), int(rss_kb) * 1024, wall


def run_once(momenta, model, n, tmp, timeout):
    """One `momenta simulate`: its summary plus the process's CPU seconds and maximum resident
    set size (bytes)."""
    out = timed([momenta, "simulate", model, "-p", "N=%d" % n, "-o", os.path.join(tmp, "out.csv")], tmp, timeout)
    if isinstance(out, str):
        return {"error": out}
    stdout, cpu, rss, wall = out
    r = parse_summary(stdout)
    r.update(wall=wall, raw=stdout, cpu=cpu, rss=rss)
    r["passes_total"] = r["load"] + sum(r["passes"].values())
    return r


def build_cpu(momenta, model, n, tmp, timeout):
    """`momenta check`: the build alone (load through compilation, plus the built-in library),
    its CPU seconds and maximum RSS (bytes)."""
    out = timed([momenta, "check", model, "-p", "N=%d" % n], tmp, timeout)
    if isinstance(out, str):
        return {"error": "check: " + out}
    _, cpu, rss, _ = out
    return {"build_cpu": cpu, "build_rss": rss}


def exponent(n0, t0, n1, t1):
    if t0 <= 0 or t1 <= 0:
        return float("nan")
    return math.log(t1 / t0) / math.log(n1 / n0)


def fmt_s(x):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "—"
    if x >= 100:
        return "%.0f" % x
    if x >= 10:
        return "%.1f" % x
    if x >= 1:
        return "%.2f" % x
    return "%.3g" % x


def fmt_n(n):
    return "{:,}".format(n).replace(",", " ")


def median_of(runs, key):
    return statistics.median(r[key] for r in runs)


def bench_model(a, name, tmp, raw):
    model = os.path.join(REPO, "models", "scalable", name + ".yaml")
    rows, spent, note = [], 0.0, ""
    for n in a.sizes:
        if n > a.limit.get(name, n):
            note = "n = %s not run here (--limit %s=%d)" % (fmt_n(n), name, a.limit[name])
            break
        if rows:
            last = rows[-1]
            if len(rows) >= 2:
                k = max(1.0, exponent(rows[-2]["n"], rows[-2]["cpu"], last["n"], last["cpu"]))
            else:
                k = 1.0
            predicted = last["cpu"] * (n / last["n"]) ** k
            if predicted > a.per_size:
                note = "n = %s not run: about %s s CPU predicted (exponent %.2f)" % (fmt_n(n), fmt_s(predicted), k)
                break
            if spent > a.budget:
                note = "n = %s not run: the model's budget of %d s is spent" % (fmt_n(n), a.budget)
                break
        runs = []
        while True:
            r = run_once(a.momenta, model, n, tmp, a.timeout)
            if "error" not in r:
                r.update(build_cpu(a.momenta, model, n, tmp, a.timeout))
            if "error" in r:
                note = "n = %s: %s" % (fmt_n(n), r["error"])
                break
            runs.append(r)
            spent += r["wall"]
            raw.write("== %s N=%d run %d: cpu %.3f s, max RSS %d B\n%s\n" % (name, n, len(runs), r["cpu"], r["rss"], r["raw"]))
            raw.flush()
            if len(runs) >= a.repeat or r["cpu"] >= a.single:
                break
        if not runs:
            break
        row = {"n": n, "runs": len(runs), "states": runs[0]["states"], "unknowns": runs[0]["unknowns"],
               "solver": runs[0]["linear_solver"], "steps": runs[0]["steps"], "residuals": runs[0]["residuals"]}
        for key in ("build", "passes_total", "integrate", "initialise", "cpu", "rss", "wall", "build_cpu", "build_rss"):
            row[key] = median_of(runs, key)
        passes = {}
        for p in runs[0]["passes"]:
            passes[p] = statistics.median(r["passes"].get(p, 0) for r in runs)
        row["slowest_pass"] = max(passes.items(), key=lambda kv: kv[1]) if passes else ("", 0)
        rows.append(row)
        print("  %s N=%s: build %s s (CPU %s s), integrate %s s, cpu %s s, %d steps, %.0f MB" % (
            name, fmt_n(n), fmt_s(row["build"]), fmt_s(row["build_cpu"]), fmt_s(row["integrate"]), fmt_s(row["cpu"]),
            row["steps"], row["rss"] / 2**20), file=sys.stderr)
        if note:
            break
    return rows, note


def table(name, rows, note):
    lines = ["#### %s" % name, "",
             "| N | states | runs | build CPU (s) | build wall (s) | slowest pass (s) | build MB | simulate CPU (s) "
             "| integrate wall (s) | steps | max RSS (MB) | kB per state | build exp. | simulate exp. |",
             "|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    prev = None
    for r in rows:
        be = ce = float("nan")
        if prev:
            be = exponent(prev["n"], prev["build_cpu"], r["n"], r["build_cpu"])
            ce = exponent(prev["n"], prev["cpu"], r["n"], r["cpu"])
        lines.append("| %s | %s | %d | %s | %s | %s %s | %.0f | %s | %s | %d | %.0f | %s | %s | %s |" % (
            fmt_n(r["n"]), fmt_n(r["states"]), r["runs"], fmt_s(r["build_cpu"]), fmt_s(r["passes_total"]),
            r["slowest_pass"][0], fmt_s(r["slowest_pass"][1]), r["build_rss"] / 2**20, fmt_s(r["cpu"]),
            fmt_s(r["integrate"]), r["steps"], r["rss"] / 2**20, fmt_s(r["rss"] / 1024 / max(1, r["states"])),
            "—" if math.isnan(be) else "%.2f" % be, "—" if math.isnan(ce) else "%.2f" % ce))
        prev = r
    if note:
        lines += ["", note + "."]
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--momenta", default=os.path.join(REPO, "build", "app", "momenta"))
    ap.add_argument("--models", default=",".join(MODELS))
    ap.add_argument("--sizes", default=",".join(str(s) for s in SIZES))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--single", type=float, default=10.0, help="CPU seconds from which one run is enough")
    ap.add_argument("--budget", type=float, default=240.0, help="seconds per model, after which no larger size starts")
    ap.add_argument("--per-size", type=float, default=150.0, help="predicted CPU seconds above which a size is skipped")
    ap.add_argument("--timeout", type=int, default=300, help="seconds allowed for one run")
    ap.add_argument("--limit", default="", help="MODEL=N,...: the largest size to run for a model")
    ap.add_argument("--raw", default=None, help="file for momenta's raw output (default: a temporary file)")
    a = ap.parse_args()
    a.sizes = [int(s) for s in a.sizes.split(",")]
    a.limit = dict((k, int(v)) for k, v in (item.split("=") for item in a.limit.split(",") if item))
    raw_path = a.raw or tempfile.mkstemp(prefix="momenta-scalable-", suffix=".txt")[1]
    out = []
    with tempfile.TemporaryDirectory() as tmp, open(raw_path, "w") as raw:
        for name in a.models.split(","):
            print("%s …" % name, file=sys.stderr)
            rows, note = bench_model(a, name, tmp, raw)
            out.append(table(name, rows, note))
    print("\n".join(out))
    print("raw output: %s" % raw_path)


if __name__ == "__main__":
    main()
