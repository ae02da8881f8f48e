#!/usr/bin/env python3
"""Build time and memory against size: load -> compiled, per pass, for one or more momenta_bench
binaries (e.g. before and after a change), on
  chain  the spring-damper chain written out, every component named (bench/gen_chain.py), and
  rc     the RC ladder written as arrays (models/rc_ladder.yaml, -p n=N).
Each size is a fresh `momenta_bench --build-only --repeat 1` process (so max RSS is that build's
peak); the figures are CPU times of the process (load) and of the building thread (each pass),
medians over --runs runs (1 run from --single-run-from components on, default 100 000). Prints Markdown tables: per size the
time per pass, total, µs/component, max RSS, bytes/component (the increase of max RSS over the
smallest size, per added component), and the scaling exponent of the total against the previous
size (log of the time ratio over log of the size ratio; 1 is linear).

usage: bench/build_scaling.py --bench LABEL=PATH [--bench LABEL=PATH ...]
                              [--chain 5,50,500,5000,50000] [--rc 5,50,500,5000,50000,500000]
                              [--runs 3] [--single-run-from 100000] [--tmp DIR] [--hugepages]
A benchmark, not a test.
"""
import argparse, math, os, statistics, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
PASSES = ["load", "flatten", "structural_parameters", "alias_elimination", "index_reduction",
          "structural_analysis", "pruning", "causalisation", "compilation"]


def run_once(bench, model, params, env):
    cmd = [bench, "--model", model, "--build-only", "--repeat", "1"]
    for p in params:
        cmd += ["-p", p]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, env=env).stdout
    fields, components = {}, None
    for line in out.splitlines():
        if line.startswith("# momenta_bench"):
            for kv in line.split():
                if kv.startswith("components="):
                    components = int(kv.split("=")[1])
        if line.startswith("run="):
            for kv in line.split():
                k, v = kv.split("=", 1)
                try:
                    fields[k] = float(v)
                except ValueError:
                    pass
    row = {"components": components, "rss_mb": fields["max_rss_mb"], "load": fields["load_cpu_s"]}
    for p in PASSES[1:]:
        row[p] = fields.get("pass_%s_cpu_s" % p, 0.0)
    row["total"] = row["load"] + sum(row[p] for p in PASSES[1:])
    return row


def measure(bench, model, params, runs, env):
    rows = [run_once(bench, model, params, env) for _ in range(runs)]
    med = {k: statistics.median(r[k] for r in rows) for k in rows[0]}
    med["runs"] = runs
    return med


def table(title, rows):
    print("\n#### %s\n" % title)
    head = ["components", "runs"] + PASSES + ["total (s)", "µs/comp.", "max RSS (MB)", "bytes/comp.", "exponent"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---:|" * len(head))
    base_rss, base_n = rows[0]["rss_mb"], rows[0]["components"]
    prev = None
    for r in rows:
        n = r["components"]
        per = (r["rss_mb"] - base_rss) * 1048576 / (n - base_n) if n > base_n else float("nan")
        expo = ""
        if prev and r["total"] > 0 and prev["total"] > 0:
            expo = "%.2f" % (math.log(r["total"] / prev["total"]) / math.log(n / prev["components"]))
        cells = ["{:,}".format(n).replace(",", " "), str(r["runs"])]
        cells += ["%.3g" % r[p] for p in PASSES]
        cells += ["%.3g" % r["total"], "%.1f" % (1e6 * r["total"] / n), "%.0f" % r["rss_mb"],
                  "" if math.isnan(per) else "%.0f" % per, expo]
        print("| " + " | ".join(cells) + " |")
        prev = r
    sys.stdout.flush()


# What momenta sets when it restarts itself for a large build (app/huge_pages.cc, Restart);
# momenta_bench does not restart itself.
HUGE_PAGES_TUNABLES = ("glibc.malloc.hugetlb=1:glibc.malloc.mmap_max=0:"
                       "glibc.malloc.trim_threshold=4294967295")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bench", action="append", required=True, help="LABEL=path to momenta_bench")
    ap.add_argument("--chain", default="5,50,500,5000,50000")
    ap.add_argument("--rc", default="5,50,500,5000,50000,500000")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--tmp", default=None)
    ap.add_argument("--single-run-from", type=int, default=100000,
                    help="one run only from this many components on")
    ap.add_argument("--hugepages", action="store_true",
                    help="also run each binary with the tunables momenta restarts itself with for a large "
                         "build (app/huge_pages.cc: malloc's memory in transparent huge pages, freed memory "
                         "kept for reuse)")
    a = ap.parse_args()
    tmp = a.tmp or tempfile.mkdtemp(prefix="momenta-build-scaling.")
    chain = [int(x) for x in a.chain.split(",") if x]
    rc = [int(x) for x in a.rc.split(",") if x]
    configs = []
    for label_path in a.bench:
        label, path = label_path.split("=", 1)
        configs.append((label, path, dict(os.environ)))
        if a.hugepages:
            env = dict(os.environ, GLIBC_TUNABLES=HUGE_PAGES_TUNABLES)
            configs.append((label + ", huge pages", path, env))
    for label, path, env in configs:
        rows = []
        for n in chain:
            model = os.path.join(tmp, "chain%d.yaml" % n)
            if not os.path.exists(model):
                subprocess.run([sys.executable, os.path.join(HERE, "gen_chain.py"), str(n), "-o", model], check=True)
            runs = a.runs if 2 * n + 3 < a.single_run_from else 1
            rows.append(measure(path, model, [], runs, env))
        if rows:
            table("%s: spring-damper chain written out (bench/gen_chain.py)" % label, rows)
        rows = []
        for n in rc:
            runs = a.runs if 2 * n + 2 < a.single_run_from else 1
            rows.append(measure(path, os.path.join(REPO, "models", "rc_ladder.yaml"), ["n=%d" % n], runs, env))
        if rows:
            table("%s: RC ladder as arrays (models/rc_ladder.yaml -p n=N)" % label, rows)


if __name__ == "__main__":
    main()
