"""Open CASCADE (OCP, from cadquery-ocp) reads what fairsurf writes and
gives what fairsurf holds: poles, knots and multiplicities one by one."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import fairsurf

from OCP.BRep import BRep_Tool
from OCP.IGESControl import IGESControl_Reader
from OCP.STEPControl import STEPControl_Reader

from fairsurf import occ

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def read(path: Path):
    reader = STEPControl_Reader() if path.suffix == ".step" else IGESControl_Reader()
    assert int(reader.ReadFile(str(path))) == 1  # IFSelect_RetDone
    reader.TransferRoots()
    return reader.OneShape()


def poles_knots(geom):
    poles = np.array([[[geom.Pole(i, j).X(), geom.Pole(i, j).Y(), geom.Pole(i, j).Z()]
                       for j in range(1, geom.NbVPoles() + 1)]
                      for i in range(1, geom.NbUPoles() + 1)])
    u = [geom.UKnot(i) for i in range(1, geom.NbUKnots() + 1)
         for _ in range(geom.UMultiplicity(i))]
    v = [geom.VKnot(i) for i in range(1, geom.NbVKnots() + 1)
         for _ in range(geom.VMultiplicity(i))]
    return poles, np.array(u), np.array(v)


@pytest.mark.parametrize("suffix", [".step", ".igs"])
@pytest.mark.parametrize("scene", ["bspline_hole_guided.json", "wu_yang_fig4_l500.json"])
def test_exports_read_back_pole_by_pole(scene: str, suffix: str, tmp_path: Path) -> None:
    """STEP and IGES exports, read by Open CASCADE: one face whose B-spline
    surface has our degree, our control points (1e-12 of the size: STEP and
    IGES carry decimal text) and our knots (a Bézier patch: 0 and 1, n + 1
    times each)."""
    r = fairsurf.solve(EXAMPLES / scene)
    path = tmp_path / ("s" + suffix)
    r.export(path)
    faces = occ.faces(read(path))
    assert len(faces) == 1
    geom = BRep_Tool.Surface_s(faces[0])
    assert (geom.UDegree(), geom.VDegree()) == r.degree
    assert not geom.IsURational() and not geom.IsVRational()
    poles, u, v = poles_knots(geom)
    cp = r.control_points
    assert poles.shape == cp.shape
    size = np.abs(cp).max()
    assert np.abs(poles - cp).max() <= 1e-12 * size
    if r.knots is None:
        p, q = r.degree
        np.testing.assert_array_equal(u, [0.0] * (p + 1) + [1.0] * (p + 1))
        np.testing.assert_array_equal(v, [0.0] * (q + 1) + [1.0] * (q + 1))
    else:
        np.testing.assert_allclose(u, r.knots[0], rtol=0, atol=1e-15)
        np.testing.assert_allclose(v, r.knots[1], rtol=0, atol=1e-15)


@pytest.mark.parametrize("scene", ["bspline_hole_guided.json", "wu_yang_fig4_l500.json"])
def test_faces_round_trip_and_evaluate_alike(scene: str) -> None:
    """to_face → from_face gives back the control points and knots exactly,
    and Open CASCADE evaluates the face's surface where fairsurf does (the
    knot domain mapped onto [0, 1]²) to 1e-14 of the size."""
    r = fairsurf.solve(EXAMPLES / scene)
    face = occ.to_face(r)
    back = occ.from_face(face)
    np.testing.assert_array_equal(back.control_points, r.control_points)
    # A Bézier patch comes back as what OCC holds: a B-spline on [0, 1]
    # without interior knots.
    assert back.surface_type == "bspline" and back.degree == r.degree
    p, q = r.degree
    knots = r.knots or ([0.0] * (p + 1) + [1.0] * (p + 1), [0.0] * (q + 1) + [1.0] * (q + 1))
    for a, b in zip(back.knots, knots):
        np.testing.assert_array_equal(a, b)
    geom = occ.to_geom(r)
    u0, u1, v0, v1 = geom.Bounds()
    s = np.linspace(0, 1, 7)
    ours = r.evaluate(s[:, None], s[None, :])
    size = np.abs(r.control_points).max()
    for i, a in enumerate(s):
        for j, b in enumerate(s):
            p = geom.Value(u0 + a * (u1 - u0), v0 + b * (v1 - v0))
            assert np.abs(np.array([p.X(), p.Y(), p.Z()]) - ours[i, j]).max() <= 1e-14 * size


def test_a_tensor_patch_is_a_bezier_surface_and_back() -> None:
    """to_bezier gives Open CASCADE's Bézier surface of the patch: the same
    poles, the same points where OCC evaluates it; from_geom reads it back
    as the same tensor patch bit for bit."""
    r = fairsurf.solve(EXAMPLES / "wu_yang_fig4_l500.json")
    geom = occ.to_bezier(r)
    assert (geom.UDegree(), geom.VDegree()) == r.degree
    assert not geom.IsURational() and not geom.IsVRational()
    back = occ.from_geom(geom)
    assert back.surface_type == "tensor"
    np.testing.assert_array_equal(back.control_points, r.control_points)
    s = np.linspace(0, 1, 5)
    ours = r.evaluate(s[:, None], s[None, :])
    size = np.abs(r.control_points).max()
    for i, a in enumerate(s):
        for j, b in enumerate(s):
            p = geom.Value(a, b)
            assert np.abs(np.array([p.X(), p.Y(), p.Z()]) - ours[i, j]).max() <= 1e-14 * size
    for other, hint in [("bspline_hole.json", "to_geom"), ("vw_pentagon_hole.json", "to_shape")]:
        with pytest.raises(ValueError, match=hint):
            occ.to_bezier(fairsurf.solve(EXAMPLES / other))


def test_what_does_not_convert_is_refused() -> None:
    tri = fairsurf.solve(EXAMPLES / "vw_pentagon_hole.json")
    with pytest.raises(ValueError, match="to_shape"):
        occ.to_geom(tri)
    from OCP.Geom import Geom_Plane
    from OCP.gp import gp_Pln

    with pytest.raises(ValueError, match="Geom_Plane"):
        occ.from_geom(Geom_Plane(gp_Pln()))
    rational = occ.to_geom(fairsurf.solve(EXAMPLES / "bspline_hole.json"))
    rational.SetWeight(2, 2, 2.0)
    with pytest.raises(ValueError, match="rational"):
        occ.from_geom(rational)


def test_a_triangular_surface_is_a_sewn_shell_of_its_patches() -> None:
    """to_shape: one face per patch, sewn into one shell whose free edges are
    the surface's boundary edges only (every interior edge shared by two
    faces); each face evaluates to its patch."""
    from OCP.ShapeAnalysis import ShapeAnalysis_FreeBounds
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_SHELL
    from OCP.TopExp import TopExp_Explorer

    scene = json.loads((EXAMPLES / "vw_pentagon_hole.json").read_text())
    tri = fairsurf.solve(scene)
    shape = occ.to_shape(tri)
    patches = tri.tensor_patches()
    assert len(occ.faces(shape)) == len(patches) == len(scene["surface"]["triangles"])
    shells = 0
    ex = TopExp_Explorer(shape, TopAbs_SHELL)
    while ex.More():
        shells += 1
        ex.Next()
    assert shells == 1
    # Boundary edges of the triangle mesh: used by one triangle only.
    uses: dict = {}
    for t in scene["surface"]["triangles"]:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            uses[frozenset((a, b))] = uses.get(frozenset((a, b)), 0) + 1
    boundary = sum(1 for n in uses.values() if n == 1)
    free = ShapeAnalysis_FreeBounds(shape, 1e-6, False, False)
    wires = free.GetClosedWires()
    edges = 0
    ex = TopExp_Explorer(wires, TopAbs_EDGE)
    while ex.More():
        edges += 1
        ex.Next()
    assert edges == boundary, f"{edges} free edges, {boundary} boundary edges"
    # Each face's surface is one of the patches, pole for pole (sewing may
    # reorder the faces).
    want = {np.ascontiguousarray(cp).tobytes() for cp in patches}
    got = set()
    for face in occ.faces(shape):
        poles, u, v = poles_knots(BRep_Tool.Surface_s(face))
        got.add(np.ascontiguousarray(poles).tobytes())
    assert got == want
