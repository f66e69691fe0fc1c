"""Writes rounded_box.step with Open CASCADE (pip cadquery-ocp): a 2 × 3 × 1.5
box with every edge rounded (radius 0.4, BRepFilletAPI_MakeFillet) and its
eight spherical corners removed — a closed shell of 6 PLANE and 12
CYLINDRICAL_SURFACE faces with eight 3-sided holes, each between three
cylinder fillets. `fairsurf fill` fills every corner (no hole is an outer
rim: the shell is closed).

    python examples/cad/rounded_box.py examples/cad/rounded_box.step
"""

import sys

from OCP.BRepAdaptor import BRepAdaptor_Surface
from OCP.BRepBuilderAPI import BRepBuilderAPI_Sewing
from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
from OCP.GeomAbs import GeomAbs_Sphere
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS


RADIUS = 0.4


def faces(only_origin: bool = False):
    """The rounded box's faces without its spherical corners (with
    `only_origin`, without only the corner at the origin, whose sphere is
    centred at (r, r, r))."""
    box = BRepPrimAPI_MakeBox(2.0, 3.0, 1.5).Shape()
    rounded = BRepFilletAPI_MakeFillet(box)
    ex = TopExp_Explorer(box, TopAbs_EDGE)
    while ex.More():
        rounded.Add(RADIUS, TopoDS.Edge(ex.Current()))
        ex.Next()
    rounded.Build()
    out = []
    ex = TopExp_Explorer(rounded.Shape(), TopAbs_FACE)
    while ex.More():
        f = TopoDS.Face(ex.Current())
        s = BRepAdaptor_Surface(f)
        if s.GetType() != GeomAbs_Sphere:
            out.append(f)
        elif only_origin:
            c = s.Sphere().Location()
            if max(abs(c.X() - RADIUS), abs(c.Y() - RADIUS), abs(c.Z() - RADIUS)) > 1e-9:
                out.append(f)
        ex.Next()
    return out


def main(path: str) -> None:
    sewing = BRepBuilderAPI_Sewing(1e-7)
    for f in faces():
        sewing.Add(f)
    sewing.Perform()
    Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    writer = STEPControl_Writer()
    writer.Transfer(sewing.SewedShape(), STEPControl_AsIs)
    if int(writer.Write(path)) != 1:
        raise SystemExit(f"could not write {path}")


if __name__ == "__main__":
    main(sys.argv[1])
