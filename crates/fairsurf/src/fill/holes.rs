//! Holes in a set of faces: the closed loops of free edges. Each face's four
//! boundaries (a boundary collapsed to a point has none) are compared with
//! every other face's at nine parameters; one that no other face shares,
//! in either direction, is free. Free edges are chained at their end
//! points into loops.

use crate::analysis::Edge;
use crate::bspline::BSplineSurface;
use crate::vec3::{bounding_diagonal, dist};
use crate::{Error, Result, Vec3};

/// One side of a hole: a whole boundary of one face, traversed from t = 0
/// to t = 1 along the boundary's parameter (the knot domain mapped onto
/// [0, 1]), or from 1 to 0 when `reversed`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Side {
    /// Index of the face.
    pub face: usize,
    /// Which boundary.
    pub edge: Edge,
    /// Traversed from t = 1 to t = 0.
    pub reversed: bool,
}

/// A closed loop of free edges, in traversal order (side k ends where side
/// k + 1 starts).
#[derive(Clone, Debug, PartialEq)]
pub struct Hole {
    /// The sides.
    pub sides: Vec<Side>,
    /// The loop's length (polygon through 33 points per side).
    pub length: f64,
}

impl Hole {
    /// The same loop traversed the other way.
    pub fn reversed(&self) -> Self {
        Self {
            sides: self
                .sides
                .iter()
                .rev()
                .map(|s| Side {
                    reversed: !s.reversed,
                    ..*s
                })
                .collect(),
            length: self.length,
        }
    }

    /// The faces around the hole, each once, in order of first appearance.
    pub fn faces(&self) -> Vec<usize> {
        let mut out: Vec<usize> = Vec::new();
        for s in &self.sides {
            if !out.contains(&s.face) {
                out.push(s.face);
            }
        }
        out
    }
}

/// The point of `face`'s boundary `edge` at t ∈ [0, 1].
pub fn edge_point(face: &BSplineSurface, edge: Edge, t: f64) -> Vec3 {
    let (u, v) = surface_param(face, edge, t);
    face.eval(u, v)
}

/// (u, v) in `face`'s knot domain of its boundary `edge` at t ∈ [0, 1].
pub fn surface_param(face: &BSplineSurface, edge: Edge, t: f64) -> (f64, f64) {
    let (s, r) = edge.param(t);
    let (ku, kv) = face.knots();
    let ((a, b), (c, d)) = (ku.domain(), kv.domain());
    (a + s * (b - a), c + r * (d - c))
}

/// Points compared per edge.
const SAMPLES: usize = 9;

/// The distance under which two points are one: 1e-9 of the faces' size,
/// at least 1e-7 (Open CASCADE's `Precision::Confusion`).
pub fn tolerance(faces: &[BSplineSurface]) -> f64 {
    let pts: Vec<Vec3> = faces
        .iter()
        .flat_map(|f| f.points().iter().copied())
        .collect();
    (1e-9 * bounding_diagonal(&pts)).max(1e-7)
}

struct BoundaryEdge {
    face: usize,
    edge: Edge,
    samples: Vec<Vec3>,
}

/// Every hole of `faces`: the loops of free edges, longest first. Errors
/// when free edges do not close into loops (the faces do not form
/// surfaces with boundaries made of whole face edges).
pub fn find_holes(faces: &[BSplineSurface]) -> Result<Vec<Hole>> {
    find_holes_within(faces, tolerance(faces))
}

/// [`find_holes`] with points closer than `tol` taken as one (faces that
/// stand in for rational ones meet only within their fit).
pub fn find_holes_within(faces: &[BSplineSurface], tol: f64) -> Result<Vec<Hole>> {
    let mut edges = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        for edge in [Edge::V0, Edge::U1, Edge::V1, Edge::U0] {
            let samples: Vec<Vec3> = (0..SAMPLES)
                .map(|k| edge_point(face, edge, k as f64 / (SAMPLES - 1) as f64))
                .collect();
            let length: f64 = samples.windows(2).map(|w| dist(w[0], w[1])).sum();
            if length > tol {
                edges.push(BoundaryEdge {
                    face: f,
                    edge,
                    samples,
                });
            }
        }
    }
    let same = |a: &BoundaryEdge, b: &BoundaryEdge| {
        let fwd = a
            .samples
            .iter()
            .zip(&b.samples)
            .all(|(p, q)| dist(*p, *q) <= tol);
        let rev = a
            .samples
            .iter()
            .zip(b.samples.iter().rev())
            .all(|(p, q)| dist(*p, *q) <= tol);
        fwd || rev
    };
    let free: Vec<&BoundaryEdge> = edges
        .iter()
        .enumerate()
        .filter(|(i, e)| !edges.iter().enumerate().any(|(j, o)| j != *i && same(e, o)))
        .map(|(_, e)| e)
        .collect();
    // Vertices: end points within tol are one.
    let mut vertices: Vec<Vec3> = Vec::new();
    let mut vertex = |p: Vec3| match vertices.iter().position(|q| dist(p, *q) <= tol) {
        Some(k) => k,
        None => {
            vertices.push(p);
            vertices.len() - 1
        }
    };
    let ends: Vec<(usize, usize)> = free
        .iter()
        .map(|e| (vertex(e.samples[0]), vertex(e.samples[SAMPLES - 1])))
        .collect();
    let mut used = vec![false; free.len()];
    let mut holes = Vec::new();
    for start in 0..free.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let mut sides = vec![(start, false)];
        let first = ends[start].0;
        let mut at = ends[start].1;
        while at != first {
            let next = (0..free.len()).find(|&k| !used[k] && (ends[k].0 == at || ends[k].1 == at));
            let Some(k) = next else {
                let p = vertices[at];
                return Err(Error::Fill {
                    why: format!(
                        "the free edges do not close into a loop: the one ending at ({}, {}, {}) \
                         (a boundary of face {}) continues nowhere",
                        p[0],
                        p[1],
                        p[2],
                        free[sides.last().expect("a side").0].face
                    ),
                });
            };
            used[k] = true;
            let reversed = ends[k].0 != at;
            at = if reversed { ends[k].0 } else { ends[k].1 };
            sides.push((k, reversed));
        }
        let length = sides
            .iter()
            .map(|&(k, _)| polyline_length(&faces[free[k].face], free[k].edge))
            .sum();
        holes.push(Hole {
            sides: sides
                .into_iter()
                .map(|(k, reversed)| Side {
                    face: free[k].face,
                    edge: free[k].edge,
                    reversed,
                })
                .collect(),
            length,
        });
    }
    holes.sort_by(|a, b| b.length.total_cmp(&a.length));
    Ok(holes)
}

/// The length of a polygon through 33 points of the edge.
fn polyline_length(face: &BSplineSurface, edge: Edge) -> f64 {
    let pts: Vec<Vec3> = (0..=32)
        .map(|k| edge_point(face, edge, k as f64 / 32.0))
        .collect();
    pts.windows(2).map(|w| dist(w[0], w[1])).sum()
}
