"""Writes trimmed_revolved.step with Open CASCADE (pip cadquery-ocp): four
trimmed faces of surfaces of revolution as CAD writes them, each with a
4-sided hole -- faces with two loops on CYLINDRICAL_SURFACE,
CONICAL_SURFACE, SPHERICAL_SURFACE and TOROIDAL_SURFACE:

- a whole pipe (cylinder of radius 1 about z, height 3: its seam edge used
  twice), the hole bounded by two arcs and two rulings (isolines);
- a cone (radius 1 at its placement, semi-angle 20 degrees) over
  u in [0, 2.5], v in [0, 2], the hole a turned square in (u, v);
- a sphere (radius 1.5) over u in [0.2, 2.2], v in [-0.6, 0.9], likewise;
- a torus (radii 2 and 0.7) over u in [0.3, 1.9], v in [-1.2, 1.5],
  likewise.

The turned squares' edges are lines of the parameter plane (not
isolines), their 3-D curves approximated by Open CASCADE to 1e-8.

    python examples/cad/trimmed_revolved.py examples/cad/trimmed_revolved.step
"""

import math
import sys
from pathlib import Path

from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
from OCP.Geom import (
    Geom_ConicalSurface,
    Geom_CylindricalSurface,
    Geom_SphericalSurface,
    Geom_ToroidalSurface,
)
from OCP.gp import gp_Ax3, gp_Dir, gp_Pnt

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fillet_hole import write_sewn  # noqa: E402
from trimmed_hole import polygon, with_hole  # noqa: E402


def holed(surface, box, corners):
    """The face of `surface` over box = (u0, u1, v0, v1) with the hole
    through the (u, v) corners (clockwise: an inner loop)."""
    return with_hole(BRepBuilderAPI_MakeFace(surface, *box, 1e-7).Face(), surface, corners)


def turned_square(centre, radius):
    return polygon(centre, radius, 4)


def faces():
    def ax(x, y, z):
        return gp_Ax3(gp_Pnt(x, y, z), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0))

    pipe = Geom_CylindricalSurface(ax(0, 0, 0), 1.0)
    cone = Geom_ConicalSurface(ax(4, 0, 0), math.radians(20), 1.0)
    sphere = Geom_SphericalSurface(ax(0, 5, 0), 1.5)
    torus = Geom_ToroidalSurface(ax(6, 6, 0), 2.0, 0.7)
    return [
        holed(pipe, (0.0, 2 * math.pi, 0.0, 3.0), [(1.0, 1.0), (1.0, 2.0), (2.0, 2.0), (2.0, 1.0)]),
        holed(cone, (0.0, 2.5, 0.0, 2.0), turned_square((1.25, 1.0), 0.5)),
        holed(sphere, (0.2, 2.2, -0.6, 0.9), turned_square((1.2, 0.15), 0.35)),
        holed(torus, (0.3, 1.9, -1.2, 1.5), turned_square((1.1, 0.15), 0.4)),
    ]


if __name__ == "__main__":
    write_sewn(faces(), sys.argv[1])
