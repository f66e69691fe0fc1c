//! The surface a scene or result holds, of any kind: what every front end
//! evaluates, meshes, draws and exports (the command line, the server and
//! the Python module use this one type).

use crate::{CadSurface, SurfaceMesh, SurfaceType};
use fairsurf::bspline::BSplineSurface;
use fairsurf::{SurfaceDerivatives, TensorPatch, TriSurface};

/// A surface of any kind.
#[derive(Clone, Debug)]
pub enum Surface {
    /// One tensor-product Bézier patch.
    Tensor(TensorPatch),
    /// Bézier triangles over a mesh.
    Triangular(TriSurface),
    /// A tensor-product B-spline surface.
    BSpline(BSplineSurface),
}

impl Surface {
    /// Its kind.
    pub fn surface_type(&self) -> SurfaceType {
        match self {
            Surface::Tensor(_) => SurfaceType::Tensor,
            Surface::Triangular(_) => SurfaceType::Triangular,
            Surface::BSpline(_) => SurfaceType::BSpline,
        }
    }

    /// The surface as a scene's `surface` object with every control point
    /// given: what [`Scene::surface`](crate::Scene::surface) and `fairsurf
    /// load` read back as this surface exactly (floats are written to
    /// round-trip).
    pub fn scene_json(&self) -> serde_json::Value {
        let rows = |pts: &[fairsurf::Vec3], cv: usize| -> Vec<Vec<fairsurf::Vec3>> {
            pts.chunks(cv).map(<[_]>::to_vec).collect()
        };
        match self {
            Surface::Tensor(p) => {
                let (n, m) = p.degree();
                serde_json::json!({
                    "type": "tensor",
                    "degree": [n, m],
                    "control_points": rows(p.points(), m + 1),
                })
            }
            Surface::BSpline(s) => {
                let ((p, q), (_, cv)) = (s.degree(), s.counts());
                let (u, v) = s.knots();
                serde_json::json!({
                    "type": "bspline",
                    "degree": [p, q],
                    "knots": [u.knots(), v.knots()],
                    "control_points": rows(s.points(), cv),
                })
            }
            Surface::Triangular(t) => {
                serde_json::to_value(crate::tri_scene::TriSurfaceSpec::from(t)).expect("JSON")
            }
        }
    }

    /// Point and derivatives up to order two at (u, v) ∈ [0, 1]² of a
    /// tensor-product surface (a B-spline surface's knot domain
    /// [u₀, u₁] × [v₀, v₁] mapped affinely onto [0, 1]²: the derivatives are
    /// with respect to the mapped parameters, so they scale by (u₁ − u₀) and
    /// (v₁ − v₀) per order). `None` for a triangular surface, which has no
    /// one (u, v) domain.
    pub fn derivatives(&self, u: f64, v: f64) -> Option<SurfaceDerivatives> {
        match self {
            Surface::Tensor(p) => Some(p.derivatives(u, v)),
            Surface::BSpline(s) => {
                let ((u0, u1), (v0, v1)) = (s.knots().0.domain(), s.knots().1.domain());
                let (su, sv) = (u1 - u0, v1 - v0);
                let d = s.derivatives(u0 + u * su, v0 + v * sv);
                let scale = |x: [f64; 3], f: f64| [x[0] * f, x[1] * f, x[2] * f];
                Some(SurfaceDerivatives {
                    point: d.point,
                    du: scale(d.du, su),
                    dv: scale(d.dv, sv),
                    duu: scale(d.duu, su * su),
                    duv: scale(d.duv, su * sv),
                    dvv: scale(d.dvv, sv * sv),
                })
            }
            Surface::Triangular(_) => None,
        }
    }

    /// The surface as tensor patches (a triangular patch is an exact tensor
    /// patch with a collapsed side, a B-spline surface its Bézier pieces):
    /// for pictures and patch-wise measures.
    pub fn tensor_patches(&self) -> Vec<TensorPatch> {
        match self {
            Surface::Tensor(p) => vec![p.clone()],
            Surface::Triangular(t) => t.tensor_patches(),
            Surface::BSpline(s) => s.bezier_pieces().into_iter().map(|p| p.patch).collect(),
        }
    }

    /// The surface as the CAD writers take it: the tensor patch, a B-spline
    /// surface whole (one face with its knots), a triangular surface's
    /// patches as tensor patches with a collapsed side.
    pub fn cad_surfaces(&self) -> Vec<CadSurface> {
        match self {
            Surface::BSpline(s) => vec![s.into()],
            other => other.tensor_patches().iter().map(Into::into).collect(),
        }
    }

    /// A triangle mesh with the curvature at every vertex. `resolution` is
    /// the quads per parameter direction of a tensor or B-spline surface; a
    /// triangular surface gets ⌈resolution / 4⌉ subdivisions per patch edge
    /// (its patches are many and small).
    pub fn mesh(&self, resolution: usize) -> SurfaceMesh {
        match self {
            Surface::Tensor(p) => SurfaceMesh::from_patch(p, resolution, resolution),
            Surface::Triangular(t) => SurfaceMesh::from_tri_surface(t, tri_resolution(resolution)),
            Surface::BSpline(s) => SurfaceMesh::from_patch(s, resolution, resolution),
        }
    }

    /// About how many triangles [`Self::mesh`] makes.
    pub fn mesh_triangles(&self, resolution: usize) -> usize {
        match self {
            Surface::Tensor(_) | Surface::BSpline(_) => 2 * resolution * resolution,
            Surface::Triangular(t) => {
                let r = tri_resolution(resolution);
                r * r * t.patch_count()
            }
        }
    }
}

/// Open CASCADE (and so FreeCAD, gmsh, CadQuery) reads B-splines up to this
/// degree and silently drops higher ones (its `BSplCLib::MaxDegree`).
pub const OCC_MAX_DEGREE: usize = 25;

/// What [`Surface::export`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Exported {
    /// One line saying what the file holds (e.g. "degree 5×5 Bézier patch as
    /// one B-spline face", "2145 vertices, 4096 triangles").
    pub summary: String,
    /// A warning for the file's readers, e.g. a degree above
    /// [`OCC_MAX_DEGREE`].
    pub warning: Option<String>,
}

impl Surface {
    /// Writes the surface to `path` (atomically) in the format its extension
    /// names: `.step`/`.stp` (AP214 B-spline faces), `.igs`/`.iges` (entity
    /// 128), or a mesh (`.obj`, `.ply` with curvature, `.stl`, `.glb`/`.gltf`
    /// with a |H| colour) of `resolution` quads per direction. An unknown
    /// extension is an [`Error::Export`](crate::Error::Export) naming the
    /// formats; nothing is written then.
    pub fn export(
        &self,
        path: &std::path::Path,
        resolution: usize,
        options: &crate::MeshOptions,
    ) -> crate::Result<Exported> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let cad = matches!(ext.as_deref(), Some("step" | "stp" | "igs" | "iges"));
        if !cad && crate::MeshFormat::from_path(path).is_err() {
            return Err(crate::Error::Export {
                path: path.to_path_buf(),
                message: "cannot tell the format from the extension; use .step, .stp, .igs, \
                          .iges, .obj, .ply, .stl, .glb or .gltf"
                    .into(),
            });
        }
        if !cad {
            let mesh = self.mesh(resolution);
            crate::write_mesh_with(path, &mesh, options)?;
            let t = mesh.mesh();
            return Ok(Exported {
                summary: format!(
                    "{} vertices, {} triangles",
                    t.positions.len(),
                    t.triangles.len()
                ),
                warning: None,
            });
        }
        let surfaces = self.cad_surfaces();
        if matches!(ext.as_deref(), Some("step" | "stp")) {
            crate::write_step_surfaces(path, &surfaces)?;
        } else {
            crate::write_iges_surfaces(path, &surfaces)?;
        }
        let (n, m) = match self {
            Surface::Tensor(p) => p.degree(),
            Surface::Triangular(t) => (t.degree(), t.degree()),
            Surface::BSpline(s) => s.degree(),
        };
        let summary = match self {
            Surface::Tensor(_) => format!("degree {n}×{m} Bézier patch as one B-spline face"),
            Surface::Triangular(t) => format!(
                "{} triangular patches of degree {n} as B-spline faces of degree {n}×{n} (one \
                 side collapsed)",
                t.patch_count()
            ),
            Surface::BSpline(s) => {
                let (cu, cv) = s.counts();
                format!(
                    "a degree {n}×{m} B-spline surface of {cu}×{cv} control points as one \
                     B-spline face with its knots"
                )
            }
        };
        let warning = (n.max(m) > OCC_MAX_DEGREE).then(|| {
            format!(
                "degree {n}×{m} is above {OCC_MAX_DEGREE}, the highest B-spline degree Open \
                 CASCADE-based readers (FreeCAD, gmsh, CadQuery) accept; they drop such surfaces"
            )
        });
        Ok(Exported { summary, warning })
    }
}

/// Subdivisions per triangular patch edge for a tensor `resolution`.
fn tri_resolution(resolution: usize) -> usize {
    resolution.div_ceil(4).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fairsurf::bspline::KnotVector;

    /// A B-spline surface's derivatives on [0, 1]² are the chain rule of its
    /// own on the knot domain: central differences of the mapped surface
    /// agree (1e-7), and the point is the surface's point.
    #[test]
    fn bspline_derivatives_follow_the_domain_map() {
        let knots = |lo: f64, hi: f64| {
            KnotVector::new(2, vec![lo, lo, lo, 0.5 * (lo + hi), hi, hi, hi]).unwrap()
        };
        let (ku, kv) = (knots(2.0, 5.0), knots(-1.0, 0.5));
        let points = (0..16)
            .map(|k| {
                let (i, j) = ((k / 4) as f64, (k % 4) as f64);
                [i, j, (i * j).sin() + 0.3 * i * i]
            })
            .collect();
        let s = BSplineSurface::new(ku, kv, points).unwrap();
        let surface = Surface::BSpline(s.clone());
        let (u, v, h) = (0.37, 0.61, 1e-5);
        let d = surface.derivatives(u, v).unwrap();
        let p = |u: f64, v: f64| surface.derivatives(u, v).unwrap().point;
        let own = s.derivatives(2.0 + 3.0 * u, -1.0 + 1.5 * v);
        assert_eq!(d.point, own.point);
        for c in 0..3 {
            let du = (p(u + h, v)[c] - p(u - h, v)[c]) / (2.0 * h);
            let dv = (p(u, v + h)[c] - p(u, v - h)[c]) / (2.0 * h);
            let duu = (p(u + h, v)[c] - 2.0 * p(u, v)[c] + p(u - h, v)[c]) / (h * h);
            let dvv = (p(u, v + h)[c] - 2.0 * p(u, v)[c] + p(u, v - h)[c]) / (h * h);
            let duv = (p(u + h, v + h)[c] - p(u + h, v - h)[c] - p(u - h, v + h)[c]
                + p(u - h, v - h)[c])
                / (4.0 * h * h);
            assert!((du - d.du[c]).abs() < 1e-7, "du {du} {}", d.du[c]);
            assert!((dv - d.dv[c]).abs() < 1e-7, "dv {dv} {}", d.dv[c]);
            assert!((duu - d.duu[c]).abs() < 1e-3, "duu {duu} {}", d.duu[c]);
            assert!((dvv - d.dvv[c]).abs() < 1e-3, "dvv {dvv} {}", d.dvv[c]);
            assert!((duv - d.duv[c]).abs() < 1e-3, "duv {duv} {}", d.duv[c]);
        }
    }
}
