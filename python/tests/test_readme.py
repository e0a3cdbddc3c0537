"""The README's Python example runs as printed."""

import os
import re
from pathlib import Path

import numpy as np

README = Path(__file__).resolve().parents[2] / "README.md"


def test_the_readme_example_runs(tmp_path):
    text = README.read_text(encoding="utf-8")
    section = text[text.index("## Python") :]
    section = section[: section.index("\n## ", 1)]
    blocks = re.findall(r"```python\n(.*?)```", section, re.S)
    assert len(blocks) == 2
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        scope = {"a_values": np.linspace(0.03, 0.05, 50), "b_values": np.full(50, 0.12)}
        for code in blocks:
            exec(compile(code, "README.md", "exec"), scope)
    finally:
        os.chdir(here)
    fs = scope["fs"]
    assert len(fs) == 360 and (tmp_path / "engine-forces.svg").exists()
    assert fs.flywheel(0.02, 40.0) > 0.0
    assert (tmp_path / "fourbar.csv").exists() and (tmp_path / "fourbar.html").exists()
    res, sw = scope["res"], scope["sw"]
    assert res["P.acceleration"].shape == (50, 360, 2) and res.ok.all()
    assert len(sw) == 360 and sw.stop is None
