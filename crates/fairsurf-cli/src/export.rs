//! `fairsurf export`: a solved surface as a mesh or as the exact surface for CAD.

use crate::Failure;
use fairsurf_io::{
    write_iges_surfaces, write_mesh_with, write_step_surfaces, CadSurface, MeshFormat, MeshOptions,
    SurfaceMesh,
};
use fairsurf_render::Range;
use std::path::PathBuf;

/// Open CASCADE (and so FreeCAD, gmsh, CadQuery) reads B-splines up to this
/// degree and silently drops higher ones (its `BSplCLib::MaxDegree`).
const OCC_MAX_DEGREE: usize = 25;

#[derive(clap::Args)]
pub struct Args {
    /// A scene (solved first) or a result file (exported as it is).
    file: PathBuf,
    /// The file to write; its extension names the format: .step/.stp (AP214
    /// B-spline faces), .igs/.iges (entity 128), .obj, .ply (with curvature),
    /// .stl, .glb/.gltf (with a |H| colour).
    #[arg(short, long)]
    output: PathBuf,
    /// Mesh resolution: quads per parameter direction (meshes only).
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=4096))]
    resolution: u32,
    /// glTF colour range of |H| as LO,HI, or auto (0 to the largest |H|).
    #[arg(long, allow_hyphen_values = true)]
    colour_range: Option<String>,
}

enum Format {
    Step,
    Iges,
    Mesh,
}

fn format(a: &Args) -> Result<Format, Failure> {
    let ext = a
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("step" | "stp") => Ok(Format::Step),
        Some("igs" | "iges") => Ok(Format::Iges),
        _ => match MeshFormat::from_path(&a.output) {
            Ok(_) => Ok(Format::Mesh),
            Err(_) => Err(Failure::input(format!(
                "-o {}: cannot tell the format; use .step, .stp, .igs, .iges, .obj, .ply, .stl, .glb or .gltf",
                a.output.display()
            ))),
        },
    }
}

/// `LO,HI` (or `auto`, the default) by the renderer's range syntax.
fn colour_range(s: &str) -> Result<Option<[f64; 2]>, Failure> {
    match Range::parse(s) {
        Ok(Range::Fixed(lo, hi)) => Ok(Some([lo, hi])),
        Ok(Range::Auto) => Ok(None),
        Err(e) => Err(Failure::input(format!("--colour-{e}"))),
    }
}

pub fn run(a: Args) -> Result<(), Failure> {
    let format = format(&a)?;
    let range = a
        .colour_range
        .as_deref()
        .map(colour_range)
        .transpose()?
        .flatten();
    let loaded = crate::input::surface(&a.file)?;
    crate::solve::ensure_parent(&a.output)?;
    let patches = loaded.patches;
    let (n, m) = patches[0].degree();
    match format {
        Format::Step | Format::Iges => {
            if n.max(m) > OCC_MAX_DEGREE {
                eprintln!(
                    "warning: degree {n}×{m} is above {OCC_MAX_DEGREE}, the highest B-spline degree \
                     Open CASCADE-based readers (FreeCAD, gmsh, CadQuery) accept; they drop such surfaces"
                );
            }
            let cad: Vec<CadSurface> = match &loaded.bspline {
                Some(b) => vec![b.into()],
                None => patches.iter().map(Into::into).collect(),
            };
            match format {
                Format::Step => write_step_surfaces(&a.output, &cad)?,
                _ => write_iges_surfaces(&a.output, &cad)?,
            }
            if let Some(b) = &loaded.bspline {
                let (cu, cv) = b.counts();
                crate::say!(
                    "{}: a degree {n}×{m} B-spline surface of {cu}×{cv} control points as one B-spline face with its knots",
                    a.output.display(),
                );
            } else if loaded.tri.is_some() {
                crate::say!(
                    "{}: {} triangular patches of degree {n} as B-spline faces of degree {n}×{m} (one side collapsed)",
                    a.output.display(),
                    patches.len()
                );
            } else {
                crate::say!(
                    "{}: degree {n}×{m} Bézier patch as one B-spline face",
                    a.output.display()
                );
            }
        }
        Format::Mesh => {
            let r = a.resolution as usize;
            let mesh = match (&loaded.tri, &loaded.bspline) {
                (Some(t), _) => SurfaceMesh::from_tri_surface(t, r),
                (None, Some(b)) => SurfaceMesh::from_bspline(b, r, r),
                (None, None) => SurfaceMesh::from_patch(&patches[0], r, r),
            };
            let options = MeshOptions {
                colour_range: range,
            };
            write_mesh_with(&a.output, &mesh, &options)?;
            let t = mesh.mesh();
            crate::say!(
                "{}: {} vertices, {} triangles",
                a.output.display(),
                t.positions.len(),
                t.triangles.len()
            );
        }
    }
    Ok(())
}
