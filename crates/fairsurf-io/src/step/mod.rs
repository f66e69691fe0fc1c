//! STEP (ISO 10303-21 files, application protocol AP214 `automotive_design`):
//! each patch an ADVANCED_FACE on a B_SPLINE_SURFACE_WITH_KNOTS, the faces
//! an OPEN_SHELL of a SHELL_BASED_SURFACE_MODEL.

use crate::cad::{utc_now, write_cad_text, CadSurface, Real};
use crate::Result;
use fairsurf::{TensorPatch, Vec3};
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

mod curves;
mod entities;
use curves::*;
#[cfg(test)]
mod tests;

/// Writes tensor-product Bézier patches as a STEP AP214 file, atomically:
/// the exact surfaces, for CAD.
///
/// A Bézier patch of degree (n, m) is the B-spline with clamped knots
/// 0ⁿ⁺¹ 1ⁿ⁺¹ × 0ᵐ⁺¹ 1ᵐ⁺¹ and the same control points, so each patch becomes a
/// `B_SPLINE_SURFACE_WITH_KNOTS` (u with the first index i of P_ij, as in
/// [`TensorPatch`]; the file's parameter domain is [0, 1]², the patch's)
/// bounded by its four boundary curves (`B_SPLINE_CURVE_WITH_KNOTS`, the
/// boundary rows and columns of the net) in an `EDGE_LOOP` that runs
/// counter-clockwise in (u, v), so the face normal is R_u × R_v. A boundary
/// collapsed to a point (all its control points equal) has no edge: the
/// loop goes through its vertex. Vertices closer than 1e-9 of the model's
/// size are one; edges with identical control points (in either
/// direction), or between the same vertices and through the same points
/// at nine parameters (within that distance; e.g. a boundary and its
/// degree-elevated or knot-refined copy), are one: patches that meet along
/// a common boundary form one connected (sewn) shell.
///
/// The file holds the AP214 product structure (one `PRODUCT` "fairsurf")
/// and a `MANIFOLD_SURFACE_SHAPE_REPRESENTATION` whose context has
/// millimetres as the length unit and an uncertainty of 1e-7. Reals carry
/// every digit of the `f64`s. Triangular patches (when they exist) are not
/// written here: they go to meshes only.
///
/// Open CASCADE (and so FreeCAD, gmsh, …) reads B-splines of degree ≤ 25
/// only and silently drops a higher one (measured with gmsh 4.15); this
/// writer still writes any degree, the standard has no limit.
///
/// An empty list or a patch of degree 0 in u or v is an
/// [`Error::Export`](crate::Error::Export); nothing is written then.
///
/// ```
/// use fairsurf::TensorPatch;
/// let p = TensorPatch::from_fn(3, 2, |i, j| [i as f64, j as f64, (i * j) as f64 / 6.0]);
/// let dir = std::env::temp_dir().join(format!("fairsurf-doc-step-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let path = dir.join("patch.step");
/// fairsurf_io::write_step(&path, &[p]).unwrap();
/// let text = std::fs::read_to_string(&path).unwrap();
/// assert!(text.contains("B_SPLINE_SURFACE_WITH_KNOTS('',3,2,"));
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write_step(path: &Path, patches: &[TensorPatch]) -> Result<()> {
    let surfaces: Vec<CadSurface> = patches.iter().map(CadSurface::from).collect();
    write_step_surfaces(path, &surfaces)
}

/// Writes B-spline surfaces (a B-spline scene's surface as one face, or
/// Bézier patches) as [`write_step`] does: each one
/// `B_SPLINE_SURFACE_WITH_KNOTS` with its knots and multiplicities, bounded
/// by its four boundary curves (`B_SPLINE_CURVE_WITH_KNOTS` with the same
/// knots).
pub fn write_step_surfaces(path: &Path, surfaces: &[CadSurface]) -> Result<()> {
    write_cad_text(path, surfaces, step_text)
}

/// [`write_step_surfaces`] with vertices and edges closer than `tol` taken
/// as one and shared (at least 1e-9 of the surfaces' size): faces that
/// meet only to a tolerance (a fill along a rational neighbour's
/// polynomial stand-in) are still sewn in the file.
pub fn write_step_sewn(path: &Path, surfaces: &[CadSurface], tol: f64) -> Result<()> {
    write_cad_text(path, surfaces, |name, patches| {
        step_text_within(name, patches, tol)
    })
}

/// The whole file.
pub(crate) fn step_text(file_name: &str, patches: &[CadSurface]) -> String {
    step_text_within(file_name, patches, 0.0)
}

/// The whole file, points closer than `tol` (or 1e-9 of the size) one.
fn step_text_within(file_name: &str, patches: &[CadSurface], tol: f64) -> String {
    let all: Vec<Vec3> = patches
        .iter()
        .flat_map(|p| p.points.iter().copied())
        .collect();
    let mut d = Data {
        tol: (1e-9 * fairsurf::vector::bounding_diagonal(&all)).max(tol),
        ..Data::default()
    };
    let context = d.header_entities();
    // Every surface's corners, each once: a side is split at the corners
    // lying inside it, whichever face comes first in the file.
    let mut seen = std::collections::HashSet::new();
    for p in patches {
        let (cu, cv) = p.counts;
        // A trimmed face's corners are its loops' curves' ends.
        let ends: Vec<Vec3> = p
            .loops
            .iter()
            .flatten()
            .flat_map(|c| [c.points[0], c.points[c.points.len() - 1]])
            .collect();
        let corners =
            [(0, 0), (cu - 1, 0), (0, cv - 1), (cu - 1, cv - 1)].map(|(i, j)| p.point(i, j));
        for c in if p.loops.is_empty() {
            &corners[..]
        } else {
            &ends[..]
        } {
            if seen.insert(bits(*c)) {
                d.corners.push(*c);
            }
        }
    }
    let faces: Vec<usize> = patches.iter().map(|p| d.face(p)).collect();
    let shell = d.add(format_args!("OPEN_SHELL('',({}))", refs(&faces)));
    let model = d.add(format_args!("SHELL_BASED_SURFACE_MODEL('',(#{shell}))"));
    let origin = d.add("CARTESIAN_POINT('',(0.,0.,0.))");
    let z = d.add("DIRECTION('',(0.,0.,1.))");
    let x = d.add("DIRECTION('',(1.,0.,0.))");
    let axes = d.add(format_args!("AXIS2_PLACEMENT_3D('',#{origin},#{z},#{x})"));
    let rep = d.add(format_args!(
        "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('fairsurf',(#{axes},#{model}),#{})",
        context.representation
    ));
    d.add(format_args!(
        "SHAPE_DEFINITION_REPRESENTATION(#{},#{rep})",
        context.shape
    ));
    let [y, mo, day, h, mi, s] = utc_now();
    let version = env!("CARGO_PKG_VERSION");
    let mut out = String::new();
    let _ = write!(
        out,
        "ISO-10303-21;\nHEADER;\n\
         FILE_DESCRIPTION(('fairsurf: B-spline surfaces'),'2;1');\n\
         FILE_NAME('{}','{y:04}-{mo:02}-{day:02}T{h:02}:{mi:02}:{s:02}',(''),(''),\
         'fairsurf {version}','fairsurf {version}','');\n\
         FILE_SCHEMA(('AUTOMOTIVE_DESIGN {{ 1 0 10303 214 1 1 1 1 }}'));\nENDSEC;\nDATA;\n",
        string(file_name)
    );
    out.push_str(&d.text);
    out.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    out
}

/// The entities of the DATA section, numbered from 1 in the order written.
#[derive(Default)]
struct Data {
    text: String,
    next: usize,
    /// VERTEX_POINT of each distinct point (by its bits).
    vertices: HashMap<[u64; 3], usize>,
    /// EDGE_CURVE of each distinct control polygon (by its bits), which runs
    /// from the polygon's first point to its last.
    edges: HashMap<Vec<[u64; 3]>, usize>,
    /// Every vertex: its point and VERTEX_POINT.
    vertex_points: Vec<(Vec3, usize)>,
    /// Every edge: points at nine parameters (first to last), its
    /// EDGE_CURVE and its curve.
    edge_samples: Vec<WrittenEdge>,
    /// Points closer than this are one.
    tol: f64,
    /// Every surface's corner points (a VERTEX_POINT is made for one when
    /// a side is split there before its own face is written).
    corners: Vec<Vec3>,
}

/// Points compared per edge when matching edges by their geometry.
const EDGE_SAMPLES: usize = 9;

/// An edge written: its samples ([`SideCurve::samples`]), EDGE_CURVE,
/// and curve (knots, control points, weights), on which another curve's
/// points are found by projection.
struct WrittenEdge {
    samples: [Vec3; EDGE_SAMPLES],
    edge: usize,
    knots: fairsurf::bspline::KnotVector,
    points: Vec<Vec3>,
    weights: Option<Vec<f64>>,
}

/// A side of a face as a curve: degree, distinct knots and
/// multiplicities, the full knot vector, and the side's weights when the
/// face is rational.
struct SideCurve<'a> {
    d: usize,
    knots: &'a Vec<f64>,
    mults: &'a Vec<usize>,
    full: &'a Vec<f64>,
    weights: Option<Vec<f64>>,
}

impl SideCurve<'_> {
    /// The curve through control points `pts` at `EDGE_SAMPLES` parameters
    /// spread evenly over its domain.
    fn samples(&self, pts: &[Vec3]) -> Option<[Vec3; EDGE_SAMPLES]> {
        let kv = fairsurf::bspline::KnotVector::new(self.d, self.full.to_vec()).ok()?;
        let (a, b) = kv.domain();
        let w = self.weights.as_deref();
        Some(std::array::from_fn(|s| {
            curve_point(
                &kv,
                pts,
                w,
                a + (b - a) * s as f64 / (EDGE_SAMPLES - 1) as f64,
            )
        }))
    }

    /// The curve entity on CARTESIAN_POINTs `ids`.
    fn entity(&self, ids: &[usize]) -> String {
        let d = self.d;
        match &self.weights {
            None => format!(
                "B_SPLINE_CURVE_WITH_KNOTS('',{d},({}),.UNSPECIFIED.,.F.,.F.,({}),({}),\
                 .UNSPECIFIED.)",
                refs(ids),
                ints(self.mults),
                reals(self.knots)
            ),
            Some(w) => format!(
                "(BOUNDED_CURVE() B_SPLINE_CURVE({d},({}),.UNSPECIFIED.,.F.,.F.) \
                 B_SPLINE_CURVE_WITH_KNOTS(({}),({}),.UNSPECIFIED.) CURVE() \
                 GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_CURVE(({})) \
                 REPRESENTATION_ITEM(''))",
                refs(ids),
                ints(self.mults),
                reals(self.knots),
                reals(w)
            ),
        }
    }

    /// The key of the curve on control points `pts`: points, knots
    /// (relative to the first), multiplicities and weights; `reversed`: of
    /// the same curve run backwards.
    fn key(&self, pts: &[Vec3], reversed: bool) -> Vec<[u64; 3]> {
        let (knots, mults) = (self.knots, self.mults);
        let (a, b) = (knots[0], knots[knots.len() - 1]);
        let ones = vec![1.0; pts.len()];
        let w = self.weights.as_deref().unwrap_or(&ones);
        let mut key: Vec<[u64; 3]>;
        if reversed {
            key = pts.iter().rev().map(|&p| bits(p)).collect();
            key.extend(knots.iter().rev().map(|&t| bits([b - t, 0.0, 0.0])));
            key.extend(mults.iter().rev().map(|&k| [k as u64, 0, 0]));
            key.extend(w.iter().rev().map(|&x| bits([x, 0.0, 0.0])));
        } else {
            key = pts.iter().map(|&p| bits(p)).collect();
            key.extend(knots.iter().map(|&t| bits([t - a, 0.0, 0.0])));
            key.extend(mults.iter().map(|&k| [k as u64, 0, 0]));
            key.extend(w.iter().map(|&x| bits([x, 0.0, 0.0])));
        }
        key
    }
}

/// The entities the geometry refers to.
struct Context {
    /// The GEOMETRIC_REPRESENTATION_CONTEXT (with units and uncertainty).
    representation: usize,
    /// The PRODUCT_DEFINITION_SHAPE.
    shape: usize,
}

fn bits(p: Vec3) -> [u64; 3] {
    // +0.0 and −0.0 are the same point.
    p.map(|c| (c + 0.0).to_bits())
}

/// `#1,#2,…`.
fn refs(ids: &[usize]) -> List<'_, usize> {
    List(ids, |f, k| write!(f, "#{k}"))
}

/// A STEP string literal: `'` doubled, `\` doubled, anything outside
/// printable ASCII replaced by `_` (no \X2\ encoding needed for a label).
fn string(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            '\'' => "''".to_string(),
            '\\' => "\\\\".to_string(),
            ' '..='~' => c.to_string(),
            _ => "_".to_string(),
        })
        .collect()
}

/// `1,2,…`.
fn ints(v: &[usize]) -> List<'_, usize> {
    List(v, |f, k| write!(f, "{k}"))
}

/// Reals as [`real`] writes them, comma-separated.
fn reals(v: &[f64]) -> List<'_, f64> {
    List(v, |f, x| write!(f, "{}", Real(*x)))
}

/// `(x,y,z)`.
fn coords(p: Vec3) -> impl std::fmt::Display {
    struct Coords(Vec3);
    impl std::fmt::Display for Coords {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            let [x, y, z] = self.0.map(Real);
            write!(f, "({x},{y},{z})")
        }
    }
    Coords(p)
}

/// Items written one by one, comma-separated, into the text that formats
/// this (the writer makes no string per number or reference).
struct List<'a, T>(
    &'a [T],
    fn(&mut std::fmt::Formatter<'_>, &T) -> std::fmt::Result,
);

impl<T> std::fmt::Display for List<'_, T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (k, x) in self.0.iter().enumerate() {
            if k > 0 {
                f.write_str(",")?;
            }
            (self.1)(f, x)?;
        }
        Ok(())
    }
}
