#!/usr/bin/env python3
"""`fairsurf fill` against Open CASCADE's BRepOffsetAPI_MakeFilling on the same holes.

Each hole is a 3 x 3 network of faces cut by Open CASCADE (Segment) from one
smooth surface, the centre face left out, sewn and written as STEP:

- bezier: the wavy bi-quintic network of examples/cad/fill_network.json;
- bspline: a bicubic B-spline sheet with uneven knots (neighbours of several
  spans and different knot vectors);
- dome: a bi-quintic Bezier patch through a spherical cap (radius 1.5);
- fillet: examples/cad/fillet_hole.py (planes and cylinders);
- trimmed: examples/cad/trimmed_hole.py, the bspline sheet as ONE face with
  a 4-sided hole whose edges are not isolines (a trimmed face);
- pipe: examples/cad/trimmed_revolved.py's pipe, a whole cylinder as ONE
  face with a hole bounded by two arcs and two rulings (a trimmed
  cylinder; the pipe's ends are rims, not filled).

MakeFilling (degree 3, 15 points per curve, 2 iterations: its defaults) gets the
hole's four edges with G1 constraints to their faces, in this process;
`fairsurf fill` reads the STEP file in its own process (`--json`). Both
results are measured here by Open CASCADE, the same way: the largest normal
angle across the four edges (65 points per edge, foot points refined by
Newton), the largest gap (distance from the edge points to the fill), and
W = integral of k1^2 + k2^2 dA over the face by Gauss-Legendre quadrature
(16 x 16 nodes on 4 x 4 cells) through the Coons map of its four boundary
pcurves (MakeFilling's face covers part of its surface's parameter
rectangle; checked: the integrated area equals the face's, BRepGProp, to
1e-6). fairsurf's own reported
figures are printed beside Open CASCADE's measurement of them.

Times (medians of --repeats runs, each tool's runs back to back after one
pause): MakeFilling's Build(); fairsurf's
in-library time (its report: boundary data, solve with its check, Willmore
steps, measurements) and the whole `fairsurf fill` process (read STEP, fill,
write STEP). The command's library time is a fresh process's (cold caches);
when this Python has the fairsurf package (python/test.sh builds it into
target/py-venv, which has Open CASCADE too) the same fill is also timed in
this process, as MakeFilling is: `fairsurf.fill` (read STEP, find the holes,
fill, measure) and the fill's own report of that call.

    python3 -m venv target/bench-venv && target/bench-venv/bin/pip install numpy cadquery-ocp
    cargo build --release -p fairsurf-cli
    target/bench-venv/bin/python bench/fill_vs_makefilling.py [--repeats 9] [--cli target/release/fairsurf] [--keep DIR]
    # with the in-process columns:
    FAIRSURF_PY_PROFILE=release bash python/test.sh
    target/py-venv/bin/python bench/fill_vs_makefilling.py
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_Sewing
from OCP.BRepGProp import BRepGProp
from OCP.BRepOffsetAPI import BRepOffsetAPI_MakeFilling
from OCP.BRepTools import BRepTools
from OCP.collections import (
    Array1_double,
    Array1_int,
    Array2_gp_Pnt,
    IndexedDataMap_TopoDS_Shape_List_TopoDS_Shape_TopTools_ShapeMapHasher as EdgeFaces,
)
from OCP.GeomAbs import GeomAbs_G1
from OCP.Geom import Geom_BezierSurface, Geom_BSplineSurface
from OCP.GeomLProp import GeomLProp_SLProps
from OCP.gp import gp_Pnt, gp_Vec
from OCP.GProp import GProp_GProps
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Reader, STEPControl_Writer
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
from OCP.TopExp import TopExp, TopExp_Explorer
from OCP.TopoDS import TopoDS

# Foot points and normals as the tests measure them.
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python" / "tests"))
from occ_check import foot  # noqa: E402
from occ_check import unit_normal as normal_at  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]

try:
    import fairsurf  # the Python package, if this Python has it
except ImportError:
    fairsurf = None


def array1(values, kind):
    a = kind(1, len(values))
    for k, x in enumerate(values):
        a.SetValue(k + 1, x)
    return a


def poles(net):
    a = Array2_gp_Pnt(1, len(net), 1, len(net[0]))
    for i, row in enumerate(net):
        for j, p in enumerate(row):
            a.SetValue(i + 1, j + 1, gp_Pnt(*p))
    return a


def network(make, us, vs):
    """Faces of the 3 x 3 pieces of `make()` cut at us x vs, centre left out."""
    faces = []
    for a, b in zip(us, us[1:]):
        for c, d in zip(vs, vs[1:]):
            if (a, c) == (us[1], vs[1]):
                continue
            s = make()
            s.Segment(a, b, c, d)
            faces.append(BRepBuilderAPI_MakeFace(s, 1e-7).Face())
    return faces


def bezier_holes():
    # The wavy patch of examples/generate.py (fill_network), whole.
    big = [[[3 * i / 5 + 0.3 * j / 5, 3 * j / 5,
             0.3 * math.sin(3.9 * i / 5) * math.cos(2.7 * j / 5) + 0.45 * i * j / 25]
            for j in range(6)] for i in range(6)]
    yield "bezier", network(lambda: Geom_BezierSurface(poles(big)), [0, 1 / 3, 2 / 3, 1],
                            [0, 1 / 3, 2 / 3, 1])
    uk, um = [0.0, 0.5, 1.0, 1.7, 2.0, 2.4, 3.0], [4, 1, 1, 1, 1, 1, 4]
    vk, vm = [0.0, 0.8, 1.2, 1.5, 2.1, 3.0], [4, 1, 1, 1, 1, 4]
    cu, cv = sum(um) - 4, sum(vm) - 4
    net = [[[0.4 * i, 0.45 * j + 0.02 * i,
             0.4 * math.cos(0.44 * i) * math.sin(0.63 * j)] for j in range(cv)] for i in range(cu)]

    def sheet():
        return Geom_BSplineSurface(poles(net), array1(uk, Array1_double), array1(vk, Array1_double),
                                   array1(um, Array1_int), array1(vm, Array1_int), 3, 3)
    yield "bspline", network(sheet, [0.0, 1.0, 2.0, 3.0], [0.0, 1.2, 2.1, 3.0])
    # A bi-quintic patch through a spherical cap: control points lifted so the
    # patch interpolates the sphere at the Greville points is not needed; the
    # net of the cap's graph is smooth and curved alike in both directions.
    r = 1.5
    cap = [[[2 * i / 5 - 1, 2 * j / 5 - 1,
             math.sqrt(r * r - (2 * i / 5 - 1) ** 2 - (2 * j / 5 - 1) ** 2)]
            for j in range(6)] for i in range(6)]
    yield "dome", network(lambda: Geom_BezierSurface(poles(cap)), [0, 1 / 3, 2 / 3, 1],
                          [0, 1 / 3, 2 / 3, 1])
    # The approximate case: examples/cad/fillet_hole.step's planes and
    # cylinders (fairsurf meets the cylinders through polynomial stand-ins).
    spec = importlib.util.spec_from_file_location("fillet", ROOT / "examples/cad/fillet_hole.py")
    fillet = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(fillet)
    yield "fillet", fillet.faces()
    # A trimmed neighbour: examples/cad/trimmed_hole.py's sheet as one face
    # with a 4-sided hole whose edges are not isolines (fairsurf meets it
    # through strips along the edges).
    spec = importlib.util.spec_from_file_location("trimmed", ROOT / "examples/cad/trimmed_hole.py")
    trimmed = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(trimmed)
    yield "trimmed", [trimmed.face()]
    spec = importlib.util.spec_from_file_location("revolved",
                                                  ROOT / "examples/cad/trimmed_revolved.py")
    revolved = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(revolved)
    yield "pipe", [revolved.faces()[0]]


def sew(faces):
    s = BRepBuilderAPI_Sewing(1e-7)
    for f in faces:
        s.Add(f)
    s.Perform()
    return s.SewedShape()


def write_step(shape, path: Path):
    w = STEPControl_Writer()
    w.Transfer(shape, STEPControl_AsIs)
    assert int(w.Write(str(path))) == 1


def read_step(path: Path):
    r = STEPControl_Reader()
    assert int(r.ReadFile(str(path))) == 1
    r.TransferRoots()
    return r.OneShape()


def faces_of(shape):
    out, ex = [], TopExp_Explorer(shape, TopAbs_FACE)
    while ex.More():
        out.append(TopoDS.Face(ex.Current()))
        ex.Next()
    return out


def hole_edges(shape, count=4):
    """(edge, its face) for the `count` free edges of the hole: the free
    edges not on the rim, found as those nearest to the centroid of all
    free edges' midpoints (the rim lies further out)."""
    m = EdgeFaces()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, m)
    free = []
    for i in range(1, m.Extent() + 1):
        if m.FindFromIndex(i).Size() == 1:
            e = TopoDS.Edge(m.FindKey(i))
            if BRep_Tool.Degenerated_s(e):
                continue  # a sphere's pole: no edge of a hole
            c = BRepAdaptor_Curve(e)
            mid = c.Value(0.5 * (c.FirstParameter() + c.LastParameter()))
            free.append((e, TopoDS.Face(m.FindFromIndex(i).First()), mid))
    centre = np.mean([[p.X(), p.Y(), p.Z()] for _, _, p in free], axis=0)
    free.sort(key=lambda t: np.linalg.norm(np.array([t[2].X(), t[2].Y(), t[2].Z()]) - centre))
    return [(e, f) for e, f, _ in free[:count]]


def seam(fill_face, edges, samples=65):
    """Largest normal angle (degrees) and gap between the fill and the
    neighbours along the hole's edges."""
    fs = BRep_Tool.Surface_s(fill_face)
    angle = gap = 0.0
    for e, nb in edges:
        ns = BRep_Tool.Surface_s(nb)
        c = BRepAdaptor_Curve(e)
        a, b = c.FirstParameter(), c.LastParameter()
        for k in range(samples):
            p = c.Value(a + (b - a) * k / (samples - 1))
            n1, q1 = normal_at(fs, *foot(fs, p))
            n2, _ = normal_at(ns, *foot(ns, p))
            gap = max(gap, q1.Distance(p))
            if n1 is None or n2 is None:
                continue  # a collapsed side's point: no normal there
            angle = max(angle, math.degrees(math.atan2(n1.Crossed(n2).Magnitude(),
                                                       abs(n1.Dot(n2)))))
    return angle, gap


def curvature_squared(s, u, v):
    """4H^2, K (k1^2 + k2^2 = 4H^2 - 2K) and |S_u x S_v| at (u, v), from Open CASCADE's
    derivatives (D2) and the fundamental forms. (Open CASCADE 8's
    GeomLProp_SLProps was not used: on these surfaces its MaxCurvature came
    out 0 where the principal curvatures from its own derivatives are 0.018
    and -0.168, and its H and K gave 4H^2 - 2K < 0 at some points.)"""
    p, su, sv, suu, svv, suv = gp_Pnt(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec()
    s.D2(u, v, p, su, sv, suu, svv, suv)
    n = su.Crossed(sv)
    da = n.Magnitude()
    n = n.Divided(da)
    E, F, G = su.Dot(su), su.Dot(sv), sv.Dot(sv)
    e, f, g = suu.Dot(n), suv.Dot(n), svv.Dot(n)
    det = E * G - F * F
    K = (e * g - f * f) / det
    H = (e * G - 2 * f * F + g * E) / (2 * det)
    return 4 * H * H, K, da


def uv_boundary(face):
    """The face's outer wire as four pcurves in loop order: functions t -> (u, v)
    and their derivatives, t in [0, 1] along the loop."""
    from OCP.BRepTools import BRepTools_WireExplorer
    from OCP.gp import gp_Pnt2d, gp_Vec2d
    from OCP.TopAbs import TopAbs_REVERSED

    sides = []
    ex = BRepTools_WireExplorer(BRepTools.OuterWire_s(face), face)
    while ex.More():
        e = ex.Current()
        c = BRep_Tool.CurveOnSurface_s(e, face, 0.0, 0.0)
        a, b = BRep_Tool.Range_s(e, face)
        if e.Orientation() == TopAbs_REVERSED:
            a, b = b, a

        def side(t, c=c, a=a, b=b):
            p, d = gp_Pnt2d(), gp_Vec2d()
            c.D1(a + (b - a) * t, p, d)
            return np.array([p.X(), p.Y()]), np.array([d.X(), d.Y()]) * (b - a)
        sides.append(side)
        ex.Next()
    assert len(sides) == 4, f"a fill face with {len(sides)} edges"
    return sides


def total_curvature(face, nodes=16, cells=4):
    """W = integral of k1^2 + k2^2 dA over the face: its parameter region is
    mapped from [0, 1]^2 by the bilinearly blended Coons patch of its four
    boundary pcurves, Gauss-Legendre on cells x cells squares; returns W, its
    parts integral 4H^2 dA and integral K dA (W = the first - 2 x the second),
    and the area so integrated over the face's area (BRepGProp; 1 when the
    map covers the face once)."""
    s = BRep_Tool.Surface_s(face)
    e0, e1, e2, e3 = uv_boundary(face)
    p00, p10, p11, p01 = e0(0)[0], e1(0)[0], e2(0)[0], e3(0)[0]

    def coons(x, y):
        (b0, db0), (b1, db1) = e0(x), e2(1 - x)
        (c0, dc0), (c1, dc1) = e3(1 - y), e1(y)
        f = ((1 - y) * b0 + y * b1 + (1 - x) * c0 + x * c1
             - ((1 - x) * (1 - y) * p00 + x * (1 - y) * p10 + x * y * p11 + (1 - x) * y * p01))
        fx = (1 - y) * db0 - y * db1 - c0 + c1 - (-(1 - y) * p00 + (1 - y) * p10 + y * p11 - y * p01)
        fy = -b0 + b1 - (1 - x) * dc0 + x * dc1 - (-(1 - x) * p00 - x * p10 + x * p11 + (1 - x) * p01)
        return f, abs(fx[0] * fy[1] - fx[1] * fy[0])

    g, w = np.polynomial.legendre.leggauss(nodes)
    g, w = (g + 1) / 2, w / 2
    willmore = gauss = area = 0.0
    for i in range(cells):
        for j in range(cells):
            for xi, wi in zip(g, w):
                for yj, wj in zip(g, w):
                    (u, v), jac = coons((i + xi) / cells, (j + yj) / cells)
                    h2, k, dA = curvature_squared(s, u, v)
                    da = dA * jac * wi * wj / cells ** 2
                    willmore += h2 * da
                    gauss += k * da
                    area += da
    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(face, props, 1e-10)
    return willmore - 2 * gauss, willmore, gauss, area / props.Mass()


def run(args):
    cli = Path(args.cli)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(args.keep) if args.keep else Path(tmp)
        tmp.mkdir(parents=True, exist_ok=True)
        for name, faces in bezier_holes():
            shape = sew(faces)
            step_in = tmp / f"{name}.step"
            write_step(shape, step_in)
            edges = hole_edges(shape)
            times, fill = [], None
            for _ in range(args.repeats):
                mf = BRepOffsetAPI_MakeFilling()
                for e, f in edges:
                    mf.Add(e, f, GeomAbs_G1, True)
                t = time.perf_counter()
                mf.Build()
                times.append(time.perf_counter() - t)
                fill = TopoDS.Face(mf.Shape())
            occ_angle, occ_gap = seam(fill, edges)
            occ_w, occ_h, occ_k, occ_rect = total_curvature(fill)
            step_out = tmp / f"{name}.filled.step"
            ptimes, ltimes, report = [], [], None
            # Open CASCADE's worker threads spin for a while after a
            # MakeFilling; on 2 cores they slowed the next process by 3x.
            # One pause, then the runs back to back, as MakeFilling's are
            # (a pause before each run made every run a cold start: the
            # process 5.4 -> 9.4 ms, MakeFilling likewise 4.2 -> 5.4 ms).
            time.sleep(0.3)
            for _ in range(args.repeats):
                t = time.perf_counter()
                out = subprocess.run([str(cli), "fill", str(step_in), "-o", str(step_out), "--json"],
                                     check=True, capture_output=True, text=True)
                ptimes.append(time.perf_counter() - t)
                report = json.loads(out.stdout)["fills"][0]
                ltimes.append(report["seconds"]["total"])
            # In this process, as MakeFilling: the call (read, holes, fill,
            # measure; no writing) and the fill's own report of it.
            calls, fills = [], []
            time.sleep(0.3)  # Open CASCADE's spinning threads, as above
            for _ in range(args.repeats if fairsurf else 0):
                t = time.perf_counter()
                filled = fairsurf.fill(step_in)
                calls.append(time.perf_counter() - t)
                fills.append(filled.report["fills"][0]["seconds"]["total"])
            inproc = (statistics.median(fills), statistics.median(calls)) if fills else None
            ours = faces_of(read_step(step_out))[-1]
            fs_angle, fs_gap = seam(ours, edges)
            fs_w, fs_h, fs_k, fs_rect = total_curvature(ours)
            assert abs(occ_rect - 1) < 1e-6 and abs(fs_rect - 1) < 1e-6, (occ_rect, fs_rect)
            rows.append((name, statistics.median(times), occ_angle, occ_gap, occ_w,
                         statistics.median(ltimes), statistics.median(ptimes), fs_angle,
                         fs_gap, fs_w, report["max_angle_deg"], report["curvature_w"],
                         occ_h, occ_k, fs_h, fs_k, inproc))
    print(f"{'hole':8} {'MakeFilling':>34} | {'fairsurf fill (measured by Open CASCADE)':>52} | "
          f"{'fairsurf reports':>20}")
    print(f"{'':8} {'ms':>7} {'angle°':>9} {'gap':>8} {'W':>9} | {'lib ms':>7} {'proc ms':>8} "
          f"{'angle°':>9} {'gap':>8} {'W':>9} {'W/W_MF':>7} | {'angle°':>9} {'W':>9}")
    for (name, mt, ma, mg, mw, lt, pt, fa, fg, fw, ra, rw, *_parts) in rows:
        print(f"{name:8} {1e3 * mt:7.2f} {ma:9.2e} {mg:8.1e} {mw:9.6f} | {1e3 * lt:7.2f} "
              f"{1e3 * pt:8.1f} {fa:9.1e} {fg:8.1e} {fw:9.6f} {fw / mw:7.4f} | {ra:9.1e} {rw:9.6f}")
    print("W = integral 4H^2 dA - 2 integral K dA (integral K dA is fixed by the boundary and its "
          "tangent planes, Gauss-Bonnet):")
    for (name, *_r, occ_h, occ_k, fs_h, fs_k, _inproc) in rows:
        print(f"  {name}: MakeFilling 4H^2 {occ_h:.6f} K {occ_k:.6f} | fairsurf 4H^2 {fs_h:.6f} "
              f"K {fs_k:.6f}")
    print("time ratio MakeFilling / fairsurf (> 1: fairsurf faster):")
    for (name, mt, _, _, _, lt, pt, *_rest, inproc) in rows:
        print(f"  {name}: the library's fill {mt / lt:.2f}, the whole fairsurf fill process {mt / pt:.2f}")
    if fairsurf is None:
        print("(no fairsurf package in this Python: no in-process times)")
    else:
        print("in this process, as MakeFilling (ms; ratio MakeFilling / fairsurf):")
        for (name, mt, *_rest, inproc) in rows:
            fill, call = inproc
            print(f"  {name}: the fill {1e3 * fill:.2f} ({mt / fill:.2f}), fairsurf.fill reading STEP "
                  f"and finding the holes too {1e3 * call:.2f} ({mt / call:.2f})")


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--repeats", type=int, default=9)
    p.add_argument("--cli", default=str(ROOT / "target" / "release" / "fairsurf"))
    p.add_argument("--keep", help="write the holes' and the fills' STEP files here")
    run(p.parse_args())
