//! B-spline normal fields on a B-spline problem (Wu & Yang's
//! ½λ∫∫ (R_u·N)² + (R_v·N)², eq. 1–2, with N on its own knots): a field
//! without interior knots is the Bézier field; inserting knots into the
//! field changes nothing; with knot lines that cut the surface's spans the
//! term equals independent quadrature between both knot sets (and a rule
//! on the surface's spans alone would not); the result is the minimum;
//! another domain is refused, and so is a B-spline field on a Bézier
//! patch's problem.

use crate::common;

use fairsurf::basis::GaussLegendre;
use fairsurf::bspline::{BSplineProblem, BSplineSurface, KnotVector};
use fairsurf::{Bend, NormalField, Problem, TensorPatch, Vec3};

fn base() -> BSplineProblem {
    common::wavy_problem()
}

/// A biquadratic field whose interior knots (0.37, 0.71 in u; 0.43 in v)
/// cut the sheet's spans: tilted normals, varying in length.
fn field() -> BSplineSurface {
    let u = KnotVector::new(2, vec![0.0, 0.0, 0.0, 0.37, 0.71, 1.0, 1.0, 1.0]).unwrap();
    let v = KnotVector::new(2, vec![0.0, 0.0, 0.0, 0.43, 1.0, 1.0, 1.0]).unwrap();
    let (cu, cv) = (u.count(), v.count());
    let points = (0..cu * cv)
        .map(|k| {
            let (i, j) = ((k / cv) as f64, (k % cv) as f64);
            [0.3 * (i - 2.0) * 0.4, 0.2 * (j - 1.5), 1.0 + 0.1 * i * j]
        })
        .collect();
    BSplineSurface::new(u, v, points).unwrap()
}

fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// ½λ∫∫ (R_u·N)² + (R_v·N)² by a 12-point Gauss rule on every piece
/// between the cuts (both directions), from point evaluations.
fn quadrature(s: &BSplineSurface, n: &BSplineSurface, lambda: f64, cuts: [&[f64]; 2]) -> f64 {
    let g = GaussLegendre::new(12);
    let nodes = |c: &[f64]| -> Vec<(f64, f64)> {
        c.windows(2)
            .flat_map(|w| {
                let (a, b) = (w[0], w[1]);
                g.nodes
                    .iter()
                    .zip(&g.weights)
                    .map(move |(&x, &wx)| (a + (b - a) * x, wx * (b - a)))
            })
            .collect()
    };
    let mut total = 0.0;
    for (u, wu) in nodes(cuts[0]) {
        for (v, wv) in nodes(cuts[1]) {
            let d = s.derivatives(u, v);
            let f = n.eval(u, v);
            total += wu * wv * (dot(d.du, f).powi(2) + dot(d.dv, f).powi(2));
        }
    }
    0.5 * lambda * total
}

/// The sorted distinct knots of both vectors.
fn union(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut c: Vec<f64> = a.iter().chain(b).copied().collect();
    c.sort_by(f64::total_cmp);
    c.dedup();
    c
}

#[test]
fn a_field_without_interior_knots_is_the_bezier_field() {
    let patch = TensorPatch::from_fn(2, 1, |i, j| [0.2 * i as f64, -0.1 * j as f64, 1.0]);
    let a = base()
        .with_term(NormalField::new(40.0, patch.clone()))
        .solve()
        .unwrap();
    let b = base()
        .with_term(NormalField::spline(
            40.0,
            BSplineSurface::from_bezier(&patch),
        ))
        .solve()
        .unwrap();
    let worst = common::max_distance(a.surface.points(), b.surface.points());
    assert!(worst < 1e-12, "{worst:e}");
    let (ea, eb) = (a.report.term("normal_field"), b.report.term("normal_field"));
    assert!(ea > 0.0 && (ea - eb).abs() < 1e-12 * ea, "{ea} vs {eb}");
}

/// Over the knot domain [0, 2] × [0, 1]: a Bézier field lives on it mapped
/// onto [0, 1]², a B-spline field on it as it is — the same function as a
/// B-spline without interior knots on [0, 2] × [0, 1] with the Bézier
/// field's coefficients gives the same net; its direction at (½, ½) of the
/// unit square is the field's at (1, ½).
#[test]
fn on_a_wider_domain_the_field_lives_on_the_knot_domain_itself() {
    let surface = common::graph_bspline(
        KnotVector::new(
            3,
            vec![0., 0., 0., 0., 0.3, 0.7, 1.0, 1.3, 1.6, 2., 2., 2., 2.],
        )
        .unwrap(),
        KnotVector::uniform(3, 5),
        |x, y| 0.15 * (2.0 * x).sin() * (3.0 * y).cos(),
    );
    let patch = TensorPatch::from_fn(2, 1, |i, j| {
        [
            0.3 * i as f64 - 0.2,
            0.1 * j as f64,
            1.0 + 0.2 * (i * j) as f64,
        ]
    });
    let same = BSplineSurface::new(
        KnotVector::new(2, vec![0.0, 0.0, 0.0, 2.0, 2.0, 2.0]).unwrap(),
        KnotVector::new(1, vec![0.0, 0.0, 1.0, 1.0]).unwrap(),
        patch.points().to_vec(),
    )
    .unwrap();
    let base = || {
        BSplineProblem::from_surface(surface.clone())
            .with_fixed_rings(2)
            .with_term(Bend::new(1.0))
    };
    let a = base()
        .with_term(NormalField::new(30.0, patch.clone()))
        .solve()
        .unwrap();
    let b = base()
        .with_term(NormalField::spline(30.0, same.clone()))
        .solve()
        .unwrap();
    let worst = common::max_distance(a.surface.points(), b.surface.points());
    assert!(worst < 1e-12, "{worst:e}");
    let d = NormalField::spline(1.0, same.clone())
        .direction(0.5, 0.5)
        .unwrap();
    let n = same.eval(1.0, 0.5);
    let len = dot(n, n).sqrt();
    assert!((0..3).all(|k| (d[k] - n[k] / len).abs() < 1e-15), "{d:?}");
}

#[test]
fn inserting_knots_into_the_field_changes_nothing() {
    let n = field();
    let refined = n.refined(&[0.5, 0.9], &[0.2]).unwrap();
    let a = base()
        .with_term(NormalField::spline(25.0, n))
        .solve()
        .unwrap();
    let b = base()
        .with_term(NormalField::spline(25.0, refined))
        .solve()
        .unwrap();
    let worst = common::max_distance(a.surface.points(), b.surface.points());
    assert!(worst < 1e-12, "{worst:e}");
    assert!((a.report.energy - b.report.energy).abs() < 1e-12 * a.report.energy);
}

#[test]
fn the_term_is_the_quadrature_between_both_knot_sets_and_minimal() {
    let (n, lambda) = (field(), 25.0);
    let problem = base().with_term(NormalField::spline(lambda, n.clone()));
    let sol = problem.solve().unwrap();
    let r = &sol.report;
    assert!(
        r.check.unwrap().energy_error < 1e-12 && r.check.unwrap().excess < 1e-10,
        "{r:?}"
    );
    let s = &sol.surface;
    let (ks, kn) = (s.knots(), n.knots());
    let exact = quadrature(
        s,
        &n,
        lambda,
        [
            &union(ks.0.knots(), kn.0.knots()),
            &union(ks.1.knots(), kn.1.knots()),
        ],
    );
    assert!(
        (r.term("normal_field") - exact).abs() < 1e-12 * exact,
        "{} vs {exact}",
        r.term("normal_field")
    );
    // The field's knot lines matter: a rule on the surface's spans alone
    // is off (the field has a kink inside them).
    let spans_only = quadrature(
        s,
        &n,
        lambda,
        [&union(ks.0.knots(), &[]), &union(ks.1.knots(), &[])],
    );
    assert!(
        (spans_only - exact).abs() > 1e-9 * exact,
        "{spans_only} vs {exact}"
    );
    // Minimal: random moves of the free points raise the energy.
    common::assert_bspline_minimal(&problem, s, r.energy, 11);
}

#[test]
fn a_field_over_another_domain_or_on_a_bezier_problem_is_refused() {
    let other = BSplineSurface::new(
        KnotVector::new(1, vec![0.0, 0.0, 2.0, 2.0]).unwrap(),
        KnotVector::new(1, vec![0.0, 0.0, 1.0, 1.0]).unwrap(),
        vec![[0.0, 0.0, 1.0]; 4],
    )
    .unwrap();
    let e = base()
        .with_term(NormalField::spline(1.0, other))
        .solve()
        .unwrap_err()
        .to_string();
    assert!(e.contains("normal field") && e.contains("domain"), "{e}");

    let frame = TensorPatch::from_fn(5, 5, |i, j| [i as f64 / 5.0, j as f64 / 5.0, 0.0]);
    let e = Problem::new((5, 5))
        .with_fixed_rings(&frame, 2)
        .with_term(Bend::new(1.0))
        .with_term(NormalField::spline(1.0, field()))
        .solve()
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("normal field") && e.contains("B-spline field"),
        "{e}"
    );
}
