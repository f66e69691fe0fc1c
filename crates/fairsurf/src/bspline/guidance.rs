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

/// The sampled term on a surface's domain: the grid's u_i and v_j mapped
/// onto the knot domain, λ·λ_k and the unit normal N_k per sample
/// (row-major, u outer), and the domain's extents (b − a, d − c) that turn
/// ∂/∂u into ∂/∂ũ.
struct SampleAxes {
    us: Vec<f64>,
    vs: Vec<f64>,
    weighted: Vec<(f64, Vec3)>,
    extent: (f64, f64),
}

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
    /// The span's whole local Hessian ([`SpanGrid::local_on`] of every
    /// basis function).
    #[cfg(test)]
    pub fn local(&self) -> [Vec<f64>; 6] {
        let (pu, pv) = (self.bu[0][0].len(), self.bv[0][0].len());
        let (ius, ivs): (Vec<usize>, Vec<usize>) = ((0..pu).collect(), (0..pv).collect());
        self.local_on(&ius, &ivs)
    }

    /// The span's local Hessian Σ_nodes w (Y Yᵀ + Z Zᵀ), Y = ∂_u B ⊗ N,
    /// Z = ∂_v B ⊗ N, for the basis functions a = (`ius[i]`, `ivs[j]`) only
    /// (numbered i·|ivs| + j), as its six coordinate blocks:
    /// `blocks[pair(c, d)]` (c ≤ d) is the s × s matrix (s = |ius|·|ivs|,
    /// row-major) of the (c, d) entries — symmetric, and the (d, c) block
    /// is the same matrix. By sum factorization over the grid in two
    /// stages: per pair and term,
    /// T_s[j, j′] = Σ_t w_st n_c n_d N_j(v_t) N_j′(v_t) (N′ for the
    /// v-derivative term), then for all pairs at once
    /// H[(i, i′), (j, j′)] = Σ_s N′_i(u_s) N′_i′(u_s) T_s[j, j′] (N for the
    /// v-derivative term) with the two terms stacked along s. Each entry
    /// is the same sum whichever indices are asked (so the same bits). The
    /// assembly asks for the free points' rows and columns; the fixed
    /// points' columns enter the right-hand side through
    /// [`SpanGrid::apply`].
    pub fn local_on(&self, ius: &[usize], ivs: &[usize]) -> [Vec<f64>; 6] {
        // The same arithmetic either way (no fused products): AVX2 where
        // the machine has it, for the wider registers.
        crate::solve::compensated::with_fma(
            #[inline(always)]
            || self.local_with(ius, ivs),
            || self.local_with(ius, ivs),
        )
    }

    #[inline(always)]
    fn local_with(&self, ius: &[usize], ivs: &[usize]) -> [Vec<f64>; 6] {
        let (pu, pv) = (ius.len(), ivs.len());
        let (nu, nv) = (self.bu.len(), self.bv.len());
        let (uu, size) = (pu * pu, pu * pv);
        // The v factors are symmetric in (j, j′): only j ≤ j′ is formed,
        // packed row by row (`upper`), the same sums per entry as the full
        // square (so the same bits) for 0.56 of the products.
        let vv = pv * (pv + 1) / 2;
        let mut upper = vec![0usize; pv * pv];
        let mut next = 0;
        for j in 0..pv {
            for j2 in j..pv {
                upper[j * pv + j2] = next;
                upper[j2 * pv + j] = next;
                next += 1;
            }
        }
        // Per term (u-derivative: N′(u) N(v); v-derivative: N(u) N′(v)) its
        // u factor's products (rows term·nu + s of `um`) and the v sums of
        // every pair (row term·nu + s of `r`, columns pair·vv + (j ≤ j′)),
        // both row-major. (faer's product of a 5 × 25 by a 25 × 64 matrix
        // took 55 µs here; these loops are contiguous and small.)
        let terms = [(1, 0), (0, 1)];
        let mut um = vec![0.0f64; 2 * nu * uu];
        let mut r = vec![0.0f64; 2 * nu * 6 * vv];
        let mut vm = vec![0.0f64; nv * vv];
        let mut picked = vec![0.0f64; pu.max(pv)];
        for (term, &(ku, kv)) in terms.iter().enumerate() {
            for (s, b) in self.bu.iter().enumerate() {
                let row = &mut um[(term * nu + s) * uu..][..uu];
                outer(gathered(&b[ku], ius, &mut picked), row);
            }
            for (t, b) in self.bv.iter().enumerate() {
                outer_upper(gathered(&b[kv], ivs, &mut picked), &mut vm[t * vv..][..vv]);
            }
            for s in 0..nu {
                let row = &mut r[(term * nu + s) * 6 * vv..][..6 * vv];
                for (t, o) in vm.chunks_exact(vv).enumerate() {
                    let k = s * nv + t;
                    let (w, n) = (self.weight[k], self.n[k]);
                    if w == 0.0 {
                        continue;
                    }
                    for (pair, &(c, d)) in PAIRS.iter().enumerate() {
                        let f = w * n[c] * n[d];
                        for (x, &y) in row[pair * vv..][..vv].iter_mut().zip(o) {
                            *x += f * y;
                        }
                    }
                }
            }
        }
        // H[(i, i′), pair·vv + (j ≤ j′)] = Σ_rows um[row, (i, i′)] r[row, ·]
        // for i ≤ i′ (H is symmetric in the pair of u indices); by hand:
        // faer's product took 0.6 ms on its first call in a process.
        let width = 6 * vv;
        let h = sum_rows(&um, &r, pu, width);
        std::array::from_fn(|pair| {
            let mut block = vec![0.0f64; size * size];
            for i in 0..pu {
                for i2 in 0..pu {
                    let hrow = &h[(i.min(i2) * pu + i.max(i2)) * width + pair * vv..][..vv];
                    for j in 0..pv {
                        let out = &mut block[(i * pv + j) * size + i2 * pv..][..pv];
                        for (x, &u) in out.iter_mut().zip(&upper[j * pv..][..pv]) {
                            *x = hrow[u];
                        }
                    }
                }
            }
            block
        })
    }

    /// The span's term's gradient at the local net `net` ((p + 1)(q + 1)
    /// points, row-major as in [`SpanGrid::local_on`]): H·x, that is
    /// g_a = Σ_nodes w ((R_u·N) ∂_u B_a + (R_v·N) ∂_v B_a) N with R the
    /// net's surface. By sum factorization: the net's partial sums along
    /// v, the derivatives at the nodes, then back along v and u.
    pub fn apply(&self, net: &[Vec3]) -> Vec<Vec3> {
        let (pu, pv) = (self.bu[0][0].len(), self.bv[0][0].len());
        let nv = self.bv.len();
        // c[(r, i, t)] = Σ_j P_ij ∂ʳN_j(v_t), r = 0, 1.
        let mut c = vec![[0.0f64; 3]; 2 * pu * nv];
        for r in 0..2 {
            for i in 0..pu {
                let row = &net[i * pv..][..pv];
                for (t, b) in self.bv.iter().enumerate() {
                    let mut x = [0.0; 3];
                    for (p, &f) in row.iter().zip(&b[r]) {
                        for k in 0..3 {
                            x[k] += f * p[k];
                        }
                    }
                    c[(r * pu + i) * nv + t] = x;
                }
            }
        }
        let mut g = vec![[0.0f64; 3]; pu * pv];
        let mut e = vec![[0.0f64; 3]; 2 * pv];
        for (s, bu) in self.bu.iter().enumerate() {
            e.iter_mut().for_each(|x| *x = [0.0; 3]);
            for (t, bv) in self.bv.iter().enumerate() {
                let k = s * nv + t;
                let (w, n) = (self.weight[k], self.n[k]);
                if w == 0.0 {
                    continue;
                }
                // R_u = Σ_i ∂N_i(u_s) c[0, i, t], R_v = Σ_i N_i(u_s) c[1, i, t].
                let (mut ru, mut rv) = ([0.0; 3], [0.0; 3]);
                for i in 0..pu {
                    let (a, b) = (c[i * nv + t], c[(pu + i) * nv + t]);
                    for k in 0..3 {
                        ru[k] += bu[1][i] * a[k];
                        rv[k] += bu[0][i] * b[k];
                    }
                }
                let (y, z) = (w * dot(ru, n), w * dot(rv, n));
                for j in 0..pv {
                    let (fu, fv) = (y * bv[0][j], z * bv[1][j]);
                    for k in 0..3 {
                        e[j][k] += fu * n[k];
                        e[pv + j][k] += fv * n[k];
                    }
                }
            }
            for i in 0..pu {
                for j in 0..pv {
                    for k in 0..3 {
                        g[i * pv + j][k] += bu[1][i] * e[j][k] + bu[0][i] * e[pv + j][k];
                    }
                }
            }
        }
        g
    }
}

/// h[(i·pu + i′)·width + k] = Σ_rows um[row, (i, i′)] r[row, k] for i ≤ i′
/// (rows of `um` pu² long, of `r` width long; the rest 0).
#[inline(always)]
fn sum_rows(um: &[f64], r: &[f64], pu: usize, width: usize) -> Vec<f64> {
    let mut h = vec![0.0f64; pu * pu * width];
    for (u, rr) in um.chunks_exact(pu * pu).zip(r.chunks_exact(width)) {
        for i in 0..pu {
            for i2 in i..pu {
                let f = u[i * pu + i2];
                if f == 0.0 {
                    continue;
                }
                for (x, &y) in h[(i * pu + i2) * width..][..width].iter_mut().zip(rr) {
                    *x += f * y;
                }
            }
        }
    }
    h
}

/// b[idx[k]] for every k, in the front of `buf`.
#[inline(always)]
fn gathered<'a>(b: &[f64], idx: &[usize], buf: &'a mut [f64]) -> &'a [f64] {
    for (x, &i) in buf.iter_mut().zip(idx) {
        *x = b[i];
    }
    &buf[..idx.len()]
}

/// b_i b_i′ for i ≤ i′, row by row (i = 0: i′ = 0 … n − 1, then i = 1 …).
fn outer_upper(b: &[f64], out: &mut [f64]) {
    let mut k = 0;
    for (i, &x) in b.iter().enumerate() {
        for &y in &b[i..] {
            out[k] = x * y;
            k += 1;
        }
    }
}

/// `out[i·n + i′]` = b_i b_i′ (n = |b|).
fn outer(b: &[f64], out: &mut [f64]) {
    for (row, &x) in out.chunks_exact_mut(b.len()).zip(b) {
        for (o, &y) in row.iter_mut().zip(b) {
            *o = x * y;
        }
    }
}

/// The coordinate pairs (c, d), c ≤ d, of [`SpanGrid::local_on`]'s blocks.
pub(crate) const PAIRS: [(usize, usize); 6] = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];

/// The index in [`PAIRS`] of (c, d) or (d, c).
pub(crate) fn pair(c: usize, d: usize) -> usize {
    let (c, d) = (c.min(d), c.max(d));
    [[0, 1, 2], [1, 3, 4], [2, 4, 5]][c][d]
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
        let samples = self.sample_axes(surface).expect("a sampled guide").weighted;
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
                    .map(|k| samples[k])
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

    /// The sampled term on `surface`'s domain, unless the term is exact.
    fn sample_axes(&self, surface: &BSplineSurface) -> Option<SampleAxes> {
        let NormalGuide::Samples {
            grid,
            normals,
            weights,
        } = &self.guide
        else {
            return None;
        };
        let ((a, b), (c, d)) = (surface.knots().0.domain(), surface.knots().1.domain());
        Some(SampleAxes {
            us: grid.us().iter().map(|&x| a + (b - a) * x).collect(),
            vs: grid.vs().iter().map(|&y| c + (d - c) * y).collect(),
            weighted: (0..grid.len())
                .map(|k| {
                    (
                        self.weight * weights.as_ref().map_or(1.0, |w| w[k]),
                        normals[k],
                    )
                })
                .collect(),
            extent: (b - a, d - c),
        })
    }

    /// ½λ∫∫ (R_u·N)² + (R_v·N)², from de Boor derivatives at the nodes (or
    /// the sampled sum, the derivatives on the sample grid at once).
    pub(crate) fn value(&self, surface: &BSplineSurface) -> f64 {
        if let Some(axes) = self.sample_axes(surface) {
            let ((su, sv), wn) = (axes.extent, &axes.weighted);
            let d = surface.derivatives_on(&axes.us, &axes.vs);
            let total: f64 = d
                .iter()
                .zip(wn)
                .map(|(d, &(w, n))| {
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
        if let Some(axes) = self.sample_axes(surface) {
            let ((su, sv), wn, us, vs) = (axes.extent, &axes.weighted, &axes.us, &axes.vs);
            // Each sample in the piece whose rectangle holds it (the one
            // KnotVector::span names), by the piece's Bernstein derivatives
            // on the grid of its samples.
            let (ku, kv) = surface.knots();
            let (spans_u, spans_v) = (ku.spans(), kv.spans());
            let by_span = |k: &KnotVector, spans: &[(usize, f64, f64)], ts: &[f64]| {
                let mut at: Vec<Vec<usize>> = vec![Vec::new(); spans.len()];
                for (i, &t) in ts.iter().enumerate() {
                    let s = k.span(t);
                    at[spans.iter().position(|x| x.0 == s).expect("a span")].push(i);
                }
                at
            };
            let (iu, iv) = (by_span(ku, &spans_u, us), by_span(kv, &spans_v, vs));
            let mut total = 0.0;
            for (a, ia) in iu.iter().enumerate() {
                for (b, ib) in iv.iter().enumerate() {
                    if ia.is_empty() || ib.is_empty() {
                        continue;
                    }
                    let piece = &pieces[a * spans_v.len() + b];
                    let (hu, hv) = (piece.u.1 - piece.u.0, piece.v.1 - piece.v.0);
                    let xs: Vec<f64> = ia.iter().map(|&i| (us[i] - piece.u.0) / hu).collect();
                    let ys: Vec<f64> = ib.iter().map(|&j| (vs[j] - piece.v.0) / hv).collect();
                    let d = piece.patch.derivatives_on(&xs, &ys);
                    for (x, &i) in ia.iter().enumerate() {
                        for (y, &j) in ib.iter().enumerate() {
                            let g = &d[x * ib.len() + y];
                            let (w, n) = wn[i * vs.len() + j];
                            let (ru, rv) = (scale(g.du, su / hu), scale(g.dv, sv / hv));
                            total += w * (dot(ru, n).powi(2) + dot(rv, n).powi(2));
                        }
                    }
                }
            }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A made-up smooth number.
    fn f(k: usize, x: f64) -> f64 {
        ((k as f64 + 1.0) * 0.37 + x).sin()
    }

    /// A span grid of made-up numbers: degrees 3 and 2 (pu = 4, pv = 3
    /// basis functions), 5 × 7 nodes.
    fn uneven_grid() -> SpanGrid {
        let (pu, pv, nu, nv) = (4, 3, 5, 7);
        let basis = |n: usize, p: usize, o: f64| -> Vec<[Vec<f64>; 2]> {
            (0..n)
                .map(|s| [0, 1].map(|r| (0..p).map(|i| f(s * 11 + i * 3 + r, o)).collect()))
                .collect()
        };
        SpanGrid {
            span: (0, 0),
            bu: basis(nu, pu, 0.1),
            bv: basis(nv, pv, 0.7),
            weight: (0..nu * nv).map(|k| 1.0 + f(k, 0.3).abs()).collect(),
            n: (0..nu * nv)
                .map(|k| [f(k, 0.5), f(k, 1.5), f(k, 2.5)])
                .collect(),
        }
    }

    /// The blocks of some rows and columns are those entries of the whole
    /// blocks, bit for bit; `apply` is the whole blocks times the net.
    #[test]
    fn some_rows_of_the_blocks_and_their_product_with_a_net() {
        let grid = uneven_grid();
        let (pu, pv) = (4, 3);
        let (size, whole) = (pu * pv, grid.local());
        let (ius, ivs) = ([1, 3], [0, 2]);
        let some = grid.local_on(&ius, &ivs);
        for pair_index in 0..6 {
            for a in 0..4 {
                for b in 0..4 {
                    let at = |a: usize| ius[a / 2] * pv + ivs[a % 2];
                    assert_eq!(
                        some[pair_index][a * 4 + b].to_bits(),
                        whole[pair_index][at(a) * size + at(b)].to_bits()
                    );
                }
            }
        }
        let net: Vec<Vec3> = (0..size)
            .map(|a| [f(a, 4.0), f(a, 5.0), f(a, 6.0)])
            .collect();
        let got = grid.apply(&net);
        for a in 0..size {
            for c in 0..3 {
                let want: f64 = (0..size)
                    .flat_map(|b| (0..3).map(move |d| (b, d)))
                    .map(|(b, d)| whole[pair(c, d)][a * size + b] * net[b][d])
                    .sum();
                assert!(
                    (got[a][c] - want).abs() <= 1e-13 * (1.0 + want.abs()),
                    "({a}, {c}): {} vs {want}",
                    got[a][c]
                );
            }
        }
    }

    /// The blocks are the definition Σ_nodes w (Y Yᵀ + Z Zᵀ), Y = ∂_u B ⊗ N,
    /// Z = ∂_v B ⊗ N, summed node by node, on an uneven grid with
    /// different degrees and node counts each way.
    #[test]
    fn local_blocks_are_the_node_sum() {
        let (pu, pv, nu, nv) = (4, 3, 5, 7);
        let grid = uneven_grid();
        let blocks = grid.local();
        let size = pu * pv;
        for pair_index in 0..6 {
            let (c, d) = PAIRS[pair_index];
            assert_eq!(pair(c, d), pair_index);
            assert_eq!(pair(d, c), pair_index);
            for a in 0..size {
                for b in 0..size {
                    let (i, j, i2, j2) = (a / pv, a % pv, b / pv, b % pv);
                    let mut want = 0.0;
                    for s in 0..nu {
                        for t in 0..nv {
                            let k = s * nv + t;
                            let (bu, bv) = (&grid.bu[s], &grid.bv[t]);
                            let y = bu[1][i] * bv[0][j] * bu[1][i2] * bv[0][j2];
                            let z = bu[0][i] * bv[1][j] * bu[0][i2] * bv[1][j2];
                            want += grid.weight[k] * grid.n[k][c] * grid.n[k][d] * (y + z);
                        }
                    }
                    let got = blocks[pair_index][a * size + b];
                    assert!(
                        (got - want).abs() <= 1e-13 * (1.0 + want.abs()),
                        "pair {pair_index} ({a}, {b}): {got} vs {want}"
                    );
                }
            }
        }
    }
}
