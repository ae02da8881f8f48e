#!/usr/bin/env python3
"""What the spring-damper chain's state choice costs and buys (issue 12, item 4).

momenta's states for models/spring_damper_chain.yaml are the masses' velocities, the positions of
masses 2..n-1, and the stretches sd[1].s_rel and sd[n].s_rel (the library's SpringDamper prefers
s_rel and v_rel, as the MSL's does); bench/handwritten_chain.cc integrates every mass's absolute
position and velocity. This script runs the same chain in momenta three ways, so that only the
state choice (and the tolerance weights that follow from it) differs:

  relative   the library's choice (stateSelect: prefer on s_rel, v_rel), unit nominals
  absolute   stateSelect: avoid on s_rel and v_rel: the masses' s and v, the hand-written choice
  library    the model as written: the library's choice and its nominal 1e-4 on s_rel

The first two use a copy of the library's SpringDamper without the nominal (so atol is the same
scalar for every state, as IDASStolerances in the hand-written program) and without the heat port
(unused here). Each runs at rtol = atol = --tol (1e-6, the model's tolerance) against a reference
at rtol = atol = --ref-tol (1e-10; the two choices' references agree to about 1e-9, printed). The
errors are the largest over all output rows (t = 0, 0.1, ..., 10) of:

  s_n     mass[n].s, the driven end's absolute position (about n metres)
  v_n     mass[n].v
  f_n     sd[n].f, the force in the last spring-damper (about 10 N)
  f_mid   sd[n/2].f, a force halfway down the chain

The hand-written program is run too (same tolerance), twice: with its output interval 0.1 s (as
bench/run.sh runs it) and with a single output at t = 10. IDA takes its first step as 0.001 of the
distance to the first output time it is asked for; momenta aims its first step one output
interval ahead, so the first run starts as momenta does (before that change momenta aimed at the
stop time, as the second run does). bench/first_step.py varies that first step. The hand-written program
prints its final values only: its errors are at t = 10. Timing is the process's CPU time
(/usr/bin/time; the hand-written program's own CPU clock), one run per configuration: steps and
errors are deterministic.

Usage: bench/chain_states.py [--momenta build/app/momenta] [--handwritten build/bench/handwritten_chain]
       [--sizes 10,100,1000,10000] [--tol 1e-6] [--ref-tol 1e-10]
"""
import argparse, csv, os, re, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)

# The library's SpringDamper (components/translational.yaml) without the nominal and the heat
# port; SELECT is the stateSelect of s_rel and v_rel.
SPRING_DAMPER = """define:
  ChainSpringDamper:
    doc: The library's SpringDamper without the nominal on s_rel and without the heat port.
    parameters:
      c: {value: 1, unit: N/m}
      d: {value: 1, unit: N.s/m}
      s_rel0: {value: 0, unit: m}
    connectors: {flange_a: Flange, flange_b: Flange}
    variables:
      s_rel: {unit: m, start: 0, stateSelect: SELECT}
      v_rel: {unit: m/s, start: 0, stateSelect: SELECT}
      f: {unit: N}
    equations:
      - s_rel = flange_b.s - flange_a.s
      - v_rel = der(s_rel)
      - flange_b.f = f
      - flange_a.f = -f
      - f = c*(s_rel - s_rel0) + d*v_rel
"""
OUTPUTS = ["mass[n].s", "mass[n].v", "sd[n].f", "sd[HALF].f"]


def variant_yaml(kind, n):
    text = open(os.path.join(REPO, "models", "spring_damper_chain.yaml")).read()
    outputs = "outputs: [%s]" % ", ".join('"%s"' % o.replace("HALF", str(max(1, n // 2))) for o in OUTPUTS)
    text = re.sub(r"\noutputs:[^\n]*", "\n" + outputs, text)
    if kind == "library":
        return text
    select = {"relative": "prefer", "absolute": "avoid"}[kind]
    text = text.replace("{type: SpringDamper,", "{type: ChainSpringDamper,")
    return text.replace("\ncomponents:", "\n" + SPRING_DAMPER.replace("SELECT", select) + "components:", 1)


def run_momenta(momenta, yaml_path, n, tol, tmp):
    out, usage = os.path.join(tmp, "out.csv"), os.path.join(tmp, "usage")
    cmd = ["/usr/bin/time", "-f", "%U %S", "-o", usage, momenta, "simulate", yaml_path, "-p", "n=%d" % n,
           "--rtol", str(tol), "--atol", str(tol), "--linear-solver", "dense" if n <= 10 else "klu", "-o", out]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("%s failed:\n%s%s" % (" ".join(cmd), p.stdout, p.stderr))
    m = re.search(r": (\d+) steps, (\d+) residual evaluations", p.stdout)
    user, system = open(usage).read().split()[-2:]
    with open(out) as f:
        rows = list(csv.reader(f))
    return {"steps": int(m.group(1)), "residuals": int(m.group(2)), "cpu": float(user) + float(system),
            "header": rows[0],
            "rows": [[float(x) for x in r] for r in rows[1:]]}


def run_handwritten(program, n, tol, interval):
    cmd = [program, "--n", str(n), "--stop", "10", "--rtol", str(tol), "--atol", str(tol), "--linear-solver",
           "dense" if n <= 10 else "klu", "--interval", str(interval), "--repeat", "1"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("%s failed:\n%s%s" % (" ".join(cmd), p.stdout, p.stderr))
    line = [l for l in p.stdout.splitlines() if l.startswith("median")][0]
    fields = dict(kv.split("=") for kv in line.split()[1:])
    return {"steps": int(fields["steps"]), "residuals": int(fields["res_evals"]), "cpu": float(fields["setup_cpu_s"]) + float(fields["solve_cpu_s"]),
            "s_n": float(fields["s_n"]), "v_n": float(fields["v_n"])}


def max_errors(run, ref):
    """Largest |run - ref| per output column over rows at the same times."""
    assert len(run["rows"]) == len(ref["rows"]), "different output rows"
    errs = []
    for j in range(1, len(ref["header"])):
        errs.append(max(abs(a[j] - b[j]) for a, b in zip(run["rows"], ref["rows"])))
    return errs


def states_of(momenta, yaml_path, n):
    p = subprocess.run([momenta, "check", yaml_path, "-p", "n=%d" % n], capture_output=True, text=True)
    line = [l for l in p.stdout.splitlines() if l.startswith("states")][0]
    return line.split(": ", 1)[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--momenta", default=os.path.join(REPO, "build", "app", "momenta"))
    ap.add_argument("--handwritten", default=os.path.join(REPO, "build", "bench", "handwritten_chain"))
    ap.add_argument("--sizes", default="10,100,1000,10000")
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--ref-tol", type=float, default=1e-10)
    a = ap.parse_args()
    kinds = ["relative", "absolute", "library"]
    lines = ["| n | run | steps | res. evals | CPU (s) | error s_n, t = 10 | error v_n, t = 10 | max error v_n "
             "| max error f_n (N) | max error f_mid (N) |",
             "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    notes = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in [int(s) for s in a.sizes.split(",")]:
            paths = {}
            for kind in kinds:
                paths[kind] = os.path.join(tmp, "%s.yaml" % kind)
                open(paths[kind], "w").write(variant_yaml(kind, n))
            if n == 10:
                for kind in kinds:
                    notes.append("states of '%s' at n = 10: %s" % (kind, states_of(a.momenta, paths[kind], n)))
            ref = run_momenta(a.momenta, paths["absolute"], n, a.ref_tol, tmp)
            ref_rel = run_momenta(a.momenta, paths["relative"], n, a.ref_tol, tmp)
            notes.append("n = %d: the two references differ by at most %s (s_n, v_n, f_n, f_mid)" % (
                n, ", ".join("%.1e" % e for e in max_errors(ref_rel, ref))))
            end = ref["rows"][-1]
            for kind in kinds:
                r = run_momenta(a.momenta, paths[kind], n, a.tol, tmp)
                e = max_errors(r, ref)
                last = r["rows"][-1]
                lines.append("| %d | momenta, %s | %d | %d | %.3g | %.1e | %.1e | %.1e | %.1e | %.1e |" % (
                    n, kind, r["steps"], r["residuals"], r["cpu"], abs(last[1] - end[1]), abs(last[2] - end[2]),
                    e[1], e[2], e[3]))
                print(lines[-1], file=sys.stderr)
            # The hand-written program with its output interval (IDA's first step is 0.001 of the
            # distance to the first output time, as momenta's) and with one output at the stop time.
            for interval in (0.1, 10):
                h = run_handwritten(a.handwritten, n, a.tol, interval)
                lines.append("| %d | hand-written, first output at %g s | %d | %d | %.3g | %.1e | %.1e | — | — | — |" % (
                    n, interval, h["steps"], h["residuals"], h["cpu"], abs(h["s_n"] - end[1]), abs(h["v_n"] - end[2])))
                print(lines[-1], file=sys.stderr)
    print("\n".join(lines))
    print()
    for note in notes:
        print("- " + note)


if __name__ == "__main__":
    main()
