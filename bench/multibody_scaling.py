#!/usr/bin/env python3
"""Cost of the 3-D library against size: build and simulate times of
  chain  models/scalable/PendulumChain3D.yaml (n Revolute joints and BodyShape links in a chain), and
  free   models/scalable/FreeBodies3D.yaml (n free Parts.Body, each its own tree with a quaternion
         state set),
for n = 10, 100, 1 000, ... (--sizes). Every body's output is written (the model is copied with one
output per link or body), so pruning keeps the whole model. The figures are CPU times of fresh
processes (user + system; the machine is shared): build = `momenta check` (load and build),
simulate = `momenta simulate` (load, build, initialise, integrate, write), run = their
difference; medians over --runs runs (--passes adds the three slowest passes of `check -v`). A
model whose run fails still has its build measured. Prints a
Markdown table per model and the scaling exponent of each figure from a least-squares fit of
log(time) on log(n) (1 is linear). A run that fails is reported with its first message line.

usage: bench/multibody_scaling.py [--momenta build/app/momenta] [--sizes 10,100,1000,10000]
                                  [--runs 3] [--timeout 300] [--passes] [--models chain,free]
                                  [--build-only-from chain=1000,free=100000]
A benchmark, not a test.
"""
import argparse, math, os, re, resource, statistics, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
MODELS = {
    "chain": ("models/scalable/PendulumChain3D.yaml", lambda n: [f"rev[{i}].phi" for i in range(1, n + 1)]),
    "free": ("models/scalable/FreeBodies3D.yaml", lambda n: [f"body[{i}].{v}" for i in range(1, n + 1) for v in ("Q[1]", "frame_a.r_0[1]", "frame_a.r_0[2]", "frame_a.r_0[3]")]),
}


def with_all_outputs(path, outputs, tmp):
    """A copy of the model whose outputs are `outputs` (so that pruning removes nothing)."""
    text = open(os.path.join(REPO, path)).read()
    text = re.sub(r"^outputs:.*$", "outputs: [" + ", ".join(f'"{o}"' for o in outputs) + "]", text, flags=re.M)
    out = os.path.join(tmp, os.path.basename(path))
    open(out, "w").write(text)
    return out


def cpu_of(cmd, timeout):
    """(CPU seconds of the child process, its completed process)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), p


def run(momenta, model, n, timeout, simulate=True):
    """(build ms, run ms, steps, states, failure) of one check and one simulate, or a string."""
    try:
        build, _ = cpu_of([momenta, "check", model, "-p", f"n={n}"], timeout)
        if not simulate:
            return (1000 * build, None, None, None, "build only (--build-only-from)")
        total, p = cpu_of([momenta, "simulate", model, "-p", f"n={n}", "-o", os.devnull], timeout)
    except subprocess.TimeoutExpired:
        return f"timed out after {timeout} s"
    text = p.stdout + p.stderr
    if p.returncode != 0:
        first = text.strip().splitlines()[0][:160] if text.strip() else f"exit {p.returncode}"
        return (1000 * build, None, None, None, first)
    steps = re.search(r"IDA [^:]*: (\d+) steps", text)
    states = re.search(r"\((\d+) states\)", text)
    return (1000 * build, 1000 * max(total - build, 0.0), int(steps.group(1)) if steps else None,
            int(states.group(1)) if states else None, None)


def passes(momenta, model, n, timeout):
    """The slowest three passes of `momenta check -v` (name and ms)."""
    try:
        p = subprocess.run([momenta, "check", "-v", model, "-p", f"n={n}"], capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "timed out"
    rows = []
    for line in p.stdout.splitlines():
        m = re.match(r"  (\w[\w ]*?)\s+([0-9.]+) (ms|s)\s", line)
        if m and m.group(1) != "total":
            rows.append((float(m.group(2)) * (1000.0 if m.group(3) == "s" else 1.0), m.group(1)))
    rows.sort(reverse=True)
    return ", ".join(f"{name} {t:.0f} ms" for t, name in rows[:3])


def exponent(ns, ts):
    pts = [(math.log(n), math.log(t)) for n, t in zip(ns, ts) if t and t > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    return sum((x - mx) * (y - my) for x, y in pts) / sum((x - mx) ** 2 for x, _ in pts)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--momenta", default=os.path.join(REPO, "build/app/momenta"))
    ap.add_argument("--sizes", default="10,100,1000,10000")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--models", default="chain,free")
    ap.add_argument("--build-only-from", default="chain=1000,free=100000",
                    help="per model, the size from which only the build is measured")
    ap.add_argument("--passes", action="store_true", help="also list the three slowest passes per size")
    a = ap.parse_args()
    sizes = [int(s) for s in a.sizes.split(",")]
    with tempfile.TemporaryDirectory() as tmp:
        for key in a.models.split(","):
            path, outputs = MODELS[key]
            limits = dict(kv.split("=") for kv in a.build_only_from.split(",") if kv)
            build_only_from = int(limits.get(key, 10**12))
            print(f"\n### {key}: {path} (medians of {a.runs})\n")
            print("| n | states | steps | build (ms) | run (ms) | build µs/n | run µs/n |" + (" slowest passes |" if a.passes else ""))
            print("|---:|---:|---:|---:|---:|---:|---:|" + ("---|" if a.passes else ""))
            ns, builds, integrates = [], [], []
            for n in sizes:
                model = with_all_outputs(path, outputs(n), tmp)
                results = [run(a.momenta, model, n, a.timeout, n < build_only_from) for _ in range(a.runs)]
                extra = f" {passes(a.momenta, model, n, a.timeout)} |" if a.passes else ""
                if any(isinstance(r, str) for r in results):
                    print(f"| {n} | – | – | – | – | – | – |{extra} {next(r for r in results if isinstance(r, str))}")
                    continue
                b = statistics.median(r[0] for r in results)
                ns.append(n), builds.append(b)
                if results[0][4]:
                    print(f"| {n} | – | – | {b:.1f} | – | {1000 * b / n:.1f} | – |{extra} {results[0][4]}")
                    continue
                t = statistics.median(r[1] for r in results)
                integrates.append(t)
                print(f"| {n} | {results[0][3]} | {results[0][2]} | {b:.1f} | {t:.1f} | {1000 * b / n:.1f} | {1000 * t / n:.1f} |{extra}")
                sys.stdout.flush()
            print(f"\nscaling exponent (log-log fit over n = {', '.join(map(str, ns))}): "
                  f"build {exponent(ns, builds):.2f}, run {exponent(ns[:len(integrates)] if integrates else [], integrates):.2f}")


if __name__ == "__main__":
    main()
