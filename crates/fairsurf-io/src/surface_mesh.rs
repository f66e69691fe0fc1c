//! A triangle mesh of a patch that also carries the surface's curvature at
//! every vertex, for the mesh writers (PLY properties, glTF colours).

use fairsurf::analysis::{curvature, Curvature};
use fairsurf::{ParamSurface, TensorPatch, TriMesh, TriSurface};

/// A [`TriMesh`] sampled from a patch together with the exact curvature of
/// the patch at each vertex's (u, v): `curvature()[k]` belongs to
/// `mesh().positions[k]`, and is `None` where the patch is not regular
/// (|R_u × R_v| ≈ 0, e.g. along a collapsed edge), where curvature is
/// undefined.
///
/// ```
/// use fairsurf::TensorPatch;
/// use fairsurf_io::SurfaceMesh;
/// // z = (x² + y²)/2 over [0, 1]²: K = 1 and H = 1 at the origin.
/// let p = TensorPatch::from_fn(2, 2, |i, j| {
///     let z = [0.0, 0.0, 0.5][i] + [0.0, 0.0, 0.5][j];
///     [i as f64 / 2.0, j as f64 / 2.0, z]
/// });
/// let m = SurfaceMesh::from_patch(&p, 8, 8);
/// assert_eq!(m.curvature().len(), m.mesh().positions.len());
/// let k0 = m.curvature()[0].unwrap(); // vertex 0 is (u, v) = (0, 0)
/// assert!((k0.gaussian - 1.0).abs() < 1e-12 && (k0.mean - 1.0).abs() < 1e-12);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceMesh {
    mesh: TriMesh,
    curvature: Vec<Option<Curvature>>,
}

impl SurfaceMesh {
    /// A surface of any tensor kind (a Bézier patch, a B-spline over its
    /// knot domain) tessellated on a (ru+1)×(rv+1) uniform grid of its
    /// domain ([`TriMesh::from_patch`]) with the curvature at every vertex.
    pub fn from_patch(surface: &impl ParamSurface, ru: usize, rv: usize) -> Self {
        let (mesh, curvature) = TriMesh::with_curvature(surface, ru, rv);
        Self { mesh, curvature }
    }

    /// A triangular surface, each patch sampled at (i, j, r−i−j)/r
    /// ([`TriSurface::mesh_with_curvature`]), with the curvature at every
    /// vertex.
    pub fn from_tri_surface(surface: &TriSurface, r: usize) -> Self {
        let (mesh, curvature) = surface.mesh_with_curvature(r);
        Self { mesh, curvature }
    }

    /// Several meshes as one (each part's vertices and triangles in turn;
    /// no vertices merged).
    pub fn joined(parts: impl IntoIterator<Item = SurfaceMesh>) -> Self {
        let mut out = SurfaceMesh {
            mesh: TriMesh {
                positions: Vec::new(),
                normals: Vec::new(),
                uvs: Vec::new(),
                triangles: Vec::new(),
            },
            curvature: Vec::new(),
        };
        for part in parts {
            let offset = out.mesh.positions.len() as u32;
            out.mesh.positions.extend(&part.mesh.positions);
            out.mesh.normals.extend(&part.mesh.normals);
            out.mesh.uvs.extend(&part.mesh.uvs);
            out.mesh
                .triangles
                .extend(part.mesh.triangles.iter().map(|t| t.map(|i| i + offset)));
            out.curvature.extend(part.curvature);
        }
        out
    }

    /// Any mesh of `patch` (its `uvs` are parameters of `patch`), with the
    /// curvature of `patch` evaluated at each vertex's (u, v).
    pub fn on_patch(patch: &TensorPatch, mesh: TriMesh) -> Self {
        let curvature = mesh
            .uvs
            .iter()
            .map(|&[u, v]| curvature(patch, u, v))
            .collect();
        Self { mesh, curvature }
    }

    /// The triangles, positions, normals and parameters.
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// The curvature at each vertex (`None` where the surface is singular).
    pub fn curvature(&self) -> &[Option<Curvature>] {
        &self.curvature
    }

    /// The mesh without the curvature.
    pub fn into_mesh(self) -> TriMesh {
        self.mesh
    }

    /// The largest |H| over the regular vertices, `None` if none is regular.
    pub fn max_abs_mean_curvature(&self) -> Option<f64> {
        self.curvature
            .iter()
            .flatten()
            .map(|c| c.mean.abs())
            .fold(None, |acc: Option<f64>, h| {
                Some(acc.map_or(h, |a| a.max(h)))
            })
    }

    /// The mean curvature H at each vertex with the singular vertices filled
    /// in by the average H of their regular neighbours (0 if they have none),
    /// for formats that cannot hold NaN (glTF).
    pub(crate) fn mean_curvature_filled(&self) -> Vec<f64> {
        let h: Vec<Option<f64>> = self.curvature.iter().map(|c| c.map(|c| c.mean)).collect();
        if h.iter().all(Option::is_some) {
            return h.into_iter().flatten().collect();
        }
        let mut sum = vec![(0.0, 0usize); h.len()];
        for t in &self.mesh.triangles {
            for &a in t {
                for &b in t {
                    if let (None, Some(hb)) = (h[a as usize], h[b as usize]) {
                        sum[a as usize].0 += hb;
                        sum[a as usize].1 += 1;
                    }
                }
            }
        }
        h.iter()
            .zip(sum)
            .map(|(x, (s, c))| x.unwrap_or(if c > 0 { s / c as f64 } else { 0.0 }))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_collapsed_edge_has_no_curvature_and_its_neighbours_fill_it_in() {
        // Cone-like patch: the whole row j = 0 collapses to the apex.
        let cone = TensorPatch::from_fn(2, 2, |i, j| {
            if j == 0 {
                [0.0; 3]
            } else {
                [i as f64 - 1.0, j as f64, 1.0 + (i * j) as f64 * 0.1]
            }
        });
        let m = SurfaceMesh::from_patch(&cone, 4, 4);
        let singular: Vec<usize> = (0..m.curvature().len())
            .filter(|&k| m.curvature()[k].is_none())
            .collect();
        // Vertex k has uv = (i/4, j/4) with k = 5i + j: the j = 0 column.
        assert_eq!(singular, vec![0, 5, 10, 15, 20]);
        let filled = m.mean_curvature_filled();
        assert!(filled.iter().all(|h| h.is_finite()));
        for k in 0..filled.len() {
            if let Some(c) = m.curvature()[k] {
                assert_eq!(filled[k], c.mean);
            }
        }
        assert!(m.max_abs_mean_curvature().unwrap() > 0.0);
    }
}
