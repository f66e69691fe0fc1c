//! The internal energy of a whole [`TriSurface`]: the sum of its patches'
//! energies (Veltkamp & Wesselink §6.1, E_stretch(S) = Σ_k E_stretch(S_k)),
//! assembled over the global control points by the patch → global map.
//!
//! ```text
//! E(S) = Σ_t E(T_t) = ½ Σ_c Pᵀ_c K P_c,   K = Σ_t Mₜᵀ K_patch Mₜ,
//! ```
//!
//! with Mₜ the 0/1 matrix picking patch t's points from the global ones.
//! Every patch has the same K_patch (each is parameterized over the same
//! equilateral triangle), so it is built once and scattered.

use super::energy::InternalEnergy;
use super::surface::TriSurface;
use crate::solve::columns::Columns;
use crate::Result;
use faer::sparse::SparseColMat;
use faer::Mat;

impl InternalEnergy {
    /// E(S) = Σ_t E(T_t) over the patches of the surface, each from its
    /// difference nets ([`InternalEnergy::value`]); or an error for a bad
    /// weight.
    ///
    /// ```
    /// use fairsurf::triangle::InternalEnergy;
    /// use fairsurf::TriSurface;
    /// let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    /// let mut s = TriSurface::new(&v, &[[0, 1, 2], [0, 2, 3]], 2);
    /// let e = InternalEnergy::new(0.0, 1.0);
    /// // Flat triangles have no bend; lifting a midpoint bends both patches.
    /// assert_eq!(e.surface_value(&s).unwrap(), 0.0);
    /// let diagonal = s.edge_points(1)[1]; // the middle of edge (0, 2)
    /// s.set_point(diagonal, [0.5, 0.5, 0.3]);
    /// assert!(e.surface_value(&s).unwrap() > 0.0);
    /// ```
    pub fn surface_value(&self, surface: &TriSurface) -> Result<f64> {
        self.validate()?;
        surface.patches().map(|p| self.value(&p)).sum()
    }

    /// The global per-coordinate matrix K (square, of the surface's point
    /// count), sparse, with E(S) = ½ Σ_c P_cᵀ K P_c; or an error for a bad
    /// weight.
    pub fn surface_matrix(&self, surface: &TriSurface) -> Result<SparseColMat<usize, f64>> {
        let k = self.matrix(surface.degree())?;
        let per = k.nrows();
        let size = surface.point_count();
        // The patches at each point (with the point's place in the patch).
        let mut start = vec![0usize; size + 1];
        for t in 0..surface.patch_count() {
            for &g in surface.patch_indices(t) {
                start[g + 1] += 1;
            }
        }
        for g in 0..size {
            start[g + 1] += start[g];
        }
        let mut at = start.clone();
        let mut incident = vec![(0usize, 0usize); start[size]];
        for t in 0..surface.patch_count() {
            for (local, &g) in surface.patch_indices(t).iter().enumerate() {
                incident[at[g]] = (t, local);
                at[g] += 1;
            }
        }
        // Column by column into a dense accumulator (Gustavson): each
        // patch's entries added in patch order, the rows sorted once per
        // column — no global sort of a million triplets.
        let mut out = Columns::new(size);
        for j in 0..size {
            for &(t, lj) in &incident[start[j]..start[j + 1]] {
                let g = surface.patch_indices(t);
                for (i, &r) in g.iter().enumerate().take(per) {
                    let v = k[(i, lj)];
                    if v != 0.0 {
                        out.add(r, v);
                    }
                }
            }
            out.next_column();
        }
        Ok(out.finish())
    }

    /// The same global matrix as [`InternalEnergy::surface_matrix`], dense
    /// (for small surfaces and tests).
    pub fn surface_matrix_dense(&self, surface: &TriSurface) -> Result<Mat<f64>> {
        let k = self.matrix(surface.degree())?;
        let size = surface.point_count();
        let mut out = Mat::<f64>::zeros(size, size);
        for t in 0..surface.patch_count() {
            let g = surface.patch_indices(t);
            for j in 0..k.ncols() {
                for i in 0..k.nrows() {
                    out[(g[i], g[j])] += k[(i, j)];
                }
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sparse_and_dense_agree() {
        let v = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.2],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.1],
        ];
        let s = TriSurface::new(&v, &[[0, 1, 2], [0, 2, 3]], 3);
        let e = InternalEnergy::new(1.0, 2.0);
        let sparse = e.surface_matrix(&s).unwrap().to_dense();
        let dense = e.surface_matrix_dense(&s).unwrap();
        assert_eq!(sparse.nrows(), s.point_count());
        for i in 0..dense.nrows() {
            for j in 0..dense.ncols() {
                assert!((sparse[(i, j)] - dense[(i, j)]).abs() < 1e-15);
            }
        }
    }
}
