"""Random parameters, poses and rates, from ordinary to absurd: every call
either returns finite numbers or raises a KinematicsError; nothing returns
NaN and nothing crashes the interpreter."""

import math

import numpy as np
import pytest

import loopkin as kin
from conftest import mechanism


def finite_motion(s):
    arrays = [s.q.array, s.qd.array, s.qdd.array]
    arrays += [v for p in s.points.values() for v in (p.position, p.velocity, p.acceleration)]
    return all(np.all(np.isfinite(a)) for a in arrays) and math.isfinite(s.conditioning)


def draw(rng, n):
    """n values: mostly sub-metre lengths, sometimes tiny, huge, zero,
    negative or not finite."""
    kind = rng.integers(0, 10, n)
    v = 10.0 ** rng.uniform(-3, 1, n)
    v[kind == 0] = 10.0 ** rng.uniform(-300, 300, (kind == 0).sum())
    v[kind == 1] = 0.0
    v[kind == 2] *= -1
    v[kind == 3] = rng.choice([np.nan, np.inf, -np.inf, 1e308, 5e-324], (kind == 3).sum())
    return v


@pytest.mark.parametrize("name", ["four_bar", "slider_crank", "rssr", "r_rtr_rrt"])
def test_random_designs_never_return_nan(name):
    cls = mechanism(name)
    rng = np.random.default_rng(2026 + len(name))
    params = cls.parameter_names()
    counts = {"ok": 0, "raised": 0}
    for trial in range(2000):
        values = dict(zip(params, draw(rng, len(params))))
        try:
            m = cls(**values)
        except kin.KinematicsError:
            counts["raised"] += 1
            continue
        coords = cls.coordinate_names()
        guess = dict(zip(coords, rng.uniform(-4, 4, len(coords))))
        rate, acc = draw(rng, 2)
        try:
            poses = m.assemble_all(guess)
        except kin.KinematicsError:
            counts["raised"] += 1
            continue
        for pose in poses:
            assert np.all(np.isfinite(pose.array))
            try:
                s = m.analyze(pose, rate=rate, acceleration=acc)
            except kin.KinematicsError:
                counts["raised"] += 1
                continue
            assert finite_motion(s), (values, pose)
            counts["ok"] += 1
        sw = m.sweep(cls.driver_names()[0], start=poses[0], steps=8, turn=True, rate=1.0)
        for col in (sw.q, sw.qd, sw.qdd):
            assert all(np.all(np.isfinite(col[k])) for k in coords)
        assert sw.stop is None or isinstance(sw.stop.message, str)
    # The fuzz reaches both outcomes.
    assert counts["ok"] > 20 and counts["raised"] > 20, counts


def test_random_batches_never_return_nan_where_a_design_ran():
    cls = mechanism("four_bar")
    rng = np.random.default_rng(11)
    n = 3000
    params = {p: draw(rng, n) for p in cls.parameter_names()}
    base = cls(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    start = base.assemble_all(phi=0.3)[0]
    res = base.batch(params, start=start, sweep=dict(driver="phi", turn=True, steps=6), outputs=["th3", "P.acceleration"])
    for i in range(n):
        k = res.samples[i]
        assert np.all(np.isfinite(res["th3"][i, :k])) and np.all(np.isfinite(res["P.acceleration"][i, :k]))
        assert np.all(np.isnan(res["th3"][i, k:]))
        assert (k == 6) == (res.stops[i] is None)
    assert res.ok.sum() > 20 and (~res.ok).sum() > 20


def finite_forces(f):
    arrays = [np.asarray(f.effort), f.shaking_force, f.shaking_moment]
    scalars = [f.kinetic_energy, f.potential_energy, f.power]
    return all(np.all(np.isfinite(a)) for a in arrays) and all(math.isfinite(x) for x in scalars)


def test_random_engines_never_return_nan_forces():
    """The engine's masses, inertias and gas law drawn as the designs
    above (negative masses, a gas height below zero, overflowing powers):
    every force is finite or raises a KinematicsError."""
    cls = mechanism("gas_engine")
    assert cls.has_dynamics()
    rng = np.random.default_rng(2027)
    params = cls.parameter_names()
    counts = {"ok": 0, "raised": 0}
    for trial in range(1500):
        values = dict(zip(params, draw(rng, len(params))))
        try:
            m = cls(**values)
            poses = m.assemble_all(dict(zip(cls.coordinate_names(), rng.uniform(-4, 4, 3))))
        except kin.KinematicsError:
            counts["raised"] += 1
            continue
        rate, acc = draw(rng, 2)
        for pose in poses:
            try:
                f = m.forces(m.analyze(pose, rate=rate, acceleration=acc))
            except kin.KinematicsError:
                counts["raised"] += 1
                continue
            assert finite_forces(f), (values, pose)
            counts["ok"] += 1
        sw = m.sweep("phi", start=poses[0], steps=8, turn=True, rate=float(rate) if math.isfinite(rate) else 1.0)
        try:
            fs = sw.forces()
        except kin.KinematicsError:
            counts["raised"] += 1
            continue
        for col in (fs.effort["phi"], fs.kinetic_energy, fs.potential_energy, fs.power, fs.shaking_force):
            assert np.all(np.isfinite(col)), values
    assert counts["ok"] > 20 and counts["raised"] > 20, counts
