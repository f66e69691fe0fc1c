//! Mesh files: Wavefront OBJ (positions, normals, uv), binary PLY
//! (positions, normals, curvature), binary STL (facets with face normals)
//! and glTF 2.0 (binary `.glb` or `.gltf` with the buffer embedded).

use crate::{gltf, write_atomic, Error, Result, SurfaceMesh};
use fairsurf::TriMesh;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Wavefront OBJ, text, with `vn` and `vt`.
    Obj,
    /// Stanford PLY, binary little-endian, with per-vertex normals.
    Ply,
    /// STL, binary, one facet per triangle.
    Stl,
    /// glTF 2.0 binary container (`.glb`).
    Glb,
    /// glTF 2.0 JSON with the buffer embedded as a base64 data URI (`.gltf`).
    Gltf,
}

impl MeshFormat {
    /// The format named by a file's extension (`.obj`, `.ply`, `.stl`,
    /// `.glb`, `.gltf`, any case).
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("obj") => Ok(MeshFormat::Obj),
            Some("ply") => Ok(MeshFormat::Ply),
            Some("stl") => Ok(MeshFormat::Stl),
            Some("glb") => Ok(MeshFormat::Glb),
            Some("gltf") => Ok(MeshFormat::Gltf),
            _ => Err(Error::scene(
                "--mesh",
                format!(
                    "cannot tell the mesh format of {}: use .obj, .ply, .stl, .glb or .gltf",
                    path.display()
                ),
            )),
        }
    }
}

/// How mesh files are written. Only glTF uses it today.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshOptions {
    /// The range [lo, hi] of |H| (absolute mean curvature) spread over the
    /// colour map in glTF's `COLOR_0`; `None` (the default) uses
    /// [0, max |H| over the mesh]. Monterde & Ugail 2004 fix [0, 1] to
    /// compare surfaces.
    pub colour_range: Option<[f64; 2]>,
}

impl MeshOptions {
    /// Colours spread |H| over [lo, hi] (values outside are clamped).
    pub fn with_colour_range(mut self, lo: f64, hi: f64) -> Self {
        self.colour_range = Some([lo, hi]);
        self
    }

    /// The |H| range for the colours of `mesh`, or why `colour_range` is unusable.
    pub(crate) fn range_for(&self, mesh: &SurfaceMesh, path: &Path) -> Result<[f64; 2]> {
        match self.colour_range {
            Some([lo, hi]) if lo.is_finite() && hi.is_finite() && lo < hi => Ok([lo, hi]),
            Some([lo, hi]) => Err(Error::Export {
                path: PathBuf::from(path),
                message: format!("colour range [{lo}, {hi}] is empty or not finite"),
            }),
            // A flat surface has max |H| = 0: any positive width colours it all alike.
            None => Ok([
                0.0,
                mesh.max_abs_mean_curvature().unwrap_or(0.0).max(1e-300),
            ]),
        }
    }
}

/// Writes a mesh in the format its extension names, atomically, with the
/// default [`MeshOptions`].
///
/// - `.obj`: positions, normals and (u, v).
/// - `.ply`: binary; positions (double), normals (float) and the curvature
///   as `double mean_curvature`, `double gaussian_curvature`, `double k1`,
///   `double k2` (κ₁ ≥ κ₂), NaN at vertices where the surface is singular.
/// - `.stl`: binary, facets with their face normals (no curvature).
/// - `.glb` / `.gltf`: see [`write_mesh_with`].
///
/// ```
/// use fairsurf::TensorPatch;
/// use fairsurf_io::{write_mesh, SurfaceMesh};
/// let p = TensorPatch::from_fn(3, 3, |i, j| [i as f64, j as f64, ((i * j) % 2) as f64]);
/// let dir = std::env::temp_dir().join(format!("fairsurf-doc-mesh-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// write_mesh(&dir.join("bump.glb"), &SurfaceMesh::from_patch(&p, 16, 16)).unwrap();
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write_mesh(path: &Path, mesh: &SurfaceMesh) -> Result<()> {
    write_mesh_with(path, mesh, &MeshOptions::default())
}

/// Writes a mesh in the format its extension names, atomically.
///
/// glTF 2.0 files hold one mesh with one triangle primitive: `POSITION`
/// (with its min/max), `NORMAL`, `COLOR_0` (|H| through
/// [`fairsurf::colour::ColourMap::Viridis`] over `options.colour_range`,
/// converted from sRGB to the linear RGB glTF asks for; grey where the
/// surface is singular), `_MEAN_CURVATURE` (H as a float; glTF forbids NaN,
/// so a singular vertex gets the average H of its regular neighbours) and
/// `u32` indices, with a double-sided, non-metal material. Coordinates are
/// written as they are (glTF viewers take +Y as up).
pub fn write_mesh_with(path: &Path, mesh: &SurfaceMesh, options: &MeshOptions) -> Result<()> {
    let format = MeshFormat::from_path(path)?;
    let m = mesh.mesh();
    match format {
        MeshFormat::Obj => write_atomic(path, |w| write_obj(w, m)),
        MeshFormat::Ply => write_atomic(path, |w| write_ply(w, mesh)),
        MeshFormat::Stl => write_atomic(path, |w| write_stl(w, m)),
        MeshFormat::Glb | MeshFormat::Gltf => {
            if m.triangles.is_empty() {
                return Err(Error::Export {
                    path: PathBuf::from(path),
                    message: "a glTF primitive needs at least one triangle".into(),
                });
            }
            let range = options.range_for(mesh, path)?;
            let doc = gltf::Gltf::new(mesh, range);
            match format {
                MeshFormat::Glb => write_atomic(path, |w| doc.write_glb(w)),
                _ => write_atomic(path, |w| doc.write_gltf(w)),
            }
        }
    }
}

fn write_obj(w: &mut dyn Write, m: &TriMesh) -> std::io::Result<()> {
    writeln!(
        w,
        "# fairsurf {}: {} vertices, {} triangles",
        env!("CARGO_PKG_VERSION"),
        m.positions.len(),
        m.triangles.len()
    )?;
    for p in &m.positions {
        writeln!(w, "v {:.17e} {:.17e} {:.17e}", p[0], p[1], p[2])?;
    }
    for n in &m.normals {
        writeln!(w, "vn {:.17e} {:.17e} {:.17e}", n[0], n[1], n[2])?;
    }
    for t in &m.uvs {
        writeln!(w, "vt {} {}", t[0], t[1])?;
    }
    for t in &m.triangles {
        let [a, b, c] = t.map(|k| k + 1);
        writeln!(w, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}")?;
    }
    Ok(())
}

fn write_ply(w: &mut dyn Write, s: &SurfaceMesh) -> std::io::Result<()> {
    let m = s.mesh();
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\ncomment fairsurf {}\n\
         comment curvature: exact, of the surface at the vertex; NaN where it is singular\n\
         element vertex {}\n\
         property double x\nproperty double y\nproperty double z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         property double mean_curvature\nproperty double gaussian_curvature\n\
         property double k1\nproperty double k2\n\
         element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        env!("CARGO_PKG_VERSION"),
        m.positions.len(),
        m.triangles.len()
    )?;
    for ((p, n), c) in m.positions.iter().zip(&m.normals).zip(s.curvature()) {
        for c in p {
            w.write_all(&c.to_le_bytes())?;
        }
        for c in n {
            w.write_all(&(*c as f32).to_le_bytes())?;
        }
        let k = c.map_or([f64::NAN; 4], |c| {
            [c.mean, c.gaussian, c.principal.0, c.principal.1]
        });
        for x in k {
            w.write_all(&x.to_le_bytes())?;
        }
    }
    for t in &m.triangles {
        w.write_all(&[3u8])?;
        for k in t {
            w.write_all(&k.to_le_bytes())?;
        }
    }
    Ok(())
}

fn write_stl(w: &mut dyn Write, m: &TriMesh) -> std::io::Result<()> {
    let v = |k: u32| {
        let p = m.positions[k as usize];
        stl_io::Vertex::new([p[0] as f32, p[1] as f32, p[2] as f32])
    };
    let tris: Vec<stl_io::Triangle> = m
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| m.positions[k as usize]);
            let n = fairsurf::vector::normalize(fairsurf::vector::cross(
                fairsurf::vector::sub(b, a),
                fairsurf::vector::sub(c, a),
            ))
            .unwrap_or([0.0; 3]);
            stl_io::Triangle {
                normal: stl_io::Normal::new([n[0] as f32, n[1] as f32, n[2] as f32]),
                vertices: [v(t[0]), v(t[1]), v(t[2])],
            }
        })
        .collect();
    stl_io::write_stl(&mut &mut *w, tris.iter())
}
