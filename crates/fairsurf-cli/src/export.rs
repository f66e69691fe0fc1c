//! `fairsurf export`: a solved surface as a mesh or as the exact surface for CAD.

use crate::Failure;
use fairsurf_io::MeshOptions;
use fairsurf_render::Range;
use std::path::PathBuf;

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

/// `LO,HI` (or `auto`, the default) by the renderer's range syntax.
fn colour_range(s: &str) -> Result<Option<[f64; 2]>, Failure> {
    match Range::parse(s) {
        Ok(Range::Fixed(lo, hi)) => Ok(Some([lo, hi])),
        Ok(Range::Auto) => Ok(None),
        Err(e) => Err(Failure::input(format!("--colour-{e}"))),
    }
}

pub fn run(a: Args) -> Result<(), Failure> {
    let range = a
        .colour_range
        .as_deref()
        .map(colour_range)
        .transpose()?
        .flatten();
    let loaded = crate::input::surface(&a.file)?;
    crate::solve::ensure_parent(&a.output)?;
    let options = MeshOptions {
        colour_range: range,
    };
    let done = loaded
        .surface
        .export(&a.output, a.resolution as usize, &options)?;
    if let Some(w) = &done.warning {
        eprintln!("warning: {w}");
    }
    crate::say!("{}: {}", a.output.display(), done.summary);
    Ok(())
}
