//! Facts about B-spline surfaces: the knot rules name what breaks them;
//! the basis sums to one and its derivatives are the difference quotients'
//! limits; knot insertion and the Bézier pieces leave the surface as it
//! is; the energies equal the Bézier pieces' closed forms; two fixed rings
//! of a biharmonic polynomial give that polynomial back at any knots;
//! refinement never raises the minimum.

use super::energy::{energy_by_pieces, energy_by_quadrature, patterns};
use super::*;
use crate::{Bend, GuideSurface, NormalField, Stretch};
use crate::{Error, TensorPatch, Vec3};

fn knots(p: usize, k: &[f64]) -> KnotVector {
    KnotVector::new(p, k.to_vec()).unwrap()
}

/// Clamped uniform knots of degree p with `spans` spans on [0, 1].
fn uniform(p: usize, spans: usize) -> KnotVector {
    let mut k = vec![0.0; p];
    k.extend((0..=spans).map(|i| i as f64 / spans as f64));
    k.extend(vec![1.0; p]);
    knots(p, &k)
}

/// Nonuniform cubic knots with a double interior knot, and quadratic ones.
fn uneven() -> (KnotVector, KnotVector) {
    (
        knots(3, &[0., 0., 0., 0., 0.2, 0.5, 0.5, 0.9, 1., 1., 1., 1.]),
        knots(3, &[0., 0., 0., 0., 0.35, 0.6, 1., 1., 1., 1.]),
    )
}

/// A pseudo-random number in [−1, 1).
fn noise(k: usize) -> f64 {
    let x = (k as f64 * 12.9898 + 78.233).sin() * 43758.5453;
    2.0 * (x - x.floor()) - 1.0
}

fn wavy(u: KnotVector, v: KnotVector) -> BSplineSurface {
    let (cu, cv) = (u.count(), v.count());
    let points = (0..cu * cv)
        .map(|k| {
            let (i, j) = (k / cv, k % cv);
            [
                i as f64 + 0.2 * noise(3 * k),
                j as f64 + 0.2 * noise(3 * k + 1),
                noise(3 * k + 2),
            ]
        })
        .collect();
    BSplineSurface::new(u, v, points).unwrap()
}

fn dist(a: Vec3, b: Vec3) -> f64 {
    (0..3).map(|c| (a[c] - b[c]).abs()).fold(0.0, f64::max)
}

/// The thin plate with two rings fixed, solved.
fn ring_thin_plate(s: BSplineSurface) -> BSplineSolution {
    BSplineProblem::from_surface(s)
        .with_fixed_rings(2)
        .with_term(Bend::new(1.0))
        .solve()
        .unwrap()
}

/// The largest coordinate difference between two nets.
fn net_gap(a: &[Vec3], b: &[Vec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(a, b)| dist(*a, *b))
        .fold(0.0, f64::max)
}

fn grid() -> impl Iterator<Item = (f64, f64)> {
    (0..=12).flat_map(|i| (0..=12).map(move |j| (i as f64 / 12.0, j as f64 / 12.0)))
}

#[test]
fn knot_rules_name_what_breaks_them() {
    let why = |p: usize, k: &[f64]| match KnotVector::new(p, k.to_vec()) {
        Err(Error::Knots { why }) => why,
        other => panic!("{other:?}"),
    };
    assert!(why(0, &[0., 1.]).contains("at least 1"));
    assert!(why(3, &[0., 0., 0., 1., 1., 1.]).contains("at least 8 knots"));
    assert!(why(2, &[0., 0., 0., f64::NAN, 1., 1., 1.]).contains("knot 3 is not finite"));
    assert!(
        why(2, &[0., 0., 0., 0.7, 0.3, 1., 1., 1.]).contains("knot 4 (0.3) is below knot 3 (0.7)")
    );
    assert!(why(2, &[0., 0., 0.5, 1., 1., 1.]).contains("first knot is repeated 2 times"));
    assert!(why(2, &[0., 0., 0., 0., 1., 1., 1.]).contains("first knot is repeated 4 times"));
    assert!(why(2, &[0., 0., 0., 0.5, 1., 1.]).contains("last knot is repeated 2 times"));
    assert!(why(2, &[0., 0., 0., 0.5, 0.5, 0.5, 1., 1., 1.])
        .contains("knot 3 (0.5) is repeated 3 times"));
    assert!(why(1, &[2., 2., 2., 2.]).contains("empty"));
    // At the limits: interior multiplicity p is allowed.
    assert_eq!(knots(2, &[0., 0., 0., 0.5, 0.5, 1., 1., 1.]).count(), 5);
    let s = BSplineSurface::new(
        KnotVector::bezier(2),
        KnotVector::bezier(2),
        vec![[0.0; 3]; 8],
    );
    assert!(matches!(s, Err(Error::Mismatch { .. })), "{s:?}");
}

#[test]
fn the_basis_sums_to_one_and_its_derivatives_are_limits_of_differences() {
    let (u, _) = uneven();
    // Degree 3 on uneven knots; degrees 1 and 2 (derivative rows above the
    // degree are 0); degree 9 with interior knots (the heap buffers).
    let more = [
        u,
        KnotVector::uniform(1, 4),
        KnotVector::uniform(2, 3),
        KnotVector::new(
            9,
            [vec![0.0; 10], vec![0.3, 0.55, 0.55], vec![1.0; 10]].concat(),
        )
        .unwrap(),
    ];
    for u in &more {
        let p = u.degree();
        let h = 1e-6;
        for k in 0..=40 {
            let t = k as f64 / 40.0;
            let span = u.span(t);
            let d = u.basis_derivatives(span, t, 3);
            assert!(
                (d[0].iter().sum::<f64>() - 1.0).abs() < 1e-14,
                "p {p} t = {t}"
            );
            assert!(d[0].iter().all(|&b| b >= 0.0));
            for (r, row) in d.iter().enumerate().skip(1) {
                let scale = row.iter().fold(1.0f64, |m, x| m.max(x.abs()));
                assert!(
                    row.iter().sum::<f64>().abs() < 1e-12 * scale,
                    "p {p} r {r} t {t}"
                );
                if r > p {
                    assert!(row.iter().all(|&x| x == 0.0), "p {p} r {r}: {row:?}");
                }
            }
            // Central differences inside a span (the basis is a polynomial
            // there): each of the first three rows' derivative is the next.
            let (a, b) = (u.knots()[span], u.knots()[span + 1]);
            if t - h > a && t + h < b {
                let (lo, hi) = (
                    u.basis_derivatives(span, t - h, 3),
                    u.basis_derivatives(span, t + h, 3),
                );
                for r in 0..3 {
                    for j in 0..=p {
                        let fd = (hi[r][j] - lo[r][j]) / (2.0 * h);
                        let scale = 1.0 + d[r + 1][j].abs() + d[r][j].abs();
                        assert!(
                            (fd - d[r + 1][j]).abs() < 1e-5 * scale,
                            "p {p} r {r} j {j} t {t}: {fd} vs {}",
                            d[r + 1][j]
                        );
                    }
                }
            }
        }
    }
    // No interior knots: the Bernstein polynomials.
    let b = KnotVector::bezier(4);
    let d = b.basis_derivatives(b.span(0.3), 0.3, 0);
    let bern = crate::basis::bernstein_all(4, 0.3);
    assert!(d[0].iter().zip(&bern).all(|(x, y)| (x - y).abs() < 1e-16));
}

/// Degrees up to 7 use stack buffers, 8 and above heap ones: every path
/// gives the Bernstein polynomials and their derivatives without interior
/// knots, and a B-spline patch's point and derivatives are its Bézier
/// patch's.
#[test]
fn every_degree_evaluates_as_the_bernstein_patch() {
    for n in [3, 7, 8, 9, 12] {
        let b = KnotVector::bezier(n);
        for t in [0.0, 0.27, 0.5, 1.0] {
            let d = b.basis_derivatives(b.span(t), t, 2);
            let bern = crate::basis::bernstein_derivatives(n, t, 2);
            for r in 0..=2 {
                for j in 0..=n {
                    let (x, y) = (d[r][j], bern[r][j]);
                    assert!(
                        (x - y).abs() < 1e-11 * (1.0 + y.abs()),
                        "n {n} t {t} r {r} j {j}: {x} vs {y}"
                    );
                }
            }
        }
        let patch = TensorPatch::from_fn(n, n - 1, |i, j| [i as f64, j as f64, noise(7 * i + j)]);
        let s = BSplineSurface::from_bezier(&patch);
        for (u, v) in [(0.1, 0.9), (0.5, 0.33), (1.0, 0.0)] {
            let (a, e) = (s.derivatives(u, v), patch.derivatives(u, v));
            for (x, y) in [
                (a.point, e.point),
                (a.du, e.du),
                (a.dv, e.dv),
                (a.duu, e.duu),
                (a.duv, e.duv),
                (a.dvv, e.dvv),
            ] {
                let gap = (0..3).fold(0.0f64, |m, c| m.max((x[c] - y[c]).abs()));
                assert!(
                    gap < 1e-9 * (1.0 + y.iter().fold(0.0f64, |m, c| m.max(c.abs()))),
                    "n {n} ({u}, {v}): {x:?} vs {y:?}"
                );
            }
        }
    }
}

#[test]
fn a_bezier_patch_is_a_bspline_without_interior_knots() {
    let p = TensorPatch::from_fn(3, 2, |i, j| [i as f64, j as f64, noise(7 * i + j)]);
    let s = BSplineSurface::from_bezier(&p);
    for (u, v) in grid() {
        assert!(dist(s.eval(u, v), p.eval(u, v)) < 1e-14);
        let (a, b) = (s.derivatives(u, v), p.derivatives(u, v));
        for (x, y) in [
            (a.du, b.du),
            (a.dv, b.dv),
            (a.duu, b.duu),
            (a.duv, b.duv),
            (a.dvv, b.dvv),
        ] {
            assert!(dist(x, y) < 1e-12, "({u}, {v})");
        }
    }
    // Its energies are the tensor patch's closed forms.
    let (d, b) = (
        crate::analysis::dirichlet(&p),
        crate::analysis::biharmonic(&p),
    );
    assert!((s.dirichlet() - d).abs() < 1e-13 * d && (s.biharmonic() - b).abs() < 1e-13 * b);
}

#[test]
fn knot_insertion_and_bezier_pieces_leave_the_surface_as_it_is() {
    let (u, v) = uneven();
    let s = wavy(u, v);
    let r = s
        .refined(&[0.1, 0.5, 0.77, 0.77], &[0.35, 0.5, 0.99])
        .unwrap();
    assert_eq!(r.counts(), (s.counts().0 + 4, s.counts().1 + 3));
    let size = 10.0;
    for (a, b) in grid() {
        assert!(
            dist(s.eval(a, b), r.eval(a, b)) < 1e-14 * size,
            "({a}, {b})"
        );
        let (x, y) = (s.derivatives(a, b), r.derivatives(a, b));
        assert!(dist(x.du, y.du) < 1e-12 * size && dist(x.duv, y.duv) < 1e-10 * size);
    }
    // Refused: outside the open domain, and beyond multiplicity p.
    assert!(matches!(s.insert_knot_u(1.0), Err(Error::Knots { .. })));
    assert!(
        matches!(r.insert_knot_u(0.5), Err(Error::Knots { why }) if why.contains("multiplicity 3"))
    );
    // Every Bézier piece is the surface over its rectangle.
    let pieces = s.bezier_pieces();
    assert_eq!(pieces.len(), 4 * 3);
    for piece in &pieces {
        let (hu, hv) = (piece.u.1 - piece.u.0, piece.v.1 - piece.v.0);
        for (a, b) in grid() {
            let q = piece.patch.eval(a, b);
            assert!(dist(q, s.eval(piece.u.0 + a * hu, piece.v.0 + b * hv)) < 1e-13 * size);
        }
    }
}

#[test]
fn energies_equal_the_bezier_pieces_closed_forms() {
    let (u, v) = uneven();
    let s = wavy(u, v);
    for (ws, wb) in [(1.0, 0.0), (0.0, 1.0), (0.3, 2.5)] {
        let pats = patterns(ws, wb);
        let gauss = energy_by_quadrature(&s.bezier_pieces(), s.degree(), &pats);
        let pieces = energy_by_pieces(&s.bezier_pieces(), s.degree(), &pats);
        assert!(
            (gauss - pieces).abs() < 1e-12 * gauss,
            "{ws} {wb}: {gauss} vs {pieces}"
        );
    }
    // The same on a refined net of the same surface.
    let r = s.refined(&[0.6], &[0.1, 0.8]).unwrap();
    assert!((r.biharmonic() - s.biharmonic()).abs() < 1e-11 * s.biharmonic());
    assert!((r.dirichlet() - s.dirichlet()).abs() < 1e-12 * s.dirichlet());
}

#[test]
fn measures_of_one_span_are_the_bezier_patchs_and_knots_change_none() {
    // One span over [0, 1]²: the Bézier patch's measures (the same grid).
    let p = TensorPatch::from_fn(4, 3, |i, j| [i as f64, j as f64, 0.6 * noise(5 * i + j)]);
    let (a, b) = (
        BSplineSurface::from_bezier(&p).measures(),
        crate::analysis::measures(&p),
    );
    let close = |x: f64, y: f64, tol: f64| (x - y).abs() <= tol * y.abs().max(1e-300);
    assert!(close(a.area, b.area, 1e-13), "{} vs {}", a.area, b.area);
    assert!(close(a.dirichlet, b.dirichlet, 1e-13) && close(a.biharmonic, b.biharmonic, 1e-13));
    let (h, g) = (a.abs_mean_curvature, b.abs_mean_curvature);
    assert_eq!((h.samples, h.singular), (g.samples, g.singular));
    assert!(
        close(h.min, g.min, 1e-9) && close(h.max, g.max, 1e-11) && close(h.mean, g.mean, 1e-12)
    );
    let (t, u) = (a.normal_turn.unwrap(), b.normal_turn.unwrap());
    assert!(
        close(t.angle, u.angle, 1e-9) && t.at == u.at,
        "{t:?} vs {u:?}"
    );
    // Inserting knots changes the net, not the surface: area to its
    // quadrature error, the functionals and |H| (the same grid points) to
    // rounding.
    let (u, v) = uneven();
    let s = wavy(u, v);
    let r = s.refined(&[0.1, 0.5, 0.77], &[0.35, 0.9]).unwrap();
    let (ms, mr) = (s.measures(), r.measures());
    assert!((ms.area - mr.area).abs() <= ms.area_error + mr.area_error + 1e-13 * ms.area);
    assert!(close(mr.dirichlet, ms.dirichlet, 1e-12) && close(mr.biharmonic, ms.biharmonic, 1e-11));
    let (h, g) = (mr.abs_mean_curvature, ms.abs_mean_curvature);
    assert_eq!(h.samples, g.samples);
    assert!(
        close(h.max, g.max, 1e-10) && close(h.mean, g.mean, 1e-10),
        "{h:?} vs {g:?}"
    );
    // And the area is the parameter-free one: an independent midpoint rule
    // of |R_u × R_v| over the knot domain, 400² points.
    let n = 400;
    let mut midpoint = 0.0;
    for i in 0..n {
        for j in 0..n {
            let d = s.derivatives((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
            let c = [
                d.du[1] * d.dv[2] - d.du[2] * d.dv[1],
                d.du[2] * d.dv[0] - d.du[0] * d.dv[2],
                d.du[0] * d.dv[1] - d.du[1] * d.dv[0],
            ];
            midpoint += (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        }
    }
    midpoint /= (n * n) as f64;
    assert!(close(ms.area, midpoint, 1e-4), "{} vs {midpoint}", ms.area);
    // The same net over a domain twice as large ([0, 2]², knots doubled):
    // the same surface, so the same area and |H|; R_u and R_v halve, so the
    // Dirichlet integral (½∫|R_u|² + |R_v|² over 4× the area) stays and
    // the thin plate's (second derivatives a quarter) is divided by 4.
    let doubled = |k: &KnotVector| {
        KnotVector::new(k.degree(), k.knots().iter().map(|t| 2.0 * t).collect()).unwrap()
    };
    let (ku, kv) = s.knots();
    let big = BSplineSurface::new(doubled(ku), doubled(kv), s.points().to_vec()).unwrap();
    let mb = big.measures();
    assert!((mb.area - ms.area).abs() <= mb.area_error + ms.area_error + 1e-13 * ms.area);
    assert!(
        close(mb.dirichlet, ms.dirichlet, 1e-12),
        "{} vs {}",
        mb.dirichlet,
        ms.dirichlet
    );
    assert!(close(4.0 * mb.biharmonic, ms.biharmonic, 1e-12));
    let (h, g) = (mb.abs_mean_curvature, ms.abs_mean_curvature);
    assert!(
        close(h.max, g.max, 1e-12) && close(h.mean, g.mean, 1e-12),
        "{h:?} vs {g:?}"
    );
    let (t, u) = (mb.normal_turn.unwrap(), ms.normal_turn.unwrap());
    assert!(close(t.angle, u.angle, 1e-12) && t.at == (2.0 * u.at.0, 2.0 * u.at.1));
}

/// The B-spline coefficients of Σ c_ab u^a v^b by blossoming: the
/// coefficient i of t^a is e_a(t_{i+1}, …, t_{i+p}) / C(p, a).
fn blossomed(u: &KnotVector, v: &KnotVector, f: &[[f64; 4]; 4]) -> Vec<f64> {
    let beta = |k: &KnotVector| -> Vec<[f64; 4]> {
        let p = k.degree();
        (0..k.count())
            .map(|i| {
                let ts = &k.knots()[i + 1..=i + p];
                let mut e = [1.0, 0.0, 0.0, 0.0];
                for &t in ts {
                    for a in (1..4).rev() {
                        e[a] += t * e[a - 1];
                    }
                }
                std::array::from_fn(|a| e[a] / crate::basis::binomial(p, a))
            })
            .collect()
    };
    let (bu, bv) = (beta(u), beta(v));
    let mut out = Vec::new();
    for i in 0..u.count() {
        for j in 0..v.count() {
            out.push(
                (0..4)
                    .flat_map(|a| (0..4).map(move |b| (a, b)))
                    .map(|(a, b)| f[a][b] * bu[i][a] * bv[j][b])
                    .sum(),
            );
        }
    }
    out
}

#[test]
fn two_fixed_rings_of_a_biharmonic_polynomial_give_it_back_at_any_knots() {
    // z = u³ − 3uv² + u²v + 2v³ + uv + u³v: Δ²z = 0, bidegree (3, 3).
    let mut z = [[0.0; 4]; 4];
    z[3][0] = 1.0;
    z[1][2] = -3.0;
    z[2][1] = 1.0;
    z[0][3] = 2.0;
    z[1][1] = 1.0;
    z[3][1] = 1.0;
    let (mut x, mut y) = ([[0.0; 4]; 4], [[0.0; 4]; 4]);
    x[1][0] = 1.0;
    y[0][1] = 1.0;
    for (u, v) in [
        uneven(),
        (KnotVector::uniform(3, 7), KnotVector::uniform(3, 5)),
    ] {
        let (bx, by, bz) = (
            blossomed(&u, &v, &x),
            blossomed(&u, &v, &y),
            blossomed(&u, &v, &z),
        );
        let exact: Vec<Vec3> = (0..bx.len()).map(|k| [bx[k], by[k], bz[k]]).collect();
        let cv = v.count();
        let truth = BSplineSurface::new(u.clone(), v.clone(), exact.clone()).unwrap();
        for (a, b) in grid() {
            let p = truth.eval(a, b);
            let want =
                a * a * a - 3.0 * a * b * b + a * a * b + 2.0 * b * b * b + a * b + a * a * a * b;
            assert!(dist(p, [a, b, want]) < 1e-14, "blossoming at ({a}, {b})");
        }
        // Interior points scrambled; two rings kept.
        let start: Vec<Vec3> = exact
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let (i, j) = (k / cv, k % cv);
                let inside = i >= 2 && j >= 2 && i + 2 < u.count() && j + 2 < cv;
                if inside {
                    [noise(k), noise(k + 1), 5.0 * noise(k + 2)]
                } else {
                    *p
                }
            })
            .collect();
        let sol = BSplineProblem::from_surface(BSplineSurface::new(u, v, start).unwrap())
            .with_fixed_rings(2)
            .with_term(Bend::new(1.0))
            .solve()
            .unwrap();
        let worst = sol
            .surface
            .points()
            .iter()
            .zip(&exact)
            .map(|(a, b)| dist(*a, *b))
            .fold(0.0, f64::max);
        assert!(worst < 1e-10, "net off by {worst:e}");
        let r = &sol.report;
        assert!(
            r.relative_gradient < 1e-14 && r.check.unwrap().energy_error < 1e-12,
            "{r:?}"
        );
        // The check's excess over the minimum, at double-double's level.
        assert!(
            r.check.unwrap().excess < 1e-20
                && r.check.unwrap().corrections <= crate::check::MAX_CORRECTIONS,
            "{r:?}"
        );
        assert!((r.energy - truth.biharmonic()).abs() < 1e-10 * r.energy);
    }
}

#[test]
fn refinement_never_raises_the_minimum_and_lowers_it_for_a_general_boundary() {
    let s = wavy(KnotVector::uniform(3, 3), KnotVector::uniform(3, 3));
    let coarse = ring_thin_plate(s);
    let refined_start = coarse
        .surface
        .refined(&[0.25, 0.5, 0.75], &[0.2, 0.6])
        .unwrap();
    // The coarse minimizer is feasible on the finer space: the fixed rings
    // are its own.
    assert!(
        (refined_start.biharmonic() - coarse.report.energy).abs() < 1e-11 * coarse.report.energy
    );
    let fine = ring_thin_plate(refined_start);
    let (e0, e1) = (coarse.report.energy, fine.report.energy);
    assert!(e1 < e0 * (1.0 - 1e-6), "coarse {e0}, refined {e1}");
    // Minimal under perturbation of any free point.
    let cv = fine.surface.counts().1;
    for k in [2 * cv + 2, 3 * cv + 4] {
        let mut pts = fine.surface.points().to_vec();
        pts[k][2] += 1e-4;
        assert!(fine.surface.with_points(pts).biharmonic() > e1);
    }
}

#[test]
fn solves_refuse_what_they_cannot_do() {
    let s = wavy(KnotVector::uniform(2, 2), KnotVector::uniform(2, 2));
    assert!(matches!(
        BSplineProblem::from_surface(s.clone())
            .with_term(Bend::new(1.0))
            .solve(),
        Err(Error::NoFreePoints { .. })
    ));
    assert!(matches!(
        BSplineProblem::from_surface(s.clone())
            .with_fixed_rings(1)
            .solve(),
        Err(Error::NoEnergy)
    ));
    assert!(matches!(
        BSplineProblem::from_surface(s)
            .with_fixed_rings(1)
            .with_term(Bend::new(-1.0))
            .solve(),
        Err(Error::NegativeWeight { .. })
    ));
}

/// With no interior knots a B-spline problem is the tensor problem: the
/// membrane, a normal field (λ = 10, a tilted 2 × 2 field, coupling x, y
/// and z) and the initial net as guide (γ = 3) give the tensor solver's net
/// (an independent implementation: dense, Bernstein closed forms).
#[test]
fn without_interior_knots_the_guided_problem_is_the_tensor_problem() {
    use crate::{GuideSurface, NormalField, Problem, Stretch};
    let net = TensorPatch::from_fn(5, 4, |i, j| {
        [i as f64 / 5.0, j as f64 / 4.0, 0.3 * noise(11 * i + j)]
    });
    let field = TensorPatch::from_fn(2, 2, |i, j| [0.2 * i as f64 - 0.2, 0.1 * j as f64, 1.0]);
    let tensor = Problem::new((5, 4))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0))
        .with_term(NormalField::new(10.0, field.clone()))
        .with_term(GuideSurface::new(3.0, net.clone()))
        .solve()
        .unwrap();
    let initial = BSplineSurface::from_bezier(&net);
    let ours = BSplineProblem::from_surface(initial.clone())
        .with_fixed_rings(1)
        .with_term(Stretch::new(1.0))
        .with_term(NormalField::new(10.0, field))
        .with_term(GuideSurface::spline(3.0, initial))
        .solve()
        .unwrap();
    let worst = net_gap(ours.surface.points(), tensor.surface.points());
    assert!(worst < 1e-12, "nets differ by {worst:e}");
    let r = &ours.report;
    assert!(
        r.coupled && r.term("normal_field") > 0.0 && r.term("guide_surface") > 0.0,
        "{r:?}"
    );
    assert!(
        (r.energy - tensor.report.energy).abs() < 1e-12 * r.energy,
        "{} vs {}",
        r.energy,
        tensor.report.energy
    );
    assert!(
        r.check.unwrap().energy_error < 1e-12 && r.relative_gradient < 1e-14,
        "{r:?}"
    );
}

/// On uneven knots the guided thin plate is a minimum: the energy (by the
/// report's roads) rises when any free coordinate moves either way.
#[test]
fn the_guided_thin_plate_is_minimal_under_perturbation() {
    let (u, v) = uneven();
    let s = wavy(u, v);
    let field = TensorPatch::from_fn(1, 1, |i, j| [0.3 * i as f64, -0.2 * j as f64, 1.0]);
    let problem = BSplineProblem::from_surface(s.clone())
        .with_fixed_rings(2)
        .with_term(Bend::new(1.0))
        .with_term(NormalField::new(50.0, field))
        .with_term(GuideSurface::spline(0.5, s));
    let sol = problem.solve().unwrap();
    let e0 = sol.report.energy;
    assert!(
        sol.report.check.unwrap().energy_error < 1e-12,
        "{:?}",
        sol.report
    );
    let cv = sol.surface.counts().1;
    for (k, c) in [(2 * cv + 2, 0), (3 * cv + 3, 1), (4 * cv + 2, 2)] {
        for step in [1e-4, -1e-4] {
            let e = energy_of(&problem, &sol.surface, k, c, step);
            assert!(e > e0, "moving ({k}, {c}) by {step} lowers {e0} to {e}");
        }
    }
}

/// The normal field's Hessian is assembled between free points only, the
/// fixed points entering the right-hand side through each span's gradient
/// (`SpanGrid::apply`): with free points that are not a rectangle of
/// indices (an L, and a lone fixed point inside it; spans holding free and
/// fixed points in any pattern) the answer is still the minimum — every
/// free coordinate moved either way raises the energy — and both energy
/// roads agree. One Bézier span (factored dense, Bernstein basis) and 6 × 6
/// cubic spans (sparse, A2.3's basis).
#[test]
fn guided_solves_with_irregular_free_points_are_minimal() {
    use crate::energy::SampleGrid;
    for (u, v) in [
        (KnotVector::bezier(5), KnotVector::bezier(5)),
        (KnotVector::uniform(3, 6), KnotVector::uniform(3, 6)),
    ] {
        let s = wavy(u, v);
        let (cu, cv) = s.counts();
        // Free: inside the second ring, but not the upper right quarter,
        // and not one point in the middle of what is left.
        let free: Vec<bool> = (0..cu * cv)
            .map(|k| {
                let (i, j) = (k / cv, k % cv);
                let inside = (2..cu - 2).contains(&i) && (2..cv - 2).contains(&j);
                inside && !(i >= cu / 2 && j >= cv / 2) && (i, j) != (3, 2)
            })
            .collect();
        let grid = SampleGrid::new(3 * cu, 3 * cv);
        let normals: Vec<Vec3> = (0..grid.len())
            .map(|k| {
                let (x, y) = grid.param(k);
                [0.4 * x - 0.2, 0.3 * y * y, 1.0]
            })
            .collect();
        let problem = BSplineProblem::from_surface(s)
            .with_free(free.clone())
            .unwrap()
            .with_term(Bend::new(1.0))
            .with_term(NormalField::sampled(40.0, grid, normals, None));
        let sol = problem.solve().unwrap();
        let r = &sol.report;
        assert!(
            r.check.unwrap().energy_error < 1e-12 && r.relative_gradient < 1e-13,
            "{cu} × {cv}: {r:?}"
        );
        let e0 = r.energy;
        for k in (0..cu * cv).filter(|&k| free[k]) {
            for c in 0..3 {
                for step in [1e-4, -1e-4] {
                    let e = energy_of(&problem, &sol.surface, k, c, step);
                    assert!(e > e0, "{cu} × {cv}: ({k}, {c}) by {step}: {e0} to {e}");
                }
            }
        }
    }
}

/// The energy of the problem's terms at the solution with one coordinate moved.
fn energy_of(problem: &BSplineProblem, at: &BSplineSurface, k: usize, c: usize, step: f64) -> f64 {
    let mut pts = at.points().to_vec();
    pts[k][c] += step;
    problem.energy_at(&at.with_points(pts)).unwrap()
}

/// The B-spline basis stays well conditioned as spans are added (de Boor:
/// the scaled Gram matrix's condition depends on the degree only), unlike
/// the Bernstein basis as its degree rises; the solve reports the system's
/// condition, which grows like a stiffness matrix's (h⁻⁴ for the thin plate).
#[test]
fn the_basis_condition_stays_bounded_as_spans_are_added() {
    use faer::{Mat, Side};
    let scaled_condition = |k: &KnotVector| {
        let g = energy::Gram1d::new(k);
        let c = k.count();
        let d: Vec<f64> = (0..c).map(|i| g.at(0, i, i).sqrt()).collect();
        let m = Mat::from_fn(c, c, |i, j| g.at(0, i, j) / (d[i] * d[j]));
        let ev = m.self_adjoint_eigenvalues(Side::Lower).unwrap();
        ev[ev.len() - 1] / ev[0]
    };
    let conds: Vec<f64> = [4, 16, 64, 256]
        .iter()
        .map(|&s| scaled_condition(&KnotVector::uniform(3, s)))
        .collect();
    assert!(conds.iter().all(|&c| c < 30.0), "{conds:?}");
    assert!(conds[3] < 1.05 * conds[2], "{conds:?}");
    // The Bernstein basis of degree 24 (one span): far worse.
    let bernstein = scaled_condition(&KnotVector::bezier(24));
    assert!(bernstein > 1e6 * conds[3], "{bernstein:e}");
    // The thin-plate system's estimate: finite, and about 16× per halving
    // of the span (h⁻⁴).
    let solve = |spans: usize| {
        let k = KnotVector::uniform(3, spans);
        let c = k.count();
        let points = (0..c * c)
            .map(|q| [(q / c) as f64, (q % c) as f64, noise(q)])
            .collect();
        BSplineProblem::from_surface(BSplineSurface::new(k.clone(), k, points).unwrap())
            .with_fixed_rings(2)
            .with_term(Bend::new(1.0))
            .solve()
            .unwrap()
            .report
            .condition_estimate
    };
    let (c8, c16) = (solve(8), solve(16));
    assert!(c8.is_finite() && c8 > 1.0, "{c8}");
    let ratio = c16 / c8;
    assert!((8.0..32.0).contains(&ratio), "{c8:e} → {c16:e}: ×{ratio}");
}

/// Degree elevation keeps the surface (1e-14 of its size, with its first
/// and second derivatives), raises every distinct knot's multiplicity by
/// one (so the continuity at each knot is kept) and adds one control point
/// per span; a Bézier patch elevates to the Bernstein elevation; and it
/// never raises the thin-plate minimum (nested spaces) but lowers it for a
/// general boundary.
#[test]
fn degree_elevation_keeps_the_surface_and_enlarges_the_space() {
    let (u, v) = uneven();
    let s = wavy(u.clone(), v.clone());
    let e = s.elevated(1, 2).unwrap();
    assert_eq!(e.degree(), (4, 5));
    let (su, sv) = (u.spans().len(), v.spans().len());
    assert_eq!(e.counts(), (s.counts().0 + su, s.counts().1 + 2 * sv));
    for &t in &[0.2, 0.5, 0.9] {
        assert_eq!(e.knots().0.multiplicity(t), u.multiplicity(t) + 1);
    }
    assert_eq!(e.knots().1.multiplicity(0.35), 3);
    let size = 10.0;
    for (a, b) in grid() {
        let (x, y) = (s.derivatives(a, b), e.derivatives(a, b));
        assert!(dist(x.point, y.point) < 1e-14 * size, "({a}, {b})");
        assert!(dist(x.du, y.du) < 1e-12 * size && dist(x.dvv, y.dvv) < 1e-10 * size);
    }
    // A Bézier patch: the Bernstein elevation, point for point.
    let patch = TensorPatch::from_fn(3, 2, |i, j| [i as f64, j as f64, noise(5 * i + j)]);
    let b = BSplineSurface::from_bezier(&patch).elevated(2, 1).unwrap();
    let want = patch.elevate(2, 1);
    for (p, q) in b.points().iter().zip(want.points()) {
        assert!(dist(*p, *q) < 1e-15 * 4.0, "{p:?} {q:?}");
    }
    // Nested spaces: the coarse minimizer elevated is feasible, and the
    // elevated problem's minimum lies strictly below it.
    let coarse = ring_thin_plate(wavy(KnotVector::uniform(3, 2), KnotVector::uniform(3, 2)));
    let start = coarse.surface.elevated(1, 1).unwrap();
    assert!((start.biharmonic() - coarse.report.energy).abs() < 1e-11 * coarse.report.energy);
    let fine = ring_thin_plate(start);
    let (e0, e1) = (coarse.report.energy, fine.report.energy);
    assert!(e1 < e0 * (1.0 - 1e-6), "bicubic {e0}, biquartic {e1}");
}

/// The sampled normal field (Wu & Yang eq. 5): with no interior knots the
/// B-spline problem is the tensor problem with the same samples, normals
/// and per-sample weights (a 9 × 7 grid, stretch, λ = 20): the same net to
/// 1e-12 and the same energy; on uneven knots (a sample on every knot line)
/// the answer is minimal under perturbation and both energy roads agree.
#[test]
fn sampled_normal_fields_match_the_tensor_problem_and_are_minimal() {
    use crate::energy::SampleGrid;
    use crate::{NormalField, Problem, Stretch};
    let net = TensorPatch::from_fn(4, 4, |i, j| {
        [i as f64 / 4.0, j as f64 / 4.0, 0.3 * noise(7 * i + j)]
    });
    let grid = SampleGrid::new(8, 6);
    let normals: Vec<Vec3> = (0..grid.len())
        .map(|k| {
            let (u, v) = grid.param(k);
            [0.4 * u - 0.2, 0.3 * v * v, 2.0]
        })
        .collect();
    let weights: Vec<f64> = (0..grid.len())
        .map(|k| 1.0 + 0.5 * noise(k).abs())
        .collect();
    // One term, given to both kinds.
    let sampled = NormalField::sampled(20.0, grid, normals.clone(), Some(weights.clone()));
    let tensor = Problem::new((4, 4))
        .with_fixed_rings(&net, 1)
        .with_term(Stretch::new(1.0))
        .with_term(sampled.clone())
        .solve()
        .unwrap();
    let ours = BSplineProblem::from_surface(BSplineSurface::from_bezier(&net))
        .with_fixed_rings(1)
        .with_term(Stretch::new(1.0))
        .with_term(sampled)
        .solve()
        .unwrap();
    let worst = net_gap(ours.surface.points(), tensor.surface.points());
    assert!(worst < 1e-12, "nets differ by {worst:e}");
    let r = &ours.report;
    assert!(
        (r.energy - tensor.report.energy).abs() < 1e-12 * r.energy && r.term("normal_field") > 0.0,
        "{} vs {}",
        r.energy,
        tensor.report.energy
    );
    // Uneven knots (0.2, 0.5 and 0.35 lie on the 1/10 and 1/20 grids).
    let (u, v) = uneven();
    let grid = SampleGrid::new(10, 20);
    let normals: Vec<Vec3> = (0..grid.len())
        .map(|k| {
            let (u, v) = grid.param(k);
            [0.3 * u, -0.2 * v, 1.0]
        })
        .collect();
    let problem = BSplineProblem::from_surface(wavy(u, v))
        .with_fixed_rings(2)
        .with_term(Bend::new(1.0))
        .with_term(NormalField::sampled(30.0, grid, normals, None));
    let sol = problem.solve().unwrap();
    assert!(
        sol.report.check.unwrap().energy_error < 1e-12 && sol.report.check.unwrap().excess < 1e-20,
        "{:?}",
        sol.report
    );
    let e0 = sol.report.energy;
    let free: Vec<usize> = (0..problem.free().len())
        .filter(|&k| problem.free()[k])
        .collect();
    for &k in [free[0], free[free.len() / 2], free[free.len() - 1]].iter() {
        for (c, d) in [(0, -1e-4), (1, 1e-4), (2, -1e-4), (2, 1e-4)] {
            let mut pts = sol.surface.points().to_vec();
            pts[k][c] += d;
            let e1 = problem.energy_at(&sol.surface.with_points(pts)).unwrap();
            assert!(e1 > e0, "{e1} vs {e0} at point {k}");
        }
    }
    // Errors: a zero normal, a wrong count, a negative weight.
    let grid = SampleGrid::new(1, 1);
    let p = || {
        BSplineProblem::from_surface(wavy(KnotVector::uniform(3, 1), KnotVector::uniform(3, 1)))
            .with_fixed_rings(1)
    };
    let zero = vec![[0.0, 0.0, 1.0], [0.0; 3], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]];
    assert!(matches!(
        p().with_term(NormalField::sampled(1.0, grid, zero, None))
            .solve(),
        Err(Error::ZeroNormal { .. })
    ));
    let three = vec![[0.0, 0.0, 1.0]; 3];
    assert!(matches!(
        p().with_term(NormalField::sampled(1.0, grid, three, None))
            .solve(),
        Err(Error::Mismatch { .. })
    ));
    let four = vec![[0.0, 0.0, 1.0]; 4];
    assert!(p()
        .with_term(NormalField::sampled(
            1.0,
            grid,
            four,
            Some(vec![1.0, -1.0, 1.0, 1.0])
        ))
        .solve()
        .is_err());
}

/// The grid evaluation gives what point-by-point de Boor gives.
#[test]
fn derivatives_on_a_grid_are_the_pointwise_ones() {
    let u = KnotVector::new(3, vec![0., 0., 0., 0., 0.3, 0.3, 1., 1.5, 1.5, 1.5, 1.5]).unwrap();
    let v = KnotVector::new(2, vec![-1., -1., -1., 0., 2., 2., 2.]).unwrap();
    let (cu, cv) = (u.count(), v.count());
    let pts = (0..cu * cv)
        .map(|k| {
            let (i, j) = ((k / cv) as f64, (k % cv) as f64);
            [i, j + 0.1 * i * i, (i * 0.7).sin() * j]
        })
        .collect();
    let s = BSplineSurface::new(u, v, pts).unwrap();
    let (us, vs) = ([0.0, 0.3, 0.71, 1.5], [-1.0, -0.2, 0.0, 1.3, 2.0]);
    let grid = s.derivatives_on(&us, &vs);
    // The first derivatives summed the other way round (fewer v's or
    // fewer u's first): the same to rounding, every grid shape.
    for (a, b) in [
        (&us[..], &vs[..]),
        (&us[..2], &vs[..]),
        (&us[..], &vs[..3]),
        (&us[..], &vs[..1]),
    ] {
        let lean = s.tangents_on(a, b);
        assert_eq!(lean.len(), a.len() * b.len());
        for (i, &x) in a.iter().enumerate() {
            for (j, &y) in b.iter().enumerate() {
                let d = s.derivatives(x, y);
                for (e, f) in lean[i * b.len() + j].iter().zip([d.point, d.du, d.dv]) {
                    for c in 0..3 {
                        assert!((e[c] - f[c]).abs() <= 1e-12 * (1.0 + f[c].abs()), "{x} {y}");
                    }
                }
            }
        }
    }
    for (i, &a) in us.iter().enumerate() {
        for (j, &b) in vs.iter().enumerate() {
            let (g, d) = (&grid[i * vs.len() + j], s.derivatives(a, b));
            for (x, y) in [
                (g.point, d.point),
                (g.du, d.du),
                (g.dv, d.dv),
                (g.duu, d.duu),
                (g.duv, d.duv),
                (g.dvv, d.dvv),
            ] {
                for c in 0..3 {
                    assert!((x[c] - y[c]).abs() <= 1e-12 * (1.0 + y[c].abs()), "{a} {b}");
                }
            }
        }
    }
}

/// The editor's drags on a B-spline surface: a kept factor is used as it is
/// when only a fixed point moved (the same answer as a fresh solve), its
/// ordering when a weight changed (sparse factors: more than
/// `DENSE_UNKNOWNS` unknowns; a dense factor has no ordering to keep), and
/// neither for another free set — counted by the reports and the cache, not
/// timed.
#[test]
fn a_cache_reuses_the_factor_for_moved_points_and_the_ordering_for_weights() {
    // 8 free points (dense), and 19 × 15 = 285 (sparse).
    for (u, v) in [uneven(), (uniform(3, 20), uniform(3, 16))] {
        let free = (u.count() - 4) * (v.count() - 4);
        let sparse = free > super::system::DENSE_UNKNOWNS;
        cache_reuse(u, v, sparse);
    }
}

/// The cache's drags on the wavy net over `u` × `v`.
fn cache_reuse(u: KnotVector, v: KnotVector, sparse: bool) {
    let cache = crate::FactorCache::new(8, 1 << 30);
    let s = wavy(u, v);
    let problem = |s: &BSplineSurface, rings: usize, bend: f64| {
        BSplineProblem::from_surface(s.clone())
            .with_fixed_rings(rings)
            .with_term(Stretch::new(0.1))
            .with_term(Bend::new(bend))
    };
    let same = |a: &BSplineSolution, b: &BSplineSolution| {
        assert!(net_gap(a.surface.points(), b.surface.points()) < 1e-12);
        assert!((a.report.energy - b.report.energy).abs() < 1e-12 * b.report.energy);
        assert!(a.report.relative_gradient < 1e-14 && a.report.check.unwrap().excess < 1e-10);
    };
    let first = cache.solve_bspline(&problem(&s, 2, 1.0)).unwrap();
    assert!(!first.report.reused && !first.report.reused_symbolic);
    same(&first, &problem(&s, 2, 1.0).solve().unwrap());
    assert_eq!(cache.len(), 1);
    // A fixed corner moved: the same matrix, only the right-hand side new.
    let mut points = s.points().to_vec();
    points[0][2] += 0.3;
    let moved = s.with_points(points);
    let dragged = cache.solve_bspline(&problem(&moved, 2, 1.0)).unwrap();
    assert!(dragged.report.reused);
    let fresh = problem(&moved, 2, 1.0).solve().unwrap();
    same(&dragged, &fresh);
    assert!(net_gap(dragged.surface.points(), first.surface.points()) > 1e-3);
    assert_eq!(
        dragged.report.condition_estimate,
        first.report.condition_estimate
    );
    assert_eq!(cache.len(), 1);
    // The bend weight doubled: the pattern kept, the numbers new.
    let heavier = cache.solve_bspline(&problem(&moved, 2, 2.0)).unwrap();
    assert!(!heavier.report.reused && heavier.report.reused_symbolic == sparse);
    same(&heavier, &problem(&moved, 2, 2.0).solve().unwrap());
    // It replaced the factor of its pattern: the weight's next step reuses
    // its ordering again, the cache still holds one.
    assert_eq!(cache.len(), 1);
    let next = cache.solve_bspline(&problem(&moved, 2, 2.5)).unwrap();
    assert!(next.report.reused_symbolic == sparse && cache.len() == 1);
    // One ring fixed: another free set, nothing reused.
    let wider = cache.solve_bspline(&problem(&moved, 1, 2.0)).unwrap();
    assert!(!wider.report.reused && !wider.report.reused_symbolic);
    assert_eq!(cache.len(), 2);
}

/// A free set the energy does not determine — only a normal field along
/// z, which no x or y move changes: those coordinates' rows are exactly
/// zero — is the same error from the dense factor (8 free points) as from
/// the sparse one (285): not positive definite, counted in free
/// coordinates, with the hint.
#[test]
fn an_undetermined_free_set_is_the_same_error_dense_or_sparse() {
    for (u, v) in [uneven(), (uniform(3, 20), uniform(3, 16))] {
        let free = (u.count() - 4) * (v.count() - 4);
        let up = vec![[0.0, 0.0, 1.0]; 4];
        let e = BSplineProblem::from_surface(wavy(u, v))
            .with_fixed_rings(2)
            .with_term(NormalField::sampled(
                1.0,
                crate::energy::SampleGrid::new(1, 1),
                up,
                None,
            ))
            .solve()
            .unwrap_err();
        match &e {
            Error::NotPositiveDefinite { unknowns, .. } => assert_eq!(*unknowns, 3 * free),
            other => panic!("{other:?}"),
        }
        assert!(
            e.to_string()
                .contains("the energy does not determine the free control points"),
            "{e}"
        );
    }
}

/// The energy check allows for derivatives that cancel (a nearly flat
/// sliver's small energy from a net of points about 1) and no more: on
/// the sliver's figures (E 1.4e-11, max H_ii · Σ x² = 1e3; the allowance
/// ε·√(E · 1e3) is 1.9e-9 of E) two roads 1e-9 of E apart agree and 1e-8
/// apart are refused; on an energy of 1 from the same net the allowance
/// is the plain 1e-10 of E (5e-11 agrees, 2e-10 is refused); a zero
/// energy agrees with 1e-25 on the other road but not with 1e-20; a NaN
/// on either road is refused.
#[test]
fn the_energy_check_allows_for_cancellation_and_no_more() {
    use super::solve::roads_agree;
    let rounding = 1e3;
    let sliver = 1.4e-11;
    assert!(roads_agree(sliver, sliver * (1.0 + 1e-9), rounding).1);
    assert!(!roads_agree(sliver, sliver * (1.0 + 1e-8), rounding).1);
    assert!(!roads_agree(sliver, 2.0 * sliver, rounding).1);
    assert!(roads_agree(1.0, 1.0 + 5e-11, rounding).1);
    assert!(!roads_agree(1.0, 1.0 + 2e-10, rounding).1);
    assert!(roads_agree(0.0, 1e-25, rounding).1);
    assert!(!roads_agree(0.0, 1e-20, rounding).1);
    assert!(!roads_agree(f64::NAN, 1.0, rounding).1);
    assert!(!roads_agree(1.0, f64::NAN, rounding).1);
    // The figure reported is the difference over the allowance.
    let (error, _) = roads_agree(sliver, sliver * (1.0 + 1e-8), rounding);
    let allowance = f64::EPSILON * (sliver * rounding).sqrt() / super::ENERGY_TOLERANCE;
    assert!(
        (error - 1e-8 * sliver / allowance).abs() < 1e-6 * error,
        "{error}"
    );
}
