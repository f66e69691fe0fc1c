//! Reading STEP files (ISO 10303-21) for `fill` and `blend`: the faces of
//! every shell (OPEN_SHELL, CLOSED_SHELL, in whichever representation holds
//! them): the file's syntax read into ruststep's syntax tree by a one-pass
//! reader of our own (`lex`: the same tree, 10× faster than ruststep's parser), shells
//! and faces converted by the `truck-stepio` crate, each face as a
//! polynomial or rational B-spline bounded by its four sides
//! ([`read_step`]): B-spline and Bézier faces (rational or not), planes
//! bounded by four straight edges, cylinders and cones bounded by two arcs
//! and two rulings, spheres and tori bounded by two parallels and two
//! meridians; or a trimmed face of any of these surfaces (bounded
//! otherwise, or with holes) as its surface and its loops' edges
//! ([`TrimEdge`], the module `trimmed`). Every other face (swept surfaces)
//! is refused by name, nothing is dropped silently.

use crate::{Error, Result};
use fairsurf::bspline::{BSplineSurface, KnotVector, RationalSurface};
use fairsurf::Vec3;
use truck_stepio::r#in::alias::{
    Curve3D, ElementarySurface, ParametricCurve, ParametricSurface, ParametricSurface3D, Point3,
    SearchNearestParameter, Surface as StepSurface, Vector3, D2,
};
use truck_stepio::r#in::Table;
use truck_topology::compress::{CompressedEdgeIndex, CompressedFace, CompressedShell};

mod analytic;
mod edges;
mod lex;
mod spline;
mod trimmed;
use analytic::*;
use edges::*;
use spline::*;
use trimmed::*;
pub use trimmed::{TrimEdge, TRIM_TOLERANCE};
#[cfg(test)]
mod tests;

/// The error for a STEP file's content (as a scene error with the entity
/// or face as its path).
fn bad(path: impl Into<String>, message: impl Into<String>) -> Error {
    Error::scene(path, message)
}

/// A face's surface, exactly as the file gives it.
#[derive(Clone, Debug, PartialEq)]
pub enum FaceSurface {
    /// A polynomial B-spline (Bézier faces, B-spline faces, rational ones
    /// with equal weights, planes bounded by four straight edges).
    Polynomial(BSplineSurface),
    /// A rational B-spline (rational faces with unequal weights, cylinders
    /// and cones bounded by two arcs and two rulings).
    Rational(RationalSurface),
}

impl FaceSurface {
    /// The control net: the polynomial surface, or the rational one's
    /// points without their weights.
    pub fn net(&self) -> &BSplineSurface {
        net(self)
    }
}

/// A face of a STEP file: bounded by four sides of its surface, or a
/// trimmed one (`loops`).
#[derive(Clone, Debug, PartialEq)]
pub struct StepFace {
    /// What the file's surface is: "B-spline", "rational B-spline",
    /// "plane", "cylinder", "cone", "sphere" or "torus"; "trimmed
    /// B-spline", "trimmed rational B-spline", "trimmed plane", "trimmed
    /// cylinder", "trimmed cone", "trimmed sphere" or "trimmed torus".
    pub kind: &'static str,
    /// The surface, whose four sides are the face's boundary; of a trimmed
    /// face the file's surface (a plane: a bilinear patch around the
    /// loops; a cylinder, cone, sphere or torus: the exact rational
    /// B-spline of the piece its loops lie on).
    pub surface: FaceSurface,
    /// A trimmed face's loops in the order the file lists them (which is
    /// the outer one is not recorded), each edge as it runs with the face
    /// on its left seen from the surface's normal; empty for a face
    /// bounded by four sides of its surface. (A face the shell uses
    /// reversed, ORIENTED_FACE .F., keeps its surface's sense here.)
    pub loops: Vec<Vec<TrimEdge>>,
}

impl StepFace {
    /// The surface as a polynomial B-spline, when it is one.
    pub fn polynomial(&self) -> Option<&BSplineSurface> {
        match &self.surface {
            FaceSurface::Polynomial(s) => Some(s),
            FaceSurface::Rational(_) => None,
        }
    }
}

/// The polynomial faces of every shell in a STEP file's text ([`read_step`]
/// with every face polynomial and bounded by its four sides); a rational
/// face (a cylinder, …) or a trimmed one is an error naming it.
pub fn read_step_faces(text: &str) -> Result<Vec<BSplineSurface>> {
    read_step(text)?
        .into_iter()
        .enumerate()
        .map(|(k, f)| match f.surface {
            _ if !f.loops.is_empty() => Err(bad(
                format!("face {k}"),
                format!(
                    "a {} face: only faces bounded by the four sides of their surfaces are \
                     taken here",
                    f.kind
                ),
            )),
            FaceSurface::Polynomial(s) => Ok(s),
            FaceSurface::Rational(_) => Err(bad(
                format!("face {k}"),
                format!(
                    "a {} face (a rational surface): only polynomial faces are taken here",
                    f.kind
                ),
            )),
        })
        .collect()
}

/// The faces of every shell in a STEP file's text, in the order of the
/// shells' entity numbers and their faces in each, each exactly as a
/// polynomial or rational B-spline bounded by its four sides:
/// B-spline and Bézier faces (rational or not) whose boundary is their
/// surface's four sides; planes bounded by four straight edges (a
/// bilinear patch); cylinders and cones bounded by two circular arcs and
/// two rulings (rational quadratic in the arcs' direction, The NURBS Book
/// §7.5); spheres and tori bounded by two parallels and two meridians (the
/// rational biquadratic surface of revolution, §8.5) — each conversion
/// checked against the file's own surface and edges. A face of any of
/// these surfaces bounded otherwise, or with holes, is a trimmed face
/// ([`StepFace::loops`]): its surface (a plane's as a bilinear patch
/// around its loops; a cylinder's, cone's, sphere's or torus's as the
/// exact rational B-spline of its revolution over the angles and the
/// stretch of meridian its loops take, 2% wider, §8.5) and its loops'
/// edges, each within [`TRIM_TOLERANCE`] (or 1e-7 of the loops' size) of
/// the surface, free when no other face of its shell uses it.
///
/// Errors name what is wrong: not STEP (with the parser's message), no
/// shell, a face of another kind (a swept surface), an edge of a trimmed
/// face off its surface, a trimmed face all the way round its axis
/// without a seam edge, a face the reader could not convert.
pub fn read_step(text: &str) -> Result<Vec<StepFace>> {
    let mut data = lex::first_data_section(text)
        .map_err(|e| {
            bad(
                "",
                format!("not a STEP file (ISO 10303-21) this reader can parse: {e}"),
            )
        })?
        .ok_or_else(|| bad("", "the STEP file has no DATA section"))?;
    curves_as_3d(&mut data);
    let data = &mut data;
    same_sense_edges(data);
    let data = &*data;
    let table = guarded(|| Table::from_data_section(data)).map_err(|e| {
        bad(
            "",
            format!("the STEP reader (truck-stepio) failed on this file: {e}"),
        )
    })?;
    let mut shells: Vec<_> = table.shell.iter().collect();
    if shells.is_empty() {
        return Err(bad(
            "",
            "no shell (OPEN_SHELL or CLOSED_SHELL) in the STEP file: fill reads the faces of shells",
        ));
    }
    shells.sort_by_key(|(id, _)| **id);
    let mut faces = Vec::new();
    for (id, shell) in shells {
        let compressed = guarded(|| table.to_compressed_shell(shell))
            .map_err(|e| {
                bad(
                    format!("#{id}"),
                    format!("the STEP reader (truck-stepio) failed on the shell: {e}"),
                )
            })?
            .map_err(|e| bad(format!("#{id}"), format!("cannot read the shell: {e}")))?;
        if compressed.faces.len() != shell.cfs_faces.len() {
            return Err(bad(
                format!("#{id}"),
                format!(
                    "the shell has {} faces and the reader converted {}: some face's surface is \
                     of a kind it does not read",
                    shell.cfs_faces.len(),
                    compressed.faces.len()
                ),
            ));
        }
        let mut read = Vec::with_capacity(compressed.faces.len());
        for (k, face) in compressed.faces.iter().enumerate() {
            let path = format!("#{id} face {k}");
            let f = guarded(|| step_face(face, &compressed))
                .unwrap_or_else(|e| Err(format!("the face's geometry could not be evaluated: {e}")))
                .map_err(|m| bad(&path, m))?;
            read.push(f);
        }
        faces.extend(with_free_edges(&compressed, read));
    }
    Ok(faces)
}

/// A face read ([`step_face`]), a trimmed one with its edges' frames.
struct Read {
    face: StepFace,
    frames: Vec<Vec<Frames>>,
}

/// The faces of a shell with their trimmed loops' edges: free where no
/// other face of the shell uses the edge, with the directions their strips
/// leave their ends by where one other free edge meets each end.
fn with_free_edges(shell: &Shell, read: Vec<Read>) -> Vec<StepFace> {
    let mut uses = vec![0usize; shell.edges.len()];
    for f in &shell.faces {
        for e in f.boundaries.iter().flatten() {
            if let Some(u) = uses.get_mut(e.index) {
                *u += 1;
            }
        }
    }
    let free = |e: &CompressedEdgeIndex| uses.get(e.index) == Some(&1);
    // Every free edge's end vertices and the directions it leaves them by
    // (trimmed faces' edges only: a four-sided face's free side is a
    // neighbour's side, its own direction there as its loop runs).
    let mut leaving: Vec<(Vec3, usize, Vec3)> = Vec::new();
    for (f, r) in shell.faces.iter().zip(&read) {
        for (k, l) in f.boundaries.iter().enumerate() {
            for (j, e) in l.iter().enumerate() {
                if !free(e) {
                    continue;
                }
                let edge = match r.frames.get(k).and_then(|l| l.get(j)) {
                    Some(fr) => (fr.start(), fr.end(), fr.leaving(true), fr.leaving(false)),
                    None => match LoopEdge::new(shell, *e) {
                        Ok(le) => {
                            let (d0, d1) = (le.at(0.0).1, le.at(1.0).1);
                            (le.start, le.end, d0, [-d1[0], -d1[1], -d1[2]])
                        }
                        Err(_) => continue,
                    },
                };
                leaving.push((edge.0, e.index, edge.2));
                leaving.push((edge.1, e.index, edge.3));
            }
        }
    }
    let size =
        fairsurf::vector::bounding_diagonal(&leaving.iter().map(|l| l.0).collect::<Vec<_>>());
    let tol = (1e-8 * size).max(EDGE_TOLERANCE);
    // The one other free edge at p, continued through it.
    let beyond = |p: Vec3, index: usize| {
        let mut others = leaving
            .iter()
            .filter(|l| l.1 != index && dist(l.0, p) <= tol);
        match (others.next(), others.next()) {
            (Some(l), None) => Some([-l.2[0], -l.2[1], -l.2[2]]),
            _ => None,
        }
    };
    shell
        .faces
        .iter()
        .zip(read)
        .map(|(f, r)| {
            let mut face = r.face;
            face.loops = r
                .frames
                .into_iter()
                .zip(&f.boundaries)
                .map(|(l, b)| {
                    l.into_iter()
                        .zip(b)
                        .map(|(fr, e)| {
                            let is_free = free(e);
                            let ends = if is_free {
                                beyond(fr.start(), e.index).zip(beyond(fr.end(), e.index))
                            } else {
                                None
                            };
                            fr.into_edge(is_free, ends.map(|(a, b)| [a, b]))
                        })
                        .collect()
                })
                .collect();
            face
        })
        .collect()
}

thread_local! {
    /// Whether a panic on this thread is [`guarded`]'s to report (not the
    /// process's panic hook's), and what it said.
    static GUARD: std::cell::RefCell<Option<Option<String>>> = const { std::cell::RefCell::new(None) };
}

/// `f()`, or what its panic said and where (truck-stepio and
/// truck-geometry `unwrap` on some malformed geometry: a plane of zero
/// normal, …). The panic is not printed: the process's panic hook is
/// wrapped once so that it stays quiet on a thread inside `guarded`, and
/// the message becomes part of the error that names the entity or face.
fn guarded<T>(f: impl FnOnce() -> T) -> std::result::Result<T, String> {
    static WRAP: std::sync::Once = std::sync::Once::new();
    WRAP.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            // `try_with`: a panic while this thread's locals are being
            // destroyed must reach the previous hook, not panic in this one.
            let quiet = GUARD.try_with(|g| {
                let mut g = g.borrow_mut();
                match g.as_mut() {
                    Some(said) => {
                        let message = info
                            .payload()
                            .downcast_ref::<&str>()
                            .map(|s| s.to_string())
                            .or_else(|| info.payload().downcast_ref::<String>().cloned())
                            .unwrap_or_else(|| "a panic".into());
                        // A dependency's file from its crate folder on
                        // (not the registry's path on this machine).
                        let place = info
                            .location()
                            .map(|l| {
                                let file = l.file();
                                let short = match file.split_once("/registry/src/") {
                                    Some((_, rest)) => rest.split_once('/').map_or(rest, |r| r.1),
                                    // Elsewhere (vendored, git): its last
                                    // two components, no local path.
                                    None => {
                                        let mut parts = file.rsplitn(3, '/');
                                        let name = parts.next().unwrap_or(file);
                                        match parts.next() {
                                            Some(dir) => {
                                                &file[file.len() - name.len() - dir.len() - 1..]
                                            }
                                            None => name,
                                        }
                                    }
                                };
                                format!(" ({short}:{})", l.line())
                            })
                            .unwrap_or_default();
                        *said = Some(format!("{message}{place}"));
                        true
                    }
                    None => false,
                }
            });
            if !matches!(quiet, Ok(true)) {
                previous(info);
            }
        }));
    });
    // Guarded from here on, nothing said yet (`Option::replace` stores
    // Some(None)); the outer state comes back after (guards nest).
    let outer = GUARD.with(|g| g.borrow_mut().replace(None));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    let said = GUARD
        .with(|g| std::mem::replace(&mut *g.borrow_mut(), outer))
        .flatten();
    result.map_err(|_| said.unwrap_or_else(|| "a panic".into()))
}

/// Every SURFACE_CURVE's preferred representation (`.PCURVE_S1.`,
/// `.PCURVE_S2.`) made its 3-D curve (`.CURVE_3D.`): truck-stepio follows a
/// pcurve preference through the pcurve on the surface, and on a periodic
/// surface (a torus, a sphere) its parameters wrap to [0, 2π) — an arc from
/// v = −0.4 to 1.2 came out as the other 4.68 rad of the circle. The 3-D
/// curve is the edge's own geometry; the pcurves only describe it on each
/// face.
fn curves_as_3d(data: &mut ruststep::ast::DataSection) {
    use ruststep::ast::{EntityInstance, Parameter};
    for e in &mut data.entities {
        let records = match e {
            EntityInstance::Simple { record, .. } => std::slice::from_mut(record),
            EntityInstance::Complex { subsuper, .. } => &mut subsuper.0[..],
        };
        for r in records {
            if let Parameter::List(ps) = &mut r.parameter {
                for p in ps {
                    if let Parameter::Enumeration(e) = p {
                        if e == "PCURVE_S1" || e == "PCURVE_S2" {
                            *e = "CURVE_3D".into();
                        }
                    }
                }
            }
        }
    }
}

/// Every EDGE_CURVE of same_sense `.F.` rewritten as its equal of
/// same_sense `.T.` (its vertices swapped), and the ORIENTED_EDGEs that
/// use it turned: truck-stepio turns a `.F.` edge's curve twice on the
/// path of a SURFACE_CURVE read by its 3-D curve (which [`read_step`]
/// asks for), so such an edge would run backwards.
fn same_sense_edges(data: &mut ruststep::ast::DataSection) {
    use ruststep::ast::{EntityInstance, Name, Parameter};
    let (yes, no) = (
        Parameter::Enumeration("T".into()),
        Parameter::Enumeration("F".into()),
    );
    let mut turned = std::collections::HashSet::new();
    for e in &mut data.entities {
        if let EntityInstance::Simple { id, record } = e {
            if record.name != "EDGE_CURVE" {
                continue;
            }
            if let Parameter::List(ps) = &mut record.parameter {
                if ps.len() == 5 && ps[4] == no {
                    ps.swap(1, 2);
                    ps[4] = yes.clone();
                    turned.insert(*id);
                }
            }
        }
    }
    if turned.is_empty() {
        return;
    }
    for e in &mut data.entities {
        if let EntityInstance::Simple { record, .. } = e {
            if record.name != "ORIENTED_EDGE" {
                continue;
            }
            if let Parameter::List(ps) = &mut record.parameter {
                let uses = matches!(ps.get(3), Some(Parameter::Ref(Name::Entity(k))) if turned.contains(k));
                if ps.len() == 5 && uses {
                    ps[4] = if ps[4] == yes {
                        no.clone()
                    } else {
                        yes.clone()
                    };
                }
            }
        }
    }
}

type Shell = CompressedShell<Point3, Curve3D, StepSurface>;
type Face = CompressedFace<StepSurface>;

fn v3(p: Point3) -> Vec3 {
    [p.x, p.y, p.z]
}

fn dist(a: Vec3, b: Vec3) -> f64 {
    fairsurf::vector::norm(fairsurf::vector::sub(a, b))
}

/// One face as a polynomial or rational B-spline bounded by its four
/// sides, or a trimmed face (with its edges' frames), or
/// why not.
fn step_face(face: &Face, shell: &Shell) -> std::result::Result<Read, String> {
    let loops: Vec<Vec<LoopEdge>> = face
        .boundaries
        .iter()
        .map(|b| {
            b.iter()
                .map(|e| LoopEdge::new(shell, *e))
                .collect::<std::result::Result<Vec<_>, String>>()
        })
        .collect::<std::result::Result<_, String>>()?;
    let trimmable = !matches!(&face.surface, StepSurface::SweptCurve(_));
    let as_trimmed = |four: String| -> std::result::Result<Read, String> {
        if !trimmable {
            return Err(four);
        }
        let (kind, surface, frames) = trimmed(face, &loops)?;
        Ok(Read {
            face: StepFace {
                kind,
                surface,
                loops: Vec::new(),
            },
            frames,
        })
    };
    if loops.len() != 1 {
        return as_trimmed(format!(
            "the face has {} boundary loops: faces with holes in them are not filled around \
             when their surface is swept (an extrusion or a revolution of a curve)",
            loops.len()
        ));
    }
    match four_sided(face, &loops[0]) {
        Ok(f) => Ok(Read {
            face: f,
            frames: Vec::new(),
        }),
        Err(why) => as_trimmed(why),
    }
}

/// One face bounded by the four sides of its surface as a polynomial or
/// rational B-spline, or why not.
fn four_sided(face: &Face, edges: &[LoopEdge]) -> std::result::Result<StepFace, String> {
    let (kind, surface) = match &face.surface {
        StepSurface::BSplineSurface(_) | StepSurface::NurbsSurface(_) => {
            let (kind, surface) = spline(&face.surface)?;
            (kind, restricted(surface, edges)?)
        }
        StepSurface::ElementarySurface(e) => match e.as_ref() {
            ElementarySurface::Plane(_) => ("plane", plane(edges)?),
            ElementarySurface::CylindricalSurface(_) => ("cylinder", ruled(edges)?),
            ElementarySurface::ConicalSurface(_) => ("cone", ruled(edges)?),
            ElementarySurface::Sphere(_) => ("sphere", revolved(edges, "sphere")?),
            ElementarySurface::ToroidalSurface(_) => ("torus", revolved(edges, "torus")?),
        },
        StepSurface::SweptCurve(_) => {
            return Err("a swept surface (extrusion or revolution): not filled around yet".into())
        }
    };
    // A B-spline face is the file's surface itself; a converted one is
    // checked against it.
    let converted = !matches!(kind, "B-spline" | "rational B-spline");
    let surface = oriented_like(surface, face, edges, converted)?;
    Ok(StepFace {
        kind,
        surface,
        loops: Vec::new(),
    })
}
