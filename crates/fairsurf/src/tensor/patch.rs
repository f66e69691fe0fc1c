//! Tensor-product Bézier patches
//! `R(u, v) = Σ_{i=0}^{n} Σ_{j=0}^{m} B_i^n(u) B_j^m(v) P_ij`, (u, v) ∈ [0, 1]².

use crate::basis::{bernstein_derivatives, bernstein_derivatives_into};
use crate::curve::{de_casteljau_split, elevate_points};
use crate::solve::compensated::with_fma;
use crate::vec3::{add, cross, dot, is_finite, norm, normalize, scale, Vec3};
use crate::{Error, Result};

/// A tensor-product Bézier patch of degree (n, m) with control points P_ij,
/// stored row-major: row i (0..=n) goes with u, column j (0..=m) with v,
/// `points[i·(m+1) + j] = P_ij`.
///
/// ```
/// use fairsurf::TensorPatch;
/// // The bilinear patch over the unit square.
/// let p = TensorPatch::from_fn(1, 1, |i, j| [i as f64, j as f64, 0.0]);
/// assert_eq!(p.eval(0.25, 0.5), [0.25, 0.5, 0.0]);
/// assert_eq!(p.normal(0.3, 0.3), Some([0.0, 0.0, 1.0]));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct TensorPatch {
    degree: (usize, usize),
    points: Vec<Vec3>,
}

/// Points per chunk of a row of [`TensorPatch::grid_rows`]: its rows are
/// padded to a multiple.
pub(crate) const GRID_LANES: usize = 8;

/// The k-th chunk of [`GRID_LANES`] points of a row's three coordinates.
#[inline(always)]
pub(crate) fn chunk3(r: &[Vec<f64>; 3], k: usize) -> [&[f64; GRID_LANES]; 3] {
    [chunk(&r[0], k), chunk(&r[1], k), chunk(&r[2], k)]
}

/// The k-th chunk of [`GRID_LANES`] values.
#[inline(always)]
pub(crate) fn chunk(x: &[f64], k: usize) -> &[f64; GRID_LANES] {
    x[k * GRID_LANES..]
        .first_chunk::<GRID_LANES>()
        .expect("rows are whole chunks")
}

/// What takes a grid's rows from [`TensorPatch::grid_rows`].
pub(crate) trait GridRows<const K: usize> {
    /// Row `a`: `rows[k][c][b]` is coordinate c of the k-th order at the
    /// row's b-th point, for b below the grid's row length rounded up to a
    /// multiple of [`GRID_LANES`] (the points past the row repeat its last
    /// one). Mark it `#[inline(always)]` to have it compiled for the vector
    /// width with the evaluation.
    fn row(&mut self, a: usize, rows: &[[Vec<f64>; 3]; K]);
}

/// Position and partial derivatives up to second order at one (u, v).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceDerivatives {
    /// R(u, v)
    pub point: Vec3,
    /// ∂R/∂u
    pub du: Vec3,
    /// ∂R/∂v
    pub dv: Vec3,
    /// ∂²R/∂u²
    pub duu: Vec3,
    /// ∂²R/∂u∂v
    pub duv: Vec3,
    /// ∂²R/∂v²
    pub dvv: Vec3,
}

impl SurfaceDerivatives {
    /// The unit normal R_u × R_v / |R_u × R_v|, or `None` where the patch is
    /// not regular.
    pub fn normal(&self) -> Option<Vec3> {
        normalize(cross(self.du, self.dv))
    }

    /// [`normal`](Self::normal), also `None` where R_u × R_v is below
    /// 1e-8 of |R_u|² + |R_v|²: at a side collapsed to a point (a sphere's
    /// pole, a fan's corner) one derivative is rounding noise and so is the
    /// direction of the cross product.
    pub fn regular_normal(&self) -> Option<Vec3> {
        regular_normal(self.du, self.dv)
    }
}

/// [`SurfaceDerivatives::regular_normal`] from the two first derivatives.
pub(crate) fn regular_normal(du: Vec3, dv: Vec3) -> Option<Vec3> {
    let n = cross(du, dv);
    let scale = dot(du, du) + dot(dv, dv);
    if norm(n) <= 1e-8 * scale {
        return None;
    }
    normalize(n)
}

impl crate::surface::ControlNet for TensorPatch {
    fn counts(&self) -> (usize, usize) {
        (self.degree.0 + 1, self.degree.1 + 1)
    }

    fn points(&self) -> &[Vec3] {
        &self.points
    }

    fn points_mut(&mut self) -> &mut [Vec3] {
        &mut self.points
    }
}

impl TensorPatch {
    /// A patch of degree (n, m) from its (n+1)(m+1) control points, row-major.
    ///
    /// # Panics
    /// If the count is wrong or a coordinate is not finite; see
    /// [`TensorPatch::try_new`].
    pub fn new(n: usize, m: usize, points: Vec<Vec3>) -> Self {
        Self::try_new(n, m, points).expect("TensorPatch::new")
    }

    /// A patch of degree (n, m), or an error naming the bad count or point.
    pub fn try_new(n: usize, m: usize, points: Vec<Vec3>) -> Result<Self> {
        let expected = (n + 1) * (m + 1);
        if points.len() != expected {
            return Err(Error::ControlPointCount {
                degree: (n, m),
                expected,
                got: points.len(),
            });
        }
        if let Some(k) = points.iter().position(|&p| !is_finite(p)) {
            return Err(Error::NotFinite {
                what: format!("control point ({}, {})", k / (m + 1), k % (m + 1)),
            });
        }
        Ok(Self {
            degree: (n, m),
            points,
        })
    }

    /// A patch whose control point P_ij is `f(i, j)`.
    ///
    /// # Panics
    /// If `f` returns a non-finite coordinate.
    pub fn from_fn(n: usize, m: usize, mut f: impl FnMut(usize, usize) -> Vec3) -> Self {
        let points = (0..=n)
            .flat_map(|i| (0..=m).map(move |j| (i, j)))
            .map(|(i, j)| f(i, j))
            .collect();
        Self::new(n, m, points)
    }

    /// (n, m).
    pub fn degree(&self) -> (usize, usize) {
        self.degree
    }

    /// Number of control points, (n+1)(m+1).
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Always false: a patch has at least one control point.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// All control points, row-major.
    pub fn points(&self) -> &[Vec3] {
        &self.points
    }

    /// Index of P_ij in [`TensorPatch::points`].
    pub fn index(&self, i: usize, j: usize) -> usize {
        i * (self.degree.1 + 1) + j
    }

    /// P_ij.
    pub fn point(&self, i: usize, j: usize) -> Vec3 {
        self.points[self.index(i, j)]
    }

    /// Replaces P_ij.
    ///
    /// # Panics
    /// If p is not finite or (i, j) is out of range.
    pub fn set_point(&mut self, i: usize, j: usize, p: Vec3) {
        assert!(is_finite(p), "control points must be finite");
        let k = self.index(i, j);
        self.points[k] = p;
    }

    /// R(u, v).
    pub fn eval(&self, u: f64, v: f64) -> Vec3 {
        self.combine(&self.basis(u, v, 0), 0, 0)
    }

    /// R and its partial derivatives to second order at (u, v).
    pub fn derivatives(&self, u: f64, v: f64) -> SurfaceDerivatives {
        let b = self.basis(u, v, 2);
        SurfaceDerivatives {
            point: self.combine(&b, 0, 0),
            du: self.combine(&b, 1, 0),
            dv: self.combine(&b, 0, 1),
            duu: self.combine(&b, 2, 0),
            duv: self.combine(&b, 1, 1),
            dvv: self.combine(&b, 0, 2),
        }
    }

    /// Derivatives at every (u, v) of a tensor grid, u-major:
    /// `out[a·vs.len() + b]` is at `(us[a], vs[b])`. Contracts the u-direction
    /// once per u-value, so each point costs O(m) rather than O(nm).
    pub fn derivatives_on(&self, us: &[f64], vs: &[f64]) -> Vec<SurfaceDerivatives> {
        /// The rows' points one after the other.
        struct Points<'a>(&'a mut Vec<SurfaceDerivatives>, usize);
        impl GridRows<6> for Points<'_> {
            #[inline(always)]
            fn row(&mut self, _: usize, rows: &[[Vec<f64>; 3]; 6]) {
                let nv = self.1;
                let [p, du, dv, duu, duv, dvv] = rows
                    .each_ref()
                    .map(|r| [&r[0][..nv], &r[1][..nv], &r[2][..nv]]);
                let at = |x: [&[f64]; 3], b: usize| [x[0][b], x[1][b], x[2][b]];
                self.0.extend((0..nv).map(|b| SurfaceDerivatives {
                    point: at(p, b),
                    du: at(du, b),
                    dv: at(dv, b),
                    duu: at(duu, b),
                    duv: at(duv, b),
                    dvv: at(dvv, b),
                }));
            }
        }
        const ORDERS: [(usize, usize); 6] = [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)];
        let mut out = Vec::with_capacity(us.len() * vs.len());
        self.grid_rows(us, vs, ORDERS, &mut Points(&mut out, vs.len()));
        out
    }

    /// (R_u, R_v) at every (u, v) of a tensor grid, u-major as
    /// [`TensorPatch::derivatives_on`], without the other derivatives, by
    /// the point-by-point loop: the tests' reference for the row-wise
    /// evaluation.
    #[cfg(test)]
    pub(crate) fn grid_tangents(&self, us: &[f64], vs: &[f64]) -> Vec<(Vec3, Vec3)> {
        let mut out = Vec::with_capacity(us.len() * vs.len());
        self.grid_partials(us, vs, [(1, 0), (0, 1)], |[du, dv]| out.push((du, dv)));
        out
    }

    /// ∂^(r+s)R/∂u^r∂v^s for each (r, s) of `orders` at every (u, v) of a
    /// tensor grid, u-major, handed to `emit`: q[r][j] = Σ_i dʳB_i^n(u) P_ij
    /// once per u, then Σ_j q[r][j] dˢB_j^m(v) per point — point by point,
    /// the tests' reference for [`TensorPatch::grid_rows`].
    #[cfg(test)]
    fn grid_partials<const K: usize>(
        &self,
        us: &[f64],
        vs: &[f64],
        orders: [(usize, usize); K],
        mut emit: impl FnMut([Vec3; K]),
    ) {
        let (n, m) = self.degree;
        let top = orders.iter().map(|&(r, s)| r.max(s)).max().unwrap_or(0);
        // Flat tables, one allocation each: bv[(k, s, j)] = dˢB_j^m(v_k),
        // bu[(r, i)] = dʳB_i^n(u), q[(r, j)] = Σ_i bu[(r, i)] P_ij.
        let (bn, bm) = ((top + 1) * (n + 1), (top + 1) * (m + 1));
        let mut bv = vec![0.0; vs.len() * bm];
        for (&v, row) in vs.iter().zip(bv.chunks_mut(bm)) {
            bernstein_derivatives_into(m, v, row);
        }
        let mut bu = vec![0.0; bn];
        let mut q = vec![[0.0; 3]; bm];
        for &u in us {
            self.contract_u(u, &mut bu, &mut q);
            for b in bv.chunks(bm) {
                let mut vals = [[0.0; 3]; K];
                for (val, &(r, s)) in vals.iter_mut().zip(&orders) {
                    let (qr, bs) = (&q[r * (m + 1)..], &b[s * (m + 1)..]);
                    for (p, &w) in qr[..=m].iter().zip(&bs[..=m]) {
                        val[0] += p[0] * w;
                        val[1] += p[1] * w;
                        val[2] += p[2] * w;
                    }
                }
                emit(vals);
            }
        }
    }

    /// q[(r, j)] = Σ_i dʳB_i^n(u) P_ij for r = 0 … (its length over m + 1) − 1,
    /// summed over i in order; `bu` holds the basis rows (as many as `q`).
    #[inline(always)]
    fn contract_u(&self, u: f64, bu: &mut [f64], q: &mut [Vec3]) {
        let (n, m) = self.degree;
        bernstein_derivatives_into(n, u, bu);
        for (r, qr) in q.chunks_exact_mut(m + 1).enumerate() {
            let w = &bu[r * (n + 1)..(r + 1) * (n + 1)];
            for (j, qj) in qr.iter_mut().enumerate() {
                *qj = (0..=n).fold([0.0; 3], |acc, i| {
                    add(acc, scale(self.points[i * (m + 1) + j], w[i]))
                });
            }
        }
    }

    /// ∂^(r+s)R/∂u^r∂v^s for each (r, s) of `orders` on a tensor grid, one
    /// row (one u) at a time, coordinates apart: `sink.row(a, rows)` with
    /// `rows[k][c][b]` the coordinate c of order k at (`us[a]`, `vs[b]`) (see
    /// [`GridRows`] for the padding) — the
    /// same sums in the same order as the point-by-point `grid_partials`, so the
    /// same bits, but the loop over a row's points is contiguous and
    /// vectorizes. Compiled for the CPU's vector width ([`with_fma`]), with
    /// the sink's `row` inlined into it.
    pub(crate) fn grid_rows<const K: usize>(
        &self,
        us: &[f64],
        vs: &[f64],
        orders: [(usize, usize); K],
        sink: &mut impl GridRows<K>,
    ) {
        let sink = std::cell::RefCell::new(sink);
        with_fma(
            #[inline(always)]
            || self.grid_rows_with(us, vs, orders, *sink.borrow_mut()),
            || self.grid_rows_with(us, vs, orders, *sink.borrow_mut()),
        )
    }

    #[inline(always)]
    fn grid_rows_with<const K: usize>(
        &self,
        us: &[f64],
        vs: &[f64],
        orders: [(usize, usize); K],
        sink: &mut impl GridRows<K>,
    ) {
        let (n, m) = self.degree;
        let Some(&last) = vs.last() else { return };
        // Rows padded to whole chunks of GRID_LANES points (the padding
        // repeats the last v).
        let np = vs.len().next_multiple_of(GRID_LANES);
        let top = orders.iter().map(|&(r, s)| r.max(s)).max().unwrap_or(0);
        // bv[(s·(m+1) + j)·np + b] = dˢB_j^m(v_b): per (s, j) a row over the
        // grid's v's.
        let (bn, bm) = ((top + 1) * (n + 1), (top + 1) * (m + 1));
        let mut bv = vec![0.0; bm * np];
        let mut one = vec![0.0; bm];
        for b in 0..np {
            bernstein_derivatives_into(m, vs.get(b).copied().unwrap_or(last), &mut one);
            for (sj, &w) in one.iter().enumerate() {
                bv[sj * np + b] = w;
            }
        }
        let mut bu = vec![0.0; bn];
        let mut q = vec![[0.0; 3]; bm];
        let mut rows: [[Vec<f64>; 3]; K] =
            std::array::from_fn(|_| std::array::from_fn(|_| vec![0.0; np]));
        for (a, &u) in us.iter().enumerate() {
            self.contract_u(u, &mut bu, &mut q);
            for (row, &(r, s)) in rows.iter_mut().zip(&orders) {
                let (qr, bs) = (
                    &q[r * (m + 1)..][..=m],
                    &bv[s * (m + 1) * np..][..(m + 1) * np],
                );
                for k in 0..np / GRID_LANES {
                    // The chunk's sums (three coordinates) stay in registers
                    // over j.
                    let mut acc = [[0.0; GRID_LANES]; 3];
                    for (j, p) in qr.iter().enumerate() {
                        let w: &[f64; GRID_LANES] = bs[j * np + k * GRID_LANES..][..GRID_LANES]
                            .try_into()
                            .expect("GRID_LANES long");
                        for (ac, &pc) in acc.iter_mut().zip(p) {
                            for (o, &wt) in ac.iter_mut().zip(w) {
                                *o += pc * wt;
                            }
                        }
                    }
                    for (out, ac) in row.iter_mut().zip(&acc) {
                        out[k * GRID_LANES..][..GRID_LANES].copy_from_slice(ac);
                    }
                }
            }
            sink.row(a, &rows);
        }
    }

    /// The unit normal R_u × R_v / |R_u × R_v| at (u, v), or `None` where the
    /// patch is not regular (e.g. a corner with collapsed edges).
    pub fn normal(&self, u: f64, v: f64) -> Option<Vec3> {
        self.derivatives(u, v).normal()
    }

    /// Splits at u = t into the patches over [0, t]×[0, 1] and [t, 1]×[0, 1].
    pub fn subdivide_u(&self, t: f64) -> (TensorPatch, TensorPatch) {
        let (n, m) = self.degree;
        let mut lo = self.clone();
        let mut hi = self.clone();
        for j in 0..=m {
            let column: Vec<Vec3> = (0..=n).map(|i| self.point(i, j)).collect();
            let (l, r) = de_casteljau_split(&column, t);
            for i in 0..=n {
                lo.points[i * (m + 1) + j] = l[i];
                hi.points[i * (m + 1) + j] = r[i];
            }
        }
        (lo, hi)
    }

    /// Splits at v = t into the patches over [0, 1]×[0, t] and [0, 1]×[t, 1].
    pub fn subdivide_v(&self, t: f64) -> (TensorPatch, TensorPatch) {
        let (a, b) = self.transposed().subdivide_u(t);
        (a.transposed(), b.transposed())
    }

    /// The same surface with parameters swapped: Q_ji = P_ij, degree (m, n).
    pub fn transposed(&self) -> TensorPatch {
        let (n, m) = self.degree;
        TensorPatch::from_fn(m, n, |j, i| self.point(i, j))
    }

    /// The same surface written with degree (n + ru, m + rv).
    pub fn elevate(&self, ru: usize, rv: usize) -> TensorPatch {
        let (n, m) = self.degree;
        // Elevate every column in u, then every row in v.
        let cols: Vec<Vec<Vec3>> = (0..=m)
            .map(|j| elevate_points(&(0..=n).map(|i| self.point(i, j)).collect::<Vec<_>>(), ru))
            .collect();
        let rows: Vec<Vec<Vec3>> = (0..=n + ru)
            .map(|i| elevate_points(&cols.iter().map(|c| c[i]).collect::<Vec<_>>(), rv))
            .collect();
        TensorPatch::new(n + ru, m + rv, rows.into_iter().flatten().collect())
    }

    /// A copy with each control point mapped by `f`.
    pub fn map(&self, f: impl FnMut(&Vec3) -> Vec3) -> TensorPatch {
        let (n, m) = self.degree;
        TensorPatch::new(n, m, self.points.iter().map(f).collect())
    }

    fn basis(&self, u: f64, v: f64, order: usize) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let (n, m) = self.degree;
        (
            bernstein_derivatives(n, u, order),
            bernstein_derivatives(m, v, order),
        )
    }

    fn combine(&self, (bu, bv): &(Vec<Vec<f64>>, Vec<Vec<f64>>), ru: usize, rv: usize) -> Vec3 {
        let m = self.degree.1;
        let mut acc = [0.0; 3];
        for (i, &wu) in bu[ru].iter().enumerate() {
            if wu == 0.0 {
                continue;
            }
            let mut row = [0.0; 3];
            for (j, &wv) in bv[rv].iter().enumerate() {
                row = add(row, scale(self.points[i * (m + 1) + j], wv));
            }
            acc = add(acc, scale(row, wu));
        }
        acc
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vec3::{norm, sub};

    fn wavy() -> TensorPatch {
        TensorPatch::from_fn(4, 3, |i, j| {
            let (x, y) = (i as f64 / 4.0, j as f64 / 3.0);
            [
                x + 0.1 * y,
                y - 0.05 * x * x,
                (3.0 * x).sin() * (2.0 * y).cos(),
            ]
        })
    }

    /// The rows, coordinates apart and padded, are bit for bit the
    /// per-point grid evaluation (`grid_partials`, a separate loop that
    /// sums point by point), within rounding of the pointwise
    /// [`TensorPatch::derivatives`] (another algorithm), and the padding
    /// repeats the row's last point.
    #[test]
    fn grid_rows_are_the_pointwise_derivatives() {
        struct Keep(Vec<[Vec<f64>; 3]>);
        impl GridRows<6> for Keep {
            fn row(&mut self, _: usize, rows: &[[Vec<f64>; 3]; 6]) {
                self.0.extend(rows.iter().cloned());
            }
        }
        let p = wavy();
        let (us, vs) = (
            [0.0, 0.3, 1.0],
            [0.1, 0.25, 0.5, 0.7, 0.75, 0.8, 0.9, 0.95, 1.0, 0.05],
        );
        let orders = [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)];
        let mut keep = Keep(Vec::new());
        p.grid_rows(&us, &vs, orders, &mut keep);
        let mut per_point = Vec::new();
        p.grid_partials(&us, &vs, orders, |d| per_point.push(d));
        assert_eq!(keep.0.len(), 6 * us.len());
        for (a, rows) in keep.0.chunks(6).enumerate() {
            for (o, row) in rows.iter().enumerate() {
                assert_eq!(row[0].len(), 16);
                for b in 0..16 {
                    let k = a * vs.len() + b.min(vs.len() - 1);
                    let got = [row[0][b], row[1][b], row[2][b]];
                    assert_eq!(got, per_point[k][o], "row {a}, order {o}");
                    let d = p.derivatives(us[a], vs[b.min(vs.len() - 1)]);
                    let want = [d.point, d.du, d.dv, d.duu, d.duv, d.dvv][o];
                    assert!(
                        norm(sub(got, want)) <= 1e-13 * (1.0 + norm(want)),
                        "{got:?} {want:?}"
                    );
                }
            }
        }
        // derivatives_on is the rows' points.
        let d = p.derivatives_on(&us, &vs);
        for (k, x) in d.iter().enumerate() {
            assert_eq!([x.point, x.du, x.dv, x.duu, x.duv, x.dvv], per_point[k]);
        }
    }

    #[test]
    fn corners_are_interpolated() {
        let p = wavy();
        assert_eq!(p.eval(0.0, 0.0), p.point(0, 0));
        assert!(norm(sub(p.eval(1.0, 1.0), p.point(4, 3))) < 1e-15);
        assert!(norm(sub(p.eval(1.0, 0.0), p.point(4, 0))) < 1e-15);
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let p = wavy();
        let h = 1e-5;
        for &(u, v) in &[(0.3, 0.6), (0.9, 0.1), (0.5, 0.5)] {
            let d = p.derivatives(u, v);
            let du = p.derivatives(u + h, v);
            let dm = p.derivatives(u - h, v);
            let vp = p.derivatives(u, v + h);
            let vm = p.derivatives(u, v - h);
            let fd = |a: Vec3, b: Vec3| scale(sub(a, b), 0.5 / h);
            assert!(norm(sub(fd(du.point, dm.point), d.du)) < 1e-8);
            assert!(norm(sub(fd(vp.point, vm.point), d.dv)) < 1e-8);
            assert!(norm(sub(fd(du.du, dm.du), d.duu)) < 1e-7);
            assert!(norm(sub(fd(vp.du, vm.du), d.duv)) < 1e-7);
            assert!(norm(sub(fd(du.dv, dm.dv), d.duv)) < 1e-7);
            assert!(norm(sub(fd(vp.dv, vm.dv), d.dvv)) < 1e-7);
        }
    }

    #[test]
    fn grid_derivatives_equal_pointwise_ones() {
        let p = wavy();
        let us = [0.0, 0.3, 1.0];
        let vs = [0.1, 0.55];
        let g = p.derivatives_on(&us, &vs);
        for (a, &u) in us.iter().enumerate() {
            for (b, &v) in vs.iter().enumerate() {
                let d = p.derivatives(u, v);
                let e = g[a * vs.len() + b];
                for (x, y) in [
                    (d.point, e.point),
                    (d.du, e.du),
                    (d.dv, e.dv),
                    (d.duu, e.duu),
                    (d.duv, e.duv),
                    (d.dvv, e.dvv),
                ] {
                    assert!(norm(sub(x, y)) < 1e-13);
                }
            }
        }
    }

    #[test]
    fn subdivision_reproduces_the_pieces() {
        let p = wavy();
        let (a, b) = p.subdivide_u(0.4);
        let (c, d) = p.subdivide_v(0.7);
        for &(s, t) in &[(0.0, 0.0), (0.3, 0.8), (1.0, 0.5)] {
            assert!(norm(sub(a.eval(s, t), p.eval(0.4 * s, t))) < 1e-14);
            assert!(norm(sub(b.eval(s, t), p.eval(0.4 + 0.6 * s, t))) < 1e-14);
            assert!(norm(sub(c.eval(s, t), p.eval(s, 0.7 * t))) < 1e-14);
            assert!(norm(sub(d.eval(s, t), p.eval(s, 0.7 + 0.3 * t))) < 1e-14);
        }
    }

    #[test]
    fn elevation_keeps_the_surface() {
        let p = wavy();
        let e = p.elevate(2, 3);
        assert_eq!(e.degree(), (6, 6));
        for &(s, t) in &[(0.1, 0.9), (0.5, 0.5), (0.77, 0.23)] {
            assert!(norm(sub(e.eval(s, t), p.eval(s, t))) < 1e-14);
        }
    }

    #[test]
    fn normal_of_a_plane_is_constant_and_degenerate_corner_is_none() {
        let plane = TensorPatch::from_fn(3, 2, |i, j| [i as f64, 2.0 * j as f64, 0.0]);
        assert_eq!(plane.normal(0.2, 0.9), Some([0.0, 0.0, 1.0]));
        // Collapse the edge v = 0 to one point: R_u = 0 there.
        let cone = TensorPatch::from_fn(2, 2, |i, j| {
            if j == 0 {
                [0.0; 3]
            } else {
                [i as f64, j as f64, 1.0]
            }
        });
        assert_eq!(cone.normal(0.5, 0.0), None);
    }

    #[test]
    fn wrong_count_and_nan_are_errors() {
        assert!(matches!(
            TensorPatch::try_new(2, 2, vec![[0.0; 3]; 8]),
            Err(Error::ControlPointCount {
                expected: 9,
                got: 8,
                ..
            })
        ));
        let mut pts = vec![[0.0; 3]; 4];
        pts[3][1] = f64::NAN;
        assert_eq!(
            TensorPatch::try_new(1, 1, pts),
            Err(Error::NotFinite {
                what: "control point (1, 1)".into()
            })
        );
    }
}
