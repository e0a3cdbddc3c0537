"""Path synthesis with exact Jacobians recovers a design from its own
coupler points, and the design found is checked by an independent closed
form of the four-bar's coupler curve."""

import math

import numpy as np
import pytest

from conftest import close, mechanism

pytest.importorskip("scipy")


def coupler_point(a, b, c, d, p, beta, phi, mode):
    """P by intersecting the circles about B and D (written here, not the
    library's)."""
    B = np.array([a * math.cos(phi), a * math.sin(phi)])
    r = np.array([d, 0.0]) - B
    L = math.hypot(*r)
    g = math.acos((b * b + L * L - c * c) / (2 * b * L))
    th3 = math.atan2(r[1], r[0]) + mode * g
    return B + p * np.array([math.cos(th3 + beta), math.sin(th3 + beta)])


def test_a_design_is_recovered_from_its_coupler_points():
    from loopkin import synthesis

    FourBar = mechanism("four_bar")
    true = dict(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    phis = np.linspace(0.0, 2 * math.pi, 9, endpoint=False)
    mode = 1
    targets = np.array([coupler_point(*true.values(), phi, mode) for phi in phis])
    start_design = FourBar(**{**true, "b": 0.125, "c": 0.095, "p": 0.055, "beta": 0.45})
    guess = start_design.assemble_all(phi=0.0)
    # The assembly whose P is nearest the first target fixes the modes.
    first = min(guess, key=lambda q: np.linalg.norm(start_design.analyze(q).points["P"].position - targets[0]))
    res = synthesis.path(start_design, "P", targets, phis, vary=["b", "c", "p", "beta"], start=first, xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert res.error < 1e-24, res
    got = res.design.params
    for k in ("b", "c", "p", "beta"):
        assert abs(got[k] - true[k]) < 1e-9, (k, got[k])
    # Independent check: the closed-form coupler curve of the design found.
    again = np.array([coupler_point(*got.values(), phi, mode) for phi in phis])
    assert close(again, targets, 1e-11)
    assert res.evaluations < 100


def test_parameters_outside_the_sensitivities_section_are_refused():
    from loopkin import synthesis

    SliderCrank = mechanism("slider_crank")
    m = SliderCrank(a=0.05, b=0.2, e=0.0)
    with pytest.raises(ValueError, match="sensitivities"):
        synthesis.path(m, "C", np.zeros((3, 2)), [0.0, 1.0, 2.0], vary=["a"])
