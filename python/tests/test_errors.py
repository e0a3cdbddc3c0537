"""Bad definitions, bad parameters and unreachable poses raise the
documented exceptions, with the library's messages."""

import math

import numpy as np
import pytest

import loopkin as kin
from conftest import mechanism

BAD = """struct Bad {
    params   { a, b }
    drivers  { phi }
    unknowns { th }
    loops    { polar(a, phi) + polar(b, tht) == vec2(0.1, 0.0); }
}"""


def test_a_bad_definition_raises_with_line_and_column():
    with pytest.raises(kin.DefinitionError) as info:
        kin.compile(BAD)
    e = info.value
    assert (e.line, e.column) == (5, 41)
    assert e.excerpt == "    loops    { polar(a, phi) + polar(b, tht) == vec2(0.1, 0.0); }"
    assert "unknown name `tht`" in e.first and "did you mean `th`" in e.first
    # The message shows the line with a caret under the offending name.
    text = str(e)
    assert "5:41" in text and "^^^" in text
    assert isinstance(e, kin.KinematicsError) and isinstance(e, ValueError)


def test_every_error_of_a_definition_is_reported():
    text = BAD.replace("params   { a, b }", "params   { a, a }")
    with pytest.raises(kin.DefinitionError) as info:
        kin.compile(text)
    assert len(info.value.diagnostics) >= 2
    for message, line, column, excerpt in info.value.diagnostics:
        assert line >= 1 and column >= 1 and excerpt == text.splitlines()[line - 1]


@pytest.mark.parametrize(
    "text",
    ["", "struct", "struct X {", "struct X { params { a } }", "}}}}", "struct X { loops { == ; } }", "\x00\ufffd", "struct X { params { a, } drivers { } unknowns { } }"],
)
def test_no_text_crashes_the_compiler(text):
    try:
        kin.compile(text)
    except kin.DefinitionError as e:
        assert e.line >= 1 and str(e)


def test_bad_parameters_raise(FourBar):
    with pytest.raises(kin.NonFiniteError) as info:
        FourBar(a=float("nan"), b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    assert info.value.name == "a" and math.isnan(info.value.value)
    with pytest.raises(kin.NonFiniteError):
        FourBar(a=0.04, b=float("inf"), c=0.10, d=0.11, p=0.06, beta=0.5)
    with pytest.raises(ValueError):
        FourBar(a="long", b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)


def test_an_unreachable_pose_raises(four_bar):
    far = four_bar.replace(d=1.0)  # the links cannot reach the far pivot
    with pytest.raises(kin.CannotAssembleError, match="no real solution"):
        far.assemble(phi=0.5)
    with pytest.raises(kin.CannotAssembleError):
        far.assemble_all(phi=0.5)
    modes, err = far.assemblies(phi=0.5)[0]
    assert isinstance(err, kin.CannotAssembleError) and modes == ("+",)
    with pytest.raises(ArithmeticError):
        far.assemble(phi=0.5, modes=["-"])


def test_newton_that_does_not_converge_raises():
    Curved = kin.compile(
        """struct Curved {
            params   { a, b, h, k }
            drivers  { phi }
            unknowns { th, y }
            loops    { polar(a, phi) + polar(b, th) == vec2(h + k * y * y, y); }
        }"""
    )
    assert Curved.blocks()[0]["method"] == "Newton–Raphson"
    m = Curved(a=0.05, b=0.2, h=0.2, k=1.0)
    ok = m.assemble(phi=0.3, th=0.5, y=0.1)
    assert np.all(np.abs(m.residual(ok)) < 1e-14)
    with pytest.raises((kin.NotConvergedError, kin.SingularError)):
        m.replace(h=5.0).assemble(phi=0.3, th=0.5, y=0.1)


def test_a_singular_pose_raises(FourBar):
    SliderCrank = mechanism("slider_crank")
    m = SliderCrank(a=0.1, b=0.1, e=0.0)
    # At φ = π/2 the rod is vertical: Φ_u = [[−b sin θ, −1], [b cos θ, 0]] is singular.
    pose = m.pose(phi=math.pi / 2, th=-math.pi / 2, x=0.0)
    with pytest.raises(kin.SingularError):
        m.analyze(pose, rate=1.0)


def test_names_are_checked(four_bar):
    with pytest.raises(KeyError, match="not a coordinate"):
        four_bar.assemble(phi=0.5, theta=1.0)
    with pytest.raises(KeyError, match="not a driver"):
        four_bar.sweep("th3", start=four_bar.pose(phi=0.5))
    with pytest.raises(KeyError, match="not a point"):
        four_bar.sweep("phi", start=four_bar.assemble_all(phi=0.5)[0], steps=4).point("Q")
    with pytest.raises(ValueError, match="change_points"):
        four_bar.sweep("phi", start=four_bar.pose(phi=0.5), change_points="jump")
    with pytest.raises(TypeError, match="drivers"):
        mechanism("robot_arm")(l1=1, l2=1, l3=1, alpha=1).analyze({"q1": 0.0}, rate=1.0)


def test_non_finite_inputs_raise(four_bar):
    with pytest.raises(kin.NonFiniteError):
        four_bar.assemble(phi=float("nan"))
    pose = four_bar.assemble_all(phi=0.5)[0]
    with pytest.raises(kin.NonFiniteError):
        four_bar.analyze(pose, rate=float("inf"))
    sw = four_bar.sweep("phi", start=pose, to=float("nan"), steps=4)
    assert sw.stop is not None and sw.stop.kind == "invalid"


def test_tolerances_must_name_sensitivity_parameters(four_bar):
    sw = four_bar.sweep("phi", start=four_bar.assemble_all(phi=0.5)[0], steps=4)
    with pytest.raises(kin.KinematicsError):
        sw.deviations("P", {"zz": 1e-3})


def test_a_transposed_name_gets_a_suggestion(FourBar, four_bar):
    with pytest.raises(TypeError, match=r"no parameter 'btea' \(did you mean 'beta'\?\)"):
        FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, btea=0.5)
    with pytest.raises(KeyError, match=r"'hpi' is not a coordinate of FourBar \(did you mean 'phi'\?\)"):
        four_bar.pose(hpi=0.5)
    # Nothing near: no suggestion.
    with pytest.raises(TypeError) as e:
        FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, omega=0.5)
    assert "did you mean" not in str(e.value)
