//! Quadrature nodes and Bernstein values in double-double, and the one
//! tensor operation the check needs: a net of one coordinate evaluated on a
//! grid of parameters, and its adjoint.

use super::dd::Dd;
use crate::basis::GaussLegendre;
use crate::solve::compensated::{two_product_err, with_fma};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// Parameters of one direction with their weights.
#[derive(Clone, Debug)]
pub(crate) struct Nodes {
    pub t: Vec<Dd>,
    pub w: Vec<Dd>,
    /// Which rule: the key of the cached Bernstein tables.
    rule: Rule,
}

/// A rule of [`Nodes`]: Gauss–Legendre with q nodes or the grid k/n.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Rule {
    Gauss(usize),
    Grid(usize),
}

/// Gauss rules and their Bernstein tables already computed, shared by every
/// check of the process: polishing the nodes and filling the tables in
/// double-double cost as much as a degree-10 check's quadrature itself.
struct Cache {
    gauss: HashMap<usize, Nodes>,
    /// (rule, degree, transposed) → table.
    tables: HashMap<(Rule, usize, bool), Arc<Table>>,
}

fn cache() -> std::sync::MutexGuard<'static, Cache> {
    static CACHE: OnceLock<Mutex<Cache>> = OnceLock::new();
    CACHE
        .get_or_init(|| {
            Mutex::new(Cache {
                gauss: HashMap::new(),
                tables: HashMap::new(),
            })
        })
        .lock()
        .unwrap_or_else(|e| e.into_inner())
}

impl Nodes {
    /// The q-point Gauss–Legendre rule on [0, 1] in double-double: the
    /// double rule's nodes polished by two Newton steps on P_q (quadratic
    /// convergence from ~1e-16), weights 2/((1 − x²) P_q′(x)²) mapped to [0, 1].
    /// Exact for polynomials of degree ≤ 2q − 1.
    pub fn gauss(q: usize) -> Self {
        if let Some(n) = cache().gauss.get(&q) {
            return n.clone();
        }
        let n = Self::polished(q);
        cache().gauss.insert(q, n.clone());
        n
    }

    fn polished(q: usize) -> Self {
        let start = GaussLegendre::new(q.max(1));
        let one = Dd::new(1.0);
        let (mut t, mut w) = (Vec::with_capacity(q), Vec::with_capacity(q));
        for &t0 in &start.nodes {
            let mut x = Dd::new(2.0 * t0 - 1.0);
            for _ in 0..2 {
                let (p, d) = legendre(q, x);
                x -= p / d;
            }
            let (_, d) = legendre(q, x);
            let weight = Dd::new(2.0) / ((one - x * x) * d * d);
            t.push((x + 1.0) * 0.5);
            w.push(weight * 0.5);
        }
        Self {
            t,
            w,
            rule: Rule::Gauss(q),
        }
    }

    /// The samples k/n, k = 0…n, each of weight 1 (Wu & Yang eq. 5).
    pub fn grid(n: usize) -> Self {
        let t = (0..=n)
            .map(|k| Dd::new(k as f64) / Dd::new(n as f64))
            .collect();
        Self {
            t,
            w: vec![Dd::new(1.0); n + 1],
            rule: Rule::Grid(n),
        }
    }

    /// [`bernstein`] of degree k at these nodes (or its transpose), from
    /// the cache for Gauss rules (their sizes are bounded by the degrees).
    pub fn bernstein(&self, k: usize, transposed: bool) -> Arc<Table> {
        let key = (self.rule, k, transposed);
        if let Rule::Grid(_) = self.rule {
            // Sample grids come in many sizes (to 2000): not kept.
            let b = bernstein(k, &self.t);
            return Arc::new(if transposed { b.transpose() } else { b });
        }
        if let Some(t) = cache().tables.get(&key) {
            return t.clone();
        }
        let b = bernstein(k, &self.t);
        let t = Arc::new(if transposed { b.transpose() } else { b });
        cache().tables.insert(key, t.clone());
        t
    }
}

/// (P_q(x), P_q′(x)) by the three-term recurrence.
fn legendre(q: usize, x: Dd) -> (Dd, Dd) {
    let (mut p0, mut p1) = (Dd::new(1.0), x);
    if q == 0 {
        return (p0, Dd::new(0.0));
    }
    for k in 1..q {
        let kf = k as f64;
        let p2 = (x * p1 * (2.0 * kf + 1.0) - p0 * kf) / Dd::new(kf + 1.0);
        (p0, p1) = (p1, p2);
    }
    // P_q′ = q (x P_q − P_{q−1}) / (x² − 1)
    let d = (x * p1 - p0) * q as f64 / (x * x - Dd::new(1.0));
    (p1, d)
}

/// B_i^k(t_a) for every node a (rows) and i = 0…k (columns), by the
/// recurrence B_i^k = (1 − t) B_i^{k−1} + t B_{i−1}^{k−1}: sums of positive
/// terms, accurate to a few units of 1e-32 relative.
pub(crate) fn bernstein(k: usize, t: &[Dd]) -> Table {
    let mut v = Vec::with_capacity(t.len() * (k + 1));
    let mut row = vec![Dd::new(0.0); k + 1];
    for &ta in t {
        let s = Dd::new(1.0) - ta;
        row.iter_mut().for_each(|x| *x = Dd::new(0.0));
        row[0] = Dd::new(1.0);
        for d in 1..=k {
            for i in (0..=d).rev() {
                let left = if i < d { row[i] * s } else { Dd::new(0.0) };
                let right = if i > 0 { row[i - 1] * ta } else { Dd::new(0.0) };
                row[i] = left + right;
            }
        }
        v.extend_from_slice(&row);
    }
    Table {
        rows: t.len(),
        cols: k + 1,
        v,
    }
}

/// A dense row-major matrix of double-doubles: a net of one coordinate
/// (rows = u-index), values on a parameter grid, or a basis table.
#[derive(Clone, Debug)]
pub(crate) struct Table {
    pub rows: usize,
    pub cols: usize,
    pub v: Vec<Dd>,
}

impl Table {
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Self {
            rows,
            cols,
            v: vec![Dd::new(0.0); rows * cols],
        }
    }

    pub fn at(&self, i: usize, j: usize) -> Dd {
        self.v[i * self.cols + j]
    }

    /// A · B, each entry a compensated sum (Ogita, Rump & Oishi's Dot2
    /// over the high parts, with the cross terms of the low parts and every
    /// rounding error gathered in a second accumulator): as accurate as
    /// summing in double-double (the products of two low parts, ~ε² of each
    /// term, are left out), at a third of the cost, and the loop over a row
    /// of B vectorizes.
    pub fn mul(&self, b: &Table) -> Table {
        with_fma(
            #[inline(always)]
            || self.mul_with::<true>(b),
            || self.mul_with::<false>(b),
        )
    }

    #[inline(always)]
    fn mul_with<const FMA: bool>(&self, b: &Table) -> Table {
        debug_assert_eq!(self.cols, b.rows);
        let n = b.cols;
        let mut out = Table::zeros(self.rows, n);
        let (mut s, mut c) = (vec![0.0; n], vec![0.0; n]);
        for i in 0..self.rows {
            s.iter_mut().for_each(|x| *x = 0.0);
            c.iter_mut().for_each(|x| *x = 0.0);
            for k in 0..self.cols {
                let a = self.at(i, k);
                if a.hi == 0.0 {
                    continue;
                }
                add_products::<FMA>(&mut s, &mut c, a, &b.v[k * n..(k + 1) * n]);
            }
            for (o, (&sj, &cj)) in out.v[i * n..(i + 1) * n].iter_mut().zip(s.iter().zip(&c)) {
                *o = Dd::new(sj) + cj;
            }
        }
        out
    }

    /// Aᵀ.
    pub fn transpose(&self) -> Table {
        let mut out = Table::zeros(self.cols, self.rows);
        for i in 0..self.rows {
            for j in 0..self.cols {
                out.v[j * self.rows + i] = self.at(i, j);
            }
        }
        out
    }

    /// The r-th derivative net along the rows of a degree rows−1 Bézier net:
    /// r times k·(P_{i+1} − P_i). Zero rows when r exceeds the degree.
    pub fn diff_rows(&self, r: usize) -> Table {
        let mut t = self.clone();
        for _ in 0..r {
            if t.rows <= 1 {
                return Table::zeros(0, t.cols);
            }
            let k = (t.rows - 1) as f64;
            let mut d = Table::zeros(t.rows - 1, t.cols);
            for i in 0..d.rows {
                for j in 0..t.cols {
                    d.v[i * t.cols + j] = (t.at(i + 1, j) - t.at(i, j)) * k;
                }
            }
            t = d;
        }
        t
    }

    /// The adjoint of [`Table::diff_rows`] from a net of `rows` rows:
    /// r times (Dᵀy)_i = k(y_{i−1} − y_i), y outside 0…k−1 taken as 0.
    pub fn diff_rows_adjoint(&self, r: usize, rows: usize) -> Table {
        let mut t = self.clone();
        for step in (0..r).rev() {
            let out_rows = rows - step;
            let k = (out_rows - 1) as f64;
            let mut d = Table::zeros(out_rows, t.cols);
            for i in 0..out_rows {
                for j in 0..t.cols {
                    let prev = if i > 0 { t.at(i - 1, j) } else { Dd::new(0.0) };
                    let this = if i < t.rows { t.at(i, j) } else { Dd::new(0.0) };
                    d.v[i * t.cols + j] = (prev - this) * k;
                }
            }
            t = d;
        }
        t
    }
}

/// s_j + c_j += a · b_j for every j, compensated: the sum in s, each
/// product's and each addition's rounding error (and the low parts' cross
/// terms) gathered in c; `Dd::new(s_j) + c_j` is the double-double result.
/// Call with `FMA = true` only inside [`with_fma`]'s fast branch.
#[inline(always)]
pub(super) fn add_products<const FMA: bool>(s: &mut [f64], c: &mut [f64], a: Dd, b: &[Dd]) {
    for ((sj, cj), bj) in s.iter_mut().zip(c.iter_mut()).zip(b) {
        let p = a.hi * bj.hi;
        let ep = two_product_err::<FMA>(a.hi, bj.hi, p);
        let t = *sj + p;
        let z = t - *sj;
        let es = (*sj - (t - z)) + (p - z);
        *sj = t;
        *cj += ep + es + (a.hi * bj.lo + a.lo * bj.hi);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The double-double rule integrates t^k exactly to ~1e-30 for k ≤ 2q−1.
    #[test]
    fn gauss_rule_integrates_monomials_to_thirty_digits() {
        for q in [1, 2, 5, 17, 40] {
            let g = Nodes::gauss(q);
            for k in 0..2 * q {
                let mut s = Dd::new(0.0);
                for (t, w) in g.t.iter().zip(&g.w) {
                    let mut p = Dd::new(1.0);
                    for _ in 0..k {
                        p = p * *t;
                    }
                    s += *w * p;
                }
                let exact = Dd::new(1.0) / Dd::new((k + 1) as f64);
                assert!((s - exact).to_f64().abs() < 1e-29, "q {q} k {k}: {s:?}");
            }
        }
    }

    /// ⟨Dᵀy, x⟩ = ⟨y, Dx⟩ for the difference operators.
    #[test]
    fn products_are_as_accurate_as_double_double_sums() {
        // Entries whose products cancel: a 1e16-scale term, a small one, the
        // big term back, with low parts that matter.
        let mut r = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            r ^= r << 13;
            r ^= r >> 7;
            r ^= r << 17;
            (r >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let (m, k, n) = (5, 9, 7);
        let mk = |rows, cols, next: &mut dyn FnMut() -> f64| Table {
            rows,
            cols,
            v: (0..rows * cols)
                .map(|e| {
                    let big = if e % 3 == 0 { 1e16 } else { 1.0 };
                    Dd::new(big * next()) + next() * 1e-17
                })
                .collect(),
        };
        let a = mk(m, k, &mut next);
        let b = mk(k, n, &mut next);
        let fast = a.mul(&b);
        for i in 0..m {
            for j in 0..n {
                let (mut exact, mut size) = (Dd::new(0.0), 0.0);
                for q in 0..k {
                    let t = a.at(i, q) * b.at(q, j);
                    exact += t;
                    size += t.to_f64().abs();
                }
                let err = (fast.at(i, j) - exact).to_f64().abs();
                assert!(err <= 1e-30 * size, "({i}, {j}): {err:e} of {size:e}");
            }
        }
    }

    #[test]
    fn difference_adjoint_is_the_transpose() {
        let x = Table {
            rows: 6,
            cols: 2,
            v: (0..12).map(|k| Dd::new((k * k % 7) as f64 - 3.0)).collect(),
        };
        for r in 0..4 {
            let dx = x.diff_rows(r);
            let y = Table {
                rows: dx.rows,
                cols: 2,
                v: (0..dx.rows * 2)
                    .map(|k| Dd::new(k as f64 * 0.5 - 1.0))
                    .collect(),
            };
            let dty = y.diff_rows_adjoint(r, 6);
            let a: Dd = (0..12).fold(Dd::new(0.0), |s, k| s + dty.v[k] * x.v[k]);
            let b: Dd = (0..dx.v.len()).fold(Dd::new(0.0), |s, k| s + y.v[k] * dx.v[k]);
            assert_eq!((a - b).to_f64(), 0.0, "r {r}");
        }
    }
}
