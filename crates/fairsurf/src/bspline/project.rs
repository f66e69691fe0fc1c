//! A guide surface of any kind for a B-spline problem: S a B-spline over
//! the same domain on its own knots and degrees (a Bézier patch is one
//! without interior knots). Wu & Yang's guide term ½γ∫|R − S|² splits, with
//! P the L² projection onto R's spline space,
//!
//! ```text
//! ∫|R − S|² = ∫|R − PS|² + ∫|S − PS|²       (R − PS ⊥ S − PS)
//! ```
//!
//! so the problem is the same-knots guide PS plus a constant. PS = s* with
//! (M_u ⊗ M_v) s* = (C_u ⊗ C_v) S: M the 1-D Gram matrices ∫N_k N_l of R's
//! basis, C the cross Gram matrices ∫N_k A_i of R's and S's bases, exact by
//! Gauss–Legendre on the union of both knot vectors' breakpoints. The
//! constant ∫|S − PS|² is integrated as it stands (exact; as ∫|S|² − s*ᵀMs*
//! it would cancel). The check's second road integrates |R − S|² directly
//! ([`guide_value_by_quadrature`]).

use super::{BSplineSurface, KnotVector};
use crate::basis::GaussLegendre;
use crate::{Error, Result, Vec3};
use faer::linalg::solvers::Solve;
use faer::Mat;

/// ∫ f_k g_l over the domain for the bases of `a` and `b` (r-th
/// derivatives 0): rows a's functions, columns b's; exact by Gauss with
/// enough nodes on every piece between both knot vectors' breakpoints.
fn cross_gram(a: &KnotVector, b: &KnotVector) -> Mat<f64> {
    let (pa, pb) = (a.degree(), b.degree());
    let mut cuts: Vec<f64> = a.knots().iter().chain(b.knots()).copied().collect();
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let rule = GaussLegendre::new((pa + pb) / 2 + 1);
    let mut m = Mat::<f64>::zeros(a.count(), b.count());
    for w in cuts.windows(2) {
        let (lo, hi) = (w[0], w[1]);
        if hi <= lo {
            continue;
        }
        let mid = 0.5 * (lo + hi);
        let (ka, kb) = (a.span(mid), b.span(mid));
        for (x, wx) in rule.nodes.iter().zip(&rule.weights) {
            let t = lo + (hi - lo) * x;
            let (na, nb) = (
                &a.basis_derivatives(ka, t, 0)[0],
                &b.basis_derivatives(kb, t, 0)[0],
            );
            let w = wx * (hi - lo);
            for (i, fa) in na.iter().enumerate() {
                for (j, fb) in nb.iter().enumerate() {
                    m[(ka - pa + i, kb - pb + j)] += w * fa * fb;
                }
            }
        }
    }
    m
}

/// M_u X M_vᵀ-type products: (A S Bᵀ) per coordinate for a row-major net S
/// of `rows` × `cols` points.
fn sandwich(a: &Mat<f64>, s: &[Vec3], cols: usize, b: &Mat<f64>) -> [Mat<f64>; 3] {
    let rows = s.len() / cols;
    std::array::from_fn(|c| {
        let x = Mat::from_fn(rows, cols, |i, j| s[i * cols + j][c]);
        a * &x * b.transpose()
    })
}

/// The L² projection PS of `guide` onto the spline space of `onto` (its
/// net, row-major) and ∫|S − PS|² dA.
pub(crate) fn project(onto: &BSplineSurface, guide: &BSplineSurface) -> Result<(Vec<Vec3>, f64)> {
    onto.check_domain(guide, "guide surface")?;
    let ((ru, rv), (su, sv)) = (onto.knots(), guide.knots());
    let (mu, mv) = (cross_gram(ru, ru), cross_gram(rv, rv));
    let (cu, cv) = (cross_gram(ru, su), cross_gram(rv, sv));
    let (lu, lv) = (mu.llt(faer::Side::Lower), mv.llt(faer::Side::Lower));
    let (lu, lv) = match (lu, lv) {
        (Ok(a), Ok(b)) => (a, b),
        _ => {
            return Err(Error::Mismatch {
                what: "guide surface projection".into(),
                expected: "positive definite Gram matrices of the surface's basis".into(),
                got: "a singular one".into(),
            })
        }
    };
    let (nu, nv) = onto.counts();
    let c = sandwich(&cu, guide.points(), guide.counts().1, &cv);
    let mut net = vec![[0.0; 3]; nu * nv];
    for (k, ck) in c.iter().enumerate() {
        // s* = M_u⁻¹ C M_v⁻¹ (M symmetric).
        let y = lu.solve(ck);
        let x = lv.solve(y.transpose()).transpose().to_owned();
        for i in 0..nu {
            for j in 0..nv {
                net[i * nv + j][k] = x[(i, j)];
            }
        }
    }
    // ∫|S − PS|² by quadrature of the difference itself (exact): as
    // ∫|S|² − s*ᵀMs* it cancels to rounding noise of ∫|S|² when S lies
    // near the space, which the check would then see (coordinates far from
    // the origin: 1e-7 relative).
    let projected = onto.with_points(net.clone());
    let rest = guide_value_by_quadrature(&projected, guide, 2.0);
    Ok((net, rest))
}

/// ½γ∫|R − S|² dA by Gauss–Legendre on every rectangle between both
/// surfaces' knot lines (exact: one polynomial there), R and S by de Boor.
pub(crate) fn guide_value_by_quadrature(
    r: &BSplineSurface,
    s: &BSplineSurface,
    weight: f64,
) -> f64 {
    let cuts = |a: &KnotVector, b: &KnotVector| {
        let mut c: Vec<f64> = a.knots().iter().chain(b.knots()).copied().collect();
        c.sort_by(f64::total_cmp);
        c.dedup();
        c
    };
    let (ru, rv) = r.knots();
    let (su, sv) = s.knots();
    let (cu, cv) = (cuts(ru, su), cuts(rv, sv));
    let (gu, gv) = (
        GaussLegendre::new(ru.degree().max(su.degree()) + 1),
        GaussLegendre::new(rv.degree().max(sv.degree()) + 1),
    );
    let nodes = |cuts: &[f64], g: &GaussLegendre| -> Vec<(f64, f64)> {
        cuts.windows(2)
            .filter(|w| w[1] > w[0])
            .flat_map(|w| {
                g.nodes
                    .iter()
                    .zip(&g.weights)
                    .map(move |(x, wx)| (w[0] + (w[1] - w[0]) * x, wx * (w[1] - w[0])))
            })
            .collect()
    };
    let (nu, nv) = (nodes(&cu, &gu), nodes(&cv, &gv));
    let (us, vs): (Vec<f64>, Vec<f64>) = (
        nu.iter().map(|n| n.0).collect(),
        nv.iter().map(|n| n.0).collect(),
    );
    let (a, b) = (r.derivatives_on(&us, &vs), s.derivatives_on(&us, &vs));
    let mut total = 0.0;
    for (i, (_, wu)) in nu.iter().enumerate() {
        for (j, (_, wv)) in nv.iter().enumerate() {
            let (x, y) = (a[i * vs.len() + j].point, b[i * vs.len() + j].point);
            let d = [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
            total += wu * wv * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
    }
    0.5 * weight * total
}
