"""Forces from the ``bodies`` and ``loads`` sections, through Python,
against a closed form derived here: a slider-crank whose crank carries a
mass under gravity and whose piston is pushed by a constant gas force.

With the crank turning at a constant rate ω, its centre of mass G at r
along it (r_G = r e(φ)), the rod and the piston massless and the gas
force −P along x on the piston at x = a cos φ + √(b² − a² sin² φ):

- the effort is the rate of the potential energies, by virtual work,
  Q = m g r cos φ + P dx/dφ = m g r cos φ − P a sin φ (1 + a cos φ / √(b² − a² sin² φ));
- T = ½ (J + m r²) ω², V = m g r sin φ, the power Q ω;
- the shaking force −m a_G = m ω² r e(φ), and over [0, π]
  ∫ Q dφ = P (x(π) − x(0)) = −2 a P.
"""

import math

import numpy as np
import pytest

import loopkin as kin
from conftest import close

ENGINE = """
struct Engine {
    params   { a, b, r, m, j, p }
    drivers  { phi }
    unknowns { th, x }
    points   { G = polar(r, phi); C = vec2(x, 0.0); }
    loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
    bodies   { crank(mass = m, center = G, angle = phi, inertia = j); }
    loads    {
        gravity(vec2(0.0, -9.81));
        force(C, vec2(-p, 0.0));
    }
}
"""

A, B, R, M, J, P, G = 0.05, 0.2, 0.03, 1.5, 2e-3, 800.0, 9.81
W = 40.0


@pytest.fixture(scope="module")
def Engine():
    return kin.compile(ENGINE)


@pytest.fixture(scope="module")
def engine(Engine):
    return Engine(a=A, b=B, r=R, m=M, j=J, p=P)


def torque(phi):
    root = math.sqrt(B * B - (A * math.sin(phi)) ** 2)
    return M * G * R * math.cos(phi) - P * A * math.sin(phi) * (1.0 + A * math.cos(phi) / root)


def start(engine):
    return engine.assemble(phi=0.0, th=-0.1, x=0.24)


def test_has_dynamics(Engine, FourBar):
    assert Engine.has_dynamics()
    assert not FourBar.has_dynamics()


def test_forces_at_one_motion_match_the_closed_form(engine):
    pose = start(engine)
    for phi in np.linspace(0.1, 2 * math.pi - 0.1, 17):
        q = engine.assemble(pose, phi=float(phi))
        f = engine.forces(engine.analyze(q, rate=W))
        scale = M * G * R + P * A * 2
        assert close(f.effort["phi"], torque(phi), 1e-12, scale)
        assert close(f.kinetic_energy, 0.5 * (J + M * R * R) * W * W, 1e-12)
        assert close(f.potential_energy, M * G * R * math.sin(phi), 1e-12)
        assert close(f.power, torque(phi) * W, 1e-12, scale * W)
        e = np.array([math.cos(phi), math.sin(phi), 0.0])
        assert close(f.shaking_force, M * W * W * R * e, 1e-12, M * W * W * R)
        assert f.shaking_force.flags.writeable is False


def test_forces_along_a_sweep(engine):
    sw = engine.sweep("phi", start=start(engine), to=math.pi, steps=180, rate=W)
    assert sw.stop is None and len(sw) == 181
    fs = sw.forces()
    assert fs.drivers == ("phi",) and len(fs) == 181
    assert close(fs.at, sw.at, 0.0)
    want = np.array([torque(phi) for phi in sw.at])
    scale = M * G * R + P * A * 2
    assert close(fs.effort["phi"], want, 1e-12, scale)
    assert close(fs.power, want * W, 1e-12, scale * W)
    assert fs.shaking_force.shape == (181, 3)
    # The mean of the closed form by the same rule, and the exact mean
    # −2aP/π within the rule's error.
    h = np.diff(sw.at)
    trapezoid = float(np.sum(0.5 * (want[1:] + want[:-1]) * h)) / math.pi
    assert close(fs.mean_effort(), trapezoid, 1e-12, scale)
    assert abs(fs.mean_effort("phi") - (-2 * A * P / math.pi)) < 1e-4 * scale
    # The energy a flywheel must absorb, from the closed form's work.
    work = np.concatenate([[0.0], np.cumsum(0.5 * (want[1:] + want[:-1]) * h)])
    excess = work - trapezoid * (sw.at - sw.at[0])
    delta = float(excess.max() - excess.min())
    assert close(fs.energy_fluctuation(), delta, 1e-12, scale)
    assert close(fs.flywheel(0.02, W), delta / (0.02 * W * W), 1e-12)
    assert close(fs.speed_fluctuation(0.5, W), delta / (0.5 * W * W), 1e-12)


def test_forces_table_and_plot(engine, tmp_path):
    fs = engine.sweep("phi", start=start(engine), turn=True, steps=72, rate=W).forces()
    text = fs.to_csv(tmp_path / "forces.csv")
    lines = text.strip().splitlines()
    assert lines[0].startswith("phi (deg),Q_phi (N·m),T (J),V (J),P (W)")
    assert len(lines) == 73
    assert (tmp_path / "forces.csv").read_text(encoding="utf-8") == text
    row = [float(x) for x in lines[10].split(",")]
    assert close(row[1], torque(math.radians(row[0])), 1e-12, M * G * R + P * A * 2)
    df = fs.to_pandas()
    assert list(df.columns[:3]) == ["phi (deg)", "Q_phi (N·m)", "T (J)"]
    assert close(df["Q_phi (N·m)"].to_numpy(), fs.effort["phi"], 1e-12, M * G * R + P * A * 2)
    fs.write_svg(tmp_path / "forces.svg")
    assert (tmp_path / "forces.svg").read_text(encoding="utf-8").lstrip().startswith("<svg")


def test_forces_errors(engine, four_bar, FourBar):
    with pytest.raises(kin.InvalidDynamicsError, match="no `bodies` or `loads` section") as e:
        four_bar.forces(four_bar.analyze(four_bar.assemble(phi=0.5, th3=0.5, th4=1.5), rate=1.0))
    assert isinstance(e.value, kin.KinematicsError) and isinstance(e.value, ValueError)
    fs = engine.sweep("phi", start=start(engine), to=1.0, steps=4, rate=W).forces()
    with pytest.raises(KeyError, match="not a driver"):
        fs.mean_effort("th")
    with pytest.raises(ValueError, match="positive"):
        fs.flywheel(0.0, W)
    with pytest.raises(ValueError, match="positive and finite"):
        fs.speed_fluctuation(-1.0, W)
    n = 5
    sim = engine.simulate(
        start=start(engine),
        duration=0.01,
        steps=n - 1,
        values={"phi": np.linspace(0.0, 0.4, n)},
        rates={"phi": np.full(n, 40.0)},
    )
    with pytest.raises(ValueError, match="simulation"):
        sim.forces()


def test_reactions_of_the_gas_engines_joints():
    """The examples' gas engine declares its joints: at every sample the
    bearing's torque is the virtual-power effort, the cylinder pushes
    normal to its axis, and the frame's forces on the links (bearing and
    cylinder) balance their rate of momentum less their weight and the
    gas force on the piston, p1 A (h1 / (h0 + a + b − x))^1.3."""
    from conftest import mechanism

    GasEngine = mechanism("gas_engine")
    v = dict(a=0.025, b=0.1, r3=0.03, m2=1.2, j2=6e-4, m3=0.25, j3=2.5e-4, m4=0.3, p1=40e5, h1=0.005, area=0.0019634954084936207, h0=0.005)
    e = GasEngine(**v)
    start = e.assemble(phi=0.0, th=0.0, x=0.125)
    sw = e.sweep("phi", start=start, turn=True, steps=72, rpm=3000)
    fs = sw.forces()
    assert list(fs.reactions) == ["bearing", "crank_pin", "piston_pin", "cylinder"]
    bearing, cylinder = fs.reactions["bearing"], fs.reactions["cylinder"]
    assert fs.reactions["crank_pin"].effort is None
    scale = np.max(np.abs(bearing.force))
    assert close(bearing.effort, fs.effort["phi"], 1e-10, scale)
    assert np.all(np.abs(cylinder.force[:, 0]) <= 1e-12 * scale)
    m = (v["m2"], v["m3"], v["m4"])
    acc = sum(mass * sw.point(p).acceleration for mass, p in zip(m, ("O", "G3", "C")))
    x = sw["x"]
    gas = v["p1"] * v["area"] * (v["h1"] / (v["h0"] + v["a"] + v["b"] - x)) ** 1.3
    ground = bearing.force + cylinder.force
    assert close(ground[:, 0], acc[:, 0] + gas, 1e-10, scale)
    assert close(ground[:, 1], acc[:, 1] + 9.81 * sum(m), 1e-10, scale)
    # The force of the engine on its frame, weights and gas force
    # included (Norton's shaking force), is what the frame's bearing and
    # cylinder carry, negated; its inertial part is −Σ m a_G.
    assert close(fs.frame_force[:, :2], -ground[:, :2], 1e-10, scale)
    assert close(fs.shaking_force[:, :2], -acc[:, :2], 1e-10, scale)
    # The crank is balanced (its centre of mass on the shaft, which does
    # not move): the bearing holds the crank pin's force and the crank's
    # weight, F_O = F_B + m2 g (0, 1).
    crank_pin = fs.reactions["crank_pin"].force
    assert close(bearing.force[:, 0], crank_pin[:, 0], 1e-10, scale)
    assert close(bearing.force[:, 1], crank_pin[:, 1] + 9.81 * v["m2"], 1e-10, scale)
    assert close(bearing.magnitude(), np.hypot(bearing.force[:, 0], bearing.force[:, 1]), 1e-15, scale)
    assert bearing.force.flags.writeable is False
    # One motion: the same reactions as the sweep's sample.
    i = 10
    r = e.reactions(e.analyze(sw.pose(i), rate=sw.qd["phi"][i]))
    assert close(r["bearing"].force, bearing.force[i], 1e-12, scale)
    assert close(r["bearing"].effort, bearing.effort[i], 1e-12, scale)
    assert r["cylinder"].effort is None


def test_reactions_need_joints(engine):
    with pytest.raises(kin.InvalidDynamicsError, match="none given"):
        engine.reactions(engine.analyze(start(engine), rate=1.0))
    fs = engine.sweep("phi", start=start(engine), to=1.0, steps=4, rate=W).forces()
    assert fs.reactions == {}


def test_mass_sensitivities_are_the_slopes_of_the_effort():
    """The efforts are linear in the masses and moments of inertia: each
    ∂Q/∂m and ∂Q/∂J equals the central difference of the gas engine's
    torque between two designs whose body differs by ±δ (the motion is the
    same: the masses do not change the kinematics)."""
    from conftest import mechanism

    GasEngine = mechanism("gas_engine")
    v = dict(a=0.025, b=0.1, r3=0.03, m2=1.2, j2=6e-4, m3=0.25, j3=2.5e-4, m4=0.3, p1=40e5, h1=0.005, area=0.0019634954084936207, h0=0.005)
    e = GasEngine(**v)
    pose = e.assemble(phi=0.7, th=-0.2, x=0.12)
    motion = e.analyze(pose, rate=300.0, acceleration=1500.0)
    s = e.mass_sensitivities(motion)
    assert list(s) == ["crank", "rod", "piston"]
    assert s["piston"].inertia is None and s["rod"].inertia is not None

    def slope(name, d=1e-3):
        plus = e.replace(**{name: v[name] + d}).forces(motion).effort["phi"]
        minus = e.replace(**{name: v[name] - d}).forces(motion).effort["phi"]
        return (plus - minus) / (2 * d)

    for body, mass, inertia in (("crank", "m2", "j2"), ("rod", "m3", "j3"), ("piston", "m4", None)):
        assert abs(s[body].mass["phi"] - slope(mass)) <= 1e-6 * (1.0 + abs(slope(mass)))
        if inertia is not None:
            assert abs(s[body].inertia["phi"] - slope(inertia, 1e-6)) <= 1e-6 * (1.0 + abs(slope(inertia, 1e-6)))
    # The rod's mass matters here: a test that can fail.
    assert abs(s["rod"].mass["phi"]) > 1e-3


SENSED = """
struct Sensed {
    params   { a, b, r, m, k, c }
    drivers  { phi }
    unknowns { th, x }
    points   { G = polar(r, phi); B = polar(a, phi); C = vec2(x, 0.0); D = vec2(0.0, 0.1); }
    loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
    bodies   { crank(mass = m, center = G, angle = phi, inertia = m * r * r / 3.0); }
    loads    {
        gravity(vec2(0.0, -9.81));
        force(x, -c * rate(x));
        spring(D, B, stiffness = k, free_length = 0.01);
    }
    sensitivities { a, b, r, m, k }
}
"""


def test_effort_sensitivities_are_the_slopes_between_designs():
    """Each ∂Q/∂p equals the fourth-order central difference of the crank
    torque between designs assembled at the same crank angle and analysed
    at the same speed and acceleration (the lengths change the motion, the
    mass and the spring's stiffness the loads)."""
    Sensed = kin.compile(SENSED)
    v = dict(a=0.05, b=0.2, r=0.03, m=1.5, k=400.0, c=2.0)
    e = Sensed(**v)
    for phi in (0.3, 2.0, 4.4):
        pose = e.assemble(phi=phi, th=-0.1, x=0.24)
        motion = e.analyze(pose, rate=W, acceleration=300.0)
        s = e.effort_sensitivities(motion)
        assert list(s) == ["a", "b", "r", "m", "k"]

        def effort(name, step):
            d = e.replace(**{name: v[name] + step})
            m = d.analyze(d.assemble(phi=phi, th=pose["th"], x=pose["x"]), rate=W, acceleration=300.0)
            return d.forces(m).effort["phi"]

        for name, value in s.items():
            h = 1e-3 * v[name]
            slope = (-effort(name, 2 * h) + 8 * effort(name, h) - 8 * effort(name, -h) + effort(name, -2 * h)) / (12 * h)
            assert abs(slope) > 1e-3, (name, slope)
            assert abs(value["phi"] - slope) <= 1e-7 * abs(slope), (name, value["phi"], slope)


def test_effort_sensitivities_without_the_section_are_empty(engine):
    motion = engine.analyze(start(engine), rate=W)
    assert engine.effort_sensitivities(motion) == {}


def test_a_sweeps_effort_sensitivities_are_the_slope_of_its_mean_effort():
    """Over two radians at constant speed, the mean of ∂Q/∂p over the
    samples (the trapezoid rule, as `mean_effort`) equals the central
    difference of the mean effort between designs swept from the same
    start: the mean is linear in the samples."""
    Sensed = kin.compile(SENSED)
    v = dict(a=0.05, b=0.2, r=0.03, m=1.5, k=400.0, c=2.0)
    e = Sensed(**v)
    pose = e.assemble(phi=0.0, th=-0.1, x=0.24)

    def sweep(d):
        return d.sweep("phi", start=pose, to=2.0, steps=90, rate=W, acceleration=0.0)

    sw = sweep(e)
    s = sw.effort_sensitivities()
    assert set(s) == {"a", "b", "r", "m", "k"}
    assert all(x.shape == (len(sw), 1) for x in s.values())
    at = sw.at
    trapezoid = getattr(np, "trapezoid", None) or np.trapz
    for name, values in s.items():
        mean = trapezoid(values[:, 0], at) / (at[-1] - at[0])
        h = 1e-3 * v[name]
        means = [sweep(e.replace(**{name: v[name] + t * h})).forces().mean_effort() for t in (2, 1, -1, -2)]
        slope = (-means[0] + 8 * means[1] - 8 * means[2] + means[3]) / (12 * h)
        assert abs(slope) > 1e-4, (name, slope)
        assert abs(mean - slope) <= 1e-7 * abs(slope), (name, mean, slope)
