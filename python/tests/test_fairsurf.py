"""Facts about the Python module: it gives what the command line gives, in
arrays of the documented shapes; every error is the documented exception;
the GIL is released while Rust works."""

from __future__ import annotations

import json
import math
import os
import struct
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import fairsurf

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
TENSOR = EXAMPLES / "wu_yang_fig4_l500.json"
TRIANGULAR = EXAMPLES / "vw_pentagon_hole.json"
BSPLINE = EXAMPLES / "bspline_hole_guided.json"


def cli_result(cli: Path, scene: Path, tmp_path: Path) -> dict:
    out = tmp_path / (scene.stem + ".result.json")
    subprocess.run([str(cli), "solve", str(scene), "-o", str(out)], check=True,
                   capture_output=True)
    return json.loads(out.read_text())


def nets(scene: dict) -> np.ndarray:
    """A result file's control points as an array (None nowhere)."""
    return np.array(scene["surface"]["control_points"], dtype=np.float64)


@pytest.mark.parametrize("scene", [TENSOR, TRIANGULAR, BSPLINE], ids=lambda p: p.stem)
def test_results_equal_the_command_lines(cli: Path, scene: Path, tmp_path: Path) -> None:
    """The same scene solved here and by `fairsurf solve`: the same control
    points to the last bit, the same energy, and the result file's text
    solves again to the same surface."""
    theirs = cli_result(cli, scene, tmp_path)
    ours = fairsurf.solve(scene)
    np.testing.assert_array_equal(
        ours.control_points.reshape(-1, 3), nets(theirs).reshape(-1, 3)
    )
    assert ours.report["energy"] == theirs["report"]["energy"]
    check = ours.report["check"]
    assert check["energy_error"] <= check["tolerance"]
    assert check["excess"] <= check["tolerance"]
    mine = json.loads(ours.to_json())
    assert mine["surface"] == theirs["surface"]
    again = fairsurf.load(ours.to_json())
    np.testing.assert_array_equal(again.control_points, ours.control_points)


def test_scenes_come_as_paths_text_or_dicts_with_numpy_arrays() -> None:
    """A dict with a numpy control net whose free points are NaN solves to
    the file's answer, as do its path (str and Path) and its text."""
    text = TENSOR.read_text()
    data = json.loads(text)
    net = np.array(
        [[[math.nan] * 3 if p is None else p for p in row]
         for row in data["surface"]["control_points"]],
        dtype=np.float64,
    )
    data["surface"]["control_points"] = net
    data["surface"]["degree"] = np.array(data["surface"]["degree"], dtype=np.int64)
    expected = fairsurf.solve(TENSOR).control_points
    for scene in (str(TENSOR), text, data):
        np.testing.assert_array_equal(fairsurf.solve(scene).control_points, expected)


def test_arrays_have_the_documented_shapes_and_dtypes() -> None:
    t = fairsurf.solve(TENSOR)
    n, m = t.degree
    assert t.surface_type == "tensor"
    assert t.control_points.shape == (n + 1, m + 1, 3)
    assert t.control_points.dtype == np.float64 and t.control_points.flags.c_contiguous
    assert t.knots is None and t.patch_indices is None

    b = fairsurf.solve(BSPLINE)
    scene = json.loads(BSPLINE.read_text())["surface"]
    u, v = b.knots
    np.testing.assert_array_equal(u, scene["knots"][0])
    np.testing.assert_array_equal(v, scene["knots"][1])
    p, q = b.degree
    assert b.control_points.shape == (len(u) - p - 1, len(v) - q - 1, 3)

    tri = fairsurf.solve(TRIANGULAR)
    deg = tri.degree[0]
    idx = tri.patch_indices
    assert idx.shape == (len(json.loads(TRIANGULAR.read_text())["surface"]["triangles"]),
                         (deg + 1) * (deg + 2) // 2)
    assert tri.control_points.shape == (idx.max() + 1, 3)

    mesh = t.mesh(8)
    assert mesh.vertices.shape == (81, 3) and mesh.faces.shape == (128, 3)
    assert mesh.faces.dtype == np.uint32 and mesh.faces.max() == 80
    assert mesh.normals.shape == (81, 3) and mesh.uvs.shape == (81, 2)
    assert mesh.mean_curvature.shape == (81,) and mesh.gaussian_curvature.shape == (81,)
    np.testing.assert_allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, atol=1e-12)


def test_evaluation_broadcasts_and_matches_the_mesh() -> None:
    """evaluate(u, v) broadcasts like numpy; its points are the mesh's
    vertices at the same parameters; normals are unit and orthogonal to the
    derivatives; a B-spline's corners are its corner control points."""
    r = fairsurf.solve(TENSOR)
    us = np.linspace(0, 1, 5)
    vs = np.linspace(0, 1, 3)
    pts = r.evaluate(us[:, None], vs[None, :])
    assert pts.shape == (5, 3, 3)
    mesh = r.mesh(4)
    k = {tuple(np.round(uv, 12)): i for i, uv in enumerate(mesh.uvs)}
    for i, u in enumerate(us):
        for j, v in enumerate(vs[[0, 2]]):
            np.testing.assert_allclose(pts[i, 2 * j], mesh.vertices[k[(u, v)]], atol=1e-14)
    d = r.derivatives(0.3, 0.7)
    assert d["points"].shape == (3,) and d["mean"].shape == ()
    assert abs(np.linalg.norm(d["normals"]) - 1) < 1e-14
    assert abs(d["normals"] @ d["du"]) < 1e-12 and abs(d["normals"] @ d["dv"]) < 1e-12
    c = r.curvatures(0.3, 0.7)
    assert abs(c.k1 + c.k2 - 2 * c.mean) < 1e-12 and abs(c.k1 * c.k2 - c.gaussian) < 1e-9

    b = fairsurf.solve(BSPLINE)
    corners = b.evaluate([0, 0, 1, 1], [0, 1, 0, 1])
    cp = b.control_points
    np.testing.assert_allclose(corners, [cp[0, 0], cp[0, -1], cp[-1, 0], cp[-1, -1]], atol=1e-14)


def test_errors_are_exceptions_that_name_the_json_path(tmp_path: Path) -> None:
    data = json.loads(TENSOR.read_text())
    data["surface"]["degree"] = [7, "seven"]
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.solve(data)
    assert e.value.path == "surface.degree[1]" and str(e.value).startswith("surface.degree[1]:")
    assert " line " not in str(e.value)  # no position in JSON text the user never saw
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(data))
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.solve(bad)
    assert str(e.value).startswith(f"{bad}: surface.degree[1]:") and " line 1 " in str(e.value)
    assert isinstance(e.value, ValueError) and isinstance(e.value, fairsurf.FairsurfError)

    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.solve({"surface": {"type": "nurbs"}})
    assert e.value.path == "surface.type" and "nurbs" in str(e.value)

    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.solve('{"surface": ')
    assert e.value.path == "surface" and "EOF" in str(e.value)

    with pytest.raises(fairsurf.SceneError):
        fairsurf.solve({"surface": {"type": "tensor", "degree": [1, 1]}, "x": float("nan")})

    with pytest.raises(FileNotFoundError):
        fairsurf.solve(tmp_path / "missing.json")
    with pytest.raises(TypeError):
        fairsurf.solve(42)  # type: ignore[arg-type]

    with pytest.raises(fairsurf.SolveError, match="would need about"):
        fairsurf.solve(TENSOR, max_memory_gb=1e-9)
    with pytest.raises(ValueError, match="max_memory_gb"):
        fairsurf.solve(TENSOR, max_memory_gb=-1)

    free = {"surface": {"type": "tensor", "degree": [1, 1],
                        "control_points": [[[0, 0, 0], None], [[1, 0, 0], [1, 1, 0]]]}}
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.load(free)
    assert e.value.path == "surface.control_points[0][1]", e.value

    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.schema("nurbs")
    assert e.value.path == "surface.type"


def test_a_triangular_surface_is_evaluated_patch_by_patch() -> None:
    """At a patch's barycentric point (u, v, 1 − u − v): the mesh's vertices
    and normals at its own uvs and patches, the corner control points at the
    corners (a Bézier triangle interpolates them), and du / dv the central
    differences of the points along u and v."""
    tri = fairsurf.solve(TRIANGULAR)
    m = tri.mesh(8)
    assert m.patches is not None and m.patches.shape == (len(m.vertices),)
    d = tri.derivatives(m.uvs[:, 0], m.uvs[:, 1], patch=m.patches)
    assert np.abs(d["points"] - m.vertices).max() < 1e-14
    assert np.abs(d["normals"] - m.normals).max() < 1e-12
    assert np.allclose(d["mean"], m.mean_curvature, atol=1e-12, equal_nan=True)
    n = tri.degree[0]
    cp, idx = tri.control_points, tri.patch_indices
    # The patch's points in order (i, j, k) with i + j + k = n; the corner
    # u = 1 is (n, 0, 0), v = 1 is (0, n, 0), w = 1 is (0, 0, n).
    for k in range(len(idx)):
        corners = tri.evaluate([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], patch=k)
        mine = cp[idx[k]]
        assert min(np.abs(mine - corners[0]).sum(axis=1)) == 0.0
        assert min(np.abs(mine - corners[1]).sum(axis=1)) == 0.0
        assert min(np.abs(mine - corners[2]).sum(axis=1)) == 0.0
    h = 1e-6
    u, v, k = np.array([0.3, 0.2]), np.array([0.25, 0.5]), np.array([0, 3])
    d = tri.derivatives(u, v, patch=k)
    du = (tri.evaluate(u + h, v, k) - tri.evaluate(u - h, v, k)) / (2 * h)
    dv = (tri.evaluate(u, v + h, k) - tri.evaluate(u, v - h, k)) / (2 * h)
    assert np.abs(du - d["du"]).max() < 1e-7 and np.abs(dv - d["dv"]).max() < 1e-7
    assert n >= 2 and np.abs(d["du"]).max() > 1e-3


def owner(a: np.ndarray) -> object:
    """What holds an array's memory (through views)."""
    while isinstance(a.base, np.ndarray):
        a = a.base
    return a.base


def test_arrays_are_the_librarys_buffers_handed_over() -> None:
    """Mesh, evaluation and control-point arrays are Rust vectors given to
    numpy as they are: their memory is held by the vector's container, not
    by a numpy allocation (numpy makes no copy)."""
    for scene in (TENSOR, TRIANGULAR, BSPLINE):
        s = fairsurf.solve(scene)
        m = s.mesh(8)
        arrays = [m.vertices, m.normals, m.faces, m.uvs, m.mean_curvature, s.control_points]
        if s.surface_type != "triangular":
            d = s.derivatives(np.array([0.5]), np.array([0.5]))
            arrays += [d["points"], d["normals"], d["mean"]]
        for a in arrays:
            assert type(owner(a)).__name__ == "PySliceContainer", (scene, type(owner(a)))
            assert a.flags.c_contiguous


def test_a_net_double_precision_cannot_hold_is_refused_with_its_own_error() -> None:
    """Degree 34, a flat square, the membrane: the written Bernstein net
    fails the double-double check (the README's limits), an
    UnverifiedError (a FairsurfError, not a SceneError) that says so."""
    n = 34
    net = np.full((n + 1, n + 1, 3), np.nan)
    for i in range(n + 1):
        for j in range(n + 1):
            if i in (0, n) or j in (0, n):
                net[i, j] = [i / n, j / n, 0.0]
    with pytest.raises(fairsurf.UnverifiedError, match="cannot be verified in double precision") as e:
        fairsurf.Problem(net).stretch(1.0).solve()
    assert isinstance(e.value, fairsurf.FairsurfError)
    assert not isinstance(e.value, fairsurf.SceneError)


def test_evaluation_errors() -> None:
    r = fairsurf.solve(TENSOR)
    with pytest.raises(ValueError, match=r"u\[1\] = 1.5"):
        r.evaluate([0.5, 1.5], 0.5)
    with pytest.raises(ValueError, match=r"v\[0\] = NaN"):
        r.evaluate(0.5, math.nan)
    tri = fairsurf.solve(TRIANGULAR)
    with pytest.raises(ValueError, match="give patch"):
        tri.evaluate(0.5, 0.5)
    with pytest.raises(ValueError, match="patch is for triangular"):
        r.evaluate(0.5, 0.5, patch=0)
    with pytest.raises(ValueError, match=r"u\[1\] \+ v\[1\]"):
        tri.evaluate([0.2, 0.7], 0.5, patch=0)
    with pytest.raises(ValueError, match=r"patch\[0\] = 1000000"):
        tri.evaluate(0.2, 0.2, patch=10**6)
    with pytest.raises(ValueError, match="integer patch indices"):
        tri.evaluate(0.2, 0.2, patch=1.7)
    with pytest.raises(ValueError, match="resolution 0"):
        r.mesh(0)
    with pytest.raises(ValueError, match="colour"):
        r.render(colour="purple")


def test_files_are_written_whole_or_not_at_all(tmp_path: Path) -> None:
    r = fairsurf.solve(BSPLINE)
    out = tmp_path / "r.json"
    r.write(out)
    again = fairsurf.solve(out)  # a result file solves again to the same net
    np.testing.assert_allclose(again.control_points, r.control_points, atol=1e-12)
    with pytest.raises(OSError):
        r.write(tmp_path / "no" / "such" / "dir" / "r.json")
    assert not (tmp_path / "no").exists()

    with pytest.raises(fairsurf.ExportError, match=".step"):
        r.export(tmp_path / "r.xyz")
    assert not (tmp_path / "r.xyz").exists()

    summary = r.export(tmp_path / "r.step")
    assert "B-spline face with its knots" in summary
    assert (tmp_path / "r.step").read_text().count("B_SPLINE_SURFACE_WITH_KNOTS") == 1

    obj = tmp_path / "r.obj"
    r.export(obj, resolution=6)
    lines = obj.read_text().splitlines()
    vertices = np.array([[float(x) for x in ln.split()[1:]] for ln in lines if ln.startswith("v ")])
    mesh = r.mesh(6)
    np.testing.assert_allclose(vertices, mesh.vertices, rtol=1e-9, atol=1e-12)
    assert sum(ln.startswith("f ") for ln in lines) == len(mesh.faces)


def test_pictures_are_png_of_the_asked_size(tmp_path: Path) -> None:
    png = fairsurf.solve(TRIANGULAR).render(tmp_path / "t.png", width=320, height=200, zebra=12)
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and png[12:16] == b"IHDR"
    assert struct.unpack(">II", png[16:24]) == (320, 200)
    assert (tmp_path / "t.png").read_bytes() == png


def test_analyse_and_schema() -> None:
    r = fairsurf.solve(TENSOR)
    m = fairsurf.analyse(r.to_json())
    assert abs(m["area"] - r.report["area"]) <= 1e-9 * r.report["area"]
    s = fairsurf.schema("bspline")
    assert s["type"] == "object" and "surface" in s["properties"]


def test_compare_gives_monterde_and_ugails_four_columns(cli: Path) -> None:
    """The comparison of the bundled model equals `fairsurf compare --json`'s;
    a triangular scene is refused at surface.type."""
    scene = EXAMPLES / "monterde_ugail_model.json"
    ours = fairsurf.compare(scene)
    theirs = json.loads(subprocess.run([str(cli), "compare", str(scene), "--json"],
                                       check=True, capture_output=True, text=True).stdout)
    assert ours == theirs and len(ours) == 4
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.compare(TRIANGULAR)
    assert e.value.path == "surface.type"


def test_solve_many_equals_one_by_one_and_reports_errors_in_place() -> None:
    scenes = [TENSOR, BSPLINE, {"surface": {"type": "nurbs"}}, TRIANGULAR]
    with pytest.raises(fairsurf.SceneError):
        fairsurf.solve_many(scenes, threads=2)
    out = fairsurf.solve_many(scenes, threads=2, return_exceptions=True)
    assert isinstance(out[2], fairsurf.SceneError) and out[2].path == "surface.type"
    for scene, r in zip([TENSOR, BSPLINE, None, TRIANGULAR], out):
        if scene is not None:
            np.testing.assert_array_equal(r.control_points, fairsurf.solve(scene).control_points)


def heavy_scene(n: int) -> dict:
    """A degree-n tensor patch, boundary fixed, stretch and a normal field."""
    net = [[[i / n, j / n, 0.3 * math.sin(3 * i / n) * math.cos(2 * j / n)]
            if i in (0, n) or j in (0, n) else None for j in range(n + 1)]
           for i in range(n + 1)]
    field = {"weight": 10, "degree": [1, 1],
             "control_points": [[[0, 0, 1], [0.1, 0, 1]], [[0, 0.2, 1], [0.1, 0.1, 1]]]}
    return {"surface": {"type": "tensor", "degree": [n, n], "control_points": net},
            "energy": {"stretch": 1, "normal_field": field}}


def test_the_gil_is_released_while_solving() -> None:
    """While one thread solves, another runs Python code: the longest pause
    of a loop in the main thread is a small part of the solve's time (a
    solve holding the GIL would pause it for the whole solve). The pauses
    measured were 4-8 ms whatever the solve's size (the scheduler: the solve
    uses both cores); the degree-18 solve came down to 21-25 ms, too short
    beside them, so the solve is of degree 22 (~70 ms). It is called again
    until 0.2 s have passed, and the pause compared with the shortest call."""
    scene = json.dumps(heavy_scene(22))
    longest_pause_is_small(lambda: fairsurf.solve(scene), repeat_for=0.2)


def test_the_gil_is_released_while_evaluating_meshing_and_drawing() -> None:
    """The same for a large grid of curvatures, a fine mesh and a picture."""
    r = fairsurf.solve(TENSOR)
    s = np.linspace(0.0, 1.0, 1200)
    # These jobs use both cores of a 2-core machine: the main thread waits
    # for a core now and then, hence half rather than a quarter.
    longest_pause_is_small(lambda: r.curvatures(s[:, None], s[None, :]), 0.5)
    longest_pause_is_small(lambda: r.mesh(900), 0.5)
    longest_pause_is_small(lambda: r.render(width=2400, height=1800, zebra=20), 0.5)


def test_the_gil_is_released_while_filling_and_blending() -> None:
    """The same for a hole fill from a STEP file (next to two cylinders:
    stand-ins, the solve, W-lowering steps, the measures) and a blend. A
    fill and a blend take a few tens of ms now, under the 0.05 s the test
    needs to tell a pause from a call: each is called again until 0.2 s have
    passed, and the pause compared with the shortest call."""
    cad = EXAMPLES / "cad"
    longest_pause_is_small(lambda: fairsurf.fill(cad / "fillet_hole.step", elevate=10), 0.5, 0.2)
    longest_pause_is_small(lambda: fairsurf.blend(cad / "blend_sheets.json"), 0.5, 0.2)


def longest_pause_is_small(job, share: float = 0.25, repeat_for: float = 0.0) -> None:
    """Runs job in a thread (again until `repeat_for` seconds have passed)
    while the main thread loops: the loop's longest pause is under `share`
    of the shortest call's time (a call holding the GIL would pause it for
    all of it)."""
    calls = []

    def work() -> None:
        start = time.perf_counter()
        while not calls or time.perf_counter() - start < repeat_for:
            t = time.perf_counter()
            job()
            calls.append(time.perf_counter() - t)

    th = threading.Thread(target=work)
    th.start()
    last = time.perf_counter()
    longest = 0.0
    ticks = 0
    while th.is_alive():
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
        ticks += 1
    th.join()
    # A repeated job's pause is compared with its shortest call, which must
    # still be long (10 ms) beside the scheduler's and the GIL's switches.
    call, least = min(calls), (0.01 if repeat_for else 0.05)
    assert call > least, f"the job took only {call:.3f} s: too short to tell"
    assert longest < share * call, f"paused {longest:.3f} s of a {call:.3f} s call"
    assert ticks > 100


def test_the_python_call_adds_little_to_a_degree_10_solve() -> None:
    """The same parse and solve, timed in Rust and called from Python,
    alternating: Python's fastest is within 10% of Rust's (the wrapper adds
    ~0.1 ms to a ~6 ms solve of the test build; the result file and the
    report are written only when asked for). The fastest of 30 is the least
    disturbed by the machine's other work, but on a busy 2-core machine even
    that drifts by 10%: up to three rounds, and one within 10% passes (a
    wrapper that really cost 10% would fail all three)."""
    from fairsurf import _fairsurf

    text = (EXAMPLES / "editor_degree10.json").read_text()
    ratios = []
    for _ in range(3):
        rust, python = [], []
        for _ in range(30):
            rust += _fairsurf._time_solve(text, 1)
            t = time.perf_counter()
            fairsurf.solve(text).control_points
            python.append(time.perf_counter() - t)
        ratios.append(min(python) / min(rust))
        print(f"degree 10: Rust {min(rust) * 1e3:.2f} ms, Python {min(python) * 1e3:.2f} ms")
        if ratios[-1] < 1.10:
            return
    pytest.fail(f"the Python call takes {min(ratios):.2f}× the library's time at best")


def test_bspline_parameters_map_the_knot_domain_onto_the_unit_square() -> None:
    """On knots over [2, 5] × [−1, 0.5]: derivatives are those of the mapped
    surface (central differences, 1e-6), the mesh's uvs lie in [0, 1]² and
    evaluate there to the mesh's vertices."""
    rng = np.random.default_rng(7)
    u = [2, 2, 2, 2, 3.5, 5, 5, 5, 5]
    v = [-1, -1, -1, -0.2, 0.5, 0.5, 0.5]
    i, j = np.meshgrid(np.arange(5.0), np.arange(4.0), indexing="ij")
    net = np.stack([i, j, np.zeros_like(i)], axis=-1) + 0.3 * rng.normal(size=(5, 4, 3))
    s = fairsurf.load({"surface": {"type": "bspline", "degree": [3, 2], "knots": [u, v],
                                   "control_points": net}})
    a, b, h = 0.37, 0.61, 1e-5
    d = s.derivatives(a, b)
    p = s.evaluate
    np.testing.assert_allclose(d["du"], (p(a + h, b) - p(a - h, b)) / (2 * h), atol=1e-6)
    np.testing.assert_allclose(d["dv"], (p(a, b + h) - p(a, b - h)) / (2 * h), atol=1e-6)
    np.testing.assert_allclose(
        d["duv"], (p(a + h, b + h) - p(a + h, b - h) - p(a - h, b + h) + p(a - h, b - h))
        / (4 * h * h), atol=1e-3)
    mesh = s.mesh(6)
    assert mesh.uvs.min() == 0.0 and mesh.uvs.max() == 1.0
    np.testing.assert_allclose(s.evaluate(mesh.uvs[:, 0], mesh.uvs[:, 1]), mesh.vertices,
                               atol=1e-13)


def test_elevation_from_python_keeps_the_boundary() -> None:
    data = json.loads(BSPLINE.read_text())
    data["refine"] = {"elevate": [1, 1]}
    r = fairsurf.solve(data)
    coarse = fairsurf.solve(BSPLINE)
    assert r.degree == (4, 4) and r.control_points.shape == (25, 25, 3)
    t = np.linspace(0, 1, 11)
    np.testing.assert_allclose(r.evaluate(t, 0), coarse.evaluate(t, 0), atol=1e-12)
    assert r.report["energy"] < coarse.report["energy"]


def test_nan_points_are_free_in_lists_too_and_other_nans_are_named() -> None:
    data = json.loads(TENSOR.read_text())
    expected = fairsurf.solve(data).control_points
    nets = [[[float("nan")] * 3 if p is None else p for p in row]
            for row in data["surface"]["control_points"]]
    data["surface"]["control_points"] = nets
    np.testing.assert_array_equal(fairsurf.solve(data).control_points, expected)
    nets[0][0] = [0.0, float("nan"), 0.0]
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.solve(data)
    assert e.value.path == "surface.control_points[0][0][1]", e.value


def test_solve_many_keeps_unreadable_scenes_in_their_place(tmp_path: Path) -> None:
    out = fairsurf.solve_many([tmp_path / "missing.json", TENSOR], return_exceptions=True)
    assert isinstance(out[0], FileNotFoundError) and isinstance(out[1], fairsurf.Result)
    with pytest.raises(FileNotFoundError):
        fairsurf.solve_many([tmp_path / "missing.json", TENSOR])
