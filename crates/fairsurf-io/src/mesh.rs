//! Mesh files: Wavefront OBJ (positions, normals, uv), binary PLY
//! (positions, normals) and binary STL (facets with face normals).

use crate::{write_atomic, Error, Result};
use fairsurf::TriMesh;
use std::io::Write;
use std::path::Path;

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Wavefront OBJ, text, with `vn` and `vt`.
    Obj,
    /// Stanford PLY, binary little-endian, with per-vertex normals.
    Ply,
    /// STL, binary, one facet per triangle.
    Stl,
}

impl MeshFormat {
    /// The format named by a file's extension (`.obj`, `.ply`, `.stl`, any case).
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("obj") => Ok(MeshFormat::Obj),
            Some("ply") => Ok(MeshFormat::Ply),
            Some("stl") => Ok(MeshFormat::Stl),
            _ => Err(Error::scene(
                "--mesh",
                format!(
                    "cannot tell the mesh format of {}: use .obj, .ply or .stl",
                    path.display()
                ),
            )),
        }
    }
}

/// Writes a mesh in the format its extension names, atomically.
pub fn write_mesh(path: &Path, mesh: &TriMesh) -> Result<()> {
    let format = MeshFormat::from_path(path)?;
    write_atomic(path, |w| match format {
        MeshFormat::Obj => write_obj(w, mesh),
        MeshFormat::Ply => write_ply(w, mesh),
        MeshFormat::Stl => write_stl(w, mesh),
    })
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

fn write_ply(w: &mut dyn Write, m: &TriMesh) -> std::io::Result<()> {
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\ncomment fairsurf {}\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        env!("CARGO_PKG_VERSION"),
        m.positions.len(),
        m.triangles.len()
    )?;
    for (p, n) in m.positions.iter().zip(&m.normals) {
        for c in p {
            w.write_all(&c.to_le_bytes())?;
        }
        for c in n {
            w.write_all(&(*c as f32).to_le_bytes())?;
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
