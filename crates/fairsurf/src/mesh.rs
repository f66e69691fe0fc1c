//! Tessellation of a patch into a triangle mesh with exact normals.

use crate::analysis::Curvature;
use crate::surface::{ParamSurface, Sample};
use crate::vec3::{cross, normalize, sub, Vec3};

/// A triangle mesh: positions, unit normals and (u, v) per vertex,
/// counter-clockwise triangles (seen from the side the normals point to).
#[derive(Clone, Debug, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals.
    pub normals: Vec<Vec3>,
    /// Parameters (u, v) of each vertex.
    pub uvs: Vec<[f64; 2]>,
    /// Vertex indices, three per triangle.
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Samples the patch on a (ru+1)×(rv+1) uniform parameter grid (ru, rv ≥ 1)
    /// and splits each cell into two triangles. Normals are the patch's exact
    /// unit normals; where the patch is not regular (a collapsed edge) the
    /// normal is taken a tiny step inside the domain, and failing that from
    /// the adjacent mesh faces.
    pub fn from_patch(surface: &impl ParamSurface, ru: usize, rv: usize) -> Self {
        Self::with_curvature(surface, ru, rv).0
    }

    /// [`TriMesh::from_patch`] together with the curvature at every vertex
    /// (`None` where the surface is singular), from the same exact
    /// derivatives ([`ParamSurface::samples_on`]); `uvs` are the surface's
    /// own parameters (a B-spline's knot domain).
    pub fn with_curvature(
        surface: &impl ParamSurface,
        ru: usize,
        rv: usize,
    ) -> (Self, Vec<Option<Curvature>>) {
        let (us, vs) = surface.uniform_grid(ru, rv);
        let samples = surface.samples_on(&us, &vs);
        let curvature = samples.iter().map(|s| s.curvature).collect();
        let normal = |u, v| inside_normal(surface, u, v);
        (Self::from_grid(&us, &vs, &samples, normal), curvature)
    }

    /// The mesh of the samples over `us` × `vs` (row-major).
    /// `fallback(u, v)` gives the normal where the derivatives do not (a
    /// collapsed edge): a tiny step inside the domain.
    fn from_grid(
        us: &[f64],
        vs: &[f64],
        samples: &[Sample],
        fallback: impl Fn(f64, f64) -> Option<Vec3>,
    ) -> Self {
        let (ru, rv) = (us.len() - 1, vs.len() - 1);
        let mut positions = Vec::with_capacity(samples.len());
        let mut normals = Vec::with_capacity(samples.len());
        let mut uvs = Vec::with_capacity(samples.len());
        for (i, &u) in us.iter().enumerate() {
            for (j, &v) in vs.iter().enumerate() {
                let s = &samples[i * (rv + 1) + j];
                positions.push(s.point);
                uvs.push([u, v]);
                let n = s.normal.or_else(|| fallback(u, v));
                normals.push(n.unwrap_or([f64::NAN; 3]));
            }
        }
        let mut mesh = Self {
            positions,
            normals,
            uvs,
            triangles: Self::grid_triangles(ru + 1, rv + 1),
        };
        mesh.repair_normals();
        mesh
    }

    /// The triangles of a rows × cols grid of vertices (row-major, vertex
    /// i·cols + j at (u_i, v_j)), as [`TriMesh::from_patch`] meshes a
    /// surface: each cell split along its (i, j)–(i+1, j+1) diagonal,
    /// counter-clockwise about R_u × R_v.
    pub fn grid_triangles(rows: usize, cols: usize) -> Vec<[u32; 3]> {
        let idx = |i: usize, j: usize| (i * cols + j) as u32;
        let mut triangles = Vec::with_capacity(2 * rows.saturating_sub(1) * cols.saturating_sub(1));
        for i in 0..rows.saturating_sub(1) {
            for j in 0..cols.saturating_sub(1) {
                // R_u × R_v orientation: (i,j) → (i+1,j) → (i+1,j+1) is counter-clockwise.
                triangles.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
                triangles.push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
            }
        }
        triangles
    }

    /// Replaces missing (NaN) normals by the normalized sum of adjacent face
    /// normals, or +z when even that vanishes.
    fn repair_normals(&mut self) {
        if self.normals.iter().all(|n| !n[0].is_nan()) {
            return;
        }
        let mut acc = vec![[0.0; 3]; self.positions.len()];
        for t in &self.triangles {
            let [a, b, c] = t.map(|k| self.positions[k as usize]);
            let f = cross(sub(b, a), sub(c, a));
            for &k in t {
                acc[k as usize] = crate::vec3::add(acc[k as usize], f);
            }
        }
        for (n, a) in self.normals.iter_mut().zip(acc) {
            if n[0].is_nan() {
                *n = normalize(a).unwrap_or([0.0, 0.0, 1.0]);
            }
        }
    }
}

/// The unit normal a tiny step (1e-7 of the domain) inside the domain from
/// (u, v): where a collapsed edge leaves none at the edge itself.
fn inside_normal(surface: &impl ParamSurface, u: f64, v: f64) -> Option<Vec3> {
    let toward = |t: f64, (lo, hi): (f64, f64)| {
        let h = 1e-7 * (hi - lo);
        (t + if t < 0.5 * (lo + hi) { h } else { -h }).clamp(lo, hi)
    };
    let [du, dv] = surface.domain();
    surface.normal(toward(u, du), toward(v, dv))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TensorPatch;

    #[test]
    fn grid_counts_and_orientation() {
        let p = TensorPatch::from_fn(2, 2, |i, j| [i as f64, j as f64, 0.0]);
        let m = TriMesh::from_patch(&p, 4, 3);
        assert_eq!(m.positions.len(), 20);
        assert_eq!(m.triangles.len(), 24);
        for t in &m.triangles {
            let [a, b, c] = t.map(|k| m.positions[k as usize]);
            assert!(
                cross(sub(b, a), sub(c, a))[2] > 0.0,
                "counter-clockwise about +z"
            );
        }
    }

    #[test]
    fn collapsed_edge_gets_a_finite_normal() {
        let cone = TensorPatch::from_fn(2, 2, |i, j| {
            if j == 0 {
                [0.0; 3]
            } else {
                [i as f64 - 1.0, j as f64, 1.0]
            }
        });
        let m = TriMesh::from_patch(&cone, 4, 4);
        assert!(m.normals.iter().all(|n| n.iter().all(|c| c.is_finite())));
    }
}
