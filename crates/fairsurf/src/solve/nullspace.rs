//! Null-space elimination of local constraint rows: the KKT system
//!
//! ```text
//! ⎡ H  Fᵀ ⎤ ⎡ x ⎤   ⎡ r₁ ⎤
//! ⎣ F  0  ⎦ ⎣ λ ⎦ = ⎣ r₂ ⎦
//! ```
//!
//! solved without factoring it, when the rows fall into small groups that
//! share no unknown (G1 at the vertices: each interior vertex's conditions
//! involve only its own ring of control points). In each group the rows
//! A x_V = r₂ pick as many basic unknowns B as they have rows (Gaussian
//! elimination with complete pivoting), so x_B = A_B⁻¹ (r₂ − A_N x_N); with
//! the free unknowns y (the non-basic ones of every group and every
//! unknown of no group), x = Z y + x₀(r₂), and
//!
//! ```text
//! Zᵀ H Z y = Zᵀ (r₁ − H x₀),        A_Bᵀ λ = (r₁ − H x)_B   per group,
//! ```
//!
//! where ZᵀHZ is symmetric positive definite whenever the problem has a
//! unique minimizer: one sparse Cholesky factorization, no saddle point, no
//! regularization. (The quasi-definite LDLᵀ of the same KKT matrix broke
//! down on G1 at the vertices of 1,000 and 10,000 cubic patches, and the LU
//! that took over needed 1.8 GB at 10,000.)

use super::columns::Columns;
use super::kkt::sparse_llt;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky};
use faer::sparse::SparseColMat;
use faer::{Conj, Mat, Par};
use std::sync::Arc;

/// Groups larger than this are not eliminated (the rows then go to the
/// KKT factorization): exact G1 across edges chains whole meshes together.
const MAX_GROUP_ROWS: usize = 64;

/// One group of rows and the unknowns they involve.
#[derive(Clone)]
struct Group {
    rows: Vec<usize>,
    /// The basic unknowns, one per row.
    basic: Vec<usize>,
    /// The group's other unknowns.
    non_basic: Vec<usize>,
    /// A_B⁻¹ (rows × rows, column-major).
    inv_b: Mat<f64>,
    /// −A_B⁻¹ A_N.
    t: Mat<f64>,
}

/// The elimination of a KKT system's rows, ready to solve for any right-hand
/// side.
pub(crate) struct NullSpace {
    n: usize,
    m: usize,
    groups: Vec<Group>,
    /// Z by rows: for every unknown, (free column, coefficient).
    z_rows: Vec<Vec<(usize, f64)>>,
    symbolic: Arc<SymbolicCholesky<usize>>,
    values: Vec<f64>,
    h: SparseColMat<usize, f64>,
}

impl NullSpace {
    /// The elimination, or `None` when a group is too large, the rows are
    /// rank-deficient within a group, or ZᵀHZ is not positive definite.
    pub(crate) fn new(h: &SparseColMat<usize, f64>, rows: &[&[(usize, f64)]]) -> Option<Self> {
        let n = h.nrows();
        let m = rows.len();
        let groups = group_rows(n, rows)?;
        let mut is_basic = vec![false; n];
        let mut built = Vec::with_capacity(groups.len());
        for (row_ids, vars) in groups {
            let g = eliminate(rows, row_ids, vars)?;
            for &v in &g.basic {
                is_basic[v] = true;
            }
            built.push(g);
        }
        let mut free_index = vec![None; n];
        let mut free = 0;
        for v in 0..n {
            if !is_basic[v] {
                free_index[v] = Some(free);
                free += 1;
            }
        }
        let mut z_rows: Vec<Vec<(usize, f64)>> = (0..n)
            .map(|v| free_index[v].map(|k| vec![(k, 1.0)]).unwrap_or_default())
            .collect();
        for g in &built {
            for (a, &v) in g.basic.iter().enumerate() {
                z_rows[v] = g
                    .non_basic
                    .iter()
                    .enumerate()
                    .filter(|&(b, _)| g.t[(a, b)] != 0.0)
                    .map(|(b, &w)| (free_index[w].expect("non-basic is free"), g.t[(a, b)]))
                    .collect();
            }
        }
        let reduced = reduced_hessian(h, &z_rows, free)?;
        let (symbolic, values) = sparse_llt(&reduced, None).ok()?;
        Some(Self {
            n,
            m,
            groups: built,
            z_rows,
            symbolic,
            values,
            h: h.clone(),
        })
    }

    /// The same elimination for another H of the same pattern: ZᵀHZ
    /// formed again and factored with this one's symbolic analysis.
    pub(crate) fn refactored(&self, h: &SparseColMat<usize, f64>) -> Option<Self> {
        let reduced = reduced_hessian(h, &self.z_rows, self.symbolic.nrows())?;
        let (symbolic, values) = sparse_llt(&reduced, Some(&self.symbolic)).ok()?;
        Some(Self {
            n: self.n,
            m: self.m,
            groups: self.groups.clone(),
            z_rows: self.z_rows.clone(),
            symbolic,
            values,
            h: h.clone(),
        })
    }

    /// Entries of the Cholesky factor of ZᵀHZ.
    pub(crate) fn factor_entries(&self) -> usize {
        self.symbolic.len_val()
    }

    /// [x; λ] = K⁻¹ [r₁; r₂] for the KKT matrix K.
    pub(crate) fn apply(&self, v: &[f64]) -> Vec<f64> {
        let (n, m) = (self.n, self.m);
        let (r1, r2) = v.split_at(n);
        // x₀: the basic unknowns from r₂, the rest 0.
        let mut x0 = vec![0.0; n];
        for g in &self.groups {
            for (a, &xb) in g.basic.iter().enumerate() {
                x0[xb] = g
                    .rows
                    .iter()
                    .enumerate()
                    .map(|(k, &r)| g.inv_b[(a, k)] * r2[r])
                    .sum();
            }
        }
        // Zᵀ (r₁ − H x₀)
        let q = residual(&self.h, r1, &x0);
        let free = self.symbolic.nrows();
        let mut y = Mat::<f64>::zeros(free, 1);
        for (i, zr) in self.z_rows.iter().enumerate() {
            for &(k, z) in zr {
                y[(k, 0)] += z * q[i];
            }
        }
        let par = Par::Seq;
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(1, par));
        LltRef::new(self.symbolic.as_ref(), &self.values).solve_in_place_with_conj(
            Conj::No,
            y.as_mut(),
            par,
            MemStack::new(&mut mem),
        );
        let mut out = vec![0.0; n + m];
        for (i, zr) in self.z_rows.iter().enumerate() {
            out[i] = x0[i] + zr.iter().map(|&(k, z)| z * y[(k, 0)]).sum::<f64>();
        }
        // λ per group: A_Bᵀ λ = (r₁ − H x)_B.
        let q = residual(&self.h, r1, &out[..n]);
        for g in &self.groups {
            for (k, &r) in g.rows.iter().enumerate() {
                out[n + r] = g
                    .basic
                    .iter()
                    .enumerate()
                    .map(|(a, &xb)| g.inv_b[(a, k)] * q[xb])
                    .sum();
            }
        }
        out
    }
}

/// r − H x.
fn residual(h: &SparseColMat<usize, f64>, r: &[f64], x: &[f64]) -> Vec<f64> {
    let mut q = r.to_vec();
    for (j, &xj) in x.iter().enumerate() {
        if xj != 0.0 {
            for (i, v) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
                q[i] -= v * xj;
            }
        }
    }
    q
}

/// The rows in groups that share no unknown (union-find over unknowns):
/// each group's rows and unknowns. `None` when a group has more than
/// [`MAX_GROUP_ROWS`] rows.
fn group_rows(n: usize, rows: &[&[(usize, f64)]]) -> Option<Vec<(Vec<usize>, Vec<usize>)>> {
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    for row in rows {
        let &(first, _) = row.first()?;
        for &(i, _) in &row[1..] {
            let (a, b) = (find(&mut parent, first), find(&mut parent, i));
            parent[a] = b;
        }
    }
    let mut by_root: std::collections::HashMap<usize, (Vec<usize>, Vec<usize>)> =
        std::collections::HashMap::new();
    for (r, row) in rows.iter().enumerate() {
        let root = find(&mut parent, row[0].0);
        let entry = by_root.entry(root).or_default();
        entry.0.push(r);
        for &(i, _) in row.iter() {
            entry.1.push(i);
        }
    }
    let mut groups: Vec<(Vec<usize>, Vec<usize>)> = by_root.into_values().collect();
    for g in &mut groups {
        if g.0.len() > MAX_GROUP_ROWS {
            return None;
        }
        g.1.sort_unstable();
        g.1.dedup();
    }
    groups.sort_unstable_by_key(|g| g.0[0]);
    Some(groups)
}

/// A⁻¹ by Gauss–Jordan elimination with partial pivoting (A small and
/// square); `None` when a pivot vanishes or the result is not finite.
fn inverse(mut a: Mat<f64>) -> Option<Mat<f64>> {
    let r = a.nrows();
    let mut inv = Mat::<f64>::identity(r, r);
    for k in 0..r {
        let p = (k..r).max_by(|&i, &j| a[(i, k)].abs().total_cmp(&a[(j, k)].abs()))?;
        if a[(p, k)] == 0.0 {
            return None;
        }
        for j in 0..r {
            let (x, y) = (a[(k, j)], a[(p, j)]);
            (a[(k, j)], a[(p, j)]) = (y, x);
            let (x, y) = (inv[(k, j)], inv[(p, j)]);
            (inv[(k, j)], inv[(p, j)]) = (y, x);
        }
        let d = a[(k, k)];
        for j in 0..r {
            a[(k, j)] /= d;
            inv[(k, j)] /= d;
        }
        for i in (0..r).filter(|&i| i != k) {
            let f = a[(i, k)];
            if f != 0.0 {
                for j in 0..r {
                    a[(i, j)] -= f * a[(k, j)];
                    inv[(i, j)] -= f * inv[(k, j)];
                }
            }
        }
    }
    (0..r)
        .all(|i| (0..r).all(|j| inv[(i, j)].is_finite()))
        .then_some(inv)
}

/// Basic unknowns of a group by Gaussian elimination with complete
/// pivoting, and A_B⁻¹, −A_B⁻¹A_N. `None` when the rows are
/// rank-deficient (a pivot below 1e-10 of the largest entry).
fn eliminate(rows: &[&[(usize, f64)]], row_ids: Vec<usize>, vars: Vec<usize>) -> Option<Group> {
    let (r, c) = (row_ids.len(), vars.len());
    let col_of = |v: usize| vars.binary_search(&v).expect("the group's unknown");
    let mut a = Mat::<f64>::zeros(r, c);
    for (k, &row) in row_ids.iter().enumerate() {
        for &(v, x) in rows[row] {
            a[(k, col_of(v))] += x;
        }
    }
    let original = a.clone();
    let scale = (0..r)
        .flat_map(|i| (0..c).map(move |j| (i, j)))
        .fold(0.0f64, |s, (i, j)| s.max(a[(i, j)].abs()));
    let mut row_left: Vec<usize> = (0..r).collect();
    let mut col_left: Vec<usize> = (0..c).collect();
    let mut basic_cols = Vec::with_capacity(r);
    for _ in 0..r {
        let (mut bi, mut bj, mut best) = (0, 0, -1.0);
        for (ii, &i) in row_left.iter().enumerate() {
            for (jj, &j) in col_left.iter().enumerate() {
                if a[(i, j)].abs() > best {
                    (bi, bj, best) = (ii, jj, a[(i, j)].abs());
                }
            }
        }
        if best <= 1e-10 * scale {
            return None;
        }
        let (pi, pj) = (row_left.swap_remove(bi), col_left.swap_remove(bj));
        basic_cols.push(pj);
        for &i in &row_left {
            let f = a[(i, pj)] / a[(pi, pj)];
            if f != 0.0 {
                for j in 0..c {
                    a[(i, j)] -= f * a[(pi, j)];
                }
            }
        }
    }
    col_left.sort_unstable();
    let a_b = Mat::from_fn(r, r, |i, k| original[(i, basic_cols[k])]);
    let a_n = Mat::from_fn(r, col_left.len(), |i, k| original[(i, col_left[k])]);
    let inv_b = inverse(a_b)?;
    let t = -(&inv_b * &a_n);
    Some(Group {
        rows: row_ids,
        basic: basic_cols.iter().map(|&k| vars[k]).collect(),
        non_basic: col_left.iter().map(|&k| vars[k]).collect(),
        inv_b,
        t,
    })
}

/// ZᵀHZ (lower triangle) for Z given by its rows: unknown v = Σ z · free.
/// Column by column into a dense accumulator (Gustavson): column b sums
/// z_a H_ij z_b over the unknowns j that free coordinate b enters, every
/// entry in the order of H's columns — no global sort of the products.
fn reduced_hessian(
    h: &SparseColMat<usize, f64>,
    z_rows: &[Vec<(usize, f64)>],
    free: usize,
) -> Option<SparseColMat<usize, f64>> {
    let mut z_cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); free];
    for (j, row) in z_rows.iter().enumerate() {
        for &(b, zb) in row {
            z_cols.get_mut(b)?.push((j, zb));
        }
    }
    let mut out = Columns::new(free);
    for (b, col) in z_cols.iter().enumerate() {
        for &(j, zb) in col {
            for (i, &hij) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
                for &(a, za) in &z_rows[i] {
                    if a >= b {
                        out.add(a, za * hij * zb);
                    }
                }
            }
        }
        out.next_column();
    }
    Some(out.finish())
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::Triplet;

    /// A tridiagonal SPD H of 12 unknowns and two groups of rows (rows 0–1
    /// over unknowns 0–3, row 2 over 7–9): K⁻¹ by the elimination equals
    /// the dense LU solve of the whole KKT matrix.
    #[test]
    fn elimination_equals_the_dense_kkt_solve() {
        let n = 12;
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, 4.0 + i as f64 * 0.1));
            if i + 1 < n {
                t.push(Triplet::new(i, i + 1, -1.0));
                t.push(Triplet::new(i + 1, i, -1.0));
            }
        }
        let h = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
        let rows: Vec<Vec<(usize, f64)>> = vec![
            vec![(0, 1.0), (1, -2.0), (3, 0.5)],
            vec![(1, 1.0), (2, 1.0)],
            vec![(7, 0.3), (8, 1.0), (9, -1.0)],
        ];
        let refs: Vec<&[(usize, f64)]> = rows.iter().map(Vec::as_slice).collect();
        let ns = NullSpace::new(&h, &refs).unwrap();
        assert_eq!(ns.groups.len(), 2);
        let size = n + rows.len();
        let mut k = Mat::<f64>::zeros(size, size);
        for j in 0..n {
            for (i, v) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
                k[(i, j)] = *v;
            }
        }
        for (r, row) in rows.iter().enumerate() {
            for &(i, a) in row {
                k[(n + r, i)] = a;
                k[(i, n + r)] = a;
            }
        }
        let v: Vec<f64> = (0..size).map(|i| (i as f64 * 0.7).sin()).collect();
        let got = ns.apply(&v);
        let rhs = Mat::from_fn(size, 1, |i, _| v[i]);
        let want = faer::linalg::solvers::Solve::solve(&k.partial_piv_lu(), &rhs);
        for i in 0..size {
            assert!(
                (got[i] - want[(i, 0)]).abs() < 1e-12,
                "{i}: {} vs {}",
                got[i],
                want[(i, 0)]
            );
        }
        // Rank-deficient groups are refused.
        let dup = [refs[0], refs[0]];
        assert!(NullSpace::new(&h, &dup).is_none());
    }

    /// ZᵀHZ column by column is the dense product's lower triangle, every
    /// entry stored once, rows sorted.
    #[test]
    fn reduced_hessian_is_the_product() {
        let n = 9;
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, 3.0 + i as f64));
            for j in [i + 1, i + 3] {
                if j < n {
                    let v = -0.5 / (1.0 + (i + j) as f64);
                    t.push(Triplet::new(i, j, v));
                    t.push(Triplet::new(j, i, v));
                }
            }
        }
        let h = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
        // Five free coordinates: unknowns 0–4 themselves, 5–8 combinations.
        let free = 5;
        let z_rows: Vec<Vec<(usize, f64)>> = (0..n)
            .map(|v| {
                if v < free {
                    vec![(v, 1.0)]
                } else {
                    vec![(v - free, 0.5), ((v - free + 2) % free, -1.25)]
                }
            })
            .collect();
        let z = Mat::from_fn(n, free, |v, k| {
            z_rows[v]
                .iter()
                .filter(|e| e.0 == k)
                .map(|e| e.1)
                .sum::<f64>()
        });
        let dense_h = Mat::from_fn(n, n, |i, j| {
            h.row_idx_of_col(j)
                .zip(h.val_of_col(j))
                .filter(|(r, _)| *r == i)
                .map(|(_, v)| *v)
                .sum::<f64>()
        });
        let want = z.transpose() * &dense_h * &z;
        let got = reduced_hessian(&h, &z_rows, free).unwrap();
        for b in 0..free {
            let rows: Vec<usize> = got.row_idx_of_col(b).collect();
            assert!(rows.windows(2).all(|w| w[0] < w[1]), "{rows:?}");
            assert!(rows.iter().all(|&a| a >= b));
            for a in b..free {
                let v = got
                    .row_idx_of_col(b)
                    .zip(got.val_of_col(b))
                    .find(|(r, _)| *r == a)
                    .map_or(0.0, |(_, v)| *v);
                assert!(
                    (v - want[(a, b)]).abs() < 1e-14,
                    "({a}, {b}): {v} vs {}",
                    want[(a, b)]
                );
            }
        }
    }
}
