#!/usr/bin/env python3
"""`fairsurf fill` on 3-, 5- and 6-sided holes against Open CASCADE's MakeFilling.

Each hole is a regular n-gon (circumradius 1) in the graph of a cubic, ringed
by n bicubic Bezier faces built by Open CASCADE (python/tests/occ_check.py,
polygon_network), sewn and written as STEP. MakeFilling (its defaults) gets
the n hole edges with G1 constraints to their faces, in this process;
`fairsurf fill` reads the STEP file in its own process and fills the hole
with a fan of n triangular patches, or a 3-sided one with a single
triangular patch when that is fairer (written as collapsed tensor patches).
Both are measured by Open CASCADE: the largest normal angle and gap across
the hole's edges (65 points per edge, Newton-refined foot points, as in
bench/fill_vs_makefilling.py), and W = integral of k1^2 + k2^2 dA — over
MakeFilling's trimmed face through a star map of its parameter region from
the centroid of its boundary pcurves, over each of fairsurf's untrimmed
patches on its parameter rectangle; both checked against BRepGProp's area.

    python3 -m venv target/bench-venv && target/bench-venv/bin/pip install numpy cadquery-ocp
    cargo build --release -p fairsurf-cli
    target/bench-venv/bin/python bench/polygon_vs_makefilling.py [--repeats 5] [--cli target/release/fairsurf] [--keep DIR]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
sys.path.insert(0, str(ROOT / "python" / "tests"))

import fill_vs_makefilling as fb  # noqa: E402
from occ_check import polygon_network  # noqa: E402

sys.path.insert(0, str(ROOT / "examples" / "cad"))
from rounded_box import faces as rounded_box_faces  # noqa: E402
from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.BRepGProp import BRepGProp  # noqa: E402
from OCP.BRepOffsetAPI import BRepOffsetAPI_MakeFilling  # noqa: E402
from OCP.BRepTools import BRepTools, BRepTools_WireExplorer  # noqa: E402
from OCP.GeomAbs import GeomAbs_G1  # noqa: E402
from OCP.gp import gp_Pnt2d, gp_Vec2d  # noqa: E402
from OCP.GProp import GProp_GProps  # noqa: E402
from OCP.TopAbs import TopAbs_REVERSED  # noqa: E402
from OCP.TopoDS import TopoDS  # noqa: E402

NODES, CELLS = 16, 4


def area_of(face):
    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(face, props, 1e-10)
    return props.Mass()


def integrate(s, points):
    """W and the area from (u, v, weight x Jacobian) quadrature points."""
    w = area = 0.0
    for u, v, jw in points:
        h2, k, da = fb.curvature_squared(s, u, v)
        w += (h2 - 2 * k) * da * jw
        area += da * jw
    return w, area


def gauss():
    g, wt = np.polynomial.legendre.leggauss(NODES)
    return (g + 1) / 2, wt / 2


def w_star(face):
    """W over a trimmed face: its parameter region as the union of the
    curved triangles (centroid, boundary pcurve k), each mapped from the unit
    square by (s, t) -> c + s (e_k(t) - c) (Jacobian s |det(e_k - c, e_k')|)."""
    s = BRep_Tool.Surface_s(face)
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
    centre = np.mean([side(k / 8)[0] for side in sides for k in range(8)], axis=0)
    g, wt = gauss()
    points = []
    for side in sides:
        for i in range(CELLS):
            for j in range(CELLS):
                for x, wx in zip(g, wt):
                    for y, wy in zip(g, wt):
                        sp, t = (i + x) / CELLS, (j + y) / CELLS
                        e, de = side(t)
                        uv = centre + sp * (e - centre)
                        jac = sp * abs((e - centre)[0] * de[1] - (e - centre)[1] * de[0])
                        points.append((uv[0], uv[1], jac * wx * wy / CELLS**2))
    w, area = integrate(s, points)
    return w, area / area_of(face)


def w_rect(face):
    """W over an untrimmed face: Gauss-Legendre on its parameter rectangle."""
    s = BRep_Tool.Surface_s(face)
    u0, u1, v0, v1 = s.Bounds()
    g, wt = gauss()
    points = []
    for i in range(CELLS):
        for j in range(CELLS):
            for x, wx in zip(g, wt):
                for y, wy in zip(g, wt):
                    u = u0 + (u1 - u0) * (i + x) / CELLS
                    v = v0 + (v1 - v0) * (j + y) / CELLS
                    points.append((u, v, (u1 - u0) * (v1 - v0) * wx * wy / CELLS**2))
    w, area = integrate(s, points)
    return w, area / area_of(face)


def nearest_face(faces, edge):
    """The face (of `faces`) that holds the edge's midpoint."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex

    c = BRepAdaptor_Curve(edge)
    mid = BRepBuilderAPI_MakeVertex(c.Value(0.5 * (c.FirstParameter() + c.LastParameter()))).Vertex()
    return min(faces, key=lambda f: BRepExtrema_DistShapeShape(mid, f).Value())


def run(args):
    cli = Path(args.cli)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(args.keep) if args.keep else Path(tmp)
        tmp.mkdir(parents=True, exist_ok=True)
        for n in (3, 5, 6, "corner"):
            if n == "corner":
                # A rounded box (every edge filleted) without the spherical
                # corner at the origin: a 3-sided hole between cylinders.
                shape = fb.sew(rounded_box_faces(only_origin=True))
                n = 3
                name = "box corner"
            else:
                shape = fb.sew(polygon_network(n))
                name = str(n)
            step_in = tmp / f"polygon{name.replace(' ', '_')}.step"
            fb.write_step(shape, step_in)
            edges = fb.hole_edges(shape, n)
            times, fill = [], None
            for _ in range(args.repeats):
                mf = BRepOffsetAPI_MakeFilling()
                for e, f in edges:
                    mf.Add(e, f, GeomAbs_G1, True)
                t = time.perf_counter()
                mf.Build()
                times.append(time.perf_counter() - t)
                fill = TopoDS.Face(mf.Shape())
            mf_angle, mf_gap = fb.seam(fill, edges)
            mf_w, mf_area = w_star(fill)
            out = tmp / f"polygon{name.replace(' ', '_')}.filled.step"
            ptimes, ltimes, report = [], [], None
            # Open CASCADE's threads spin on after MakeFilling: one pause,
            # then the runs back to back, as MakeFilling's (a pause before
            # each made every run a cold start).
            time.sleep(0.3)
            for _ in range(args.repeats):
                t = time.perf_counter()
                run = subprocess.run([str(cli), "fill", str(step_in), "-o", str(out), "--json"],
                                     check=True, capture_output=True, text=True)
                ptimes.append(time.perf_counter() - t)
                report = json.loads(run.stdout)["fills"][0]
                ltimes.append(report["seconds"]["total"])
            fan = fb.faces_of(fb.read_step(out))[len(fb.faces_of(shape)):]
            assert len(fan) == report["patches"]
            fs_angle = fs_gap = fs_w = 0.0
            for e, nb in edges:
                a, g = fb.seam(nearest_face(fan, e), [(e, nb)])
                fs_angle, fs_gap = max(fs_angle, a), max(fs_gap, g)
            for f in fan:
                w, area = w_rect(f)
                assert abs(area - 1) < 1e-6, area
                fs_w += w
            assert abs(mf_area - 1) < 1e-6, mf_area
            rows.append((name, statistics.median(times), mf_angle, mf_gap, mf_w,
                         statistics.median(ltimes), statistics.median(ptimes), fs_angle, fs_gap,
                         fs_w, report["max_angle_deg"], report["inner_angle_deg"],
                         report["curvature_w"]))
    print(f"{'sides':>10} {'MakeFilling':>34} | {'fairsurf fill: fan (measured by Open CASCADE)':>52} | "
          f"{'fairsurf reports':>30}")
    print(f"{'':10} {'ms':>7} {'angle°':>9} {'gap':>8} {'W':>9} | {'lib ms':>7} {'proc ms':>8} "
          f"{'angle°':>9} {'gap':>8} {'W':>9} {'W/W_MF':>7} | {'angle°':>9} {'inner°':>9} {'W':>9}")
    for (n, mt, ma, mg, mw, lt, pt, fa, fg, fw, ra, ri, rw) in rows:
        print(f"{n:>10} {1e3 * mt:7.2f} {ma:9.2e} {mg:8.1e} {mw:9.6f} | {1e3 * lt:7.2f} "
              f"{1e3 * pt:8.1f} {fa:9.1e} {fg:8.1e} {fw:9.6f} {fw / mw:7.4f} | {ra:9.1e} "
              f"{ri:9.1e} {rw:9.6f}")


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--cli", default=str(ROOT / "target" / "release" / "fairsurf"))
    p.add_argument("--keep", help="write the holes' and the fills' STEP files here")
    run(p.parse_args())
