//! Reading the surface a command works on.

use crate::Failure;
use fairsurf_io::{Scene, SolvedScene, Surface, TensorScene};
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
    /// The scene as read.
    pub scene: Scene,
    /// The solve, when the scene was solved here (a result file is not).
    pub solved: Option<SolvedScene>,
    /// The surface: the solved one, or a result file's as it is.
    pub surface: Surface,
}

/// The scene in `path` and its surface: a result file (one with a
/// `"report"`) as it is, any other scene solved.
pub(crate) fn surface(path: &Path) -> Result<Loaded, Failure> {
    let scene = Scene::from_json(&read(path)?).map_err(with_file(path))?;
    let (solved, surface) = if scene.is_result() {
        (None, scene.surface().map_err(with_file(path))?)
    } else {
        let solved = scene.solve().map_err(with_file(path))?;
        let surface = solved.surface();
        (Some(solved), surface)
    };
    Ok(Loaded {
        scene,
        solved,
        surface,
    })
}

/// The tensor scene in `path`; another kind is refused naming what `what`
/// (the command) works on.
pub(crate) fn tensor_scene(path: &Path, what: &str) -> Result<TensorScene, Failure> {
    match Scene::from_json(&read(path)?).map_err(with_file(path))? {
        Scene::Tensor(s) => Ok(s),
        other => Err(Failure::input(format!(
            "{}: surface.type: {what} works on tensor-product scenes, this one is {}",
            path.display(),
            other.surface_type().name()
        ))),
    }
}
