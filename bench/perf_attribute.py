#!/usr/bin/env python3
"""Attributes the samples of a `perf record --call-graph dwarf` profile of momenta_bench or of a
hand-written IDA program (handwritten_chain, handwritten_rc) to the parts of a simulation.

usage: perf script -i FILE.data -F comm,ip,sym | bench/perf_attribute.py [--title T]

Each sample's stack (leaf first) is classified by the first rule that matches:
  build             below momenta::BuildModel / LoadModelFile (momenta only)
  initialisation    below momenta::SolveInitialization (momenta only)
  residual: program  Program::Run below the IDA residual callback
  residual: wrapper  the rest of the residual callback (register loads, finiteness check)
  jacobian: program  Program::Run below the IDA Jacobian callback
  jacobian: fill     FillMatrix / the rest of the Jacobian callback (CSC copy)
  KLU factor        klu_*factor / klu_*refactor / klu_*analyze (and what they call)
  KLU solve         klu_*solve, lsolve, usolve
  SUNDIALS linsol/matrix  SUNLinSol_*, SUNMatrix_* (e.g. SUNMatZero, copies, scaling)
  NVector ops       N_V* / V* serial kernels called by IDA
  IDA internals     everything else below IDASolve
  event detection   below the simulator's FirstCrossing/Crossed/Locate/NextTimeEvent (state
                    interpolation with IDAGetDky + condition evaluation after each step)
  output rows       below the simulator's EmitGrid/Emit/Outputs (interpolation at output times)
  other             the rest (start-up, libc, kernel outside the above)
Percentages are of all samples, and of the samples of the simulation proper (IDASolve and what it
calls, plus initialisation) so that momenta and hand-written programs can be compared.
"""
import re
import sys
from collections import Counter


def frames(sample_lines):
    out = []
    for line in sample_lines:
        parts = line.strip().split(None, 1)
        if len(parts) == 2:
            out.append(parts[1])
        elif parts:
            out.append("[unknown]")
    return out


def classify(stack):
    joined = "\n".join(stack)
    if "momenta::BuildModel" in joined or "momenta::LoadModelFile" in joined or "BuiltinLibrary" in joined:
        return "build"
    if "momenta::SolveInitialization" in joined:
        return "initialisation"
    in_solve = "IDASolve" in joined
    if not in_solve and re.search(r"FirstCrossing|Crossed|Locate|NextTimeEvent|ZeroCrossings", joined):
        return "event detection (outside IDA)"
    if not in_solve and re.search(r"EmitGrid|Emit\b|::Outputs|IDAGetDky", joined):
        return "output rows (outside IDA)"
    residual_cb = re.search(r"\(anonymous namespace\)::Residual\b|::res\(|Chain::res|RcLadder::res", joined)
    jac_cb = re.search(r"\(anonymous namespace\)::Jacobian\b|jac_sparse|jac_dense", joined)
    leaf = stack[0] if stack else ""
    if re.search(r"klu_\w*(factor|analyze|refactor)|klu_l_kernel|klu_kernel|amd_|colamd|btf_", joined):
        return "KLU factor"
    if re.search(r"klu_\w*solve", joined):
        return "KLU solve"
    if jac_cb:
        if re.search(r"jac_sparse|jac_dense", joined):
            return "jacobian: hand-written"
        if "Program::Run" in leaf:
            return "jacobian: program"
        if re.search(r"jac_sparse|jac_dense", leaf):
            return "jacobian: hand-written"
        return "jacobian: fill/other"
    if residual_cb:
        if re.search(r"Chain::res|RcLadder::res", joined):
            return "residual: hand-written"
        if "Program::Run" in leaf:
            return "residual: program"
        if re.search(r"::res\(|Chain::res|RcLadder::res", leaf):
            return "residual: hand-written"
        return "residual: wrapper"
    if re.search(r"SUNLinSol|SUNMat|SUNSparse|SUNDense|denseGETRF|denseGETRS|DenseGETRF|DenseGETRS", leaf):
        return "SUNDIALS linsol/matrix"
    if in_solve and re.match(r"(N_V|V[A-Z][a-z]|Vaxpy|VLin|VSum|VDiff|VScale)", leaf):
        return "NVector ops"
    if in_solve:
        return "IDA internals"
    return "other"


def main():
    title = ""
    if "--title" in sys.argv:
        title = sys.argv[sys.argv.index("--title") + 1]
    counts = Counter()
    leaves = Counter()
    block = []
    for line in sys.stdin:
        if line.strip() == "":
            if len(block) > 1:
                st = frames(block[1:])
                c = classify(st)
                counts[c] += 1
                leaves[(c, st[0] if st else "?")] += 1
            block = []
            continue
        block.append(line)
    if len(block) > 1:
        st = frames(block[1:])
        counts[classify(st)] += 1
    total = sum(counts.values())
    sim = sum(v for k, v in counts.items() if k not in ("build", "other"))
    order = ["build", "initialisation", "residual: program", "residual: hand-written", "residual: wrapper",
             "jacobian: program", "jacobian: hand-written", "jacobian: fill/other", "KLU factor", "KLU solve",
             "SUNDIALS linsol/matrix", "NVector ops", "IDA internals", "event detection (outside IDA)",
             "output rows (outside IDA)", "other"]
    print(f"### {title}" if title else "###")
    print(f"{total} samples, {sim} in the simulation (initialisation, IDASolve, event checks, output rows)\n")
    print("| part | samples | % of all | % of simulation |")
    print("|---|---:|---:|---:|")
    for k in order:
        if counts.get(k):
            v = counts[k]
            s = f"{100.0 * v / sim:.1f}" if k not in ("build", "other") and sim else ""
            print(f"| {k} | {v} | {100.0 * v / total:.1f} | {s} |")
    print("\nTop leaf functions in the simulation:\n")
    print("| part | function | % of simulation |")
    print("|---|---|---:|")
    sim_leaves = [(k, v) for k, v in leaves.items() if k[0] not in ("build", "other")]
    for (c, fn), v in sorted(sim_leaves, key=lambda kv: -kv[1])[:15]:
        fn = re.sub(r"\s+", " ", fn)[:90]
        print(f"| {c} | `{fn}` | {100.0 * v / sim:.1f} |")


if __name__ == "__main__":
    main()
