//! Holes in a set of faces: the closed loops of free edges. Each face's four
//! boundaries (a boundary collapsed to a point has none) are cut where
//! another boundary's end point lies inside them (a T-junction: a face
//! bordering only part of a neighbour's side); the pieces are compared
//! with every other face's: one that no other piece shares (the same end
//! points, either way round, and points inside on the other's curve) is
//! free. Free pieces are chained at their end points into loops.

use crate::analysis::Edge;
use crate::basis::GaussLegendre;
use crate::bspline::BSplineSurface;
use crate::vec3::{add, bounding_diagonal, cross, dist, dot, norm, scale, sub};
use crate::{Error, Result, Vec3};

/// One side of a hole: a boundary of one face, or the part `range` of it,
/// traversed from `range[0]` to `range[1]` along the boundary's parameter t
/// (the knot domain mapped onto [0, 1]), or back when `reversed`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Side {
    /// Index of the face.
    pub face: usize,
    /// Which boundary.
    pub edge: Edge,
    /// Traversed from t = `range[1]` to t = `range[0]`.
    pub reversed: bool,
    /// The part of the boundary, 0 ≤ `range[0]` < `range[1]` ≤ 1: [0, 1] for
    /// the whole boundary.
    pub range: [f64; 2],
}

impl Side {
    /// The whole boundary `edge` of `face`.
    pub fn whole(face: usize, edge: Edge, reversed: bool) -> Self {
        Self {
            face,
            edge,
            reversed,
            range: [0.0, 1.0],
        }
    }

    /// Whether the side is the face's whole boundary.
    pub fn is_whole(&self) -> bool {
        self.range == [0.0, 1.0]
    }

    /// The boundary's parameter at s ∈ [0, 1] along the side as the hole
    /// runs.
    pub fn boundary_t(&self, s: f64) -> f64 {
        let [a, b] = self.range;
        let s = if self.reversed { 1.0 - s } else { s };
        a + (b - a) * s
    }
}

/// A closed loop of free edges, in traversal order (side k ends where side
/// k + 1 starts).
#[derive(Clone, Debug, PartialEq)]
pub struct Hole {
    /// The sides.
    pub sides: Vec<Side>,
    /// The loop's length (its sides' arc lengths).
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

    /// Whether the loop bounds its faces from outside — the outer rim of
    /// an open sheet — rather than being a hole in them: its vector area
    /// ½∮ x × dx, taken the way each face's own boundary runs (counter-
    /// clockwise in (u, v) about R_u × R_v), against the faces' normals
    /// there. A rim runs around its faces' area (positive), a hole against
    /// it (negative: around a missing piece, whose normals agree with the
    /// faces'), on a sheet and on a closed shell alike. Per side, with its
    /// own face's sense and normal (faces oriented every which way still
    /// agree side by side); None when the sum is not clear (below 1e-9 of
    /// the loop's area scale, or a face without a normal at every side's
    /// middle).
    pub fn bounds_from_outside(&self, faces: &[BSplineSurface]) -> Option<bool> {
        let points = self.points(faces, 16)?;
        let area = vector_area(&points);
        let mut sense = 0.0;
        for side in &self.sides {
            let face = &faces[side.face];
            let (u, v) = surface_param(face, side.edge, 0.5 * (side.range[0] + side.range[1]));
            let d = face.derivatives_on(&[u], &[v])[0];
            let n = d.regular_normal()?;
            // t increasing runs counter-clockwise along V0 and U1.
            let ccw = matches!(side.edge, Edge::V0 | Edge::U1) != side.reversed;
            sense += if ccw { 1.0 } else { -1.0 } * dot(area, n);
        }
        let scale_ = norm(area) * self.sides.len() as f64;
        (sense.abs() > 1e-9 * scale_ && scale_ > 0.0).then_some(sense > 0.0)
    }

    /// Points of the loop as it runs, `per_side` on each side from its
    /// start; None when a side names no face.
    fn points(&self, faces: &[BSplineSurface], per_side: usize) -> Option<Vec<Vec3>> {
        let mut points = Vec::with_capacity(per_side * self.sides.len());
        for side in &self.sides {
            let face = faces.get(side.face)?;
            let [a, b] = side.range;
            for j in 0..per_side {
                let x = j as f64 / per_side as f64;
                let t = if side.reversed {
                    b - (b - a) * x
                } else {
                    a + (b - a) * x
                };
                points.push(edge_point(face, side.edge, t));
            }
        }
        Some(points)
    }

    /// Whether the missing face is a ring between this loop and `other`'s
    /// (a fillet round a boss, whose band left a circle on the plate and
    /// one on the boss; an island face in a hole), so that a fill of this
    /// loop alone would cover `other`'s faces: seen along this loop's
    /// vector area (its mean normal), every point of `other` lies inside
    /// the outline by more than 1e-3 of its size and no farther from the
    /// outline's mean plane than the outline is wide, **and** the missing
    /// face leaves each loop towards the other (the mean over a loop's
    /// points of D̂ · (q − p)/|q − p|, D the cross-boundary derivative into
    /// the hole, q the nearest point of the other loop, above
    /// [`RING_HEADING`] both ways). The second test keeps apart two holes
    /// of a closed shell one above the other (a sphere open at both poles,
    /// a slab with a hole in its top and a smaller one in its bottom: each
    /// missing face leaves its loop away from the other) and a sheet's
    /// outline round a hole in it (the outline's missing face leaves it
    /// outwards). The largest distance of `other`'s points from the plane,
    /// or None.
    pub fn ring_with(&self, faces: &[BSplineSurface], other: &Hole) -> Option<f64> {
        let inner = other.points(faces, 8)?;
        let towards = |a: &Hole, b: &[Vec3]| a.heading(faces, b).is_some_and(|c| c > RING_HEADING);
        // The cheap test first: a hole's missing face seldom heads for
        // another loop (a sheet's outline heads away from its holes).
        if !towards(self, &inner) {
            return None;
        }
        let outline = self.points(faces, 32)?;
        let area = vector_area(&outline);
        let n = crate::vec3::normalize(area)?;
        let size = bounding_diagonal(&outline);
        let centre = scale(
            outline.iter().fold([0.0; 3], |c, p| add(c, *p)),
            1.0 / outline.len() as f64,
        );
        // Axes of the plane.
        let e1 = crate::vec3::normalize(sub(outline[0], centre))
            .map(|e| sub(e, scale(n, dot(e, n))))
            .and_then(crate::vec3::normalize)?;
        let e2 = cross(n, e1);
        let flat = |p: Vec3| {
            let d = sub(p, centre);
            [dot(d, e1), dot(d, e2)]
        };
        let polygon: Vec<[f64; 2]> = outline.iter().map(|&p| flat(p)).collect();
        let mut height = 0.0f64;
        for &q in &inner {
            let h = dot(sub(q, centre), n).abs();
            let q2 = flat(q);
            if !(h <= size
                && inside(&polygon, q2)
                && edge_distance2(&polygon, q2) > (1e-3 * size).powi(2))
            {
                return None;
            }
            height = height.max(h);
        }
        towards(other, &outline).then_some(height)
    }

    /// The mean over the loop's points p (8 per side) of D̂ · (q − p)/|q − p|,
    /// D the cross-boundary derivative into the hole (the way the missing
    /// face leaves the loop), q the nearest of `targets`: near 1 when the
    /// missing face heads for them, negative when it turns away. Points
    /// where D vanishes (a collapsed corner) are left out; None when every
    /// point is, or a side's strip cannot be taken.
    fn heading(&self, faces: &[BSplineSurface], targets: &[Vec3]) -> Option<f64> {
        const PER_SIDE: usize = 8;
        let (mut sum, mut count) = (0.0, 0usize);
        for side in &self.sides {
            let strip = super::strip::Strip::of_side(faces.get(side.face)?, *side).ok()?;
            for j in 0..PER_SIDE {
                let at = strip.at((j as f64 + 0.5) / PER_SIDE as f64);
                let Some(d) = crate::vec3::normalize(at.der) else {
                    continue;
                };
                // The nearest target (squared distances: no roots; the
                // first of equals, NaN ordered as `total_cmp` orders it).
                let d2 = |t: &Vec3| {
                    let e = sub(*t, at.pos);
                    dot(e, e)
                };
                let mut q = *targets.first()?;
                let mut near = d2(&q);
                for t in &targets[1..] {
                    let d = d2(t);
                    if d.total_cmp(&near).is_lt() {
                        (near, q) = (d, *t);
                    }
                }
                if let Some(towards) = crate::vec3::normalize(sub(q, at.pos)) {
                    sum += dot(d, towards);
                    count += 1;
                }
            }
        }
        (count > 0).then(|| sum / count as f64)
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

/// How firmly the missing face must head from each of two nested loops
/// for the other for them to bound one ring ([`Hole::ring_with`]): a
/// fillet band a quarter circle wide heads 0.71 both ways, a flat annulus
/// 1; two holes of a closed shell one above the other head away from each
/// other at least one way (below 0).
pub const RING_HEADING: f64 = 0.25;

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
    range: [f64; 2],
    samples: Vec<Vec3>,
}

impl BoundaryEdge {
    fn new(face: &BSplineSurface, f: usize, edge: Edge, range: [f64; 2]) -> Self {
        let samples = (0..SAMPLES)
            .map(|k| {
                let t = range[0] + (range[1] - range[0]) * k as f64 / (SAMPLES - 1) as f64;
                edge_point(face, edge, t)
            })
            .collect();
        Self {
            face: f,
            edge,
            range,
            samples,
        }
    }

    fn ends(&self) -> (Vec3, Vec3) {
        (self.samples[0], self.samples[SAMPLES - 1])
    }
}

/// Every hole of `faces`: the loops of free edges, longest first. Errors
/// when free edges do not close into loops (the faces do not form
/// surfaces with boundaries made of face edges).
pub fn find_holes(faces: &[BSplineSurface]) -> Result<Vec<Hole>> {
    find_holes_within(faces, tolerance(faces))
}

/// [`find_holes`] with points closer than `tol` taken as one (faces that
/// stand in for rational ones meet only within their fit).
pub fn find_holes_within(faces: &[BSplineSurface], tol: f64) -> Result<Vec<Hole>> {
    find_holes_where(faces, tol, |_, _| true)
}

/// [`find_holes_within`] over the boundaries `is_boundary(face, edge)`
/// says are edges of the model: a strip stand-in along a trimmed face's
/// edge ([`crate::bspline::strip_stand_in`]) has one, its side V0 — its
/// other sides are inside the trimmed face.
pub fn find_holes_where(
    faces: &[BSplineSurface],
    tol: f64,
    is_boundary: impl Fn(usize, Edge) -> bool,
) -> Result<Vec<Hole>> {
    let mut whole = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        for edge in [Edge::V0, Edge::U1, Edge::V1, Edge::U0] {
            if !is_boundary(f, edge) {
                continue;
            }
            let e = BoundaryEdge::new(face, f, edge, [0.0, 1.0]);
            let length: f64 = e.samples.windows(2).map(|w| dist(w[0], w[1])).sum();
            if length > tol {
                whole.push(e);
            }
        }
    }
    // Each boundary cut where another's end point lies inside it.
    let corners: Vec<Vec3> = whole
        .iter()
        .flat_map(|e| [e.ends().0, e.ends().1])
        .collect();
    let mut edges = Vec::new();
    for e in &whole {
        let face = &faces[e.face];
        let (box_lo, box_hi) = boundary_box(face, e.edge, tol);
        let (p0, p1) = e.ends();
        let mut cuts: Vec<f64> = corners
            .iter()
            .filter(|c| (0..3).all(|i| box_lo[i] <= c[i] && c[i] <= box_hi[i]))
            .filter(|c| dist(**c, p0) > tol && dist(**c, p1) > tol)
            .filter_map(|c| {
                let (t, d) = nearest_on_boundary(face, e.edge, [0.0, 1.0], *c);
                (d <= tol && t > 0.0 && t < 1.0).then_some(t)
            })
            .collect();
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|a, b| {
            dist(edge_point(face, e.edge, *a), edge_point(face, e.edge, *b)) <= tol
        });
        let mut start = 0.0;
        for t in cuts.into_iter().chain([1.0]) {
            edges.push(BoundaryEdge::new(face, e.face, e.edge, [start, t]));
            start = t;
        }
    }
    // Two pieces are one edge when their ends meet (either way round) and
    // the points inside one lie on the other's curve.
    // The usual case first: the two pieces sampled alike (the same curve
    // parametrized the same way, either direction), sample for sample
    // within tol — each of a's samples is then within tol of a point of b;
    // else the nearest point of b's curve to each.
    let same = |a: &BoundaryEdge, b: &BoundaryEdge| {
        let ((a0, a1), (b0, b1)) = (a.ends(), b.ends());
        let forward = dist(a0, b0) <= tol && dist(a1, b1) <= tol;
        let backward = dist(a0, b1) <= tol && dist(a1, b0) <= tol;
        let inner = 1..SAMPLES - 1;
        let alike = |k: usize| {
            let j = if forward { k } else { SAMPLES - 1 - k };
            dist(a.samples[k], b.samples[j]) <= tol
        };
        (forward || backward)
            && (inner.clone().all(alike)
                || a.samples[inner]
                    .iter()
                    .all(|p| nearest_on_boundary(&faces[b.face], b.edge, b.range, *p).1 <= tol))
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
        let start_vertex = |&(k, reversed): &(usize, bool)| {
            if reversed {
                ends[k].1
            } else {
                ends[k].0
            }
        };
        for sides in split_at_repeated_vertices(sides, start_vertex) {
            let length = sides
                .iter()
                .map(|&(k, _)| arc_length(&faces[free[k].face], free[k].edge, free[k].range))
                .sum();
            holes.push(Hole {
                sides: sides
                    .into_iter()
                    .map(|(k, reversed)| Side {
                        face: free[k].face,
                        edge: free[k].edge,
                        reversed,
                        range: free[k].range,
                    })
                    .collect(),
                length,
            });
        }
    }
    holes.sort_by(|a, b| b.length.total_cmp(&a.length));
    Ok(holes)
}

/// A closed walk of sides cut into loops that pass each vertex once:
/// where holes touch at a vertex (four or more free edges meet there), the
/// walk may go on into the other hole and come back to the vertex later;
/// the stretch between two visits of a vertex is then a loop of its own
/// (between two holes that touch only there it is exactly one of them),
/// and what is left is again a closed walk. `start` gives the vertex a side
/// starts from (side k + 1 starts where side k ends, the last ends where
/// the first starts).
fn split_at_repeated_vertices<T: Copy>(
    mut walk: Vec<T>,
    start: impl Fn(&T) -> usize,
) -> Vec<Vec<T>> {
    let mut loops = Vec::new();
    'cut: loop {
        for j in 1..walk.len() {
            if let Some(i) = (0..j).find(|&i| start(&walk[i]) == start(&walk[j])) {
                loops.push(walk.drain(i..j).collect());
                continue 'cut;
            }
        }
        break;
    }
    loops.push(walk);
    loops
}

/// ½ Σ p_k × p_(k+1) over a closed polygon: its vector area.
fn vector_area(points: &[Vec3]) -> Vec3 {
    let mut area = [0.0; 3];
    for (k, p) in points.iter().enumerate() {
        area = add(area, scale(cross(*p, points[(k + 1) % points.len()]), 0.5));
    }
    area
}

/// Whether q is inside the closed polygon (its winding number is not 0).
fn inside(polygon: &[[f64; 2]], q: [f64; 2]) -> bool {
    let mut winding = 0i64;
    for (k, a) in polygon.iter().enumerate() {
        let b = polygon[(k + 1) % polygon.len()];
        let side = (b[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (b[1] - a[1]);
        if a[1] <= q[1] && b[1] > q[1] && side > 0.0 {
            winding += 1;
        } else if a[1] > q[1] && b[1] <= q[1] && side < 0.0 {
            winding -= 1;
        }
    }
    winding != 0
}

/// The squared distance from q to the closed polygon's edges.
fn edge_distance2(polygon: &[[f64; 2]], q: [f64; 2]) -> f64 {
    (0..polygon.len())
        .map(|k| {
            let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let l2 = d[0] * d[0] + d[1] * d[1];
            let t = if l2 > 0.0 {
                (((q[0] - a[0]) * d[0] + (q[1] - a[1]) * d[1]) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let e = [q[0] - a[0] - t * d[0], q[1] - a[1] - t * d[1]];
            e[0] * e[0] + e[1] * e[1]
        })
        .fold(f64::INFINITY, f64::min)
}

/// The length of the edge's part `range`: ∫ |dS/dt| dt by 16-point
/// Gauss–Legendre on each knot span of the edge (a polygon through 33
/// points made a unit circle 6.273).
fn arc_length(face: &BSplineSurface, edge: Edge, range: [f64; 2]) -> f64 {
    let (ku, kv) = face.knots();
    let along_u = matches!(edge, Edge::V0 | Edge::V1);
    let k = if along_u { ku } else { kv };
    let (a, b) = k.domain();
    let mut cuts = vec![range[0]];
    cuts.extend(
        k.knots()
            .iter()
            .map(|&x| (x - a) / (b - a))
            .filter(|&t| t > range[0] && t < range[1]),
    );
    cuts.push(range[1]);
    cuts.dedup();
    static RULE: std::sync::OnceLock<GaussLegendre> = std::sync::OnceLock::new();
    let rule = RULE.get_or_init(|| GaussLegendre::new(16));
    // Every node's surface parameter along the edge (the other is fixed),
    // the basis functions once per node.
    let params: Vec<(f64, f64)> = cuts
        .windows(2)
        .flat_map(|w| rule.nodes.iter().map(move |&x| w[0] + (w[1] - w[0]) * x))
        .map(|t| surface_param(face, edge, t))
        .collect();
    let Some(&(u0, v0)) = params.first() else {
        return 0.0;
    };
    let speeds: Vec<f64> = if along_u {
        let us: Vec<f64> = params.iter().map(|p| p.0).collect();
        let d = face.derivatives_on(&us, &[v0]);
        d.iter().map(|d| norm(d.du) * (b - a)).collect()
    } else {
        let vs: Vec<f64> = params.iter().map(|p| p.1).collect();
        let d = face.derivatives_on(&[u0], &vs);
        d.iter().map(|d| norm(d.dv) * (b - a)).collect()
    };
    let n = rule.nodes.len();
    cuts.windows(2)
        .zip(speeds.chunks_exact(n))
        .map(|(w, f)| {
            (w[1] - w[0])
                * rule
                    .weights
                    .iter()
                    .zip(f)
                    .map(|(&w, &f)| w * f)
                    .sum::<f64>()
        })
        .sum()
}

/// The bounding box of the boundary's control points (which hold the
/// curve), widened by `tol`.
fn boundary_box(face: &BSplineSurface, edge: Edge, tol: f64) -> (Vec3, Vec3) {
    let (cu, cv) = face.counts();
    let points: Vec<Vec3> = match edge {
        Edge::U0 => (0..cv).map(|j| face.point(0, j)).collect(),
        Edge::U1 => (0..cv).map(|j| face.point(cu - 1, j)).collect(),
        Edge::V0 => (0..cu).map(|i| face.point(i, 0)).collect(),
        Edge::V1 => (0..cu).map(|i| face.point(i, cv - 1)).collect(),
    };
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &points {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c] - tol);
            hi[c] = hi[c].max(p[c] + tol);
        }
    }
    (lo, hi)
}

/// The boundary parameter t in `range` of the point of the boundary
/// nearest to p, and the distance: the nearest of 33 samples, then Newton
/// steps on (C(t) − p)·C′(t) = 0 kept in the range while they come closer.
fn nearest_on_boundary(face: &BSplineSurface, edge: Edge, range: [f64; 2], p: Vec3) -> (f64, f64) {
    // dC/dt from the surface's derivatives along the boundary's direction.
    let (s0, r0) = edge.param(0.0);
    let (s1, r1) = edge.param(1.0);
    let (ku, kv) = face.knots();
    let ((a, b), (c, d)) = (ku.domain(), kv.domain());
    let (du_dt, dv_dt) = ((s1 - s0) * (b - a), (r1 - r0) * (d - c));
    let curve = |t: f64| {
        let (u, v) = surface_param(face, edge, t);
        let x = face.derivatives(u, v);
        let d1 = add(scale(x.du, du_dt), scale(x.dv, dv_dt));
        let d2 = add(
            add(
                scale(x.duu, du_dt * du_dt),
                scale(x.duv, 2.0 * du_dt * dv_dt),
            ),
            scale(x.dvv, dv_dt * dv_dt),
        );
        [x.point, d1, d2]
    };
    let point = |t: f64| {
        let (u, v) = surface_param(face, edge, t);
        face.eval(u, v)
    };
    crate::curve::nearest_parameter_by(point, curve, (range[0], range[1]), p)
}

#[cfg(test)]
mod tests {
    use super::{arc_length, split_at_repeated_vertices};
    use crate::analysis::Edge;
    use crate::bspline::{BSplineSurface, KnotVector};

    /// An edge's length is its arc length: the parabola (0,0) → (1,1) →
    /// (2,0) of a quadratic × linear face, √2 + asinh 1 (∫₋₁¹ √(1 + x²)
    /// dx), whole and, cut at a knot inserted at its middle, by halves.
    #[test]
    fn an_edge_is_as_long_as_its_arc() {
        let points = vec![
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 0.0],
            [1.0, 1.0, 1.0],
            [2.0, 0.0, 0.0],
            [2.0, 0.0, 1.0],
        ];
        let face =
            BSplineSurface::new(KnotVector::bezier(2), KnotVector::bezier(1), points).unwrap();
        let whole = 2f64.sqrt() + 1f64.asinh();
        assert!((arc_length(&face, Edge::V0, [0.0, 1.0]) - whole).abs() <= 1e-11 * whole);
        let cut = face.insert_knot_u(0.5).unwrap();
        let halves =
            arc_length(&cut, Edge::V0, [0.0, 0.5]) + arc_length(&cut, Edge::V0, [0.5, 1.0]);
        assert!((halves - whole).abs() <= 1e-11 * whole, "{halves}");
        // A straight side: its chord.
        assert!((arc_length(&face, Edge::U0, [0.0, 1.0]) - 1.0).abs() <= 1e-15);
    }

    /// Sides as (start, end) vertices; each loop closes on itself and
    /// every side is in exactly one loop.
    fn loops(walk: &[(usize, usize)]) -> Vec<Vec<(usize, usize)>> {
        let out = split_at_repeated_vertices(walk.to_vec(), |s| s.0);
        for l in &out {
            for (k, s) in l.iter().enumerate() {
                assert_eq!(s.1, l[(k + 1) % l.len()].0, "{l:?} closes");
            }
        }
        assert_eq!(out.iter().map(Vec::len).sum::<usize>(), walk.len());
        out
    }

    #[test]
    fn a_walk_through_a_vertex_twice_is_two_loops() {
        // 5 → 0, then the other hole 0 → 1 → 2 → 0, then 0 → 6 → 5.
        let walk = [(5, 0), (0, 1), (1, 2), (2, 0), (0, 6), (6, 5)];
        let out = loops(&walk);
        assert_eq!(
            out,
            [vec![(0, 1), (1, 2), (2, 0)], vec![(5, 0), (0, 6), (6, 5)]]
        );
        // Three holes at one vertex, and a walk that passes nothing twice.
        let walk = [(0, 1), (1, 0), (0, 2), (2, 3), (3, 0), (0, 4), (4, 0)];
        assert_eq!(loops(&walk).len(), 3);
        let walk = [(0, 1), (1, 2), (2, 0)];
        assert_eq!(loops(&walk), [walk.to_vec()]);
    }
}
