//! Triangular re-solves with a kept KKT factorization
//! (`FactorCache::solve_triangular`): when only fixed values, point
//! targets, plane offsets or operator targets move, the kept factorization
//! gives the fresh solve's surface; another matrix (a turned normal, a
//! weight) is factored anew — a weight with the kept ordering (symbolic
//! analysis), only the numbers factored again; rows that turn inconsistent
//! are reported as a fresh solve reports them.

use crate::common;

use fairsurf::operator::{Operator, Target};
use fairsurf::triangle::{
    Constraint, Continuity, DomainPoint, EdgeContinuity, Factorization, Place, TriProblem,
    TriSolution,
};
use fairsurf::FactorCache;
use fairsurf::{Bend, Stretch};

/// Moves of the right-hand side only.
#[derive(Clone, Copy)]
struct Moves {
    target: f64,
    fixed: f64,
    offset: f64,
    attractor: f64,
    normal: [f64; 3],
    stretch: f64,
}

const START: Moves = Moves {
    target: 0.3,
    fixed: 0.0,
    offset: 0.1,
    attractor: 0.2,
    normal: [0.3, 0.0, 1.0],
    stretch: 0.1,
};

fn problem(m: Moves) -> TriProblem {
    let at = |triangle, bary| DomainPoint { triangle, bary };
    let surface = common::tri_grid(3, 4);
    // An interior control point of patch 7 (not on the fixed boundary).
    let interior = surface.patch_indices(7)[7];
    TriProblem::from_mesh(surface)
        .with_term(Stretch::new(m.stretch))
        .with_term(Bend::new(1.0))
        .with_fixed_boundary()
        .with_constraint(
            "pull",
            Constraint::Point {
                at: at(9, [0.3, 0.3, 0.4]),
                target: [0.55, 0.5, m.target],
            },
        )
        .with_constraint(
            "tilt",
            Constraint::Normal {
                at: at(9, [0.3, 0.3, 0.4]),
                normal: m.normal,
            },
        )
        .with_constraint(
            "shelf",
            Constraint::InPlane {
                at: at(3, [0.2, 0.5, 0.3]),
                normal: [0.0, 0.2, 1.0],
                offset: m.offset,
            },
        )
        .with_constraint(
            "pin",
            Constraint::Fixed {
                point: interior,
                value: [0.4, 0.2, m.fixed],
            },
        )
        .with_operator(Operator {
            name: "up".into(),
            target: Target::Point([0.7, 0.7, m.attractor]),
            place: Place::Point(at(14, [1.0 / 3.0; 3])),
            strength: 5.0,
            repel: false,
        })
}

/// The largest coordinate difference between two results.
fn gap(a: &TriSolution, b: &TriSolution) -> f64 {
    a.surface
        .points()
        .iter()
        .zip(b.surface.points())
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()))
        .fold(0.0, f64::max)
}

#[test]
fn moved_values_reuse_the_factorization() {
    let cache = FactorCache::new(4, usize::MAX);
    let first = cache.solve_triangular(&problem(START)).unwrap();
    assert!(!first.report.reused);
    assert_eq!(cache.len(), 1);
    for k in 1..=3 {
        let s = 0.1 * k as f64;
        let moved = Moves {
            target: START.target + s,
            fixed: START.fixed - s,
            offset: START.offset + 0.5 * s,
            attractor: START.attractor - s,
            ..START
        };
        let p = problem(moved);
        let got = cache.solve_triangular(&p).unwrap();
        let fresh = p.solve().unwrap();
        assert!(got.report.reused, "step {k}");
        assert!(!fresh.report.reused);
        // Counted: the kept factorization solved it, none was made.
        assert_eq!(got.figures().factorizations, 0);
        assert!(fresh.figures().factorizations >= 1);
        assert!(gap(&got, &fresh) < 1e-12, "step {k}: {}", gap(&got, &fresh));
        let (r, f) = (&got.report, &fresh.report);
        assert!((r.energy - f.energy).abs() <= 1e-12 * f.energy);
        assert!(r.max_violation <= 1e-10, "{:?}", r.constraints);
        assert!(r.kkt.unwrap().relative_residual < 1e-12);
        assert!(r.relative_gradient < 1e-10);
        assert_eq!(
            got.figures().independent_rows,
            fresh.figures().independent_rows
        );
        // The kept one moved: the surface did too.
        assert!(gap(&got, &first) > 0.01);
    }
    assert_eq!(cache.len(), 1);
}

#[test]
fn another_matrix_is_factored_anew_and_both_are_kept() {
    let cache = FactorCache::new(4, usize::MAX);
    cache.solve_triangular(&problem(START)).unwrap();
    let turned = Moves {
        normal: [0.0, 0.4, 1.0],
        ..START
    };
    let stiffer = Moves {
        stretch: 1.0,
        ..START
    };
    for (m, what) in [(turned, "a turned normal"), (stiffer, "a stretch weight")] {
        let p = problem(m);
        let got = cache.solve_triangular(&p).unwrap();
        assert!(!got.report.reused, "{what} changes the matrix");
        // A weight keeps the pattern: the ordering is reused; a turned
        // normal changes a row: everything is new.
        let symbolic = got.report.kkt.unwrap().reused_symbolic;
        assert_eq!(symbolic, what.contains("weight"), "{what}");
        assert!(gap(&got, &p.solve().unwrap()) < 1e-13);
    }
    assert_eq!(cache.len(), 3);
    // Each is found again among the kept ones.
    for m in [START, turned, stiffer] {
        let p = problem(Moves { target: 0.5, ..m });
        let got = cache.solve_triangular(&p).unwrap();
        assert!(got.report.reused);
        assert!(gap(&got, &p.solve().unwrap()) < 1e-12);
    }
    assert_eq!(cache.len(), 3);
}

/// A second point constraint at the same point is dependent while its
/// target agrees and inconsistent once it does not; the kept rows are the
/// same, so the factorization serves, and the report says what a fresh
/// solve says.
#[test]
fn rows_that_turn_inconsistent_are_reported_as_fresh() {
    let at = DomainPoint {
        triangle: 1,
        bary: [0.25, 0.25, 0.5],
    };
    let p = |z: f64| {
        TriProblem::from_mesh(common::tri_grid(2, 3))
            .with_term(Bend::new(1.0))
            .with_fixed_boundary()
            .with_continuity(Continuity::none())
            .with_constraint(
                "first",
                Constraint::Point {
                    at,
                    target: [0.4, 0.5, 0.2],
                },
            )
            .with_constraint(
                "second",
                Constraint::Point {
                    at,
                    target: [0.4, 0.5, z],
                },
            )
    };
    let cache = FactorCache::new(2, usize::MAX);
    let agree = cache.solve_triangular(&p(0.2)).unwrap().report;
    assert!(agree.triangular.unwrap().inconsistent.is_empty());
    let clash = p(0.5);
    let got = cache.solve_triangular(&clash).unwrap();
    let fresh = clash.solve().unwrap();
    assert!(got.report.reused);
    assert_eq!(got.figures().inconsistent, fresh.figures().inconsistent);
    assert_eq!(got.figures().inconsistent.len(), 1);
    assert_eq!(got.figures().inconsistent[0].name, "second, z");
    assert!(gap(&got, &fresh) < 1e-13);
}

/// When the strict row tolerance failed only for the right-hand side's sake
/// (refinement stalling above 1e-12 on nearly dependent G1 conditions), a
/// fresh solve of another right-hand side might not need the looser one:
/// such a factorization is not kept, and the next solve factors anew, to
/// the same answer as a fresh solve.
#[test]
fn a_looser_tolerance_chosen_for_the_right_hand_side_is_not_reused() {
    let bump = |x: f64, y: f64| 0.2 * (3.0 * x).sin() * (2.0 * y + 0.5).cos();
    // The same sheet, pulled at one point to a target that moves: only the
    // right-hand side differs.
    let sheet = |z: f64| {
        let mut s = common::tri_grid(8, 3);
        let pts: Vec<_> = s
            .points()
            .iter()
            .map(|p| [p[0], p[1], bump(p[0], p[1])])
            .collect();
        s.set_points(pts).unwrap();
        TriProblem::from_mesh(s)
            .with_term(Stretch::new(0.1))
            .with_term(Bend::new(1.0))
            .with_fixed_boundary()
            .with_constraint(
                "pull",
                Constraint::Point {
                    at: DomainPoint {
                        triangle: 40,
                        bary: [1.0 / 3.0; 3],
                    },
                    target: [0.5, 0.3, z],
                },
            )
    };
    let cache = FactorCache::new(4, usize::MAX);
    let first = cache.solve_triangular(&sheet(0.1)).unwrap();
    assert!(
        first.figures().row_tolerance > 1e-9,
        "{}",
        first.figures().row_tolerance
    );
    assert!(
        cache.is_empty(),
        "kept although chosen for this right-hand side"
    );
    let p = sheet(0.2);
    let again = cache.solve_triangular(&p).unwrap();
    assert!(!again.report.reused);
    let fresh = p.solve().unwrap();
    assert_eq!(again.figures().row_tolerance, fresh.figures().row_tolerance);
    assert!(gap(&again, &fresh) < 1e-13);
}

/// A problem of a stretch weight and a height.
type Variant = dyn Fn(f64, f64) -> TriProblem;

/// A weight slider keeps the ordering: for each kind of factorization that
/// has a symbolic part (sparse Cholesky of one matrix for x, y and z; the
/// null-space elimination of G1 at the vertices; the KKT LDLᵀ), a changed
/// stretch weight refactors the numbers only (counted in the report), to
/// the fresh solve's surface; a moved point then reuses the numbers too.
#[test]
fn a_weight_change_keeps_the_ordering() {
    let g1_vertices = Continuity {
        vertices: true,
        edges: EdgeContinuity::Off,
        boundary_angles: Vec::new(),
        boundary_rules: Vec::new(),
    };
    // The boundary fixed, an interior control point pinned at height z.
    let pinned = |continuity: Continuity, stretch: f64, z: f64| {
        let grid = common::tri_grid(4, 3);
        let point = grid.patch_indices(9)[7];
        TriProblem::from_mesh(grid)
            .with_term(Stretch::new(stretch))
            .with_term(Bend::new(1.0))
            .with_fixed_boundary()
            .with_continuity(continuity)
            .with_constraint(
                "pin",
                Constraint::Fixed {
                    point,
                    value: [0.5, 0.4, z],
                },
            )
    };
    let kinds: [(&str, Box<Variant>); 3] = [
        (
            "C0",
            Box::new(move |stretch, z| pinned(Continuity::none(), stretch, z)),
        ),
        (
            "G1 at the vertices",
            Box::new(move |stretch, z| pinned(g1_vertices.clone(), stretch, z)),
        ),
        (
            "constraints",
            Box::new(|stretch, z| {
                problem(Moves {
                    stretch,
                    target: z,
                    ..START
                })
            }),
        ),
    ];
    let mut seen = Vec::new();
    for (what, p) in &kinds {
        let cache = FactorCache::new(4, usize::MAX);
        let first = cache.solve_triangular(&p(0.1, 0.2)).unwrap().report;
        let k = first.kkt.unwrap();
        assert!(!k.reused_symbolic && !first.reused, "{what}");
        seen.push(k.factorization);
        let heavier = p(0.7, 0.2);
        let got = cache.solve_triangular(&heavier).unwrap();
        let k2 = got.report.kkt.unwrap();
        assert!(k2.reused_symbolic, "{what}: the ordering was not kept");
        assert!(!got.report.reused, "{what}");
        assert_eq!(k2.factorization, k.factorization, "{what}");
        assert_eq!(k2.factor_nonzeros, k.factor_nonzeros, "{what}");
        let fresh = heavier.solve().unwrap();
        assert!(!fresh.report.kkt.unwrap().reused_symbolic);
        assert!(gap(&got, &fresh) < 1e-12, "{what}: {}", gap(&got, &fresh));
        assert!(got.report.check.unwrap().passed());
        // The same weight again with a moved point: the numbers serve too.
        let moved = cache.solve_triangular(&p(0.7, 0.35)).unwrap();
        assert!(moved.report.reused, "{what}");
        assert!(gap(&moved, &p(0.7, 0.35).solve().unwrap()) < 1e-12);
    }
    assert!(seen.contains(&Factorization::Llt), "{seen:?}");
    assert!(seen.contains(&Factorization::NullSpace), "{seen:?}");
    assert!(seen.contains(&Factorization::Ldlt), "{seen:?}");
}
