"""The Python API: poses, motions, sweeps, batches, sensitivities,
tolerances, outputs and pickling, each checked independently (finite
differences of assembled positions, closed forms, or the one-at-a-time
path against the batched one)."""

import math
import pickle

import numpy as np
import pytest

import loopkin as kin
from conftest import close, mechanism


def test_compiling_the_same_text_gives_the_same_class(FourBar):
    again = kin.compile(FourBar.definition())
    assert again is FourBar
    assert FourBar.__name__ == "FourBar"
    assert FourBar.driver_names() == ("phi",)
    assert FourBar.unknown_names() == ("th3", "th4")
    assert FourBar.kinds() == {"phi": "angle", "th3": "angle", "th4": "angle"}
    assert FourBar.point_names() == ("A", "B", "D", "C", "P")
    [block] = FourBar.blocks()
    assert block["unknowns"] == ["th3", "th4"] and block["modes"] and block["method"].startswith("closed form")


def test_a_mechanism_describes_itself(FourBar):
    # The four-bar's loop, two scalar equations in θ3 and θ4, is one RRR
    # dyad (the coupler and the rocker meeting at C) with two assemblies,
    # the open and the crossed.
    text = FourBar.describe()
    lines = text.splitlines()
    assert lines[0] == "FourBar: 1 driver, 2 unknowns, 2 scalar equations"
    assert "  th3, th4 from equations 1, 2: closed form, RRR dyad, two modes" in lines
    assert lines[-1] == "assemblies: 2"


def test_parameters_are_keywords_and_a_design_is_immutable(FourBar, four_bar):
    assert four_bar.params == dict(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    with pytest.raises(TypeError, match="missing parameter"):
        FourBar(a=0.04)
    with pytest.raises(TypeError, match="no parameter 'e'"):
        FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5, e=1.0)
    with pytest.raises(AttributeError, match="immutable"):
        four_bar.a = 1.0
    other = four_bar.replace(a=0.05)
    assert other.params["a"] == 0.05 and four_bar.params["a"] == 0.04
    assert other != four_bar and four_bar.replace() == four_bar


def test_every_assembly_closes_and_can_be_asked_for_by_its_modes(four_bar):
    poses = four_bar.assemble_all(phi=0.5)
    assert [p.modes for p in poses] == [("+",), ("-",)]
    for p in poses:
        assert np.all(np.abs(four_bar.residual(p)) < 1e-15)
        again = four_bar.assemble(phi=0.5, modes=p.modes)
        assert np.array_equal(again.array, p.array)
    # The two assemblies are mirror images about the line BD.
    assert abs(poses[0]["th3"] - poses[1]["th3"]) > 0.1


def _fd_point(m, pose, name, h=1e-5):
    """dr/dφ and d²r/dφ² of a point by central differences of assembled
    positions (in the pose's modes)."""

    def r(phi):
        q = m.assemble(pose, phi=phi, modes=pose.modes)
        return m.analyze(q).points[name].position

    phi = pose["phi"]
    rp, r0, rm = r(phi + h), r(phi), r(phi - h)
    return (rp - rm) / (2 * h), (rp - 2 * r0 + rm) / (h * h)


def test_velocities_and_accelerations_against_finite_differences(four_bar):
    w, al = 10.0, 3.0
    for pose in four_bar.assemble_all(phi=1.1):
        s = four_bar.analyze(pose, rate=w, acceleration=al)
        d1, d2 = _fd_point(four_bar, pose, "P")
        assert close(s.points["P"].velocity, w * d1, 1e-7)
        assert close(s.points["P"].acceleration, w * w * d2 + al * d1, 1e-4)
        assert s.conditioning > 0 and s.residual < 1e-15


def test_step_is_assemble_then_analyze(four_bar):
    guess = four_bar.pose(phi=0.7, th3=0.8, th4=1.5)
    s = four_bar.step(guess, rate=2.0)
    t = four_bar.analyze(four_bar.assemble(guess), rate=2.0)
    assert np.array_equal(s.q.array, t.q.array)
    assert close(s.qdd.array, t.qdd.array, 1e-14)


def test_a_sweep_gives_the_motion_of_every_sample(four_bar):
    start = four_bar.assemble_all(phi=0.5)[1]
    sw = four_bar.sweep("phi", start=start, turn=True, steps=72, rpm=600)
    assert len(sw) == 72 and sw.stop is None
    w = 600 * 2 * math.pi / 60
    assert np.allclose(sw.at, 0.5 + np.arange(72) * 2 * math.pi / 72, rtol=0, atol=1e-14)
    assert np.all(sw.qd["phi"] == w)
    P = sw.point("P")
    assert P.position.shape == (72, 2) and P.speed.shape == (72,)
    for i in (0, 17, 71):
        s = four_bar.analyze(sw.pose(i), rate=w)
        assert close(sw["th3"][i], s.q["th3"], 1e-15)
        assert close(sw.qdd["th4"][i], s.qdd["th4"], 1e-13, scale=w * w)
        assert close(P.velocity[i], s.points["P"].velocity, 1e-13, scale=w)
    # The branch is kept: every sample in the start's mode, det Φ_u of one sign.
    assert len(set(np.sign(sw.det_sign))) == 1


def test_a_sweep_stops_at_a_limit_position_where_the_closed_form_says(FourBar):
    # a + d > b + c: the crank cannot turn; it stops where |D − B| = b + c.
    a, b, c, d = 0.08, 0.10, 0.07, 0.15
    m = FourBar(a=a, b=b, c=c, d=d, p=0.05, beta=0.0)
    start = m.assemble_all(phi=0.5)[0]
    sw = m.sweep("phi", start=start, from_=0.5, to=3.0, steps=250)
    assert sw.stop is not None and sw.stop.kind == "limit_position"
    assert "th3, th4" in sw.stop.unknowns and "limit" in str(sw.stop)
    limit = math.acos((a * a + d * d - (b + c) ** 2) / (2 * a * d))
    assert abs(sw.stop.at - limit) < 1e-9
    assert sw.at[-1] <= limit + 1e-12 and len(sw) < 251


def test_csv_text_and_pandas_have_the_same_columns(four_bar, tmp_path):
    start = four_bar.assemble_all(phi=0.0)[0]
    sw = four_bar.sweep("phi", start=start, turn=True, steps=12, rate=3.0)
    path = tmp_path / "sweep.csv"
    text = sw.to_csv(path)
    assert path.read_text() == text
    header = text.splitlines()[0].split(",")
    df = sw.to_pandas()
    assert list(df.columns) == header and len(df) == 12
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    assert close(data[:, header.index("th3_rad")], sw["th3"], 1e-12)
    assert close(df["P_vx_m_s"].to_numpy(), sw.point("P").velocity[:, 0], 1e-15)
    assert len(sw.to_text(every=6).splitlines()) == 1 + 3
    assert sw.to_csv(unit="mm").splitlines()[0].split(",")[header.index("P_x_m")] == "P_x_mm"


def test_a_sweeps_columns_are_read_only_and_its_tables_read_them(four_bar):
    # The columns are the sweep's own data (no copy): numpy refuses to
    # write them, and the CSV and the deviations read the same values.
    start = four_bar.assemble_all(phi=0.0)[0]
    sw = four_bar.sweep("phi", start=start, turn=True, steps=24, rate=2.0)
    for column in (sw.at, sw["th3"], sw.qd["th4"], sw.qdd["th3"], sw.conditioning, sw.residual):
        with pytest.raises(ValueError):
            column[0] = 1.0
    with pytest.raises(ValueError):
        sw._points[0, 0, 0, 0] = 1.0
    header, rows = sw._native.table("m")
    assert rows.shape == (24, len(header))
    assert np.array_equal(rows[:, header.index("th4_rad")], sw["th4"])
    assert np.array_equal(rows[:, header.index("P_ay_m_s2")], sw.point("P").acceleration[:, 1])
    assert sw._native.columns()["q"] is sw.q._table


def test_the_animation_and_the_plots_are_written(four_bar, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from loopkin import plot

    start = four_bar.assemble_all(phi=0.0)[0]
    sw = four_bar.sweep("phi", start=start, turn=True, steps=36, rate=1.0)
    html = tmp_path / "four_bar.html"
    sw.write_animation(html, links=[("A", "B"), ("B", "C"), ("C", "D"), ("B", "P"), ("C", "P")])
    page = html.read_text()
    assert "<svg" in page and page.count("FourBar") >= 1
    with pytest.raises(ValueError, match="projection"):
        sw.write_animation(html, projection="xw")
    axes = plot.motion(sw)
    assert len(axes[0].lines) == 2
    ax = plot.path(sw, ["P", "C"])
    xs = ax.lines[0].get_xdata()
    assert np.array_equal(xs, sw.point("P").position[:, 0])
    plot.point(sw, "P")


def test_sensitivities_against_finite_differences_of_the_parameters(four_bar):
    pose = four_bar.assemble_all(phi=1.3)[0]
    s = four_bar.analyze(pose, rate=5.0)
    sens = four_bar.sensitivities(s)
    assert set(sens) == {"a", "b", "c", "d", "p", "beta"}
    for p, h in (("a", 1e-7), ("d", 1e-7), ("beta", 1e-7)):
        plus, minus = four_bar.replace(**{p: four_bar.params[p] + h}), four_bar.replace(**{p: four_bar.params[p] - h})

        def at(m):
            q = m.assemble(pose, modes=pose.modes)
            return m.analyze(q, rate=5.0)

        sp, sm = at(plus), at(minus)
        dq = (sp.q.array - sm.q.array) / (2 * h)
        dv = (sp.points["P"].velocity - sm.points["P"].velocity) / (2 * h)
        assert close(sens[p].q.array, dq, 1e-6)
        assert close(sens[p].points["P"].velocity, dv, 1e-5)


def test_tolerance_deviations_are_the_sum_of_the_sensitivities(four_bar):
    start = four_bar.assemble_all(phi=0.0)[0]
    sw = four_bar.sweep("phi", start=start, turn=True, steps=8, rate=1.0)
    t = {"a": 1e-4, "b": 2e-4, "beta": 1e-3}
    dev = sw.deviations("P", t)
    assert dev.position_components.shape == (8, 2)
    for i in (0, 5):
        sens = four_bar.sensitivities(four_bar.analyze(sw.pose(i), rate=1.0))
        worst = sum(np.abs(sens[k].points["P"].position) * v for k, v in t.items())
        rss = np.sqrt(sum((sens[k].points["P"].position * v) ** 2 for k, v in t.items()))
        assert close(dev.position_components[i], worst, 1e-12)
        assert close(dev.position_rss[i], rss, 1e-12)


def test_a_batch_equals_the_designs_run_one_at_a_time(FourBar, four_bar):
    rng = np.random.default_rng(7)
    n = 40
    a = rng.uniform(0.02, 0.06, n)
    b = rng.uniform(0.10, 0.14, n)
    a[3] = 0.09  # cannot turn: stops at a limit position
    start = four_bar.assemble_all(phi=0.0)[0]
    res = four_bar.batch({"a": a, "b": b}, start=start, sweep=dict(driver="phi", turn=True, steps=24, rpm=60), outputs=["th3", "P.velocity", "conditioning"])
    assert res["th3"].shape == (n, 24) and res["P.velocity"].shape == (n, 24, 2)
    assert res.params.shape == (n, 6) and np.array_equal(res.params[:, 0], a)
    for i in range(n):
        m = four_bar.replace(a=a[i], b=b[i])
        try:
            sw = m.sweep("phi", start=start, turn=True, steps=24, rpm=60)
        except kin.KinematicsError as e:  # pragma: no cover
            raise AssertionError(e)
        k = len(sw)
        assert res.samples[i] == k
        assert np.array_equal(res["th3"][i, :k], sw["th3"])
        assert np.array_equal(res["P.velocity"][i, :k], sw.point("P").velocity)
        assert np.array_equal(res["conditioning"][i, :k], sw.conditioning)
        assert np.all(np.isnan(res["th3"][i, k:]))
        assert res.ok[i] == (sw.stop is None)
        assert (res.stops[i] is None) == (sw.stop is None)
    assert not res.ok[3] and "limit" in res.stops[3]


def test_a_batch_of_single_steps(four_bar):
    d = np.linspace(0.10, 0.12, 5)
    start = four_bar.pose(phi=0.3, th3=0.9, th4=1.6)
    res = four_bar.batch({"d": d}, start=start, rate=2.0, outputs=["th4", "th4.rate", "P"])
    assert res["th4"].shape == (5,) and res["P"].shape == (5, 2)
    for i in range(5):
        s = four_bar.replace(d=d[i]).step(start, rate=2.0)
        assert res["th4"][i] == s.q["th4"] and res["th4.rate"][i] == s.qd["th4"]
        assert np.array_equal(res["P"][i], s.points["P"].position)
    with pytest.raises(KeyError, match="not an output"):
        four_bar.batch({"d": d}, start=start, outputs=["Q"])
    with pytest.raises(ValueError, match="one value per design"):
        four_bar.batch({"d": d, "a": d[:3]}, start=start)


def test_a_reduced_batch_keeps_each_designs_extremes(four_bar):
    rng = np.random.default_rng(3)
    n = 30
    a = rng.uniform(0.02, 0.06, n)
    a[4] = 0.09  # does not assemble at the start: no sample, NaN
    start = four_bar.assemble_all(phi=0.0)[0]
    sweep = dict(driver="phi", turn=True, steps=48, rpm=60)
    every = four_bar.batch({"a": a}, start=start, sweep=sweep, outputs=["th3", "P.acceleration"])
    ran = every.samples > 0
    assert not ran[4] and ran.sum() == n - 1
    acc = every["P.acceleration"][ran]
    norm = np.linalg.norm(acc, axis=2)
    peak = four_bar.batch({"a": a}, start=start, sweep=sweep, outputs=["th3", "P.acceleration"], reduce="peak")
    assert peak["th3"].shape == (n,) and peak["P.acceleration"].shape == (n,)
    assert np.allclose(peak["P.acceleration"][ran], norm.max(axis=1), rtol=1e-15, atol=0)
    assert np.array_equal(peak["th3"][ran], np.abs(every["th3"][ran]).max(axis=1))
    assert np.isnan(peak["th3"][4]) and np.isnan(peak["P.acceleration"][4])
    high = four_bar.batch({"a": a}, start=start, sweep=sweep, outputs=["P.acceleration"], reduce="max")
    low = four_bar.batch({"a": a}, start=start, sweep=sweep, outputs=["P.acceleration"], reduce="min")
    assert high["P.acceleration"].shape == (n, 2)
    assert np.array_equal(high["P.acceleration"][ran], acc.max(axis=1))
    assert np.array_equal(low["P.acceleration"][ran], acc.min(axis=1))
    assert np.array_equal(peak.samples, every.samples) and peak.stops == every.stops
    with pytest.raises(ValueError, match="reduce must be"):
        four_bar.batch({"a": a}, start=start, sweep=sweep, outputs=["th3"], reduce="mean")


def test_a_batch_of_positions_only_is_each_designs_poses(four_bar):
    rng = np.random.default_rng(5)
    n = 12
    a = rng.uniform(0.03, 0.05, n)
    start = four_bar.assemble_all(phi=0.0)[0]
    sweep = dict(driver="phi", turn=True, steps=90)
    res = four_bar.batch({"a": a}, start=start, sweep=sweep, outputs=["th3", "P"], positions_only=True)
    assert bool(res.ok.all()) and res["P"].shape == (n, 90, 2)
    for k in range(n):
        poses = four_bar.replace(a=a[k]).poses("phi", start=start, turn=True, steps=90)
        assert np.array_equal(res["th3"][k], poses["th3"])
        assert np.array_equal(res["P"][k], poses.point("P").position)
    with pytest.raises(kin.InvalidOptionError, match="a point's position"):
        four_bar.batch({"a": a}, start=start, sweep=sweep, outputs=["P.velocity"], positions_only=True)


def test_designs_and_classes_pickle_as_their_text(FourBar, four_bar):
    again = pickle.loads(pickle.dumps(four_bar))
    assert again == four_bar and type(again) is FourBar
    assert pickle.loads(pickle.dumps(FourBar)) is FourBar


def test_a_design_runs_in_another_process(four_bar):
    import concurrent.futures
    import multiprocessing

    start = four_bar.assemble_all(phi=0.2)[0]
    ctx = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(1, mp_context=ctx) as pool:
        there = pool.submit(_sweep_th3, four_bar, start).result()
    assert np.array_equal(there, _sweep_th3(four_bar, start))


def _sweep_th3(m, start):
    return np.array(m.sweep("phi", start=start, turn=True, steps=10)["th3"])


def test_a_spatial_mechanism_has_frames_and_three_components():
    RobotArm = mechanism("robot_arm")
    m = RobotArm(l1=1.2, l2=0.6, l3=0.2, alpha=math.pi / 3)
    pose = m.assemble(q1=0.0, q4=0.0, q5=0.0)
    sw = m.sweep("q1", start=pose, turn=True, steps=8, rate=1.0)
    arm = sw.frame("arm")
    assert arm.rotation.shape == (8, 3, 3) and sw.point("B").position.shape == (8, 3)
    # A turn about z carries B round a circle at constant height.
    z = sw.point("B").position[:, 2]
    assert np.ptp(z) < 1e-15
    # R is orthonormal at every sample.
    for R in arm.rotation:
        assert close(R @ R.T, np.eye(3), 1e-15)


def test_options_are_checked(four_bar):
    with pytest.raises(kin.InvalidOptionError):
        four_bar.assemble(phi=0.5, options=kin.Options(tolerance=-1.0))
    with pytest.raises(ValueError, match="branch"):
        four_bar.assemble(phi=0.5, options=kin.Options(branch="left"))
    neg = four_bar.assemble(phi=0.5, th3=1.0, th4=1.0, options=kin.Options(branch="negative"))
    pos = four_bar.assemble(phi=0.5, th3=1.0, th4=1.0, options=kin.Options(branch="positive"))
    assert four_bar.analyze(neg).det_sign < 0 < four_bar.analyze(pos).det_sign


def test_poses_are_the_sweeps_positions(FourBar, four_bar):
    start = four_bar.assemble_all(phi=0.3)[1]
    ps = four_bar.poses("phi", start=start, turn=True, steps=90)
    sw = four_bar.sweep("phi", start=start, turn=True, steps=90)
    assert ps.stop is None and len(ps) == 90
    assert np.array_equal(ps.at, sw.at)
    assert close(ps["th3"], sw["th3"], 1e-14)
    assert close(ps.point("P"), sw.point("P").position, 1e-15)
    # One point type for sweeps and poses: the poses' has no motion.
    assert type(ps.point("P")) is type(sw.point("P"))
    assert close(ps.point("P").position, sw.point("P").position, 1e-15)
    assert ps.point("P").velocity is None
    with pytest.raises(ValueError, match="positions only"):
        ps.point("P").speed
    # A crank that cannot turn: the poses end before the limit position.
    m = FourBar(a=0.08, b=0.10, c=0.07, d=0.15, p=0.05, beta=0.0)
    short = m.poses("phi", start=m.assemble_all(phi=0.5)[0], from_=0.5, to=3.0, steps=250)
    # |D − B| = b + c at φ = 90°: the limit, by bisection as the sweep finds it.
    assert short.stop is not None and short.stop.kind == "limit_position"
    assert abs(short.stop.at - math.pi / 2) < 1e-9 and short.at[-1] <= math.pi / 2 and len(short) < 251


def test_the_benchmarks_native_repeat_runs_the_same_sweeps(FourBar, four_bar):
    # The hook python/benchmarks/python_overhead.py times against the
    # calls from Python: it takes their arguments and refuses what they
    # refuse (a sweep that cannot start, an unknown kind).
    start = four_bar.assemble_all(phi=0.3)[1]
    q = start.array.tolist()
    spec = (None, None, 1.0, 36, 10.0, 0.0, "stop")
    assert four_bar._m._repeat_in_rust("sweep", "phi", q, spec, None, 2) == (36, None)
    assert four_bar._m._repeat_in_rust("poses", "phi", q, spec, None, 2) == (36, None)
    # A crank that cannot turn: both stop where the Python calls stop.
    m = FourBar(a=0.08, b=0.10, c=0.07, d=0.15, p=0.05, beta=0.0)
    s = m.assemble_all(phi=0.5)[0]
    short = (0.5, 3.0, None, 250, 1.0, 0.0, "stop")
    rows, stop = m._m._repeat_in_rust("sweep", "phi", s.array.tolist(), short, None, 1)
    sw = m.sweep("phi", start=s, from_=0.5, to=3.0, steps=250)
    assert (rows, stop) == (len(sw), sw.stop.kind) and stop == "limit_position"
    rows, stop = m._m._repeat_in_rust("poses", "phi", s.array.tolist(), short, None, 1)
    ps = m.poses("phi", start=s, from_=0.5, to=3.0, steps=250)
    assert (rows, stop) == (len(ps), ps.stop.kind)
    with pytest.raises(ValueError, match="kind"):
        four_bar._m._repeat_in_rust("forces", "phi", q, spec, None, 1)
    with pytest.raises(kin.InvalidOptionError):
        four_bar._m._repeat_in_rust("poses", "th3", q, spec, None, 1)
    # The arrays handed out are C-ordered, read-only, of the sweep's
    # shape, and own no copy: their base is the sweep's memory itself.
    sw = four_bar.sweep("phi", start=start, turn=True, steps=36)
    for a, shape in ((sw.q._table, (36, 3)), (sw._points, (36, 5, 3, 2))):
        assert a.shape == shape and a.flags.c_contiguous and not a.flags.writeable
        assert not isinstance(a.base, np.ndarray)
    ps = four_bar.poses("phi", start=start, turn=True, steps=36)
    assert ps.points.shape == (36, 5, 2) and not ps.points.flags.writeable
    assert not isinstance(ps.points.base, np.ndarray)


def test_a_simulation_follows_its_profile(four_bar):
    # The crank starts from rest with φ'' = 20 rad/s² for one second:
    # φ = 10 t², φ' = 20 t; every sample is the analysis at its pose.
    start = four_bar.assemble_all(phi=0.0)[1]
    t = np.linspace(0.0, 1.0, 101)
    sim = four_bar.simulate(start=start, duration=1.0, steps=100, values={"phi": 10 * t * t},
                            rates={"phi": 20 * t}, accelerations={"phi": np.full(101, 20.0)})
    assert sim.variable == "t" and len(sim) == 101 and sim.stop is None
    assert np.allclose(sim.at, t, rtol=0, atol=1e-15)
    assert np.array_equal(sim["phi"], 10 * t * t) and np.array_equal(sim.qd["phi"], 20 * t)
    for k in (0, 37, 100):
        s = four_bar.analyze(sim.pose(k), rate=20 * t[k], acceleration=20.0)
        assert close(sim.qdd["th3"][k], s.qdd["th3"], 1e-13, scale=400)
        assert close(sim.point("P").velocity[k], s.points["P"].velocity, 1e-13, scale=20)
    with pytest.raises(ValueError, match="101"):
        four_bar.simulate(start=start, duration=1.0, steps=100, values={"phi": t[:50]})
    with pytest.raises(KeyError, match="not a driver"):
        four_bar.simulate(start=start, duration=1.0, steps=100, rates={"th3": t})


def test_a_batch_sweep_takes_its_rate_and_acceleration_from_the_sweep(four_bar):
    start = four_bar.assemble_all(phi=0.0)[0]
    res = four_bar.batch({"a": [0.04, 0.05]}, start=start, outputs=["th3.acceleration"],
                         sweep=dict(driver="phi", turn=True, steps=12, rate=3.0, acceleration=2.0))
    for i, a in enumerate((0.04, 0.05)):
        sw = four_bar.replace(a=a).sweep("phi", start=start, turn=True, steps=12, rate=3.0, acceleration=2.0)
        assert np.array_equal(res["th3.acceleration"][i], sw.qdd["th3"])
    with pytest.raises(TypeError, match="rate or its rpm"):
        four_bar.batch({"a": [0.04]}, start=start, sweep=dict(driver="phi", rate=3.0, rpm=60))
    with pytest.raises(TypeError, match="not both"):
        four_bar.batch({"a": [0.04]}, start=start, acceleration=1.0, sweep=dict(driver="phi", acceleration=2.0))
    with pytest.raises(TypeError, match="unknown sweep key"):
        four_bar.batch({"a": [0.04]}, start=start, sweep=dict(driver="phi", stepz=3))


def test_assemble_all_at_every_scale_assemble_handles(FourBar):
    # The same four-bar drawn 10^±100 times larger: every assembly's
    # angles are those of the unscaled design (the loop equations are
    # homogeneous in the lengths), as assemble gives them.
    base = [p.array for p in FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5).assemble_all(phi=0.5)]
    for s in (1e-100, 1e100):
        m = FourBar(a=0.04 * s, b=0.12 * s, c=0.10 * s, d=0.11 * s, p=0.06 * s, beta=0.5)
        got = [p.array for p in m.assemble_all(phi=0.5)]
        assert len(got) == len(base) == 2
        for g, b in zip(got, base):
            assert close(g, b, 1e-14)


def test_a_sweep_backwards_needs_a_negative_rate(four_bar):
    start = four_bar.assemble(phi=0.5, th3=0.9, th4=1.7)
    with pytest.raises(ValueError, match="runs phi backwards.*give a negative rate"):
        four_bar.sweep("phi", start=start, turns=-1, rate=10.0)
    with pytest.raises(ValueError, match="runs phi backwards"):
        four_bar.sweep("phi", start=start, to=0.0, steps=10, rate=10.0)
    # With the rate of the motion, the samples' rates are that motion's:
    # φ' = −10 and each unknown's rate the slope of its values times it.
    sw = four_bar.sweep("phi", start=start, turns=-1, steps=3600, rate=-10.0)
    assert sw.stop is None and close(sw.qd["phi"], -10.0, 1e-15)
    slope = np.gradient(sw["th3"], sw.at)
    assert close(sw.qd["th3"][1:-1], -10.0 * slope[1:-1], 1e-4, scale=10.0)


def test_a_sweep_forwards_and_from_a_given_value(four_bar):
    """The check of a sweep's direction reads the start's value of the
    driver only where it matters, and reads it right: forwards to an end
    above the start runs; from a given value, an end below it with a
    positive rate is backwards, and with a negative rate runs."""
    start = four_bar.assemble(phi=0.5, th3=0.9, th4=1.7)
    sw = four_bar.sweep("phi", start=start, to=1.0, steps=10, rate=10.0)
    assert len(sw) == 11 and sw.stop is None and close(sw.at[-1], 1.0, 1e-15)
    with pytest.raises(ValueError, match="runs phi backwards, from 1 to 0.7"):
        four_bar.sweep("phi", start=start, from_=1.0, to=0.7, steps=10, rate=10.0)
    sw = four_bar.sweep("phi", start=start, from_=1.0, to=0.7, steps=10, rate=-10.0)
    assert len(sw) == 11 and close(sw.at[0], 1.0, 1e-15) and close(sw.qd["phi"], -10.0, 1e-15)


def test_a_sweeps_columns_are_made_when_read(four_bar):
    """A sweep hands each column to numpy at its first reading, and the
    same array after; the tables and figures read every column, whether
    read before or not."""
    start = four_bar.assemble(phi=0.3, th3=1.0, th4=1.6)
    sw = four_bar.sweep("phi", start=start, turn=True, steps=12, rate=2.0)
    # Before any column is read: the CSV has every sample.
    text = sw.to_csv()
    assert len(text.strip().splitlines()) == 1 + 12
    native = sw._native
    assert native.column(1) is native.column(1)
    assert sw.at is sw.at and sw.q._table is native.column(1)
    with pytest.raises(ValueError, match="9 columns, not column 9"):
        native.column(9)
    again = four_bar.sweep("phi", start=start, turn=True, steps=12, rate=2.0)
    assert np.array_equal(again.qd["th3"], sw.qd["th3"])
    assert again.to_csv() == text and len(again) == 12
    assert sw.variable == "phi" and sw.change_points == [] and sw.stop is None


def test_results_are_read_only(four_bar):
    """The arrays a result hands out hold its data (which its tables and
    figures read back): none can be written."""
    start = four_bar.assemble(phi=0.3, th3=1.0, th4=1.6)
    sw = four_bar.sweep("phi", start=start, turn=True, steps=12)
    s = four_bar.analyze(start, rate=2.0)
    for a in (
        sw.at,
        sw["th3"],
        sw.qd["th3"],
        sw.point("P").position,
        sw.conditioning,
        s.q.array,
        s.qd.array,
        s.points["P"].velocity,
        s.frames if not s.frames else next(iter(s.frames.values())).origin,
    ):
        if isinstance(a, np.ndarray):
            assert a.flags.writeable is False
            with pytest.raises(ValueError):
                a[...] = 0.0
    assert sw.to_csv().startswith("phi")


def test_a_model_without_parameters_runs_one_design_per_row():
    Crank = kin.compile(
        "struct Crank { drivers { phi } unknowns { th, x } loops { polar(0.1, phi) + polar(0.3, th) == vec2(x, 0.0); } }"
    )
    m = Crank()
    res = m.batch({}, start=m.pose(phi=0.3, th=-0.1, x=0.39), rate=2.0, outputs=["x", "x.rate"])
    assert res["x"].shape == (1,) and res.ok.all()
    # x = a cos φ + √(b² − a² sin² φ), ẋ = −a ω sin φ (1 + a cos φ / √…).
    root = math.sqrt(0.09 - 0.01 * math.sin(0.3) ** 2)
    assert abs(res["x"][0] - (0.1 * math.cos(0.3) + root)) < 1e-15
    assert abs(res["x.rate"][0] + 0.2 * math.sin(0.3) * (1 + 0.1 * math.cos(0.3) / root)) < 1e-14
