//! Reading the surface a command works on.

use crate::Failure;
use fairsurf::TensorPatch;
use fairsurf_io::Scene;
use std::path::Path;

/// Prefixes an I/O-crate error with the file it is about.
pub(crate) fn with_file(path: &Path) -> impl Fn(fairsurf_io::Error) -> Failure + '_ {
    move |e| {
        let mut f = Failure::from(e);
        f.message = format!("{}: {}", path.display(), f.message);
        f
    }
}

/// The scene in `path` and its surface: a result file (one with a
/// `"report"`) as it is, any other scene solved.
pub(crate) fn surface(path: &Path) -> Result<(Scene, TensorPatch), Failure> {
    let scene = Scene::read(path).map_err(with_file(path))?;
    let patch = if scene.report.is_some() {
        scene.surface_patch().map_err(with_file(path))?
    } else {
        scene.solve().map_err(with_file(path))?.patch().clone()
    };
    Ok((scene, patch))
}
