//! STEP (ISO 10303-21 files, application protocol AP214 `automotive_design`):
//! each patch an ADVANCED_FACE on a B_SPLINE_SURFACE_WITH_KNOTS, the faces
//! an OPEN_SHELL of a SHELL_BASED_SURFACE_MODEL.

use crate::cad::{real, utc_now, write_cad_text, CadSurface};
use crate::Result;
use fairsurf::{TensorPatch, Vec3};
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

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
        for (i, j) in [(0, 0), (cu - 1, 0), (0, cv - 1), (cu - 1, cv - 1)] {
            let c = p.point(i, j);
            if seen.insert(bits(c)) {
                d.corners.push(c);
            }
        }
    }
    let faces: Vec<usize> = patches.iter().map(|p| d.face(p)).collect();
    let shell = d.add(format!("OPEN_SHELL('',({}))", refs(&faces)));
    let model = d.add(format!("SHELL_BASED_SURFACE_MODEL('',(#{shell}))"));
    let origin = d.add("CARTESIAN_POINT('',(0.,0.,0.))".into());
    let z = d.add("DIRECTION('',(0.,0.,1.))".into());
    let x = d.add("DIRECTION('',(1.,0.,0.))".into());
    let axes = d.add(format!("AXIS2_PLACEMENT_3D('',#{origin},#{z},#{x})"));
    let rep = d.add(format!(
        "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('fairsurf',(#{axes},#{model}),#{})",
        context.representation
    ));
    d.add(format!(
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
    /// Every edge: points at nine parameters (first to last) and its
    /// EDGE_CURVE.
    edge_samples: Vec<([Vec3; EDGE_SAMPLES], usize)>,
    /// Points closer than this are one.
    tol: f64,
    /// Every surface's corner points (a VERTEX_POINT is made for one when
    /// a side is split there before its own face is written).
    corners: Vec<Vec3>,
}

/// Points compared per edge when matching edges by their geometry.
const EDGE_SAMPLES: usize = 9;

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

fn refs(ids: &[usize]) -> String {
    ids.iter()
        .map(|k| format!("#{k}"))
        .collect::<Vec<_>>()
        .join(",")
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

impl Data {
    fn add(&mut self, entity: String) -> usize {
        self.next += 1;
        let _ = writeln!(self.text, "#{}={};", self.next, entity);
        self.next
    }

    /// Application context, product, its definition and shape, units and
    /// the representation context (the usual AP214 skeleton).
    fn header_entities(&mut self) -> Context {
        let app = self.add(
            "APPLICATION_CONTEXT('core data for automotive mechanical design processes')".into(),
        );
        self.add(format!(
            "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,#{app})"
        ));
        let pc = self.add(format!("PRODUCT_CONTEXT('',#{app},'mechanical')"));
        let product = self.add(format!("PRODUCT('fairsurf','fairsurf surface','',(#{pc}))"));
        self.add(format!(
            "PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#{product}))"
        ));
        let pdf = self.add(format!("PRODUCT_DEFINITION_FORMATION('','',#{product})"));
        let pdc = self.add(format!(
            "PRODUCT_DEFINITION_CONTEXT('part definition',#{app},'design')"
        ));
        let pd = self.add(format!("PRODUCT_DEFINITION('design','',#{pdf},#{pdc})"));
        let shape = self.add(format!("PRODUCT_DEFINITION_SHAPE('','',#{pd})"));
        let mm = self.add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))".into());
        let rad = self.add("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))".into());
        let sr = self.add("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())".into());
        let unc = self.add(format!(
            "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.0E-7),#{mm},\
             'distance_accuracy_value','confusion accuracy')"
        ));
        let representation = self.add(format!(
            "(GEOMETRIC_REPRESENTATION_CONTEXT(3)\
             GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{unc}))\
             GLOBAL_UNIT_ASSIGNED_CONTEXT((#{mm},#{rad},#{sr}))\
             REPRESENTATION_CONTEXT('fairsurf','3D'))"
        ));
        Context {
            representation,
            shape,
        }
    }

    /// The ADVANCED_FACE of one surface (with its surface, edges and vertices).
    fn face(&mut self, s: &CadSurface) -> usize {
        let ((n, m), (cu, cv)) = (s.degree, s.counts);
        let points: Vec<usize> = s
            .points
            .iter()
            .map(|&p| self.add(format!("CARTESIAN_POINT('',{})", coords(p))))
            .collect();
        let id = |i: usize, j: usize| points[i * cv + j];
        let rows: Vec<String> = (0..cu)
            .map(|i| format!("({})", refs(&(0..cv).map(|j| id(i, j)).collect::<Vec<_>>())))
            .collect();
        let (ku, mu) = s.distinct_knots(0);
        let (kv, mv) = s.distinct_knots(1);
        let surface = match &s.weights {
            None => self.add(format!(
                "B_SPLINE_SURFACE_WITH_KNOTS('',{n},{m},({}),.UNSPECIFIED.,.F.,.F.,.F.,\
                 ({}),({}),({}),({}),.UNSPECIFIED.)",
                rows.join(","),
                ints(&mu),
                ints(&mv),
                reals(&ku),
                reals(&kv)
            )),
            // A complex instance, its partial entities in alphabetical order
            // (ISO 10303-21 §11.2.5.3), as Open CASCADE writes it.
            Some(w) => {
                let weights: Vec<String> = (0..cu)
                    .map(|i| format!("({})", reals(&w[i * cv..(i + 1) * cv])))
                    .collect();
                self.add(format!(
                    "(BOUNDED_SURFACE() B_SPLINE_SURFACE({n},{m},({}),.UNSPECIFIED.,.F.,.F.,.F.) \
                     B_SPLINE_SURFACE_WITH_KNOTS(({}),({}),({}),({}),.UNSPECIFIED.) \
                     GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_SURFACE(({})) \
                     REPRESENTATION_ITEM('') SURFACE())",
                    rows.join(","),
                    ints(&mu),
                    ints(&mv),
                    reals(&ku),
                    reals(&kv),
                    weights.join(",")
                ))
            }
        };
        // Counter-clockwise in (u, v): v = 0 and u = 1 along their parameter,
        // v = 1 and u = 0 against it. Each side: (i, j) in parameter order,
        // with the knots of its direction.
        // (i, j) of each side in parameter order, forward or not, direction.
        type Side = (Vec<(usize, usize)>, bool, usize);
        let sides: [Side; 4] = [
            ((0..cu).map(|i| (i, 0)).collect(), true, 0),
            ((0..cv).map(|j| (cu - 1, j)).collect(), true, 1),
            ((0..cu).map(|i| (i, cv - 1)).collect(), false, 0),
            ((0..cv).map(|j| (0, j)).collect(), false, 1),
        ];
        let mut oriented = Vec::new();
        for (side, forward, dir) in &sides {
            let pts: Vec<Vec3> = side.iter().map(|&(i, j)| s.point(i, j)).collect();
            let ids: Vec<usize> = side.iter().map(|&(i, j)| id(i, j)).collect();
            let (d, knots, mults) = if *dir == 0 {
                (n, &ku, &mu)
            } else {
                (m, &kv, &mv)
            };
            let curve = SideCurve {
                d,
                knots,
                mults,
                full: &s.knots[*dir],
                weights: s
                    .weights
                    .as_ref()
                    .map(|_| side.iter().map(|&(i, j)| s.weight(i, j)).collect()),
            };
            let mut edges = self.edges_along(&pts, &ids, &curve);
            if !forward {
                edges.reverse();
            }
            for (edge, same) in edges {
                let sense = if same == *forward { ".T." } else { ".F." };
                oriented.push(self.add(format!("ORIENTED_EDGE('',*,*,#{edge},{sense})")));
            }
        }
        let bound = if oriented.is_empty() {
            // Every side collapsed: the whole boundary is one point.
            let v = self.vertex(s.point(0, 0), id(0, 0));
            self.add(format!("VERTEX_LOOP('',#{v})"))
        } else {
            self.add(format!("EDGE_LOOP('',({}))", refs(&oriented)))
        };
        let outer = self.add(format!("FACE_OUTER_BOUND('',#{bound},.T.)"));
        self.add(format!("ADVANCED_FACE('',(#{outer}),#{surface},.T.)"))
    }

    /// The EDGE_CURVEs along one side (in its parameter order, each with
    /// whether it runs that way): the side's own edge, shared when another
    /// face wrote it; or, when vertices written before lie
    /// inside the side (neighbours whose edges cover parts of it, e.g. two
    /// faces along one side of a fill), one edge between each two
    /// consecutive vertices on the side's curve, shared with an edge
    /// written before that joins the same vertices along the same curve.
    /// Empty for a collapsed side.
    fn edges_along(
        &mut self,
        pts: &[Vec3],
        ids: &[usize],
        curve: &SideCurve,
    ) -> Vec<(usize, bool)> {
        if pts.iter().all(|&p| bits(p) == bits(pts[0])) {
            return Vec::new();
        }
        if let Some(found) = self.known_edge(pts, curve) {
            return vec![found];
        }
        let Ok(kv) = fairsurf::bspline::KnotVector::new(curve.d, curve.full.clone()) else {
            return vec![self.new_edge(pts, ids, curve)];
        };
        let w = curve.weights.as_deref();
        let tol = self.tol;
        let last = pts.len() - 1;
        let (a, b) = kv.domain();
        // Vertices written before that lie inside the side: within the
        // control polygon's box (the curve lies in it), off its ends.
        let (lo, hi) = pts
            .iter()
            .fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), p| {
                (
                    std::array::from_fn(|c| lo[c].min(p[c] - tol)),
                    std::array::from_fn(|c| hi[c].max(p[c] + tol)),
                )
            });
        // Vertices written, and corners of faces still to come.
        let candidates = self
            .vertex_points
            .iter()
            .map(|&(q, v)| (q, Some(v)))
            .chain(self.corners.iter().map(|&q| (q, None)));
        let mut found: Vec<(f64, Vec3, Option<usize>)> = candidates
            .filter(|(q, _)| (0..3).all(|c| q[c] >= lo[c] && q[c] <= hi[c]))
            .filter(|(q, _)| dist(*q, pts[0]) > tol && dist(*q, pts[last]) > tol)
            .filter_map(|(q, v)| {
                let t = project(&kv, pts, w, q)?;
                (t > a && t < b && dist(curve_point(&kv, pts, w, t), q) <= tol).then_some((t, q, v))
            })
            .collect();
        // Written vertices first, then by parameter, each point once.
        found.sort_by_key(|x| x.2.is_none());
        let mut unique: Vec<(f64, Vec3, Option<usize>)> = Vec::new();
        for f in found {
            if !unique.iter().any(|u| dist(u.1, f.1) <= tol) {
                unique.push(f);
            }
        }
        if unique.is_empty() {
            return vec![self.new_edge(pts, ids, curve)];
        }
        unique.sort_by(|x, y| x.0.total_cmp(&y.0));
        let inside: Vec<(f64, usize)> = unique
            .into_iter()
            .map(|(t, q, v)| {
                let v = v.unwrap_or_else(|| {
                    let point = self.add(format!("CARTESIAN_POINT('',{})", coords(q)));
                    self.vertex(q, point)
                });
                (t, v)
            })
            .collect();
        let start = self.vertex(pts[0], ids[0]);
        let end = self.vertex(pts[last], ids[last]);
        let mut chain = vec![(a, start)];
        chain.extend(inside);
        chain.push((b, end));
        let mut out = Vec::new();
        for pair in chain.windows(2) {
            let ((ta, va), (tb, vb)) = (pair[0], pair[1]);
            let samples: [Vec3; EDGE_SAMPLES] = std::array::from_fn(|k| {
                curve_point(
                    &kv,
                    pts,
                    w,
                    ta + (tb - ta) * k as f64 / (EDGE_SAMPLES - 1) as f64,
                )
            });
            if let Some(found) = self.matching_edge(&samples) {
                out.push(found);
                continue;
            }
            // Each piece its own curve, cut exactly at the vertices (a
            // reader that projects the vertices onto a longer curve finds
            // their parameters only to its own tolerance: Open CASCADE put
            // them 3e-8 off).
            let c = match cut_curve(&kv, pts, w, ta, tb) {
                Some((k, piece, weights)) => {
                    let ids: Vec<usize> = piece
                        .iter()
                        .map(|&p| self.add(format!("CARTESIAN_POINT('',{})", coords(p))))
                        .collect();
                    let (knots, mults) = crate::cad::distinct(k.knots());
                    self.add(
                        SideCurve {
                            d: k.degree(),
                            knots: &knots,
                            mults: &mults,
                            full: &k.knots().to_vec(),
                            weights,
                        }
                        .entity(&ids),
                    )
                }
                None => self.add(curve.entity(ids)),
            };
            let e = self.add(format!("EDGE_CURVE('',#{va},#{vb},#{c},.T.)"));
            self.edge_samples.push((samples, e));
            out.push((e, true));
        }
        out
    }

    /// An edge written before along the same curve as `pts` (by its
    /// points and knots, or by its samples), and whether it runs the same
    /// way.
    fn known_edge(&self, pts: &[Vec3], curve: &SideCurve) -> Option<(usize, bool)> {
        for (reversed, same) in [(false, true), (true, false)] {
            if let Some(&e) = self.edges.get(&curve.key(pts, reversed)) {
                return Some((e, same));
            }
        }
        self.matching_edge(&curve.samples(pts)?)
    }

    /// An edge written before through `samples` (first to last, or last to
    /// first), and whether it runs the same way.
    fn matching_edge(&self, samples: &[Vec3; EDGE_SAMPLES]) -> Option<(usize, bool)> {
        let tol = self.tol;
        let close = |a: &[Vec3], b: &mut dyn Iterator<Item = Vec3>| {
            a.iter().zip(b).all(|(p, q)| dist(*p, q) <= tol)
        };
        for (other, e) in &self.edge_samples {
            if close(other, &mut samples.iter().copied()) {
                return Some((*e, true));
            }
            if close(other, &mut samples.iter().rev().copied()) {
                return Some((*e, false));
            }
        }
        None
    }

    /// A new EDGE_CURVE along the control polygon `pts` (CARTESIAN_POINTs
    /// `ids`) of degree d with distinct knots and multiplicities, from the
    /// polygon's first point to its last, registered for sharing.
    fn new_edge(&mut self, pts: &[Vec3], ids: &[usize], side: &SideCurve) -> (usize, bool) {
        let curve = self.add(side.entity(ids));
        let last = pts.len() - 1;
        let start = self.vertex(pts[0], ids[0]);
        let end = self.vertex(pts[last], ids[last]);
        let e = self.add(format!("EDGE_CURVE('',#{start},#{end},#{curve},.T.)"));
        self.edges.insert(side.key(pts, false), e);
        if let Some(samples) = side.samples(pts) {
            self.edge_samples.push((samples, e));
        }
        (e, true)
    }

    /// The VERTEX_POINT at `p` (a CARTESIAN_POINT `point`), shared by all
    /// corners at the same point.
    fn vertex(&mut self, p: Vec3, point: usize) -> usize {
        if let Some(&v) = self.vertices.get(&bits(p)) {
            return v;
        }
        let tol = self.tol;
        let near = self.vertex_points.iter().find(|(q, _)| dist(p, *q) <= tol);
        if let Some(&(_, v)) = near {
            return v;
        }
        let v = self.add(format!("VERTEX_POINT('',#{point})"));
        self.vertices.insert(bits(p), v);
        self.vertex_points.push((p, v));
        v
    }
}

fn dist(p: Vec3, q: Vec3) -> f64 {
    let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// The curve (degree and knots `kv`, control points `pts`, weights `w` when
/// rational) and its first derivative at t; rational by the quotient rule
/// on the homogeneous curve.
fn curve_derivs(
    kv: &fairsurf::bspline::KnotVector,
    pts: &[Vec3],
    w: Option<&[f64]>,
    t: f64,
) -> [Vec3; 2] {
    let d = kv.degree();
    let k = kv.span(t);
    let n = kv.basis_derivatives(k, t, 1);
    let weight = |i: usize| w.map_or(1.0, |w| w[i]);
    // A = Σ N w P and W = Σ N w, and their derivatives.
    let a: [Vec3; 2] = std::array::from_fn(|r| {
        (0..=d).fold([0.0; 3], |acc, i| {
            let j = k - d + i;
            let (p, c) = (pts[j], n[r][i] * weight(j));
            [acc[0] + c * p[0], acc[1] + c * p[1], acc[2] + c * p[2]]
        })
    });
    let ws: [f64; 2] = std::array::from_fn(|r| (0..=d).map(|i| n[r][i] * weight(k - d + i)).sum());
    let c = a[0].map(|x| x / ws[0]);
    let dc = std::array::from_fn(|x| (a[1][x] - ws[1] * c[x]) / ws[0]);
    [c, dc]
}

fn curve_point(
    kv: &fairsurf::bspline::KnotVector,
    pts: &[Vec3],
    w: Option<&[f64]>,
    t: f64,
) -> Vec3 {
    curve_derivs(kv, pts, w, t)[0]
}

/// The parameter of the curve's point nearest to q: the best of 64
/// samples, then Newton steps on (C(t) − q)·C′(t) = 0 (first order, kept
/// in the domain).
fn project(
    kv: &fairsurf::bspline::KnotVector,
    pts: &[Vec3],
    w: Option<&[f64]>,
    q: Vec3,
) -> Option<f64> {
    let (a, b) = kv.domain();
    let mut t = (0..=64)
        .map(|k| a + (b - a) * k as f64 / 64.0)
        .min_by(|&x, &y| {
            dist(curve_point(kv, pts, w, x), q).total_cmp(&dist(curve_point(kv, pts, w, y), q))
        })?;
    for _ in 0..20 {
        let [c, dc] = curve_derivs(kv, pts, w, t);
        let r = [c[0] - q[0], c[1] - q[1], c[2] - q[2]];
        let g = r[0] * dc[0] + r[1] * dc[1] + r[2] * dc[2];
        let h = dc[0] * dc[0] + dc[1] * dc[1] + dc[2] * dc[2];
        if h == 0.0 {
            break;
        }
        let next = (t - g / h).clamp(a, b);
        if (next - t).abs() <= 1e-15 * (b - a) {
            t = next;
            break;
        }
        t = next;
    }
    t.is_finite().then_some(t)
}

/// The part of the curve (knots `kv`, points `pts`, weights `w`) over
/// [ta, tb], cut by knot insertion (the homogeneous points w·P and the
/// weights alike): its knots, points and weights.
#[allow(clippy::type_complexity)]
fn cut_curve(
    kv: &fairsurf::bspline::KnotVector,
    pts: &[Vec3],
    w: Option<&[f64]>,
    ta: f64,
    tb: f64,
) -> Option<(fairsurf::bspline::KnotVector, Vec<Vec3>, Option<Vec<f64>>)> {
    use fairsurf::bspline::{BSplineSurface, KnotVector};
    let weight = |i: usize| w.map_or(1.0, |w| w[i]);
    // Columns w·P and (w, 0, 0) of a surface linear in v.
    let net = BSplineSurface::new(
        kv.clone(),
        KnotVector::bezier(1),
        pts.iter()
            .enumerate()
            .flat_map(|(i, p)| [p.map(|x| x * weight(i)), [weight(i), 0.0, 0.0]])
            .collect(),
    )
    .ok()?;
    let cut = net.restricted_u(ta, tb).ok()?;
    let n = cut.counts().0;
    let weights: Vec<f64> = (0..n).map(|i| cut.point(i, 1)[0]).collect();
    let points = (0..n)
        .map(|i| cut.point(i, 0).map(|x| x / weights[i]))
        .collect();
    Some((cut.knots().0.clone(), points, w.map(|_| weights)))
}

fn ints(v: &[usize]) -> String {
    v.iter()
        .map(|k| k.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

fn reals(v: &[f64]) -> String {
    v.iter().map(|&t| real(t)).collect::<Vec<_>>().join(",")
}

fn coords(p: Vec3) -> String {
    format!("({},{},{})", real(p[0]), real(p[1]), real(p[2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn count(text: &str, entity: &str) -> usize {
        text.matches(&format!("={entity}(")).count()
    }

    #[test]
    fn a_patch_is_one_face_with_four_edges() {
        let p = TensorPatch::from_fn(3, 4, |i, j| [i as f64, j as f64, 0.1 * (i * j) as f64]);
        let t = step_text("x.step", &[(&p).into()]);
        assert_eq!(count(&t, "ADVANCED_FACE"), 1);
        assert_eq!(count(&t, "EDGE_CURVE"), 4);
        assert_eq!(count(&t, "VERTEX_POINT"), 4);
        assert_eq!(count(&t, "ORIENTED_EDGE"), 4);
        assert_eq!(count(&t, "CARTESIAN_POINT"), 20 + 1);
        assert!(t.contains(",(4,4),(5,5),(0.0,1.0),(0.0,1.0),.UNSPECIFIED.)"));
    }

    #[test]
    fn a_collapsed_side_has_no_edge_and_shared_sides_are_shared() {
        // Side u = 0 (i = 0) collapsed to the origin.
        let p = TensorPatch::from_fn(2, 2, |i, j| {
            if i == 0 {
                [0.0; 3]
            } else {
                [i as f64, j as f64 - 1.0, 0.0]
            }
        });
        let t = step_text("x.step", &[(&p).into()]);
        assert_eq!(count(&t, "EDGE_CURVE"), 3);
        assert_eq!(count(&t, "VERTEX_POINT"), 3);
        // Two patches meeting along u = 1 of the first / u = 0 of the second.
        let a = TensorPatch::from_fn(2, 2, |i, j| [i as f64, j as f64, (i * j) as f64]);
        let b = TensorPatch::from_fn(2, 2, |i, j| [2.0 + i as f64, j as f64, (2 * j) as f64]);
        let t = step_text("x.step", &[(&a).into(), (&b).into()]);
        assert_eq!(count(&t, "ADVANCED_FACE"), 2);
        assert_eq!(count(&t, "EDGE_CURVE"), 7);
        assert_eq!(count(&t, "VERTEX_POINT"), 6);
        let shared = t
            .lines()
            .filter(|l| l.contains(",.F.);") && l.contains("ORIENTED_EDGE"));
        // Top and left of each run against their edges; the shared edge is
        // used once each way (a by its right side, b by its left).
        assert_eq!(shared.count(), 4);
    }

    /// A neighbour's boundary and the same curve degree-elevated (another
    /// surface's boundary) are one edge.
    #[test]
    fn a_boundary_and_its_elevated_copy_are_one_edge() {
        let a = TensorPatch::from_fn(2, 2, |i, j| [i as f64, j as f64, (i * j) as f64]);
        let b = TensorPatch::from_fn(2, 2, |i, j| [2.0 + i as f64, j as f64, (2 * j) as f64]);
        let b = b.elevate(1, 1);
        let t = step_text("x.step", &[(&a).into(), (&b).into()]);
        assert_eq!(count(&t, "EDGE_CURVE"), 7);
        assert_eq!(count(&t, "VERTEX_POINT"), 6);
        // Moved off by 1e-6 of the size, it is not.
        let c = b.map(|p| [p[0], p[1], p[2] + 1e-6 * (p[0] - 2.0).abs().max(0.0) + 1e-6]);
        let t = step_text("x.step", &[(&a).into(), (&c).into()]);
        assert_eq!(count(&t, "EDGE_CURVE"), 8);
    }

    #[test]
    fn labels_are_escaped() {
        assert_eq!(string("it's a\\b é"), "it''s a\\\\b _");
    }

    /// A side that two later faces each cover half of is split at their
    /// common corner and shares its halves with them, whichever order the
    /// faces come in.
    #[test]
    fn a_side_is_split_at_corners_of_faces_written_later() {
        let quad = |x0: f64, x1: f64, y0: f64, y1: f64| {
            TensorPatch::from_fn(1, 1, |i, j| {
                [
                    if i == 0 { x0 } else { x1 },
                    if j == 0 { y0 } else { y1 },
                    0.0,
                ]
            })
        };
        let (a, b, c) = (
            quad(0.0, 2.0, -1.0, 0.0),
            quad(0.0, 1.0, 0.0, 1.0),
            quad(1.0, 2.0, 0.0, 1.0),
        );
        for order in [[&a, &b, &c], [&b, &c, &a], [&b, &a, &c]] {
            let surfaces: Vec<CadSurface> = order.iter().map(|p| CadSurface::from(*p)).collect();
            let t = step_text("x.step", &surfaces);
            assert_eq!(count(&t, "EDGE_CURVE"), 10, "{t}");
            assert_eq!(count(&t, "VERTEX_POINT"), 8, "{t}");
            assert_eq!(count(&t, "ORIENTED_EDGE"), 13, "{t}");
            // fairsurf reads its own split sides back: the faces as written.
            let back = crate::read_step_faces(&t).unwrap();
            let written: Vec<_> = order
                .iter()
                .map(|p| fairsurf::bspline::BSplineSurface::from_bezier(p))
                .collect();
            assert_eq!(back, written);
        }
    }
}
