#!/usr/bin/env python3
"""The spring-damper chain written out, as a user (or a script of theirs) would write it.

Same physics as models/spring_damper_chain.yaml, but without arrays or for-loops: every mass and
spring-damper is its own named component (sd1, mass1, sd2, mass2, ...) and every connection is
listed. n masses give 2n + 3 components (wall, force and sine besides the chain). This is the
build benchmark for "individually named components" (issue 12, item 3).

usage: bench/gen_chain.py N [-o FILE]   (stdout when no file is given)
"""
import argparse, sys


def write_chain(n, out):
    w = out.write
    w("model: SpringDamperChainWrittenOut\n")
    w("doc: The spring-damper chain of models/spring_damper_chain.yaml with n = %d, written out.\n" % n)
    w("components:\n")
    w("  wall: {type: Fixed, s0: 0}\n")
    for i in range(1, n + 1):
        w("  sd%d: {type: SpringDamper, c: 1e4, d: 10, s_rel0: 1}\n" % i)
        w("  mass%d: {type: Mass, m: 1, L: 0, s: {start: %d, fixed: true}, v: {start: 0, fixed: true}}\n" % (i, i))
    w("  force: {type: Force}\n")
    w("  sine: {type: Sine, amplitude: 10, f: 1}\n")
    w("connections:\n")
    w("  - [wall.flange, sd1.flange_a]\n")
    for i in range(1, n + 1):
        w("  - [sd%d.flange_b, mass%d.flange_a]\n" % (i, i))
        if i < n:
            w("  - [mass%d.flange_b, sd%d.flange_a]\n" % (i, i + 1))
    w("  - [mass%d.flange_b, force.flange]\n" % n)
    w("  - [sine.y, force.f]\n")
    w("experiment: {start: 0, stop: 10, tolerance: 1e-6, interval: 0.1}\n")
    w("outputs: [mass%d.s, mass%d.v]\n" % (n, n))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("n", type=int, help="number of masses (and of spring-dampers)")
    ap.add_argument("-o", "--output", help="file to write (default: stdout)")
    a = ap.parse_args()
    if a.n < 1:
        ap.error("n must be at least 1")
    if a.output:
        with open(a.output, "w") as f:
            write_chain(a.n, f)
    else:
        write_chain(a.n, sys.stdout)


if __name__ == "__main__":
    main()
