"""Figures of merit and units from Python, against closed forms written
here: one four-bar per Grashof class (classified by hand), the four-bar's
transmission angle from the law of cosines in the triangle B C D, the
offset slider-crank's stroke and time ratio (crank and rod in line at
both dead centres), and values with units read into radians."""

import math

import numpy as np
import pytest

import loopkin as kin
from loopkin.errors import InvalidGeometryError

from conftest import close, mechanism


@pytest.mark.parametrize(
    "lengths, kind",
    [
        ((0.11, 0.04, 0.12, 0.10), "crank-rocker"),  # 0.16 < 0.21, input shortest
        ((2.0, 4.0, 5.0, 4.5), "double-crank"),  # 7 < 8.5, ground shortest
        ((4.0, 4.5, 2.0, 5.0), "double-rocker"),  # coupler shortest
        ((4.0, 4.5, 5.0, 2.0), "rocker-crank"),  # output shortest
        ((6.0, 3.0, 4.0, 4.5), "triple-rocker"),  # 9 > 8.5
        ((0.09, 0.04, 0.09, 0.04), "change-point"),  # 0.13 = 0.13
    ],
)
def test_one_four_bar_per_grashof_class(lengths, kind):
    g = kin.grashof(*lengths)
    assert g.kind == kind
    s = sorted(lengths)
    assert close(g.s_plus_l, s[0] + s[3], 1e-15) and close(g.p_plus_q, s[1] + s[2], 1e-15)


def test_a_loop_that_cannot_close_is_refused():
    with pytest.raises(InvalidGeometryError, match="cannot close"):
        kin.grashof(1.0, 1.0, 1.0, 3.0)


def test_transmission_angle_from_the_law_of_cosines(FourBar):
    a, b, c, d = 0.04, 0.12, 0.10, 0.11
    m = FourBar(a=a, b=b, c=c, d=d, p=0.06, beta="30deg")
    assert close(m.params["beta"], math.pi / 6, 1e-15)
    start = m.assemble(phi=0.0, th3=1.0, th4=1.6)
    sw = m.sweep("phi", start=start, turn=True, steps=360)
    t = sw.transmission("th3", "th4")
    f2 = a * a + d * d - 2 * a * d * np.cos(sw.at)
    mu = np.arccos((b * b + c * c - f2) / (2 * b * c))
    assert close(t.values, mu, 1e-12)
    assert close(t.at_min, 0.0, 1e-12) and close(t.min, mu[0], 1e-12)
    assert close(t.at_max, math.pi, 1e-9) and close(t.max, mu[180], 1e-12)
    assert close(t.worst_departure, max(math.pi / 2 - mu[0], mu[180] - math.pi / 2), 1e-12)


def test_mechanical_advantage_from_the_velocity_loop(FourBar):
    """ω2/ω4 = c sin(θ4 − θ3) / (a sin(φ − θ3)): the velocity loop dotted
    with the coupler's direction, which drops ω3."""
    a, c = 0.04, 0.10
    m = FourBar(a=a, b=0.12, c=c, d=0.11, p=0.06, beta=0.5)
    sw = m.sweep("phi", start=m.assemble(phi=0.0, th3=1.0, th4=1.6), turn=True, steps=120, rate=5.0)
    ma = sw.mechanical_advantage("th4")
    exact = c * np.sin(sw["th4"] - sw["th3"]) / (a * np.sin(sw.at - sw["th3"]))
    assert close(ma.values, exact, 1e-9, np.abs(exact))
    k = int(np.argmin(np.abs(exact)))
    assert close(ma.least, abs(exact[k]), 1e-9) and close(ma.at_least, sw.at[k], 1e-12)
    assert ma.values.flags.writeable is False
    with pytest.raises(InvalidGeometryError, match="swept driver"):
        sw.mechanical_advantage("phi")
    # Over time, the input is the one driver: φ = 3 t, φ' = 3.
    t = np.linspace(0.0, 1.0, 41)
    sim = m.simulate(start=m.assemble(phi=0.0, th3=1.0, th4=1.6), duration=1.0, steps=40,
                     values={"phi": 3.0 * t}, rates={"phi": np.full(41, 3.0)}, accelerations={"phi": np.zeros(41)})
    over_time = sim.mechanical_advantage("th4")
    exact = c * np.sin(sim["th4"] - sim["th3"]) / (a * np.sin(sim["phi"] - sim["th3"]))
    assert close(over_time.values, exact, 1e-9, np.abs(exact))


def test_offset_slider_crank_stroke_and_time_ratio():
    a, b, e = 1.0, 3.0, 1.0
    m = mechanism("slider_crank")(a=a, b=b, e=e)
    sw = m.sweep("phi", start=m.assemble(phi=0.5, th=-0.1, x=3.5), turn=True, steps=360, rpm=60)
    alpha = math.asin(e / (b - a)) - math.asin(e / (a + b))
    assert close(sw.time_ratio("x").ratio, (math.pi + alpha) / (math.pi - alpha), 1e-8)
    stroke = math.sqrt((a + b) ** 2 - e * e) - math.sqrt((b - a) ** 2 - e * e)
    assert close(sw.stroke("x").length, stroke, 2e-9)
    centres = sw.dead_centres("x")
    assert sorted(c.maximum for c in centres) == [False, True]
    top = next(c for c in centres if c.maximum)
    assert close(top.at % (2 * math.pi), math.asin(e / (a + b)), 1e-8)
    with pytest.raises(InvalidGeometryError, match="not one full turn"):
        m.sweep("phi", start=m.assemble(phi=0.5, th=-0.1, x=3.5), to=1.0, steps=10).time_ratio("x")


def test_values_with_units_and_degrees_out(FourBar, four_bar):
    # 30° is π/6; 120 rpm is 4π rad/s; 90°/s² is π/2 rad/s².
    pose = four_bar.assemble(phi="30deg", th3=0.9, th4=1.7)
    assert close(pose["phi"], math.pi / 6, 1e-15)
    s = four_bar.analyze(pose, rate="120rpm", acceleration="90deg/s2")
    assert close(s.qd["phi"], 4 * math.pi, 1e-15) and close(s.qdd["phi"], math.pi / 2, 1e-15)
    sw = four_bar.sweep("phi", start=pose, from_="30deg", to="60deg", steps=30, rate="30deg/s")
    assert close(sw.at, np.radians(np.linspace(30.0, 60.0, 31)), 1e-12)
    header = sw.to_csv(degrees=True).splitlines()[0].split(",")
    assert header[:4] == ["phi_deg", "phi_deg_s", "phi_deg_s2", "th3_deg"]
    first = [float(v) for v in sw.to_csv(degrees=True).splitlines()[1].split(",")]
    assert close(first[:2], [30.0, 30.0], 1e-11)
    with pytest.raises(ValueError, match="the unit `degs` is not known"):
        four_bar.pose(phi="30degs")
    with pytest.raises(ValueError, match="not the unit of a rate"):
        four_bar.analyze(pose, rate="30deg")


def test_a_change_point_stop_says_how_to_continue_in_python(FourBar):
    # The parallelogram (a = c, b = d) through its fold at φ = 0: the two
    # branches meet there.
    m = FourBar(a=0.05, b=0.12, c=0.05, d=0.12, p=0.0, beta=0.0)
    start = m.assemble(phi=-0.5, th3=0.0, th4=-0.5)
    sw = m.sweep("phi", start=start, to=0.5, steps=19)
    assert sw.stop is not None and sw.stop.kind == "change_point"
    assert 'continue with change_points="smooth" (or "switch")' in sw.stop.message
    assert "ChangePoints::" not in sw.stop.message


def test_an_angle_of_many_turns_in_radians_warns(FourBar):
    """``phi=90`` is 14.3 turns: read in radians, with a warning that says
    how to write degrees; a small angle or one with its unit does not
    warn."""
    import warnings

    m = FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    with pytest.warns(kin.errors.RadiansWarning, match=r'phi=90 is read as 90 rad \(14.3 turns\); write phi="90deg"') as w:
        q = m.pose(phi=np.float64(90))
    assert q["phi"] == 90.0
    # The warning names the caller's line, not the package's.
    assert w[0].filename == __file__
    start = m.assemble(phi=0.0, th3=1.0, th4=1.6)
    with pytest.warns(kin.errors.RadiansWarning) as record:
        m.poses("phi", start=start, from_=30, to=31, steps=2)
    assert [str(w.message).split(" is ")[0] for w in record] == ["phi=30", "phi=31"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m.pose(phi=6.0)
        m.pose(phi="90deg")
        m.sweep("phi", start=start, from_="30deg", to="40deg", steps=2)
        # Radians computed, not typed: three turns, as a sweep of turns ends.
        m.poses("phi", start=start, from_=0.0, to=6 * math.pi, steps=4)
