#!/usr/bin/env python3
"""`fairsurf blend` against Open CASCADE's BRepOffsetAPI_MakeFilling on the same blend.

The two surfaces of examples/cad/blend_sheets.json (a bicubic B-spline sheet
and a tilted biquartic Bezier sheet) are built by Open CASCADE and written as
one STEP shell; `fairsurf blend` (its own process, `--json`) joins A's u1 edge
to B's u0 edge. MakeFilling then gets the same four boundary curves: the two
edges the blend shares with A and B, G1 to those faces, and the blend's two
made sides (cubic Hermite curves), C0, as free constraints; degree 3, 15
points per curve, 2 iterations: its defaults. Both are measured by Open
CASCADE the same way as in bench/fill_vs_makefilling.py: the largest normal
angle across the two G1 edges (65 points per edge, Newton-refined foot
points), the largest gap there, and W = integral of k1^2 + k2^2 dA by
Gauss-Legendre through the Coons map of the face's pcurves.

Rows: fairsurf with the bulges chosen by W (the default) and with both
bulges 1; MakeFilling with each of their boundaries. Times: medians of
--repeats; fairsurf's in-library time is its report's (the whole bulge search
when there is one).

    python3 -m venv target/bench-venv && target/bench-venv/bin/pip install numpy cadquery-ocp
    cargo build --release -p fairsurf-cli
    target/bench-venv/bin/python bench/blend_vs_makefilling.py [--repeats 5]
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

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
sys.path.insert(0, str(ROOT / "python" / "tests"))

import fill_vs_makefilling as fb  # noqa: E402
from occ_check import bezier_face, bspline_surface  # noqa: E402
from OCP.BRep import BRep_Builder  # noqa: E402
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace  # noqa: E402
from OCP.BRepOffsetAPI import BRepOffsetAPI_MakeFilling  # noqa: E402
from OCP.GeomAbs import GeomAbs_C0, GeomAbs_G1  # noqa: E402
from OCP.TopAbs import TopAbs_EDGE  # noqa: E402
from OCP.TopExp import TopExp_Explorer  # noqa: E402
from OCP.TopoDS import TopoDS, TopoDS_Shell  # noqa: E402


def distinct(knots):
    """(distinct values, multiplicities) of a full knot vector."""
    values, mults = [], []
    for k in knots:
        if values and k == values[-1]:
            mults[-1] += 1
        else:
            values.append(float(k))
            mults.append(1)
    return values, mults


def occ_face(spec):
    """An Open CASCADE face of a blend scene's inline face."""
    if spec["type"] == "tensor":
        return bezier_face(spec["control_points"])
    (uk, um), (vk, vm) = distinct(spec["knots"][0]), distinct(spec["knots"][1])
    s = bspline_surface(spec["control_points"], uk, um, vk, vm, *spec["degree"])
    return BRepBuilderAPI_MakeFace(s, 1e-7).Face()


def edges_of(face):
    out, ex = [], TopExp_Explorer(face, TopAbs_EDGE)
    while ex.More():
        out.append(TopoDS.Edge(ex.Current()))
        ex.Next()
    return out


def run(args):
    cli = Path(args.cli)
    scene = json.loads((ROOT / "examples" / "cad" / "blend_sheets.json").read_text())
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        builder, shell = BRep_Builder(), TopoDS_Shell()
        builder.MakeShell(shell)
        for s in scene["surfaces"]:
            builder.Add(shell, occ_face(s["face"]))
        fb.write_step(shell, tmp / "sheets.step")
        for label, bulge in (("least W", None), ("bulge 1", [1.0, 1.0])):
            job = {"surfaces": [
                {"step": "sheets.step", "index": 0, "edge": scene["surfaces"][0]["edge"]},
                {"step": "sheets.step", "index": 1, "edge": scene["surfaces"][1]["edge"]},
            ]}
            if bulge:
                job["bulge"] = bulge
            (tmp / "job.json").write_text(json.dumps(job))
            out = tmp / "blended.step"
            ptimes, ltimes, report = [], [], None
            for _ in range(args.repeats):
                time.sleep(0.3)  # Open CASCADE's threads spin on after MakeFilling
                t = time.perf_counter()
                run = subprocess.run([str(cli), "blend", str(tmp / "job.json"), "-o", str(out),
                                      "--json"], check=True, capture_output=True, text=True)
                ptimes.append(time.perf_counter() - t)
                report = json.loads(run.stdout)
                search = report["bulge_search"]
                ltimes.append(search["seconds"] if search else report["seconds"]["total"])
            a, b, ours = fb.faces_of(fb.read_step(out))
            # The blend's edges: shared with A, with B, and the two made sides.
            g1, made = [], []
            for e in edges_of(ours):
                owner = next((f for f in (a, b) if any(e.IsSame(x) for x in edges_of(f))), None)
                if owner is None:
                    made.append(e)
                else:
                    g1.append((e, owner))
            assert len(g1) == 2 and len(made) == 2, (len(g1), len(made))
            times, fill = [], None
            for _ in range(args.repeats):
                mf = BRepOffsetAPI_MakeFilling()
                for e, f in g1:
                    mf.Add(e, f, GeomAbs_G1, True)
                for e in made:
                    mf.Add(e, GeomAbs_C0, True)
                t = time.perf_counter()
                mf.Build()
                times.append(time.perf_counter() - t)
                fill = TopoDS.Face(mf.Shape())
            mf_angle, mf_gap = fb.seam(fill, g1)
            mf_w, _, _, mf_rect = fb.total_curvature(fill)
            fs_angle, fs_gap = fb.seam(ours, g1)
            fs_w, _, _, fs_rect = fb.total_curvature(ours)
            assert abs(mf_rect - 1) < 1e-6 and abs(fs_rect - 1) < 1e-6, (mf_rect, fs_rect)
            rows.append((label, report["bulge"], statistics.median(times), mf_angle, mf_gap, mf_w,
                         statistics.median(ltimes), statistics.median(ptimes), fs_angle, fs_gap,
                         fs_w, report["max_angle_deg"], report["curvature_w"]))
    print(f"{'fairsurf':9} {'bulge':>17} | {'MakeFilling (same boundary)':>36} | "
          f"{'fairsurf blend (measured by Open CASCADE)':>53} | {'fairsurf reports':>20}")
    print(f"{'':9} {'':>17} | {'ms':>7} {'angle°':>9} {'gap':>8} {'W':>9} | {'lib ms':>7} "
          f"{'proc ms':>8} {'angle°':>9} {'gap':>8} {'W':>9} {'W/W_MF':>7} | {'angle°':>9} {'W':>9}")
    for (label, bulge, mt, ma, mg, mw, lt, pt, fa, fg, fw, ra, rw) in rows:
        print(f"{label:9} [{bulge[0]:7.4f},{bulge[1]:7.4f}] | {1e3 * mt:7.2f} {ma:9.2e} {mg:8.1e} "
              f"{mw:9.6f} | {1e3 * lt:7.2f} {1e3 * pt:8.1f} {fa:9.1e} {fg:8.1e} {fw:9.6f} "
              f"{fw / mw:7.4f} | {ra:9.1e} {rw:9.6f}")


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--cli", default=str(ROOT / "target" / "release" / "fairsurf"))
    run(p.parse_args())
