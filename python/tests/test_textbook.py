"""The cases the Rust tests check against the textbook, through Python:
the printed answers (to one unit of their last decimal) and closed forms
derived here, independently of the library (to 1e-13)."""

import math

import numpy as np
import pytest

from conftest import close, mechanism


def book(computed, printed, decimals=3):
    assert abs(computed - printed) < 10.0 ** (-decimals), (computed, printed)


def four_bar_closed_form(a, b, c, d, p, beta, phi, w, al, mode):
    """Position by intersecting the circles about B and D, and the rates and
    accelerations from the loop a e(φ) + b e(θ3) − c e(θ4) − d = 0 dotted
    with e(θ4) and e(θ3) (e(x) = (cos x, sin x))."""
    B = np.array([a * math.cos(phi), a * math.sin(phi)])
    r = np.array([d, 0.0]) - B
    L = math.hypot(*r)
    gamma = math.acos((b * b + L * L - c * c) / (2 * b * L))
    th3 = math.atan2(r[1], r[0]) + mode * gamma
    C = B + b * np.array([math.cos(th3), math.sin(th3)])
    th4 = math.atan2(C[1], C[0] - d)
    s34 = math.sin(th3 - th4)
    w3 = a * w * math.sin(th4 - phi) / (b * s34)
    w4 = a * w * math.sin(th3 - phi) / (c * s34)
    a3 = (a * al * math.sin(th4 - phi) - a * w * w * math.cos(phi - th4) - b * w3 * w3 * math.cos(th3 - th4) + c * w4 * w4) / (b * s34)
    a4 = (a * al * math.sin(th3 - phi) - a * w * w * math.cos(phi - th3) - b * w3 * w3 + c * w4 * w4 * math.cos(th3 - th4)) / (c * s34)

    def e(x):
        return np.array([math.cos(x), math.sin(x)])

    def n(x):
        return np.array([-math.sin(x), math.cos(x)])

    t = th3 + beta
    P = B + p * e(t)
    vP = a * w * n(phi) + p * w3 * n(t)
    aP = a * (al * n(phi) - w * w * e(phi)) + p * (a3 * n(t) - w3 * w3 * e(t))
    return (th3, th4), (w3, w4), (a3, a4), (P, vP, aP)


@pytest.mark.parametrize("phi", [0.0, 0.5, 1.7, 3.0, 4.4, 6.0])
def test_four_bar_against_its_closed_form(four_bar, phi):
    m = four_bar
    w, al = 10.0, 25.0
    for pose in m.assemble_all(phi=phi):
        s = m.analyze(pose, rate=w, acceleration=al)
        # The mode is the side of BD on which C lies: match it by θ3.
        best = None
        for mode in (1, -1):
            cf = four_bar_closed_form(0.04, 0.12, 0.10, 0.11, 0.06, 0.5, phi, w, al, mode)
            d = abs(math.remainder(cf[0][0] - pose["th3"], 2 * math.pi))
            if best is None or d < best[0]:
                best = (d, cf)
        (th, rates, accs, (P, vP, aP)) = best[1]
        assert abs(math.remainder(pose["th3"] - th[0], 2 * math.pi)) < 1e-13
        assert abs(math.remainder(pose["th4"] - th[1], 2 * math.pi)) < 1e-13
        assert close([s.qd["th3"], s.qd["th4"]], rates, 1e-13, scale=w)
        assert close([s.qdd["th3"], s.qdd["th4"]], accs, 1e-13, scale=w * w)
        pt = s.points["P"]
        assert close(pt.position, P, 1e-13)
        assert close(pt.velocity, vP, 1e-13, scale=w * 0.1)
        assert close(pt.acceleration, aP, 1e-13, scale=w * w * 0.1)


@pytest.mark.parametrize("phi", [0.0, 1.0, 2.5, 4.0, 5.5])
def test_offset_slider_crank_against_its_closed_form(phi):
    SliderCrank = mechanism("slider_crank")
    a, b, e = 0.05, 0.2, 0.01
    m = SliderCrank(a=a, b=b, e=e)
    w, al = 30.0, -4.0
    for pose in m.assemble_all(phi=phi, th=0.0, x=0.0):
        s = m.analyze(pose, rate=w, acceleration=al)
        sin_t = (e - a * math.sin(phi)) / b
        # The two modes: θ = asin(…) (slider to the right) or π − asin(…).
        th = math.asin(sin_t) if math.cos(pose["th"]) > 0 else math.pi - math.asin(sin_t)
        x = a * math.cos(phi) + b * math.cos(th)
        wt = -a * w * math.cos(phi) / (b * math.cos(th))
        vx = -a * w * math.sin(phi) - b * wt * math.sin(th)
        at = (-a * (al * math.cos(phi) - w * w * math.sin(phi)) + b * wt * wt * math.sin(th)) / (b * math.cos(th))
        ax = -a * (al * math.sin(phi) + w * w * math.cos(phi)) - b * (at * math.sin(th) + wt * wt * math.cos(th))
        assert abs(math.remainder(pose["th"] - th, 2 * math.pi)) < 1e-13
        assert abs(pose["x"] - x) < 1e-13
        assert close([s.qd["th"], s.qd["x"]], [wt, vx], 1e-13, scale=w)
        assert close([s.qdd["th"], s.qdd["x"]], [at, ax], 1e-13, scale=w * w)
        C = s.points["C"]
        assert close(C.velocity, [vx, 0.0], 1e-13, scale=w)


def test_example_4_1_r_trr():
    RTrr = mechanism("r_trr")
    m = RTrr(ac=0.100, bc=0.300)
    pose = m.assemble(phi=math.radians(45), s=0.35, phi3=math.radians(60))
    omega = 3.141  # the book's rounded 30 rev/min, used in every step
    s = m.analyze(pose, rate=omega)
    B = s.points["B"]
    book(B.position[0], 0.256)
    book(B.position[1], 0.256)
    book(B.velocity[0], -0.999)
    book(B.velocity[1], 0.609)
    book(B.speed, 1.171)
    book(B.acceleration[0], -1.802)
    book(float(np.linalg.norm(B.acceleration)), 4.620)
    book(math.degrees(pose["phi3"]), 58.633)
    book(s.qd["phi3"], 3.903)
    book(s.qdd["phi3"], -2.252)
    # a_By as printed is the value at ω = π exactly (the stated 30 rev/min).
    book(m.analyze(pose, rate=math.pi).points["B"].acceleration[1], -4.255)
    # Closed form: B is on the crank line and on the circle about C.
    x, y = B.position
    assert abs(math.atan2(y, x - 0.1) - pose["phi3"]) < 1e-13
    assert abs(math.hypot(x - 0.1, y) - 0.3) < 1e-13
    assert abs(math.hypot(x, y) - pose["s"]) < 1e-13


def test_example_4_2_r_rtr_rrt():
    RRtrRrt = mechanism("r_rtr_rrt")
    m = RRtrRrt(ab=0.100, ac=0.150, cd=0.075, de=0.200)
    pose = m.assemble(phi=math.radians(45), s=0.2, phi3=math.radians(70), x_e=0.2, phi4=math.radians(20))
    s = m.analyze(pose, rate=4.712)
    D, E = s.points["D"], s.points["E"]
    book(math.degrees(pose["phi3"]), 72.235)
    book(s.qd["phi3"], 1.807)
    book(s.qdd["phi3"], 1.020)
    book(D.position[0], -0.023)
    book(D.position[1], -0.071)
    book(D.velocity[0], 0.129)
    book(D.velocity[1], -0.041)
    book(D.speed, 0.135)
    book(D.acceleration[0], 0.147)
    book(D.acceleration[1], 0.210)
    book(float(np.linalg.norm(D.acceleration)), 0.256)
    book(E.position[0], 0.164)
    book(E.velocity[0], 0.113)
    book(E.acceleration[0], 0.217)
    book(math.degrees(pose["phi4"]), 20.923)
    book(s.qd["phi4"], 0.221)
    book(s.qdd["phi4"], -1.105)
    # Closed form of the first loop: φ3 = atan2(y_B, x_B), B = (ab cos φ, ac + ab sin φ).
    phi = math.radians(45)
    assert abs(pose["phi3"] - math.atan2(0.15 + 0.1 * math.sin(phi), 0.1 * math.cos(phi))) < 1e-13
    assert abs(math.hypot(*D.position) - 0.075) < 1e-13


def test_example_7_3_rssr():
    Rssr = mechanism("rssr")
    m = Rssr(a=0.102, b=0.381, c=0.254, d=0.314)
    phi = math.pi / 3
    pose = m.assemble(phi=phi, psi=1.5)
    assert abs(math.degrees(pose["psi"]) - 88.42) < 5e-3
    a, b, c, d = 0.102, 0.381, 0.254, 0.314
    cos_psi = (b * b - a * a - c * c - d * d + 2 * a * d * math.cos(phi)) / (2 * c * (d - a * math.cos(phi)))
    assert abs(math.cos(pose["psi"]) - cos_psi) < 1e-13
    w1 = 240 * math.pi / 30
    s = m.analyze(pose, rate=w1)
    assert abs(s.qd["psi"] - 10.7) < 0.05
    sp, cp = math.sin(pose["psi"]), math.cos(pose["psi"])
    ratio = a * math.sin(phi) * (d + c * cp) / (c * sp * (d - a * math.cos(phi)))
    assert abs(s.qd["psi"] - ratio * w1) < 1e-13 * w1
    # At φ = 0 (ψ = 70.64° printed), a_A = 1611 i + 32.05 k m/s².
    pose0 = m.assemble(phi=0.0, psi=1.2)
    assert abs(math.degrees(pose0["psi"]) - 70.64) < 5e-3
    s0 = m.analyze(pose0, rate=1200 * math.pi / 30, acceleration=3000 * math.pi / 30)
    assert close(s0.points["A"].acceleration, [1611.0, 0.0, 32.05], 0.5 / 1611, scale=1611)
    assert abs(s0.qd["psi"]) < 1e-12
    assert abs(s0.qdd["psi"] - 12607) / 12607 < 2e-3


def test_robot_arm_worked_problem():
    RobotArm = mechanism("robot_arm")
    al = math.pi / 3
    m = RobotArm(l1=1.2, l2=0.6, l3=0.2, alpha=al)
    pose = m.assemble(q1=0.0, q4=0.0, q5=0.0)
    s = m.analyze(pose, rates={"q1": 1.0, "q4": 1.0, "q5": 1.0})
    arm = s.frames["arm"]
    sa, ca = math.sin(al), math.cos(al)
    # ω_arm = −ω₄E₁ + ω₅ sin α E₂ + (ω₁ − ω₅ cos α)E₃.
    assert close(arm.angular_velocity, [-1.0, sa, 0.5], 1e-13)
    # α_arm = −ω₁ω₅ sin α E₁ − (ω₄ω₅ cos α + ω₁ω₄)E₂ − ω₄ω₅ sin α E₃.
    assert close(arm.angular_acceleration, [-sa, -(ca + 1.0), -sa], 1e-13)
    # v_B = (−1.12, −0.20, −0.69) m/s, printed to two decimals.
    assert close(s.points["B"].velocity, [-1.12, -0.20, -0.69], 5e-3)
    # a^A = 2ω₁ω₄L₂ cos α E₁ − (ω₁²L₁ cos α + ω₄²L₂ sin α + ω₁²L₂ sin α)E₂ + ω₄²L₂ cos α E₃.
    assert close(s.points["A"].acceleration, [1.2 * ca, -(1.2 * ca + 1.2 * sa), 0.6 * ca], 1e-13)
