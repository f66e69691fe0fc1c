//! One problem type for every tensor kind: `Problem<S>` over a Bézier patch
//! and over a B-spline surface takes the same energy terms, and each kind
//! refuses what its assembly cannot integrate, naming the term.

use crate::common;

use fairsurf::bspline::{BSplineProblem, BSplineSurface, KnotVector};
use fairsurf::energy::Measure;
use fairsurf::{
    Bend, EnergyTerm, Error, GuideSurface, NormalField, Problem, SampleGrid, Stretch, TensorPatch,
};

/// The same four terms on a Bézier patch and on the B-spline surface
/// without interior knots that is the same polynomial: the same net, and
/// the same terms in the report, in the order they were given.
#[test]
fn the_same_terms_give_the_same_surface_and_report_for_both_kinds() {
    let net = common::random_net(5, 4, 7);
    let field = common::tilted_field();
    let terms = || -> Vec<Box<dyn EnergyTerm>> {
        vec![
            Box::new(Bend::new(1.0)),
            Box::new(Stretch::new(0.25)),
            Box::new(NormalField::new(8.0, field.clone())),
            Box::new(GuideSurface::new(2.0, net.clone())),
        ]
    };
    let mut bezier = Problem::from_surface(net.clone())
        .with_free(ring_free(6, 5, 1))
        .unwrap();
    let mut spline = BSplineProblem::from_surface(BSplineSurface::from_bezier(&net))
        .with_free(ring_free(6, 5, 1))
        .unwrap();
    for t in terms() {
        bezier.push_term(t);
    }
    for t in terms() {
        spline.push_term(t);
    }
    let (a, b) = (bezier.solve().unwrap(), spline.solve().unwrap());
    let worst = common::max_distance(a.surface.points(), b.surface.points());
    assert!(worst < 1e-12, "nets differ by {worst:e}");
    let names = |r: &fairsurf::SolveReport| -> Vec<String> {
        r.terms.iter().map(|t| t.name.clone()).collect()
    };
    assert_eq!(names(&a.report), names(&b.report));
    assert_eq!(
        names(&b.report),
        ["bend", "stretch", "normal_field", "guide_surface"]
    );
    for (ta, tb) in a.report.terms.iter().zip(&b.report.terms) {
        assert!(
            (ta.value - tb.value).abs() <= 1e-11 * ta.value.abs().max(1e-12),
            "{}: {} vs {}",
            ta.name,
            ta.value,
            tb.value
        );
    }
    assert_eq!(b.report.basis, "b-spline");
}

/// `Problem::from_surface` + `with_free` is the degree constructor with
/// fixed rings: the same free set, the same solve.
#[test]
fn from_surface_is_the_degree_constructor_with_rings() {
    let net = common::random_net(4, 4, 3);
    let a = Problem::new((4, 4))
        .with_fixed_rings(&net, 2)
        .with_term(Bend::new(1.0))
        .solve()
        .unwrap();
    let p = Problem::from_surface(net.clone())
        .with_free(ring_free(5, 5, 2))
        .unwrap()
        .with_term(Bend::new(1.0));
    assert_eq!(
        p.known().iter().filter(|k| k.is_none()).count(),
        1,
        "one free point at degree 4 with two rings"
    );
    let b = p.solve().unwrap();
    assert_eq!(a.surface.points(), b.surface.points());
    // Free flags of the wrong length are refused, naming the net.
    let e = Problem::from_surface(net)
        .with_free(vec![true; 3])
        .unwrap_err()
        .to_string();
    assert!(e.contains("free flags of the 5 × 5 net"), "{e}");
}

/// A Bézier guide on a B-spline surface is the patch over the knot domain
/// mapped onto [0, 1]²: on a domain [0, 2] × [1, 3] without interior knots
/// it gives the net of the same guide as a B-spline on that domain.
#[test]
fn a_bezier_guide_on_a_bspline_is_the_patch_over_the_knot_domain() {
    let net = common::random_net(3, 3, 5);
    let guide = common::random_net(2, 3, 9);
    let clamped = |p: usize, a: f64, b: f64| {
        KnotVector::new(p, [vec![a; p + 1], vec![b; p + 1]].concat()).unwrap()
    };
    let on = |patch: &TensorPatch| {
        let (n, m) = patch.degree();
        BSplineSurface::new(
            clamped(n, 0.0, 2.0),
            clamped(m, 1.0, 3.0),
            patch.points().to_vec(),
        )
        .unwrap()
    };
    let base = || {
        BSplineProblem::from_surface(on(&net))
            .with_fixed_rings(1)
            .with_term(Bend::new(1.0))
    };
    let a = base()
        .with_term(GuideSurface::new(5.0, guide.clone()))
        .solve()
        .unwrap();
    let b = base()
        .with_term(GuideSurface::spline(5.0, on(&guide)))
        .solve()
        .unwrap();
    let worst = common::max_distance(a.surface.points(), b.surface.points());
    assert!(worst < 1e-13, "{worst:e}");
    let (ea, eb) = (
        a.report.term("guide_surface"),
        b.report.term("guide_surface"),
    );
    assert!((ea - eb).abs() < 1e-13 * eb, "{ea} vs {eb}");
    // Independently: ½γ∫∫|R(u, v) − S((u − 0)/2, (v − 1)/2)|² du dv over
    // [0, 2] × [1, 3] by an 8 × 8 Gauss rule (exact: the integrand has
    // degree 6 in u and in v), R by de Boor, S by de Casteljau.
    let g = fairsurf::basis::GaussLegendre::new(8);
    let mut quad = 0.0;
    for (&x, &wx) in g.nodes.iter().zip(&g.weights) {
        for (&y, &wy) in g.nodes.iter().zip(&g.weights) {
            let (u, v) = (2.0 * x, 1.0 + 2.0 * y);
            let d = fairsurf::vector::sub(a.surface.eval(u, v), guide.eval(x, y));
            quad += 4.0 * wx * wy * fairsurf::vector::dot(d, d);
        }
    }
    let quad = 0.5 * 5.0 * quad;
    assert!(
        (ea - quad).abs() < 1e-12 * quad,
        "{ea} vs quadrature {quad}"
    );
}

/// What a kind cannot integrate is refused by its solve, naming the term.
#[test]
fn each_kind_refuses_what_it_cannot_integrate() {
    let net = common::random_net(3, 3, 1);
    let spline =
        || BSplineProblem::from_surface(BSplineSurface::from_bezier(&net)).with_fixed_rings(1);
    let message = |p: BSplineProblem| p.solve().unwrap_err().to_string();
    // A sampled thin plate: B-spline surfaces integrate it exactly only.
    let grid = SampleGrid::new(4, 4);
    let e = message(spline().with_term(Bend::new(1.0).with_measure(Measure::Grid(grid))));
    assert!(e.contains("energy term bend") && e.contains("exact"), "{e}");
    // A sampled guide.
    let e =
        message(spline().with_term(Bend::new(1.0)).with_term(
            GuideSurface::new(1.0, net.clone()).with_measure(Measure::Grid(grid), None),
        ));
    assert!(e.contains("energy term guide_surface"), "{e}");
    // A sampled B-spline guide.
    let e = message(
        spline().with_term(Bend::new(1.0)).with_term(
            GuideSurface::spline(1.0, BSplineSurface::from_bezier(&net))
                .with_measure(Measure::Grid(grid), None),
        ),
    );
    assert!(
        e.contains("energy term guide_surface") && e.contains("sampled"),
        "{e}"
    );
    // Two normal fields, two guides.
    let field = common::tilted_field();
    let e = message(
        spline()
            .with_term(NormalField::new(1.0, field.clone()))
            .with_term(NormalField::new(2.0, field)),
    );
    assert!(e.contains("one normal field"), "{e}");
    let e = message(
        spline()
            .with_term(GuideSurface::new(1.0, net.clone()))
            .with_term(GuideSurface::new(1.0, net.clone())),
    );
    assert!(e.contains("one guide surface"), "{e}");
    // A term of one's own without an integrand.
    #[derive(Debug)]
    struct Own;
    impl EnergyTerm for Own {
        fn name(&self) -> &'static str {
            "own"
        }
        fn form_in(
            &self,
            space: &fairsurf::energy::Space,
        ) -> fairsurf::Result<fairsurf::energy::TermForm> {
            Stretch::new(1.0).form_in(space)
        }
    }
    let e = message(spline().with_term(Own));
    assert!(
        e.contains("energy term own") && e.contains("integrand"),
        "{e}"
    );
    // The Bézier patch's solve takes it (its own form) …
    let own = Problem::new((3, 3))
        .with_fixed_rings(&net, 1)
        .with_term(Own)
        .solve()
        .unwrap();
    assert!(own.report.relative_gradient < 1e-13);
    // … and refuses a B-spline guide.
    let e = Problem::new((3, 3))
        .with_fixed_rings(&net, 1)
        .with_term(Bend::new(1.0))
        .with_term(GuideSurface::spline(1.0, BSplineSurface::from_bezier(&net)))
        .solve()
        .unwrap_err();
    assert!(
        matches!(&e, Error::Mismatch { what, .. } if what == "guide surface"),
        "{e}"
    );
    // A negative weight, as for every term.
    assert!(matches!(
        spline().with_term(Stretch::new(-1.0)).solve(),
        Err(Error::NegativeWeight { .. })
    ));
}

/// Row-major free flags with the outer `k` rings of a `cu` × `cv` net
/// fixed.
fn ring_free(cu: usize, cv: usize, k: usize) -> Vec<bool> {
    (0..cu * cv)
        .map(|p| {
            let (i, j) = (p / cv, p % cv);
            i.min(j).min(cu - 1 - i).min(cv - 1 - j) >= k
        })
        .collect()
}

/// A triangular surface takes the same Stretch and Bend terms (their
/// weights add up) and refuses, naming it, any term its assembly cannot
/// integrate.
#[test]
fn a_triangular_problem_takes_the_same_terms() {
    use fairsurf::triangle::TriProblem;
    let s = common::tri_grid(2, 2);
    let lifted = {
        let mut s = s.clone();
        let pts = s
            .points()
            .iter()
            .map(|p| [p[0], p[1], (2.0 * p[0]).sin() * p[1]])
            .collect();
        s.set_points(pts).unwrap();
        s
    };
    let solve = |p: TriProblem| p.with_fixed_boundary().solve();
    let one = solve(
        TriProblem::from_mesh(lifted.clone())
            .with_term(Stretch::new(0.3))
            .with_term(Bend::new(1.0)),
    )
    .unwrap();
    let halves = solve(
        TriProblem::from_mesh(lifted.clone())
            .with_term(Bend::new(0.5))
            .with_term(Stretch::new(0.3))
            .with_term(Bend::new(0.5)),
    )
    .unwrap();
    let worst = common::max_distance(one.surface.points(), halves.surface.points());
    assert!(worst < 1e-13, "{worst:e}");
    assert!((one.report.energy - halves.report.energy).abs() < 1e-14 * one.report.energy);
    assert!(one.report.term("stretch") > 0.0 && one.report.term("bend") > 0.0);
    let message = |p: TriProblem| solve(p).unwrap_err().to_string();
    let e = message(
        TriProblem::from_mesh(lifted.clone())
            .with_term(NormalField::new(1.0, common::tilted_field())),
    );
    assert!(
        e.contains("energy term normal_field on a triangular surface"),
        "{e}"
    );
    let grid = SampleGrid::new(3, 3);
    let e = message(
        TriProblem::from_mesh(lifted.clone())
            .with_term(Bend::new(1.0).with_measure(Measure::Grid(grid))),
    );
    assert!(e.contains("energy term bend") && e.contains("exact"), "{e}");
    assert!(matches!(
        solve(TriProblem::from_mesh(lifted.clone())),
        Err(Error::NoEnergy)
    ));
    assert!(matches!(
        solve(TriProblem::from_mesh(lifted).with_term(Bend::new(-1.0))),
        Err(Error::NegativeWeight { .. })
    ));
}
