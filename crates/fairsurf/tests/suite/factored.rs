//! Reusing a factorization ([`Problem::factor`], [`Factored::solve`]): a
//! problem whose known points, guide surface, attractor targets or
//! repellors moved is solved with the old factor to the same surface as a
//! fresh solve, with the same accuracy reported; anything that changes the
//! matrix is refused with a message saying what.

use crate::common::{random_net, tilted_field};
use fairsurf::energy::{Space, TermForm};
use fairsurf::operator::{Operator, Target, TensorOperator, TensorPlace};
use fairsurf::{
    Bend, EnergyTerm, Error, GuideSurface, NormalField, Problem, Solution, SolveOptions, Stretch,
    TensorPatch,
};

/// Degree 10 with λ > 0 (coupled) and a guide surface equal to the net.
fn problem(net: &TensorPatch, rings: usize, lambda: f64) -> Problem {
    Problem::new(net.degree())
        .with_fixed_rings(net, rings)
        .with_term(Stretch::new(1.0))
        .with_term(NormalField::new(lambda, tilted_field()))
        .with_term(GuideSurface::new(0.5, net.clone()))
}

/// max |P − Q| over the control points, relative to the net's size.
fn difference(a: &Solution, b: &Solution) -> f64 {
    a.surface
        .points()
        .iter()
        .zip(b.surface.points())
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()))
        .fold(0.0, f64::max)
}

fn moved(net: &TensorPatch, seed: u64) -> TensorPatch {
    let other = random_net(net.degree().0, net.degree().1, seed);
    TensorPatch::from_fn(net.degree().0, net.degree().1, |i, j| {
        let (p, q) = (net.point(i, j), other.point(i, j));
        [p[0], p[1], p[2] + 0.5 * (q[2] - p[2])]
    })
}

#[test]
fn moved_boundary_and_guide_solve_to_the_fresh_surface() {
    let opts = SolveOptions::default();
    for (rings, tensor_basis) in [(1, true), (2, true), (1, false)] {
        let opts = SolveOptions {
            tensor_basis,
            ..opts
        };
        let net = random_net(10, 10, 7);
        let factored = problem(&net, rings, 10.0).factor(&opts).unwrap();
        for seed in [1, 2, 3] {
            let p = problem(&moved(&net, seed), rings, 10.0);
            let again = factored.solve(&p, &opts).unwrap();
            let fresh = p.solve_with(&opts).unwrap();
            assert!(again.report.reused && !fresh.report.reused);
            assert_eq!(again.report.timings.factor, 0.0);
            let d = difference(&again, &fresh);
            assert!(d < 1e-12, "rings {rings}: reused and fresh differ by {d}");
            // The same accuracy, measured on the new system.
            assert!(again.report.relative_gradient < 1e-15);
            assert!(
                (again.report.energy - fresh.report.energy).abs() <= 1e-12 * fresh.report.energy
            );
            assert_eq!(again.report.basis, fresh.report.basis);
            assert_eq!(
                again.report.condition_estimate,
                fresh.report.condition_estimate
            );
        }
        // The factored problem itself.
        let p = problem(&net, rings, 10.0);
        let d = difference(
            &factored.solve(&p, &opts).unwrap(),
            &p.solve_with(&opts).unwrap(),
        );
        assert!(d < 1e-13, "{d}");
    }
}

/// Moving an attractor's target (a point, a plane's offset, a line's point)
/// keeps the matrix; the reused solve meets the new target like a fresh one.
#[test]
fn moved_attractor_targets_reuse_the_factor() {
    let net = random_net(6, 6, 11);
    let ops = |z: f64, offset: f64| -> Vec<TensorOperator> {
        vec![
            Operator {
                name: "pull".into(),
                target: Target::Point([0.5, 0.5, z]),
                place: TensorPlace::Point([0.4, 0.6]),
                strength: 5.0,
                repel: false,
            },
            Operator {
                name: "plane".into(),
                target: Target::Plane {
                    normal: [0.0, 0.0, 1.0],
                    offset,
                },
                place: TensorPlace::Region(vec![[0.1, 0.1], [0.4, 0.1], [0.3, 0.35]]),
                strength: 2.0,
                repel: false,
            },
            Operator {
                name: "push".into(),
                target: Target::Point([0.7, 0.3, z + 0.3]),
                place: TensorPlace::Point([0.7, 0.3]),
                strength: 1e-3,
                repel: true,
            },
        ]
    };
    let build = |z, offset| {
        let mut p = Problem::new((6, 6))
            .with_fixed_rings(&net, 1)
            .with_term(Bend::new(1.0));
        for o in ops(z, offset) {
            p = p.with_operator(o);
        }
        p
    };
    let opts = SolveOptions::default();
    let factored = build(0.5, 0.1).factor(&opts).unwrap();
    for (z, offset) in [(0.9, 0.0), (-0.4, 0.3)] {
        let p = build(z, offset);
        assert!(factored.fits(&p));
        let again = factored.solve(&p, &opts).unwrap();
        let fresh = p.solve_with(&opts).unwrap();
        assert!(again.report.reused);
        assert!(
            again.report.newton.is_some(),
            "the repellor still runs Newton"
        );
        let d = difference(&again, &fresh);
        assert!(d < 1e-10, "z {z}: reused and fresh differ by {d}");
        for (a, b) in again.report.operators.iter().zip(&fresh.report.operators) {
            assert!((a.energy - b.energy).abs() <= 1e-9 * b.energy.abs().max(1e-12));
        }
    }
}

/// A term that keeps the default `hessian_key` (None).
#[derive(Debug)]
struct Opaque(Stretch);

impl EnergyTerm for Opaque {
    fn name(&self) -> &'static str {
        "opaque"
    }
    fn form_in(&self, space: &Space) -> fairsurf::Result<TermForm> {
        self.0.form_in(space)
    }
}

fn mismatch(factored: &fairsurf::Factored, p: &Problem, needle: &str) {
    assert!(!factored.fits(p));
    match factored.solve(p, &SolveOptions::default()) {
        Err(Error::Mismatch { got, .. }) => assert!(got.contains(needle), "{got}"),
        other => panic!("expected a mismatch naming {needle:?}, got {other:?}"),
    }
}

#[test]
fn another_matrix_is_refused_saying_what_differs() {
    let net = random_net(5, 5, 3);
    let opts = SolveOptions::default();
    let factored = problem(&net, 1, 1.0).factor(&opts).unwrap();
    assert!(factored.fits(&problem(&moved(&net, 9), 1, 1.0)));
    mismatch(&factored, &problem(&net, 1, 2.0), "term 1 (normal_field");
    mismatch(
        &factored,
        &problem(&net, 2, 1.0),
        "control point (1, 1) is known",
    );
    mismatch(&factored, &problem(&random_net(5, 4, 3), 1, 1.0), "degree");
    let fewer = Problem::new((5, 5))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0));
    mismatch(&factored, &fewer, "1 energy terms instead of 3");
    let other_field = Problem::new((5, 5))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0))
        .with_term(NormalField::new(1.0, random_net(2, 2, 1)))
        .with_term(GuideSurface::new(0.5, net.clone()));
    mismatch(&factored, &other_field, "term 1 (normal_field");
    let attracted = problem(&net, 1, 1.0).with_operator(Operator {
        name: "pull".into(),
        target: Target::Point([0.0, 0.0, 1.0]),
        place: TensorPlace::Point([0.5, 0.5]),
        strength: 1.0,
        repel: false,
    });
    mismatch(
        &factored,
        &attracted,
        "1 attractors and directors instead of 0",
    );
    // An attractor moved to another (u, v) changes the matrix.
    let at = |uv, strength| {
        Problem::new((5, 5))
            .with_fixed_rings(&net, 1)
            .with_term(Bend::new(1.0))
            .with_operator(Operator {
                name: "pull".into(),
                target: Target::Point([0.0, 0.0, 1.0]),
                place: TensorPlace::Point(uv),
                strength,
                repel: false,
            })
    };
    let f = at([0.5, 0.5], 1.0).factor(&opts).unwrap();
    mismatch(&f, &at([0.5, 0.6], 1.0), "attractor or director 0");
    mismatch(&f, &at([0.5, 0.5], 2.0), "attractor or director 0");
    assert!(f.fits(&at([0.5, 0.5], 1.0)));
    // A term that cannot tell is never reused, even when unchanged.
    let opaque = |net: &TensorPatch| {
        Problem::new((5, 5))
            .with_fixed_rings(net, 1)
            .with_term(Opaque(Stretch::new(1.0)))
    };
    let f = opaque(&net).factor(&opts).unwrap();
    mismatch(&f, &opaque(&net), "cannot tell");
    // …but solves the problem it came from through Problem::solve.
    assert!(opaque(&net).solve().unwrap().report.relative_gradient < 1e-15);
}

#[test]
fn bad_values_are_errors_not_mismatches() {
    let net = random_net(4, 4, 5);
    let factored = problem(&net, 1, 1.0)
        .factor(&SolveOptions::default())
        .unwrap();
    let mut p = problem(&net, 1, 1.0);
    p.fix(0, 2, [f64::NAN, 0.0, 0.0]);
    assert!(matches!(
        factored.solve(&p, &SolveOptions::default()),
        Err(Error::NotFinite { .. })
    ));
    // A guide surface of too high a degree is the term's own error.
    let p = Problem::new((4, 4))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0))
        .with_term(NormalField::new(1.0, tilted_field()))
        .with_term(GuideSurface::new(0.5, random_net(5, 5, 1)));
    assert!(matches!(
        factored.solve(&p, &SolveOptions::default()),
        Err(Error::Mismatch { what, .. }) if what == "guide surface degree"
    ));
}
