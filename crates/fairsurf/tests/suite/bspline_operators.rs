//! External energy operators on B-spline surfaces (Veltkamp & Wesselink §5
//! with the basis N_i,p(u)·N_j,q(v)): a B-spline without interior knots
//! gives the tensor solve's surface with the same operators (another
//! implementation: the tensor place, the dense solve); on many spans, a
//! region that crosses knot lines has the energy an independent quadrature
//! gives (Gauss rules on the sub-rectangles the knots cut it into); no
//! perturbation lowers the total energy; bad operators are refused, naming
//! them.

use crate::common;

use fairsurf::basis::GaussLegendre;
use fairsurf::bspline::{BSplineProblem, BSplineSurface, KnotVector};
use fairsurf::operator::{PatchEdge, Target, TensorOperator, TensorPlace};
use fairsurf::vector::{dot, normalize};
use fairsurf::{Bend, BezierCurve, Problem, Stretch, TensorPatch, Vec3};

fn op(name: &str, target: Target, place: TensorPlace, strength: f64) -> TensorOperator {
    common::attractor(name, target, place, strength)
}

/// A point, a director, a plane, a line and a surface attractor.
fn operators() -> Vec<TensorOperator> {
    let region = vec![[0.2, 0.2], [0.7, 0.25], [0.6, 0.7], [0.25, 0.6]];
    vec![
        op(
            "pull",
            Target::Point([0.4, 0.45, 0.3]),
            TensorPlace::Point([0.4, 0.45]),
            50.0,
        ),
        op(
            "tilt",
            Target::Direction([0.3, -0.2, 1.0]),
            TensorPlace::Region(region.clone()),
            3.0,
        ),
        op(
            "shelf",
            Target::Plane {
                normal: [0.0, 0.0, 2.0],
                offset: 0.1,
            },
            TensorPlace::Region(vec![[0.6, 0.6], [0.9, 0.6], [0.9, 0.9]]),
            20.0,
        ),
        op(
            "rail",
            Target::Line {
                point: [0.8, 0.2, 0.0],
                direction: [0.0, 0.0, 1.0],
            },
            TensorPlace::Point([0.8, 0.2]),
            30.0,
        ),
        op(
            "sheet",
            Target::TensorSurface(TensorPatch::from_fn(2, 1, |i, j| {
                [i as f64 / 2.0, j as f64, 0.1 * i as f64]
            })),
            TensorPlace::Region(vec![[0.1, 0.7], [0.4, 0.7], [0.4, 0.95], [0.1, 0.95]]),
            5.0,
        ),
    ]
}

/// A degree-5 Bézier net over the unit square with a bent edge.
fn frame() -> TensorPatch {
    TensorPatch::from_fn(5, 5, |i, j| {
        let (u, v) = (i as f64 / 5.0, j as f64 / 5.0);
        [u, v, 0.2 * (std::f64::consts::PI * u).sin() * v]
    })
}

fn with_all(mut p: BSplineProblem, ops: &[TensorOperator]) -> BSplineProblem {
    for o in ops {
        p = p.with_operator(o.clone());
    }
    p
}

#[test]
fn a_bezier_knot_bspline_gives_the_tensor_solve_surface() {
    let ops = operators();
    let mut tensor = Problem::new((5, 5))
        .with_fixed_rings(&frame(), 1)
        .with_term(Stretch::new(0.1))
        .with_term(Bend::new(1.0));
    for o in &ops {
        tensor = tensor.with_operator(o.clone());
    }
    let t = tensor.solve().unwrap();
    let base = BSplineProblem::from_surface(BSplineSurface::from_bezier(&frame()))
        .with_fixed_rings(1)
        .with_term(Stretch::new(0.1))
        .with_term(Bend::new(1.0));
    let s = with_all(base, &ops).solve().unwrap();
    let worst = common::max_distance(t.surface.points(), s.surface.points());
    assert!(worst < 1e-10, "nets differ by {worst:e}");
    let r = &s.report;
    assert!((t.report.energy - r.energy).abs() < 1e-11 * t.report.energy);
    assert!((t.report.external - r.external).abs() < 1e-11 * t.report.external);
    assert_eq!(r.operators.len(), ops.len());
    for (a, b) in t.report.operators.iter().zip(&r.operators) {
        assert_eq!((&a.name, &a.kind), (&b.name, &b.kind));
        assert!(
            (a.energy - b.energy).abs() < 1e-10 * a.energy.max(1e-12),
            "{a:?} {b:?}"
        );
        assert!((a.measure - b.measure).abs() < 1e-9, "{a:?} {b:?}");
    }
    assert!(r.coupled && r.check.unwrap().energy_error < 1e-12 && r.check.unwrap().excess < 1e-10);
}

/// A bicubic surface of 6 × 5 uneven spans over [0, 2] × [0, 1], wavy.
fn sheet() -> BSplineSurface {
    let u = KnotVector::new(
        3,
        vec![0., 0., 0., 0., 0.3, 0.7, 1.0, 1.3, 1.6, 2., 2., 2., 2.],
    )
    .unwrap();
    common::graph_bspline(u, KnotVector::uniform(3, 5), |x, y| {
        0.15 * (2.0 * x).sin() * (3.0 * y).cos()
    })
}

/// ∫ f over the rectangle [a, b] × [c, d], cut at the surface's knots
/// (one polynomial per piece), by 12 × 12 Gauss points per piece.
fn rectangle_integral(
    s: &BSplineSurface,
    [a, b, c, d]: [f64; 4],
    f: impl Fn(f64, f64) -> f64,
) -> f64 {
    let cuts = |knots: &[f64], lo: f64, hi: f64| -> Vec<f64> {
        let mut x: Vec<f64> = std::iter::once(lo)
            .chain(knots.iter().copied().filter(|&k| lo < k && k < hi))
            .chain(std::iter::once(hi))
            .collect();
        x.dedup();
        x
    };
    let (ku, kv) = s.knots();
    let (us, vs) = (cuts(ku.knots(), a, b), cuts(kv.knots(), c, d));
    let g = GaussLegendre::new(12);
    let mut total = 0.0;
    for wu in us.windows(2) {
        for wv in vs.windows(2) {
            for (x, wx) in g.nodes.iter().zip(&g.weights) {
                for (y, wy) in g.nodes.iter().zip(&g.weights) {
                    let (u, v) = (wu[0] + (wu[1] - wu[0]) * x, wv[0] + (wv[1] - wv[0]) * y);
                    total += wx * wy * (wu[1] - wu[0]) * (wv[1] - wv[0]) * f(u, v);
                }
            }
        }
    }
    total
}

#[test]
fn regions_across_knot_lines_have_the_independent_quadratures_energy() {
    let rect = [0.25, 1.45, 0.15, 0.85];
    let region = vec![[0.25, 0.15], [1.45, 0.15], [1.45, 0.85], [0.25, 0.85]];
    let n = normalize([0.3, -0.2, 1.0]).unwrap();
    let ops = vec![
        op(
            "plane",
            Target::Plane {
                normal: [0.0, 0.0, 2.0],
                offset: 0.1,
            },
            TensorPlace::Region(region.clone()),
            20.0,
        ),
        op(
            "tilt",
            Target::Direction(n),
            TensorPlace::Region(region),
            3.0,
        ),
    ];
    let problem = with_all(
        BSplineProblem::from_surface(sheet())
            .with_fixed_rings(2)
            .with_term(Bend::new(1.0)),
        &ops,
    );
    let sol = problem.solve().unwrap();
    let s = &sol.surface;
    let plane = 20.0 * rectangle_integral(s, rect, |u, v| (s.eval(u, v)[2] - 0.05).powi(2));
    let tilt = 3.0
        * rectangle_integral(s, rect, |u, v| {
            let d = s.derivatives(u, v);
            dot(d.du, n).powi(2) + dot(d.dv, n).powi(2)
        });
    let got: Vec<f64> = sol.report.operators.iter().map(|o| o.energy).collect();
    assert!(
        (got[0] - plane).abs() < 1e-12 * plane,
        "{} vs {plane}",
        got[0]
    );
    assert!((got[1] - tilt).abs() < 1e-12 * tilt, "{} vs {tilt}", got[1]);
    assert!((sol.report.external - plane - tilt).abs() < 1e-12 * (plane + tilt));
    // The solve is the minimum of the total energy: random moves of the
    // free points raise it.
    let e0 = problem.energy_at(s).unwrap();
    assert!((e0 - sol.report.energy).abs() < 1e-12 * e0);
    let free: Vec<usize> = (0..problem.free().len())
        .filter(|&k| problem.free()[k])
        .collect();
    let (ku, kv) = s.knots();
    let mut seed = 99u64;
    for trial in 0..6 {
        let mut points: Vec<Vec3> = s.points().to_vec();
        for &g in &free {
            for c in 0..3 {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                points[g][c] += 1e-3 * ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
            }
        }
        let moved = BSplineSurface::new(ku.clone(), kv.clone(), points).unwrap();
        let e = problem.energy_at(&moved).unwrap();
        assert!(e > e0, "trial {trial}: {e} ≤ {e0}");
    }
}

/// A repellor (s/E_attr, Newton's method on the total energy): a B-spline
/// without interior knots gives the tensor solve's net (its Newton on the
/// dense system) and energy; the surface moves away from the point.
#[test]
fn a_repellor_pushes_like_the_tensor_solves() {
    let mut push = op(
        "push",
        Target::Point([0.5, 0.5, -0.1]),
        TensorPlace::Point([0.5, 0.5]),
        0.05,
    );
    push.repel = true;
    let t = Problem::new((5, 5))
        .with_fixed_rings(&frame(), 1)
        .with_term(Bend::new(1.0))
        .with_operator(push.clone())
        .solve()
        .unwrap();
    let base = || {
        BSplineProblem::from_surface(BSplineSurface::from_bezier(&frame()))
            .with_fixed_rings(1)
            .with_term(Bend::new(1.0))
    };
    let plain = base().solve().unwrap();
    let s = with_all(base(), &[push]).solve().unwrap();
    let worst = common::max_distance(t.surface.points(), s.surface.points());
    assert!(worst < 1e-8, "nets differ by {worst:e}");
    assert!((t.report.energy - s.report.energy).abs() < 1e-10 * t.report.energy);
    let n = s.report.newton.expect("Newton's report");
    assert!(n.iterations > 0 && n.relative_gradient < 1e-9, "{n:?}");
    assert!(n.energy <= n.start_energy);
    let dz = |x: &BSplineSurface| x.eval(0.5, 0.5)[2];
    assert!(dz(&s.surface) > dz(&plain.surface) + 1e-3);
}

/// The ring fixed but the inner points of one boundary edge (u = 0 with
/// `along_v`, else v = 0), the rest free.
fn free_edge(s: &BSplineSurface, along_v: bool) -> Vec<bool> {
    let (cu, cv) = s.counts();
    (0..cu * cv)
        .map(|k| {
            let (i, j) = (k / cv, k % cv);
            let ring = i == 0 || j == 0 || i == cu - 1 || j == cv - 1;
            let inner = if along_v {
                i == 0 && j > 0 && j < cv - 1
            } else {
                j == 0 && i > 0 && i < cu - 1
            };
            !ring || inner
        })
        .collect()
}

/// ∫₀¹ |E(τ) − C(τ)|² dτ along the u = 0 edge (`along_v`) or the v = 0
/// edge of `s`, τ the edge's parameter mapped onto [0, 1], by 40 midpoints
/// per span of the surface evaluated.
fn edge_integral(s: &BSplineSurface, c: &BezierCurve, along_v: bool) -> f64 {
    let knots = if along_v { s.knots().1 } else { s.knots().0 };
    let (a, b) = knots.domain();
    let mut integral = 0.0;
    for &(_, lo, hi) in &knots.spans() {
        let k = 40;
        for i in 0..k {
            let t = lo + (hi - lo) * (i as f64 + 0.5) / k as f64;
            let e = if along_v {
                s.eval(a, t)
            } else {
                s.eval(t, 0.0)
            };
            let d = fairsurf::vector::sub(e, c.eval((t - a) / (b - a)));
            integral += dot(d, d) * (hi - lo) / ((b - a) * k as f64);
        }
    }
    integral
}

/// An edge-to-curve attractor on a free edge (the other points of the
/// edge free, the rest of the ring fixed): without interior knots the
/// tensor solve's net and energy (its Bernstein edge rule); on many spans
/// the report's energy is ∫₀¹ |E(τ) − C(τ)|² dτ by an independent rule
/// (the boundary curve evaluated on the surface, 40 midpoints per span:
/// to 1e-3), and the edge follows the curve more closely as the strength
/// grows.
#[test]
fn an_edge_attractor_pulls_a_boundary_curve() {
    let curve = BezierCurve::new(vec![[0.0, 0.0, 0.0], [0.0, 0.5, 0.6], [0.0, 1.0, 0.0]]);
    let hem = |s: f64| {
        op(
            "hem",
            Target::Curve(curve.clone()),
            TensorPlace::Edge(PatchEdge::U0),
            s,
        )
    };
    // Degree 5, no interior knots: ring 1 fixed but the u = 0 edge's
    // inner points.
    let f = frame();
    let mut known: Vec<Option<Vec3>> = vec![None; 36];
    let mut free = vec![true; 36];
    for i in 0..6 {
        for j in 0..6 {
            let ring = i == 0 || j == 0 || i == 5 || j == 5;
            let loose = i == 0 && (1..5).contains(&j);
            if ring && !loose {
                known[i * 6 + j] = Some(f.point(i, j));
                free[i * 6 + j] = false;
            }
        }
    }
    let t = Problem::new((5, 5))
        .with_known(known)
        .unwrap()
        .with_term(Bend::new(1.0))
        .with_operator(hem(20.0))
        .solve()
        .unwrap();
    let b = BSplineProblem::from_surface(BSplineSurface::from_bezier(&f))
        .with_free(free)
        .unwrap()
        .with_term(Bend::new(1.0))
        .with_operator(hem(20.0))
        .solve()
        .unwrap();
    let worst = common::max_distance(t.surface.points(), b.surface.points());
    assert!(worst < 1e-9, "nets differ by {worst:e}");
    let (et, eb) = (t.report.external, b.report.external);
    assert!((et - eb).abs() < 1e-9 * et, "{et} vs {eb}");

    // Many spans: the sheet (knot domain [0, 2] × [0, 1]), the u = 0 edge
    // free but its ends.
    let s0 = sheet();
    let free = free_edge(&s0, true);
    let (mut first, mut last) = (f64::NAN, f64::INFINITY);
    for strength in [1.0, 10.0, 100.0] {
        let sol = BSplineProblem::from_surface(s0.clone())
            .with_free(free.clone())
            .unwrap()
            .with_term(Bend::new(1.0))
            .with_operator(hem(strength))
            .solve()
            .unwrap();
        let r = &sol.report;
        assert!(
            r.check.unwrap().energy_error < 1e-12 && r.check.unwrap().excess < 1e-10,
            "{r:?}"
        );
        let want = strength * edge_integral(&sol.surface, &curve, true);
        assert!(
            (r.external - want).abs() < 1e-3 * want,
            "{strength}: {} vs {want}",
            r.external
        );
        let m = r.operators[0].measure;
        assert!(m < last, "{strength}: {m} not below {last}");
        if strength == 1.0 {
            first = m;
        }
        last = m;
    }
    // Strength 1 leaves the edge 0.21 (rms) from the curve, 100: 0.042.
    assert!(last < 0.25 * first, "{last} vs {first}");
}

/// On the v = 0 edge of the sheet (u over [0, 2]) the curve lives on the
/// edge's parameter mapped onto [0, 1]: the report's energy is
/// ∫₀¹ |E(2τ) − C(τ)|² dτ by an independent midpoint rule (1e-3); the
/// operator is marked at the edge's midpoint.
#[test]
fn an_edge_attractor_along_a_wider_knot_domain() {
    let curve = BezierCurve::new(vec![[0.0, 0.0, 0.0], [1.0, -0.4, 0.3], [2.0, 0.0, 0.0]]);
    let s0 = sheet();
    let free = free_edge(&s0, false);
    let strength = 10.0;
    let sol = BSplineProblem::from_surface(s0)
        .with_free(free)
        .unwrap()
        .with_term(Bend::new(1.0))
        .with_operator(op(
            "hem",
            Target::Curve(curve.clone()),
            TensorPlace::Edge(PatchEdge::V0),
            strength,
        ))
        .solve()
        .unwrap();
    let r = &sol.report;
    assert!(
        r.check.unwrap().energy_error < 1e-12 && r.check.unwrap().excess < 1e-10,
        "{r:?}"
    );
    let want = strength * edge_integral(&sol.surface, &curve, false);
    assert!(
        (r.external - want).abs() < 1e-3 * want,
        "{} vs {want}",
        r.external
    );
    assert_eq!(r.operators[0].at, Some(sol.surface.eval(1.0, 0.0)));
}

#[test]
fn bad_operators_are_refused_naming_them() {
    let base = || {
        BSplineProblem::from_surface(sheet())
            .with_fixed_rings(2)
            .with_term(Bend::new(1.0))
    };
    let far = op(
        "far",
        Target::Point([0.0; 3]),
        TensorPlace::Point([0.5, 1.5]),
        1.0,
    );
    let e = base().with_operator(far).solve().unwrap_err().to_string();
    assert!(
        e.contains("far") && e.contains("knot domain [0, 2] × [0, 1]"),
        "{e}"
    );
    let mut turn = op(
        "turn",
        Target::Direction([0.0, 0.0, 1.0]),
        TensorPlace::Point([0.5, 0.5]),
        1.0,
    );
    turn.repel = true;
    let e = base().with_operator(turn).solve().unwrap_err().to_string();
    assert!(e.contains("turn") && e.contains("director"), "{e}");
    let edge = op(
        "hem",
        Target::Curve(BezierCurve::new(vec![[0.0; 3], [0.0, 1.0, 0.0]])),
        TensorPlace::Point([0.5, 0.5]),
        1.0,
    );
    let e = base().with_operator(edge).solve().unwrap_err().to_string();
    assert!(e.contains("hem") && e.contains("an edge"), "{e}");
    let bent = op(
        "bent",
        Target::Point([0.0; 3]),
        TensorPlace::Region(vec![[0.1, 0.1], [0.9, 0.1], [0.5, 0.3], [0.5, 0.9]]),
        1.0,
    );
    let e = base().with_operator(bent).solve().unwrap_err().to_string();
    assert!(e.contains("bent") && e.contains("convex"), "{e}");
}
