//! Edge curves: a face side's B-spline curve, its points and derivatives,
//! the nearest parameter of a point on it, and the part between two
//! parameters.

use super::*;

pub(super) fn dist(p: Vec3, q: Vec3) -> f64 {
    let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// The curve (degree and knots `kv`, control points `pts`, weights `w` when
/// rational) and its first derivative at t; rational by the quotient rule
/// on the homogeneous curve.
pub(super) fn curve_derivs(
    kv: &fairsurf::bspline::KnotVector,
    pts: &[Vec3],
    w: Option<&[f64]>,
    t: f64,
) -> [Vec3; 2] {
    let d = kv.degree();
    let k = kv.span(t);
    let n = kv.basis_derivatives(k, t, 1);
    let weight = |i: usize| w.map_or(1.0, |w| w[i]);
    // A = Σ N w P and W = Σ N w, and their derivatives.
    let a: [Vec3; 2] = std::array::from_fn(|r| {
        (0..=d).fold([0.0; 3], |acc, i| {
            let j = k - d + i;
            let (p, c) = (pts[j], n[r][i] * weight(j));
            [acc[0] + c * p[0], acc[1] + c * p[1], acc[2] + c * p[2]]
        })
    });
    let ws: [f64; 2] = std::array::from_fn(|r| (0..=d).map(|i| n[r][i] * weight(k - d + i)).sum());
    let c = a[0].map(|x| x / ws[0]);
    let dc = std::array::from_fn(|x| (a[1][x] - ws[1] * c[x]) / ws[0]);
    [c, dc]
}

pub(super) fn curve_point(
    kv: &fairsurf::bspline::KnotVector,
    pts: &[Vec3],
    w: Option<&[f64]>,
    t: f64,
) -> Vec3 {
    curve_derivs(kv, pts, w, t)[0]
}

/// The parameter of the curve's point nearest to q: the best of 64
/// samples, then Newton steps on (C(t) − q)·C′(t) = 0 (first order, kept
/// in the domain).
pub(super) fn project(
    kv: &fairsurf::bspline::KnotVector,
    pts: &[Vec3],
    w: Option<&[f64]>,
    q: Vec3,
) -> Option<f64> {
    let (a, b) = kv.domain();
    let mut t = (0..=64)
        .map(|k| a + (b - a) * k as f64 / 64.0)
        .min_by(|&x, &y| {
            dist(curve_point(kv, pts, w, x), q).total_cmp(&dist(curve_point(kv, pts, w, y), q))
        })?;
    for _ in 0..20 {
        let [c, dc] = curve_derivs(kv, pts, w, t);
        let r = [c[0] - q[0], c[1] - q[1], c[2] - q[2]];
        let g = r[0] * dc[0] + r[1] * dc[1] + r[2] * dc[2];
        let h = dc[0] * dc[0] + dc[1] * dc[1] + dc[2] * dc[2];
        if h == 0.0 {
            break;
        }
        let next = (t - g / h).clamp(a, b);
        if (next - t).abs() <= 1e-15 * (b - a) {
            t = next;
            break;
        }
        t = next;
    }
    t.is_finite().then_some(t)
}

/// The part of the curve (knots `kv`, points `pts`, weights `w`) over
/// [ta, tb], cut by knot insertion (the homogeneous points w·P and the
/// weights alike): its knots, points and weights.
#[allow(clippy::type_complexity)]
pub(super) fn cut_curve(
    kv: &fairsurf::bspline::KnotVector,
    pts: &[Vec3],
    w: Option<&[f64]>,
    ta: f64,
    tb: f64,
) -> Option<(fairsurf::bspline::KnotVector, Vec<Vec3>, Option<Vec<f64>>)> {
    use fairsurf::bspline::{BSplineSurface, KnotVector};
    let weight = |i: usize| w.map_or(1.0, |w| w[i]);
    // Columns w·P and (w, 0, 0) of a surface linear in v.
    let net = BSplineSurface::new(
        kv.clone(),
        KnotVector::bezier(1),
        pts.iter()
            .enumerate()
            .flat_map(|(i, p)| [p.map(|x| x * weight(i)), [weight(i), 0.0, 0.0]])
            .collect(),
    )
    .ok()?;
    let cut = net.restricted_u(ta, tb).ok()?;
    let n = cut.counts().0;
    let weights: Vec<f64> = (0..n).map(|i| cut.point(i, 1)[0]).collect();
    let points = (0..n)
        .map(|i| cut.point(i, 0).map(|x| x / weights[i]))
        .collect();
    Some((cut.knots().0.clone(), points, w.map(|_| weights)))
}
