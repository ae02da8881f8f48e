#!/usr/bin/env python3
"""Writes the Filter entry of components/blocks_continuous.yaml (MSL Blocks.Continuous.Filter).

The MSL computes the filter's coefficients with functions and sizes its states by `order`; a
momenta type has a fixed structure, so the entry holds N_MAX states and selects, with structural
ifs on the Integer parameters, which of them are real poles, which pairs of conjugate poles and
which are unused (held at 0). Run it after changing the table or N_MAX:
    scripts/gen-filter-yaml.py > /tmp/filter.yaml   (then paste over the Filter entry)
"""
N_MAX = 6

# Normalized Bessel prototypes (MSL Internal.Filter.Utilities.BesselBaseCoefficients):
# order -> (alpha, c1 of the real pole or None, [(c2[i,1], c2[i,2]), ...])
BESSEL = {
    1: (1.002377293007601, 0.9976283451109835, []),
    2: (0.7356641785819585, None, [(0.6159132201783791, 1.359315879600889)]),
    3: (0.5704770156982642, 0.7548574865985343, [(0.4756958028827457, 0.9980615136104388)]),
    4: (0.4737978580281427, None, [(0.4873729247240677, 1.337564170455762),
                                   (0.3877724315741958, 0.7730405590839861)]),
    5: (0.4126226974763408, 0.6645723262620757, [(0.4115231900614016, 1.138349926728708),
                                                 (0.3234938702877912, 0.6205992985771313)]),
    6: (0.3705098000736233, None, [(0.3874508649098960, 1.219740879520741),
                                   (0.3493298843155746, 0.9670265529381365),
                                   (0.2747419229514599, 0.5122165075105700)]),
}


def chain(cases, default):
    """'if c1 then v1 elseif c2 then v2 … else default' from [(c, v)]."""
    s = ""
    for i, (c, v) in enumerate(cases):
        s += ("if " if i == 0 else " elseif ") + f"{c} then {v}"
    return s + f" else {default}" if cases else default


def q(s):
    return '"' + s + '"'


def main():
    P = N_MAX // 2
    out = []
    w = out.append
    w("Filter:")
    w("  doc: \"Low or high pass IIR filter of type CriticalDamping, Bessel, Butterworth or ChebyshevI "
      f"of order 1 to {N_MAX} (MSL Continuous.Filter; band pass and band stop are not here yet).\"")
    w("  parameters:")
    w("    analogFilter: {value: 1, type: Integer, min: 1, max: 4, doc: \"1 CriticalDamping, 2 Bessel, 3 Butterworth, 4 ChebyshevI (MSL Types.AnalogFilter)\"}")
    w("    filterType: {value: 1, type: Integer, min: 1, max: 2, doc: \"1 LowPass, 2 HighPass (MSL Types.FilterType; 3 BandPass and 4 BandStop are not here yet)\"}")
    w(f"    order: {{value: 2, type: Integer, min: 1, max: {N_MAX}, doc: \"order of the filter (at most {N_MAX} here)\"}}")
    w("    f_cut: {value: 1, unit: Hz, min: 1e-300, doc: \"cut-off frequency (the MSL has no default; set it)\"}")
    w("    gain: {value: 1, doc: amplitude of the frequency response at zero frequency}")
    w("    A_ripple: {value: 0.5, min: 1e-300, doc: \"pass band ripple of the Chebyshev filter in dB, below 3 dB here (otherwise not used)\"}")
    w("    f_min: {value: 0, unit: Hz, doc: lower band frequency of band pass and band stop filters (not used here)}")
    w("    normalized: {value: true, type: Boolean, doc: \"true: the amplitude at f_cut is -3 dB; false: the unmodified filter\"}")
    w("    init: {value: 2, type: Integer, min: 1, max: 4, doc: \"1 NoInit, 2 SteadyState, 3 InitialState (x = x_start), 4 InitialOutput (y = y_start, the other states steady) (MSL Types.Init)\"}")
    w(f"    x_start: {{shape: [{N_MAX}], value: 0, doc: initial or guess values of the states}}")
    w("    y_start: {value: 0, doc: initial value of the output}")
    w("    u_nominal: {value: 1, min: 1e-300, doc: nominal value of the input (scales the states)}")
    # Structural selectors.
    w("    criticalDamping: {value: analogFilter == 1, type: Boolean, doc: every pole real (internal)}")
    w("    odd: {value: " + q(" or ".join(f"order == {n}" for n in range(1, N_MAX + 1, 2))) +
      ", type: Boolean, doc: one real pole and conjugate pairs (internal)}")
    w("    highPass: {value: filterType == 2, type: Boolean, doc: high pass (internal)}")
    w("    w_cut: {value: 2*pi*f_cut, unit: rad/s, doc: cut-off angular frequency (internal)}")
    # Prototype (w_cut = 1) coefficients: real pole cr0 and pairs s^2 + c1*s + c0.
    w("    alphaCD: {value: \"if normalized then sqrt(10^(3/10/order) - 1) else 1\", doc: frequency correction of the critically damped filter (internal)}")
    w("    alphaBessel: {value: " + q(chain([(f"order == {n}", repr(BESSEL[n][0])) for n in BESSEL], "1")) +
      ", doc: frequency correction of the Bessel filter (internal)}")
    w("    sB: {value: \"if normalized then 1 else alphaBessel\", doc: scaling of the Bessel prototype (internal)}")
    w("    epsilon: {value: \"sqrt(10^(A_ripple/10) - 1)\", doc: Chebyshev ripple factor (internal)}")
    w("    fac: {value: \"log(1/epsilon + sqrt(1/epsilon^2 + 1))/order\", doc: asinh(1/epsilon)/order (internal)}")
    # -3 dB frequency of the DC-normalised Chebyshev prototype: T_n(alpha) = T below, in closed
    # form where the MSL iterates (normalizationFactor); valid for a ripple below 3 dB.
    w("    T3dB: {value: \"if odd then 1/epsilon else sqrt(1 + 2*epsilon^2)/epsilon\", doc: Chebyshev polynomial's value at the -3 dB frequency (internal)}")
    w("    alphaCheb: {value: \"if normalized then cosh(log(T3dB + sqrt(T3dB^2 - 1))/order) else 1\", doc: \"frequency correction of the Chebyshev filter, cosh(acosh(T3dB)/order) (internal)\"}")
    cr_cases = [("analogFilter == 1", "1/alphaCD"),
                ("analogFilter == 2", chain([(f"order == {n}", f"1/({BESSEL[n][1]!r}*sB)")
                                             for n in BESSEL if BESSEL[n][1] is not None], "1")),
                ("analogFilter == 3", "1")]
    w("    cr0: {value: " + q(chain(cr_cases, "sinh(fac)/alphaCheb")) + ", doc: real pole of the prototype (internal)}")
    for i in range(1, P + 1):
        bc0 = chain([(f"order == {n}", f"1/({BESSEL[n][2][i-1][0]!r}*sB^2)")
                     for n in BESSEL if len(BESSEL[n][2]) >= i], "1")
        bc1 = chain([(f"order == {n}", f"{BESSEL[n][2][i-1][1]!r}/({BESSEL[n][2][i-1][0]!r}*sB)")
                     for n in BESSEL if len(BESSEL[n][2]) >= i], "0")
        th = f"(if odd then {i}*pi/order else {2*i-1}*pi/(2*order))"
        c0 = chain([(f"analogFilter == 1 or order < {2*i}", "1"), ("analogFilter == 2", bc0),
                    ("analogFilter == 3", "1")], f"(cosh(fac)^2 - cos({th})^2)/alphaCheb^2")
        c1 = chain([(f"analogFilter == 1 or order < {2*i}", "0"), ("analogFilter == 2", bc1),
                    ("analogFilter == 3", f"-2*cos(pi*(0.5 + {i - 0.5}/order))")],
                   f"2*sinh(fac)*cos({th})/alphaCheb")
        w(f"    c0_{i}: {{value: {q(c0)}, doc: s^0 coefficient of conjugate pair {i} of the prototype (internal)}}")
        w(f"    c1_{i}: {{value: {q(c1)}, doc: s^1 coefficient of conjugate pair {i} of the prototype (internal)}}")
    # Roots at w_cut (MSL Internal.Filter.roots.lowPass / highPass).
    w("    r: {value: \"if highPass then -w_cut/cr0 else -w_cut*cr0\", unit: 1/s, doc: real eigenvalue (internal)}")
    for i in range(1, P + 1):
        w(f"    cc0_{i}: {{value: \"if highPass then w_cut^2/c0_{i} else w_cut^2*c0_{i}\", doc: (internal)}}")
        w(f"    cc1_{i}: {{value: \"if highPass then w_cut*c1_{i}/c0_{i} else w_cut*c1_{i}\", doc: (internal)}}")
        w(f"    a_{i}: {{value: -cc1_{i}/2, doc: real part of the eigenvalues of pair {i} (internal)}}")
        w(f"    b_{i}: {{value: \"sqrt(cc0_{i} - a_{i}^2)\", doc: imaginary part of the eigenvalues of pair {i} (internal)}}")
        w(f"    ku_{i}: {{value: cc0_{i}/b_{i}, doc: input gain of pair {i} (internal)}}")
        w(f"    k1_{i}: {{value: \"if a_{i} == 0 then 0 else 2*a_{i}/ku_{i}\", doc: high pass output gain of pair {i} (internal)}}")
        w(f"    k2_{i}: {{value: \"if a_{i} == 0 then 0 else (1 - (b_{i}/a_{i})^2)/(1 + (b_{i}/a_{i})^2)\", doc: high pass output gain of pair {i} (internal)}}")
    w("  connectors:")
    w("    u: {type: RealInput, doc: input signal}")
    w("    y: {type: RealOutput, doc: filtered output signal}")
    w("  variables:")
    w(f"    x: {{shape: [{N_MAX}], start: x_start, doc: \"filter states, the MSL's x[1..nx]; those past the order are 0\"}}")
    w(f"    uu: {{shape: [{N_MAX + 1}], doc: \"input of each first or second order section, uu[1] = u/u_nominal; past the last section uu repeats its output\"}}")
    w("  equations:")
    w("    - uu[1] = u/u_nominal")

    # Element k: which section it belongs to, in each layout.
    def element_eq(k):
        real = lambda inp: f"der(x[{k}]) - r*(x[{k}] - uu[{inp}])"
        def pair(i, first, inp):
            e1, e2 = (k, k + 1) if first else (k - 1, k)
            if first:
                return f"der(x[{e1}]) - (a_{i}*x[{e1}] - b_{i}*x[{e2}] + ku_{i}*uu[{inp}])"
            return f"der(x[{e2}]) - (b_{i}*x[{e1}] + a_{i}*x[{e2}])"
        cd = real(k)
        if k == 1:
            od = real(1)
        elif k % 2 == 0 and k + 1 > N_MAX:
            od = f"x[{k}]"  # its pair would pass N_MAX: an even order, never this layout
        else:
            i = k // 2
            od = pair(i, k % 2 == 0, i + 1)
        i = (k + 1) // 2
        ev = pair(i, k % 2 == 1, i)
        return f"0 = if order < {k} then x[{k}] elseif criticalDamping then {cd} elseif odd then {od} else {ev}"

    def section_eq(m):
        through = f"uu[{m+1}] - uu[{m}]"
        def real_out(e):
            return f"uu[{m+1}] - (if highPass then uu[{m}] - x[{e}] else x[{e}])"
        def pair_out(i, e1, e2):
            return (f"uu[{m+1}] - (if highPass then k1_{i}*x[{e1}] + k2_{i}*x[{e2}] + uu[{m}] else x[{e2}])")
        cd = f"if order < {m} then {through} else {real_out(m)}"
        if m == 1:
            od = real_out(1)
        else:
            i = m - 1
            od = (through if 2*i + 1 > N_MAX else
                  f"if order < {2*i+1} then {through} else {pair_out(i, 2*i, 2*i+1)}")
        ev = (through if 2*m > N_MAX else
              f"if order < {2*m} then {through} else {pair_out(m, 2*m-1, 2*m)}")
        return f"0 = if criticalDamping then ({cd}) elseif odd then ({od}) else ({ev})"

    for k in range(1, N_MAX + 1):
        w(f"    - {q(element_eq(k))}")
    for m in range(1, N_MAX + 1):
        w(f"    - {q(section_eq(m))}")
    w(f"    - y = gain*u_nominal*uu[{N_MAX + 1}]")
    w("  initial_equations:")
    for k in range(1, N_MAX + 1):
        w(f"    - \"0 = if order < {k} then 0 elseif init == 2 then der(x[{k}]) elseif init == 3 then x[{k}] - x_start[{k}] "
          f"elseif init == 4 and order > {k} then der(x[{k}]) else 0\"")
    w("    - \"0 = if init == 4 then y - y_start else 0\"")
    print("\n".join(out))


main()
