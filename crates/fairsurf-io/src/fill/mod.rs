//! Fill scenes and fill jobs ([`fairsurf::fill`]): the neighbour faces from
//! a JSON fill scene or a STEP file, their holes, which to fill, the fills,
//! the sewn STEP output (the input faces and the fills, sharing the hole's
//! edges) and the report.
//!
//! Field docs here become the descriptions in `fairsurf schema --type fill`.

use crate::step_read::{FaceSurface, TrimEdge};
use crate::tensor_scene::Net;
use crate::validate::parse_net;
use crate::{CadCurve, CadSurface, Error, Result};
use fairsurf::analysis::Edge;
use fairsurf::bspline::{
    edge_stand_in, strip_stand_in, strip_stand_in_towards, BSplineSurface, FitTolerance,
    KnotVector, RationalSurface,
};
use fairsurf::fill::{
    find_holes_where, tolerance, CornerMismatch, FanFill, Fill, FillOptions, FillSeconds, Hole,
    HoleFill, SideFit, TotalCurvature,
};
use fairsurf::Vec3;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};
use std::path::Path;
use std::sync::Arc;

mod report;
pub use report::*;
#[cfg(test)]
mod tests;

/// A fill scene: the faces around one or more holes, which holes to fill,
/// and how.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FillScene {
    /// Free text: a title.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Free text: what the scene shows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The faces: Bézier patches or B-spline surfaces, every control point
    /// given. Holes are the closed loops of boundaries no other face
    /// shares.
    pub faces: Vec<FaceSpec>,
    /// Which holes to fill, by their index in `fairsurf fill --list`
    /// (longest loop first). Default: every hole but the outer rims (the
    /// loops that bound their faces from outside, one per open sheet — a
    /// closed shell has none — and, beside other loops, those whose sense
    /// is unclear, as a pipe's ends); none left is an error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub holes: Option<Vec<usize>>,
    /// How to fill.
    #[serde(default)]
    pub fill: FillSpec,
}

/// `"tensor"` (a Bézier patch) or `"bspline"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum FaceKind {
    /// A tensor-product Bézier patch.
    Tensor,
    /// A tensor-product B-spline surface.
    Bspline,
}

/// One face.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FaceSpec {
    /// `"tensor"` or `"bspline"`.
    #[serde(rename = "type")]
    pub kind: FaceKind,
    /// `[p, q]`: degree in u and in v, 1 to 25.
    pub degree: [usize; 2],
    /// `[U, V]`: full clamped knot vectors (B-spline faces only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub knots: Option<[Vec<f64>; 2]>,
    /// Rows (one per u index) of points `[x, y, z]`.
    pub control_points: Net,
}

/// How to fill; every field optional ([`FillOptions::default`]).
#[derive(Clone, Debug, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FillSpec {
    /// Degrees the fill gets above its sides' largest (default 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elevate: Option<usize>,
    /// At least this many control points per direction (default 8, at
    /// least 5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_points: Option<usize>,
    /// Membrane weight (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stretch: Option<f64>,
    /// Thin-plate weight (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bend: Option<f64>,
    /// λ of the normal field from the boundary data, per unit area, that
    /// guides the thin plate (0: the plain thin plate). Not given: 100, used
    /// only when `descent_steps` is 0 (the descent on W reaches the same W
    /// from the plain thin plate, faster); given: used either way.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_weight: Option<f64>,
    /// Normal samples per control point and direction (default 3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<usize>,
    /// Linearized Willmore steps after the solve, each kept only if it
    /// lowers W (default 0: the descent alone reaches the same W; 0 to 50).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub willmore_steps: Option<usize>,
    /// Then at most this many steps lowering W itself (L-BFGS), stopping
    /// after three in a row that each gain less than 1e-8 of W (1e-6 for
    /// triangular patches; default 200; 0 to 10000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub descent_steps: Option<usize>,
}

/// The largest degree of a face (Open CASCADE reads up to 25).
const MAX_FACE_DEGREE: usize = 25;
/// The largest fill degree asked through `elevate`.
const MAX_ELEVATE: usize = 10;

impl FillSpec {
    /// The options; errors name `fill.<field>`.
    pub fn options(&self) -> Result<FillOptions> {
        let d = FillOptions::default();
        let weight = |name: &str, w: Option<f64>, default: f64| -> Result<f64> {
            let w = w.unwrap_or(default);
            crate::validate::check_weight(&format!("fill.{name}"), w)?;
            Ok(w)
        };
        let elevate = self.elevate.unwrap_or(d.elevate);
        if elevate > MAX_ELEVATE {
            return Err(Error::scene(
                "fill.elevate",
                format!("expected 0 to {MAX_ELEVATE}, got {elevate}"),
            ));
        }
        let min_points = self.min_points.unwrap_or(d.min_points);
        if !(5..=64).contains(&min_points) {
            return Err(Error::scene(
                "fill.min_points",
                format!("expected 5 to 64, got {min_points}"),
            ));
        }
        let willmore_steps = self.willmore_steps.unwrap_or(d.willmore_steps);
        if willmore_steps > 50 {
            return Err(Error::scene(
                "fill.willmore_steps",
                format!("expected 0 to 50, got {willmore_steps}"),
            ));
        }
        let descent_steps = self.descent_steps.unwrap_or(d.descent_steps);
        if descent_steps > 10_000 {
            return Err(Error::scene(
                "fill.descent_steps",
                format!("expected 0 to 10000, got {descent_steps}"),
            ));
        }
        let samples = self.samples.unwrap_or(d.samples);
        if !(1..=16).contains(&samples) {
            return Err(Error::scene(
                "fill.samples",
                format!("expected 1 to 16, got {samples}"),
            ));
        }
        let options = FillOptions {
            elevate,
            min_points,
            stretch: weight("stretch", self.stretch, d.stretch)?,
            bend: weight("bend", self.bend, d.bend)?,
            normal_weight: weight("normal_weight", self.normal_weight, d.normal_weight)?,
            // A λ the scene gives guides the solve before the descent too.
            guide_with_descent: self.normal_weight.is_some(),
            samples,
            willmore_steps,
            descent_steps,
            angle_tolerance: d.angle_tolerance,
            rational_faces: Vec::new(),
            edge_faces: Vec::new(),
        };
        if options.stretch == 0.0 && options.bend == 0.0 {
            return Err(Error::scene(
                "fill",
                "stretch and bend are both 0: the fill needs a membrane or thin-plate energy",
            ));
        }
        Ok(options)
    }
}

impl FillScene {
    /// Parses a fill scene; errors name the JSON path.
    pub fn from_json(text: &str) -> Result<FillScene> {
        crate::scene::parse_with_path(text)
    }

    /// The JSON Schema of fill scenes.
    pub fn json_schema() -> Value {
        serde_json::to_value(schemars::schema_for!(FillScene)).expect("a schema serializes")
    }

    /// The faces as B-spline surfaces; errors name `faces[k].…`.
    pub fn faces(&self) -> Result<Vec<BSplineSurface>> {
        if self.faces.is_empty() {
            return Err(Error::scene("faces", "no faces: a hole needs neighbours"));
        }
        self.faces
            .iter()
            .enumerate()
            .map(|(k, f)| f.surface(&format!("faces[{k}]")))
            .collect()
    }
}

impl FaceSpec {
    /// The face; errors name `{path}.degree`, `.knots` or `.control_points`.
    pub fn surface(&self, path: &str) -> Result<BSplineSurface> {
        for (k, &d) in self.degree.iter().enumerate() {
            if !(1..=MAX_FACE_DEGREE).contains(&d) {
                return Err(Error::scene(
                    format!("{path}.degree[{k}]"),
                    format!("must be 1 to {MAX_FACE_DEGREE}, got {d}"),
                ));
            }
        }
        let (u, v) = match (self.kind, &self.knots) {
            (FaceKind::Tensor, None) => (
                KnotVector::bezier(self.degree[0]),
                KnotVector::bezier(self.degree[1]),
            ),
            (FaceKind::Tensor, Some(_)) => {
                return Err(Error::scene(
                    format!("{path}.knots"),
                    "a tensor (Bézier) face has no knots: use \"type\": \"bspline\"",
                ))
            }
            (FaceKind::Bspline, None) => {
                return Err(Error::scene(
                    format!("{path}.knots"),
                    "a bspline face needs its knot vectors [U, V]",
                ))
            }
            (FaceKind::Bspline, Some(k)) => {
                let one = |i: usize| {
                    KnotVector::new(self.degree[i], k[i].clone())
                        .map_err(|e| Error::scene(format!("{path}.knots[{i}]"), e.to_string()))
                };
                (one(0)?, one(1)?)
            }
        };
        let (cu, cv) = (u.count(), v.count());
        let net = parse_net(
            &self.control_points,
            &format!("{path}.control_points"),
            (cu - 1, cv - 1),
            false,
        )?;
        let points: Vec<Vec3> = net.into_iter().map(|p| p.expect("no null")).collect();
        Ok(BSplineSurface::new(u, v, points)?)
    }
}

/// The faces to fill between, from a file: a JSON fill scene, or a STEP
/// file (`.step`, `.stp`).
///
/// A trimmed face of a STEP file (bounded otherwise than by four sides of
/// its surface, or with holes) is met through strip stand-ins along its
/// loops' free edges ([`fairsurf::bspline::strip_stand_in`]; an edge
/// another face shares, which no fill meets, by its curve alone:
/// [`fairsurf::bspline::edge_stand_in`]): they follow the file's faces in
/// `faces` ([`Self::strips`]), and only their sides V0 are edges of the
/// model ([`Self::is_boundary`]).
#[derive(Clone, Debug)]
pub struct FillInput {
    /// The faces as polynomial B-splines: a rational face (a cylinder, …)
    /// by its polynomial stand-in (see `stand_ins`), a trimmed one by its
    /// surface (no boundary of it is an edge of the model); then the
    /// strips along the trimmed faces' edges ([`Self::strips`]).
    pub faces: Vec<BSplineSurface>,
    /// What each face is in the file ("B-spline", "plane", "cylinder", …).
    pub kinds: Vec<&'static str>,
    /// Per face, for a rational one: how far its stand-in is from it along
    /// its sides (position, angle in radians).
    pub stand_ins: Vec<Option<(f64, f64)>>,
    /// The holes the scene chose, if it did.
    pub holes: Option<Vec<usize>>,
    /// The scene's fill options (the defaults for STEP), with the rational
    /// faces the stand-ins approximate (`rational_faces`).
    pub options: FillOptions,
    /// The tolerance the stand-ins were fitted within ([`Self::fit`]).
    fit: FitTolerance,
    /// Per face, the directions its stand-in is one span in
    /// ([`Self::one_span_sides`]); a refit keeps them.
    one_span: Vec<[bool; 2]>,
    /// Per face of the file, a trimmed one's surface and loops.
    trimmed: Vec<Option<(FaceSurface, Vec<Vec<TrimEdge>>)>>,
    /// The strips, in the order they follow the file's faces in `faces`.
    strips: Vec<StripOf>,
    /// Per strip, whether it is one span along its edge
    /// ([`Self::one_span_sides`]); a refit keeps them.
    strip_one_span: Vec<bool>,
}

/// A strip stand-in along an edge of a trimmed face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StripOf {
    /// The trimmed face (its index in the file's faces).
    pub face: usize,
    /// Its loop (0: the first the file lists).
    pub loop_index: usize,
    /// The edge in the loop.
    pub edge: usize,
}

impl FillInput {
    /// Reads `path`: STEP by its extension (`.step`, `.stp`, any case),
    /// else a JSON fill scene.
    pub fn read(path: &Path) -> Result<FillInput> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_text(&text, matches!(ext.as_deref(), Some("step" | "stp")))
    }

    /// From a STEP file's text (`step`) or a JSON fill scene's; rational
    /// faces get stand-ins within the default [`FitTolerance`].
    pub fn from_text(text: &str, step: bool) -> Result<FillInput> {
        if step {
            let read = crate::step_read::read_step(text)?;
            let mut input = FillInput {
                faces: Vec::with_capacity(read.len()),
                kinds: read.iter().map(|f| f.kind).collect(),
                stand_ins: vec![None; read.len()],
                holes: None,
                options: FillOptions::default(),
                fit: FitTolerance::default(),
                one_span: vec![[false; 2]; read.len()],
                trimmed: Vec::with_capacity(read.len()),
                strips: Vec::new(),
                strip_one_span: Vec::new(),
            };
            for f in read {
                if !f.loops.is_empty() {
                    // Only its strips meet fills (built below).
                    input.faces.push(f.surface.net().clone());
                    input.options.rational_faces.push(None);
                    input.trimmed.push(Some((f.surface, f.loops)));
                    continue;
                }
                input.trimmed.push(None);
                match f.surface {
                    FaceSurface::Polynomial(s) => {
                        input.faces.push(s);
                        input.options.rational_faces.push(None);
                    }
                    FaceSurface::Rational(r) => {
                        // Refitted below.
                        input.faces.push(r.net().clone());
                        input.options.rational_faces.push(Some(Arc::new(r)));
                    }
                }
            }
            input.refit(FitTolerance::default())?;
            return Ok(input);
        }
        let scene = FillScene::from_json(text)?;
        let faces = scene.faces()?;
        let count = faces.len();
        Ok(FillInput {
            kinds: vec!["B-spline"; faces.len()],
            stand_ins: vec![None; faces.len()],
            faces,
            holes: scene.holes.clone(),
            options: scene.fill.options()?,
            fit: FitTolerance::default(),
            one_span: vec![[false; 2]; count],
            trimmed: vec![None; count],
            strips: Vec::new(),
            strip_one_span: Vec::new(),
        })
    }

    /// The tolerance the rational faces' stand-ins are fitted within.
    pub fn fit(&self) -> FitTolerance {
        self.fit
    }

    /// Fits the rational faces' stand-ins anew within `fit` (those made
    /// one span by [`Self::one_span_sides`] stay so); the fill's choice
    /// between candidates takes `fit.angle` too
    /// ([`FillOptions::angle_tolerance`]).
    pub fn refit(&mut self, fit: FitTolerance) -> Result<()> {
        self.fit = fit;
        self.options.angle_tolerance = fit.angle;
        for (k, r) in self.options.rational_faces.iter().enumerate() {
            if let Some(r) = r {
                let s = stand_in(r, fit, self.one_span[k], k, self.kinds[k])?;
                self.stand_ins[k] = Some((s.position, s.angle));
                self.faces[k] = s.surface;
            }
        }
        self.build_strips()
    }

    /// The number of the file's faces (the strips follow them in
    /// `faces`).
    pub fn file_faces(&self) -> usize {
        self.trimmed.len()
    }

    /// The strips along the trimmed faces' edges, in the order they follow
    /// the file's faces in `faces`.
    pub fn strips(&self) -> &[StripOf] {
        &self.strips
    }

    /// The file's face that face `k` of `faces` is (a strip's: its
    /// trimmed face).
    pub fn face_of(&self, k: usize) -> usize {
        match k.checked_sub(self.file_faces()) {
            Some(s) => self.strips[s].face,
            None => k,
        }
    }

    /// Whether boundary `edge` of face `k` is an edge of the model: every
    /// side of a four-sided face, none of a trimmed face's surface, a
    /// strip's side V0.
    pub fn is_boundary(&self, k: usize, edge: Edge) -> bool {
        match k.checked_sub(self.file_faces()) {
            Some(_) => edge == Edge::V0,
            None => self.trimmed.get(k).is_none_or(Option::is_none),
        }
    }

    /// (Re)builds the strips along every trimmed face's edges within
    /// [`Self::fit`]: each `strip_stand_in_towards` its edge's ends where
    /// the reader found them (else, or where that fails, across the edge
    /// at right angles, a quarter of the edge's length wide), one span
    /// along a fan's side ([`Self::one_span_sides`]); an edge another face
    /// shares by its curve alone (`edge_stand_in`, kind "edge curve": a
    /// strip of the reader's filled dome, its seam edge into the pole,
    /// took 0.35 s to fail at 512 pieces). Errors name the
    /// face, loop and edge; the input then has no strips (its trimmed
    /// faces no model edges), consistently.
    fn build_strips(&mut self) -> Result<()> {
        let built = self.try_build_strips();
        if built.is_err() {
            self.drop_strips();
        }
        built
    }

    /// The input without strips: its per-face lists cut back to the
    /// file's faces.
    fn drop_strips(&mut self) {
        let n = self.file_faces();
        self.faces.truncate(n);
        self.kinds.truncate(n);
        self.stand_ins.truncate(n);
        self.one_span.truncate(n);
        self.options.rational_faces.truncate(n);
        self.options.edge_faces.clear();
        self.strips.clear();
    }

    fn try_build_strips(&mut self) -> Result<()> {
        self.drop_strips();
        let n = self.file_faces();
        let mut edges: Vec<Option<fairsurf::bspline::TrueEdge>> = vec![None; n];
        for (k, t) in self.trimmed.iter().enumerate() {
            let Some((_, loops)) = t else { continue };
            for (l, edges_) in loops.iter().enumerate() {
                for (j, e) in edges_.iter().enumerate() {
                    let one_span = self.strip_one_span.get(self.strips.len()) == Some(&true);
                    let named = |err: fairsurf::Error| {
                        let fan = if one_span {
                            " (the edge is a side of a hole a fan of triangular patches \
                             fills, whose sides must each be one polynomial piece; a \
                             looser tolerance may let one span do)"
                        } else {
                            ""
                        };
                        Error::scene(
                            format!("face {k}"),
                            format!("a {}: loop {l}, edge {j}: {err}{fan}", self.kinds[k]),
                        )
                    };
                    // No fill meets an edge another face shares: its
                    // curve alone stands in (the face may have no normal
                    // along it: a seam edge into a pole).
                    let (s, kind) = if e.free {
                        let towards = e.ends.and_then(|ends| {
                            strip_stand_in_towards(&e.edge, ends, self.fit, one_span).ok()
                        });
                        let s = match towards {
                            Some(s) => s,
                            None => strip_stand_in(&e.edge, 0.25 * e.length, self.fit, one_span)
                                .map_err(named)?,
                        };
                        (s, "strip")
                    } else {
                        (
                            edge_stand_in(&e.edge, self.fit).map_err(named)?,
                            "edge curve",
                        )
                    };
                    self.faces.push(s.surface);
                    self.kinds.push(kind);
                    self.stand_ins.push(Some((s.position, s.angle)));
                    self.one_span.push([false; 2]);
                    self.options.rational_faces.push(None);
                    edges.push(Some(e.edge.clone()));
                    self.strips.push(StripOf {
                        face: k,
                        loop_index: l,
                        edge: j,
                    });
                }
            }
        }
        self.options.edge_faces = if self.strips.is_empty() {
            Vec::new()
        } else {
            edges
        };
        Ok(())
    }

    /// The file's faces followed by the fills (a fan as its patches), for
    /// the STEP writer: a rational face as that, a trimmed one as its
    /// surface bounded by its loops, each edge the side V0 of its strip
    /// (within [`Self::fit`] of the edge; the fills along it share it).
    pub fn surfaces(&self, fills: &[HoleFill]) -> Vec<CadSurface> {
        let n = self.file_faces();
        let mut out = fill_surfaces(&self.faces[..n], &self.options.rational_faces, fills);
        for (k, t) in self.trimmed.iter().enumerate() {
            let Some((surface, loops)) = t else { continue };
            let mut cad = match surface {
                FaceSurface::Polynomial(p) => CadSurface::from(p),
                FaceSurface::Rational(r) => CadSurface::from(r),
            };
            cad.loops = loops
                .iter()
                .enumerate()
                .map(|(l, edges)| {
                    (0..edges.len())
                        .map(|j| {
                            let s = self
                                .strips
                                .iter()
                                .position(|s| {
                                    *s == StripOf {
                                        face: k,
                                        loop_index: l,
                                        edge: j,
                                    }
                                })
                                .expect("a strip per edge");
                            let strip = &self.faces[n + s];
                            let (cu, _) = strip.counts();
                            CadCurve {
                                degree: strip.degree().0,
                                knots: strip.knots().0.knots().to_vec(),
                                points: (0..cu).map(|i| strip.point(i, 0)).collect(),
                            }
                        })
                        .collect()
                })
                .collect();
            out[k] = cad;
        }
        out
    }

    /// The holes to fill ([`HoleChoice::of`]: `asked`, else the input's
    /// own choice, else every hole but the outer rims), with the
    /// stand-ins along the sides of those that fans fill made one span
    /// each ([`Self::one_span_sides`]): what [`HoleChoice::fill`] takes.
    pub fn choose(&mut self, asked: Option<&[usize]>) -> Result<HoleChoice> {
        let asked = asked.map(<[usize]>::to_vec).or_else(|| self.holes.clone());
        let choice = HoleChoice::of(self, asked.as_deref())?;
        self.one_span_sides(&choice)?;
        Ok(choice)
    }

    /// Refits, as one polynomial span along the side, the stand-in of each
    /// rational face that is a side of a chosen hole filled by triangular
    /// patches (other than four sides: each side must be one polynomial
    /// piece) and is several spans along it
    /// ([`RationalSurface::polynomial_spans`], within [`Self::fit`]): the
    /// corner of a box rounded by three cylinder fillets. The holes keep
    /// their sides (the same faces, edges and parameters; a stand-in goes
    /// through its face's corners). Returns the faces refitted (a face
    /// whose weights do not vary along the side keeps its own knots there:
    /// it is exact, and not refitted). Errors name the face.
    pub fn one_span_sides(&mut self, choice: &HoleChoice) -> Result<Vec<usize>> {
        let mut one_span: Vec<[bool; 2]> = vec![[false; 2]; self.faces.len()];
        let mut strips: Vec<usize> = Vec::new();
        for &h in &choice.chosen {
            let hole = &choice.holes[h];
            if fairsurf::fill::is_four_sided(&self.faces, hole) {
                continue;
            }
            for side in &hole.sides {
                let k = side.face;
                if let Some(s) = k.checked_sub(self.file_faces()) {
                    strips.push(s);
                    continue;
                }
                if self.options.rational(k).is_none() {
                    continue;
                }
                // Edge U0 / U1 runs along v, V0 / V1 along u.
                let along_v = matches!(side.edge, Edge::U0 | Edge::U1);
                let knots = self.faces[k].knots();
                let along = if along_v { knots.1 } else { knots.0 };
                if along.spans().len() > 1 {
                    one_span[k][usize::from(along_v)] = true;
                }
            }
        }
        let mut refitted = Vec::new();
        // Strips along fans' sides, one span each (their indices in
        // `faces` stay).
        let n = self.file_faces();
        self.strip_one_span.resize(self.strips.len(), false);
        let more: Vec<usize> = strips
            .into_iter()
            .filter(|&s| !self.strip_one_span[s])
            .collect();
        if !more.is_empty() {
            for &s in &more {
                self.strip_one_span[s] = true;
            }
            let before: Vec<BSplineSurface> =
                more.iter().map(|&s| self.faces[n + s].clone()).collect();
            self.build_strips()?;
            for (s, b) in more.into_iter().zip(before) {
                if self.faces[n + s] != b && !refitted.contains(&(n + s)) {
                    refitted.push(n + s);
                }
            }
        }
        for (k, flags) in one_span.into_iter().enumerate().take(n) {
            let flags = [
                flags[0] || self.one_span[k][0],
                flags[1] || self.one_span[k][1],
            ];
            if flags == self.one_span[k] {
                continue;
            }
            let r = self.options.rational(k).expect("a rational face");
            let s = stand_in(r, self.fit, flags, k, self.kinds[k])?;
            self.one_span[k] = flags;
            if s.surface != self.faces[k] {
                self.stand_ins[k] = Some((s.position, s.angle));
                self.faces[k] = s.surface;
                refitted.push(k);
            }
        }
        Ok(refitted)
    }

    /// The distance under which boundary points are one when finding
    /// holes: [`tolerance`], or four times the largest stand-in's distance
    /// from its face when that is larger (two stand-ins of one edge may
    /// differ by twice that).
    pub fn hole_tolerance(&self) -> f64 {
        // Two faces' edges meet at a vertex the file wrote off their
        // curves: within twice its offset of each other, and some.
        let file = self
            .trimmed
            .iter()
            .flatten()
            .flat_map(|(_, loops)| loops.iter().flatten())
            .map(|e| e.vertex_off)
            .fold(0.0, f64::max);
        sew_tolerance(&self.faces, &self.stand_ins).max(2.5 * file)
    }

    /// The faces to picture and mesh: the file's, but trimmed ones (their
    /// surfaces run beyond their loops).
    pub fn pictured_faces(&self) -> Vec<&BSplineSurface> {
        (0..self.file_faces())
            .filter(|&k| self.trimmed[k].is_none())
            .map(|k| &self.faces[k])
            .collect()
    }

    /// The rational faces and their stand-ins, as JSON: face, kind, and the
    /// stand-in's largest gap and angle along the face's sides.
    /// A strip's entry also names its trimmed face, loop and edge
    /// (`"of_face"`, `"loop"`, `"edge"`) and how far the file's edge is
    /// from the face's surface (`"edge_off_surface"`: the strip follows
    /// the edge).
    pub fn stand_ins_json(&self) -> Value {
        let mut out = stand_ins_json(&self.kinds, &self.stand_ins);
        let n = self.file_faces();
        for entry in out.as_array_mut().into_iter().flatten() {
            let k = entry["face"].as_u64().unwrap_or(0) as usize;
            if let Some(s) = k.checked_sub(n).and_then(|s| self.strips.get(s)) {
                entry["of_face"] = json!(s.face);
                entry["loop"] = json!(s.loop_index);
                entry["edge"] = json!(s.edge);
                if let Some((_, loops)) = &self.trimmed[s.face] {
                    entry["edge_off_surface"] = json!(loops[s.loop_index][s.edge].off_surface);
                }
            }
        }
        out
    }

    /// `e` with every "face K" of a strip (K ≥ [`Self::file_faces`]) in a
    /// fill's refusal named as the file's: "face F (loop L, edge E)" — the
    /// library numbers faces as [`Self::faces`](FillInput::faces) does.
    pub fn name_faces(&self, e: Error) -> Error {
        match e {
            Error::Solve(fairsurf::Error::Fill { why }) if !self.strips.is_empty() => {
                Error::Solve(fairsurf::Error::Fill {
                    why: self.named(&why),
                })
            }
            e => e,
        }
    }

    /// `text` with "face K" of a strip named as the file's face.
    fn named(&self, text: &str) -> String {
        let mut out = String::with_capacity(text.len());
        let mut rest = text;
        while let Some(i) = rest.find("face ") {
            let (head, tail) = rest.split_at(i + 5);
            out.push_str(head);
            let digits = tail.bytes().take_while(u8::is_ascii_digit).count();
            let strip = tail[..digits]
                .parse::<usize>()
                .ok()
                .and_then(|k| k.checked_sub(self.file_faces()))
                .and_then(|s| self.strips.get(s));
            match strip {
                Some(s) => out.push_str(&format!(
                    "{} (loop {}, edge {})",
                    s.face, s.loop_index, s.edge
                )),
                None => out.push_str(&tail[..digits]),
            }
            rest = &tail[digits..];
        }
        out.push_str(rest);
        out
    }

    /// The `--list` table ([`HoleChoice::list_json`]) with each hole's
    /// faces the file's (a strip's: its trimmed face).
    pub fn list_json(&self, choice: &HoleChoice) -> Value {
        let mut out = choice.list_json();
        for hole in out.as_array_mut().into_iter().flatten() {
            let mut faces: Vec<usize> = Vec::new();
            for f in hole["faces"].as_array().into_iter().flatten() {
                let k = self.face_of(f.as_u64().unwrap_or(0) as usize);
                if !faces.contains(&k) {
                    faces.push(k);
                }
            }
            hole["faces"] = json!(faces);
        }
        out
    }

    /// [`fill_report_json`] of fills of this input (`faces`: the file's),
    /// a side along a strip naming the trimmed face (`"face"`), its loop
    /// and edge (`"edge"`: "loop L edge E") and the strip (`"strip"`: its
    /// index in [`Self::faces`](FillInput::faces), as `stand_ins` lists
    /// it); a hole's faces are the file's.
    pub fn report_json(
        &self,
        choice: &HoleChoice,
        fills: &[HoleFill],
        tolerance: FitTolerance,
    ) -> Value {
        let mut out = fill_report_json(self.file_faces(), choice, fills, tolerance);
        let n = self.file_faces();
        out["holes"] = self.list_json(choice);
        for fill in out["fills"].as_array_mut().into_iter().flatten() {
            for side in fill["sides"].as_array_mut().into_iter().flatten() {
                let k = side["face"].as_u64().unwrap_or(0) as usize;
                if let Some(s) = k.checked_sub(n).and_then(|s| self.strips.get(s)) {
                    side["face"] = json!(s.face);
                    side["edge"] = json!(format!("loop {} edge {}", s.loop_index, s.edge));
                    side["strip"] = json!(k);
                }
            }
        }
        out
    }
}

/// A rational face's stand-in within `fit` (one span in u and/or v as
/// `one_span` says); errors name face `k` and its kind.
pub(crate) fn stand_in(
    r: &RationalSurface,
    fit: FitTolerance,
    one_span: [bool; 2],
    k: usize,
    kind: &str,
) -> Result<fairsurf::bspline::StandIn> {
    r.polynomial_spans(fit, one_span)
        .map_err(|e| Error::scene(format!("face {k}"), format!("a {kind}: {e}")))
}

/// [`tolerance`] of `faces`, or four times the largest stand-in's
/// distance from its face when that is larger (two stand-ins of one edge
/// may differ by twice that): under it, points are one when finding holes
/// and sharing edges in the STEP file.
pub(crate) fn sew_tolerance(faces: &[BSplineSurface], stand_ins: &[Option<(f64, f64)>]) -> f64 {
    let fit = stand_ins.iter().flatten().map(|s| s.0).fold(0.0, f64::max);
    tolerance(faces).max(4.0 * fit)
}

/// The rational faces and their stand-ins, as JSON: face, kind, and the
/// stand-in's largest gap and angle along the face's sides.
pub(crate) fn stand_ins_json(kinds: &[&str], stand_ins: &[Option<(f64, f64)>]) -> Value {
    Value::Array(
        stand_ins
            .iter()
            .enumerate()
            .filter_map(|(k, s)| {
                s.map(|(gap, angle)| {
                    json!({
                        "face": k,
                        "kind": kinds[k],
                        "gap": gap,
                        "angle_deg": angle.to_degrees(),
                    })
                })
            })
            .collect(),
    )
}
