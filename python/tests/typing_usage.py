"""The package's annotations as a user's code meets them: every call below
is documented (values with units as strings, poses as mappings, a
forward run, a batch) and must pass ``mypy`` as well as run. CI type-checks this file
with the package (``mypy -p loopkin``, then ``mypy tests/typing_usage.py``)
and runs it.

    python tests/typing_usage.py
"""

import inspect
import math
import typing

import numpy as np

import loopkin as kin

FourBar = kin.compile(
    """
    struct TypedFourBar {
        params   { a, b, c, d, beta }
        drivers  { phi }
        unknowns { th3, th4 }
        points   { B = polar(a, phi); C = vec2(d, 0.0) + polar(c, th4); P = B + polar(0.05, th3 + beta); }
        loops    { B + polar(b, th3) == C; }
        bodies   { coupler(mass = 0.5, center = B, angle = th3, inertia = 6.0e-4); }
        loads    { gravity(vec2(0.0, -9.81)); }
    }
    """
)


def main() -> None:
    m = FourBar(a=0.04, b=0.12, c=0.10, d=0.11, beta="20deg")
    assert abs(m.params["beta"] - math.radians(20.0)) < 1e-15
    pose = m.assemble(phi="30deg", th3=0.3, th4=1.6)
    again = m.assemble({"phi": "30deg", "th3": 0.3, "th4": 1.6})
    assert abs(pose["th4"] - again["th4"]) < 1e-12
    motion = m.analyze(pose, rate="120rpm", acceleration=0.0)
    # 120 rev/min is 4π rad/s.
    assert abs(motion.qd["phi"] - 4.0 * math.pi) < 1e-12
    step = m.step(pose, rates={"phi": "120rpm"})
    assert abs(step.qd["phi"] - motion.qd["phi"]) < 1e-12
    turned = m.replace(beta="30deg", b=0.125)
    assert abs(turned.params["beta"] - math.radians(30.0)) < 1e-15 and turned.params["b"] == 0.125
    sweep = m.sweep("phi", start={"phi": "30deg", "th3": 0.3, "th4": 1.6}, turn=True, steps=36, rpm=60)
    assert len(sweep) > 1
    run = m.forward(start={"phi": "30deg", "th3": 0.3, "th4": 1.6}, until="0.1s", samples=10)
    assert run.ended == "complete"
    batch = m.batch({"a": np.array([0.04, 0.045])}, start={"phi": "30deg", "th3": 0.3, "th4": 1.6})
    assert batch is not None
    # Every public method's annotations resolve at run time too (for
    # tools that read them with typing.get_type_hints).
    for name, method in inspect.getmembers(kin.Mechanism, callable):
        if not name.startswith("_"):
            typing.get_type_hints(method)


if __name__ == "__main__":
    main()
    print("typing_usage: every call ran")
