"""loopkin: kinematic analysis of mechanisms from vector loop-closure
equations, with exact derivatives, closed-form assembly and native code.

Define a mechanism once, as text::

    import loopkin as kin
    FourBar = kin.compile('''
        struct FourBar {
            params   { a, b, c, d, p, beta }
            drivers  { phi }
            unknowns { th3, th4 }
            points   { B = polar(a, phi); C = vec2(d, 0.0) + polar(c, th4);
                       P = B + polar(p, th3 + beta); }
            loops    { B + polar(b, th3) == C; }
        }''')
    m = FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    poses = m.assemble_all(phi=0.5)            # every assembly, by mode
    s = m.analyze(poses[0], rate=10.0)         # s.qd["th3"], s.points["P"].velocity
    sw = m.sweep("phi", start=poses[0], turn=True, steps=360, rpm=600)

The definition language, its checks and its messages are those of the Rust
crate's ``mechanism!`` macro; the definition is compiled to machine code in
this process. See :func:`compile`, :class:`Mechanism`, :class:`Sweep` and
:mod:`loopkin.errors`.
"""

from . import errors, merit
from ._model import (
    Forces,
    FrameMotion,
    JointReaction,
    MassSensitivity,
    Mechanism,
    Motion,
    Options,
    PointMotion,
    Pose,
    Sensitivity,
    Values,
    compile,
    load,
)
from ._forward import Trajectory
from ._sweep import Batch, Deviations, ForceSweep, Link, PointColumns, Poses, ReactionColumns, Stop, Sweep
from .errors import *  # noqa: F401,F403
from .merit import grashof

__all__ = [
    "compile",
    "load",
    "Mechanism",
    "Options",
    "Pose",
    "Values",
    "Motion",
    "PointMotion",
    "FrameMotion",
    "Sensitivity",
    "Sweep",
    "Forces",
    "ForceSweep",
    "JointReaction",
    "MassSensitivity",
    "ReactionColumns",
    "Poses",
    "Stop",
    "PointColumns",
    "Deviations",
    "Batch",
    "Link",
    "Trajectory",
    "errors",
    "merit",
    "grashof",
] + errors.__all__

try:
    from importlib.metadata import version as _version

    __version__ = _version("loopkin")
except Exception:  # pragma: no cover (not installed: run from the source tree)
    __version__ = "0.0.0"
