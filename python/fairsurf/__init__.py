"""fairsurf: fair surfaces by energy minimization, from Python.

The Rust library does the work; this module hands it scenes and gives back
numpy arrays. A scene is what ``fairsurf solve`` reads: a path to a JSON
file, the JSON text, or a dict (numpy arrays inside are fine; in a control
net, a point of three NaNs is a free point, as ``null`` is in the file).

>>> import fairsurf
>>> r = fairsurf.solve("examples/wu_yang_fig4_l500.json")   # doctest: +SKIP
>>> r.control_points.shape                                   # doctest: +SKIP
(6, 6, 3)
>>> r.report["energy"]                                       # doctest: +SKIP

A scene can also be built from numpy arrays with :class:`Problem`
(``fairsurf.Problem(net).fix_rings(2).bend(1).solve()``).

Every solve, evaluation, mesh, export and picture releases the GIL, so
Python threads overlap; :func:`solve_many` spreads scenes over threads.
Errors are exceptions: :class:`SceneError` (a ``ValueError`` whose ``path``
names the JSON path), :class:`SolveError` and :class:`UnverifiedError` for
refusals, ``OSError`` for files.
"""

from __future__ import annotations

import json
import math
import os
import re
import warnings
from pathlib import Path
from typing import Any, Dict, List, Mapping, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import _fairsurf
from ._errors import ExportError, FairsurfError, SceneError, SolveError, UnverifiedError
from ._problem import Problem, TriProblem

__all__ = [
    "Problem",
    "TriProblem",
    "solve",
    "solve_many",
    "load",
    "analyse",
    "compare",
    "schema",
    "fill",
    "Filled",
    "blend",
    "Blended",
    "Result",
    "Surface",
    "Mesh",
    "Curvatures",
    "FairsurfError",
    "SceneError",
    "SolveError",
    "UnverifiedError",
    "ExportError",
    "SceneLike",
]

__version__: str = _fairsurf.__version__

#: What the functions take as a scene: a path, JSON text or a dict.
SceneLike = Union[str, "os.PathLike[str]", Mapping[str, Any]]


def _nan_point(x: Any) -> bool:
    """Whether x is a point of three NaNs (a free point)."""
    return (
        isinstance(x, (list, tuple, np.ndarray))
        and len(x) == 3
        and all(isinstance(c, (float, np.floating)) and math.isnan(c) for c in x)
    )


def _plain(x: Any, path: str = "") -> Any:
    """numpy values as JSON values; a point of three NaNs as null; any other
    NaN or infinity a SceneError naming its JSON path."""
    if _nan_point(x):
        return None
    if isinstance(x, np.ndarray):
        if x.ndim == 0:
            return _plain(x.item(), path)
        return [_plain(v, f"{path}[{i}]") for i, v in enumerate(x)]
    if isinstance(x, np.generic):
        return _plain(x.item(), path)
    if isinstance(x, Mapping):
        return {k: _plain(v, f"{path}.{k}" if path else str(k)) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v, f"{path}[{i}]") for i, v in enumerate(x)]
    if isinstance(x, float) and not math.isfinite(x):
        err = SceneError(
            f"{path or 'scene'}: {x} is not a number JSON can hold (only a point of three "
            "NaNs means a free point)"
        )
        err.path = path
        raise err
    return x


def _scene_text(scene: SceneLike) -> str:
    """The JSON text of a scene given as a path, text or dict."""
    if isinstance(scene, Mapping):
        plain = _plain(scene)
        try:
            return json.dumps(plain, allow_nan=False)
        except TypeError as e:
            err = SceneError(f"scene: cannot be written as JSON: {e}")
            err.path = ""
            raise err from None
    if isinstance(scene, os.PathLike):
        return Path(scene).read_text(encoding="utf-8")
    if isinstance(scene, str):
        if scene.lstrip().startswith("{"):
            return scene
        return Path(scene).read_text(encoding="utf-8")
    raise TypeError(
        f"a scene is a path, JSON text or a dict, not {type(scene).__name__}"
    )


_POSITION = re.compile(r" at line \d+ column \d+")


def _located(err: BaseException, scene: SceneLike) -> BaseException:
    """A scene error told where the user can look: a file's name in front,
    and for a dict no line and column of the JSON text made from it."""
    if not isinstance(err, SceneError) or not err.args:
        return err
    message = str(err.args[0])
    if isinstance(scene, Mapping):
        message = _POSITION.sub("", message)
    elif isinstance(scene, os.PathLike) or (
        isinstance(scene, str) and not scene.lstrip().startswith("{")
    ):
        message = f"{os.fspath(scene)}: {message}"
    err.args = (message,) + tuple(err.args[1:])
    return err


def _call(fn: Any, scene: SceneLike, *args: Any) -> Any:
    """fn(the scene's text, *args), its SceneError located."""
    text = _scene_text(scene)
    try:
        return fn(text, *args)
    except SceneError as e:
        raise _located(e, scene) from None


class Curvatures(NamedTuple):
    """Curvatures at parameter points (arrays of the parameters' shape; NaN
    where the surface is singular)."""

    gaussian: np.ndarray
    mean: np.ndarray
    k1: np.ndarray
    k2: np.ndarray


class Mesh(NamedTuple):
    """A triangle mesh of a surface with the curvature at every vertex."""

    vertices: np.ndarray
    """(V, 3) float64 positions."""
    faces: np.ndarray
    """(F, 3) uint32 vertex indices, counter-clockwise about the normal."""
    normals: np.ndarray
    """(V, 3) float64 unit normals."""
    uvs: np.ndarray
    """(V, 2) float64 parameters of each vertex: in [0, 1]² as
    :meth:`Surface.evaluate` takes them for a tensor or B-spline surface (a
    B-spline's knot domain mapped); within its own patch for a triangular
    surface."""
    mean_curvature: np.ndarray
    """(V,) float64 mean curvature H (NaN where singular)."""
    gaussian_curvature: np.ndarray
    """(V,) float64 Gaussian curvature K (NaN where singular)."""
    patches: Optional[np.ndarray] = None
    """(V,) int64: the patch of each vertex of a triangular surface (with
    :attr:`uvs`, what :meth:`Surface.evaluate` takes); None otherwise."""


def _parameters(u: Any, v: Any) -> Tuple[Tuple[int, ...], np.ndarray, np.ndarray]:
    ub, vb = np.broadcast_arrays(np.asarray(u, dtype=np.float64), np.asarray(v, dtype=np.float64))
    return ub.shape, np.ascontiguousarray(ub.ravel()), np.ascontiguousarray(vb.ravel())


class Surface:
    """A surface of any kind: tensor (one Bézier patch), triangular (Bézier
    triangles over a mesh) or bspline."""

    def __init__(self, native: Any) -> None:
        self._native = native

    def __repr__(self) -> str:
        n, m = self.degree
        return f"<fairsurf.Surface {self.surface_type} degree {n}×{m}>"

    def __reduce__(self) -> Any:
        # A surface pickles as the scene that gives it, every control point
        # given (floats round-trip exactly).
        return (_surface_from_text, (self._native.scene_text(),))

    @property
    def surface_type(self) -> str:
        """``"tensor"``, ``"triangular"`` or ``"bspline"``."""
        return self._native.surface_type

    @property
    def degree(self) -> Tuple[int, int]:
        """(n, m); (n, n) for a triangular surface."""
        return self._native.degree

    @property
    def control_points(self) -> np.ndarray:
        """(n+1, m+1, 3) for a tensor patch, (count_u, count_v, 3) for a
        B-spline surface, (N, 3) for a triangular surface (see
        :attr:`patch_indices`). float64, C order."""
        return self._native.control_points

    @property
    def knots(self) -> Optional[Tuple[np.ndarray, np.ndarray]]:
        """The full knot vectors (U, V) of a B-spline surface, else None."""
        return self._native.knots

    @property
    def patch_indices(self) -> Optional[np.ndarray]:
        """For a triangular surface, each patch's indices into
        :attr:`control_points`, shape (patches, (n+1)(n+2)/2), uint64."""
        return self._native.patch_indices

    def tensor_patches(self) -> List[np.ndarray]:
        """The surface as tensor Bézier patches, each (n+1, m+1, 3): the
        patch itself, a B-spline surface's Bézier pieces, or a triangular
        surface's patches as exact tensor patches with one side collapsed."""
        return self._native.tensor_patches()

    def derivatives(self, u: Any, v: Any, patch: Any = None) -> Dict[str, np.ndarray]:
        """Points, first and second derivatives, normals and curvatures at
        (u, v) ∈ [0, 1]² (broadcast; a B-spline surface's knot domain is
        mapped onto [0, 1]²). On a triangular surface, at the barycentric
        point (u, v, 1 − u − v) of patch ``patch`` (broadcast with u and v;
        u + v ≤ 1), the derivatives along its first two barycentric
        directions. Keys: points, du, dv, duu, duv, dvv, normals (shape +
        (3,)); gaussian, mean, k1, k2 (shape). The arrays are built in Rust
        and handed to numpy as they are (numpy makes no copy)."""
        if patch is None:
            shape, uf, vf = _parameters(u, v)
            out = self._native._evaluate(uf, vf)
        else:
            k = np.asarray(patch)
            if k.dtype.kind not in "iu":
                raise ValueError(f"patch: expected integer patch indices, got dtype {k.dtype}")
            ub, vb, kb = np.broadcast_arrays(np.asarray(u, dtype=np.float64),
                                             np.asarray(v, dtype=np.float64),
                                             k.astype(np.int64))
            shape = ub.shape
            out = self._native._evaluate(np.ascontiguousarray(ub.ravel()),
                                         np.ascontiguousarray(vb.ravel()),
                                         np.ascontiguousarray(kb.ravel()))
        return {
            k: a.reshape(shape + ((3,) if a.ndim == 2 else ())) for k, a in out.items()
        }

    def evaluate(self, u: Any, v: Any, patch: Any = None) -> np.ndarray:
        """Points R(u, v), shape broadcast(u, v) + (3,) (``patch``: see
        :meth:`derivatives`)."""
        return self.derivatives(u, v, patch)["points"]

    def normals(self, u: Any, v: Any, patch: Any = None) -> np.ndarray:
        """Unit normals R_u × R_v / |R_u × R_v| (NaN where singular)."""
        return self.derivatives(u, v, patch)["normals"]

    def curvatures(self, u: Any, v: Any, patch: Any = None) -> Curvatures:
        """Gaussian, mean and principal curvatures (κ₁ ≥ κ₂)."""
        d = self.derivatives(u, v, patch)
        return Curvatures(d["gaussian"], d["mean"], d["k1"], d["k2"])

    def mesh(self, resolution: int = 64) -> Mesh:
        """A triangle mesh: ``resolution`` quads per direction of a tensor or
        B-spline surface, ⌈resolution/4⌉ subdivisions per triangular patch."""
        return Mesh(**self._native._mesh(resolution))

    def export(
        self,
        path: Union[str, "os.PathLike[str]"],
        resolution: int = 64,
        colour_range: Optional[Tuple[float, float]] = None,
    ) -> str:
        """Writes the surface in the format the extension names: .step/.stp
        (AP214 B-spline faces), .igs/.iges (entity 128), .obj, .ply (with
        curvature), .stl, .glb/.gltf (|H| colours in ``colour_range``).
        Returns what was written; warns (``UserWarning``) about a degree that
        Open CASCADE-based readers drop."""
        rng = None if colour_range is None else (float(colour_range[0]), float(colour_range[1]))
        summary, warning = self._native.export(os.fspath(path), resolution, rng)
        if warning:
            warnings.warn(warning, stacklevel=2)
        return summary

    def render(
        self,
        path: Union[str, "os.PathLike[str]", None] = None,
        **options: Any,
    ) -> bytes:
        """A PNG picture as ``fairsurf render`` draws it (options: width,
        height, colour, range, view, net, boundary, zebra, isophotes,
        resolution, colour_bar). Returns the PNG bytes; also writes them to
        ``path`` when given."""
        png: bytes = self._native.render(**options)
        if path is not None:
            Path(path).write_bytes(png)
        return png


class Result(Surface):
    """A solved scene: the surface (every :class:`Surface` method), its
    report and the result file. Results pickle (as their result file's
    text), so they cross process boundaries: multiprocessing, Dask, Ray."""

    def __init__(
        self,
        surface: Any,
        result_text: Optional[str],
        report_json: Optional[str],
        solved: Any = None,
    ) -> None:
        super().__init__(surface)
        # The result file's text and the report are written from the native
        # solution when first asked for (a solve's caller may want neither).
        self._solved = solved
        self._text_cache = result_text
        self._report_json_cache = report_json
        self._report: Optional[Dict[str, Any]] = None

    @classmethod
    def _of(cls, solved: Any) -> "Result":
        return cls(solved.surface, None, None, solved)

    @property
    def _text(self) -> str:
        if self._text_cache is None:
            self._text_cache = self._solved.to_json()
        return self._text_cache

    @property
    def _report_json(self) -> str:
        if self._report_json_cache is None:
            self._report_json_cache = self._solved.report_json()
        return self._report_json_cache

    def __reduce__(self) -> Any:
        return (_result_from_text, (self._text, self._report_json))

    def __repr__(self) -> str:
        n, m = self.degree
        energy = self.report.get("energy")
        return f"<fairsurf.Result {self.surface_type} degree {n}×{m} energy {energy}>"

    @property
    def surface(self) -> Surface:
        """The solved surface alone."""
        return Surface(self._native)

    @property
    def report(self) -> Dict[str, Any]:
        """The report, as in the result file: energy and its terms,
        gradient_norm, residual, check, timings_s, measures, notes…"""
        if self._report is None:
            self._report = json.loads(self._report_json)
        return self._report

    def to_json(self) -> str:
        """The result file's text (it solves again to the same surface)."""
        return self._text

    def write(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes the result file (atomically: nothing is left on an error)."""
        _fairsurf.write_text(os.fspath(path), self._text)


def _surface_from_text(text: str) -> Surface:
    """A surface again from the scene text it pickled as."""
    return Surface(_fairsurf.load(text))


def _result_from_text(text: str, report_json: str) -> Result:
    """A result again from its result file's text (unpickling): the surface
    read back exactly (floats are written to round-trip)."""
    return Result(_fairsurf.load(text), text, report_json)


def solve(scene: SceneLike, max_memory_gb: float = 8.0) -> Result:
    """Validates and solves a scene (see the module docs for what a scene
    may be). Raises :class:`SceneError` naming the JSON path of a bad value,
    :class:`SolveError` / :class:`UnverifiedError` when the solver refuses
    (also when the solve's estimated memory exceeds ``max_memory_gb``)."""
    return Result._of(_call(_fairsurf.solve, scene, max_memory_gb))


def solve_many(
    scenes: Sequence[SceneLike],
    threads: Optional[int] = None,
    return_exceptions: bool = False,
    max_memory_gb: float = 8.0,
) -> List[Any]:
    """Solves many scenes on ``threads`` threads (default: the CPU count),
    in order. An error raises the first scene's exception, unless
    ``return_exceptions``: then its place in the list holds it. Each solve
    has its own memory budget of ``max_memory_gb``."""
    texts: List[str] = []
    failed: Dict[int, BaseException] = {}
    for k, scene in enumerate(scenes):
        try:
            texts.append(_scene_text(scene))
        except Exception as e:  # a missing file, a dict JSON cannot hold
            if not return_exceptions:
                raise
            failed[k] = e
    n = threads if threads is not None else (os.cpu_count() or 1)
    solved = iter(_fairsurf.solve_many(texts, n, max_memory_gb))
    results: List[Any] = []
    for k in range(len(scenes)):
        r = failed[k] if k in failed else next(solved)
        if isinstance(r, BaseException):
            r = _located(r, scenes[k])
            if not return_exceptions:
                raise r
            results.append(r)
        else:
            results.append(Result._of(r))
    return results


def load(scene: SceneLike) -> Surface:
    """The surface a scene gives as it is, without solving: a result file,
    or a scene whose control points are all given."""
    return Surface(_call(_fairsurf.load, scene))


def analyse(scene: SceneLike) -> Dict[str, Any]:
    """Measures of the surface a scene gives (area, functionals, curvature,
    normal turn…), as ``fairsurf analyse --json`` prints them."""
    return json.loads(_call(_fairsurf.analyse, scene))


def compare(scene: SceneLike) -> Dict[str, Any]:
    """Monterde & Ugail's comparison for a tensor scene's boundary: the
    harmonic and biharmonic surfaces and the two masks with their area,
    functionals and curvature (``fairsurf compare --json``)."""
    return json.loads(_call(_fairsurf.compare, scene))


class Filled:
    """Holes filled between faces (:func:`fill`): the input ``faces``, the
    ``fills`` (:class:`Surface` objects, one per filled hole: B-spline for a
    4-sided hole, triangular (a fan around a centre) otherwise; G1 to
    their neighbours) and the ``report`` (``fairsurf fill --json``).
    A rational face of a STEP file (a cylinder, a cone, a NURBS face) is
    in ``faces`` as its polynomial stand-in (``report["stand_ins"]`` says
    how far it is from the face; the fill's sides along it are measured
    against the face itself and have ``"exact": False``); :meth:`write`
    writes the rational face itself."""

    def __init__(self, native: Any) -> None:
        self._native = native
        self.faces: List[Surface] = [Surface(f) for f in native.faces()]
        self.fills: List[Surface] = [Surface(f) for f in native.fills()]
        self.report: Dict[str, Any] = json.loads(native.report_json())

    def __repr__(self) -> str:
        return f"<fairsurf.Filled {len(self.faces)} faces, {len(self.fills)} fills>"

    def write(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes the faces and the fills as one sewn STEP shell."""
        self._native.write_step(os.fspath(path))


def fill(
    faces: SceneLike,
    holes: Optional[Sequence[int]] = None,
    *,
    normal_weight: Optional[float] = None,
    elevate: Optional[int] = None,
    willmore_steps: Optional[int] = None,
    descent_steps: Optional[int] = None,
) -> Filled:
    """Fills the holes between faces: ``faces`` is a STEP file's path
    (``.step``/``.stp``), or a JSON fill scene as a path, text or dict
    (``schema("fill")``). ``holes`` chooses holes by index (longest loop
    first; default: all but the outer rims — each open sheet's outline,
    and a pipe's ends; :class:`SolveError` when every loop is a rim, as in a
    file whose holes are all filled). ``normal_weight``, ``elevate``,
    ``willmore_steps`` and ``descent_steps`` (steps of L-BFGS on W itself;
    0 for none) override the scene's ``fill`` options (a ``normal_weight``
    given guides the thin plate before the descent too; by default the
    normal field guides it only when the descent is off). Raises :class:`SceneError` for
    bad input (with ``.path``), :class:`SolveError` for a hole that cannot be
    filled (e.g. an N-sided hole whose sides have interior knots). For Open CASCADE shapes see
    :func:`fairsurf.occ.fill_shape`."""
    step = isinstance(faces, (str, os.PathLike)) and not (
        isinstance(faces, str) and faces.lstrip().startswith("{")
    ) and Path(faces).suffix.lower() in (".step", ".stp")
    text = Path(faces).read_text(encoding="utf-8") if step else _scene_text(faces)
    try:
        native = _fairsurf.fill(
            text, step, None if holes is None else list(holes), normal_weight, elevate,
            willmore_steps, descent_steps,
        )
    except SceneError as e:
        raise _located(e, faces) from None
    return Filled(native)


class Blended:
    """A transition surface between two surfaces (:func:`blend`): the input
    ``faces``, the ``blend`` (a B-spline :class:`Surface`, G1 to both) and
    the ``report`` (``fairsurf blend --json``)."""

    def __init__(self, native: Any) -> None:
        self._native = native
        self.faces: List[Surface] = [Surface(f) for f in native.faces()]
        self.blend: Surface = Surface(native.blend())
        self.report: Dict[str, Any] = json.loads(native.report_json())

    def __repr__(self) -> str:
        return f"<fairsurf.Blended {len(self.faces)} faces and the blend>"

    def write(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes the faces and the blend as one sewn STEP shell."""
        self._native.write_step(os.fspath(path))


def blend(
    scene: SceneLike,
    *,
    bulge: Optional[Sequence[float]] = None,
    normal_weight: Optional[float] = None,
    elevate: Optional[int] = None,
    clamp_sides: Optional[bool] = None,
) -> Blended:
    """Blends two surfaces along one edge of each: ``scene`` is a JSON blend
    scene as a path, text or dict (``schema("blend")``); the STEP files it
    names are found next to the scene file (the working folder for text or
    a dict). ``bulge`` (two numbers > 0: the tangent lengths across,
    relative to the gap) and the other options override the scene's.
    Raises :class:`SceneError` for bad input (with ``.path``),
    :class:`SolveError` for edges that cannot be blended."""
    is_file = isinstance(scene, os.PathLike) or (
        isinstance(scene, str) and not scene.lstrip().startswith("{")
    )
    folder = Path(scene).resolve().parent if is_file else Path.cwd()
    pair = None if bulge is None else tuple(float(x) for x in bulge)
    if pair is not None and len(pair) != 2:
        raise ValueError(f"bulge {list(pair)}: expected two numbers (A, B)")
    native = _call(_fairsurf.blend, scene, os.fspath(folder), pair, normal_weight, elevate,
                   clamp_sides)
    return Blended(native)


def schema(kind: str = "tensor") -> Dict[str, Any]:
    """The JSON Schema of scenes of a kind: tensor, triangular or bspline;
    or of fill and blend scenes ("fill", "blend")."""
    return json.loads(_fairsurf.schema(kind))
