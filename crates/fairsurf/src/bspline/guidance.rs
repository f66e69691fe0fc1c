//! Wu & Yang's guidance terms on B-spline surfaces: the normal field
//! ½λ∫∫ (R_u·N)² + (R_v·N)² (eq. 1–2; N a Bézier field over the knot
//! domain mapped onto [0, 1]², it couples x, y and z) and the guide surface
//! ½γ∫∫ |R − S|² (S a net on the same knots).
//!
//! The normal-field integrand is a polynomial on every span of degree
//! 2(p + n₁) in u (2(q + m₁) in v), so the (p + n₁ + 1) × (q + m₁ + 1)
//! Gauss–Legendre rule per span is exact for its Hessian and its value.
//!
//! The sampled variant (Wu & Yang eq. 5) sums over a uniform grid of
//! samples (u_i, v_j) = (i/np, j/mp) of the domain mapped onto [0, 1]²:
//! ½λ Σ λ_ij ((R_ũ·N_ij)² + (R_ṽ·N_ij)²) with unit normals N_ij and the
//! derivatives with respect to the mapped parameters ũ, ṽ, so that a
//! B-spline without interior knots on [0, 1] has the tensor scene's energy.

use super::energy::Gram1d;
use super::{BSplineSurface, BezierPiece};
use crate::basis::GaussLegendre;
use crate::energy::NormalGuide;
use crate::{TensorPatch, Vec3};

/// The normal-field term: λ and the guide, a Bézier field N or unit normals
/// at grid samples (normalized when the term is made).
#[derive(Clone, Debug)]
pub(crate) struct NormalTerm {
    pub weight: f64,
    pub guide: NormalGuide,
}

/// A sample of the sampled term: knot-domain (u, v), λ·λ_k and the unit
/// normal N_k.
type Sample = (f64, f64, f64, Vec3);

/// One Gauss node of a span: its weight (with the span's area), the
/// field there, and the basis functions' first derivatives (local index
/// i·(q+1) + j for N_{ku−p+i}(u) N_{kv−q+j}(v)).
pub(crate) struct Node {
    pub weight: f64,
    pub n: Vec3,
    pub du: Vec<f64>,
    pub dv: Vec<f64>,
}

impl NormalTerm {
    fn rule(
        field: &TensorPatch,
        surface: &BSplineSurface,
        extra: usize,
    ) -> (GaussLegendre, GaussLegendre) {
        let ((p, q), (n1, m1)) = (surface.degree(), field.degree());
        (
            GaussLegendre::new(p + n1 + 1 + extra),
            GaussLegendre::new(q + m1 + 1 + extra),
        )
    }

    /// N at the surface's parameters (u, v).
    fn field_at(field: &TensorPatch, surface: &BSplineSurface, u: f64, v: f64) -> Vec3 {
        let ((a, b), (c, d)) = (surface.knots().0.domain(), surface.knots().1.domain());
        field.eval((u - a) / (b - a), (v - c) / (d - c))
    }

    /// The samples as (knot-domain u, v, λ·λ_k, N_k), with the domain's
    /// extents (b − a, d − c) that turn ∂/∂u into ∂/∂ũ.
    fn samples(&self, surface: &BSplineSurface) -> Option<(Vec<Sample>, (f64, f64))> {
        let NormalGuide::Samples {
            grid,
            normals,
            weights,
        } = &self.guide
        else {
            return None;
        };
        let ((a, b), (c, d)) = (surface.knots().0.domain(), surface.knots().1.domain());
        let out = (0..grid.len())
            .map(|k| {
                let (su, sv) = grid.param(k);
                let w = self.weight * weights.as_ref().map_or(1.0, |w| w[k]);
                (a + (b - a) * su, c + (d - c) * sv, w, normals[k])
            })
            .collect();
        Some((out, (b - a, d - c)))
    }

    /// Every span (ku, kv) with its nodes, for the Hessian: Gauss nodes of
    /// a field, or the samples in it (a sample on a knot line counts once,
    /// in the span `KnotVector::span` gives).
    pub(crate) fn spans(&self, surface: &BSplineSurface) -> Vec<((usize, usize), Vec<Node>)> {
        let field = match &self.guide {
            NormalGuide::Field(f) => f,
            NormalGuide::Samples { .. } => return self.sample_spans(surface),
        };
        let (ku, kv) = surface.knots();
        let (gu, gv) = Self::rule(field, surface, 0);
        let (p, q) = surface.degree();
        let mut out = Vec::new();
        for &(su, u0, u1) in &ku.spans() {
            for &(sv, v0, v1) in &kv.spans() {
                let mut nodes = Vec::with_capacity(gu.nodes.len() * gv.nodes.len());
                for (&x, &wx) in gu.nodes.iter().zip(&gu.weights) {
                    let u = u0 + (u1 - u0) * x;
                    let bu = ku.basis_derivatives(su, u, 1);
                    for (&y, &wy) in gv.nodes.iter().zip(&gv.weights) {
                        let v = v0 + (v1 - v0) * y;
                        let bv = kv.basis_derivatives(sv, v, 1);
                        let (mut du, mut dv) = (Vec::new(), Vec::new());
                        for i in 0..=p {
                            for j in 0..=q {
                                du.push(bu[1][i] * bv[0][j]);
                                dv.push(bu[0][i] * bv[1][j]);
                            }
                        }
                        nodes.push(Node {
                            weight: self.weight * wx * wy * (u1 - u0) * (v1 - v0),
                            n: Self::field_at(field, surface, u, v),
                            du,
                            dv,
                        });
                    }
                }
                out.push(((su, sv), nodes));
            }
        }
        out
    }

    /// The samples grouped by span, with the basis derivatives with
    /// respect to the mapped parameters.
    fn sample_spans(&self, surface: &BSplineSurface) -> Vec<((usize, usize), Vec<Node>)> {
        let (samples, (su, sv)) = self.samples(surface).expect("a sampled guide");
        let (ku, kv) = surface.knots();
        let (p, q) = surface.degree();
        let mut by_span: std::collections::BTreeMap<(usize, usize), Vec<Node>> =
            std::collections::BTreeMap::new();
        for (u, v, w, n) in samples {
            let (k, l) = (ku.span(u), kv.span(v));
            let (bu, bv) = (ku.basis_derivatives(k, u, 1), kv.basis_derivatives(l, v, 1));
            let (mut du, mut dv) = (Vec::new(), Vec::new());
            for i in 0..=p {
                for j in 0..=q {
                    du.push(su * bu[1][i] * bv[0][j]);
                    dv.push(sv * bu[0][i] * bv[1][j]);
                }
            }
            by_span.entry((k, l)).or_default().push(Node {
                weight: w,
                n,
                du,
                dv,
            });
        }
        by_span.into_iter().collect()
    }

    /// ½λ∫∫ (R_u·N)² + (R_v·N)², from de Boor derivatives at the nodes (or
    /// the sampled sum).
    pub(crate) fn value(&self, surface: &BSplineSurface) -> f64 {
        if let Some((samples, (su, sv))) = self.samples(surface) {
            let total: f64 = samples
                .iter()
                .map(|&(u, v, w, n)| {
                    let d = surface.derivatives(u, v);
                    w * (dot(scale(d.du, su), n).powi(2) + dot(scale(d.dv, sv), n).powi(2))
                })
                .sum();
            return 0.5 * total;
        }
        let NormalGuide::Field(field) = &self.guide else {
            unreachable!("a field when not sampled")
        };
        let (gu, gv) = Self::rule(field, surface, 0);
        let (ku, kv) = surface.knots();
        let mut total = 0.0;
        for &(_, u0, u1) in &ku.spans() {
            for &(_, v0, v1) in &kv.spans() {
                for (&x, &wx) in gu.nodes.iter().zip(&gu.weights) {
                    for (&y, &wy) in gv.nodes.iter().zip(&gv.weights) {
                        let (u, v) = (u0 + (u1 - u0) * x, v0 + (v1 - v0) * y);
                        let d = surface.derivatives(u, v);
                        let n = Self::field_at(field, surface, u, v);
                        let w = wx * wy * (u1 - u0) * (v1 - v0);
                        total += w * (dot(d.du, n).powi(2) + dot(d.dv, n).powi(2));
                    }
                }
            }
        }
        0.5 * self.weight * total
    }

    /// The same by another road: one more node each way, from the Bézier
    /// pieces' derivatives.
    pub(crate) fn value_by_pieces(&self, surface: &BSplineSurface, pieces: &[BezierPiece]) -> f64 {
        if let Some((samples, (su, sv))) = self.samples(surface) {
            // Each sample in the piece whose rectangle holds it (the one
            // KnotVector::span names), by the piece's Bernstein derivatives.
            let (ku, kv) = surface.knots();
            let (spans_u, spans_v) = (ku.spans(), kv.spans());
            let total: f64 = samples
                .iter()
                .map(|&(u, v, w, n)| {
                    let a = spans_u
                        .iter()
                        .position(|s| s.0 == ku.span(u))
                        .expect("a span");
                    let b = spans_v
                        .iter()
                        .position(|s| s.0 == kv.span(v))
                        .expect("a span");
                    let piece = &pieces[a * spans_v.len() + b];
                    let (hu, hv) = (piece.u.1 - piece.u.0, piece.v.1 - piece.v.0);
                    let d = piece
                        .patch
                        .derivatives((u - piece.u.0) / hu, (v - piece.v.0) / hv);
                    let (ru, rv) = (scale(d.du, su / hu), scale(d.dv, sv / hv));
                    w * (dot(ru, n).powi(2) + dot(rv, n).powi(2))
                })
                .sum();
            return 0.5 * total;
        }
        let NormalGuide::Field(field) = &self.guide else {
            unreachable!("a field when not sampled")
        };
        let (gu, gv) = Self::rule(field, surface, 1);
        let mut total = 0.0;
        for piece in pieces {
            let (hu, hv) = (piece.u.1 - piece.u.0, piece.v.1 - piece.v.0);
            let d = piece.patch.grid_derivatives(&gu.nodes, &gv.nodes);
            for (a, (&x, &wx)) in gu.nodes.iter().zip(&gu.weights).enumerate() {
                for (b, (&y, &wy)) in gv.nodes.iter().zip(&gv.weights).enumerate() {
                    let g = &d[a * gv.nodes.len() + b];
                    let n = Self::field_at(field, surface, piece.u.0 + hu * x, piece.v.0 + hv * y);
                    let (ru, rv) = (scale(g.du, 1.0 / hu), scale(g.dv, 1.0 / hv));
                    total += wx * wy * hu * hv * (dot(ru, n).powi(2) + dot(rv, n).powi(2));
                }
            }
        }
        0.5 * self.weight * total
    }
}

/// ½γ Σ_c (x − s)ᵀ (M₀ᵘ ⊗ M₀ᵛ) (x − s): the guide term from the 1-D Gram
/// matrices, on the difference (whose entries are all ≥ 0 in M₀: no
/// cancellation).
pub(crate) fn guide_value(gu: &Gram1d, gv: &Gram1d, weight: f64, x: &[Vec3], s: &[Vec3]) -> f64 {
    let cv = gv.count();
    let diff: Vec<Vec3> = x
        .iter()
        .zip(s)
        .map(|(a, b)| [a[0] - b[0], a[1] - b[1], a[2] - b[2]])
        .collect();
    let mut total = 0.0;
    for (k, dk) in diff.iter().enumerate() {
        let (i, j) = (k / cv, k % cv);
        for i2 in gu.band(i) {
            for j2 in gv.band(j) {
                let m = gu.at(0, i, i2) * gv.at(0, j, j2);
                total += m * dot(*dk, diff[i2 * cv + j2]);
            }
        }
    }
    0.5 * weight * total
}

/// The guide term by Gauss quadrature of |R − S|² over the pieces of both.
pub(crate) fn guide_value_by_pieces(
    pieces: &[BezierPiece],
    guide: &[BezierPiece],
    (p, q): (usize, usize),
    weight: f64,
) -> f64 {
    let (gu, gv) = (GaussLegendre::new(p + 1), GaussLegendre::new(q + 1));
    let mut total = 0.0;
    for (r, s) in pieces.iter().zip(guide) {
        let (hu, hv) = (r.u.1 - r.u.0, r.v.1 - r.v.0);
        for (&x, &wx) in gu.nodes.iter().zip(&gu.weights) {
            for (&y, &wy) in gv.nodes.iter().zip(&gv.weights) {
                let (a, b) = (r.patch.eval(x, y), s.patch.eval(x, y));
                let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
                total += wx * wy * hu * hv * dot(d, d);
            }
        }
    }
    0.5 * weight * total
}

fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn scale(a: Vec3, s: f64) -> Vec3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
