"""Forward dynamics of a motor-driven four-bar, loopkin against SciPy
integrating a hand-written equation of motion, in one process: CPU time of
a 3 s start-up from rest.

    pip install ./python numpy scipy
    python python/benchmarks/forward_scipy.py [--rounds N]

The mechanism: crank AB = 0.04, coupler BC = 0.12, rocker DC = 0.10,
ground AD = 0.11 (a crank-rocker, C above the ground line), the three bars'
masses at their midpoints with their inertias, gravity, a DC motor on the
crank (0.5 N·m at stall, none at 60 rad/s), and a spring-damper (50 N/m,
free length 0.10 m, 2 N·s/m) from P0 = (0.05, 0.15) to the coupler's
centre; from rest at φ = 0.

SciPy's side is what one writes by hand for a single degree of freedom:
the Lagrange equation M(φ) φ̈ + ½ M'(φ) φ̇² + V'(φ) = Q as ``rhs(t, y)``
on plain floats, with C from the intersection of the two circles, the
kinematic coefficients θ₃', θ₄' and θ₃'', θ₄'' from the velocity and
acceleration loop equations, and the coupler centre's velocity and
acceleration coefficients. The angles θ₃, θ₄ are never formed (their
cosines and sines are C's coordinates over b and c), so one evaluation
calls sin once, cos once, sqrt twice (the circle intersection and the
spring's length) and atan2 never. It is integrated by ``solve_ivp`` with
RK45 and with Radau (Radau's Jacobian by SciPy's default finite
differences, no analytic Jacobian given), rtol = atol = 1e-10,
dense_output=False, t_eval=None. loopkin: ``Mechanism.forward`` on the
definition below (the mechanism assembled at every evaluation,
Dormand–Prince 5(4)), tolerance 1e-10, 300 samples.

Before timing, ``rhs`` integrated by DOP853 at 1e-13 is checked against
the 34-digit reference of tests/reference/four_bar_forward.py (φ and φ̇ at
eight instants, to 1e-10 relative), and loopkin's φ(3 s) against that
DOP853 run (to 1e-7 relative). Each round runs every variant once in turn
(thread CPU time, ``time.thread_time``); the medians and the ranges over
the rounds are printed, and the ratios per round; then DOP853's steps,
evaluations and error at 1e-10 and 1e-11, counted only. "steps" is
``len(sol.t) - 1`` for SciPy; "evaluations" counts every call of ``rhs``,
the Radau Jacobian's included (SciPy's ``nfev`` leaves those out: it is
printed beside). Without loopkin installed only SciPy is timed.
"""

import argparse
import math
import statistics
import time

from scipy.integrate import solve_ivp

A, B, C, D = 0.04, 0.12, 0.10, 0.11
M2, M3, M4 = 0.3, 0.5, 0.4
J2, J3, J4 = 2.0e-3, 6.0e-4, 3.5e-4
G = 9.81
STALL, NO_LOAD = 0.5, 60.0
K, L0, DAMPING = 50.0, 0.10, 2.0
P0 = (0.05, 0.15)
UNTIL, TOL = 3.0, 1e-10

TEXT = """
struct FourBar {
    params   { a, b, c, d }
    drivers  { phi }
    unknowns { th3, th4 }
    points {
        G2 = polar(a / 2.0, phi);
        G3 = polar(a, phi) + polar(b / 2.0, th3);
        G4 = vec2(d, 0.0) + polar(c / 2.0, th4);
        P0 = vec2(0.05, 0.15);
    }
    loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
    bodies {
        crank(mass = 0.3, center = G2, angle = phi, inertia = 2.0e-3);
        coupler(mass = 0.5, center = G3, angle = th3, inertia = 6.0e-4);
        rocker(mass = 0.4, center = G4, angle = th4, inertia = 3.5e-4);
    }
    loads {
        gravity(vec2(0.0, -9.81));
        force(phi, 0.5 * (1.0 - rate(phi) / 60.0));
        spring(P0, G3, stiffness = 50.0, free_length = 0.10, damping = 2.0);
    }
}
"""

# t, φ, φ̇ from tests/reference/four_bar_forward.py (Gauss–Legendre, 34
# digits, converged to 5e-16), as it prints them.
REFERENCE = [
    (0.25, 3.3560632674773675, 30.612428586128006),
    (0.50, 12.532291902910316, 38.426410445380159),
    (0.75, 24.178238752533962, 47.450009397192642),
    (1.00, 36.819794024413326, 49.147263243076653),
    (1.25, 49.899232128337858, 45.567378721633435),
    (1.50, 63.207476847653535, 57.020816200474412),
    (1.75, 76.707316162770101, 52.207742041885490),
    (2.00, 90.162193834372381, 51.099813639845865),
]


def make_rhs():
    """rhs(t, y) for y = (φ, φ̇), every constant a local of the closure."""
    sin, cos, sqrt = math.sin, math.cos, math.sqrt
    a, b, c, d = A, B, C, D
    bb, cc, hb = b * b, c * c, b / 2
    m0 = J2 + M2 * a * a / 4  # the crank: |G2'|² = a²/4, constant
    i4 = J4 + M4 * cc / 4  # the rocker about D
    m3, j3 = M3, J3
    g2, g3, g4 = G * M2 * a / 2, G * M3, G * M4 * c / 2
    px, py = P0
    k, l0, cd, ts, w0 = K, L0, DAMPING, STALL, NO_LOAD

    def rhs(t, y):
        phi, w = y.tolist()
        s, co = sin(phi), cos(phi)
        bx, by = a * co, a * s
        # C: the circles (B, b) and (D, c), on the left of B→D.
        ex, ey = d - bx, -by
        l2 = ex * ex + ey * ey
        p = (bb - cc + l2) / (2.0 * l2)
        h = sqrt(bb / l2 - p * p)
        cx, cy = bx + p * ex - h * ey, by + p * ey + h * ex
        c3, s3 = (cx - bx) / b, (cy - by) / b
        c4, s4 = (cx - d) / c, cy / c
        s43 = s4 * c3 - c4 * s3  # sin(θ4 − θ3)
        c43 = c4 * c3 + s4 * s3  # cos(θ4 − θ3)
        # a e^(iφ) + b θ3' e^(iθ3) = c θ4' e^(iθ4), and its derivative in φ
        t3 = a * (s * c4 - co * s4) / (b * s43)  # θ3' = a sin(φ − θ4) / (b sin(θ4 − θ3))
        t4 = a * (s * c3 - co * s3) / (c * s43)  # θ4' = a sin(φ − θ3) / (c sin(θ4 − θ3))
        t3t, t4t = t3 * t3, t4 * t4
        u3 = (a * (co * c4 + s * s4) + b * t3t * c43 - c * t4t) / (b * s43)  # θ3''
        u4 = (a * (co * c3 + s * s3) + b * t3t - c * t4t * c43) / (c * s43)  # θ4''
        # G3 = B + (b/2) e^(iθ3): velocity and acceleration coefficients
        vx, vy = -by - hb * t3 * s3, bx + hb * t3 * c3
        ax = -bx - hb * (u3 * s3 + t3t * c3)
        ay = -by + hb * (u3 * c3 - t3t * s3)
        mass = m0 + m3 * (vx * vx + vy * vy) + j3 * t3t + i4 * t4t
        half = m3 * (vx * ax + vy * ay) + j3 * t3 * u3 + i4 * t4 * u4  # M'/2
        vg = g2 * co + g3 * vy + g4 * c4 * t4  # gravity's V'
        # the spring-damper P0–G3: tension k (L − L0) + c L̇, L̇ = L' φ̇
        rx, ry = bx + hb * c3 - px, by + hb * s3 - py
        ln = sqrt(rx * rx + ry * ry)
        lp = (rx * vx + ry * vy) / ln
        q = ts * (1.0 - w / w0) - (k * (ln - l0) + cd * lp * w) * lp
        return w, (q - half * w * w - vg) / mass

    return rhs


RHS = make_rhs()


def check_rhs():
    """DOP853 at 1e-13 from one reference instant to the next, against the
    reference; then on to 3 s. Returns φ(3 s)."""
    t, y, worst = 0.0, [0.0, 0.0], 0.0
    for t1, phi, w in REFERENCE + [(UNTIL, None, None)]:
        sol = solve_ivp(RHS, (t, t1), y, method="DOP853", rtol=1e-13, atol=1e-13)
        assert sol.success, sol.message
        t, y = t1, sol.y[:, -1]
        if phi is not None:
            worst = max(worst, abs(y[0] - phi) / abs(phi), abs(y[1] - w) / abs(w))
    print(f"rhs by DOP853 at 1e-13: φ, φ̇ agree with the 34-digit reference to {worst:.1e} (relative) at 8 instants")
    assert worst < 1e-10, worst
    return float(y[0])


def scipy_run(method, fun=RHS):
    return solve_ivp(fun, (0.0, UNTIL), [0.0, 0.0], method=method, rtol=TOL, atol=TOL)


def scipy_counts(method, phi3):
    """Steps, rhs calls (all of them), nfev and the error of φ(3 s)."""
    calls = [0]

    def counted(t, y):
        calls[0] += 1
        return RHS(t, y)

    sol = scipy_run(method, counted)
    assert sol.success, sol.message
    return len(sol.t) - 1, calls[0], sol.nfev, abs(sol.y[0, -1] - phi3) / phi3


def loopkin_model():
    try:
        import loopkin as kin
    except ImportError as e:
        print(f"loopkin not importable ({e}): timing SciPy alone")
        return None
    return kin.compile(TEXT)(a=A, b=B, c=C, d=D)


def loopkin_run(m):
    return m.forward(start={"phi": 0.0, "th3": 1.2, "th4": 1.9}, until=UNTIL, samples=300, tolerance=TOL)


def loopkin_counts(m, phi3):
    run = loopkin_run(m)
    assert run.ended == "complete", run.ended
    assert abs(run.sweep.at[-1] - UNTIL) < 1e-12, run.sweep.at[-1]
    err = abs(run.sweep["phi"][-1] - phi3) / phi3
    print(f"loopkin φ(3 s) = {run.sweep['phi'][-1]:.12f}, DOP853 {phi3:.12f}: {err:.1e} relative")
    assert err < 1e-7, err
    return run.steps, run.evaluations, None, err


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=7)
    rounds = ap.parse_args().rounds
    phi3 = check_rhs()
    variants = {
        "SciPy RK45": lambda: scipy_run("RK45"),
        "SciPy Radau": lambda: scipy_run("Radau"),
    }
    counts = {k: scipy_counts(k.split()[1], phi3) for k in variants}
    m = loopkin_model()
    if m is not None:
        counts["loopkin"] = loopkin_counts(m, phi3)
        variants["loopkin"] = lambda: loopkin_run(m)
    times = {k: [] for k in variants}
    for _ in range(rounds):
        for k, f in variants.items():
            t0 = time.thread_time()
            f()
            times[k].append((time.thread_time() - t0) * 1e3)
    print(f"\n{UNTIL:g} s from rest at tolerance {TOL:g}: CPU ms, median (range) over {rounds} rounds")
    print(f"  {'':12s} {'steps':>6s} {'evaluations':>11s} {'(nfev)':>7s} {'φ(3 s) error':>13s} {'CPU ms':>9s}")
    for k, v in times.items():
        steps, calls, nfev, err = counts[k]
        nf = "" if nfev is None else f"({nfev})"
        print(f"  {k:12s} {steps:6d} {calls:11d} {nf:>7s} {err:13.1e} {statistics.median(v):9.2f}"
              f"  ({min(v):.2f}–{max(v):.2f})")
    if "loopkin" in times:
        for k in ("SciPy RK45", "SciPy Radau"):
            r = [s / u for s, u in zip(times[k], times["loopkin"])]
            print(f"  {k} / loopkin: {statistics.median(r):.1f}× ({min(r):.1f}–{max(r):.1f})")
    # A higher-order pair, counted, not timed: whether it needs fewer
    # evaluations than RK45 for the accuracy RK45 reaches.
    for tol in (TOL, TOL / 10):
        calls = [0]

        def counted(t, y):
            calls[0] += 1
            return RHS(t, y)

        sol = solve_ivp(counted, (0.0, UNTIL), [0.0, 0.0], method="DOP853", rtol=tol, atol=tol)
        err = abs(sol.y[0, -1] - phi3) / phi3
        print(f"  SciPy DOP853 at {tol:g} (counted, not timed): {len(sol.t) - 1} steps, "
              f"{calls[0]} evaluations, φ(3 s) error {err:.1e}")


if __name__ == "__main__":
    main()
