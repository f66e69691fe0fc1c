"""Writes revolved.step with Open CASCADE (pip cadquery-ocp): faces on a
torus and on a sphere as CAD writes them -- TOROIDAL_SURFACE and
SPHERICAL_SURFACE bounded by four CIRCLE arcs (two parallels, two
meridians) -- for crates/fairsurf-io/tests/suite/revolved.rs.

    python crates/fairsurf-io/tests/data/revolved.py crates/fairsurf-io/tests/data/revolved.step

Torus: axis z through (1, 2, 3), major radius 2, minor radius 0.5, u in
[0.3, 1.9] (about the axis, 92 degrees), v in [-0.4, 1.2] (about the tube).
Sphere: centre (-3, 0, 1), radius 1.5, u in [0.2, 2.2], v in [-0.6, 0.9].
Octant: centre (0, -4, 0), radius 1, u and v in [0, pi/2] (up to the
north pole: three edges, the pole a vertex).
"""

import math
import sys
from pathlib import Path

from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
from OCP.gp import gp_Ax3, gp_Dir, gp_Pnt, gp_Sphere, gp_Torus

sys.path.insert(0, str(Path(__file__).resolve().parents[4] / "examples" / "cad"))
from fillet_hole import write_sewn  # noqa: E402


def write(path: str) -> None:
    torus = gp_Torus(gp_Ax3(gp_Pnt(1, 2, 3), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)), 2.0, 0.5)
    sphere = gp_Sphere(gp_Ax3(gp_Pnt(-3, 0, 1), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)), 1.5)
    octant = gp_Sphere(gp_Ax3(gp_Pnt(0, -4, 0), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)), 1.0)
    write_sewn([BRepBuilderAPI_MakeFace(torus, 0.3, 1.9, -0.4, 1.2).Face(),
                BRepBuilderAPI_MakeFace(sphere, 0.2, 2.2, -0.6, 0.9).Face(),
                BRepBuilderAPI_MakeFace(octant, 0.0, math.pi / 2, 0.0, math.pi / 2).Face()],
               path)


if __name__ == "__main__":
    write(sys.argv[1])
