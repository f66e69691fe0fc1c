//! External energy operators on a tensor-product patch (Veltkamp &
//! Wesselink §5 with the tensor basis): region energies equal independent
//! quadrature, stronger operators meet their targets better, regions are
//! additive, repellors converge by Newton's method, the solve is
//! translation-invariant, and bad operators are refused.

use crate::common;

use fairsurf::basis::polygon::{fan_rule, Uv};
use fairsurf::operator::{Operator, PatchEdge, Target, TensorOperator, TensorPlace};
use fairsurf::vector::{add, dot, norm, normalize, sub};
use fairsurf::{Bend, BezierCurve, Error, Problem, Solution, Stretch, TensorPatch, Vec3};

/// A 5×5 bicubic-ish net (degree 4): flat square with a bent edge.
fn frame() -> TensorPatch {
    TensorPatch::from_fn(4, 4, |i, j| {
        let (u, v) = (i as f64 / 4.0, j as f64 / 4.0);
        [u, v, 0.2 * (std::f64::consts::PI * u).sin() * v]
    })
}

fn op(name: &str, target: Target, place: TensorPlace, strength: f64) -> TensorOperator {
    Operator {
        name: name.into(),
        target,
        place,
        strength,
        repel: false,
    }
}

fn problem(ops: &[TensorOperator]) -> Problem {
    let mut p = Problem::new((4, 4))
        .with_fixed_rings(&frame(), 1)
        .with_term(Stretch::new(0.1))
        .with_term(Bend::new(1.0));
    for o in ops {
        p = p.with_operator(o.clone());
    }
    p
}

fn solve(ops: &[TensorOperator]) -> Solution {
    problem(ops).solve().unwrap()
}

const REGION: [Uv; 4] = [[0.2, 0.2], [0.7, 0.25], [0.6, 0.7], [0.25, 0.6]];

/// ∫_Ω f du dv by the fan rule (Duffy), not the trapezoids the solve uses.
fn region_integral(f: impl Fn(f64, f64) -> f64) -> f64 {
    fan_rule(&REGION, 14)
        .iter()
        .map(|(p, w)| w * f(p[0], p[1]))
        .sum()
}

#[test]
fn region_energies_equal_independent_quadrature() {
    let target = [0.5, 0.5, 0.4];
    let n = normalize([0.3, -0.2, 1.0]).unwrap();
    let t_surface = TensorPatch::from_fn(2, 3, |i, j| {
        [i as f64 / 2.0, j as f64 / 3.0, 0.1 * (i + j) as f64]
    });
    let s = solve(&[
        op(
            "pull",
            Target::Point(target),
            TensorPlace::Region(REGION.to_vec()),
            2.0,
        ),
        op(
            "tilt",
            Target::Direction(n),
            TensorPlace::Region(REGION.to_vec()),
            3.0,
        ),
        op(
            "plane",
            Target::Plane {
                normal: [0.0, 0.0, 2.0],
                offset: 0.2,
            },
            TensorPlace::Region(REGION.to_vec()),
            0.5,
        ),
        op(
            "surface",
            Target::TensorSurface(t_surface.clone()),
            TensorPlace::Region(REGION.to_vec()),
            0.7,
        ),
    ]);
    let p = &s.surface;
    let ops = &s.report.operators;
    let point = 2.0
        * region_integral(|u, v| {
            let d = sub(p.eval(u, v), target);
            dot(d, d)
        });
    let director = 3.0
        * region_integral(|u, v| {
            let d = p.derivatives(u, v);
            dot(d.du, n).powi(2) + dot(d.dv, n).powi(2)
        });
    let plane = 0.5 * region_integral(|u, v| (p.eval(u, v)[2] - 0.1).powi(2));
    let surface = 0.7
        * region_integral(|u, v| {
            let d = sub(p.eval(u, v), t_surface.eval(u, v));
            dot(d, d)
        });
    for (o, want) in ops.iter().zip([point, director, plane, surface]) {
        assert!(
            (o.energy - want).abs() <= 1e-13 * want.max(1e-3),
            "{}: {} vs {want}",
            o.name,
            o.energy
        );
    }
    let internal: f64 = s.report.terms.iter().map(|t| t.value).sum();
    assert!((s.report.energy - internal - s.report.external).abs() < 1e-14);
    assert!(
        s.report.relative_gradient < 1e-13,
        "{}",
        s.report.relative_gradient
    );
    assert_eq!(s.report.basis, "bernstein");
}

/// Stronger operators meet their targets better, for every kind.
#[test]
fn raising_strength_lowers_the_measure() {
    let region = || TensorPlace::Region(REGION.to_vec());
    let at = || TensorPlace::Point([0.4, 0.55]);
    let kinds: Vec<(&str, Target, TensorPlace)> = vec![
        ("point at", Target::Point([0.4, 0.6, 0.5]), at()),
        ("point region", Target::Point([0.5, 0.5, 0.4]), region()),
        (
            "plane",
            Target::Plane {
                normal: [0.2, 0.0, 1.0],
                offset: 0.3,
            },
            region(),
        ),
        (
            "line",
            Target::Line {
                point: [0.0, 0.5, 0.3],
                direction: [1.0, 0.2, 0.0],
            },
            region(),
        ),
        (
            "surface",
            Target::TensorSurface(TensorPatch::from_fn(1, 1, |i, j| [i as f64, j as f64, 0.3])),
            region(),
        ),
        (
            "director region",
            Target::Direction([0.5, 0.0, 1.0]),
            region(),
        ),
        ("director at", Target::Direction([0.0, 0.6, 1.0]), at()),
    ];
    for (name, target, place) in kinds {
        let measures: Vec<f64> = [0.1, 1.0, 10.0, 100.0]
            .iter()
            .map(|&s| {
                let sol = solve(&[op(name, target.clone(), place.clone(), s)]);
                assert!(sol.report.relative_gradient < 1e-12, "{name}");
                sol.report.operators[0].measure
            })
            .collect();
        for w in measures.windows(2) {
            assert!(w[1] < w[0], "{name}: {measures:?}");
        }
    }
}

/// An edge with free control points (only the corners fixed) follows a
/// curve more closely as the attractor grows.
#[test]
fn edge_to_curve_attractor() {
    let f = frame();
    let mut known = vec![None; 25];
    for (i, j) in [(0, 0), (0, 4), (4, 0), (4, 4)] {
        known[i * 5 + j] = Some(f.point(i, j));
    }
    let curve = BezierCurve::new(vec![[0.0, 0.0, 0.0], [0.0, 0.5, 0.6], [0.0, 1.0, 0.0]]);
    let measures: Vec<f64> = [0.1, 1.0, 10.0, 100.0]
        .iter()
        .map(|&s| {
            let sol = Problem::new((4, 4))
                .with_known(known.clone())
                .unwrap()
                .with_term(Stretch::new(1.0))
                .with_operator(op(
                    "edge",
                    Target::Curve(curve.clone()),
                    TensorPlace::Edge(PatchEdge::U0),
                    s,
                ))
                .solve()
                .unwrap();
            // The u = 0 edge is the curve of P_0j: its rms distance to the
            // target by the midpoint rule agrees with the report's.
            let edge = BezierCurve::new((0..5).map(|j| sol.surface.point(0, j)).collect());
            let k = 4000;
            let rms = ((0..k)
                .map(|i| {
                    let t = (i as f64 + 0.5) / k as f64;
                    norm(sub(edge.eval(t), curve.eval(t))).powi(2)
                })
                .sum::<f64>()
                / k as f64)
                .sqrt();
            let m = sol.report.operators[0].measure;
            assert!((rms - m).abs() < 1e-6 * m, "{rms} vs {m}");
            assert_eq!(sol.report.operators[0].at, Some(edge.eval(0.5)));
            m
        })
        .collect();
    for w in measures.windows(2) {
        assert!(w[1] < w[0], "{measures:?}");
    }
    assert!(measures[3] < 0.02, "{measures:?}");
}

/// Each outcome's `at` is a point of the result where the operator acts:
/// the surface point itself, or a point of the surface over the region.
#[test]
fn outcomes_say_where_they_act() {
    let target = Target::Point([0.5, 0.5, 0.4]);
    let sol = solve(&[
        op(
            "point",
            target.clone(),
            TensorPlace::Point([0.4, 0.55]),
            5.0,
        ),
        op("region", target, TensorPlace::Region(REGION.to_vec()), 5.0),
    ]);
    let ops = &sol.report.operators;
    assert_eq!(ops[0].at, Some(sol.surface.eval(0.4, 0.55)));
    let at = ops[1].at.unwrap();
    // Within the sampling error of a fine grid over the region.
    let inside = |u: f64, v: f64| {
        (0..4).all(|k| {
            let (a, b) = (REGION[k], REGION[(k + 1) % 4]);
            (b[0] - a[0]) * (v - a[1]) - (b[1] - a[1]) * (u - a[0]) >= 0.0
        })
    };
    let k = 400;
    let nearest = (0..=k)
        .flat_map(|i| (0..=k).map(move |j| (i as f64 / k as f64, j as f64 / k as f64)))
        .filter(|&(u, v)| inside(u, v))
        .map(|(u, v)| norm(sub(sol.surface.eval(u, v), at)))
        .fold(f64::INFINITY, f64::min);
    assert!(
        nearest < 5e-3,
        "{at:?} is {nearest} from the surface over the region"
    );
    // Near the middle of the region, not at any node of it: within a node
    // spacing or so of the surface over the region's vertex mean.
    let c = REGION
        .iter()
        .fold([0.0; 2], |m, p| [m[0] + p[0] / 4.0, m[1] + p[1] / 4.0]);
    let middle = norm(sub(sol.surface.eval(c[0], c[1]), at));
    assert!(middle < 0.06, "{at:?} is {middle} from the region's middle");
    let corner = norm(sub(sol.surface.eval(REGION[0][0], REGION[0][1]), at));
    assert!(corner > 0.2, "{corner}");
}

/// Splitting a region in two gives two operators whose energies add up to
/// the whole one's and the same surface.
#[test]
fn regions_are_additive() {
    let whole = [[0.1, 0.1], [0.8, 0.1], [0.8, 0.7], [0.1, 0.7]];
    let left = [[0.1, 0.1], [0.45, 0.1], [0.45, 0.7], [0.1, 0.7]];
    let right = [[0.45, 0.1], [0.8, 0.1], [0.8, 0.7], [0.45, 0.7]];
    let t = Target::Point([0.5, 0.4, 0.5]);
    let a = solve(&[op(
        "whole",
        t.clone(),
        TensorPlace::Region(whole.to_vec()),
        3.0,
    )]);
    let b = solve(&[
        op("left", t.clone(), TensorPlace::Region(left.to_vec()), 3.0),
        op("right", t, TensorPlace::Region(right.to_vec()), 3.0),
    ]);
    assert!(common::max_dist(&a.surface, &b.surface) < 1e-13);
    let split: f64 = b.report.operators.iter().map(|o| o.energy).sum();
    assert!((a.report.external - split).abs() < 1e-13 * split);
}

/// Moving the frame and every target by the same vector moves the result.
#[test]
fn translation_invariance() {
    let shift: Vec3 = [3.0, -2.0, 5.0];
    let ops = |d: Vec3| {
        vec![
            op(
                "p",
                Target::Point(add([0.5, 0.5, 0.4], d)),
                TensorPlace::Point([0.5, 0.5]),
                4.0,
            ),
            op(
                "plane",
                Target::Plane {
                    normal: [0.0, 1.0, 1.0],
                    offset: 0.3 + d[1] + d[2],
                },
                TensorPlace::Region(REGION.to_vec()),
                1.0,
            ),
            op(
                "dir",
                Target::Direction([0.2, 0.1, 1.0]),
                TensorPlace::Region(REGION.to_vec()),
                1.0,
            ),
        ]
    };
    let a = solve(&ops([0.0; 3]));
    let moved = frame().map(|p| add(*p, shift));
    let mut p = Problem::new((4, 4))
        .with_fixed_rings(&moved, 1)
        .with_term(Stretch::new(0.1))
        .with_term(Bend::new(1.0));
    for o in ops(shift) {
        p = p.with_operator(o);
    }
    let b = p.solve().unwrap();
    let back = b.surface.map(|p| sub(*p, shift));
    assert!(common::max_dist(&a.surface, &back) < 1e-12);
    assert!((a.report.external - b.report.external).abs() < 1e-10 * a.report.external);
}

#[test]
fn repellor_by_newton() {
    let target = [0.5, 0.5, -0.1];
    let mut last = 0.0;
    for s in [1e-4, 1e-3, 1e-2] {
        let mut o = op(
            "push",
            Target::Point(target),
            TensorPlace::Point([0.5, 0.5]),
            s,
        );
        o.repel = true;
        let sol = solve(&[o]);
        let n = sol.report.newton.expect("a Newton report");
        assert!(n.relative_gradient <= 1e-9, "{n:?}");
        assert!(n.energy <= n.start_energy, "{n:?}");
        assert!(sol.report.relative_gradient <= 1e-9);
        // Every step's KKT matrix has the first one's pattern (the
        // steps of one kind reuse its ordering), to the same convergence.
        assert!(
            n.iterations < 2 || n.reused_orderings >= n.iterations - 1,
            "{n:?}"
        );
        let d = sol.report.operators[0].measure;
        assert!(d > last, "{s}: {d} ≤ {last}");
        last = d;
        // The frame holds.
        for j in 0..5 {
            assert_eq!(sol.surface.point(0, j), frame().point(0, j));
        }
    }
}

#[test]
fn bad_operators_are_refused() {
    let tri =
        fairsurf::TriPatch::try_new(1, vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]).unwrap();
    let cases: Vec<(TensorOperator, &str)> = vec![
        (
            op(
                "a",
                Target::Point([0.0; 3]),
                TensorPlace::Point([1.5, 0.5]),
                1.0,
            ),
            "a: point",
        ),
        (
            op(
                "b",
                Target::Point([0.0; 3]),
                TensorPlace::Region(vec![[0.0, 0.0], [1.2, 0.0], [0.0, 1.0]]),
                1.0,
            ),
            "b: region",
        ),
        (
            op(
                "c",
                Target::Point([0.0; 3]),
                TensorPlace::Region(vec![[0.0, 0.0], [1.0, 0.0]]),
                1.0,
            ),
            "c: region",
        ),
        (
            op(
                "d",
                Target::Surface(tri),
                TensorPlace::Point([0.5, 0.5]),
                1.0,
            ),
            "d: surface",
        ),
        (
            op(
                "e",
                Target::Curve(BezierCurve::new(vec![[0.0; 3], [1.0; 3]])),
                TensorPlace::Point([0.5, 0.5]),
                1.0,
            ),
            "e: place",
        ),
        (
            op(
                "f",
                Target::Point([0.0; 3]),
                TensorPlace::Edge(PatchEdge::V1),
                1.0,
            ),
            "f: place",
        ),
        (
            op(
                "g",
                Target::Point([0.0; 3]),
                TensorPlace::Point([0.5, 0.5]),
                -1.0,
            ),
            "g: strength",
        ),
        (
            op(
                "h",
                Target::Direction([0.0; 3]),
                TensorPlace::Point([0.5, 0.5]),
                1.0,
            ),
            "h: direction",
        ),
        (
            Operator {
                repel: true,
                ..op(
                    "i",
                    Target::Direction([0.0, 0.0, 1.0]),
                    TensorPlace::Point([0.5, 0.5]),
                    1.0,
                )
            },
            "i: repel",
        ),
    ];
    for (o, want) in cases {
        match problem(&[o]).solve() {
            Err(e @ Error::Mismatch { .. }) => {
                assert!(e.to_string().contains(want), "{e} lacks {want}")
            }
            other => panic!("{want}: {other:?}"),
        }
    }
}
