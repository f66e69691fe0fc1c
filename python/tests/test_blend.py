"""`fairsurf blend` checked by Open CASCADE: two B-spline surfaces that
Open CASCADE built and wrote are blended; Open CASCADE reads the result,
sews it (the blend shares an edge with each surface, no free edge there)
and measures the normal angle across those edges that fairsurf reports."""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import pytest
from occ_check import bspline_surface, count, free_edges_after_sewing, read_step, seams
from OCP.TopAbs import TopAbs_FACE

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "cad"


def two_sheets(path: Path) -> None:
    """A bicubic B-spline sheet (uneven knots in u and v) and a tilted
    biquartic one, a gap between A's u = 1 edge and B's u = 0 edge, in one
    STEP shell written by Open CASCADE."""
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
    from OCP.TopoDS import TopoDS_Shell

    a = bspline_surface(
        [[(0.4 * i, 0.3 * j, 0.2 * math.sin(0.9 * i + 0.7 * j)) for j in range(5)]
         for i in range(6)],
        [0.0, 0.3, 0.5, 1.0], [4, 1, 1, 4], [0.0, 0.6, 1.0], [4, 1, 4], 3, 3)
    b = bspline_surface(
        [[(3.0 + 0.3 * i + 0.05 * j, -0.1 + 0.32 * j, 0.8 + 0.25 * i + 0.05 * math.cos(j) * i)
          for j in range(5)] for i in range(5)],
        [0.0, 1.0], [5, 5], [0.0, 1.0], [5, 5], 4, 4)
    builder, shell = BRep_Builder(), TopoDS_Shell()
    builder.MakeShell(shell)
    for s in (a, b):
        builder.Add(shell, BRepBuilderAPI_MakeFace(s, 1e-7).Face())
    writer = STEPControl_Writer()
    writer.Transfer(shell, STEPControl_AsIs)
    assert int(writer.Write(str(path))) == 1


def test_a_blend_of_open_cascade_surfaces_is_sewn_and_g1(cli: Path, tmp_path: Path):
    two_sheets(tmp_path / "sheets.step")
    scene = tmp_path / "blend.json"
    scene.write_text(json.dumps({"surfaces": [
        {"step": "sheets.step", "index": 0, "edge": "u1"},
        {"step": "sheets.step", "index": 1, "edge": "u0"},
    ]}))
    out = tmp_path / "blended.step"
    run = subprocess.run([str(cli), "blend", str(scene), "-o", str(out), "--json"],
                         check=True, capture_output=True, text=True)
    report = json.loads(run.stdout)
    assert report["faces"] == 2
    shape = read_step(out)
    assert count(shape, TopAbs_FACE) == 3
    # Free after sewing: A's and B's three other edges, the blend's two
    # made sides; none where the blend meets a surface.
    assert free_edges_after_sewing(shape) == 8
    across = [s for s in seams(shape) if 2 in s[0]]
    assert sorted(s[0] for s in across) == [[0, 2], [1, 2]]
    measured = max(s[1] for s in across)
    reported = report["max_angle_deg"]
    assert measured < 1e-9 and reported < 1e-9, (measured, reported)
    assert max(s[2] for s in across) < 1e-12
    # The edges named are the ones joined: A's u = 1 edge lies at x = 2,
    # B's u = 0 edge at x from 3 to 3.2.
    from OCP.BRep import BRep_Tool
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    ex, faces = TopExp_Explorer(shape, TopAbs_FACE), []
    while ex.More():
        faces.append(BRep_Tool.Surface_s(TopoDS.Face(ex.Current())))
        ex.Next()
    blend = faces[2]
    u0, u1, v0, v1 = blend.Bounds()
    for t in (0.0, 0.3, 1.0):
        u = u0 + t * (u1 - u0)
        assert abs(blend.Value(u, v0).X() - 2.0) < 1e-12
        assert 3.0 - 1e-12 < blend.Value(u, v1).X() < 3.2 + 1e-12


def test_the_python_blend_gives_what_the_command_line_gives(cli: Path, tmp_path: Path):
    import fairsurf

    scene = EXAMPLES / "blend_sheets.json"
    blended = fairsurf.blend(scene)
    assert len(blended.faces) == 2
    out = tmp_path / "cli.step"
    run = subprocess.run([str(cli), "blend", str(scene), "-o", str(out), "--json"],
                         check=True, capture_output=True, text=True)
    theirs = json.loads(run.stdout)
    ours = dict(blended.report)
    for r in (ours, theirs):
        r.pop("seconds")
        r["solve"].pop("timings_s")
        r["solve"]["check"].pop("seconds")
        r["bulge_search"].pop("seconds")
    theirs.pop("input")
    theirs.pop("output")
    assert ours == theirs
    assert blended.blend.control_points.shape == tuple(theirs["control_points"]) + (3,)
    # Options override the scene's; α scales with the bulge.
    one = fairsurf.blend(json.loads(scene.read_text()), bulge=(1.0, 1.0))
    wide = fairsurf.blend(json.loads(scene.read_text()), bulge=(2.0, 1.0))
    assert wide.report["alpha"][0] == pytest.approx(2 * one.report["alpha"][0], rel=1e-14)
    assert wide.report["alpha"][1] == pytest.approx(one.report["alpha"][1], rel=1e-14)
    assert one.report["bulge_search"] is None and ours["bulge_search"]["evaluations"] >= 4
    with pytest.raises(ValueError, match="bulge"):
        fairsurf.blend(scene, bulge=(0.0, 1.0))
    with pytest.raises(fairsurf.SceneError, match=r"surfaces\[1\]\.edge") as e:
        bad = json.loads(scene.read_text())
        bad["surfaces"][1]["edge"] = "w"
        fairsurf.blend(bad)
    assert e.value.path == "surfaces[1].edge"
    with pytest.raises(fairsurf.SolveError, match="meet at their"):
        bad = json.loads(scene.read_text())
        bad["surfaces"][1] = dict(bad["surfaces"][0], edge="v0")
        fairsurf.blend(bad)
    blended.write(tmp_path / "py.step")
    assert count(read_step(tmp_path / "py.step"), TopAbs_FACE) == 3
    assert fairsurf.schema("blend")["properties"]["surfaces"]["type"] == "array"
