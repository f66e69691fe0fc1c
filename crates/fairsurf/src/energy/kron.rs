//! The one assembly primitive behind every energy term.
//!
//! Each term of Wu & Yang's functionals (eq. 1, 2 and their sampled form
//! eq. 5) is, per pair of coordinates, a bilinear form
//!
//! ```text
//! Q[(i,j),(k,l)] = ∫∫ ω(u,v) · ∂ᵘ^{r}∂ᵛ^{s} B_ij(u,v) · ∂ᵘ^{r}∂ᵛ^{s} B_kl(u,v)  dμ(u) dμ(v)
//! ```
//!
//! with `B_ij = B_i^n(u) B_j^m(v)` and a weight ω that is either a tensor
//! Bernstein polynomial `Σ W_αβ B_α^{w}(u) B_β^{w'}(v)` under the Lebesgue
//! measure (continuous functionals), or a table `W_αβ` of per-sample weights
//! under the counting measure of a sample grid (eq. 5). Either way
//!
//! ```text
//! Q = Σ_{α,β} W_αβ · M^u_α ⊗ M^v_β
//! ```
//!
//! where `M^u_α[i][k]` is the 1D integral (or sample) of the two u-factors with
//! the α-th weight basis function. Summing over α first (sum factorization)
//! makes the cost |α|·|β|·n² + |β|·n²m² instead of |α|·|β|·n²m².

use super::{Basis1d, Space};
use crate::basis::{
    bernstein_derivatives, derivative_matrix, triple_product_integrals, GaussLegendre,
};
use crate::solve::dense::dot;
use faer::Mat;
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::Arc;

/// How one parameter direction is integrated.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Axis {
    /// ∫₀¹ … dt against the Bernstein weight basis of this degree
    /// (degree 0: the constant weight 1).
    Bernstein(usize),
    /// Σ over these sample parameters, one weight basis function per sample.
    Samples(Vec<f64>),
}

/// The 1D matrices `M_α[i][k]` for derivative order r in a 1D basis:
/// Bernstein of degree n, exact: `∫ dʳB_i^n · B_α^w · dʳB_k^n dt = (Dᵣᵀ T_α Dᵣ)[i][k]`
/// with `T_α = ∫ B^{n−r} B_α^w B^{n−r}`; sampled: `dʳφ_i(t_α) · dʳφ_k(t_α)`;
/// the solver's Jacobi basis against a Bernstein weight: Gauss–Legendre with
/// enough nodes to be exact for the degree 2(n−r) + w of the integrand.
///
/// Against a Bernstein weight the matrices depend only on the basis (its
/// degree, or a Jacobi block's degree and range), r and the weight's
/// degree: they are kept per thread (a solve builds the same ones for its
/// Hessian, its report's energies and its check).
pub(crate) fn axis_matrices(basis: &Basis1d, r: usize, axis: &Axis) -> Arc<Vec<Mat<f64>>> {
    /// (Jacobi?, n, a, b, r, w) → the matrices; cleared when it grows past
    /// `LIMIT` keys (a server meeting many degrees).
    type Cache = HashMap<(bool, usize, usize, usize, usize, usize), Arc<Vec<Mat<f64>>>>;
    const LIMIT: usize = 512;
    thread_local! {
        static CACHE: RefCell<Cache> = RefCell::new(HashMap::new());
    }
    let key = match (basis, axis) {
        (Basis1d::Bernstein(n), Axis::Bernstein(w)) => Some((false, *n, 0, 0, r, *w)),
        (Basis1d::Jacobi(j), Axis::Bernstein(w)) => Some((true, j.n, j.a, j.b, r, *w)),
        (_, Axis::Samples(_)) => None,
    };
    let Some(key) = key else {
        return Arc::new(axis_matrices_uncached(basis, r, axis));
    };
    if let Some(hit) = CACHE.with(|c| c.borrow().get(&key).cloned()) {
        return hit;
    }
    let m = Arc::new(axis_matrices_uncached(basis, r, axis));
    CACHE.with(|c| {
        let mut c = c.borrow_mut();
        if c.len() >= LIMIT {
            c.clear();
        }
        c.insert(key, m.clone());
    });
    m
}

fn axis_matrices_uncached(basis: &Basis1d, r: usize, axis: &Axis) -> Vec<Mat<f64>> {
    let k = basis.len();
    match (basis, axis) {
        (Basis1d::Bernstein(n), Axis::Bernstein(w)) => {
            let n = *n;
            if r > n {
                return vec![Mat::zeros(n + 1, n + 1); w + 1];
            }
            let d = derivative_matrix(n, r);
            triple_product_integrals(n - r, *w, n - r)
                .iter()
                .map(|t| d.transpose() * t * &d)
                .collect()
        }
        (Basis1d::Jacobi(j), Axis::Bernstein(w)) => {
            // M_α = Φᵀ diag(g ∘ B_α) Φ with Φ[a][p] = φ_p(t_a).
            let gl = GaussLegendre::new(j.n + w / 2 + 2);
            let phis: Vec<Vec<f64>> = gl.nodes.iter().map(|&t| basis.eval(t, r)).collect();
            let phi = Mat::from_fn(phis.len(), k, |a, p| phis[a][p]);
            let weights: Vec<Vec<f64>> = gl
                .nodes
                .iter()
                .map(|&t| bernstein_derivatives(*w, t, 0).swap_remove(0))
                .collect();
            (0..=*w)
                .map(|alpha| {
                    let scaled = Mat::from_fn(phis.len(), k, |a, p| {
                        gl.weights[a] * weights[a][alpha] * phis[a][p]
                    });
                    phi.transpose() * scaled
                })
                .collect()
        }
        (_, Axis::Samples(ts)) => ts
            .iter()
            .map(|&t| {
                let phi = basis.eval(t, r);
                Mat::from_fn(k, k, |i, q| phi[i] * phi[q])
            })
            .collect(),
    }
}

/// A coefficient and the 1D matrices M^u_α, M^v_β of one pattern.
pub(crate) type KronTerm = (f64, Arc<Vec<Mat<f64>>>, Arc<Vec<Mat<f64>>>);

/// `Σ_terms c · Σ_{α,β} W[α][β] · mu[α] ⊗ mv[β]` for terms (c, mu, mv),
/// ordered like the control points: row index `i·(m+1) + j` with i the
/// u-index. Every M^v_β is symmetric (a Gram matrix of one basis against
/// itself), so the inner loop runs along its rows; the result is symmetric
/// and only its lower half (row (i, j) ≥ column (k, l)) is summed, then
/// mirrored.
pub(crate) fn weighted_kron(w: &Mat<f64>, terms: &[KronTerm]) -> Mat<f64> {
    let Some((_, mu0, mv0)) = terms.first() else {
        return Mat::zeros(0, 0);
    };
    let (nu, nv) = (mu0[0].nrows(), mv0[0].nrows());
    let size = nu * nv;
    let mut out = Mat::<f64>::zeros(size, size);
    let mut t = vec![0.0; nu * nu];
    for (c, mu, mv) in terms {
        debug_assert_eq!((w.nrows(), w.ncols()), (mu.len(), mv.len()));
        // Flatten the small matrices once: tiny faer operations cost more in
        // overhead than in arithmetic here.
        let mu_flat = flatten(mu);
        let mv_flat = flatten(mv);
        for beta in 0..mv.len() {
            // T_β = c Σ_α W[α][β] M^u_α (row-major)
            if !sum_factor(w, beta, &mu_flat, nu, &mut t) {
                continue;
            }
            t.iter_mut().for_each(|x| *x *= c);
            let mvb = &mv_flat[beta * nv * nv..(beta + 1) * nv * nv];
            for k in 0..nu {
                for l in 0..nv {
                    let col = out.col_as_slice_mut(k * nv + l);
                    let row = &mvb[l * nv..(l + 1) * nv];
                    for i in k..nu {
                        let tik = t[i * nu + k];
                        if tik == 0.0 {
                            continue;
                        }
                        let from = if i == k { l } else { 0 };
                        let dst = &mut col[i * nv + from..(i + 1) * nv];
                        for (x, &m) in dst.iter_mut().zip(&row[from..]) {
                            *x += tik * m;
                        }
                    }
                }
            }
        }
    }
    for j in 0..size {
        for i in 0..j {
            out[(i, j)] = out[(j, i)];
        }
    }
    out
}

/// Matrices, each flattened row-major, one after the other.
fn flatten(ms: &[Mat<f64>]) -> Vec<f64> {
    ms.iter()
        .flat_map(|m| {
            let (r, c) = (m.nrows(), m.ncols());
            (0..r * c).map(move |e| m[(e / c, e % c)])
        })
        .collect()
}

/// `out ← Σ_α W[α][β] M_α` over flattened k×k matrices; false (and `out`
/// zero) when column β of W is all zero.
fn sum_factor(w: &Mat<f64>, beta: usize, flat: &[f64], k: usize, out: &mut [f64]) -> bool {
    out.iter_mut().for_each(|x| *x = 0.0);
    let mut any = false;
    for alpha in 0..w.nrows() {
        let c = w[(alpha, beta)];
        if c != 0.0 {
            any = true;
            for (x, &m) in out
                .iter_mut()
                .zip(&flat[alpha * k * k..(alpha + 1) * k * k])
            {
                *x += c * m;
            }
        }
    }
    any
}

/// Derivative patterns `∂ᵘ^{ru} ∂ᵛ^{rv}` of a degree (n, m) patch, each with
/// a coefficient, integrated with weights `w` along the given axes: Σ c·Q
/// with Q the matrix of the module docs, summed in one pass.
pub(crate) fn form(
    space: &Space,
    patterns: &[((usize, usize), f64)],
    axes: (&Axis, &Axis),
    w: &Mat<f64>,
) -> Mat<f64> {
    if patterns.is_empty() {
        return Mat::zeros(space.len(), space.len());
    }
    weighted_kron(w, &kron_terms(space, patterns, axes))
}

/// Each pattern's coefficient and 1-D matrices ([`KronTerm`]).
fn kron_terms(
    space: &Space,
    patterns: &[((usize, usize), f64)],
    (axis_u, axis_v): (&Axis, &Axis),
) -> Vec<KronTerm> {
    patterns
        .iter()
        .map(|&((ru, rv), c)| {
            (
                c,
                axis_matrices(&space.u, ru, axis_u),
                axis_matrices(&space.v, rv, axis_v),
            )
        })
        .collect()
}

/// The six coordinate pairs (a, b) with a ≤ b, in the order of the
/// coupled forms' weight tables: (0,0), (0,1), (0,2), (1,1), (1,2), (2,2).
pub(crate) fn pairs() -> impl Iterator<Item = (usize, usize)> {
    (0..3).flat_map(|a| (a..3).map(move |b| (a, b)))
}

/// The coupled 3N×3N form (point-major: row 3p + a) of derivative patterns
/// weighted by the six coordinate pairs' tables `ws` ((0,0), (0,1), (0,2),
/// (1,1), (1,2), (2,2)): block (a, b) is the pair's [`form`], and block
/// (b, a) the same matrix.
///
/// With κ running over the patterns' weight basis functions β, Q[(i,j),(k,l)]
/// = Σ_κ T_κ[i][k] M^v_κ[j][l] (T_κ = c Σ_α W[α][β] M^u_α) is one matrix
/// product per pair, C = B Aᵀ with B[(l,j), κ] = M^v_κ[l][j] and A[(i,k), κ] =
/// T_κ[i][k]; C's columns are then copied into the system's interleaved
/// layout, every entry written once. A cancelled solve stops between pairs.
pub(crate) fn coupled_form(
    space: &Space,
    patterns: &[((usize, usize), f64)],
    axes: (&Axis, &Axis),
    ws: &[Mat<f64>],
) -> crate::Result<Mat<f64>> {
    let np = space.len();
    let mut h = Mat::<f64>::zeros(3 * np, 3 * np);
    let terms = kron_terms(space, patterns, axes);
    let Some((_, mu0, mv0)) = terms.first() else {
        return Ok(h);
    };
    let (nu, nv) = (mu0[0].nrows(), mv0[0].nrows());
    let kappa: Vec<(usize, usize)> = (terms.iter().enumerate())
        .flat_map(|(t, (_, _, mv))| (0..mv.len()).map(move |beta| (t, beta)))
        .collect();
    let b = Mat::from_fn(nv * nv, kappa.len(), |r, k| {
        let (t, beta) = kappa[k];
        terms[t].2[beta][(r / nv, r % nv)]
    });
    let mu_flat: Vec<Vec<f64>> = terms.iter().map(|(_, mu, _)| flatten(mu)).collect();
    let mut a = Mat::<f64>::zeros(nu * nu, kappa.len());
    let mut c = Mat::<f64>::zeros(nv * nv, nu * nu);
    let mut t = vec![0.0; nu * nu];
    for ((x, y), w) in pairs().zip(ws) {
        crate::budget::checkpoint()?;
        for (k, &(ti, beta)) in kappa.iter().enumerate() {
            sum_factor(w, beta, &mu_flat[ti], nu, &mut t);
            let coef = terms[ti].0;
            for (dst, &v) in a.col_as_slice_mut(k).iter_mut().zip(&t) {
                *dst = coef * v;
            }
        }
        product_bat(&mut c, &b, &a);
        copy_pair(&mut h, &c, (nu, nv), (x, y));
    }
    Ok(h)
}

/// C ← B Aᵀ (B has nv² rows, A nu² rows). faer's product costs ~0.1 ms more
/// than these loops for a degree-5 patch (its set-up); past 144 points
/// (nu·nv) it is the faster.
fn product_bat(c: &mut Mat<f64>, b: &Mat<f64>, a: &Mat<f64>) {
    if b.nrows() * a.nrows() > 144 * 144 {
        faer::linalg::matmul::matmul(
            c.as_mut(),
            faer::Accum::Replace,
            b.as_ref(),
            a.transpose(),
            1.0,
            faer::Par::Seq,
        );
        return;
    }
    for col in 0..a.nrows() {
        let dst = c.col_as_slice_mut(col);
        dst.fill(0.0);
        for k in 0..a.ncols() {
            let x = a[(col, k)];
            if x != 0.0 {
                for (d, &v) in dst.iter_mut().zip(b.col_as_slice(k)) {
                    *d += x * v;
                }
            }
        }
    }
}

/// Pair (x, y)'s Q, held as C[(l,j),(i,k)] = Q[(i,j),(k,l)], into blocks
/// (x, y) and (y, x) of the interleaved system: h[(3p + x, 3q + y)] = Q[p, q].
fn copy_pair(h: &mut Mat<f64>, c: &Mat<f64>, (nu, nv): (usize, usize), (x, y): (usize, usize)) {
    let orientations: &[(usize, usize)] = if x == y { &[(x, y)] } else { &[(x, y), (y, x)] };
    for k in 0..nu {
        for l in 0..nv {
            for &(row, col) in orientations {
                let dst = h.col_as_slice_mut(3 * (k * nv + l) + col);
                for i in 0..nu {
                    let src = &c.col_as_slice(i * nu + k)[l * nv..(l + 1) * nv];
                    let rows = dst[3 * i * nv..3 * (i + 1) * nv].chunks_exact_mut(3);
                    for (d, &v) in rows.zip(src) {
                        d[row] = v;
                    }
                }
            }
        }
    }
}

/// The r-th u- and s-th v-derivative control net of one coordinate:
/// `D_r · P_c · D_sᵀ`, an (n−r+1)×(m−s+1) matrix (a zero 1×… when r > n).
pub(crate) fn derivative_net(
    points: &[crate::Vec3],
    (n, m): (usize, usize),
    (r, s): (usize, usize),
    c: usize,
) -> Mat<f64> {
    let p = Mat::from_fn(n + 1, m + 1, |i, j| points[i * (m + 1) + j][c]);
    derivative_matrix(n, r) * p * derivative_matrix(m, s).transpose()
}

/// `Σ_αβ W_αβ ⟨A, T^u_α B T^v_β⟩` for derivative nets A, B of the pattern
/// (r, s): the value of the pattern's bilinear form evaluated from the
/// derivative nets against the lower-degree Bernstein products, whose
/// entries are all ≥ 0. Folding the differences into the matrix instead
/// (Dᵀ T D) cancels catastrophically at high degree (≈1e-8 relative error at
/// degree 24, measured); this form keeps energies accurate.
pub(crate) fn pattern_value(
    degree: (usize, usize),
    pattern: (usize, usize),
    axes: (&Axis, &Axis),
    w: &Mat<f64>,
    a: &Mat<f64>,
    b: &Mat<f64>,
) -> f64 {
    PatternForm::new(degree, pattern, axes).value(w, a, b)
}

/// The product tables T^u_α, T^v_β of [`pattern_value`] for one pattern and
/// pair of axes, built once for several weight tables and nets.
pub(crate) struct PatternForm {
    /// (n − r + 1, m − s + 1); `None` when the pattern vanishes (r > n or s > m).
    size: Option<(usize, usize)>,
    tu_flat: Vec<f64>,
    tv: Arc<Vec<Mat<f64>>>,
}

impl PatternForm {
    pub(crate) fn new(
        (n, m): (usize, usize),
        (r, s): (usize, usize),
        (axis_u, axis_v): (&Axis, &Axis),
    ) -> Self {
        if r > n || s > m {
            return Self {
                size: None,
                tu_flat: Vec::new(),
                tv: Arc::new(Vec::new()),
            };
        }
        let tu = axis_matrices(&Basis1d::Bernstein(n - r), 0, axis_u);
        let tv = axis_matrices(&Basis1d::Bernstein(m - s), 0, axis_v);
        Self {
            size: Some((n - r + 1, m - s + 1)),
            tu_flat: flatten(&tu),
            tv,
        }
    }

    /// [`PatternForm::value`] for every pair (a, b), a ≤ b, of three nets
    /// (`ws[k]` the weights of the k-th pair, in the order (0,0), (0,1),
    /// (0,2), (1,1), (1,2), (2,2)): ⟨A, T^u_α B T^v_β⟩ = ⟨T^u_α A, B T^v_β⟩
    /// (T^u_α symmetric), so the products T^u_α A_a and B_b T^v_β are made
    /// once per net instead of once per pair, and each pair's value is
    /// Σ_αβ W_αβ times inner products of them.
    pub(crate) fn pair_values(&self, ws: &[Mat<f64>], nets: [&Mat<f64>; 3]) -> [f64; 6] {
        let Some((ku, kv)) = self.size else {
            return [0.0; 6];
        };
        let (wu, wv) = (ws[0].nrows(), ws[0].ncols());
        // d[a][α] = T^u_α A_a, c[b][β] = B_b T^v_β: ku × kv, row-major.
        let product = |x: &[f64], y: &[f64], inner: usize| {
            let mut out = vec![0.0; ku * kv];
            for (i, row) in out.chunks_exact_mut(kv).enumerate() {
                for (l, &xil) in x[i * inner..][..inner].iter().enumerate() {
                    for (o, &y) in row.iter_mut().zip(&y[l * kv..][..kv]) {
                        *o += xil * y;
                    }
                }
            }
            out
        };
        let nets = nets.map(|m| flatten(std::slice::from_ref(m)));
        let tv = flatten(&self.tv);
        let d: Vec<Vec<Vec<f64>>> = nets
            .iter()
            .map(|a| {
                (0..wu)
                    .map(|alpha| product(&self.tu_flat[alpha * ku * ku..][..ku * ku], a, ku))
                    .collect()
            })
            .collect();
        let c: Vec<Vec<Vec<f64>>> = nets
            .iter()
            .map(|b| {
                tv.chunks_exact(kv * kv)
                    .map(|t| product(b, t, kv))
                    .collect()
            })
            .collect();
        let mut values = [0.0; 6];
        for ((value, (a, b)), w) in values.iter_mut().zip(pairs()).zip(ws) {
            for alpha in 0..wu {
                for beta in 0..wv {
                    let x = w[(alpha, beta)];
                    if x != 0.0 {
                        *value += x * dot(&d[a][alpha], &c[b][beta]);
                    }
                }
            }
        }
        values
    }

    /// `Σ_αβ W_αβ ⟨A, T^u_α B T^v_β⟩`.
    pub(crate) fn value(&self, w: &Mat<f64>, a: &Mat<f64>, b: &Mat<f64>) -> f64 {
        let Some((ku, kv)) = self.size else {
            return 0.0;
        };
        let mut total = 0.0;
        let mut u = vec![0.0; ku * ku];
        for (beta, tvb) in self.tv.iter().enumerate() {
            // U_β = Σ_α W_αβ T^u_α (sum factorization), then ⟨A, U_β B T^v_β⟩.
            if !sum_factor(w, beta, &self.tu_flat, ku, &mut u) {
                continue;
            }
            let um = Mat::from_fn(ku, ku, |i, j| u[i * ku + j]);
            let t = um * (b * tvb);
            for j in 0..kv {
                for i in 0..ku {
                    total += a[(i, j)] * t[(i, j)];
                }
            }
        }
        total
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::{bernstein_derivatives, GaussLegendre};

    /// Every pair's value from the shared products is the pair's own
    /// [`PatternForm::value`] (to rounding), for both patterns of a normal
    /// field and weights with zero entries.
    #[test]
    fn pair_values_are_the_values() {
        let (n, m, wu, wv) = (6, 5, 4, 6);
        let net = |c: usize, (r, s): (usize, usize)| {
            Mat::from_fn(n - r + 1, m - s + 1, |i, j| {
                ((3 * i + 5 * j + 7 * c) % 11) as f64 - 4.5 + 0.1 * (i * j) as f64
            })
        };
        for pattern in [(1, 0), (0, 1)] {
            let nets = [net(0, pattern), net(1, pattern), net(2, pattern)];
            let ws: Vec<Mat<f64>> = (0..6)
                .map(|k| {
                    Mat::from_fn(wu + 1, wv + 1, |a, b| {
                        if (a + b + k) % 5 == 0 {
                            0.0
                        } else {
                            0.2 + (a * (k + 1)) as f64 - 0.3 * b as f64
                        }
                    })
                })
                .collect();
            let pf = PatternForm::new(
                (n, m),
                pattern,
                (&Axis::Bernstein(wu), &Axis::Bernstein(wv)),
            );
            let got = pf.pair_values(&ws, [&nets[0], &nets[1], &nets[2]]);
            let mut size = 0.0;
            for (k, (a, b)) in pairs().enumerate() {
                let want = pf.value(&ws[k], &nets[a], &nets[b]);
                size += want.abs();
                assert!(
                    (got[k] - want).abs() <= 1e-13 * want.abs().max(1.0),
                    "{pattern:?} ({a}, {b}): {} vs {want}",
                    got[k]
                );
            }
            assert!(size > 1.0, "the values are not all zero: {size}");
        }
    }

    /// The coupled form's block (a, b) and block (b, a) are the pair's own
    /// [`form`] (its lower half summed then mirrored: another road), entry
    /// by entry, in the Bernstein space, a Jacobi block and on sample axes,
    /// with weight columns that vanish, by both roads to the product.
    #[test]
    fn coupled_form_blocks_are_the_pair_forms() {
        let (n, m) = (6, 5);
        let spaces = [
            (
                Space::bernstein((n, m)),
                (Axis::Bernstein(4), Axis::Bernstein(6)),
            ),
            (
                Space::jacobi((n, m), (1, 1), (2, 1)),
                (Axis::Bernstein(3), Axis::Bernstein(2)),
            ),
            (
                Space::bernstein((n, m)),
                (
                    Axis::Samples(vec![0.0, 0.3, 0.8]),
                    Axis::Samples(vec![0.1, 0.5, 0.9, 1.0]),
                ),
            ),
            // Past 144 points the product is faer's.
            (
                Space::bernstein((12, 13)),
                (Axis::Bernstein(2), Axis::Bernstein(4)),
            ),
        ];
        for (space, (au, av)) in &spaces {
            let (ku, kv) = (axis_len(au), axis_len(av));
            let ws: Vec<Mat<f64>> = (0..6)
                .map(|k| {
                    Mat::from_fn(ku, kv, |a, b| {
                        if b == 1 || (a + b + k) % 5 == 0 {
                            0.0
                        } else {
                            0.2 + (a * (k + 1)) as f64 - 0.3 * b as f64
                        }
                    })
                })
                .collect();
            let patterns = [((1, 0), 1.0), ((0, 1), 0.5)];
            let h = coupled_form(space, &patterns, (au, av), &ws).unwrap();
            let np = space.len();
            assert_eq!((h.nrows(), h.ncols()), (3 * np, 3 * np));
            for ((a, b), w) in pairs().zip(&ws) {
                let q = form(space, &patterns, (au, av), w);
                let size = (0..np).map(|p| q[(p, p)].abs()).fold(0.0, f64::max);
                assert!(size > 0.1, "({a}, {b}) is not all zero");
                for p in 0..np {
                    for r in 0..np {
                        for (x, y) in [(a, b), (b, a)] {
                            let got = h[(3 * p + x, 3 * r + y)];
                            assert!(
                                (got - q[(p, r)]).abs() <= 1e-13 * size,
                                "({x}, {y}) at ({p}, {r}): {got} vs {}",
                                q[(p, r)]
                            );
                        }
                    }
                }
            }
        }
    }

    fn axis_len(axis: &Axis) -> usize {
        match axis {
            Axis::Bernstein(w) => w + 1,
            Axis::Samples(ts) => ts.len(),
        }
    }

    /// The Kronecker assembly of a Bernstein-weighted form equals direct
    /// tensor Gauss quadrature of the same integrand, entry by entry.
    #[test]
    fn weighted_form_equals_tensor_quadrature() {
        let (n, m, wu, wv) = (3, 2, 2, 3);
        let w = Mat::from_fn(wu + 1, wv + 1, |a, b| 0.3 + a as f64 - 0.7 * b as f64);
        let q = form(
            &Space::bernstein((n, m)),
            &[((1, 2), 1.0)],
            (&Axis::Bernstein(wu), &Axis::Bernstein(wv)),
            &w,
        );
        let gl = GaussLegendre::new(12);
        for p in 0..(n + 1) * (m + 1) {
            for s in 0..(n + 1) * (m + 1) {
                let (i, j, k, l) = (p / (m + 1), p % (m + 1), s / (m + 1), s % (m + 1));
                let mut acc = 0.0;
                for (&u, &a) in gl.nodes.iter().zip(&gl.weights) {
                    for (&v, &b) in gl.nodes.iter().zip(&gl.weights) {
                        let du = bernstein_derivatives(n, u, 1);
                        let dv = bernstein_derivatives(m, v, 2);
                        let bu = bernstein_derivatives(wu, u, 0);
                        let bv = bernstein_derivatives(wv, v, 0);
                        let mut omega = 0.0;
                        for x in 0..=wu {
                            for y in 0..=wv {
                                omega += w[(x, y)] * bu[0][x] * bv[0][y];
                            }
                        }
                        acc += a * b * omega * du[1][i] * dv[2][j] * du[1][k] * dv[2][l];
                    }
                }
                assert!((acc - q[(p, s)]).abs() < 1e-12, "entry ({p},{s})");
            }
        }
    }
}
