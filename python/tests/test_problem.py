"""fairsurf.Problem: scenes built from numpy arrays solve exactly as the
bundled scene files they rebuild, sweeps share a base, and mistakes are
SceneErrors naming the JSON path."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import fairsurf

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def example(name: str) -> dict:
    return json.loads((EXAMPLES / name).read_text())


def net(points) -> np.ndarray:
    """A scene's control points as an array, null points NaN."""
    return np.array([[[math.nan] * 3 if p is None else p for p in row] for row in points],
                    dtype=np.float64)


def same_solution(built: fairsurf.Problem, name: str) -> None:
    """The built scene and the file give the same surface to the last bit
    and the same energy (constructions report none)."""
    ours, theirs = built.solve(), fairsurf.solve(EXAMPLES / name)
    np.testing.assert_array_equal(ours.control_points, theirs.control_points)
    assert ours.report.get("energy") == theirs.report.get("energy")


def test_wu_and_yang_terms_rebuild_fig1() -> None:
    """Stretch, a Bézier normal field and the initial surface as guide."""
    d = example("wu_yang_fig1_l10_g100.json")
    e = d["energy"]
    built = (fairsurf.Problem(net(d["surface"]["control_points"]))
             .fix_rings(1)
             .stretch(e["stretch"])
             .normal_field(e["normal_field"]["weight"], e["normal_field"]["control_points"])
             .guide(e["guide_surface"]["weight"]))
    same_solution(built, "wu_yang_fig1_l10_g100.json")


def test_constraints_and_operators_rebuild_the_tensor_examples() -> None:
    for name, key in [("tensor_constraints.json", "constraints"),
                      ("tensor_operators.json", "operators")]:
        d = example(name)
        p = (fairsurf.Problem(net(d["surface"]["control_points"]))
             .fix_rings(d["fixed_rings"])
             .stretch(d["energy"]["stretch"])
             .bend(d["energy"]["bend"]))
        for item in d[key]:
            fields = {k: v for k, v in item.items() if k != "type"}
            p = p.constraint(item["type"], **fields) if key == "constraints" else \
                p.operator(item["type"], **fields)
        same_solution(p, name)


def test_operators_rebuild_the_bspline_example() -> None:
    d = example("bspline_operators.json")
    s = d["surface"]
    p = (fairsurf.Problem(net(s["control_points"]), knots=s["knots"])
         .fix_rings(d["fixed_rings"])
         .stretch(d["energy"]["stretch"])
         .bend(d["energy"]["bend"]))
    for item in d["operators"]:
        p = p.operator(item["type"], **{k: v for k, v in item.items() if k != "type"})
    same_solution(p, "bspline_operators.json")
    assert len(p.solve().report["operators"]) == 4


def test_constraints_rebuild_the_bspline_example() -> None:
    d = example("bspline_constraints.json")
    s = d["surface"]
    p = (fairsurf.Problem(net(s["control_points"]), knots=s["knots"])
         .fix_rings(d["fixed_rings"])
         .stretch(d["energy"]["stretch"])
         .bend(d["energy"]["bend"]))
    for item in d["constraints"]:
        p = p.constraint(item["type"], **{k: v for k, v in item.items() if k != "type"})
    same_solution(p, "bspline_constraints.json")
    peak = p.solve().evaluate(np.array([0.35]), np.array([0.4]))
    assert np.abs(peak - [0.35, 0.4, 0.3]).max() < 1e-12


def test_a_bspline_problem_rebuilds_the_guided_hole() -> None:
    d = example("bspline_hole_guided.json")
    s, e = d["surface"], d["energy"]
    built = (fairsurf.Problem(net(s["control_points"]), knots=s["knots"])
             .fix_rings(d["fixed_rings"])
             .bend(e["bend"])
             .normal_field(e["normal_field"]["weight"], e["normal_field"]["control_points"]))
    assert built["surface"]["degree"] == s["degree"]
    same_solution(built, "bspline_hole_guided.json")


def test_constructions_are_methods() -> None:
    d = example("monterde_ugail_fig7_harmonic_mask.json")
    built = fairsurf.Problem(net(d["surface"]["control_points"])).method(d["method"])
    same_solution(built, "monterde_ugail_fig7_harmonic_mask.json")


def test_a_base_serves_a_sweep_unchanged() -> None:
    """Each step returns a new Problem: the base keeps its scene, and the
    sweep solved on threads equals the runs one by one (and the text)."""
    d = example("wu_yang_fig1_l10_g100.json")
    field = d["energy"]["normal_field"]["control_points"]
    base = fairsurf.Problem(net(d["surface"]["control_points"])).fix_rings(1).stretch(1.0)
    before = base.to_json()
    sweep = [base.normal_field(lam, field) for lam in (1.0, 10.0, 100.0)]
    assert base.to_json() == before and "energy" in base and "normal_field" not in base["energy"]
    many = fairsurf.solve_many(sweep, threads=2)
    for p, r in zip(sweep, many):
        np.testing.assert_array_equal(r.control_points, p.solve().control_points)
        np.testing.assert_array_equal(
            r.control_points, fairsurf.solve(p.to_json()).control_points)
    # More normal-field weight: the surface follows the field more closely.
    terms = [r.report["terms"]["normal_field"] / lam for r, lam in zip(many, (1.0, 10.0, 100.0))]
    assert terms[0] > terms[1] > terms[2]


def test_mistakes_are_scene_errors_naming_the_path() -> None:
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.Problem(np.zeros((3, 3)))
    assert e.value.path == "surface.control_points"
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.Problem(np.zeros((3, 3, 3)), degree=(3, 3))
    assert e.value.path == "surface.degree"
    flat = np.zeros((4, 4, 3))
    flat[..., 0], flat[..., 1] = np.meshgrid(np.arange(4), np.arange(4), indexing="ij")
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.Problem(flat).normal_field(1.0, np.zeros(3))
    assert e.value.path == "energy.normal_field.control_points"
    # What the library refuses names the path in the scene the builder made.
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.Problem(flat).fix_rings(1).bend(1).constraint("bogus", at={"uv": [0.5, 0.5]}).solve()
    assert "constraints[0]" in str(e.value), str(e.value)
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.Problem(flat).fix_rings(1).bend(-1.0).solve()
    assert "energy.bend" in str(e.value), str(e.value)


def test_steps_copy_and_compare_and_refuse_what_the_kind_lacks() -> None:
    """Problems compare by their scenes; nothing a caller holds changes a
    Problem; free points accumulate; a key the surface kind does not have
    is refused at the call, naming it."""
    d = example("wu_yang_fig1_l10_g100.json")
    a = fairsurf.Problem(net(d["surface"]["control_points"])).fix_rings(1).stretch(1.0)
    b = fairsurf.Problem(net(d["surface"]["control_points"])).fix_rings(1).stretch(1.0)
    assert a == b and a != a.bend(1.0)
    target = [0.5, 0.5, 0.3]
    c = a.constraint("point", at={"uv": [0.5, 0.5]}, target=target)
    target[2] = 9.0
    c["constraints"][0]["target"][2] = 7.0
    assert c["constraints"][0]["target"] == [0.5, 0.5, 0.3]
    assert a.free_points([(2, 2)]).free_points([(2, 2), (3, 3)])["free_points"] == [[2, 2], [3, 3]]
    assert a.method("minimize").solve().report["energy"] == a.solve().report["energy"]
    h = example("bspline_hole.json")["surface"]
    spline = fairsurf.Problem(net(h["control_points"]), knots=h["knots"]).fix_rings(2)
    for step, key in [(lambda p: p.method("harmonic"), "method")]:
        with pytest.raises(fairsurf.SceneError) as e:
            step(spline)
        assert e.value.path == key
    with pytest.raises(fairsurf.SceneError) as e:
        a.refine(elevate=[1, 1])
    assert e.value.path == "refine"
    refined = spline.bend(1.0).refine(elevate=[1, 1]).solve()
    assert refined.degree == (4, 4)


@pytest.mark.parametrize("name", ["vw_fig1_point_normal.json", "vw_fig2_curve.json",
                                  "vw_fig6_attractors.json", "vw_repellor.json",
                                  "vw_pentagon_hole.json"])
def test_tri_problems_rebuild_the_triangular_examples(name: str) -> None:
    """Mesh, degree, control points, weights, continuity, constraints
    (point, normal, curve) and operators (attractors, a repellor) written
    step by step give the example's surface to the last bit."""
    d = example(name)
    s = d["surface"]
    p = fairsurf.TriProblem(np.array(s["vertices"]), np.array(s["triangles"]), s["degree"],
                            control_points=s.get("control_points"))
    for key, value in d["energy"].items():
        p = getattr(p, key)(value)
    if "continuity" in d:
        p = p.continuity(**d["continuity"])
    for key in ("constraints", "operators"):
        for item in d.get(key, []):
            fields = {k: v for k, v in item.items() if k != "type"}
            p = getattr(p, key[:-1])(item["type"], **fields)
    same_solution(p, name)


def test_tri_problem_steps_copy_and_mistakes_name_their_path() -> None:
    d = example("vw_fig1_point_normal.json")["surface"]
    base = fairsurf.TriProblem(d["vertices"], d["triangles"], 3).bend(1.0)
    free = base.fix_boundary(False).continuity(edges="off")
    assert "fix_boundary" not in base and free["fix_boundary"] is False
    assert free["continuity"] == {"edges": "off"}
    assert free.continuity(vertices=False)["continuity"] == {"edges": "off", "vertices": False}
    assert repr(base).startswith("<fairsurf.TriProblem triangular degree 3")
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.TriProblem(d["vertices"], np.array(d["triangles"], dtype=float), 3)
    assert e.value.path == "surface.triangles"
    with pytest.raises(fairsurf.SceneError) as e:
        fairsurf.TriProblem(np.zeros((4, 2)), d["triangles"], 3)
    assert e.value.path == "surface.vertices"
    with pytest.raises(fairsurf.SceneError) as e:
        base.constraint("point", at={"triangle": 10**6, "bary": [1, 0, 0]},
                        target=[0, 0, 0]).solve()
    assert e.value.path == "constraints[0].at", e.value.path
    with pytest.raises(fairsurf.SceneError) as e:
        base.continuity(edges="sometimes").solve()
    assert e.value.path.startswith("continuity.edges"), e.value.path


def test_a_bspline_problem_takes_a_guide_of_its_own_kind() -> None:
    """A Bézier guide over the knot domain and a B-spline guide on other
    knots: the scene says so, the solve confirms the term (its check) and
    the built scene solves like the dict it writes."""
    h = example("bspline_hole.json")["surface"]
    base = fairsurf.Problem(net(h["control_points"]), knots=h["knots"]).fix_rings(2).bend(1.0)
    patch = np.array([[[2 * i / 3, 2 * j / 3, 0.1 * i * j / 9] for j in range(4)] for i in range(4)])
    b = base.guide(20.0, patch, bezier=True)
    assert b["energy"]["guide_surface"]["degree"] == [3, 3]
    knots = ([0, 0, 0, 0, 0.5, 1, 1, 1, 1], [0, 0, 0, 0, 1, 1, 1, 1])
    coarse = np.array([[[0.5 * i, 2 * j / 3, 0.05 * i] for j in range(4)] for i in range(5)])
    c = base.guide(20.0, coarse, knots=knots)
    for p in (b, c):
        r = p.solve()
        assert r.report["terms"]["guide_surface"] > 0.0
        assert r.report["check"]["energy_error"] < 1e-12
        again = fairsurf.solve(json.loads(p.to_json()))
        np.testing.assert_array_equal(again.control_points, r.control_points)


def test_a_bspline_problem_takes_a_normal_field_on_its_own_knots() -> None:
    """normal_field(knots=...): the scene carries the knots (no degree),
    the solve confirms the term, and the same field as a Bézier patch
    (no interior knots) gives the Bézier field's net."""
    h = example("bspline_hole.json")["surface"]
    base = fairsurf.Problem(net(h["control_points"]), knots=h["knots"]).fix_rings(2).bend(1.0)
    field = np.array([[[0.1 * i - 0.15, 0.05 * j, 1 + 0.05 * i * j] for j in range(3)]
                      for i in range(4)])
    p = base.normal_field(30.0, field, knots=([0, 0, 0, 0.4, 1, 1, 1], [0, 0, 0, 1, 1, 1]))
    assert "degree" not in p["energy"]["normal_field"]
    r = p.solve()
    assert r.report["terms"]["normal_field"] > 0.0
    assert r.report["check"]["energy_error"] < 1e-12
    flat = field[:3]
    a = base.normal_field(30.0, flat).solve()
    b = base.normal_field(30.0, flat, knots=([0, 0, 0, 1, 1, 1], [0, 0, 0, 1, 1, 1])).solve()
    np.testing.assert_allclose(b.control_points, a.control_points, rtol=0, atol=1e-12)
    with pytest.raises(fairsurf.SceneError) as e:
        base.normal_field(1.0, field, knots=([0, 0, 0, 0.4, 2, 2, 2], [0, 0, 0, 1, 1, 1])).solve()
    assert e.value.path == "energy.normal_field", e.value.path


def test_builders_copy_the_callers_arrays_and_compare_without_raising() -> None:
    h = example("bspline_hole.json")["surface"]
    points = net(h["control_points"])
    p = fairsurf.Problem(points, knots=h["knots"]).fix_rings(2).bend(1.0)
    before = p.to_json()
    points[0, 0] = [9.0, 9.0, 9.0]
    assert p.to_json() == before
    d = example("vw_fig1_point_normal.json")["surface"]
    vertices = np.array(d["vertices"])
    t = fairsurf.TriProblem(vertices, d["triangles"], 3)
    before = t.to_json()
    vertices[0] = [5.0, 5.0, 5.0]
    assert t.to_json() == before
    assert (p.bend(math.nan) == p.bend(math.nan)) is False
    with pytest.raises(fairsurf.SceneError) as e:
        p.guide(1.0, knots=([0, 0, 1, 1], [0, 0, 1, 1]))
    assert e.value.path == "energy.guide_surface.control_points"
    with pytest.raises(fairsurf.SceneError):
        p.guide(1.0, bezier=True)
