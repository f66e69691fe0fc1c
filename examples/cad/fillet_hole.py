"""Writes fillet_hole.step with Open CASCADE (pip cadquery-ocp): a filleted
corner as CAD writes it -- plane | quarter cylinder (radius 1) | plane, in
three rows along the cylinder's axis, the middle cylinder face missing.
The planes are PLANE faces, the cylinders CYLINDRICAL_SURFACE faces bounded
by two CIRCLE arcs and two LINEs; everything sewn into one open shell.

    python examples/cad/fillet_hole.py examples/cad/fillet_hole.step
"""

import math
import sys

from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_Sewing
from OCP.gp import gp_Ax3, gp_Cylinder, gp_Dir, gp_Pln, gp_Pnt
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer


def faces(rows: int = 3, missing: int = 1):
    out = []
    for row in range(rows):
        y0, y1 = float(row), float(row + 1)
        # z = 0, x in [-1, 0].
        a = gp_Pln(gp_Ax3(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)))
        out.append(BRepBuilderAPI_MakeFace(a, -1.0, 0.0, y0, y1).Face())
        if row != missing:
            # Axis along -y through (0, 0, 1); angle 0 at (0, y, 0), pi/2 at (1, y, 1).
            axes = gp_Ax3(gp_Pnt(0, 0, 1), gp_Dir(0, -1, 0), gp_Dir(0, 0, -1))
            c = gp_Cylinder(axes, 1.0)
            out.append(BRepBuilderAPI_MakeFace(c, 0.0, math.pi / 2, -y1, -y0).Face())
        # x = 1, z in [1, 2].
        b = gp_Pln(gp_Ax3(gp_Pnt(1, 0, 0), gp_Dir(1, 0, 0), gp_Dir(0, 0, 1)))
        out.append(BRepBuilderAPI_MakeFace(b, 1.0, 2.0, -y1, -y0).Face())
    return out


def write(path: str) -> None:
    write_sewn(faces(), path)


def write_sewn(faces, path: str) -> None:
    """Open CASCADE sews the faces (1e-6) and writes them as AP214 STEP."""
    sew = BRepBuilderAPI_Sewing(1e-6)
    for f in faces:
        sew.Add(f)
    sew.Perform()
    writer = STEPControl_Writer()
    Interface_Static.SetCVal_s("write.step.schema", "AP214")
    writer.Transfer(sew.SewedShape(), STEPControl_AsIs)
    writer.Write(path)


if __name__ == "__main__":
    write(sys.argv[1])
