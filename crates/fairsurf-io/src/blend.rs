//! Blend scenes and blend jobs ([`fairsurf::fill::blend`]): two surfaces,
//! each given inline or as a face of a STEP file, one edge of each, the
//! transition surface between them, its report, and the faces for the
//! sewn STEP output.
//!
//! Field docs here become the descriptions in `fairsurf schema --type blend`.

use crate::fill::{
    patch_json, sew_tolerance, side_json, stand_in, stand_ins_json, FaceSpec, FillSpec,
};
use crate::step_read::FaceSurface;
use crate::{CadSurface, Error, Result};
use fairsurf::analysis::Edge;
use fairsurf::bspline::{BSplineSurface, FitTolerance, RationalSurface};
use fairsurf::fill::{blend, Blend, BlendOptions, Bulge};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A blend scene: a transition surface between two surfaces along one
/// edge of each, G¹ to both (Wu & Yang 2015, Fig. 5).
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BlendScene {
    /// Free text: a title.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Free text: what the scene shows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The two surfaces, A then B, each with the edge the blend starts
    /// (A, v = 0 of the blend) or ends (B, v = 1) on.
    pub surfaces: Vec<BlendSurfaceSpec>,
    /// `[A, B]`: the tangent length across at each edge, relative to the
    /// gap between the edges (> 0, at most 10). Default: the pair with the
    /// least W = ∫∫ κ₁² + κ₂² dA (each in [1/4, 4]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bulge: Option<[f64; 2]>,
    /// Also fix the made sides' cross derivatives (clamped on all four
    /// sides); default false: the energy chooses them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clamp_sides: Option<bool>,
    /// The energy and its options, as in a fill scene.
    #[serde(default)]
    pub fill: FillSpec,
}

/// A boundary of a surface, in its own parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum EdgeName {
    /// u = u_min.
    U0,
    /// u = u_max.
    U1,
    /// v = v_min.
    V0,
    /// v = v_max.
    V1,
}

impl From<EdgeName> for Edge {
    fn from(e: EdgeName) -> Edge {
        match e {
            EdgeName::U0 => Edge::U0,
            EdgeName::U1 => Edge::U1,
            EdgeName::V0 => Edge::V0,
            EdgeName::V1 => Edge::V1,
        }
    }
}

/// One of the two surfaces: `face` inline, or `step` and `index`.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BlendSurfaceSpec {
    /// The surface inline (as a fill scene's faces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub face: Option<FaceSpec>,
    /// A STEP file (relative to the scene's folder) whose shells hold the
    /// surface; every face of it goes to the output.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<String>,
    /// The face's index in the STEP file (its shells' faces in order, as
    /// `fairsurf fill --list` counts them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub index: Option<usize>,
    /// `"u0"`, `"u1"`, `"v0"` or `"v1"`: the surface's boundary the blend
    /// meets.
    pub edge: EdgeName,
}

/// A blend job read from a scene: every face for the output, which two the
/// blend joins, and how.
#[derive(Clone, Debug)]
pub struct BlendInput {
    /// The inline faces and every face of the STEP files named, each file
    /// once, in the order first named; a rational face (a cylinder, …) by
    /// its polynomial stand-in (within the default [`FitTolerance`]).
    pub faces: Vec<BSplineSurface>,
    /// What each face is ("B-spline", "plane", "cylinder", …).
    pub kinds: Vec<&'static str>,
    /// Per face, the rational surface a stand-in stands for (written as
    /// that, and what A or B is measured against).
    pub rational: Vec<Option<Arc<RationalSurface>>>,
    /// Per rational face, its stand-in's distance from it along its sides
    /// (position, angle in radians).
    pub stand_ins: Vec<Option<(f64, f64)>>,
    /// A's and B's indices in `faces`, and their edges.
    pub ends: [(usize, Edge); 2],
    /// How to blend.
    pub options: BlendOptions,
}

/// The largest bulge.
const MAX_BULGE: f64 = 10.0;

impl BlendScene {
    /// Parses a blend scene; errors name the JSON path.
    pub fn from_json(text: &str) -> Result<BlendScene> {
        crate::scene::parse_with_path(text)
    }

    /// The JSON Schema of blend scenes.
    pub fn json_schema() -> Value {
        serde_json::to_value(schemars::schema_for!(BlendScene)).expect("a schema serializes")
    }

    /// The options; errors name `bulge[k]` or `fill.<field>`.
    pub fn options(&self) -> Result<BlendOptions> {
        let bulge = match self.bulge {
            Some(b) => Bulge::Fixed(
                check_bulge(b).map_err(|(k, why)| Error::scene(format!("bulge[{k}]"), why))?,
            ),
            None => Bulge::Least,
        };
        Ok(BlendOptions {
            fill: self.fill.options()?,
            bulge,
            clamp_sides: self.clamp_sides.unwrap_or(false),
        })
    }
}

/// The pair if both are > 0 and ≤ 10; else which is not, and why.
pub fn check_bulge(b: [f64; 2]) -> std::result::Result<[f64; 2], (usize, String)> {
    match b.iter().position(|&x| !(x > 0.0 && x <= MAX_BULGE)) {
        Some(k) => Err((
            k,
            format!("expected a number > 0 and ≤ {MAX_BULGE}, got {}", b[k]),
        )),
        None => Ok(b),
    }
}

impl BlendInput {
    /// Reads the blend scene at `path` and the STEP files it names.
    pub fn read(path: &Path) -> Result<BlendInput> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let folder = path.parent().unwrap_or(Path::new("."));
        Self::from_text(&text, folder)
    }

    /// From a blend scene's text; STEP files are found relative to
    /// `folder`. Errors name the JSON path: `surfaces[k].index` for a face
    /// the file does not have, `surfaces[k].step` for a file that cannot
    /// be read (with the file's own error).
    pub fn from_text(text: &str, folder: &Path) -> Result<BlendInput> {
        let scene = BlendScene::from_json(text)?;
        if scene.surfaces.len() != 2 {
            return Err(Error::scene(
                "surfaces",
                format!("a blend joins two surfaces, got {}", scene.surfaces.len()),
            ));
        }
        let options = scene.options()?;
        let mut faces: Vec<BSplineSurface> = Vec::new();
        let mut kinds: Vec<&'static str> = Vec::new();
        let mut rational: Vec<Option<Arc<RationalSurface>>> = Vec::new();
        let mut stand_ins: Vec<Option<(f64, f64)>> = Vec::new();
        // Each STEP file once: (its path, the index of its first face).
        let mut files: Vec<(PathBuf, usize, usize)> = Vec::new();
        let mut ends = [(0, Edge::U0); 2];
        for (k, s) in scene.surfaces.iter().enumerate() {
            let path = format!("surfaces[{k}]");
            let index = match (&s.face, &s.step, s.index) {
                (Some(f), None, None) => {
                    faces.push(f.surface(&format!("{path}.face"))?);
                    kinds.push("B-spline");
                    rational.push(None);
                    stand_ins.push(None);
                    faces.len() - 1
                }
                (None, Some(step), Some(i)) => {
                    // One file however its path is spelled.
                    let file = folder.join(step);
                    let file = file.canonicalize().unwrap_or(file);
                    let (first, count) = match files.iter().find(|f| f.0 == file) {
                        Some(&(_, first, count)) => (first, count),
                        None => {
                            let read = std::fs::read_to_string(&file)
                                .map_err(|e| {
                                    Error::scene(
                                        format!("{path}.step"),
                                        format!("cannot read {}: {e}", file.display()),
                                    )
                                })
                                .and_then(|t| {
                                    crate::step_read::read_step(&t).map_err(|e| {
                                        Error::scene(
                                            format!("{path}.step"),
                                            format!("{}: {e}", file.display()),
                                        )
                                    })
                                })?;
                            let (first, count) = (faces.len(), read.len());
                            for (j, f) in read.into_iter().enumerate() {
                                if !f.loops.is_empty() {
                                    return Err(Error::scene(
                                        format!("{path}.step"),
                                        format!(
                                            "{}: face {j} is a {} face: a blend takes files whose \
                                             faces are bounded by four sides of their surfaces \
                                             (`fairsurf fill` takes trimmed ones)",
                                            file.display(),
                                            f.kind
                                        ),
                                    ));
                                }
                                kinds.push(f.kind);
                                match f.surface {
                                    FaceSurface::Polynomial(s) => {
                                        faces.push(s);
                                        rational.push(None);
                                        stand_ins.push(None);
                                    }
                                    FaceSurface::Rational(r) => {
                                        let s = stand_in(
                                            &r,
                                            FitTolerance::default(),
                                            [false, false],
                                            j,
                                            f.kind,
                                        )
                                        .map_err(|e| {
                                            Error::scene(
                                                format!("{path}.step"),
                                                format!("{}: {e}", file.display()),
                                            )
                                        })?;
                                        faces.push(s.surface);
                                        rational.push(Some(Arc::new(r)));
                                        stand_ins.push(Some((s.position, s.angle)));
                                    }
                                }
                            }
                            files.push((file.clone(), first, count));
                            (first, count)
                        }
                    };
                    if i >= count {
                        return Err(Error::scene(
                            format!("{path}.index"),
                            if count == 0 {
                                format!("{} has no faces", file.display())
                            } else {
                                format!(
                                    "{} has {count} faces (0 to {}), not {i}",
                                    file.display(),
                                    count - 1
                                )
                            },
                        ));
                    }
                    first + i
                }
                (None, Some(_), None) => {
                    return Err(Error::scene(
                        format!("{path}.index"),
                        "a surface from a STEP file needs the face's index",
                    ))
                }
                (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                    return Err(Error::scene(
                        path,
                        "give either \"face\" (inline) or \"step\" and \"index\", not both",
                    ))
                }
                (None, None, _) => {
                    return Err(Error::scene(
                        path,
                        "no surface: give \"face\" (inline) or \"step\" and \"index\"",
                    ))
                }
            };
            ends[k] = (index, s.edge.into());
        }
        Ok(BlendInput {
            faces,
            kinds,
            rational,
            stand_ins,
            ends,
            options,
        })
    }

    /// The blend: a rational A or B through its stand-in, measured against
    /// the rational surface.
    pub fn blend(&self) -> Result<Blend> {
        let [(a, ea), (b, eb)] = self.ends;
        let mut options = self.options.clone();
        options.fill.rational_faces = vec![self.rational[a].clone(), self.rational[b].clone()];
        Ok(blend(&self.faces[a], ea, &self.faces[b], eb, &options)?)
    }

    /// Every face (a rational one as it is) and the blend, for the CAD
    /// writers.
    pub fn surfaces(&self, blend: &Blend) -> Vec<CadSurface> {
        crate::fill::fill_surfaces(&self.faces, &self.rational, &[])
            .into_iter()
            .chain([CadSurface::from(&blend.surface)])
            .collect()
    }

    /// Under this distance vertices and edges are shared in the STEP file
    /// (the stand-ins' fit; see `fill`'s hole tolerance).
    pub fn sew_within(&self) -> f64 {
        sew_tolerance(&self.faces, &self.stand_ins)
    }
}

/// A blend's report: the surface's size, against A and B the gap and
/// normal angle measured on it, the corners, α, W, the solve's figures and
/// the time.
pub fn blend_json(input: &BlendInput, blend: &Blend) -> Value {
    let r = &blend.report;
    let sides = r
        .sides
        .iter()
        .zip(input.ends)
        .map(|(f, (face, _))| side_json(f, face))
        .collect();
    let mut out = patch_json(
        &blend.surface,
        sides,
        &r.sides,
        &r.corners,
        &r.curvature,
        &r.willmore,
        r.normal_weight,
        &r.solve,
        &r.seconds,
    );
    out["faces"] = json!(input.faces.len());
    out["stand_ins"] = stand_ins_json(&input.kinds, &input.stand_ins);
    out["flipped"] = json!(r.flipped);
    out["alpha"] = json!(r.alpha);
    out["bulge"] = json!(r.bulge);
    out["bulge_search"] = json!(r.bulge_search.map(|b| json!({
        "evaluations": b.evaluations,
        "curvature_w_at_one": b.w_at_one,
        "seconds": b.seconds,
    })));
    out["clamp_sides"] = json!(input.options.clamp_sides);
    out["fairsurf_version"] = json!(env!("CARGO_PKG_VERSION"));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example() -> (String, PathBuf) {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cad");
        let text = std::fs::read_to_string(dir.join("blend_sheets.json")).unwrap();
        (text, dir)
    }

    fn err(text: &str, folder: &Path) -> String {
        BlendInput::from_text(text, folder).unwrap_err().to_string()
    }

    /// A surface named as a face of a STEP file is that face: the blend
    /// from the STEP file equals the inline one, every face of the file
    /// goes to the output, and a file named twice is read once.
    #[test]
    fn a_surface_from_a_step_file_is_the_same_surface() {
        let (text, dir) = example();
        let inline = BlendInput::from_text(&text, &dir).unwrap();
        let tmp = std::env::temp_dir().join(format!("fairsurf-blend-{}", std::process::id()));
        std::fs::create_dir_all(&tmp).unwrap();
        let cad: Vec<CadSurface> = inline.faces.iter().map(CadSurface::from).collect();
        crate::write_step_surfaces(&tmp.join("two.step"), &cad).unwrap();
        let mut v: Value = serde_json::from_str(&text).unwrap();
        v["surfaces"][0] = json!({"step": "two.step", "index": 0, "edge": "u1"});
        v["surfaces"][1] = json!({"step": "two.step", "index": 1, "edge": "u0"});
        let from_step = BlendInput::from_text(&v.to_string(), &tmp).unwrap();
        assert_eq!(from_step.faces.len(), 2, "the file read once");
        assert_eq!(from_step.ends, [(0, Edge::U1), (1, Edge::U0)]);
        let (a, b) = (inline.blend().unwrap(), from_step.blend().unwrap());
        let d = a
            .surface
            .points()
            .iter()
            .zip(b.surface.points())
            .map(|(p, q)| fairsurf::vector::norm(fairsurf::vector::sub(*p, *q)))
            .fold(0.0, f64::max);
        assert!(d < 1e-12, "{d}");
        v["surfaces"][1]["index"] = json!(2);
        assert!(
            err(&v.to_string(), &tmp).starts_with("surfaces[1].index: "),
            "{}",
            err(&v.to_string(), &tmp)
        );
        assert!(err(&v.to_string(), &tmp).ends_with("has 2 faces (0 to 1), not 2"));
        v["surfaces"][1] = json!({"step": "none.step", "index": 0, "edge": "u0"});
        let e = err(&v.to_string(), &tmp);
        assert!(
            e.starts_with("surfaces[1].step: cannot read ") && e.contains("none.step"),
            "{e}"
        );
        std::fs::write(tmp.join("bad.step"), "not step").unwrap();
        v["surfaces"][1] = json!({"step": "bad.step", "index": 0, "edge": "u0"});
        let e = err(&v.to_string(), &tmp);
        assert!(
            e.starts_with("surfaces[1].step: ") && e.contains("not a STEP file"),
            "{e}"
        );
        std::fs::remove_dir_all(&tmp).unwrap();
    }

    /// Every malformed scene names its JSON path.
    #[test]
    fn bad_scenes_name_the_path() {
        let (text, dir) = example();
        let v: Value = serde_json::from_str(&text).unwrap();
        let with = |f: &dyn Fn(&mut Value)| {
            let mut w = v.clone();
            f(&mut w);
            err(&w.to_string(), &dir)
        };
        type Edit = Box<dyn Fn(&mut Value)>;
        let cases: Vec<(Edit, &str)> = vec![
            (
                Box::new(|w| {
                    w["surfaces"].as_array_mut().unwrap().pop();
                }),
                "surfaces: a blend joins two surfaces, got 1",
            ),
            (
                Box::new(|w| w["surfaces"][0]["edge"] = json!("w2")),
                "surfaces[0].edge: unknown variant `w2`",
            ),
            (
                Box::new(|w| w["surfaces"][1]["step"] = json!("x.step")),
                "surfaces[1]: give either \"face\"",
            ),
            (
                Box::new(|w| {
                    w["surfaces"][1] = json!({"step": "x.step", "edge": "u0"});
                }),
                "surfaces[1].index: a surface from a STEP file needs",
            ),
            (
                Box::new(|w| w["surfaces"][1] = json!({"edge": "u0"})),
                "surfaces[1]: no surface",
            ),
            (
                Box::new(|w| w["bulge"] = json!([1.0, 0.0])),
                "bulge[1]: expected a number > 0",
            ),
            (
                Box::new(|w| w["bulge"] = json!([11.0, 1.0])),
                "bulge[0]: expected a number > 0 and ≤ 10, got 11",
            ),
            (
                Box::new(|w| w["fill"] = json!({"elevate": 11})),
                "fill.elevate: expected 0 to 10",
            ),
            (
                Box::new(|w| w["surfaces"][0]["face"]["degree"] = json!([3, 2])),
                "surfaces[0].face.knots[1]: ",
            ),
            (
                Box::new(|w| w["surfaces"][1]["face"]["degree"] = json!([4, 3])),
                "surfaces[1].face.control_points",
            ),
            (Box::new(|w| w["colour"] = json!(1)), "colour"),
        ];
        for (f, want) in cases {
            let e = with(&*f);
            assert!(e.contains(want), "{e} (wanted {want})");
        }
        // The same surface's two edges: a blend of a sheet with itself.
        let mut w = v.clone();
        w["surfaces"][1] = w["surfaces"][0].clone();
        w["surfaces"][1]["edge"] = json!("u0");
        let input = BlendInput::from_text(&w.to_string(), &dir).unwrap();
        assert_eq!(input.faces.len(), 2);
        // The two ends touching: the solve's refusal, named.
        w["surfaces"][1]["edge"] = json!("v0");
        let input = BlendInput::from_text(&w.to_string(), &dir).unwrap();
        let e = input.blend().unwrap_err().to_string();
        assert!(e.contains("meet at their"), "{e}");
    }

    /// A blend between two cylinder faces of a STEP file (rational faces,
    /// through their stand-ins): within the tolerance of both, measured
    /// against the cylinders and reported as not exact; the file read once
    /// however its path is spelled; the cylinders written as rational
    /// surfaces.
    #[test]
    fn a_blend_between_cylinders_is_within_tolerance() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cad");
        let text = r#"{"surfaces": [
            {"step": "fillet_hole.step", "index": 1, "edge": "v1"},
            {"step": "./fillet_hole.step", "index": 6, "edge": "v0"}]}"#;
        let input = BlendInput::from_text(text, &dir).unwrap();
        assert_eq!(input.faces.len(), 8);
        assert_eq!((input.kinds[1], input.kinds[6]), ("cylinder", "cylinder"));
        let b = input.blend().unwrap();
        for f in &b.report.sides {
            assert!(!f.exact, "{f:?}");
            assert!(f.gap <= 1e-6 && f.angle.to_degrees() <= 0.01, "{f:?}");
        }
        let cad = input.surfaces(&b);
        assert_eq!(cad.len(), 9);
        assert!(cad[1].weights.is_some() && cad[6].weights.is_some());
        assert!(cad[0].weights.is_none() && cad[8].weights.is_none());
        let json = blend_json(&input, &b);
        assert_eq!(json["stand_ins"].as_array().unwrap().len(), 2, "{json}");
        assert!(input.sew_within() >= 4.0 * input.stand_ins[1].unwrap().0);
    }
}
