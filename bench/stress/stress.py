#!/usr/bin/env python3
"""momenta's numerical stress suite: what each extreme costs and what it gives.

Generates models into a temporary directory, runs the CLI on each (`--repeat` times; the median
wall time of the whole process: load, build, simulate, write) and prints Markdown tables, one row a
case: outcome, IDA steps, residual evaluations, time, error against a closed form.
  stiffness   a mass (1 kg) on a spring c = 1e3 .. 1e12 N/m, pushed by F = c * 1 mm, 0.1 s;
              without damping and with damping ratio 0.5 (SpringDamper). Error: max |s - exact| / 1 mm.
  mass ratio  a 1 kg mass on a 1 Hz spring, x0 = 1 m, carrying a light mass m = 1e-3 .. 1e-9 kg on
              a 1 N/m spring, undamped and critically damped; 2 s. Error: max |s_heavy - cos(2 pi t)|
              (the limit m -> 0; the exact answer differs from it by O(m)).
  undamped    a 1 Hz oscillator over 1e4 periods against rtol, the BDF order and the amplitude (the
              absolute tolerance is rtol x 1 m unless --atol is given): energy error
              |E(T)/E(0) - 1| and phase error at T; and the same oscillator with SUNDIALS directly
              (bench/stress/conservative.cc): IDA, CVODE Adams, CVODE BDF.
  sliding     relations whose branches each drive the relation back (sign friction at v = 0; a
              sliding-mode controller on v + s = 0): the outcome must be a named chattering error.
  impacts     rows of N touching balls (Newton's cradle, e = 1) struck from one side, and from both
              sides at the same instant: momentum and energy errors after the impacts.
  singular    the slider-crank (models/slider_crank.yaml) with the rod length l = R (1 + eps): as eps
              -> 0 the constraint Jacobian becomes singular where the crank passes -pi/2. Error:
              max |guide.s - (R cos theta + sqrt(l^2 - R^2 sin^2 theta))|.
usage: bench/stress/stress.py [--momenta build/app/momenta] [--repeat 3] [--only NAME,...]
A benchmark, not a test: it asserts nothing. The figures are in bench/RESULTS.md.
"""
import argparse, csv, math, os, re, shutil, statistics, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
TIMEOUT = 300


def run(args, model, extra, repeat):
    """Runs `momenta simulate model extra` `repeat` times; returns (outcome, steps, resid, median s, csv)."""
    out = os.path.join(args.tmp, "out.csv")
    if os.path.exists(out):
        os.remove(out)
    times, proc = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        try:
            proc = subprocess.run([args.momenta, "simulate", model, "-o", out] + extra, capture_output=True,
                                  text=True, timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            return f"hang (> {TIMEOUT} s)", "-", "-", TIMEOUT, None
        times.append(time.perf_counter() - t0)
        if time.perf_counter() - t0 > 5:
            break  # long runs once
    m = re.search(r"(\d+) steps, (\d+) residual evaluations", proc.stdout)
    steps, resid = (m.group(1), m.group(2)) if m else ("-", "-")
    if proc.returncode == 0:
        outcome = "ok"
    else:
        outcome = f"exit {proc.returncode}: " + Outcome(proc.stderr)
    return outcome, steps, resid, statistics.median(times), out


def Outcome(stderr):
    if "chattering" in stderr:
        return "chattering (named)"
    if "IDA_TOO_MUCH_WORK" in stderr:
        m = re.search(r"oscillation at ([^ ]+) rad/s", stderr)
        return "too much work" + (f", names the {m.group(1)} rad/s mode" if m else "")
    line = stderr.strip().splitlines()[0] if stderr.strip() else "?"
    return line[-90:]


def rows(path):
    with open(path) as f:
        r = list(csv.reader(f))
    return r[0], [[float(x) for x in row] for row in r[1:]]


def write(args, name, text):
    path = os.path.join(args.tmp, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def table(title, header):
    print(f"\n### {title}\n")
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))


def line(cells):
    print("| " + " | ".join(str(c) for c in cells) + " |")
    sys.stdout.flush()


def sci(v):
    """1e+03 -> 1e3."""
    return re.sub(r"e([+-])0*(\d)", lambda m: "e" + ("-" if m.group(1) == "-" else "") + m.group(2), f"{v:.0e}")


def ms(seconds):
    return f"{1e3 * seconds:.0f}"


# ---- stiffness ---------------------------------------------------------------------------------
def stiffness(args):
    table("Stiffness: 1 kg on a spring c, F = c * 1 mm, 0 .. 0.1 s, rtol 1e-6 (default)",
          ["c [N/m]", "damping", "outcome", "steps", "residual evals", "time [ms]", "max error / 1 mm"])
    for c in [1e3, 1e6, 1e9, 1e12]:
        for zeta in [0, 0.5]:
            w = math.sqrt(c)
            spring = ("{type: Spring, c: c}" if zeta == 0 else f"{{type: SpringDamper, c: c, d: {2 * zeta * w}}}")
            model = write(args, "stiff.yaml", f"""model: Stiffness
parameters:
  c: {{value: {c:g}, unit: N/m}}
components:
  ground: {{type: Fixed}}
  spring: {spring}
  mass: {{type: Mass, m: 1, s: {{start: 0, fixed: true}}, v: {{start: 0, fixed: true}}}}
  push: {{type: ConstantForce, f_constant: c*1e-3}}
connections:
  - [ground.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
  - [push.flange, mass.flange_b]
experiment: {{start: 0, stop: 0.1, interval: 1e-3}}
outputs: [mass.s]
""")
            outcome, steps, resid, sec, out = run(args, model, [], args.repeat)
            err = "-"
            if outcome == "ok":
                _, data = rows(out)
                wd = w * math.sqrt(1 - zeta * zeta)
                exact = lambda t: 1e-3 * (1 - math.exp(-zeta * w * t) * (math.cos(wd * t) + zeta / math.sqrt(
                    1 - zeta * zeta) * math.sin(wd * t)))
                err = f"{max(abs(r[1] - exact(r[0])) for r in data) / 1e-3:.1e}"
            line([sci(c), "none" if zeta == 0 else "ratio 0.5", outcome, steps, resid, ms(sec), err])


# ---- mass ratio --------------------------------------------------------------------------------
def mass_ratio(args):
    table("Mass ratio: a light mass m on 1 N/m riding a 1 kg mass on a 1 Hz spring, 0 .. 2 s",
          ["m / M", "light mode", "outcome", "steps", "residual evals", "time [ms]", "max error [m]"])
    for r in [1e-3, 1e-6, 1e-9]:
        for damped in [False, True]:
            d = 2 * math.sqrt(r) if damped else 0
            model = write(args, "ratio.yaml", f"""model: MassRatio
components:
  ground: {{type: Fixed}}
  spring: {{type: Spring, c: {4 * math.pi ** 2!r}}}
  heavy: {{type: Mass, m: 1, s: {{start: 1, fixed: true}}, v: {{start: 0, fixed: true}}}}
  link: {{type: SpringDamper, c: 1, d: {d!r}}}
  light: {{type: Mass, m: {r:g}, s: {{start: 1, fixed: true}}, v: {{start: 0, fixed: true}}}}
connections:
  - [ground.flange, spring.flange_a]
  - [spring.flange_b, heavy.flange_a]
  - [heavy.flange_b, link.flange_a]
  - [link.flange_b, light.flange_a]
experiment: {{start: 0, stop: 2, interval: 0.01}}
outputs: [heavy.s, light.s]
""")
            outcome, steps, resid, sec, out = run(args, model, [], args.repeat)
            err = "-"
            if outcome == "ok":
                _, data = rows(out)
                err = f"{max(abs(row[1] - math.cos(2 * math.pi * row[0])) for row in data):.1e}"
            mode = f"{sci(math.sqrt(1 / r))} rad/s, " + ("ratio 1" if damped else "undamped")
            line([sci(r), mode, outcome, steps, resid, ms(sec), err])


# ---- long undamped runs ------------------------------------------------------------------------
OSCILLATOR = """model: Oscillator
components:
  ground: {type: Fixed}
  spring: {type: Spring, c: 39.47841760435743}
  mass: {type: Mass, m: 1, s: {start: 1, fixed: true}, v: {start: 0, fixed: true}}
connections:
  - [ground.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
experiment: {start: 0, stop: 10000, interval: 0.25}
outputs: [mass.s, mass.v]
"""


def energy_phase(out, amplitude):
    _, data = rows(out)
    t, s, v = data[-1]
    w = 2 * math.pi
    energy = (s * s + v * v / (w * w)) / amplitude ** 2
    phase = math.atan2(-v / w, s)
    return abs(energy - 1), abs(math.remainder(phase - w * t, 2 * math.pi))


def undamped(args):
    model = write(args, "osc.yaml", OSCILLATOR)
    small = write(args, "osc_small.yaml", OSCILLATOR.replace("start: 1, fixed", "start: 0.1, fixed"))
    table("Undamped 1 Hz oscillator over 1e4 periods (momenta simulate); amplitude 1 m unless said",
          ["rtol", "options", "outcome", "steps", "residual evals", "time [ms]", "energy error", "phase error [rad]"])
    cases = [(1e-6, [], 1), (1e-6, ["--interval", "20"], 1), (1e-6, ["--max-order", "3"], 1), (1e-7, [], 1),
             (1e-8, [], 1), (1e-8, ["--max-order", "3"], 1), (1e-9, [], 1), (1e-10, [], 1), (1e-6, [], 0.1),
             (1e-6, ["--atol", "1e-7"], 0.1), (1e-8, [], 0.1)]
    for rtol, extra, amplitude in cases:
        outcome, steps, resid, sec, out = run(args, model if amplitude == 1 else small,
                                              ["--rtol", str(rtol)] + extra, args.repeat)
        e, p = energy_phase(out, amplitude) if outcome == "ok" else ("-", "-")
        options = " ".join(extra) or "interval 0.25"
        if amplitude != 1:
            options += f", amplitude {amplitude:g} m"
        line([sci(rtol), options, outcome, steps, resid, ms(sec),
              f"{e:.1e}" if e != "-" else e, f"{p:.1e}" if p != "-" else p])
    conservative(args)


def conservative(args):
    exe = os.path.join(args.tmp, "conservative")
    build = ["g++", "-O2", "-std=c++17", os.path.join(HERE, "conservative.cc"), "-o", exe, "-lsundials_cvode",
             "-lsundials_ida", "-lsundials_nvecserial", "-lsundials_sunmatrixdense", "-lsundials_sunlinsoldense",
             "-lsundials_sunnonlinsolfixedpoint"]
    if subprocess.run(build, capture_output=True).returncode != 0:
        print("\n(conservative.cc not built: the system's SUNDIALS with CVODE, libsundials-dev, is needed)")
        return
    table("The same oscillator with SUNDIALS directly (bench/stress/conservative.cc), 1e4 periods",
          ["method", "rtol", "steps", "f evals", "time [ms]", "energy error", "phase error [rad]"])
    for method in ["ida", "adams", "bdf"]:
        for rtol in [1e-6, 1e-8, 1e-10]:
            times, fields = [], {}
            for _ in range(args.repeat):
                p = subprocess.run([exe, "--method", method, "--rtol", str(rtol)], capture_output=True, text=True)
                fields = dict(kv.split("=") for kv in p.stdout.split())
                times.append(float(fields["seconds"]))
                if times[-1] > 5:
                    break
            name = {"ida": "IDA (BDF, DAE)", "adams": "CVODE Adams", "bdf": "CVODE BDF"}[method]
            line([name, sci(rtol), fields["steps"], fields["fevals"], ms(statistics.median(times)),
                  f"{float(fields['energy_error']):.1e}", f"{float(fields['phase_error']):.1e}"])


# ---- sliding modes -----------------------------------------------------------------------------
SIGN_FRICTION = """model: SignFriction
define:
  Coulomb:
    connectors: {flange: Flange}
    parameters: {F: {value: 1, unit: N}}
    variables: {v: {unit: m/s}}
    equations:
      - v = der(flange.s)
      - flange.f = if v > 0 then F else -F
components:
  mass: {type: Mass, m: 1, s: {start: 0, fixed: true}, v: {start: 1, fixed: true}}
  friction: {type: Coulomb, F: 1}
connections:
  - [friction.flange, mass.flange_a]
experiment: {start: 0, stop: 2, interval: 0.01}
outputs: [mass.s, mass.v]
"""

SLIDING_CONTROL = """model: SlidingControl
define:
  Relay:
    connectors: {flange: Flange}
    parameters: {F: {value: 10, unit: N}, T: {value: 1, unit: s}}
    variables: {v: {unit: m/s}, s: {unit: m}}
    equations:
      - s = flange.s
      - v = der(s)
      - flange.f = if v + s/T > 0 then F else -F  # the mass receives -flange.f
components:
  mass: {type: Mass, m: 1, s: {start: 1, fixed: true}, v: {start: 0, fixed: true}}
  relay: {type: Relay, F: 10}
connections:
  - [relay.flange, mass.flange_a]
experiment: {start: 0, stop: 5, interval: 0.01}
outputs: [mass.s, mass.v]
"""


def sliding(args):
    table("Sliding modes (each branch drives the relation back)",
          ["model", "outcome", "steps", "residual evals", "time [ms]", "rows kept up to"])
    for name, text in [("sign friction, v(0) = 1 m/s (sticks at t = 1 s)", SIGN_FRICTION),
                       ("relay control on v + s = 0, s(0) = 1 m", SLIDING_CONTROL)]:
        model = write(args, "slide.yaml", text)
        outcome, steps, resid, sec, out = run(args, model, [], args.repeat)
        kept = f"t = {rows(out)[1][-1][0]:g} s" if os.path.exists(out) else "-"
        line([name, outcome, steps, resid, ms(sec), kept])


# ---- simultaneous impacts ----------------------------------------------------------------------
def cradle(n, both):
    gap_start = "(if i == 1 then -gap else 0)" + (" + (if i == n then gap else 0)" if both else "")
    v_start = "if i == 1 then v0 else " + ("(if i == n then -v0 else 0)" if both else "0")
    return f"""model: Cradle
parameters:
  n: {{value: {n}, type: Integer}}
  m: {{value: 0.1, unit: kg}}
  r: {{value: 0.02, unit: m}}
  v0: {{value: 1, unit: m/s}}
  gap: {{value: 0.05, unit: m}}
components:
  ball: {{type: Mass, count: n, m: m, L: 2*r,
         s: {{start: "2*r*(i - 1) + {gap_start}", fixed: true}},
         v: {{start: "{v_start}", fixed: true}}}}
  contact: {{type: Impact, count: n - 1, e: 1}}
connections:
  - for: i in 1:n-1
    connect: ["ball[i].flange_b", "contact[i].flange_a"]
  - for: i in 1:n-1
    connect: ["contact[i].flange_b", "ball[i+1].flange_a"]
experiment: {{start: 0, stop: 0.2, tolerance: 1e-8, interval: 0.001}}
outputs: [{", ".join(f'"ball[{k}].v"' for k in range(1, n + 1))}]
"""


def impacts(args):
    table("Simultaneous impacts: N touching balls (0.1 kg, e = 1), struck at 1 m/s, 0 .. 0.2 s, rtol 1e-8",
          ["N", "struck from", "outcome", "steps", "residual evals", "time [ms]", "momentum error", "energy error",
           "first / last ball v"])
    for n in [5, 20, 100]:
        for both in [False, True]:
            model = write(args, "cradle.yaml", cradle(n, both))
            outcome, steps, resid, sec, out = run(args, model, [], args.repeat)
            pe = ee = fl = "-"
            if outcome == "ok":
                _, data = rows(out)
                v = data[-1][1:]
                p0 = 0.0 if both else 1.0
                e0 = 2.0 if both else 1.0
                pe = f"{abs(sum(v) - p0):.1e}"
                ee = f"{abs(sum(x * x for x in v) / e0 - 1):.1e}"
                fl = f"{v[0]:.4f} / {v[-1]:.4f}"
            line([n, "both ends at once" if both else "one end", outcome, steps, resid, ms(sec), pe, ee, fl])


# ---- near-singular constraint Jacobian ---------------------------------------------------------
def singular(args):
    table("Near-singular constraints: slider-crank with l = R (1 + eps), R = 0.1 m, 0 .. 5 s, rtol 1e-6",
          ["eps", "outcome", "steps", "residual evals", "time [ms]", "max position error [m]"])
    model = os.path.join(REPO, "models", "slider_crank.yaml")
    for eps in [2.5, 1e-1, 1e-2, 1e-4, 1e-6, 0]:
        l = 0.1 * (1 + eps)
        outcome, steps, resid, sec, out = run(args, model, ["-p", f"l={l!r}"], args.repeat)
        err = "-"
        if out and os.path.exists(out) and outcome == "ok":
            header, data = rows(out)
            ip, ig = header.index("crank.phi"), header.index("guide.s")
            exact = lambda th: 0.1 * math.cos(th) + math.sqrt(max(0.0, l * l - (0.1 * math.sin(th)) ** 2))
            err = f"{max(abs(row[ig] - exact(row[ip])) for row in data):.1e}"
        line([f"{eps:g}", outcome, steps, resid, ms(sec), err])


SUITES = {"stiffness": stiffness, "ratio": mass_ratio, "undamped": undamped, "sliding": sliding,
          "impacts": impacts, "singular": singular}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--momenta", default=os.path.join(REPO, "build", "app", "momenta"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--only", default=",".join(SUITES))
    args = ap.parse_args()
    args.tmp = tempfile.mkdtemp(prefix="momenta-stress.")
    try:
        for name in args.only.split(","):
            SUITES[name](args)
    finally:
        shutil.rmtree(args.tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
