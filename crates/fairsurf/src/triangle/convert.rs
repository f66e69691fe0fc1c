//! A triangular patch as a tensor-product patch with one collapsed side,
//! and a triangle mesh of a whole triangular surface.
//!
//! With u = s, v = (1 − s)t, w = (1 − s)(1 − t) over the unit square,
//!
//! ```text
//! B^n_ijk(u, v, w) = B^n_i(s) · B^{n−i}_j(t),
//! ```
//!
//! so T(s, t) = Σ_i Σ_j P_{i,j,n−i−j} B^n_i(s) B^{n−i}_j(t); raising each
//! B^{n−i}_j(t) to degree n (Farin, eq. 6.7) gives the degree n × n tensor
//! patch exactly. Its side s = 1 collapses to the corner P_n00; the
//! Jacobian of (s, t) ↦ (u, v) is 1 − s > 0, so normals keep their
//! direction. CAD exports and the renderer take tensor patches, so this is
//! how triangular surfaces reach them.

use super::patch::TriPatch;
use super::surface::TriSurface;
use crate::analysis::{curvature_from, Curvature};
use crate::basis::binomial;
use crate::mesh::TriMesh;
use crate::vec3::{add, scale};
use crate::TensorPatch;

/// The tensor point (i, l) of [`TriPatch::to_tensor`] of degree n as
/// Σ_j c_j P_{i,j,n−i−j}: each (j, c_j). B^m_j (m = n − i) raised to
/// degree n contributes C(m, j) C(n−m, l−j) / C(n, l) to B^n_l.
pub(crate) fn tensor_weights(n: usize, i: usize, l: usize) -> impl Iterator<Item = (usize, f64)> {
    let m = n - i;
    let lo = l.saturating_sub(n - m);
    (lo..=l.min(m)).map(move |j| (j, binomial(m, j) * binomial(n - m, l - j) / binomial(n, l)))
}

impl TriPatch {
    /// The same surface as a degree n × n tensor-product patch over
    /// (s, t) ∈ [0, 1]², with (u, v, w) = (s, (1 − s)t, (1 − s)(1 − t)):
    /// exact, its side s = 1 collapsed to corner 0.
    ///
    /// ```
    /// use fairsurf::TriPatch;
    /// let t = TriPatch::from_fn(3, |i, j, k| [i as f64, j as f64, (i * j * k) as f64]);
    /// let q = t.to_tensor();
    /// let (s, r) = (0.3, 0.6);
    /// let (a, b) = (t.eval([s, (1.0 - s) * r, (1.0 - s) * (1.0 - r)]), q.eval(s, r));
    /// assert!((0..3).all(|c| (a[c] - b[c]).abs() < 1e-13));
    /// ```
    pub fn to_tensor(&self) -> TensorPatch {
        let n = self.degree();
        TensorPatch::from_fn(n, n, |i, l| {
            tensor_weights(n, i, l).fold([0.0; 3], |acc, (j, c)| {
                add(acc, scale(self.point(i, j, n - i - j), c))
            })
        })
    }

    /// A triangle mesh of the patch: sampled at the barycentric points
    /// (i, j, r−i−j)/r (r ≥ 1) and cut into r² triangles counter-clockwise
    /// in (u, v), with the exact unit normals and the curvature at every
    /// vertex (`None` where the patch is singular: there the normal is
    /// taken a little inside). `uvs` holds each vertex's (u, v).
    pub fn mesh_with_curvature(&self, r: usize) -> (TriMesh, Vec<Option<Curvature>>) {
        let r = r.max(1);
        let per = (r + 1) * (r + 2) / 2;
        let mut mesh = TriMesh {
            positions: Vec::with_capacity(per),
            normals: Vec::with_capacity(per),
            uvs: Vec::with_capacity(per),
            triangles: Vec::with_capacity(r * r),
        };
        let mut curvature = Vec::with_capacity(per);
        // Local index of (i, j): rows of constant j.
        let local = |i: usize, j: usize| (j * (2 * r + 3 - j) / 2 + i) as u32;
        let centre = self.eval([1.0 / 3.0; 3]);
        for j in 0..=r {
            for i in 0..=r - j {
                let (u, v) = (i as f64 / r as f64, j as f64 / r as f64);
                let b = [u, v, (1.0 - u - v).max(0.0)];
                let d = self.derivatives(b);
                let normal = self.normal(b).or_else(|| {
                    let inner = [0.999 * b[0] + 0.001 / 3.0, 0.999 * b[1] + 0.001 / 3.0, 0.0];
                    self.normal([inner[0], inner[1], 1.0 - inner[0] - inner[1]])
                });
                mesh.positions.push(d.point);
                mesh.normals.push(normal.unwrap_or_else(|| {
                    crate::vec3::normalize(crate::vec3::sub(d.point, centre))
                        .unwrap_or([0.0, 0.0, 1.0])
                }));
                mesh.uvs.push([u, v]);
                curvature.push(curvature_from(&d));
            }
        }
        for j in 0..r {
            for i in 0..r - j {
                let (a, b, c) = (local(i, j), local(i + 1, j), local(i, j + 1));
                mesh.triangles.push([a, b, c]);
                if i + j + 1 < r {
                    mesh.triangles.push([b, local(i + 1, j + 1), c]);
                }
            }
        }
        (mesh, curvature)
    }
}

impl TriSurface {
    /// Every patch as a tensor patch ([`TriPatch::to_tensor`]).
    pub fn tensor_patches(&self) -> Vec<TensorPatch> {
        self.patches().map(|p| p.to_tensor()).collect()
    }

    /// A triangle mesh of the surface: every patch's
    /// [`TriPatch::mesh_with_curvature`], concatenated. The patches'
    /// vertices are not merged; `uvs` holds each vertex's (u, v) in its
    /// patch.
    pub fn mesh_with_curvature(&self, r: usize) -> (TriMesh, Vec<Option<Curvature>>) {
        let mut mesh = TriMesh {
            positions: vec![],
            normals: vec![],
            uvs: vec![],
            triangles: vec![],
        };
        let mut curvature = vec![];
        for patch in self.patches() {
            let (m, k) = patch.mesh_with_curvature(r);
            let base = mesh.positions.len() as u32;
            mesh.positions.extend(m.positions);
            mesh.normals.extend(m.normals);
            mesh.uvs.extend(m.uvs);
            mesh.triangles
                .extend(m.triangles.iter().map(|t| t.map(|i| i + base)));
            curvature.extend(k);
        }
        (mesh, curvature)
    }
}
