"""Drawings a shop can use, read back by an independent reader: the DXF
drawing of a sweep opened with ``ezdxf``, its lines at the positions the
sweep's own columns give for the points they join, its paths through
every sample; the links found from the motion."""

import ezdxf
import ezdxf.recover
import numpy as np
import pytest

from conftest import close


@pytest.fixture(scope="module")
def sweep(four_bar):
    return four_bar.sweep("phi", start={"phi": 0.0, "th3": 1.0, "th4": 1.6}, turn=True, steps=90)


def test_the_links_are_found_from_the_motion(sweep):
    links = sweep.links()
    assert links[0].frame and set(links[0].points) == {"A", "D"}
    moving = {frozenset(l.points) for l in links if not l.frame}
    assert moving == {frozenset("AB"), frozenset("BCP"), frozenset("DC")}
    assert "frame {A, D}" in repr(links[0])


def test_the_dxf_drawing_reads_back_in_an_independent_reader(sweep, tmp_path):
    path = tmp_path / "four_bar.dxf"
    sweep.write_dxf(path, sample=10)
    doc = ezdxf.readfile(str(path))
    assert doc.dxfversion == "AC1009"
    msp = doc.modelspace()
    assert {layer.dxf.name for layer in doc.layers} >= {"LINKS", "PIVOTS", "JOINTS", "PATHS", "NAMES"}
    at = {name: sweep.point(name).position[10] for name in ("A", "B", "C", "D", "P")}
    # Every line joins two of the points, at the sample's positions.
    lines = msp.query("LINE")
    assert len(lines) >= 3
    for line in lines:
        ends = [np.array(line.dxf.start)[:2], np.array(line.dxf.end)[:2]]
        for e in ends:
            assert any(close(e, p, 1e-15) for p in at.values()), e
    # The crank A–B is one of them.
    joined = {
        frozenset(n for e in (l.dxf.start, l.dxf.end) for n, p in at.items() if close(np.array(e)[:2], p, 1e-15))
        for l in lines
    }
    assert frozenset("AB") in joined
    # The pivots on their layer, the others on theirs.
    pivots = [np.array(c.dxf.center)[:2] for c in msp.query("CIRCLE[layer=='PIVOTS']")]
    assert len(pivots) == 2 and any(close(p, at["D"], 1e-15) for p in pivots)
    assert len(msp.query("CIRCLE[layer=='JOINTS']")) == 3
    assert sorted(t.dxf.text for t in msp.query("TEXT")) == ["A", "B", "C", "D", "P"]
    # A closed path per moving point, through every sample.
    paths = msp.query("POLYLINE")
    assert len(paths) == 3
    coupler = sweep.point("P").position
    for pl in paths:
        assert pl.is_closed
        vertices = np.array([v.dxf.location for v in pl.vertices])[:, :2]
        assert len(vertices) == len(sweep)
    assert any(close(np.array([v.dxf.location for v in pl.vertices])[:, :2], coupler, 1e-15) for pl in paths)


def test_links_given_by_hand_and_a_wrong_sample_or_point(sweep, tmp_path):
    path = tmp_path / "crank.dxf"
    sweep.write_dxf(path, links=[("A", "B")])
    assert len(ezdxf.readfile(str(path)).modelspace().query("LINE")) == 1
    # As the command writes a link, "A-B"; a string that is no pair fails.
    sweep.write_dxf(path, links=["A-B", ("B", "C")])
    assert len(ezdxf.readfile(str(path)).modelspace().query("LINE")) == 2
    with pytest.raises(ValueError, match="a link is two point names"):
        sweep.write_dxf(path, links=["AB"])
    # Every point is a PointColumns of positions, usable as an array.
    poses = sweep.design.poses("phi", start=sweep.pose(0), turn=True, steps=12)
    xy = poses.point("P")
    assert xy.shape == (12, 2) and close(xy[:, 0], xy.T[0], 0) and not np.shares_memory(np.array(xy, copy=True), xy.position)
    with pytest.raises(IndexError, match="sample 90 of a sweep of 90"):
        sweep.write_dxf(path, sample=90)
    with pytest.raises(Exception, match="Q"):
        sweep.write_dxf(path, links=[("A", "Q")])


def test_names_past_ascii_read_back(tmp_path):
    import loopkin as kin

    Crank = kin.compile("struct Crank { params { a } drivers { phi } unknowns { } points { Ω = vec2(0.0, 0.0); Pé = polar(a, phi); } }")
    sw = Crank(a=1.0).sweep("phi", start={"phi": 0.0}, turn=True, steps=8)
    path = tmp_path / "crank.dxf"
    sw.write_dxf(path, links=[("Ω", "Pé")])
    # Written as AutoCAD writes characters past its code page in files
    # before release 2007, \U+XXXX (the file itself is ASCII); ezdxf's
    # recovering reader decodes them, its plain reader keeps them.
    assert path.read_bytes().isascii()
    doc, auditor = ezdxf.recover.readfile(str(path))
    names = sorted(t.dxf.text for t in doc.modelspace().query("TEXT"))
    assert names == ["Pé", "Ω"]
    plain = sorted(t.dxf.text for t in ezdxf.readfile(str(path)).modelspace().query("TEXT"))
    assert plain == ["P\\U+00E9", "\\U+03A9"]
