"""Forward dynamics from Python (``Mechanism.forward``) against closed
forms written here: a flywheel started by a DC motor,
ω(t) = ω₀ (1 − e^(−t/τ)) with τ = J ω₀ / T_s and
φ(t) = ω₀ (t − τ (1 − e^(−t/τ))); a pendulum's half swing at small
amplitude, π √(I_O / (m g r)) (1 + θ₀²/16); and the errors."""

import math

import numpy as np
import pytest

import loopkin as kin

FLYWHEEL = """
struct Flywheel {
    params   { j, ts, w0 }
    drivers  { phi }
    unknowns { }
    points   { O = vec2(0.0, 0.0); P = polar(0.1, phi); }
    bodies   { wheel(mass = 5.0, center = O, angle = phi, inertia = j); }
    loads    { force(phi, ts * (1.0 - rate(phi) / w0)); }
}
"""

SWING = """
struct Swing {
    params   { r, m, j }
    drivers  { phi }
    unknowns { }
    points   { G = polar(r, phi); }
    bodies   { bob(mass = m, center = G, angle = phi, inertia = j); }
    loads    { gravity(vec2(0.0, -9.81)); }
}
"""

NO_MASSES = """
struct Crank { params { a } drivers { phi } unknowns { } points { B = polar(a, phi); } }
"""


def test_a_flywheel_started_by_a_dc_motor_follows_its_exponential():
    j, ts, w0 = 0.5, 4.0, 100.0
    m = kin.compile(FLYWHEEL)(j=j, ts=ts, w0=w0)
    run = m.forward(start={"phi": 0.0}, until="30s", samples=60, tolerance=1e-11)
    assert isinstance(run, kin.Trajectory)
    assert run.ended == "complete" and run.at == 30.0
    tau = j * w0 / ts
    t = run.sweep.at
    assert np.array_equal(t, run.t) and len(t) == 61
    np.testing.assert_allclose(run.sweep.qd["phi"], w0 * (1 - np.exp(-t / tau)), rtol=0, atol=1e-8 * w0)
    np.testing.assert_allclose(run.sweep["phi"], w0 * (t - tau * (1 - np.exp(-t / tau))), rtol=0, atol=1e-7 * w0)
    # The motor's work is the kinetic energy the wheel has: no loss.
    assert run.work_names == ["force on phi"]
    np.testing.assert_allclose(run.work[:, 0], run.kinetic, rtol=1e-9, atol=1e-9)
    assert run.energy_error() < 1e-9
    assert np.all(np.abs(run.balance - run.balance[0]) < 1e-8 * run.kinetic.max())
    # The model's own sections: every evaluation by its compiled equations.
    assert run.evaluations > 0 and run.compiled >= run.evaluations and run.summed == 0


def test_a_torque_of_the_time_turns_the_flywheel_as_its_closed_form():
    # force(phi, k * time) on the inertia j: ω = k t² / (2 j), φ = k t³ / (6 j).
    j, k = 0.4, 3.0
    text = FLYWHEEL.replace("params   { j, ts, w0 }", "params   { j, k }").replace(
        "ts * (1.0 - rate(phi) / w0)", "k * time"
    )
    run = kin.compile(text)(j=j, k=k).forward(start={"phi": 0.0}, until=2.0, samples=20, tolerance=1e-11)
    t = run.t
    np.testing.assert_allclose(run.sweep.qd["phi"], k * t**2 / (2 * j), rtol=0, atol=1e-10 * k / j)
    np.testing.assert_allclose(run.sweep["phi"], k * t**3 / (6 * j), rtol=0, atol=1e-10 * k / j)
    # Outside a load's value `time` is an error at its token.
    with pytest.raises(kin.DefinitionError, match="may be used only in the value of a `force"):
        kin.compile(text.replace("P = polar(0.1, phi)", "P = polar(0.1, phi + time)"))


OSCILLATOR = """
struct Oscillator {
    params   { m, k }
    drivers  { x }
    unknowns { }
    points   { C = vec2(x, 0.0); }
    bodies   { block(mass = m, center = C); }
    loads    { force(x, -k * x); }
}
"""


def test_events_count_in_the_direction_asked_for():
    # x = A cos ω t from x = A at rest: A/2 is reached decreasing at ω t = π/3
    # and increasing at 5π/3, −A/2 increasing at 4π/3.
    a, mass, k = 0.1, 2.0, 50.0
    w = math.sqrt(k / mass)
    m = kin.compile(OSCILLATOR)(m=mass, k=k)

    def end(stop_when):
        run = m.forward(start={"x": a}, until=10.0, stop_when=stop_when, tolerance=1e-12)
        assert run.ended == "event"
        return run.event, run.at

    assert end({"x": a / 2}) == (0, pytest.approx(math.pi / 3 / w, abs=1e-9))
    assert end({"x": (a / 2, "increasing")}) == (0, pytest.approx(5 * math.pi / 3 / w, abs=1e-9))
    assert end([("x", a / 2, "increasing"), ("x", -a / 2, "increasing")]) == (
        1,
        pytest.approx(4 * math.pi / 3 / w, abs=1e-9),
    )
    assert end([("rate(x)", 0.0, "increasing")]) == (0, pytest.approx(math.pi / w, abs=1e-9))
    assert end({"rate(x)": [0.0, " decreasing "]}) == (0, pytest.approx(2 * math.pi / w, abs=1e-9))
    with pytest.raises(ValueError, match="increasing"):
        m.forward(start={"x": a}, until=1.0, stop_when={"x": (0.05, "upward")})
    with pytest.raises(ValueError, match="not \\(coordinate, value\\)"):
        m.forward(start={"x": a}, until=1.0, stop_when=[("x",)])


def test_a_speed_reached_ends_the_run_where_it_is_reached():
    j, ts, w0 = 0.5, 4.0, 100.0
    m = kin.compile(FLYWHEEL)(j=j, ts=ts, w0=w0)
    run = m.forward(start={"phi": 0.0}, until=60.0, stop_when={"rate(phi)": 50.0}, tolerance=1e-11)
    assert run.ended == "event" and run.event == 0
    # Half the no-load speed at t = τ ln 2.
    assert run.at == pytest.approx(j * w0 / ts * math.log(2.0), rel=1e-9)
    assert run.sweep.qd["phi"][-1] == pytest.approx(50.0, rel=1e-9)


def test_a_pendulum_swings_with_its_period():
    r, mass, j = 0.1, 2.0, 0.01
    m = kin.compile(SWING)(r=r, m=mass, j=j)
    amplitude = 1e-3
    run = m.forward(
        start={"phi": -math.pi / 2 + amplitude},
        until=5.0,
        stop_when={"rate(phi)": 0.0},
        tolerance=1e-12,
    )
    omega = math.sqrt(mass * 9.81 * r / (j + mass * r * r))
    assert run.ended == "event"
    assert 2 * run.at == pytest.approx(2 * math.pi / omega * (1 + amplitude**2 / 16), rel=1e-9)
    # Released at rest: the free driver's effort is zero throughout.
    assert np.all(run.effort == 0.0)


def test_errors_say_what_is_wrong():
    with pytest.raises(kin.InvalidDynamicsError, match="bodies"):
        kin.compile(NO_MASSES)(a=0.1).forward(start={"phi": 0.0}, until=1.0)
    m = kin.compile(FLYWHEEL)(j=0.5, ts=4.0, w0=100.0)
    with pytest.raises(kin.InvalidDynamicsError, match="no coordinate `psi`"):
        m.forward(start={"phi": 0.0}, until=1.0, stop_when={"psi": 1.0})
    with pytest.raises(ValueError, match="until"):
        m.forward(start={"phi": 0.0}, until="soon")
    with pytest.raises(KeyError, match="not a driver"):
        m.forward(start={"phi": 0.0}, until=1.0, rates={"x": 1.0})


def test_a_stiff_spring_is_integrated_implicitly_and_the_method_is_checked():
    stiff = kin.compile(
        """
        struct Stiff {
            params   { j, k, c }
            drivers  { phi }
            unknowns { }
            points   { O = vec2(0.0, 0.0); P = polar(0.1, phi); }
            bodies   { wheel(mass = 1.0, center = O, angle = phi, inertia = j); }
            loads    { force(phi, -k * phi - c * rate(phi)); }
        }
        """
    )
    j, k, c = 0.4, 1.0e4, 4.0e4
    m = stiff(j=j, k=k, c=c)
    run = m.forward(start={"phi": 1.0}, until=10.0, samples=20, tolerance=1e-7, method="implicit")
    assert run.ended == "complete" and run.steps < 300
    # J φ'' + c φ' + k φ = 0 from φ = 1 at rest, overdamped.
    root = math.sqrt(c * c - 4 * j * k)
    s1, s2 = (-c + root) / (2 * j), (-c - root) / (2 * j)
    a = s2 / (s2 - s1)
    t = run.sweep.at
    np.testing.assert_allclose(run.sweep["phi"], a * np.exp(s1 * t) + (1 - a) * np.exp(s2 * t), rtol=0, atol=1e-5)
    with pytest.raises(ValueError, match="implicit"):
        m.forward(start={"phi": 1.0}, until=1.0, method="rk4")


def test_the_trajectory_sensitivity_to_the_inertia_is_its_closed_form():
    text = FLYWHEEL.replace("loads    {", "sensitivities { j }\n    loads    {")
    j, ts, w0 = 0.5, 4.0, 100.0
    m = kin.compile(text)(j=j, ts=ts, w0=w0)
    run = m.forward(start={"phi": 0.0}, until=20.0, samples=20, tolerance=1e-11, sensitivities=True)
    assert run.parameters == ["j"]
    assert run.position_sensitivity.shape == (21, 1, 1)
    t = run.sweep.at
    tau = j * w0 / ts
    e = np.exp(-t / tau)
    # ω = ω₀ (1 − e^(−t/τ)), φ = ω₀ (t − τ (1 − e^(−t/τ))), τ = J ω₀ / T_s:
    # ∂/∂J = ∂/∂τ · τ/J.
    d_rate = -w0 * e * t / tau**2 * (tau / j)
    d_phi = -w0 * (1 - e - t / tau * e) * (tau / j)
    np.testing.assert_allclose(run.rate_sensitivity[:, 0, 0], d_rate, rtol=0, atol=1e-7 * np.abs(d_rate).max())
    np.testing.assert_allclose(run.position_sensitivity[:, 0, 0], d_phi, rtol=0, atol=1e-7 * np.abs(d_phi).max())


def test_a_pendulum_bounces_off_a_stop():
    r, mass, j = 0.1, 2.0, 0.01
    m = kin.compile(SWING)(r=r, m=mass, j=j)
    theta = 0.8
    run = m.forward(
        start={"phi": -math.pi / 2 + theta},
        until=2.0,
        tolerance=1e-11,
        stops={"phi": ("-90deg", 0.5)},
    )
    omega = math.sqrt(2 * mass * 9.81 * r * (1 - math.cos(theta)) / (j + mass * r * r))
    t, index, before, after = run.impacts[0]
    assert index == 0 and before == pytest.approx(-omega, rel=1e-8)
    assert after == pytest.approx(0.5 * omega, rel=1e-10)
    assert run.work_names == ["impacts at phi"]
    assert run.energy_error() < 1e-9
    assert np.all(run.sweep["phi"] >= -math.pi / 2 - 1e-9)
