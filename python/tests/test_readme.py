"""The Python code of the project's README and of the package's README runs
as printed, from a fresh namespace, in a temporary folder."""

import math
import os
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def blocks(path):
    text = path.read_text(encoding="utf-8")
    return re.findall(r"```python\n(.*?)```", text, re.S)


def run(path, tmp_path):
    scope = {}
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        for code in blocks(path):
            exec(compile(code, str(path), "exec"), scope)
    finally:
        os.chdir(here)
    return scope


def test_the_front_page_quick_start_runs(tmp_path, capsys):
    assert len(blocks(ROOT / "README.md")) == 1
    scope = run(ROOT / "README.md", tmp_path)
    sw = scope["sw"]
    assert len(sw) == 360 and sw.stop is None
    # The rocker's swing, against the law of cosines at the two dead
    # centres of the crank-rocker (crank and coupler in line: the rocker
    # pin at distance b + a and b − a from the crank's pivot).
    a, b, c, d = 0.04, 0.12, 0.10, 0.11

    def rocker(r):
        # Angle at D between DA (pointing to −x) and DC, with |AC| = r.
        return math.pi - math.acos((c * c + d * d - r * r) / (2 * c * d))

    swing = abs(rocker(b + a) - rocker(b - a))
    assert abs((sw["th4"].max() - sw["th4"].min()) - swing) < 1e-3
    assert "None" in capsys.readouterr().out


def test_the_package_readme_runs(tmp_path):
    assert len(blocks(ROOT / "python" / "README.md")) == 3
    scope = run(ROOT / "python" / "README.md", tmp_path)
    fs = scope["fs"]
    assert len(fs) == 360 and (tmp_path / "engine-forces.svg").exists()
    assert fs.flywheel(0.02, 40.0) > 0.0
    assert (tmp_path / "fourbar.csv").exists() and (tmp_path / "fourbar.html").exists()
    res, sw = scope["res"], scope["sw"]
    assert res["P.acceleration"].shape == (50, 360, 2) and res.ok.all()
    assert len(sw) == 360 and sw.stop is None
    # The offset slider-crank's time ratio (π + α)/(π − α), α = asin(e/(b − a))
    # − asin(e/(a + b)), and stroke √((a + b)² − e²) − √((b − a)² − e²).
    turn = scope["turn"]
    alpha = math.asin(0.5) - math.asin(0.25)
    assert abs(turn.time_ratio("x").ratio - (math.pi + alpha) / (math.pi - alpha)) < 1e-8
    assert abs(turn.stroke("x").length - (math.sqrt(15) - math.sqrt(3))) < 2e-9
