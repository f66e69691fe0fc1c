"""`fairsurf.Problem` and `fairsurf.TriProblem`: scenes built from numpy
arrays, one step at a time.

The Python face of the library's ``Problem`` (tensor Bézier patches),
``BSplineProblem`` and ``TriProblem`` (triangular Bézier surfaces over a
mesh, Veltkamp & Wesselink): the same vocabulary — a control net whose NaN points are
free, fixed rings, the energy terms of Wu & Yang (stretch, bend, a normal
field, a guide surface), Veltkamp & Wesselink's constraints and operators,
Monterde & Ugail's constructions — written into the scene that ``fairsurf
solve`` reads. It holds no math: the Rust library validates and solves the
scene, and a mistake is a :class:`SceneError` naming the scene's JSON path.
"""

from __future__ import annotations

import copy
import json
from typing import Any, Dict, Iterator, Mapping, Optional, Sequence, Tuple

import numpy as np

from ._errors import SceneError


def _net(points: Any, what: str, least: int = 1) -> np.ndarray:
    """A control net as an (n + 1, m + 1, 3) float array with n, m >= least
    (a surface's degree is at least 1, a field's at least 0), or a
    SceneError."""
    a = np.array(points, dtype=float)  # a copy: the caller's array may change
    if a.ndim != 3 or a.shape[2] != 3 or min(a.shape[:2]) < least + 1:
        err = SceneError(
            f"{what}: a control net is an array of shape (n + 1, m + 1, 3) with n, m >= {least}, "
            f"not {a.shape}"
        )
        err.path = what
        raise err
    return a


class _Scene(Mapping[str, Any]):
    """A scene dict that every step copies: the shared half of the builders."""

    _scene: Dict[str, Any]

    # The mapping: the scene as a dict (copies: a builder does not change).
    def __getitem__(self, key: str) -> Any:
        return copy.deepcopy(self._scene[key])

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, type(self)):
            return NotImplemented
        try:
            return self.to_json() == other.to_json()
        except SceneError:  # a value JSON cannot hold (NaN weight): unequal, as NaN is
            return False

    __hash__ = None  # type: ignore[assignment]

    def __iter__(self) -> Iterator[str]:
        return iter(self._scene)

    def __len__(self) -> int:
        return len(self._scene)

    def _with(self, edit: Any) -> Any:
        new = copy.copy(self)
        new._scene = copy.deepcopy(self._scene)
        edit(new._scene)
        return new

    def _energy(self, key: str, value: Any) -> Any:
        def edit(s: Dict[str, Any]) -> None:
            s.setdefault("energy", {})[key] = value

        return self._with(edit)

    def _append(self, key: str, kind: str, fields: Mapping[str, Any]) -> Any:
        item = {"type": str(kind), **copy.deepcopy(dict(fields))}

        def edit(s: Dict[str, Any]) -> None:
            s.setdefault(key, []).append(item)

        return self._with(edit)

    @property
    def scene(self) -> Dict[str, Any]:
        """A copy of the scene as a dict (numpy arrays inside)."""
        return copy.deepcopy(self._scene)

    def stretch(self, weight: float) -> Any:
        """The membrane term with this weight (Wu & Yang eq. 3; Veltkamp &
        Wesselink eq. 6 on triangular surfaces)."""
        return self._energy("stretch", float(weight))

    def bend(self, weight: float) -> Any:
        """The thin-plate term with this weight (Wu & Yang eq. 4; Veltkamp &
        Wesselink eq. 7 on triangular surfaces)."""
        return self._energy("bend", float(weight))

    def constraint(self, kind: str, **fields: Any) -> Any:
        """Adds a constraint (Veltkamp & Wesselink §4.1) held exactly:
        ``kind`` is ``"point"`` (``target``), ``"normal"`` (``normal``),
        ``"in_plane"`` (``normal``, ``offset``), ``"on_line"`` (``point``,
        ``direction``), each ``at=`` a point of the domain — ``{"uv": [u,
        v]}`` on a Bézier patch ([0, 1]²) or a B-spline (its knot domain),
        ``{"triangle": t, "bary": [a, b, c]}`` on a triangular surface, which
        also takes ``"fixed"`` and ``"curve"`` constraints; optional
        ``name``."""
        return self._append("constraints", kind, fields)

    def operator(self, kind: str, **fields: Any) -> Any:
        """Adds an external energy operator (Veltkamp & Wesselink §5):
        ``kind`` is e.g. ``"point_attractor"``, ``"director"``,
        ``"plane_attractor"``, with ``strength`` and the fields the scene
        format names (``fairsurf.schema()``); on a B-spline, places lie in
        the knot domain and an edge's curve over the edge's parameter
        interval mapped onto [0, 1]."""
        return self._append("operators", kind, fields)

    def to_json(self) -> str:
        """The scene as JSON text (free points as ``null``)."""
        from . import _scene_text

        return json.dumps(json.loads(_scene_text(self)), indent=1)

    def solve(self, max_memory_gb: float = 8.0) -> Any:
        """:func:`fairsurf.solve` of this scene."""
        from . import solve

        return solve(self, max_memory_gb=max_memory_gb)


class Problem(_Scene):
    """A tensor (Bézier) or B-spline scene, built step by step.

    ``control_points`` is an array of shape (n + 1, m + 1, 3); a point of
    three NaNs is free (the solve finds it), every other point is kept
    unless a method frees it. With ``knots`` = (U, V) (full clamped knot
    vectors) the surface is a B-spline of the degrees those imply (or
    ``degree``), else one Bézier patch of degree (n, m).

    Every method returns a new Problem and leaves this one as it is, so a
    base serves a whole sweep::

        base = fairsurf.Problem(net).fix_rings(2).bend(1.0)
        runs = fairsurf.solve_many([base.normal_field(lam, field) for lam in (10, 100, 500)])

    A Problem is a mapping (the scene's dict), so every function that takes
    a scene takes it: :func:`fairsurf.solve`, :func:`fairsurf.solve_many`,
    :func:`fairsurf.analyse`, :func:`fairsurf.compare`.
    """

    def __init__(
        self,
        control_points: Any,
        *,
        knots: Optional[Tuple[Sequence[float], Sequence[float]]] = None,
        degree: Optional[Tuple[int, int]] = None,
        name: Optional[str] = None,
    ) -> None:
        net = _net(control_points, "surface.control_points")
        n, m = net.shape[0] - 1, net.shape[1] - 1
        surface: Dict[str, Any] = {"type": "tensor", "degree": [n, m], "control_points": net}
        if knots is not None:
            u, v = (np.asarray(k, dtype=float) for k in knots)
            p, q = degree if degree is not None else (len(u) - n - 2, len(v) - m - 2)
            surface = {
                "type": "bspline",
                "degree": [int(p), int(q)],
                "knots": [u, v],
                "control_points": net,
            }
        elif degree is not None and tuple(degree) != (n, m):
            err = SceneError(
                f"surface.degree: a Bézier patch of {n + 1} x {m + 1} points has degree "
                f"({n}, {m}), not {tuple(degree)} (give knots for a B-spline)"
            )
            err.path = "surface.degree"
            raise err
        self._scene: Dict[str, Any] = {"surface": surface}
        if name is not None:
            self._scene["name"] = name

    def __repr__(self) -> str:
        s = self._scene["surface"]
        parts = [f"{s['type']} {tuple(s['degree'])}"]
        parts += [k for k in ("fixed_rings", "energy", "constraints", "operators", "method")
                  if k in self._scene]
        return f"<fairsurf.Problem {', '.join(parts)}>"

    def fix_rings(self, rings: int) -> "Problem":
        """Keeps the ``rings`` outer rings of control points (1: the
        boundary; 2: boundary and cross-boundary tangents, G1), frees the
        rest."""
        return self._with(lambda s: s.__setitem__("fixed_rings", int(rings)))

    def free_points(self, indices: Sequence[Tuple[int, int]]) -> "Problem":
        """Frees the control points (i, j) listed, on top of the NaN points
        and of those freed before."""
        pairs = [[int(i), int(j)] for i, j in indices]

        def edit(s: Dict[str, Any]) -> None:
            have = s.setdefault("free_points", [])
            have.extend(p for p in pairs if p not in have)

        return self._with(edit)

    def normal_field(
        self,
        weight: float,
        control_points: Any,
        *,
        knots: Optional[Tuple[Sequence[float], Sequence[float]]] = None,
    ) -> "Problem":
        """Wu & Yang's normal-field term λ ∫ (R_u·N)² + (R_v·N)² (eq. 5–6)
        with λ = ``weight`` and N the Bézier field of ``control_points``
        ((a + 1, b + 1, 3); the field's own degree) — on a B-spline problem
        over the knot domain mapped onto [0, 1]², or with ``knots`` = (U, V)
        a B-spline field on its own knots over the knot domain (degrees
        from the counts)."""
        net = _net(control_points, "energy.normal_field.control_points", least=0)
        block: Dict[str, Any] = {"weight": float(weight), "control_points": net}
        if knots is None:
            block["degree"] = [net.shape[0] - 1, net.shape[1] - 1]
        else:
            block["knots"] = [np.asarray(k, dtype=float) for k in knots]
        return self._energy("normal_field", block)

    def guide(
        self,
        weight: float,
        control_points: Any = None,
        *,
        knots: Optional[Tuple[Sequence[float], Sequence[float]]] = None,
        bezier: bool = False,
    ) -> "Problem":
        """Wu & Yang's guide term γ ∫ |R − S|² (eq. 7) with γ = ``weight``
        and S the surface of ``control_points`` — for a Bézier problem a net
        of any degree; for a B-spline one a net on the surface's knots, or
        S's own B-spline with ``knots`` = (U, V), or with ``bezier=True`` a
        Bézier patch of any degree over the knot domain — or, by default,
        the initial surface (the net as given)."""
        block: Dict[str, Any] = {"weight": float(weight)}
        if control_points is None and (knots is not None or bezier):
            err = SceneError(
                "energy.guide_surface.control_points: required with knots or bezier=True "
                "(the guide's own net)"
            )
            err.path = "energy.guide_surface.control_points"
            raise err
        if control_points is not None:
            net = _net(control_points, "energy.guide_surface.control_points", least=0)
            block["control_points"] = net
            if self._scene["surface"]["type"] == "tensor" or bezier:
                block["degree"] = [net.shape[0] - 1, net.shape[1] - 1]
            if knots is not None:
                block["knots"] = [np.asarray(k, dtype=float) for k in knots]
        return self._energy("guide_surface", block)

    def refine(self, **fields: Any) -> "Problem":
        """Exact refinement of a B-spline problem before the solve (the
        scene's ``refine``: ``elevate``, ``u``, ``v``, ``split``)."""
        self._only("bspline", "refine")
        return self._with(lambda s: s.__setitem__("refine", copy.deepcopy(dict(fields))))

    def method(self, name: str) -> "Problem":
        """A construction instead of the energy (Bézier problems):
        ``"harmonic"``, ``"biharmonic"``, ``"harmonic_mask"``,
        ``"biharmonic_mask"`` (Monterde & Ugail 2004), or ``"minimize"``
        (the energy; the default)."""
        self._only("tensor", "method")
        return self._with(lambda s: s.__setitem__("method", str(name)))

    def least_squares(self, on: bool = True) -> "Problem":
        """Solve an inconsistent construction in the least-squares sense
        instead of refusing it (Bézier problems)."""
        self._only("tensor", "least_squares")
        return self._with(lambda s: s.__setitem__("least_squares", bool(on)))

    def _only(self, kind: str, key: str) -> None:
        """A SceneError naming `key` unless the surface is of `kind`."""
        have = self._scene["surface"]["type"]
        if have != kind:
            name = {"tensor": "Bézier", "bspline": "B-spline"}
            err = SceneError(
                f"{key}: a {name[have]} problem has no {key} (only {name[kind]} problems do)"
            )
            err.path = key
            raise err


class TriProblem(_Scene):
    """A triangular scene (Veltkamp & Wesselink): Bézier triangles of
    ``degree`` over the mesh of ``vertices`` ((V, 3)) and ``triangles``
    ((T, 3) vertex indices, counter-clockwise), built step by step like
    :class:`Problem`. ``control_points`` ((N, 3), the global net in the
    library's order) starts the surface elsewhere than on the flat
    triangles. The boundary is fixed and the patches meet with exact G1
    unless :meth:`fix_boundary` and :meth:`continuity` say otherwise.
    """

    def __init__(
        self,
        vertices: Any,
        triangles: Any,
        degree: int,
        *,
        control_points: Any = None,
        name: Optional[str] = None,
    ) -> None:
        v = np.array(vertices, dtype=float)  # copies: the caller's arrays may change
        t = np.array(triangles)
        for a, cols, what in ((v, 3, "vertices"), (t, 3, "triangles")):
            if a.ndim != 2 or a.shape[1] != cols:
                err = SceneError(f"surface.{what}: expected an array of shape (N, 3), not {a.shape}")
                err.path = f"surface.{what}"
                raise err
        if t.dtype.kind not in "iu":
            err = SceneError(f"surface.triangles: expected integer vertex indices, not {t.dtype}")
            err.path = "surface.triangles"
            raise err
        surface: Dict[str, Any] = {"type": "triangular", "degree": int(degree),
                                   "vertices": v, "triangles": t.astype(np.int64)}
        if control_points is not None:
            surface["control_points"] = np.array(control_points, dtype=float)
        self._scene = {"surface": surface}
        if name is not None:
            self._scene["name"] = name

    def __repr__(self) -> str:
        s = self._scene["surface"]
        parts = [f"triangular degree {s['degree']}, {len(s['triangles'])} patches"]
        parts += [k for k in ("energy", "continuity", "constraints", "operators")
                  if k in self._scene]
        return f"<fairsurf.TriProblem {', '.join(parts)}>"

    def fix_boundary(self, on: bool = True) -> "TriProblem":
        """Keeps the boundary curves' control points (the default) or frees
        them."""
        return self._with(lambda s: s.__setitem__("fix_boundary", bool(on)))

    def continuity(self, **fields: Any) -> "TriProblem":
        """The continuity between patches (the scene's ``continuity``):
        ``edges`` (``"exact"``, ``"relaxed"``, ``"off"``), ``vertices`` (G1 at
        the vertices), ``boundary_angles``; fields not given keep their
        earlier value or default."""
        def edit(s: Dict[str, Any]) -> None:
            s.setdefault("continuity", {}).update(copy.deepcopy(dict(fields)))

        return self._with(edit)

