"""`fairsurf.Problem`: a scene built from numpy arrays, one step at a time.

The Python face of the library's ``Problem`` (tensor Bézier patches) and
``BSplineProblem``: the same vocabulary — a control net whose NaN points are
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
    a = np.asarray(points, dtype=float)
    if a.ndim != 3 or a.shape[2] != 3 or min(a.shape[:2]) < least + 1:
        err = SceneError(
            f"{what}: a control net is an array of shape (n + 1, m + 1, 3) with n, m >= {least}, "
            f"not {a.shape}"
        )
        err.path = what
        raise err
    return a


class Problem(Mapping[str, Any]):
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

    # The mapping: the scene as a dict (copies: a Problem does not change).
    def __getitem__(self, key: str) -> Any:
        return copy.deepcopy(self._scene[key])

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Problem):
            return NotImplemented
        return self.to_json() == other.to_json()

    __hash__ = None  # type: ignore[assignment]

    def __iter__(self) -> Iterator[str]:
        return iter(self._scene)

    def __len__(self) -> int:
        return len(self._scene)

    def __repr__(self) -> str:
        s = self._scene["surface"]
        parts = [f"{s['type']} {tuple(s['degree'])}"]
        parts += [k for k in ("fixed_rings", "energy", "constraints", "operators", "method")
                  if k in self._scene]
        return f"<fairsurf.Problem {', '.join(parts)}>"

    def _with(self, edit: Any) -> "Problem":
        new = copy.copy(self)
        new._scene = copy.deepcopy(self._scene)
        edit(new._scene)
        return new

    def _energy(self, key: str, value: Any) -> "Problem":
        def edit(s: Dict[str, Any]) -> None:
            s.setdefault("energy", {})[key] = value

        return self._with(edit)

    @property
    def scene(self) -> Dict[str, Any]:
        """A copy of the scene as a dict (numpy arrays inside)."""
        return copy.deepcopy(self._scene)

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

    def stretch(self, weight: float) -> "Problem":
        """The membrane term ∫ |R_u|² + |R_v|² (Wu & Yang eq. 3) with this weight."""
        return self._energy("stretch", float(weight))

    def bend(self, weight: float) -> "Problem":
        """The thin-plate term ∫ |R_uu|² + 2|R_uv|² + |R_vv|² (Wu & Yang eq. 4)."""
        return self._energy("bend", float(weight))

    def normal_field(self, weight: float, control_points: Any) -> "Problem":
        """Wu & Yang's normal-field term λ ∫ (R_u·N)² + (R_v·N)² (eq. 5–6)
        with λ = ``weight`` and N the Bézier field of ``control_points``
        ((a + 1, b + 1, 3); the field's own degree)."""
        net = _net(control_points, "energy.normal_field.control_points", least=0)
        return self._energy("normal_field", {
            "weight": float(weight),
            "degree": [net.shape[0] - 1, net.shape[1] - 1],
            "control_points": net,
        })

    def guide(self, weight: float, control_points: Any = None) -> "Problem":
        """Wu & Yang's guide term γ ∫ |R − S|² (eq. 7) with γ = ``weight``
        and S the surface of ``control_points`` — for a Bézier problem a net
        of any degree, for a B-spline one a net on the surface's knots —
        or, by default, the initial surface (the net as given)."""
        block: Dict[str, Any] = {"weight": float(weight)}
        if control_points is not None:
            net = _net(control_points, "energy.guide_surface.control_points", least=0)
            block["control_points"] = net
            if self._scene["surface"]["type"] == "tensor":
                block["degree"] = [net.shape[0] - 1, net.shape[1] - 1]
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

    def constraint(self, kind: str, **fields: Any) -> "Problem":
        """Adds a constraint (Veltkamp & Wesselink §4.1) held exactly:
        ``kind`` is ``"point"`` (``target``), ``"normal"`` (``normal``),
        ``"in_plane"`` (``normal``, ``offset``), ``"on_line"`` (``point``,
        ``direction``), each ``at={"uv": [u, v]}`` ((u, v) in [0, 1]² on a
        Bézier patch, in the knot domain on a B-spline); optional ``name``."""
        return self._append("constraints", kind, fields)

    def operator(self, kind: str, **fields: Any) -> "Problem":
        """Adds an external energy operator (Veltkamp & Wesselink §5):
        ``kind`` is e.g. ``"point_attractor"``, ``"director"``,
        ``"plane_attractor"``, with ``strength`` and the fields the scene
        format names (``fairsurf.schema()``); on a B-spline, places lie in
        the knot domain, and repellors and edges are refused."""
        return self._append("operators", kind, fields)

    def _append(self, key: str, kind: str, fields: Mapping[str, Any]) -> "Problem":
        item = {"type": str(kind), **copy.deepcopy(dict(fields))}

        def edit(s: Dict[str, Any]) -> None:
            s.setdefault(key, []).append(item)

        return self._with(edit)

    def to_json(self) -> str:
        """The scene as JSON text (free points as ``null``)."""
        from . import _scene_text

        return json.dumps(json.loads(_scene_text(self)), indent=1)

    def solve(self, max_memory_gb: float = 8.0) -> Any:
        """:func:`fairsurf.solve` of this scene."""
        from . import solve

        return solve(self, max_memory_gb=max_memory_gb)
