//! Reading the surface a command works on.

use crate::Failure;
use fairsurf::{TensorPatch, TriSurface};
use fairsurf_io::{is_triangular, Built, Scene, TriScene};
use std::path::Path;

/// Prefixes an I/O-crate error with the file it is about.
pub(crate) fn with_file(path: &Path) -> impl Fn(fairsurf_io::Error) -> Failure + '_ {
    move |e| {
        let mut f = Failure::from(e);
        f.message = format!("{}: {}", path.display(), f.message);
        f
    }
}

/// Largest scene file read: 256 MB (a 10,000-patch triangular scene is a
/// few MB; /dev/zero was read until memory ran out).
pub(crate) const MAX_FILE: u64 = 256 << 20;

/// The text of a scene file, at most [`MAX_FILE`] bytes.
pub(crate) fn read(path: &Path) -> Result<String, Failure> {
    use std::io::Read;
    let fail = |source| {
        with_file(path)(fairsurf_io::Error::Read {
            path: path.to_path_buf(),
            source,
        })
    };
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_FILE + 1).read_to_end(&mut bytes))
        .map_err(fail)?;
    if bytes.len() as u64 > MAX_FILE {
        return Err(Failure::input(format!(
            "{}: larger than {} MB; scene files are read whole",
            path.display(),
            MAX_FILE >> 20
        )));
    }
    String::from_utf8(bytes).map_err(|e| {
        fail(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("not UTF-8 text ({e})"),
        ))
    })
}

/// A scene file and its surface.
pub(crate) struct Loaded {
    /// The tensor scene as read (None for a triangular scene).
    pub scene: Option<Scene>,
    /// The surface as tensor patches: the patch of a tensor scene, or every
    /// triangular patch as an exact tensor patch with a collapsed side.
    pub patches: Vec<TensorPatch>,
    /// The triangular surface, for a triangular scene.
    pub tri: Option<TriSurface>,
    /// The validated tensor scene, when it was solved here (a result file is not).
    pub built: Option<Built>,
}

/// The scene in `path` and its surface: a result file (one with a
/// `"report"`) as it is, any other scene solved.
pub(crate) fn surface(path: &Path) -> Result<Loaded, Failure> {
    let text = read(path)?;
    if is_triangular(&text) {
        let scene = TriScene::from_json(&text).map_err(with_file(path))?;
        let tri = if scene.report.is_some() {
            scene.surface().map_err(with_file(path))?
        } else {
            scene.solve().map_err(with_file(path))?.solution.surface
        };
        return Ok(Loaded {
            scene: None,
            patches: tri.tensor_patches(),
            tri: Some(tri),
            built: None,
        });
    }
    let scene = Scene::from_json(&text).map_err(with_file(path))?;
    if scene.report.is_some() {
        let patch = scene.surface_patch().map_err(with_file(path))?;
        return Ok(Loaded {
            scene: Some(scene),
            patches: vec![patch],
            tri: None,
            built: None,
        });
    }
    let solved = scene.solve().map_err(with_file(path))?;
    Ok(Loaded {
        patches: vec![solved.patch().clone()],
        built: Some(solved.built),
        scene: Some(scene),
        tri: None,
    })
}
