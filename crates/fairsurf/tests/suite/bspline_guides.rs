//! Guide surfaces of any kind on a B-spline problem (Wu & Yang's
//! ½γ∫|R − S|² with S on its own knots and degrees): a guide whose space
//! lies inside the surface's gives what the same-knots guide of its exact
//! refinement gives; a guide outside it (a Bézier patch of higher degree)
//! has its term confirmed by direct quadrature of |R − S|² and the result
//! is the minimum (random moves raise the energy); another domain is
//! refused.

use crate::common;

use fairsurf::bspline::{BSplineProblem, BSplineSurface, KnotVector};
use fairsurf::{Bend, GuideSurface};
use fairsurf::{TensorPatch, Vec3};

fn sheet() -> BSplineSurface {
    common::wavy_sheet()
}

fn base() -> BSplineProblem {
    common::wavy_problem()
}

#[test]
fn a_guide_inside_the_space_gives_its_refinements_solution() {
    // S: bicubic on 3 × 5 spans (every knot of it is one of the sheet's
    // after inserting 1/6, 1/2, 5/6: a subspace), a different wave.
    let coarse = common::graph_bspline(
        KnotVector::uniform(3, 3),
        KnotVector::uniform(3, 5),
        |x, y| 0.1 * (2.0 * x).cos() * y,
    );
    let refined = coarse.refined(&[1.0 / 6.0, 0.5, 5.0 / 6.0], &[]).unwrap();
    assert_eq!(refined.knots().0.knots(), sheet().knots().0.knots());
    let a = base()
        .with_term(GuideSurface::spline(30.0, coarse))
        .solve()
        .unwrap();
    let b = base()
        .with_term(GuideSurface::spline(30.0, refined.clone()))
        .solve()
        .unwrap();
    let worst = common::max_distance(a.surface.points(), b.surface.points());
    assert!(worst < 1e-12, "{worst:e}");
    let (ea, eb) = (
        a.report.term("guide_surface"),
        b.report.term("guide_surface"),
    );
    assert!((ea - eb).abs() < 1e-12 * eb.max(1e-12), "{ea} vs {eb}");
    assert!(
        a.report.check.unwrap().energy_error < 1e-12,
        "{}",
        a.report.check.unwrap().energy_error
    );
}

#[test]
fn a_guide_outside_the_space_is_confirmed_by_quadrature_and_minimal() {
    // S: a degree-5 × 4 Bézier patch over the same unit square.
    let patch = TensorPatch::from_fn(5, 4, |i, j| {
        let (u, v) = (i as f64 / 5.0, j as f64 / 4.0);
        [
            u + 0.02 * v,
            v,
            0.2 * (u - 0.5) * (v - 0.3) + 0.05 * (i * j % 3) as f64,
        ]
    });
    let guide = BSplineSurface::from_bezier(&patch);
    let problem = base().with_term(GuideSurface::spline(50.0, guide));
    let sol = problem.solve().unwrap();
    let r = &sol.report;
    // The closed forms (projection + constant) against quadrature of
    // |R − S|² between both surfaces' knot lines.
    assert!(
        r.check.unwrap().energy_error < 1e-12,
        "{}",
        r.check.unwrap().energy_error
    );
    assert!(r.term("guide_surface") > 0.0 && r.check.unwrap().excess < 1e-10);
    common::assert_bspline_minimal(&problem, &sol.surface, r.energy, 5);
}

#[test]
fn a_guide_over_another_domain_is_refused() {
    let other = BSplineSurface::new(
        KnotVector::new(1, vec![0.0, 0.0, 2.0, 2.0]).unwrap(),
        KnotVector::new(1, vec![0.0, 0.0, 1.0, 1.0]).unwrap(),
        vec![[0.0; 3], [0.0, 1.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0]],
    )
    .unwrap();
    let e = base()
        .with_term(GuideSurface::spline(1.0, other))
        .solve()
        .unwrap_err()
        .to_string();
    assert!(e.contains("guide surface") && e.contains("domain"), "{e}");
}

/// Far from the origin (x shifted by 100, CAD-like coordinates) a guide
/// given on its own knots — here the surface's own degree-elevated, so
/// PS = S — solves as
/// the same-knots guide does: the constant ∫|S − PS|² is integrated as it
/// stands (as ∫|S|² − s*ᵀMs* it cancelled to 1e-7 of the energy and the
/// check refused the solve).
#[test]
fn a_guide_far_from_the_origin_is_not_lost_to_cancellation() {
    let u = KnotVector::uniform(3, 3);
    let sheet = common::graph_bspline(u.clone(), u, |x, y| 0.05 * (3.0 * x).sin() * y);
    // Several offsets: the old cancellation's sign varied with them.
    for shift in [12.5, 37.0, 100.0, 250.0, 1000.0] {
        let points: Vec<Vec3> = sheet
            .points()
            .iter()
            .map(|p| [p[0] + shift, p[1], p[2]])
            .collect();
        let (ku, kv) = sheet.knots();
        let s = BSplineSurface::new(ku.clone(), kv.clone(), points).unwrap();
        let base = || {
            BSplineProblem::from_surface(s.clone())
                .with_fixed_rings(1)
                .with_term(Bend::new(1e-3))
        };
        let own = base()
            .with_term(GuideSurface::spline(1e3, s.elevated(1, 1).unwrap()))
            .solve()
            .unwrap();
        let same = base()
            .with_term(GuideSurface::spline(1e3, s.clone()))
            .solve()
            .unwrap();
        let worst = common::max_distance(own.surface.points(), same.surface.points());
        assert!(worst < 1e-10, "shift {shift}: {worst:e}");
        assert!(
            own.report.check.unwrap().energy_error < 1e-10,
            "shift {shift}: {}",
            own.report.check.unwrap().energy_error
        );
    }
}
