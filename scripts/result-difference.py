#!/usr/bin/env python3
"""How far a run's results moved, measured in the integration tolerance.

    scripts/result-difference.py OLD.csv NEW.csv [MODEL.yaml | --rtol R] [--atol A]

Prints the largest |new - old| / (rtol*|old| + atol) over every column and every row at a time
both files hold (IDA's weighted error for one value: below 1 is within the tolerance the run was
asked for), with the column and time where it is reached, and the rows that only one file holds
(an event that moved). rtol is the model's experiment `tolerance` (1e-6 unless set) or --rtol;
atol is --atol, else rtol (the solver's default; it scales atol by each variable's nominal, taken
here as 1). Exit code 0; 2 on bad input. scripts/same-behaviour.sh prints it for each model whose
results differ.
"""
import argparse
import csv
import math
import re
import sys


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ValueError(f"{path}: empty")
    return rows[0], [[float(x) for x in r] for r in rows[1:] if r]


def model_rtol(path):
    """The experiment's tolerance in a model file, 1e-6 when it names none."""
    with open(path) as f:
        text = f.read()
    m = re.search(r"^experiment:.*?\btolerance:\s*([0-9.eE+-]+)", text, re.M | re.S)
    return float(m.group(1)) if m else 1e-6


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("model", nargs="?")
    ap.add_argument("--rtol", type=float)
    ap.add_argument("--atol", type=float)
    a = ap.parse_args()
    try:
        rtol = a.rtol if a.rtol is not None else (model_rtol(a.model) if a.model else 1e-6)
        atol = a.atol if a.atol is not None else rtol
        old_head, old = read(a.old)
        new_head, new = read(a.new)
    except (OSError, ValueError) as e:
        print(f"result-difference: {e}", file=sys.stderr)
        return 2
    if old_head != new_head:
        print(f"columns differ: {len(old_head)} then {len(new_head)}")
        return 0
    # Rows matched by time; a time that occurs twice (an event's left and right limits) by its
    # occurrence.
    def keyed(rows):
        seen, out = {}, {}
        for r in rows:
            n = seen.get(r[0], 0)
            seen[r[0]] = n + 1
            out[(r[0], n)] = r
        return out

    ko, kn = keyed(old), keyed(new)
    common = [k for k in ko if k in kn]
    worst, where = 0.0, "-"
    for k in common:
        ro, rn = ko[k], kn[k]
        for c in range(1, len(old_head)):
            d = abs(rn[c] - ro[c])
            if d == 0:
                continue
            w = d / (rtol * abs(ro[c]) + atol) if math.isfinite(d) else math.inf
            if w > worst:
                worst, where = w, f"{old_head[c]} at t = {k[0]:g}"
    only = len(ko) - len(common) + len(kn) - len(common)
    print(f"max |new-old|/(rtol*|old|+atol) = {worst:.3g} ({where}; rtol {rtol:g}, atol {atol:g})"
          + (f", {only} rows at times only one run has" if only else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
