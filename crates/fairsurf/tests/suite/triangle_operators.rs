//! External energy operators on triangular surfaces (Veltkamp & Wesselink
//! §5–6): region energies equal independent quadrature, stronger operators
//! meet their targets better, regions split across patches equal regions
//! split by hand, repellors converge by Newton's method.

use crate::common;

use fairsurf::basis::polygon::{fan_rule, Uv};
use fairsurf::triangle::{
    Continuity, DomainPoint, EdgeContinuity, Operator, Place, RegionPiece, Target, TriProblem,
    TriSolution,
};
use fairsurf::vector::{dot, norm, sub};
use fairsurf::{Bend, Stretch};
use fairsurf::{BezierCurve, Error, TriPatch, TriSurface};

fn grid(m: usize, n: usize) -> TriSurface {
    common::tri_grid(m, n)
}

fn op(name: &str, target: Target, place: Place, strength: f64) -> Operator {
    common::attractor(name, target, place, strength)
}

fn solve(ops: &[Operator]) -> TriSolution {
    let mut p = TriProblem::from_mesh(grid(3, 3))
        .with_term(Stretch::new(0.1))
        .with_term(Bend::new(1.0))
        .with_fixed_boundary()
        .with_continuity(Continuity {
            edges: EdgeContinuity::Relaxed,
            ..Continuity::default()
        });
    for o in ops {
        p = p.with_operator(o.clone());
    }
    p.solve().unwrap()
}

/// √3/2: (u, v) area to the equilateral domain's.
const AREA: f64 = 0.866_025_403_784_438_6;

fn piece() -> RegionPiece {
    RegionPiece {
        triangle: 8,
        polygon: vec![[0.1, 0.1], [0.7, 0.1], [0.5, 0.4], [0.1, 0.6]],
    }
}

fn region_integral(
    s: &TriSolution,
    piece: &RegionPiece,
    f: impl Fn(&TriPatch, [f64; 3]) -> f64,
) -> f64 {
    let patch = s.surface.patch(piece.triangle);
    let mut poly: Vec<Uv> = piece.polygon.clone();
    if fairsurf::basis::polygon::signed_area(&poly) < 0.0 {
        poly.reverse();
    }
    fan_rule(&poly, 14)
        .iter()
        .map(|(p, w)| w * AREA * f(&patch, [p[0], p[1], 1.0 - p[0] - p[1]]))
        .sum()
}

#[test]
fn region_energies_equal_independent_quadrature() {
    let target = [0.5, 0.5, 0.4];
    let n = [0.3, -0.2, 1.0];
    let nn = {
        let l = norm(n);
        [n[0] / l, n[1] / l, n[2] / l]
    };
    let s = solve(&[
        op(
            "pull",
            Target::Point(target),
            Place::Patches(vec![piece()]),
            5.0,
        ),
        op(
            "tilt",
            Target::Direction(n),
            Place::Patches(vec![piece()]),
            2.0,
        ),
        op(
            "plane",
            Target::Plane {
                normal: [0.0, 0.0, 2.0],
                offset: 0.3,
            },
            Place::Patches(vec![RegionPiece {
                triangle: 3,
                ..piece()
            }]),
            1.5,
        ),
    ]);
    let r = &s.report;
    let pull = region_integral(&s, &piece(), |p, b| {
        let d = sub(p.eval(b), target);
        dot(d, d)
    });
    assert!(
        (r.operators[0].energy - 5.0 * pull).abs() < 1e-13 * pull.max(1.0),
        "{} vs {}",
        r.operators[0].energy,
        5.0 * pull
    );
    // S_x·N and S_y·N along orthonormal directions of the equilateral domain.
    let k = 1.0 / 3.0f64.sqrt();
    let tilt = region_integral(&s, &piece(), |p, b| {
        let sx = p.directional_derivative(b, [-1.0, 1.0, 0.0]);
        let sy = p.directional_derivative(b, [-k, -k, 2.0 * k]);
        dot(sx, nn).powi(2) + dot(sy, nn).powi(2)
    });
    assert!(
        (r.operators[1].energy - 2.0 * tilt).abs() < 1e-12 * tilt.max(1.0),
        "{} vs {}",
        r.operators[1].energy,
        2.0 * tilt
    );
    let plane = region_integral(
        &s,
        &RegionPiece {
            triangle: 3,
            ..piece()
        },
        |p, b| (p.eval(b)[2] - 0.15).powi(2),
    );
    assert!((r.operators[2].energy - 1.5 * plane).abs() < 1e-13 * plane.max(1.0));
    assert!((r.external - r.operators.iter().map(|o| o.energy).sum::<f64>()).abs() < 1e-15);
    assert!((r.energy - r.term("stretch") - r.term("bend") - r.external).abs() < 1e-14 * r.energy);
    assert!(r.relative_gradient < 1e-10, "{:e}", r.relative_gradient);
}

fn measures(make: impl Fn(f64) -> Operator) -> Vec<f64> {
    [0.01, 0.1, 1.0, 10.0, 100.0]
        .iter()
        .map(|&s| solve(&[make(s)]).report.operators[0].measure)
        .collect()
}

fn strictly_falling(m: &[f64], what: &str) {
    assert!(m.windows(2).all(|w| w[1] < w[0]), "{what}: {m:?}");
}

#[test]
fn stronger_attractors_come_closer_and_stronger_directors_turn_further() {
    let at = DomainPoint {
        triangle: 8,
        bary: [0.3, 0.3, 0.4],
    };
    strictly_falling(
        &measures(|s| op("p", Target::Point([0.5, 0.5, 0.5]), Place::Point(at), s)),
        "point",
    );
    strictly_falling(
        &measures(|s| {
            op(
                "r",
                Target::Point([0.5, 0.5, 0.5]),
                Place::Patches(vec![piece()]),
                s,
            )
        }),
        "region to point",
    );
    strictly_falling(
        &measures(|s| {
            op(
                "pl",
                Target::Plane {
                    normal: [1.0, 0.0, 1.0],
                    offset: 0.8,
                },
                Place::Point(at),
                s,
            )
        }),
        "plane",
    );
    strictly_falling(
        &measures(|s| {
            op(
                "l",
                Target::Line {
                    point: [0.0, 0.0, 0.3],
                    direction: [1.0, 1.0, 0.0],
                },
                Place::Patches(vec![piece()]),
                s,
            )
        }),
        "line",
    );
    let tilted = TriPatch::from_fn(1, |i, j, _| {
        [0.3 + 0.3 * i as f64, 0.4 + 0.3 * j as f64, 0.3]
    });
    let tri = RegionPiece {
        triangle: 8,
        polygon: vec![[0.1, 0.1], [0.8, 0.1], [0.1, 0.8]],
    };
    strictly_falling(
        &measures(|s| {
            op(
                "t",
                Target::Surface(tilted.clone()),
                Place::Patches(vec![tri.clone()]),
                s,
            )
        }),
        "surface",
    );
    strictly_falling(
        &measures(|s| {
            op(
                "d",
                Target::Direction([0.5, 0.2, 1.0]),
                Place::Patches(vec![piece()]),
                s,
            )
        }),
        "director angle",
    );
    strictly_falling(
        &measures(|s| {
            op(
                "dp",
                Target::Direction([-0.4, 0.2, 1.0]),
                Place::Point(at),
                s,
            )
        }),
        "director at a point",
    );
    // An interior edge of the 3 × 3 grid toward a curve above it.
    let curve = BezierCurve::new(vec![
        [1.0 / 3.0, 1.0 / 3.0, 0.0],
        [0.5, 0.5, 0.4],
        [2.0 / 3.0, 2.0 / 3.0, 0.0],
    ]);
    strictly_falling(
        &measures(|s| op("c", Target::Curve(curve.clone()), Place::Edge([5, 10]), s)),
        "edge to curve",
    );
}

#[test]
fn a_region_across_patches_equals_the_region_split_by_hand() {
    // The rectangle [0.1, 0.25] × [0.05, 0.3] in the grid's (x, y): it
    // crosses the diagonal of the square [0, 1/3]² (triangles 0 and 1) and
    // the line y = 1/3 into triangle 7 (square (0, 1), lower half).
    let whole = Place::Domain(vec![[0.1, 0.05], [0.25, 0.05], [0.25, 0.3], [0.1, 0.3]]);
    // Triangle 0: (0,0), (1/3,0), (1/3,1/3): u = 1 − 3x, v = 3x − 3y.
    // Triangle 1: (0,0), (1/3,1/3), (0,1/3): u = 1 − 3y, v = 3x.
    let t0 = |x: f64, y: f64| [1.0 - 3.0 * x, 3.0 * x - 3.0 * y];
    let t1 = |x: f64, y: f64| [1.0 - 3.0 * y, 3.0 * x];
    let by_hand = Place::Patches(vec![
        RegionPiece {
            triangle: 0,
            polygon: vec![t0(0.1, 0.05), t0(0.25, 0.05), t0(0.25, 0.25), t0(0.1, 0.1)],
        },
        RegionPiece {
            triangle: 1,
            polygon: vec![t1(0.1, 0.1), t1(0.25, 0.25), t1(0.25, 0.3), t1(0.1, 0.3)],
        },
    ]);
    // y ≤ 0.3 < 1/3: nothing in triangle 7 after all; both ways agree on that too.
    let target = Target::Point([0.2, 0.2, 0.3]);
    let a = solve(&[op("a", target.clone(), whole, 3.0)]);
    let b = solve(&[op("b", target, by_hand, 3.0)]);
    let (ea, eb) = (a.report.operators[0].energy, b.report.operators[0].energy);
    assert!((ea - eb).abs() < 1e-13 * ea, "{ea} vs {eb}");
    for (p, q) in a.surface.points().iter().zip(b.surface.points()) {
        assert!(norm(sub(*p, *q)) < 1e-12);
    }
}

#[test]
fn a_repellor_pushes_away_and_newton_converges() {
    let at = DomainPoint {
        triangle: 8,
        bary: [0.3, 0.3, 0.4],
    };
    let mut last = 0.0;
    for s in [0.001, 0.01, 0.1] {
        let o = Operator {
            repel: true,
            ..op(
                "away",
                Target::Point([0.45, 0.5, 0.05]),
                Place::Point(at),
                s,
            )
        };
        let sol = solve(&[o]);
        let r = &sol.report;
        let nr = r.newton.expect("a repellor runs Newton's method");
        assert!(nr.relative_gradient <= 1e-9, "{nr:?}");
        assert!(nr.energy <= nr.start_energy, "{nr:?}");
        assert!(r.relative_gradient <= 1e-9);
        // Every step's KKT matrix has the first one's pattern: steps reuse
        // an earlier one's ordering (not after an LU, which keeps its own).
        assert!(nr.iterations < 2 || nr.reused_orderings >= 1, "{nr:?}");
        assert_eq!(r.operators[0].kind, "point_repellor");
        let d = r.operators[0].measure;
        assert!(d > last, "{s}: {d} after {last}");
        last = d;
        // The fixed boundary stayed put.
        assert!(r.max_violation == 0.0);
    }
}

#[test]
fn bad_operators_are_errors_naming_them() {
    let surface = grid(2, 3);
    let check = |o: Operator, needle: &str| {
        let e = TriProblem::from_mesh(surface.clone())
            .with_term(Bend::new(1.0))
            .with_fixed_boundary()
            .with_operator(o)
            .solve()
            .unwrap_err();
        let text = e.to_string();
        assert!(matches!(e, Error::Mismatch { .. }), "{text}");
        assert!(text.contains("bad") && text.contains(needle), "{text}");
    };
    let at = Place::Point(DomainPoint {
        triangle: 0,
        bary: [0.2, 0.3, 0.5],
    });
    check(
        op("bad", Target::Point([0.0; 3]), at.clone(), -1.0),
        "strength",
    );
    check(
        op("bad", Target::Direction([0.0; 3]), at.clone(), 1.0),
        "direction",
    );
    check(
        op("bad", Target::Point([f64::NAN, 0.0, 0.0]), at.clone(), 1.0),
        "point",
    );
    check(
        op(
            "bad",
            Target::Point([0.0; 3]),
            Place::Point(DomainPoint {
                triangle: 99,
                bary: [1.0, 0.0, 0.0],
            }),
            1.0,
        ),
        "triangle",
    );
    check(
        op(
            "bad",
            Target::Point([0.0; 3]),
            Place::Patches(vec![RegionPiece {
                triangle: 0,
                polygon: vec![[0.0, 0.0], [1.0, 0.0]],
            }]),
            1.0,
        ),
        "convex",
    );
    check(
        op(
            "bad",
            Target::Point([0.0; 3]),
            Place::Patches(vec![RegionPiece {
                triangle: 0,
                polygon: vec![[0.5, 0.5], [1.5, 0.5], [0.5, 1.0]],
            }]),
            1.0,
        ),
        "u + v ≤ 1",
    );
    check(
        op("bad", Target::Point([0.0; 3]), Place::Edge([0, 8]), 1.0),
        "edge",
    );
    check(
        op(
            "bad",
            Target::Curve(BezierCurve::new(vec![[0.0; 3], [1.0; 3]])),
            at.clone(),
            1.0,
        ),
        "edge",
    );
    check(
        Operator {
            repel: true,
            ..op("bad", Target::Direction([0.0, 0.0, 1.0]), at.clone(), 1.0)
        },
        "director",
    );
    check(
        op(
            "bad",
            Target::Point([0.0; 3]),
            Place::Domain(vec![[5.0, 5.0], [6.0, 5.0], [5.0, 6.0]]),
            1.0,
        ),
        "overlapping",
    );
}
