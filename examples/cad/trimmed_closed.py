"""Writes trimmed_closed.step with Open CASCADE (pip cadquery-ocp): faces of
surfaces of revolution that reach a pole, go all the way round, or span
more than half a turn, each with a 4-sided hole (a turned square in (u, v),
its edges approximated to 1e-8):

- a dome: the unit sphere about (4, 0, 0) over v in [0, pi/2], all the way
  round (its seam edge from the equator to the pole, used twice);
- a wide piece of the unit sphere about (8, 0, 0): u in [0.3, 4.8] (more
  than half a turn), v in [-0.8, 0.9];
- a whole torus about (0, 6, 0), radii 2 and 0.6 (two seam edges; the
  hole is its only free loop).

Also `ball()` (the whole unit sphere but a hole: Open CASCADE writes it
with no seam edge) and `point()` (a cone face up to its apex), which
fairsurf refuses, and `lune()` (the unit sphere from pole to pole over
u in [0.3, 4.8], bounded by two meridians only, with a hole).

    python examples/cad/trimmed_closed.py examples/cad/trimmed_closed.step
"""

import math
import sys
from pathlib import Path

from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
from OCP.Geom import Geom_ConicalSurface, Geom_SphericalSurface, Geom_ToroidalSurface
from OCP.gp import gp_Ax3, gp_Dir, gp_Pnt

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fillet_hole import write_sewn  # noqa: E402
from trimmed_hole import polygon, with_hole  # noqa: E402


def ax(x, y, z):
    return gp_Ax3(gp_Pnt(x, y, z), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0))


def holed(surface, box, corners):
    return with_hole(BRepBuilderAPI_MakeFace(surface, *box, 1e-7).Face(), surface, corners)


def faces():
    return [
        holed(Geom_SphericalSurface(ax(4, 0, 0), 1.0), (0, 2 * math.pi, 0, math.pi / 2),
              polygon((2.0, 0.6), 0.3, 4)),
        holed(Geom_SphericalSurface(ax(8, 0, 0), 1.0), (0.3, 4.8, -0.8, 0.9),
              polygon((2.5, 0.0), 0.4, 4)),
        holed(Geom_ToroidalSurface(ax(0, 6, 0), 2.0, 0.6), (0, 2 * math.pi, 0, 2 * math.pi),
              polygon((1.0, 1.0), 0.4, 4)),
    ]


def ball():
    return holed(Geom_SphericalSurface(ax(0, 0, 0), 1.0), (0, 2 * math.pi, -math.pi / 2, math.pi / 2),
                 polygon((1.0, 0.2), 0.4, 4))


def lune():
    return holed(Geom_SphericalSurface(ax(0, 0, 0), 1.0), (0.3, 4.8, -math.pi / 2, math.pi / 2),
                 polygon((2.5, 0.0), 0.4, 4))


def point():
    angle = math.radians(25)
    return holed(Geom_ConicalSurface(ax(6, 6, 0), angle, 1.0),
                 (0, 2 * math.pi, -1.0 / math.sin(angle), 1.0), polygon((2.0, -0.5), 0.4, 4))


if __name__ == "__main__":
    write_sewn(faces(), sys.argv[1])
