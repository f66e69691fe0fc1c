//! Reading the surface a command works on.

use crate::Failure;
use fairsurf::TensorPatch;
use fairsurf_io::{Built, Scene};
use std::path::Path;

/// Prefixes an I/O-crate error with the file it is about.
pub(crate) fn with_file(path: &Path) -> impl Fn(fairsurf_io::Error) -> Failure + '_ {
    move |e| {
        let mut f = Failure::from(e);
        f.message = format!("{}: {}", path.display(), f.message);
        f
    }
}

/// A scene file and its surface.
pub(crate) struct Loaded {
    /// The scene as read.
    pub scene: Scene,
    /// Its surface.
    pub patch: TensorPatch,
    /// The validated scene, when it was solved here (a result file is not).
    pub built: Option<Built>,
}

/// The scene in `path` and its surface: a result file (one with a
/// `"report"`) as it is, any other scene solved.
pub(crate) fn surface(path: &Path) -> Result<Loaded, Failure> {
    let scene = Scene::read(path).map_err(with_file(path))?;
    if scene.report.is_some() {
        let patch = scene.surface_patch().map_err(with_file(path))?;
        return Ok(Loaded {
            scene,
            patch,
            built: None,
        });
    }
    let solved = scene.solve().map_err(with_file(path))?;
    Ok(Loaded {
        patch: solved.patch().clone(),
        built: Some(solved.built),
        scene,
    })
}
