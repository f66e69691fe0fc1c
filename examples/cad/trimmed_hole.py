"""Writes trimmed_hole.step with Open CASCADE (pip cadquery-ocp): a wavy
bicubic B-spline sheet as ONE face with a hole in it (4 sides, or the
number given) -- a face with two loops, the hole's edges lines of the
surface's parameter plane (not isolines), their 3-D curves approximated
by Open CASCADE to 1e-8.

    python examples/cad/trimmed_hole.py examples/cad/trimmed_hole.step [SIDES]
"""

import math
import sys

from OCP.BRepBuilderAPI import (
    BRepBuilderAPI_MakeEdge,
    BRepBuilderAPI_MakeFace,
    BRepBuilderAPI_MakeWire,
)
from OCP.BRepLib import BRepLib
from OCP.Geom import Geom_BSplineSurface
from OCP.Geom2d import Geom2d_Line
from OCP.GeomAbs import GeomAbs_C2
from OCP.gp import gp_Dir2d, gp_Pnt, gp_Pnt2d
from OCP.Interface import Interface_Static
from OCP.ShapeFix import ShapeFix_Face
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
from OCP.collections import Array1_double, Array1_int, Array2_gp_Pnt


def sheet() -> Geom_BSplineSurface:
    """The bicubic sheet of the fill tests over [0, 3]², uneven knots."""
    uk, um = [0.0, 0.5, 1.0, 1.7, 2.0, 2.4, 3.0], [4, 1, 1, 1, 1, 1, 4]
    vk, vm = [0.0, 0.8, 1.2, 1.5, 2.1, 3.0], [4, 1, 1, 1, 1, 4]
    cu, cv = sum(um) - 4, sum(vm) - 4
    poles = Array2_gp_Pnt(1, cu, 1, cv)
    for i in range(cu):
        for j in range(cv):
            poles.SetValue(i + 1, j + 1, gp_Pnt(
                0.4 * i, 0.45 * j + 0.02 * i, 0.4 * math.cos(0.44 * i) * math.sin(0.63 * j)))

    def arr(values, kind):
        a = kind(1, len(values))
        for k, x in enumerate(values):
            a.SetValue(k + 1, x)
        return a

    return Geom_BSplineSurface(
        poles, arr(uk, Array1_double), arr(vk, Array1_double),
        arr(um, Array1_int), arr(vm, Array1_int), 3, 3)


def polygon_wire(s, corners):
    """A closed wire of the surface's parameter-plane segments through
    `corners` (u, v)."""
    wire = BRepBuilderAPI_MakeWire()
    for k in range(len(corners)):
        (u0, v0), (u1, v1) = corners[k], corners[(k + 1) % len(corners)]
        length = math.hypot(u1 - u0, v1 - v0)
        line = Geom2d_Line(gp_Pnt2d(u0, v0), gp_Dir2d(u1 - u0, v1 - v0))
        wire.Add(BRepBuilderAPI_MakeEdge(line, s, 0.0, length).Edge())
    return wire.Wire()


def polygon(centre, radius: float, sides: int, turn: float = 0.3):
    """A regular polygon's corners clockwise in (u, v) (an inner loop)."""
    return [(centre[0] + radius * math.cos(-2 * math.pi * k / sides + turn),
             centre[1] + radius * math.sin(-2 * math.pi * k / sides + turn))
            for k in range(sides)]


def with_hole(outer, surface, corners):
    """The face `outer` of `surface` with the hole through the (u, v)
    corners (clockwise), its edges' 3-D curves built to 1e-8."""
    make = BRepBuilderAPI_MakeFace(outer)
    make.Add(polygon_wire(surface, corners))
    f = make.Face()
    BRepLib.BuildCurves3d_s(f, 1e-8, GeomAbs_C2, 14, 200)
    fix = ShapeFix_Face(f)
    fix.Perform()
    return fix.Face()


def face(sides: int = 4, radius: float = 0.6, centre=(1.5, 1.4)):
    s = sheet()
    return with_hole(BRepBuilderAPI_MakeFace(s, 1e-7).Face(), s, polygon(centre, radius, sides))


def write(path: str, sides: int = 4) -> None:
    writer = STEPControl_Writer()
    Interface_Static.SetCVal_s("write.step.schema", "AP214")
    writer.Transfer(face(sides), STEPControl_AsIs)
    writer.Write(path)


if __name__ == "__main__":
    write(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 4)
