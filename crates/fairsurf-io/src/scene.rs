//! One scene file, whatever its surface: the entry point of every front end.
//!
//! A scene is a JSON object whose `surface.type` says what it holds:
//! `"tensor"` ([`TensorScene`]: one tensor-product Bézier patch, Wu & Yang,
//! Monterde & Ugail), `"triangular"` ([`TriScene`]: Bézier triangles over
//! a mesh, Veltkamp & Wesselink) or `"bspline"` ([`BSplineScene`]: a
//! tensor-product B-spline surface). [`Scene::from_json`] reads the type and
//! parses the text once into the matching struct, so that errors keep their
//! JSON path and line; an unknown type is an error at `surface.type`.

use crate::{write_atomic, Surface, TriScene};
use crate::{BSplineScene, SolvedBSplineScene};
use crate::{Error, Measures, Result, SolvedTensorScene, SolvedTriScene, SurfaceMesh, TensorScene};
use fairsurf::{FactorCache, SolveOptions, TensorPatch};
use serde_json::Value;
use std::path::Path;

/// The kinds of surface a scene can hold (`surface.type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SurfaceType {
    /// `"tensor"`: a tensor-product Bézier patch of degree (n, m).
    Tensor,
    /// `"triangular"`: triangular Bézier patches over a triangle mesh.
    Triangular,
    /// `"bspline"`: a tensor-product B-spline surface.
    BSpline,
}

impl SurfaceType {
    /// Every kind, in the order error messages list them.
    pub const ALL: [SurfaceType; 3] = [
        SurfaceType::Tensor,
        SurfaceType::Triangular,
        SurfaceType::BSpline,
    ];

    /// The name scenes use for it in `surface.type`.
    pub fn name(self) -> &'static str {
        match self {
            SurfaceType::Tensor => "tensor",
            SurfaceType::Triangular => "triangular",
            SurfaceType::BSpline => "bspline",
        }
    }

    fn from_name(name: &str) -> Option<SurfaceType> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The kind a scene text holds, read from `surface.type` without
    /// parsing the rest; the error of [`Scene::from_json`] for an unknown
    /// kind. A text without a readable type counts as tensor (the tensor
    /// parser then names what is wrong).
    pub fn of_json(text: &str) -> Result<SurfaceType> {
        surface_type(text)
    }

    /// The JSON Schema of this kind's scene files.
    pub fn json_schema(self) -> Value {
        match self {
            SurfaceType::Tensor => TensorScene::json_schema(),
            SurfaceType::Triangular => TriScene::json_schema(),
            SurfaceType::BSpline => BSplineScene::json_schema(),
        }
    }
}

/// A scene of any kind, as read from a file; it writes as that kind's
/// scene (its `surface.type` says which).
#[derive(Clone, Debug, serde::Serialize)]
#[serde(untagged)]
pub enum Scene {
    /// `surface.type` `"tensor"`.
    Tensor(TensorScene),
    /// `surface.type` `"triangular"`.
    Triangular(TriScene),
    /// `surface.type` `"bspline"`.
    BSpline(BSplineScene),
}

impl Scene {
    /// Parses a scene of any kind. Errors name the JSON path: a malformed
    /// value (`surface.degree[1]: invalid type: …`), or an unknown kind
    /// (`surface.type: unknown surface type "nurbs": expected "tensor" or
    /// "triangular"`).
    pub fn from_json(text: &str) -> Result<Scene> {
        match SurfaceType::of_json(text)? {
            SurfaceType::Tensor => TensorScene::from_json(text).map(Scene::Tensor),
            SurfaceType::Triangular => TriScene::from_json(text).map(Scene::Triangular),
            SurfaceType::BSpline => BSplineScene::from_json(text).map(Scene::BSpline),
        }
    }

    /// Reads and parses a scene file.
    pub fn read(path: &Path) -> Result<Scene> {
        Self::from_json(&read_text(path)?)
    }

    /// What kind of surface the scene holds.
    pub fn surface_type(&self) -> SurfaceType {
        match self {
            Scene::Tensor(_) => SurfaceType::Tensor,
            Scene::Triangular(_) => SurfaceType::Triangular,
            Scene::BSpline(_) => SurfaceType::BSpline,
        }
    }

    /// The scene's `name`, if it has one.
    pub fn name(&self) -> Option<&str> {
        match self {
            Scene::Tensor(s) => s.name.as_deref(),
            Scene::Triangular(s) => s.name.as_deref(),
            Scene::BSpline(s) => s.name.as_deref(),
        }
    }

    /// Whether this is a result file (it has a `"report"`): its control
    /// points are the solved surface.
    pub fn is_result(&self) -> bool {
        match self {
            Scene::Tensor(s) => s.report.is_some(),
            Scene::Triangular(s) => s.report.is_some(),
            Scene::BSpline(s) => s.report.is_some(),
        }
    }

    /// Validates and solves with default options.
    pub fn solve(&self) -> Result<SolvedScene> {
        self.solve_using(&SolveOptions::default(), None)
    }

    /// Validates and solves with `opts` (a triangular solve always
    /// analyses its result: its measures are part of the solve).
    pub fn solve_with(&self, opts: &SolveOptions) -> Result<SolvedScene> {
        self.solve_using(opts, None)
    }

    /// Validates and solves, reusing a factorization from `cache` when one
    /// fits (and keeping this one there): for a designer dragging points.
    pub fn solve_cached(&self, opts: &SolveOptions, cache: &FactorCache) -> Result<SolvedScene> {
        self.solve_using(opts, Some(cache))
    }

    fn solve_using(&self, opts: &SolveOptions, cache: Option<&FactorCache>) -> Result<SolvedScene> {
        Ok(match (self, cache) {
            (Scene::Tensor(s), Some(c)) => SolvedScene::Tensor(s.solve_cached(opts, c)?),
            (Scene::Tensor(s), None) => SolvedScene::Tensor(s.solve_with(opts)?),
            (Scene::Triangular(s), Some(c)) => SolvedScene::Triangular(s.solve_cached(c)?),
            (Scene::Triangular(s), None) => SolvedScene::Triangular(s.solve()?),
            (Scene::BSpline(s), Some(c)) => {
                SolvedScene::BSpline(Box::new(s.solve_cached(opts, c)?))
            }
            (Scene::BSpline(s), None) => SolvedScene::BSpline(Box::new(s.solve_with(opts)?)),
        })
    }

    /// Measures of the surface as the scene gives it, without solving (see
    /// [`TensorScene::analyse`], [`TriScene::analyse`]).
    pub fn analyse(&self) -> Result<Measures> {
        match self {
            Scene::Tensor(s) => s.analyse(),
            Scene::Triangular(s) => s.analyse(),
            Scene::BSpline(s) => s.analyse(),
        }
    }

    /// The surface as the scene gives it; a `null` control point is an
    /// error naming it.
    pub fn surface(&self) -> Result<Surface> {
        Ok(match self {
            Scene::Tensor(s) => Surface::Tensor(s.surface_patch()?),
            Scene::Triangular(s) => Surface::Triangular(s.surface()?),
            Scene::BSpline(s) => Surface::BSpline(s.surface()?),
        })
    }

    /// The surface as the scene gives it, as tensor patches
    /// ([`Surface::tensor_patches`]).
    pub fn tensor_patches(&self) -> Result<Vec<TensorPatch>> {
        Ok(self.surface()?.tensor_patches())
    }

    /// A mesh of the surface as the scene gives it ([`Surface::mesh`]).
    pub fn mesh(&self, resolution: usize) -> Result<SurfaceMesh> {
        Ok(self.surface()?.mesh(resolution))
    }
}

/// A solved scene of any kind.
#[derive(Debug)]
pub enum SolvedScene {
    /// A solved (or constructed) tensor patch.
    Tensor(SolvedTensorScene),
    /// A solved triangular surface.
    Triangular(SolvedTriScene),
    /// A solved B-spline surface.
    BSpline(Box<SolvedBSplineScene>),
}

impl SolvedScene {
    /// What kind of surface was solved.
    pub fn surface_type(&self) -> SurfaceType {
        match self {
            SolvedScene::Tensor(_) => SurfaceType::Tensor,
            SolvedScene::Triangular(_) => SurfaceType::Triangular,
            SolvedScene::BSpline(_) => SurfaceType::BSpline,
        }
    }

    /// The `"report"` object of the result file.
    pub fn report_json(&self) -> Value {
        match self {
            SolvedScene::Tensor(s) => s.report_json(),
            SolvedScene::Triangular(s) => s.report_json(),
            SolvedScene::BSpline(s) => s.report_json(),
        }
    }

    /// The result file's content, pretty-printed JSON: the scene with every
    /// control point and the report, in the scene's field order; solving it
    /// again gives the same surface.
    pub fn result_text(&self) -> String {
        let text = match self {
            SolvedScene::Tensor(s) => serde_json::to_string_pretty(&s.result_scene()),
            SolvedScene::Triangular(s) => serde_json::to_string_pretty(&s.result_scene()),
            SolvedScene::BSpline(s) => serde_json::to_string_pretty(&s.result_scene()),
        };
        text.expect("a scene serializes")
    }

    /// Writes the result file (atomically).
    pub fn write(&self, path: &Path) -> Result<()> {
        let text = self.result_text();
        write_atomic(path, |w| {
            w.write_all(text.as_bytes())?;
            w.write_all(b"\n")
        })
    }

    /// What the result's reader should know (the report's `notes`).
    pub fn notes(&self) -> Vec<String> {
        match self {
            SolvedScene::Tensor(s) => s.notes(),
            SolvedScene::Triangular(s) => s.notes(),
            SolvedScene::BSpline(s) => s.notes(),
        }
    }

    /// The solved surface (a copy).
    pub fn surface(&self) -> Surface {
        match self {
            SolvedScene::Tensor(s) => Surface::Tensor(s.patch().clone()),
            SolvedScene::Triangular(s) => Surface::Triangular(s.surface().clone()),
            SolvedScene::BSpline(s) => Surface::BSpline(s.surface().clone()),
        }
    }

    /// The solved surface as tensor patches ([`Surface::tensor_patches`]):
    /// for STEP, IGES and pictures.
    pub fn tensor_patches(&self) -> Vec<TensorPatch> {
        self.surface().tensor_patches()
    }

    /// The solved surface as the CAD writers take it
    /// ([`Surface::cad_surfaces`]).
    pub fn cad_surfaces(&self) -> Vec<crate::CadSurface> {
        self.surface().cad_surfaces()
    }

    /// A triangle mesh of the solved surface ([`Surface::mesh`]).
    pub fn mesh(&self, resolution: usize) -> SurfaceMesh {
        self.surface().mesh(resolution)
    }

    /// About how many triangles [`Self::mesh`] makes.
    pub fn mesh_triangles(&self, resolution: usize) -> usize {
        self.surface().mesh_triangles(resolution)
    }
}

/// The text of a file; an error names it.
pub(crate) fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path).map_err(|source| Error::Read {
        path: path.to_path_buf(),
        source,
    })
}

/// Parses JSON into `T`; errors name the JSON path.
pub(crate) fn parse_with_path<T: serde::de::DeserializeOwned>(text: &str) -> Result<T> {
    let de = &mut serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        let path = e.path().to_string();
        Error::scene(
            if path == "." { String::new() } else { path },
            e.into_inner().to_string(),
        )
    })?;
    // One JSON value and nothing after it but white space.
    de.end().map_err(|e| {
        Error::scene(
            String::new(),
            format!("more after the scene's closing brace ({e}): a file holds one scene"),
        )
    })?;
    Ok(value)
}

/// The kind of surface a JSON text holds, from `surface.type`, read by a
/// pass that keeps nothing else. A text without a readable type is taken
/// as tensor, so that the tensor parser names what is wrong with its path
/// (a missing `type`, a number there, a missing `surface`).
///
/// A text that is not valid JSON (a NaN, 1e999, a truncated file) is
/// triangular when it says `"type": "triangular"` anywhere (no other scene
/// field has that value), so that the triangular parser names the real
/// problem and its path.
fn surface_type(text: &str) -> Result<SurfaceType> {
    #[derive(serde::Deserialize)]
    struct Skim {
        surface: Option<SkimSurface>,
    }
    #[derive(serde::Deserialize)]
    struct SkimSurface {
        #[serde(rename = "type")]
        kind: Option<String>,
    }
    let kind = match serde_json::from_str::<Skim>(text) {
        Ok(skim) => skim.surface.and_then(|s| s.kind),
        Err(_) if says_triangular(text) => return Ok(SurfaceType::Triangular),
        Err(_) => None,
    };
    let Some(kind) = kind else {
        return Ok(SurfaceType::Tensor);
    };
    SurfaceType::from_name(&kind).ok_or_else(|| {
        let names: Vec<String> = SurfaceType::ALL
            .iter()
            .map(|k| format!("{:?}", k.name()))
            .collect();
        Error::scene(
            "surface.type",
            format!(
                "unknown surface type {kind:?}: expected {}",
                match names.split_last() {
                    Some((last, rest)) if !rest.is_empty() =>
                        format!("{} or {last}", rest.join(", ")),
                    _ => names.join(""),
                }
            ),
        )
    })
}

/// Whether the text has `"type"`, a colon and `"triangular"` in a row
/// (white space allowed between them).
fn says_triangular(text: &str) -> bool {
    text.match_indices("\"type\"").any(|(k, key)| {
        let rest = text[k + key.len()..].trim_start();
        rest.strip_prefix(':')
            .is_some_and(|r| r.trim_start().starts_with("\"triangular\""))
    })
}
