"""Open CASCADE's view of what fairsurf writes: STEP read and written,
faces sewn, free edges counted, and the normal angle and gap across every
edge two faces share, measured at the faces' foot points."""

from __future__ import annotations

import math
from pathlib import Path

from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepBuilderAPI import BRepBuilderAPI_Sewing
from OCP.collections import (
    IndexedDataMap_TopoDS_Shape_List_TopoDS_Shape_TopTools_ShapeMapHasher as EdgeFaces,
)
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
from OCP.gp import gp_Pnt, gp_Vec
from OCP.ShapeAnalysis import ShapeAnalysis_FreeBounds
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_REVERSED
from OCP.TopExp import TopExp, TopExp_Explorer
from OCP.TopoDS import TopoDS


def read_step(path: Path):
    reader = STEPControl_Reader()
    assert int(reader.ReadFile(str(path))) == 1  # IFSelect_RetDone
    reader.TransferRoots()
    return reader.OneShape()


def count(shape, kind) -> int:
    n, ex = 0, TopExp_Explorer(shape, kind)
    while ex.More():
        n += 1
        ex.Next()
    return n


def foot(surface, p: gp_Pnt) -> tuple[float, float]:
    """(u, v) of the point of `surface` nearest to p: Open CASCADE's
    projection, then Newton steps to rounding, kept in the parameter
    rectangle (at a collapsed side the Jacobian is singular and a free step
    would leave it); a step that does not bring the point closer ends
    them."""
    u0, u1, v0, v1 = surface.Bounds()
    u, v = GeomAPI_ProjectPointOnSurf(p, surface).LowerDistanceParameters()
    best = surface.Value(u, v).Distance(p)
    for _ in range(4):
        q, su, sv, suu, svv, suv = gp_Pnt(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec()
        surface.D2(u, v, q, su, sv, suu, svv, suv)
        d = gp_Vec(p, q)
        f1, f2 = d.Dot(su), d.Dot(sv)
        a11, a12, a22 = su.Dot(su) + d.Dot(suu), su.Dot(sv) + d.Dot(suv), sv.Dot(sv) + d.Dot(svv)
        det = a11 * a22 - a12 * a12
        if det == 0.0:
            break
        nu = min(max(u - (a22 * f1 - a12 * f2) / det, u0), u1)
        nv = min(max(v - (a11 * f2 - a12 * f1) / det, v0), v1)
        dist = surface.Value(nu, nv).Distance(p)
        if dist > best:
            break
        u, v, best = nu, nv, dist
    return u, v


def unit_normal(surface, u: float, v: float):
    """The unit normal and the point; the normal is None where the
    parameterization is singular: a side collapsed to a point, where one
    derivative vanishes (below 1e-8 of the other; rounding then decides
    S_u x S_v's direction)."""
    q, su, sv = gp_Pnt(), gp_Vec(), gp_Vec()
    surface.D1(u, v, q, su, sv)
    n = su.Crossed(sv)
    a, b = su.Magnitude(), sv.Magnitude()
    if min(a, b) <= 1e-8 * max(a, b) or n.Magnitude() == 0.0:
        return None, q
    return n.Divided(n.Magnitude()), q


def faces_of(shape) -> list:
    """The shape's faces in Open CASCADE's order."""
    faces = []
    ex = TopExp_Explorer(shape, TopAbs_FACE)
    while ex.More():
        faces.append(TopoDS.Face(ex.Current()))
        ex.Next()
    return faces


def seams(shape, samples: int = 65):
    """Per edge shared by two faces: (face indices, largest normal angle in
    degrees, largest distance between the faces' foot points), measured by
    Open CASCADE at `samples` points of the edge (the angle where both
    faces have a normal)."""
    faces = faces_of(shape)
    m = EdgeFaces()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, m)
    out = []
    for i in range(1, m.Extent() + 1):
        pair = [TopoDS.Face(f) for f in m.FindFromIndex(i)]
        if len(pair) != 2:
            continue
        index = [next(k for k, f in enumerate(faces) if f.IsSame(g)) for g in pair]
        curve = BRepAdaptor_Curve(TopoDS.Edge(m.FindKey(i)))
        a, b = curve.FirstParameter(), curve.LastParameter()
        worst_angle = worst_gap = 0.0
        for k in range(samples):
            p = curve.Value(a + (b - a) * k / (samples - 1))
            (n1, q1), (n2, q2) = (
                unit_normal(s, *foot(s, p))
                for s in (BRep_Tool.Surface_s(f) for f in pair)
            )
            worst_gap = max(worst_gap, q1.Distance(q2))
            if n1 is None or n2 is None:
                continue  # a collapsed side's point: no normal to compare
            angle = math.degrees(math.atan2(n1.Crossed(n2).Magnitude(), abs(n1.Dot(n2))))
            worst_angle = max(worst_angle, angle)
        out.append((sorted(index), worst_angle, worst_gap))
    return out


def face_normal(face, p: gp_Pnt):
    """The unit normal of `face` at the foot of p, its orientation counted
    (reversed for a face used reversed); None where it has none."""
    surface = BRep_Tool.Surface_s(face)
    n, _ = unit_normal(surface, *foot(surface, p))
    if n is not None and face.Orientation() == TopAbs_REVERSED:
        n.Reverse()
    return n


def normals_agree_across_edges(shape) -> list[bool]:
    """Per edge shared by two faces (as the file shares it): whether the
    faces' oriented normals agree at its middle — a consistently oriented
    shell says True for all."""
    faces = EdgeFaces()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, faces)
    out = []
    for i in range(1, faces.Extent() + 1):
        pair = [TopoDS.Face(f) for f in faces.FindFromIndex(i)]
        if len(pair) != 2 or pair[0].IsSame(pair[1]):
            continue
        curve = BRepAdaptor_Curve(TopoDS.Edge(faces.FindKey(i)))
        p = curve.Value(0.5 * (curve.FirstParameter() + curve.LastParameter()))
        n1, n2 = (face_normal(f, p) for f in pair)
        out.append(n1.Dot(n2) > 0)
    return out


def free_edges_after_sewing(shape) -> int:
    sewing = BRepBuilderAPI_Sewing(1e-7)
    sewing.Add(shape)
    sewing.Perform()
    bounds = ShapeAnalysis_FreeBounds(sewing.SewedShape(), 1e-7, False, False)
    return count(bounds.GetClosedWires(), TopAbs_EDGE) + count(bounds.GetOpenWires(), TopAbs_EDGE)


def sewn_step(faces, path: Path) -> None:
    """Open CASCADE sews `faces` (OCP faces) and writes them as STEP."""
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    sewing = BRepBuilderAPI_Sewing(1e-7)
    for f in faces:
        sewing.Add(f)
    sewing.Perform()
    writer = STEPControl_Writer()
    writer.Transfer(sewing.SewedShape(), STEPControl_AsIs)
    assert int(writer.Write(str(path))) == 1


def bezier_face(net):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.collections import Array2_gp_Pnt
    from OCP.Geom import Geom_BezierSurface

    poles = Array2_gp_Pnt(1, len(net), 1, len(net[0]))
    for i, row in enumerate(net):
        for j, p in enumerate(row):
            poles.SetValue(i + 1, j + 1, gp_Pnt(*p))
    return BRepBuilderAPI_MakeFace(Geom_BezierSurface(poles), 1e-7).Face()


def bspline_surface(net, uk, um, vk, vm, p: int, q: int):
    """Open CASCADE's B-spline surface of the poles `net` (rows along u),
    distinct knots uk, vk with multiplicities um, vm, degrees p and q."""
    from OCP.collections import Array1_double, Array1_int, Array2_gp_Pnt
    from OCP.Geom import Geom_BSplineSurface

    def array(values, kind):
        a = kind(1, len(values))
        for k, x in enumerate(values):
            a.SetValue(k + 1, x)
        return a

    poles = Array2_gp_Pnt(1, len(net), 1, len(net[0]))
    for i, row in enumerate(net):
        for j, pt in enumerate(row):
            poles.SetValue(i + 1, j + 1, gp_Pnt(*pt))
    return Geom_BSplineSurface(poles, array(uk, Array1_double), array(vk, Array1_double),
                               array(um, Array1_int), array(vm, Array1_int), p, q)


def polygon_network(n: int):
    """A regular n-gon hole (circumradius 1) in the graph of a cubic, ringed
    by n bicubic Bezier faces (each the graph over the quad between a hole
    side and the polygon of radius 2), as Open CASCADE faces."""
    return [bezier_face(net) for net in polygon_nets(n)]


def polygon_nets(n: int):
    """The control nets of `polygon_network`'s faces (4 x 4 each, rows along
    u: u runs along the hole's side, v away from it)."""
    import numpy as np
    from math import comb

    def f(x, y):
        return 0.3 * x * x - 0.2 * x * y + 0.15 * y * y + 0.1 * x + 0.06 * x**3 - 0.05 * x * y * y

    def corner(k, r):
        a = 2 * math.pi * k / n + 0.3
        return np.array([r * math.cos(a), r * math.sin(a)])

    t = np.linspace(0.0, 1.0, 4)
    b = np.array([[comb(3, i) * x**i * (1 - x) ** (3 - i) for i in range(4)] for x in t])
    inv = np.linalg.inv(b)
    faces = []
    for k in range(n):
        c0, c1, o0, o1 = corner(k, 1), corner(k + 1, 1), corner(k, 2), corner(k + 1, 2)
        vals = np.zeros((4, 4, 3))
        for i, s in enumerate(t):
            for j, w in enumerate(t):
                xy = (1 - w) * ((1 - s) * c0 + s * c1) + w * ((1 - s) * o0 + s * o1)
                vals[i, j] = [xy[0], xy[1], f(*xy)]
        net = np.einsum("ia,jb,abc->ijc", inv, inv, vals)
        faces.append(net.tolist())
    return faces
