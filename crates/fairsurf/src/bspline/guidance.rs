//! Wu & Yang's guidance terms on B-spline surfaces: the normal field
//! ½λ∫∫ (R_u·N)² + (R_v·N)² (eq. 1–2; N a Bézier field over the knot
//! domain mapped onto [0, 1]², or a B-spline field on its own knots over
//! the knot domain; it couples x, y and z) and the guide surface
//! ½γ∫∫ |R − S|² (S a net on the same knots).
//!
//! The normal-field integrand is a polynomial of degree 2(p + n₁) in u
//! (2(q + m₁) in v) on every span of the surface — on every piece of it
//! between the field's knot lines for a B-spline field — so the
//! (p + n₁ + 1) × (q + m₁ + 1) Gauss–Legendre rule per piece is exact for
//! its Hessian and its value.
//!
//! The sampled variant (Wu & Yang eq. 5) sums over a uniform grid of
//! samples (u_i, v_j) = (i/np, j/mp) of the domain mapped onto [0, 1]²:
//! ½λ Σ λ_ij ((R_ũ·N_ij)² + (R_ṽ·N_ij)²) with unit normals N_ij and the
//! derivatives with respect to the mapped parameters ũ, ṽ, so that a
//! B-spline without interior knots on [0, 1] has the tensor scene's energy.

use super::energy::Gram1d;
use super::{BSplineSurface, BezierPiece, KnotVector};
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

/// A span's samples in one direction: (sample index, [basis values,
/// derivatives]).
type AxisNodes = Vec<(usize, [Vec<f64>; 2])>;

/// The nodes of one span, a tensor grid (Gauss nodes of a field, or the
/// samples that fall in the span): at each u node the p + 1 nonzero basis
/// functions N_{ku−p+i} and their derivatives (with respect to the mapped
/// parameter for samples), likewise in v, and at node (s, t) the weight
/// (with the span's area, and λ) and the field N.
pub(crate) struct SpanGrid {
    pub span: (usize, usize),
    /// Per u node: [values, derivatives], p + 1 each.
    pub bu: Vec<[Vec<f64>; 2]>,
    /// Per v node: [values, derivatives], q + 1 each.
    pub bv: Vec<[Vec<f64>; 2]>,
    /// Weight at node (s, t), row-major s·nv + t.
    pub weight: Vec<f64>,
    /// N at node (s, t).
    pub n: Vec<Vec3>,
}

impl SpanGrid {
    /// The span's local Hessian Σ_nodes w (Y Yᵀ + Z Zᵀ), Y = ∂_u B ⊗ N,
    /// Z = ∂_v B ⊗ N, as an m × m matrix (m = 3(p+1)(q+1), row 3a + c for
    /// basis function a = i(q+1) + j and coordinate c), by sum
    /// factorization over the grid: for each pair (c, d),
    /// Σ_s N′_i(u_s) N′_i′(u_s) Σ_t w_st n_c n_d N_j(v_t) N_j′(v_t), and the
    /// same with the derivative in v — (p+1)²(q+1)² per u node instead of
    /// 9(p+1)²(q+1)² per node.
    pub fn local(&self) -> Vec<f64> {
        let (pu, pv) = (self.bu[0][0].len(), self.bv[0][0].len());
        let (nu, nv) = (self.bu.len(), self.bv.len());
        let size = pu * pv;
        let m = 3 * size;
        let mut local = vec![0.0f64; m * m];
        let mut t = vec![0.0f64; pv * pv];
        for c in 0..3 {
            for d in c..3 {
                // (u factor index, v factor index): the u-derivative term
                // pairs N′(u) with N(v), the v-derivative term N(u) with N′(v).
                for (ku, kv) in [(1, 0), (0, 1)] {
                    for s in 0..nu {
                        t.fill(0.0);
                        for tt in 0..nv {
                            let k = s * nv + tt;
                            let w = self.weight[k] * self.n[k][c] * self.n[k][d];
                            if w == 0.0 {
                                continue;
                            }
                            let b = &self.bv[tt][kv];
                            for j in 0..pv {
                                let wj = w * b[j];
                                for j2 in 0..pv {
                                    t[j * pv + j2] += wj * b[j2];
                                }
                            }
                        }
                        // The (c, d) block is symmetric in its basis pair
                        // (a, b) (both factors are): its upper triangle
                        // a ≤ b here, the rest mirrored below.
                        let b = &self.bu[s][ku];
                        for i in 0..pu {
                            for i2 in i..pu {
                                let f = b[i] * b[i2];
                                if f == 0.0 {
                                    continue;
                                }
                                for j in 0..pv {
                                    let row = 3 * (i * pv + j) + c;
                                    let from = if i2 == i { j } else { 0 };
                                    for j2 in from..pv {
                                        let col = 3 * (i2 * pv + j2) + d;
                                        local[row * m + col] += f * t[j * pv + j2];
                                    }
                                }
                            }
                        }
                    }
                }
                // Mirror: entry (3b + c, 3a + d) = (3a + c, 3b + d) for a < b,
                // and the (d, c) block is the (c, d) one.
                for a in 0..size {
                    for b in a..size {
                        let v = local[(3 * a + c) * m + 3 * b + d];
                        local[(3 * b + c) * m + 3 * a + d] = v;
                        local[(3 * a + d) * m + 3 * b + c] = v;
                        local[(3 * b + d) * m + 3 * a + c] = v;
                    }
                }
            }
        }
        local
    }
}

/// An exactly integrated field: a Bézier patch over the knot domain
/// mapped onto [0, 1]², or a B-spline on its own knots over the domain.
#[derive(Clone, Copy)]
enum Exact<'a> {
    Bezier(&'a TensorPatch),
    Spline(&'a BSplineSurface),
}

impl Exact<'_> {
    fn degree(self) -> (usize, usize) {
        match self {
            Exact::Bezier(f) => f.degree(),
            Exact::Spline(f) => f.degree(),
        }
    }

    /// N at the surface's parameters (u, v).
    fn at(self, surface: &BSplineSurface, u: f64, v: f64) -> Vec3 {
        match self {
            Exact::Bezier(f) => {
                let ((a, b), (c, d)) = (surface.knots().0.domain(), surface.knots().1.domain());
                f.eval((u - a) / (b - a), (v - c) / (d - c))
            }
            Exact::Spline(f) => f.eval(u, v),
        }
    }

    /// The Gauss nodes of [lo, hi] in direction `k` (0: u): the rule on
    /// every piece between the field's interior knots inside the interval,
    /// as (t, weight × the piece's length).
    fn nodes(self, k: usize, (lo, hi): (f64, f64), rule: &GaussLegendre) -> Vec<(f64, f64)> {
        let mut cuts = vec![lo];
        if let Exact::Spline(f) = self {
            let knots: &KnotVector = if k == 0 { f.knots().0 } else { f.knots().1 };
            let mut inner: Vec<f64> = knots
                .knots()
                .iter()
                .copied()
                .filter(|&t| t > lo && t < hi)
                .collect();
            inner.dedup();
            cuts.extend(inner);
        }
        cuts.push(hi);
        cuts.windows(2)
            .flat_map(|w| {
                let (a, b) = (w[0], w[1]);
                rule.nodes
                    .iter()
                    .zip(&rule.weights)
                    .map(move |(&x, &wx)| (a + (b - a) * x, wx * (b - a)))
            })
            .collect()
    }
}

impl NormalTerm {
    /// The exact field, unless the term is sampled.
    fn exact(&self) -> Option<Exact<'_>> {
        match &self.guide {
            NormalGuide::Field(f) => Some(Exact::Bezier(f)),
            NormalGuide::Spline(f) => Some(Exact::Spline(f)),
            NormalGuide::Samples { .. } => None,
        }
    }

    fn rule(
        field: Exact,
        surface: &BSplineSurface,
        extra: usize,
    ) -> (GaussLegendre, GaussLegendre) {
        let ((p, q), (n1, m1)) = (surface.degree(), field.degree());
        (
            GaussLegendre::new(p + n1 + 1 + extra),
            GaussLegendre::new(q + m1 + 1 + extra),
        )
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

    /// Every span's node grid, for the Hessian: Gauss nodes of a field, or
    /// the samples in it (a sample on a knot line counts once, in the span
    /// `KnotVector::span` gives).
    pub(crate) fn spans(&self, surface: &BSplineSurface) -> Vec<SpanGrid> {
        let Some(field) = self.exact() else {
            return self.sample_spans(surface);
        };
        let (ku, kv) = surface.knots();
        let (gu, gv) = Self::rule(field, surface, 0);
        let mut out = Vec::new();
        for &(su, u0, u1) in &ku.spans() {
            let us = field.nodes(0, (u0, u1), &gu);
            let bu: Vec<[Vec<f64>; 2]> = us
                .iter()
                .map(|&(u, _)| {
                    let b = ku.basis_derivatives(su, u, 1);
                    [b[0].clone(), b[1].clone()]
                })
                .collect();
            for &(sv, v0, v1) in &kv.spans() {
                let vs = field.nodes(1, (v0, v1), &gv);
                let bv = vs
                    .iter()
                    .map(|&(v, _)| {
                        let b = kv.basis_derivatives(sv, v, 1);
                        [b[0].clone(), b[1].clone()]
                    })
                    .collect();
                let mut weight = Vec::with_capacity(us.len() * vs.len());
                let mut n = Vec::with_capacity(us.len() * vs.len());
                for &(u, wu) in &us {
                    for &(v, wv) in &vs {
                        weight.push(self.weight * wu * wv);
                        n.push(field.at(surface, u, v));
                    }
                }
                out.push(SpanGrid {
                    span: (su, sv),
                    bu: bu.clone(),
                    bv,
                    weight,
                    n,
                });
            }
        }
        out
    }

    /// The samples grouped by span (the samples of a span are the grid's u
    /// samples in its u-interval times its v samples in its v-interval),
    /// with the basis derivatives with respect to the mapped parameters.
    fn sample_spans(&self, surface: &BSplineSurface) -> Vec<SpanGrid> {
        let NormalGuide::Samples { grid, .. } = &self.guide else {
            unreachable!("a sampled guide");
        };
        // λ·λ_k and N_k per sample, row-major (the sampled value's own list).
        let (samples, _) = self.samples(surface).expect("a sampled guide");
        let (ku, kv) = surface.knots();
        let (np, mp) = grid.size();
        // Per direction, by span: (sample index, [basis values, derivatives
        // with respect to the mapped parameter]).
        let axis = |k: &crate::bspline::KnotVector, count: usize| {
            let (lo, hi) = k.domain();
            let mut by_span: std::collections::BTreeMap<usize, AxisNodes> = Default::default();
            for i in 0..=count {
                let x = lo + (hi - lo) * (i as f64 / count as f64);
                let span = k.span(x);
                let mut bs = k.basis_derivatives(span, x, 1);
                let d: Vec<f64> = bs[1].iter().map(|v| v * (hi - lo)).collect();
                by_span
                    .entry(span)
                    .or_default()
                    .push((i, [bs.swap_remove(0), d]));
            }
            by_span
        };
        let (gu, gv) = (axis(ku, np), axis(kv, mp));
        let mut out = Vec::new();
        for (&su, us) in &gu {
            for (&sv, vs) in &gv {
                let (weight, n) = us
                    .iter()
                    .flat_map(|(i, _)| vs.iter().map(move |(j, _)| i * (mp + 1) + j))
                    .map(|k| (samples[k].2, samples[k].3))
                    .unzip();
                out.push(SpanGrid {
                    span: (su, sv),
                    bu: us.iter().map(|(_, b)| b.clone()).collect(),
                    bv: vs.iter().map(|(_, b)| b.clone()).collect(),
                    weight,
                    n,
                });
            }
        }
        out
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
        let field = self.exact().expect("a field when not sampled");
        let (gu, gv) = Self::rule(field, surface, 0);
        let (ku, kv) = surface.knots();
        let mut total = 0.0;
        for &(_, u0, u1) in &ku.spans() {
            let us = field.nodes(0, (u0, u1), &gu);
            for &(_, v0, v1) in &kv.spans() {
                for &(v, wv) in &field.nodes(1, (v0, v1), &gv) {
                    for &(u, wu) in &us {
                        let d = surface.derivatives(u, v);
                        let n = field.at(surface, u, v);
                        total += wu * wv * (dot(d.du, n).powi(2) + dot(d.dv, n).powi(2));
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
        let field = self.exact().expect("a field when not sampled");
        let (gu, gv) = Self::rule(field, surface, 1);
        let mut total = 0.0;
        for piece in pieces {
            let (hu, hv) = (piece.u.1 - piece.u.0, piece.v.1 - piece.v.0);
            let (us, vs) = (field.nodes(0, piece.u, &gu), field.nodes(1, piece.v, &gv));
            let xs: Vec<f64> = us.iter().map(|&(u, _)| (u - piece.u.0) / hu).collect();
            let ys: Vec<f64> = vs.iter().map(|&(v, _)| (v - piece.v.0) / hv).collect();
            let d = piece.patch.derivatives_on(&xs, &ys);
            for (a, &(u, wu)) in us.iter().enumerate() {
                for (b, &(v, wv)) in vs.iter().enumerate() {
                    let g = &d[a * vs.len() + b];
                    let n = field.at(surface, u, v);
                    let (ru, rv) = (scale(g.du, 1.0 / hu), scale(g.dv, 1.0 / hv));
                    total += wu * wv * (dot(ru, n).powi(2) + dot(rv, n).powi(2));
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
