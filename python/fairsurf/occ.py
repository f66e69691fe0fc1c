"""Open CASCADE in and out: fairsurf surfaces as ``Geom_BSplineSurface`` and
``TopoDS_Face``, and B-spline or Bézier faces back as fairsurf surfaces.

Needs OCP (``pip install cadquery-ocp``, the bindings CadQuery and build123d
use; written against OCP 8 / OCCT 8); importing this module without it
raises ``ImportError``.

>>> from fairsurf import occ                       # doctest: +SKIP
>>> face = occ.to_face(fairsurf.solve("examples/bspline_hole.json"))  # doctest: +SKIP

The conversions are exact: poles are the control points, knots and
multiplicities the knot vectors (a Bézier patch is a B-spline on [0, 1] with
end multiplicities n + 1), so OCC evaluates the same surface.
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
from typing import Any, Iterator, List, Optional, Sequence, Tuple

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_Sewing
from OCP.Geom import Geom_BezierSurface, Geom_BSplineSurface
from OCP.collections import Array1_double, Array1_int, Array2_gp_Pnt
from OCP.gp import gp_Pnt
from OCP.TopAbs import TopAbs_FACE
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS, TopoDS_Face, TopoDS_Shape

from . import Filled, Surface, fill, load

__all__ = ["to_geom", "to_bezier", "to_face", "to_shape", "from_face", "from_geom", "faces", "fill_shape"]


def _distinct(knots: np.ndarray) -> Tuple[List[float], List[int]]:
    """A full knot vector as distinct values and multiplicities."""
    values: List[float] = []
    mults: List[int] = []
    for k in knots.tolist():
        if values and k == values[-1]:
            mults[-1] += 1
        else:
            values.append(k)
            mults.append(1)
    return values, mults


def _reals(xs: List[float]) -> Array1_double:
    a = Array1_double(1, len(xs))
    for i, x in enumerate(xs, 1):
        a.SetValue(i, float(x))
    return a


def _ints(xs: List[int]) -> Array1_int:
    a = Array1_int(1, len(xs))
    for i, x in enumerate(xs, 1):
        a.SetValue(i, int(x))
    return a


def _poles(cp: np.ndarray) -> Array2_gp_Pnt:
    """A net (nu, nv, 3) as Open CASCADE's 1-based array of poles."""
    nu, nv = cp.shape[:2]
    poles = Array2_gp_Pnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            x, y, z = cp[i, j].tolist()
            poles.SetValue(i + 1, j + 1, gp_Pnt(x, y, z))
    return poles


def _geom(cp: np.ndarray, p: int, q: int, u: List[float], um: List[int],
          v: List[float], vm: List[int]) -> Geom_BSplineSurface:
    return Geom_BSplineSurface(_poles(cp), _reals(u), _reals(v), _ints(um), _ints(vm), p, q)


def _bezier_geom(cp: np.ndarray) -> Geom_BSplineSurface:
    p, q = cp.shape[0] - 1, cp.shape[1] - 1
    return _geom(cp, p, q, [0.0, 1.0], [p + 1] * 2, [0.0, 1.0], [q + 1] * 2)


def to_geom(surface: Surface) -> Geom_BSplineSurface:
    """The surface as a non-rational ``Geom_BSplineSurface``: a tensor patch
    on [0, 1]², a B-spline surface on its own knots. A triangular surface has
    one face per patch and is refused (``ValueError``: use :func:`to_shape`)."""
    if surface.surface_type == "triangular":
        raise ValueError(
            "a triangular surface is many patches, one face each: use to_shape"
        )
    if surface.knots is None:
        return _bezier_geom(surface.control_points)
    p, q = surface.degree
    (u, um), (v, vm) = (_distinct(k) for k in surface.knots)
    return _geom(surface.control_points, p, q, u, um, v, vm)


def to_bezier(surface: Surface) -> Geom_BezierSurface:
    """A tensor patch as a ``Geom_BezierSurface`` on [0, 1]² (its control
    points the poles, exactly). Other kinds are refused (``ValueError``: a
    B-spline surface is :func:`to_geom`'s, a triangular one
    :func:`to_shape`'s)."""
    if surface.surface_type != "tensor":
        raise ValueError(
            f"a {surface.surface_type} surface is no Bézier patch: use "
            + ("to_shape" if surface.surface_type == "triangular" else "to_geom")
        )
    return Geom_BezierSurface(_poles(surface.control_points))


def to_face(surface: Surface, tolerance: float = 1e-7) -> TopoDS_Face:
    """The surface as a ``TopoDS_Face`` bounded by its parameter domain."""
    return BRepBuilderAPI_MakeFace(to_geom(surface), tolerance).Face()


def to_shape(surface: Surface, tolerance: float = 1e-7) -> TopoDS_Shape:
    """The surface as a shape: one face for a tensor or B-spline surface; for
    a triangular surface a shell of one face per patch (each patch's exact
    tensor form, one side collapsed), sewn so neighbouring patches share
    their edges."""
    if surface.surface_type != "triangular":
        return to_face(surface, tolerance)
    sewing = BRepBuilderAPI_Sewing(tolerance)
    for cp in surface.tensor_patches():
        sewing.Add(BRepBuilderAPI_MakeFace(_bezier_geom(cp), tolerance).Face())
    sewing.Perform()
    return sewing.SewedShape()


def from_geom(geom: object) -> Surface:
    """A ``Geom_BSplineSurface`` or ``Geom_BezierSurface`` as a fairsurf
    surface (``"bspline"`` or ``"tensor"``), exactly. Rational, periodic and
    other surfaces are refused with ``ValueError`` naming what they are."""
    if isinstance(geom, Geom_BezierSurface):
        if geom.IsURational() or geom.IsVRational():
            raise ValueError("a rational Bézier surface: fairsurf surfaces are polynomial")
        net = [[_xyz(geom.Pole(i, j)) for j in range(1, geom.NbVPoles() + 1)]
               for i in range(1, geom.NbUPoles() + 1)]
        return load({"surface": {"type": "tensor", "degree": [geom.UDegree(), geom.VDegree()],
                                 "control_points": net}})
    if not isinstance(geom, Geom_BSplineSurface):
        raise ValueError(
            f"a {type(geom).__name__}: only B-spline and Bézier surfaces convert exactly"
        )
    if geom.IsURational() or geom.IsVRational():
        raise ValueError("a rational B-spline (NURBS) surface: fairsurf surfaces are polynomial")
    if geom.IsUPeriodic() or geom.IsVPeriodic():
        raise ValueError("a periodic B-spline surface: fairsurf takes clamped knot vectors")

    def full(n: int, value, mult) -> List[float]:
        return [value(i) for i in range(1, n + 1) for _ in range(mult(i))]

    u = full(geom.NbUKnots(), geom.UKnot, geom.UMultiplicity)
    v = full(geom.NbVKnots(), geom.VKnot, geom.VMultiplicity)
    net = [[_xyz(geom.Pole(i, j)) for j in range(1, geom.NbVPoles() + 1)]
           for i in range(1, geom.NbUPoles() + 1)]
    return load({"surface": {"type": "bspline", "degree": [geom.UDegree(), geom.VDegree()],
                             "knots": [u, v], "control_points": net}})


def from_face(face: TopoDS_Face) -> Surface:
    """The underlying surface of a face (its trimming is not kept)."""
    return from_geom(BRep_Tool.Surface_s(face))


def faces(shape: TopoDS_Shape) -> List[TopoDS_Face]:
    """The faces of a shape, in the order Open CASCADE explores them."""
    out = []
    ex = TopExp_Explorer(shape, TopAbs_FACE)
    while ex.More():
        out.append(TopoDS.Face(ex.Current()))
        ex.Next()
    return out


def _xyz(p: gp_Pnt) -> List[float]:
    return [p.X(), p.Y(), p.Z()]


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """Open CASCADE's STEP writer prints its statistics on the process's
    standard output (file descriptor 1, below Python's sys.stdout): sent
    to /dev/null meanwhile."""
    sys.stdout.flush()
    saved = os.dup(1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(devnull)


def fill_shape(
    shape: TopoDS_Shape,
    holes: Optional[Sequence[int]] = None,
    tolerance: float = 1e-7,
    **options: Any,
) -> Tuple[TopoDS_Shape, Filled]:
    """Fills the holes of an Open CASCADE shape (its B-spline and Bézier
    faces; see :func:`fairsurf.fill` for ``holes`` and the options) and
    returns the shape sewn with the fills (``BRepBuilderAPI_Sewing`` at
    ``tolerance``: the fills share the holes' edges) and the
    :class:`fairsurf.Filled` with the report. The shape crosses to fairsurf
    as a STEP file written by Open CASCADE in a temporary directory."""
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "shape.step")
        with _quiet():
            writer = STEPControl_Writer()
            writer.Transfer(shape, STEPControl_AsIs)
            done = writer.Write(path)
        if done != IFSelect_RetDone:
            raise OSError(f"Open CASCADE could not write {path}")
        filled = fill(path, holes, **options)
    sewing = BRepBuilderAPI_Sewing(tolerance)
    sewing.Add(shape)
    for surface in filled.fills:
        # A polygonal hole's fill is triangular: a shell of its patches.
        sewing.Add(to_shape(surface, tolerance))
    sewing.Perform()
    return sewing.SewedShape(), filled
