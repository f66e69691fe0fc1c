//! Linear constraints on B-spline surfaces (Veltkamp & Wesselink eq. 31 at a
//! point (u, v) of the knot domain), solved through the core's KKT back
//! ends: the rows of a B-spline without interior knots are the Bézier
//! patch's; such a B-spline gives the tensor solve's surface (a different
//! back end: the dense range-space method); on many spans every kind holds
//! on the written net, measured by evaluating it, with and without a normal
//! field; no move along the constraints lowers the energy; bad constraints
//! are refused, naming them.

use crate::common;

use fairsurf::bspline::{BSplineProblem, BSplineSurface, KnotVector};
use fairsurf::constraint::{ConstraintSurface, Row};
use fairsurf::vector::{norm, sub};
use fairsurf::{Bend, Error, Problem, Stretch, TensorConstraint, TensorPatch, Vec3};
use fairsurf::{GuideSurface, NormalField};

fn constraints() -> Vec<(&'static str, TensorConstraint)> {
    common::four_constraints()
}

/// How far the surface is from meeting the constraint, by evaluating it.
fn miss(s: &BSplineSurface, c: &TensorConstraint) -> f64 {
    common::constraint_miss(
        |[u, v]| {
            let d = s.derivatives(u, v);
            (d.point, d.du, d.dv)
        },
        c,
    )
}

/// A degree-6 Bézier net over the unit square with a wavy boundary.
fn frame() -> TensorPatch {
    TensorPatch::from_fn(6, 6, |i, j| {
        let (u, v) = (i as f64 / 6.0, j as f64 / 6.0);
        [u, v, 0.1 * (3.0 * u).sin() * (2.0 * v).cos()]
    })
}

/// A bicubic surface of 7 × 6 uniform spans over the unit square, wavy.
fn sheet() -> BSplineSurface {
    common::graph_bspline(
        KnotVector::uniform(3, 7),
        KnotVector::uniform(3, 6),
        |x, y| 0.15 * (3.0 * x).sin() * (2.0 * y).cos(),
    )
}

fn with_all(p: BSplineProblem) -> BSplineProblem {
    constraints()
        .into_iter()
        .fold(p, |p, (name, c)| p.with_constraint(name, c))
}

#[test]
fn rows_of_a_bspline_without_interior_knots_are_the_bezier_patchs() {
    let patch = frame();
    let spline = BSplineSurface::from_bezier(&patch);
    for (name, c) in constraints() {
        let (a, b): (Vec<Row>, Vec<Row>) = (c.rows(&patch, name), c.rows(&spline, name));
        assert_eq!(a.len(), b.len(), "{name}");
        for (ra, rb) in a.iter().zip(&b) {
            assert_eq!(ra.name, rb.name);
            assert!((ra.rhs - rb.rhs).abs() <= 1e-15, "{name}");
            let mut ta = ra.terms.clone();
            let mut tb = rb.terms.clone();
            ta.sort_by_key(|t| t.0);
            tb.sort_by_key(|t| t.0);
            assert_eq!(ta.len(), tb.len(), "{name}");
            for (x, y) in ta.iter().zip(&tb) {
                assert_eq!(x.0, y.0, "{name}");
                assert!((x.1 - y.1).abs() <= 1e-13 * x.1.abs().max(1.0), "{name}");
            }
        }
        assert!(norm(sub(patch.value_at([0.3, 0.4]), spline.value_at([0.3, 0.4]))) < 1e-15);
    }
}

#[test]
fn a_bezier_knot_bspline_gives_the_tensor_solve_surface() {
    let tensor = constraints().into_iter().fold(
        Problem::new((6, 6))
            .with_fixed_rings(&frame(), 1)
            .with_term(Stretch::new(0.1))
            .with_term(Bend::new(1.0)),
        |p, (name, c)| p.with_constraint(name, c),
    );
    let t = tensor.solve().unwrap();
    let s = with_all(
        BSplineProblem::from_surface(BSplineSurface::from_bezier(&frame()))
            .with_fixed_rings(1)
            .with_term(Stretch::new(0.1))
            .with_term(Bend::new(1.0)),
    )
    .solve()
    .unwrap();
    let worst = common::max_distance(t.surface.points(), s.surface.points());
    assert!(worst < 1e-10, "nets differ by {worst:e}");
    assert!((t.report.energy - s.report.energy).abs() < 1e-12 * t.report.energy);
    assert_eq!(s.report.constraints.len(), 4);
    assert!(s.report.kkt.is_some());
}

#[test]
fn every_kind_holds_on_many_spans_and_the_result_is_the_minimum_over_them() {
    let field = TensorPatch::new(
        1,
        1,
        vec![
            [0.0, 0.0, 1.0],
            [0.1, 0.0, 1.0],
            [0.0, 0.1, 1.0],
            [0.1, 0.1, 1.0],
        ],
    );
    for with_field in [false, true] {
        let mut base = BSplineProblem::from_surface(sheet())
            .with_fixed_rings(2)
            .with_term(Bend::new(1.0));
        if with_field {
            base = base.with_term(NormalField::new(10.0, field.clone()));
        }
        let free_solution = base.solve().unwrap();
        let problem = with_all(base);
        let sol = problem.solve().unwrap();
        let r = &sol.report;
        for (name, c) in constraints() {
            let m = miss(&sol.surface, &c);
            assert!(m < 1e-12, "{name} (field {with_field}): missed by {m:e}");
            assert!(miss(&free_solution.surface, &c) > 1e-4, "{name}");
        }
        assert!(r.max_violation < 1e-12, "{:?}", r.constraints);
        assert_eq!(r.coupled, with_field);
        assert!(r.relative_gradient < 1e-14, "{}", r.relative_gradient);
        assert!(r.check.unwrap().excess <= 1e-10 && r.check.unwrap().energy_error < 1e-10);
        assert!(r.energy > free_solution.report.energy);
        // No move along the constraints lowers the energy.
        let rows: Vec<Row> = constraints()
            .iter()
            .flat_map(|(name, c)| c.rows(&sol.surface, name))
            .collect();
        let free: Vec<usize> = (0..problem.free().len())
            .filter(|&k| problem.free()[k])
            .collect();
        let (ku, kv) = sol.surface.knots();
        let e0 = problem.energy_at(&sol.surface).unwrap();
        for (seed, d) in common::moves_along(&rows, &free, 7, 3).iter().enumerate() {
            for eps in [1e-3, -1e-3] {
                let mut points: Vec<Vec3> = sol.surface.points().to_vec();
                for (k, &g) in free.iter().enumerate() {
                    for c in 0..3 {
                        points[g][c] += eps * d[3 * k + c];
                    }
                }
                let moved = BSplineSurface::new(ku.clone(), kv.clone(), points).unwrap();
                let e = problem.energy_at(&moved).unwrap();
                assert!(
                    e > e0,
                    "field {with_field}, seed {seed}, ε {eps}: {e} ≤ {e0}"
                );
            }
        }
    }
}

#[test]
fn bad_constraints_are_refused_naming_them() {
    let base = || {
        BSplineProblem::from_surface(sheet())
            .with_fixed_rings(2)
            .with_term(Bend::new(1.0))
    };
    let peak = TensorConstraint::Point {
        at: [0.3, 0.4],
        target: [0.3, 0.4, 0.2],
    };
    // The same point twice: the second depends on the first.
    match base()
        .with_constraint("peak", peak.clone())
        .with_constraint("again", peak)
        .solve()
    {
        Err(Error::DependentConstraint { row }) => assert_eq!(row, "again, x"),
        other => panic!("{other:?}"),
    }
    // A point where only fixed control points act (the corner), off the
    // surface: nothing free can meet it.
    let corner = TensorConstraint::Point {
        at: [0.0, 0.0],
        target: [0.0, 0.0, 1.0],
    };
    let e = base()
        .with_constraint("corner", corner)
        .solve()
        .unwrap_err();
    let e = e.to_string();
    assert!(
        e.contains("corner, z") && e.contains("known control points alone"),
        "{e}"
    );
    // Outside the knot domain.
    let outside = TensorConstraint::Normal {
        at: [1.2, 0.5],
        normal: [0.0, 0.0, 1.0],
    };
    let e = base().with_constraint("far", outside).solve().unwrap_err();
    assert!(
        e.to_string().contains("far") && e.to_string().contains("knot domain"),
        "{e}"
    );
    // A zero normal.
    let zero = TensorConstraint::Normal {
        at: [0.5, 0.5],
        normal: [0.0, 0.0, 0.0],
    };
    let e = base().with_constraint("flat", zero).solve().unwrap_err();
    assert!(e.to_string().contains("flat"), "{e}");
}

/// Rows that only fixed control points enter, met by them (a point on the
/// fixed boundary, the boundary's own normal at a corner whose two rings
/// are fixed), are accepted and hold; a net without fixed points (a guide
/// term decides it) meets a normal constraint, whose right-hand side is 0.
#[test]
fn rows_the_fixed_points_meet_and_nets_without_fixed_points_solve() {
    let s = sheet();
    let on_rim = s.eval(0.0, 0.5);
    let corner_normal = s.normal(1.0, 1.0).unwrap();
    let sol = BSplineProblem::from_surface(s.clone())
        .with_fixed_rings(2)
        .with_term(Bend::new(1.0))
        .with_constraint(
            "rim",
            TensorConstraint::Point {
                at: [0.0, 0.5],
                target: on_rim,
            },
        )
        .with_constraint(
            "corner",
            TensorConstraint::Normal {
                at: [1.0, 1.0],
                normal: corner_normal,
            },
        )
        .with_constraint("peak", common::four_constraints()[0].1.clone())
        .solve()
        .unwrap();
    assert!(
        sol.report.max_violation < 1e-12,
        "{:?}",
        sol.report.constraints
    );
    let n = s.points().len();
    let guided = BSplineProblem::from_surface(s.clone())
        .with_free(vec![true; n])
        .unwrap()
        .with_term(Bend::new(1.0))
        .with_term(GuideSurface::spline(1.0, s))
        .with_constraint("tilt", common::four_constraints()[1].1.clone())
        .solve()
        .unwrap();
    assert!(guided.report.max_violation < 1e-12);
    assert!(miss(&guided.surface, &common::four_constraints()[1].1) < 1e-12);
}

#[test]
fn a_fixed_constraint_fixes_the_control_point() {
    let s = sheet();
    let (_, cv) = s.counts();
    let k = 4 * cv + 3;
    let sol = BSplineProblem::from_surface(s)
        .with_fixed_rings(2)
        .with_term(Bend::new(1.0))
        .with_constraint(
            "pin",
            TensorConstraint::Fixed {
                point: k,
                value: [0.5, 0.4, 0.3],
            },
        )
        .solve()
        .unwrap();
    assert_eq!(sol.surface.points()[k], [0.5, 0.4, 0.3]);
    assert!(sol.report.constraints.is_empty() && sol.report.kkt.is_none());
}
