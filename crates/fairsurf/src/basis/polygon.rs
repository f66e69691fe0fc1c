//! Exact integration over a convex polygon Ω of a patch's parameter domain
//! (Veltkamp & Wesselink §6.1, eq. (28)).
//!
//! Ω is cut at its vertices' u-coordinates into trapezoids
//!
//! ```text
//! { (u, v) | a ≤ u ≤ b,  a₀ + a₁u ≤ v ≤ b₀ + b₁u }                    (28)
//! ```
//!
//! and each trapezoid is mapped from the unit square by u = a + (b − a)s,
//! v = lower(u) + t·(upper(u) − lower(u)), whose Jacobian (b − a)(upper −
//! lower)(u) is linear in s. A polynomial integrand of total degree d
//! becomes one of degree ≤ d + 1 in s and ≤ d in t, so a Gauss–Legendre
//! product rule of ⌈(d + 2)/2⌉ points per direction integrates it exactly
//! (up to rounding). Every operator energy is such an integral of products
//! of Bernstein polynomials and their derivatives, so the rule gives its
//! closed form. [`fan_rule`] integrates over the same polygon differently
//! (a fan of triangles, Duffy's collapsed square) to check it.

use crate::basis::GaussLegendre;
use crate::{Error, Result};

/// A point of the (u, v) parameter plane.
pub type Uv = [f64; 2];

/// Quadrature nodes and weights: Σ w·f(node) = ∫_Ω f du dv.
pub type Rule = Vec<(Uv, f64)>;

/// Checks that `polygon` is a convex polygon with at least three vertices
/// and positive area, in either orientation; returns it counter-clockwise.
pub fn convex(polygon: &[Uv], what: &str) -> Result<Vec<Uv>> {
    let bad = |why: String| Error::Mismatch {
        what: what.into(),
        expected: "a convex polygon of at least 3 vertices with positive area".into(),
        got: why,
    };
    if polygon.len() < 3 {
        return Err(bad(format!("{} vertices", polygon.len())));
    }
    if polygon.iter().flatten().any(|x| !x.is_finite()) {
        return Err(bad("a non-finite coordinate".into()));
    }
    let area = signed_area(polygon);
    let scale = polygon
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()))
        .max(1e-300);
    if area.abs() <= 1e-14 * scale * scale {
        return Err(bad(format!("area {area:e}")));
    }
    let mut p = polygon.to_vec();
    if area < 0.0 {
        p.reverse();
    }
    let n = p.len();
    for i in 0..n {
        let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
        let turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
        if turn < -1e-12 * scale * scale {
            return Err(bad(format!("not convex at vertex {}", (i + 1) % n)));
        }
    }
    Ok(p)
}

/// The signed area (positive counter-clockwise), by the shoelace formula.
pub fn signed_area(polygon: &[Uv]) -> f64 {
    let n = polygon.len();
    0.5 * (0..n)
        .map(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
}

/// The trapezoid rule of eq. (28) for a convex polygon (counter-clockwise,
/// see [`convex`]), exact for polynomials of total degree ≤ `degree`.
pub fn trapezoid_rule(polygon: &[Uv], degree: usize) -> Rule {
    let g = GaussLegendre::new(degree.div_ceil(2) + 1);
    let mut cuts: Vec<f64> = polygon.iter().map(|p| p[0]).collect();
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() <= 1e-15 * (1.0 + b.abs()));
    let mut rule = Vec::new();
    for w in cuts.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b - a <= 0.0 {
            continue;
        }
        let mid = 0.5 * (a + b);
        // The polygon's extent in v along a vertical line, linear in u on (a, b).
        let (lo_a, hi_a) = vertical_extent(polygon, mid, a);
        let (lo_b, hi_b) = vertical_extent(polygon, mid, b);
        for (s, ws) in g.nodes.iter().zip(&g.weights) {
            let u = a + (b - a) * s;
            let lo = lo_a + (lo_b - lo_a) * s;
            let hi = hi_a + (hi_b - hi_a) * s;
            if hi <= lo {
                continue;
            }
            for (t, wt) in g.nodes.iter().zip(&g.weights) {
                rule.push(([u, lo + (hi - lo) * t], ws * wt * (b - a) * (hi - lo)));
            }
        }
    }
    rule
}

/// The lowest and highest v, at u = `at` (an end of the slab), of the
/// polygon's edges that cross the slab's middle u = `mid`: no vertex lies
/// inside a slab, so exactly those edges bound it, each linear across it.
fn vertical_extent(polygon: &[Uv], mid: f64, at: f64) -> (f64, f64) {
    let n = polygon.len();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..n {
        let (p, q) = (polygon[i], polygon[(i + 1) % n]);
        let (u0, u1) = (p[0].min(q[0]), p[0].max(q[0]));
        if !(u0 < mid && mid < u1) {
            continue;
        }
        let v = p[1] + (q[1] - p[1]) * (at - p[0]) / (q[0] - p[0]);
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (lo, hi)
}

/// The same integral by a fan of triangles from vertex 0, each integrated
/// by Duffy's collapsed Gauss–Legendre rule with q points per direction
/// (exact for total degree ≤ 2q − 2): a check on [`trapezoid_rule`].
pub fn fan_rule(polygon: &[Uv], q: usize) -> Rule {
    let g = GaussLegendre::new(q);
    let mut rule = Vec::new();
    let p0 = polygon[0];
    for k in 1..polygon.len() - 1 {
        let (p1, p2) = (polygon[k], polygon[k + 1]);
        let e1 = [p1[0] - p0[0], p1[1] - p0[1]];
        let e2 = [p2[0] - p0[0], p2[1] - p0[1]];
        let det = (e1[0] * e2[1] - e1[1] * e2[0]).abs();
        for (s, ws) in g.nodes.iter().zip(&g.weights) {
            for (t, wt) in g.nodes.iter().zip(&g.weights) {
                // (a, b) = (s, (1 − s)t) covers the unit triangle, Jacobian 1 − s.
                let (a, b) = (*s, (1.0 - s) * t);
                rule.push((
                    [p0[0] + a * e1[0] + b * e2[0], p0[1] + a * e1[1] + b * e2[1]],
                    ws * wt * (1.0 - s) * det,
                ));
            }
        }
    }
    rule
}

/// The part of the convex polygon inside the half-plane where
/// `(p − a) × (b − a) ≤ 0`, i.e. left of the directed line a → b
/// (Sutherland–Hodgman); may come back with fewer than 3 vertices.
fn clip(polygon: &[Uv], a: Uv, b: Uv) -> Vec<Uv> {
    let side = |p: Uv| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
    let n = polygon.len();
    let mut out = Vec::with_capacity(n + 1);
    for i in 0..n {
        let (p, q) = (polygon[i], polygon[(i + 1) % n]);
        let (sp, sq) = (side(p), side(q));
        if sp >= 0.0 {
            out.push(p);
        }
        if (sp >= 0.0) != (sq >= 0.0) {
            let t = sp / (sp - sq);
            out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    out
}

/// The part of a counter-clockwise convex polygon inside the
/// counter-clockwise triangle `tri`, or None when they overlap in less
/// than a sliver (area ≤ 1e-14 of the triangle's).
pub fn clip_to_triangle(polygon: &[Uv], tri: [Uv; 3]) -> Option<Vec<Uv>> {
    let mut p = polygon.to_vec();
    for k in 0..3 {
        p = clip(&p, tri[k], tri[(k + 1) % 3]);
        if p.len() < 3 {
            return None;
        }
    }
    (signed_area(&p) > 1e-14 * signed_area(&tri).abs()).then_some(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn integrate(rule: &Rule, f: impl Fn(f64, f64) -> f64) -> f64 {
        rule.iter().map(|(p, w)| w * f(p[0], p[1])).sum()
    }

    #[test]
    fn trapezoids_integrate_monomials_over_the_unit_triangle_exactly() {
        // ∫_T u^i v^j = i! j! / (i + j + 2)!
        let fact = |n: usize| (1..=n).map(|k| k as f64).product::<f64>();
        let tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        for i in 0..6 {
            for j in 0..6 - i {
                let rule = trapezoid_rule(&tri, i + j);
                let got = integrate(&rule, |u, v| u.powi(i as i32) * v.powi(j as i32));
                let want = fact(i) * fact(j) / fact(i + j + 2);
                assert!((got - want).abs() < 1e-15, "u^{i} v^{j}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn trapezoid_and_fan_rules_agree_on_a_pentagon() {
        let p = convex(
            &[
                [0.1, 0.1],
                [0.5, 0.05],
                [0.6, 0.3],
                [0.3, 0.55],
                [0.05, 0.4],
            ],
            "region",
        )
        .unwrap();
        let f = |u: f64, v: f64| (1.0 + u * u * v - 3.0 * v.powi(4)) * (2.0 - u).powi(3);
        let a = integrate(&trapezoid_rule(&p, 8), f);
        let b = integrate(&fan_rule(&p, 12), f);
        assert!((a - b).abs() < 1e-15 * a.abs().max(1.0), "{a} vs {b}");
        let area = integrate(&trapezoid_rule(&p, 0), |_, _| 1.0);
        assert!((area - signed_area(&p)).abs() < 1e-15);
    }

    #[test]
    fn vertical_edges_and_clockwise_input_are_handled() {
        let square = convex(&[[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]], "sq").unwrap();
        assert!(signed_area(&square) > 0.0);
        let got = integrate(&trapezoid_rule(&square, 4), |u, v| u * u * v * v);
        assert!((got - 1.0 / 9.0).abs() < 1e-15);
    }

    #[test]
    fn clipping_splits_a_region_into_pieces_that_add_up() {
        // The unit square cut by its diagonal into two triangles.
        let region = convex(&[[0.2, 0.1], [0.9, 0.3], [0.7, 0.8], [0.1, 0.6]], "r").unwrap();
        let lower = clip_to_triangle(&region, [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]).unwrap();
        let upper = clip_to_triangle(&region, [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]).unwrap();
        let f = |u: f64, v: f64| u.powi(3) + u * v * v + 1.0;
        let whole = integrate(&trapezoid_rule(&region, 3), f);
        let parts =
            integrate(&trapezoid_rule(&lower, 3), f) + integrate(&trapezoid_rule(&upper, 3), f);
        assert!((whole - parts).abs() < 1e-15, "{whole} vs {parts}");
        assert!(clip_to_triangle(&region, [[2.0, 2.0], [3.0, 2.0], [2.0, 3.0]]).is_none());
    }

    #[test]
    fn bad_polygons_are_errors() {
        assert!(convex(&[[0.0, 0.0], [1.0, 0.0]], "r").is_err());
        assert!(convex(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]], "r").is_err());
        let dart = [[0.0, 0.0], [1.0, 0.0], [0.3, 0.3], [0.0, 1.0]];
        let e = convex(&dart, "operators[0].region")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("operators[0].region") && e.contains("convex"),
            "{e}"
        );
        assert!(convex(&[[0.0, 0.0], [f64::NAN, 0.0], [0.0, 1.0]], "r").is_err());
    }
}
