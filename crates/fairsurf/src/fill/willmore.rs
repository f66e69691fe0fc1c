//! Lowering W = ∫∫ κ₁² + κ₂² dA of a fill with its two outer rings fixed.
//!
//! With position and tangent plane fixed along the boundary, ∫∫ K dA is
//! fixed too (Gauss–Bonnet: 2π minus the boundary's geodesic curvature and
//! turning angles), so W = ∫∫ 4H² dA − 2∫∫ K dA is lowered exactly when the
//! Willmore energy ∫∫ 4H² dA is. On a surface, Δ_g R = 2H n (Δ_g the
//! Laplace–Beltrami operator of its metric g), so ∫∫ 4H² dA = ∫∫ |Δ_g R|² dA_g.
//! With g (and the Christoffel symbols Γ^k_ij = g^kl R_ij·R_l) frozen at a
//! reference surface this is a quadratic form in R,
//!
//! ```text
//! E(R) = ∫∫ |g^ij (R_ij − Γ^k_ij R_k)|² √det g du dv
//! ```
//!
//! one scalar operator for x, y and z; its minimizer over the free control
//! points becomes the next reference (a linearized Willmore flow taken to
//! its fixed point). The integrand is rational: Gauss–Legendre with
//! p + q + 4 nodes per span and direction.

use crate::basis::GaussLegendre;
use crate::bspline::BSplineSurface;
use crate::vec3::dot;
use crate::{Error, Result, Vec3};
use faer::Mat;

/// One step: the surface on `reference`'s knots that minimizes E with g
/// and Γ from `reference`, the points where `free` is false kept.
pub(crate) fn step(reference: &BSplineSurface, free: &[bool]) -> Result<BSplineSurface> {
    let (ku, kv) = reference.knots();
    let ((p, q), (_, cv)) = (reference.degree(), reference.counts());
    let slot: Vec<Option<usize>> = {
        let mut k = 0;
        free.iter()
            .map(|&f| {
                f.then(|| {
                    k += 1;
                    k - 1
                })
            })
            .collect()
    };
    let nf = free.iter().filter(|&&f| f).count();
    let mut h = Mat::<f64>::zeros(nf, nf);
    let mut b = Mat::<f64>::zeros(nf, 3);
    let (gu, gv) = (GaussLegendre::new(p + q + 4), GaussLegendre::new(p + q + 4));
    let size = (p + 1) * (q + 1);
    let nodes = gu.nodes.len() * gv.nodes.len();
    // Per span: the rows √w·L(B_a) at every node, and LᵀL by one product.
    let mut lm = Mat::<f64>::zeros(nodes, size);
    for &(su, u0, u1) in &ku.spans() {
        let us: Vec<f64> = gu.nodes.iter().map(|&x| u0 + (u1 - u0) * x).collect();
        let bu: Vec<Vec<Vec<f64>>> = us.iter().map(|&u| ku.basis_derivatives(su, u, 2)).collect();
        for &(sv, v0, v1) in &kv.spans() {
            let vs: Vec<f64> = gv.nodes.iter().map(|&y| v0 + (v1 - v0) * y).collect();
            let bv: Vec<Vec<Vec<f64>>> =
                vs.iter().map(|&v| kv.basis_derivatives(sv, v, 2)).collect();
            let grid = reference.derivatives_on(&us, &vs);
            lm.fill(0.0);
            for (x, &wx) in gu.weights.iter().enumerate() {
                let nu = &bu[x];
                for (y, &wy) in gv.weights.iter().enumerate() {
                    let nv = &bv[y];
                    let d = &grid[x * vs.len() + y];
                    let (e, f, g) = (dot(d.du, d.du), dot(d.du, d.dv), dot(d.dv, d.dv));
                    let det = e * g - f * f;
                    if det.is_nan() || det <= 0.0 {
                        continue;
                    }
                    // g^ij and Γ^k_ij = g^kl (R_ij · R_l) for ij = uu, uv, vv.
                    let gi = [g / det, -f / det, e / det];
                    let gamma = |rij: Vec3| {
                        let (a, c) = (dot(rij, d.du), dot(rij, d.dv));
                        (gi[0] * a + gi[1] * c, gi[1] * a + gi[2] * c)
                    };
                    let (guu, guv, gvv) = (gamma(d.duu), gamma(d.duv), gamma(d.dvv));
                    // L(B) = g^uu (B_uu − Γ·B′) + 2 g^uv (B_uv − Γ·B′) + g^vv (B_vv − Γ·B′).
                    let cu = gi[0] * guu.0 + 2.0 * gi[1] * guv.0 + gi[2] * gvv.0;
                    let cvv = gi[0] * guu.1 + 2.0 * gi[1] * guv.1 + gi[2] * gvv.1;
                    let sw = (wx * wy * (u1 - u0) * (v1 - v0) * det.sqrt()).sqrt();
                    let row = x * vs.len() + y;
                    for i in 0..=p {
                        for j in 0..=q {
                            lm[(row, i * (q + 1) + j)] = sw
                                * (gi[0] * nu[2][i] * nv[0][j]
                                    + 2.0 * gi[1] * nu[1][i] * nv[1][j]
                                    + gi[2] * nu[0][i] * nv[2][j]
                                    - cu * nu[1][i] * nv[0][j]
                                    - cvv * nu[0][i] * nv[1][j]);
                        }
                    }
                }
            }
            // Small products: sequential (a thread pool's start costs more).
            let mut local = Mat::<f64>::zeros(size, size);
            faer::linalg::matmul::matmul(
                local.as_mut(),
                faer::Accum::Replace,
                lm.transpose(),
                lm.as_ref(),
                1.0,
                faer::Par::Seq,
            );
            for a in 0..size {
                let ka = (su - p + a / (q + 1)) * cv + sv - q + a % (q + 1);
                let Some(ra) = slot[ka] else { continue };
                for c in 0..size {
                    let kc = (su - p + c / (q + 1)) * cv + sv - q + c % (q + 1);
                    let hac = local[(a, c)];
                    match slot[kc] {
                        Some(rc) => h[(ra, rc)] += hac,
                        None => {
                            let pt = reference.points()[kc];
                            for k in 0..3 {
                                b[(ra, k)] -= hac * pt[k];
                            }
                        }
                    }
                }
            }
        }
    }
    let llt = h.llt(faer::Side::Lower).map_err(|_| Error::Fill {
        why: "the linearized Willmore system is not positive definite".into(),
    })?;
    let x = faer::linalg::solvers::Solve::solve(&llt, &b);
    let points = reference
        .points()
        .iter()
        .zip(&slot)
        .map(|(&pt, s)| s.map_or(pt, |r| [x[(r, 0)], x[(r, 1)], x[(r, 2)]]))
        .collect();
    Ok(reference.with_points(points))
}
