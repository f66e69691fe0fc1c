//! Tangent-plane (G1) continuity of a triangular surface as linear
//! constraints (Veltkamp & Wesselink §4.3, eq. 9–12), and its measurement.
//!
//! Along an interior edge from vertex A = M₀ to B = M_n, with the edge's
//! control points M_i, the next row of the left patch L_i and of the right
//! patch R_i (i = 0 … n−1, L_i between M_i and M_{i+1}), the three
//! derivatives of degree n − 1 along the edge are
//!
//! ```text
//! E(t) = Σ (M_{i+1} − M_i) B_i(t),  L(t) = Σ (L_i − M_i) B_i(t),  R(t) = Σ (R_i − M_i) B_i(t)
//! ```
//!
//! (along the edge, and across it towards the left and right third
//! corners, each divided by n). The tangent planes agree along the edge
//! when e(t)E + f(t)L + g(t)R = 0 with f, g > 0; with e, f, g linear in t
//! this is linear in the control points, and its n + 1 Bernstein
//! coefficients are
//!
//! ```text
//! (n−m)(e₀E_m + f₀L_m + g₀R_m) + m(e₁E_{m−1} + f₁L_{m−1} + g₁R_{m−1}) = 0,   m = 0 … n.
//! ```
//!
//! m = 0 and m = n are the vertex conditions (eq. 9, 10), the others the
//! edge conditions (eq. 11, 12 for cubics, up to adding eq. 9 or 10). The
//! coefficients come from the vertex rules of §4.3, written without
//! division (the paper's e = 1, f = g = −1/(2cos θ) times −2cos θ, which
//! also covers its valence-4 case e = 0, f = g = 1):
//!
//! ```text
//! interior vertex of valence k:       d_{i−1} + d_{i+1} − 2cos(2π/k) d_i = 0
//! boundary vertex, k patches, angle α: d_{i−1} + d_{i+1} − 2cos(α/k) d_i = 0   (interior edges i)
//! ```
//!
//! for the tangents d_i = (first control point along edge i) − (vertex) in
//! order around the vertex: at A, (e₀, f₀, g₀) = (−2cos θ_A, 1, 1). At B the
//! paper sets "e₁, f₁, g₁ analogously", but L_{n−1} − M_{n−1} is not B's
//! tangent: it is d_L − d_M with d_M = M_{n−1} − M_n, so matching B's rule
//! needs (e₁, f₁, g₁) = (2cos θ_B − 2, 1, 1).
//!
//! The relaxed variant keeps only one condition per inner edge segment,
//! e(t_r)(M_{r+1} − M_r) + f(t_r)(L_r − M_r) + g(t_r)(R_r − M_r) = 0 at
//! t_r = r/(n−1), r = 1 … n−2 (the paper's e₂, f₂, g₂ for cubics): n − 2
//! conditions instead of n − 1, approximate G1 only.

use super::index::{index_of, linear_index};
use super::surface::TriSurface;
use crate::basis::bernstein_all;
use crate::constraint::Row;
use crate::vec3::{add, angle, cross, dot, normalize, scale, sub, Vec3};
use crate::{Error, Result};
use std::f64::consts::PI;

/// Tangent-plane continuity across the interior edges (§4.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EdgeContinuity {
    /// Exact G1 along each interior edge (eq. 11–12 and their degree-n form).
    #[default]
    Exact,
    /// The paper's less restrictive variant: approximate G1.
    Relaxed,
    /// Only what the vertex conditions give (G1 at the vertices).
    Off,
}

/// An explicit tangent rule at a boundary vertex ([`Continuity::boundary_rules`]):
/// the vertex and its weight on each of its three neighbours.
pub type BoundaryRule = (usize, [(usize, f64); 3]);

/// Which default continuity constraints apply (§4.3). They yield to the
/// user's interpolation constraints: a condition that contradicts them is
/// dropped and reported.
#[derive(Clone, Debug, PartialEq)]
pub struct Continuity {
    /// G1 at the vertices (eq. 9–10). Default on.
    pub vertices: bool,
    /// G1 across the edges. Default [`EdgeContinuity::Exact`].
    pub edges: EdgeContinuity,
    /// The angle α (radians, in (0, 2π)) the surface makes at a boundary
    /// vertex, by vertex. Where not given it is measured in the net being
    /// solved (the angle between the two boundary edges' first tangents;
    /// π for a straight boundary, the paper's default).
    pub boundary_angles: Vec<(usize, f64)>,
    /// Explicit tangent rules at boundary vertices where two patches meet
    /// (one interior edge), by vertex: Σ w_y·d_y = 0 over the vertex's three
    /// neighbours y (the two along the boundary and the interior edge's
    /// other end), d_y the first control point along the edge towards y
    /// minus the vertex. They replace the angle rule there; on a straight
    /// boundary (α = π) the angle rule asks d_{i−1} + d_{i+1} = 0, tangents
    /// of equal length, where |d_{i+1}|·d_{i−1} + |d_{i−1}|·d_{i+1} = 0
    /// asks only that they be opposite (the fan of a hole whose side runs
    /// on through a knot, [`crate::fill::fill_fan`]). The weights along the
    /// boundary must be positive.
    pub boundary_rules: Vec<BoundaryRule>,
}

impl Default for Continuity {
    fn default() -> Self {
        Self {
            vertices: true,
            edges: EdgeContinuity::Exact,
            boundary_angles: Vec::new(),
            boundary_rules: Vec::new(),
        }
    }
}

impl Continuity {
    /// No continuity constraints (C0 only).
    pub fn none() -> Self {
        Self {
            vertices: false,
            edges: EdgeContinuity::Off,
            boundary_angles: Vec::new(),
            boundary_rules: Vec::new(),
        }
    }

    /// The condition rows for `surface` (each three, one per coordinate,
    /// with the same coefficients), vertex conditions first; or an error
    /// naming a bad boundary angle.
    pub fn rows(&self, surface: &TriSurface) -> Result<Vec<Row>> {
        let n = surface.degree();
        let mut vertex_theta = self.vertex_angles(surface)?;
        self.check_rules(surface)?;
        let rules = &self.boundary_rules;
        for &(x, _) in rules {
            vertex_theta[x] = 0.0; // finite: the rule applies there
        }
        let rule = |x: usize| rules.iter().find(|r| r.0 == x).map(|r| r.1);
        let mut vertex_rows = Vec::new();
        let mut edge_rows = Vec::new();
        for (e, edge) in surface.edges().iter().enumerate() {
            let Some(nb) = EdgeNeighbourhood::new(surface, e) else {
                continue;
            };
            let [a, b] = edge.vertices;
            let (ta, tb) = (vertex_theta[a], vertex_theta[b]);
            // The rule f·d_L + g·d_R − c·d_M = 0 at A reads (e₀, f₀, g₀) =
            // (−c, f, g); at B (e₁, f₁, g₁) = (c − f − g, f, g) (d_M towards
            // the other end, d_L and d_R towards the patches' third corners).
            let weight =
                |w: [(usize, f64); 3], y: usize| w.iter().find(|p| p.0 == y).map_or(0.0, |p| p.1);
            let start = match rule(a) {
                Some(w) => {
                    Coefficients::new(weight(w, b), weight(w, nb.third[0]), weight(w, nb.third[1]))
                }
                None => Coefficients::new(-2.0 * ta.cos(), 1.0, 1.0),
            };
            let end = match rule(b) {
                Some(w) => {
                    let (f, g) = (weight(w, nb.third[0]), weight(w, nb.third[1]));
                    Coefficients {
                        sum: Some(-weight(w, a)),
                        ..Coefficients::new(-weight(w, a) - f - g, f, g)
                    }
                }
                None => Coefficients::new(2.0 * tb.cos() - 2.0, 1.0, 1.0),
            };
            let label = format!("edge {a}–{b}");
            if self.vertices {
                if ta.is_finite() {
                    let terms = nb.condition(0, start, 0, n as f64);
                    push_xyz(
                        &mut vertex_rows,
                        &terms,
                        &format!("G1 at vertex {a} along {label}"),
                    );
                }
                if tb.is_finite() {
                    let terms = nb.condition(n - 1, end, n - 1, n as f64);
                    push_xyz(
                        &mut vertex_rows,
                        &terms,
                        &format!("G1 at vertex {b} along {label}"),
                    );
                }
            }
            if !(ta.is_finite() && tb.is_finite()) {
                continue;
            }
            match self.edges {
                EdgeContinuity::Exact => {
                    for m in 1..n {
                        let mut terms = nb.condition(m, start, m, (n - m) as f64);
                        terms.extend(nb.condition(m - 1, end, m - 1, m as f64));
                        let name = format!("G1 across {label} (condition {m} of {})", n - 1);
                        push_xyz(&mut edge_rows, &merge(terms), &name);
                    }
                }
                EdgeContinuity::Relaxed => {
                    for r in 1..n.saturating_sub(1) {
                        let t = r as f64 / (n - 1) as f64;
                        let c = start.lerp(end, t);
                        let name =
                            format!("G1 (relaxed) across {label} (condition {r} of {})", n - 2);
                        push_xyz(&mut edge_rows, &nb.condition(r, c, r, 1.0), &name);
                    }
                }
                EdgeContinuity::Off => {}
            }
        }
        vertex_rows.extend(edge_rows);
        Ok(vertex_rows)
    }

    /// Checks the explicit boundary rules: each at a boundary vertex of two
    /// patches, one per vertex, its weights on its three neighbours,
    /// positive along the boundary, finite.
    fn check_rules(&self, surface: &TriSurface) -> Result<()> {
        let v = surface.vertex_count();
        let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); v];
        let mut on_boundary: Vec<Vec<usize>> = vec![Vec::new(); v];
        for edge in surface.edges() {
            let [a, b] = edge.vertices;
            neighbours[a].push(b);
            neighbours[b].push(a);
            if edge.is_boundary() {
                on_boundary[a].push(b);
                on_boundary[b].push(a);
            }
        }
        for (r, &(x, w)) in self.boundary_rules.iter().enumerate() {
            let what = format!("boundary rule at vertex {x}");
            if x >= v {
                return Err(Error::Mismatch {
                    what,
                    expected: "a vertex of the surface".into(),
                    got: format!("vertex {x} of {v}"),
                });
            }
            if self.boundary_rules[..r].iter().any(|p| p.0 == x) {
                return Err(Error::Mismatch {
                    what,
                    expected: "one rule per vertex".into(),
                    got: "a second rule".into(),
                });
            }
            let fits = on_boundary[x].len() == 2 && neighbours[x].len() == 3 && {
                let mut ys: Vec<usize> = w.iter().map(|p| p.0).collect();
                let mut ns = neighbours[x].clone();
                ys.sort_unstable();
                ns.sort_unstable();
                ys == ns
            };
            if !fits {
                return Err(Error::Mismatch {
                    what,
                    expected: "a boundary vertex of two patches, weights on its three neighbours"
                        .into(),
                    got: format!("{w:?}"),
                });
            }
            let along_boundary_positive = w
                .iter()
                .filter(|p| on_boundary[x].contains(&p.0))
                .all(|p| p.1 > 0.0);
            if !(along_boundary_positive && w.iter().all(|p| p.1.is_finite())) {
                return Err(Error::Mismatch {
                    what,
                    expected: "finite weights, positive along the boundary".into(),
                    got: format!("{w:?}"),
                });
            }
        }
        Ok(())
    }

    /// θ for each vertex's rule: 2π/k inside, α/k on the boundary (k
    /// incident patches); NaN where no rule applies (a boundary vertex of
    /// one patch, or one where the boundary is not a simple fan).
    fn vertex_angles(&self, surface: &TriSurface) -> Result<Vec<f64>> {
        let v = surface.vertex_count();
        let mut valence = vec![0usize; v];
        for t in surface.triangles() {
            for &c in t {
                valence[c] += 1;
            }
        }
        let mut boundary: Vec<Vec<usize>> = vec![Vec::new(); v];
        for e in surface.boundary_edges() {
            for &x in &surface.edges()[e].vertices {
                boundary[x].push(e);
            }
        }
        let mut theta: Vec<f64> = (0..v)
            .map(|x| match boundary[x].len() {
                0 => 2.0 * PI / valence[x] as f64,
                2 if valence[x] >= 2 => {
                    measured_angle(surface, x, [boundary[x][0], boundary[x][1]]) / valence[x] as f64
                }
                _ => f64::NAN,
            })
            .collect();
        for &(x, alpha) in &self.boundary_angles {
            let what = format!("boundary angle at vertex {x}");
            if x >= v || boundary[x].is_empty() {
                return Err(Error::Mismatch {
                    what,
                    expected: "a boundary vertex".into(),
                    got: if x >= v {
                        format!("vertex {x} of {v}")
                    } else {
                        format!("interior vertex {x}")
                    },
                });
            }
            if !(alpha.is_finite() && alpha > 0.0 && alpha < 2.0 * PI) {
                return Err(Error::Mismatch {
                    what,
                    expected: "an angle in (0, 2π) radians".into(),
                    got: alpha.to_string(),
                });
            }
            if valence[x] >= 2 && boundary[x].len() == 2 {
                theta[x] = alpha / valence[x] as f64;
            }
        }
        Ok(theta)
    }
}

/// The angle at vertex x between its two boundary edges' first tangents.
fn measured_angle(surface: &TriSurface, x: usize, edges: [usize; 2]) -> f64 {
    let p = surface.points();
    let d = edges.map(|e| {
        let g = surface.edge_points(e);
        let next = if g[0] == x { g[1] } else { g[g.len() - 2] };
        sub(p[next], p[x])
    });
    let a = angle(d[0], d[1]);
    if a > 1e-9 {
        a
    } else {
        PI
    }
}

#[derive(Clone, Copy, Debug)]
struct Coefficients {
    e: f64,
    f: f64,
    g: f64,
    /// e + f + g given exactly (an explicit rule's −w_a at B, 0 when the
    /// rule puts no weight on the spoke): the coefficient of M_j is then
    /// not left to the rounding of e + f + g, whose ~1e-16 would make a
    /// row of fixed points hold one free point by a rounding-sized
    /// coefficient (a singular KKT system).
    sum: Option<f64>,
}

impl Coefficients {
    fn new(e: f64, f: f64, g: f64) -> Self {
        Self { e, f, g, sum: None }
    }

    fn lerp(self, other: Self, t: f64) -> Self {
        let l = |a: f64, b: f64| a + t * (b - a);
        Self::new(l(self.e, other.e), l(self.f, other.f), l(self.g, other.g))
    }
}

/// The control points around an interior edge: M_0 … M_n along it (from
/// its smaller vertex), L_0 … L_{n−1} and R_0 … R_{n−1} in the next rows of
/// the patch running it forwards and backwards.
struct EdgeNeighbourhood {
    m: Vec<usize>,
    l: Vec<usize>,
    r: Vec<usize>,
    /// The third corners of the left and the right patch.
    third: [usize; 2],
}

impl EdgeNeighbourhood {
    fn new(surface: &TriSurface, e: usize) -> Option<Self> {
        let edge = surface.edges()[e];
        let (left, right) = (edge.triangles[0]?, edge.triangles[1]?);
        let row = |t: usize| next_row(surface, t, edge.vertices);
        let third = |t: usize| {
            surface.triangles()[t]
                .into_iter()
                .find(|c| !edge.vertices.contains(c))
                .expect("a triangle's third corner")
        };
        Some(Self {
            m: surface.edge_points(e),
            l: row(left),
            r: row(right),
            third: [third(left), third(right)],
        })
    }

    /// Terms (point, coefficient) of s·(c.e(M_{i+1} − M_i) + c.f(L_j − M_j) + c.g(R_j − M_j)).
    fn condition(&self, i: usize, c: Coefficients, j: usize, s: f64) -> Vec<(usize, f64)> {
        if let (Some(sum), true) = (c.sum, i == j) {
            return merge(vec![
                (self.m[i + 1], s * c.e),
                (self.m[i], -s * sum),
                (self.l[j], s * c.f),
                (self.r[j], s * c.g),
            ]);
        }
        merge(vec![
            (self.m[i + 1], s * c.e),
            (self.m[i], -s * c.e),
            (self.l[j], s * c.f),
            (self.m[j], -s * c.f),
            (self.r[j], s * c.g),
            (self.m[j], -s * c.g),
        ])
    }
}

/// The n points next to the edge (a, b) in triangle t, from a's end: the
/// multi-index with n−1−i at a's corner, i at b's and 1 at the third.
fn next_row(surface: &TriSurface, t: usize, [a, b]: [usize; 2]) -> Vec<usize> {
    let n = surface.degree();
    let tri = surface.triangles()[t];
    let corner = |x: usize| (0..3).find(|&c| tri[c] == x).expect("edge of its triangle");
    let (ca, cb) = (corner(a), corner(b));
    let cc = 3 - ca - cb;
    let g = surface.patch_indices(t);
    (0..n)
        .map(|i| {
            let mut m = [0; 3];
            m[ca] = n - 1 - i;
            m[cb] = i;
            m[cc] = 1;
            g[index_of(n, m)]
        })
        .collect()
}

/// Sums coefficients of repeated points and drops zeros.
fn merge(mut terms: Vec<(usize, f64)>) -> Vec<(usize, f64)> {
    terms.sort_by_key(|&(g, _)| g);
    let mut out: Vec<(usize, f64)> = Vec::with_capacity(terms.len());
    for (g, a) in terms {
        match out.last_mut() {
            Some(last) if last.0 == g => last.1 += a,
            _ => out.push((g, a)),
        }
    }
    out.retain(|&(_, a)| a.abs() > 1e-15);
    out
}

fn push_xyz(rows: &mut Vec<Row>, terms: &[(usize, f64)], name: &str) {
    for (c, axis) in ["x", "y", "z"].iter().enumerate() {
        rows.push(Row {
            terms: terms.iter().map(|&(g, a)| (3 * g + c, a)).collect(),
            rhs: 0.0,
            name: format!("{name}, {axis}"),
        });
    }
}

/// The tangent-plane jump along the interior edges of a surface: the angle
/// (radians) between the two patches' normals at `samples` evenly spaced
/// points of each interior edge (both ends included), the largest over all
/// edges with the edge's vertices, or None when there is no interior edge
/// or no sample has both normals defined.
pub fn max_edge_normal_angle(surface: &TriSurface, samples: usize) -> Option<(f64, [usize; 2])> {
    let samples = samples.max(2);
    let n = surface.degree();
    if n == 0 {
        return None;
    }
    // Bernstein values of degree n − 1 at the samples, shared by all edges.
    let basis: Vec<Vec<f64>> = (0..samples)
        .map(|s| bernstein_all(n - 1, s as f64 / (samples - 1) as f64))
        .collect();
    // The longest chord |n_l − n_r|² of unit normals is the largest angle
    // (2 arcsin(|n − m|/2) rises with it): one angle at the end instead of
    // one arctangent per sample.
    let mut worst: Option<(f64, Vec3, Vec3, [usize; 2])> = None;
    for edge in surface.edges() {
        let (Some(l), Some(r)) = (edge.triangles[0], edge.triangles[1]) else {
            continue;
        };
        let (dl, dr) = (
            edge_derivatives(surface, l, edge.vertices),
            edge_derivatives(surface, r, edge.vertices),
        );
        for b in &basis {
            let normal = |d: &[Vec<Vec3>; 2]| {
                let at = |c: &[Vec3]| {
                    c.iter()
                        .zip(b)
                        .fold([0.0; 3], |acc, (p, w)| add(acc, scale(*p, *w)))
                };
                normalize(cross(at(&d[0]), at(&d[1])))
            };
            let (Some(nl), Some(nr)) = (normal(&dl), normal(&dr)) else {
                continue;
            };
            let d = sub(nl, nr);
            let chord = dot(d, d);
            if worst.is_none_or(|(w, ..)| chord > w) {
                worst = Some((chord, nl, nr, edge.vertices));
            }
        }
    }
    worst.map(|(_, nl, nr, edge)| (angle(nl, nr), edge))
}

/// The derivatives of patch `tri` in the barycentric directions
/// (1, 0, −1) and (0, 1, −1) along its edge from vertex a to vertex b, as
/// the control points of two Bézier curves of degree n − 1 in the edge's
/// parameter (0 at a). On the edge the opposite barycentric is 0, so only
/// the points of the difference nets on that side enter: the curve's j-th
/// point is Σ_c d_c P_{(n−1−j)e_a + j e_b + e_c} (up to the factor n).
/// Their cross product is the patch normal's direction there, as
/// [`TriPatch::normal`](super::TriPatch::normal) gives it.
fn edge_derivatives(surface: &TriSurface, tri: usize, [a, b]: [usize; 2]) -> [Vec<Vec3>; 2] {
    let n = surface.degree();
    let corners = surface.triangles()[tri];
    let ia = corners.iter().position(|&v| v == a).expect("a corner");
    let ib = corners.iter().position(|&v| v == b).expect("a corner");
    let idx = surface.patch_indices(tri);
    let point = |m: [usize; 3]| surface.points()[idx[linear_index(n, m[0], m[1], m[2])]];
    [[1.0, 0.0, -1.0], [0.0, 1.0, -1.0]].map(|d: [f64; 3]| {
        (0..n)
            .map(|j| {
                let mut m = [0; 3];
                m[ia] = n - 1 - j;
                m[ib] = j;
                (0..3).fold([0.0; 3], |acc, c| {
                    let mut mc = m;
                    mc[c] += 1;
                    add(acc, scale(point(mc), d[c]))
                })
            })
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Barycentrics in triangle t of the point at parameter s from a to b.
    fn bary_on_edge(surface: &TriSurface, t: usize, [a, b]: [usize; 2], s: f64) -> [f64; 3] {
        let tri = surface.triangles()[t];
        let mut out = [0.0; 3];
        for c in 0..3 {
            if tri[c] == a {
                out[c] = 1.0 - s;
            } else if tri[c] == b {
                out[c] = s;
            }
        }
        out
    }

    /// The definition: both patches' normals by de Casteljau at each sample.
    fn by_patch_normals(surface: &TriSurface, samples: usize) -> Option<(f64, [usize; 2])> {
        let mut worst: Option<(f64, [usize; 2])> = None;
        for edge in surface.edges() {
            let (Some(l), Some(r)) = (edge.triangles[0], edge.triangles[1]) else {
                continue;
            };
            let (pl, pr) = (surface.patch(l), surface.patch(r));
            for s in 0..samples {
                let t = s as f64 / (samples - 1) as f64;
                let at = |tri: usize| bary_on_edge(surface, tri, edge.vertices, t);
                let (Some(nl), Some(nr)) = (pl.normal(at(l)), pr.normal(at(r))) else {
                    continue;
                };
                let a = angle(nl, nr);
                if worst.is_none_or(|(w, _)| a > w) {
                    worst = Some((a, edge.vertices));
                }
            }
        }
        worst
    }

    /// The edge curves give the patch normals' angles: on a wavy surface
    /// (every edge kinked) the largest agrees with the de Casteljau normals
    /// at every degree, on the same edge.
    #[test]
    fn edge_curves_give_the_patch_normals() {
        let v = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.4, 0.0],
        ];
        // Each triangle's corners rotated (orientation kept) by k + its
        // index, so the interior edges lie at every pair of corner positions.
        let fan = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
        let rotated = |k: usize| -> Vec<[usize; 3]> {
            fan.iter()
                .enumerate()
                .map(|(i, t)| {
                    let r = (k + i) % 3;
                    [t[r], t[(r + 1) % 3], t[(r + 2) % 3]]
                })
                .collect()
        };
        for (n, k) in (1..=6).flat_map(|n| (0..3).map(move |k| (n, k))) {
            let mut s = TriSurface::new(&v, &rotated(k), n);
            let pts = s
                .points()
                .iter()
                .enumerate()
                .map(|(g, p)| [p[0], p[1], 0.3 * ((g * 7919) % 13) as f64 / 13.0])
                .collect();
            s.set_points(pts).unwrap();
            let (fast, at) = max_edge_normal_angle(&s, 33).unwrap();
            let (slow, at_slow) = by_patch_normals(&s, 33).unwrap();
            assert!((fast - slow).abs() < 1e-12, "n = {n}: {fast} vs {slow}");
            assert_eq!(at, at_slow, "n = {n}");
            assert!(fast > 0.01, "n = {n}: the surface is kinked");
        }
    }

    /// A boundary rule is checked: at a boundary vertex of two patches,
    /// with weights on its three neighbours, positive along the boundary;
    /// a straight boundary's rule |d_b|·d_a + |d_a|·d_b = 0 holds on a
    /// plane's fan whose boundary tangents there are opposite and of
    /// unequal length (no row is violated).
    #[test]
    fn boundary_rules_are_checked() {
        // Two triangles (0, 1, 2) and (0, 2, 3) over a plane, vertex 2 on
        // the straight boundary 1–2–3, |1 − 2| = 1 and |3 − 2| = 2.
        let v = [
            [0.0, 1.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
        ];
        let s = TriSurface::new(&v, &[[0, 1, 2], [0, 2, 3]], 3);
        let rows = |rules: Vec<BoundaryRule>| {
            Continuity {
                boundary_rules: rules,
                ..Continuity::default()
            }
            .rows(&s)
        };
        // At 2: weights on vertex 1 (|d_3| ∝ 2) and 3 (|d_1| ∝ 1), none on
        // 0. At 0 (tangents (−1, −1), (2, −1), (0, −1) to 1, 3, 2, each
        // over 3): 2·d_1 + d_3 − 3·d_2 = 0.
        let good = rows(vec![
            (2, [(1, 2.0), (3, 1.0), (0, 0.0)]),
            (0, [(1, 2.0), (3, 1.0), (2, -3.0)]),
        ])
        .unwrap();
        let x: Vec<f64> = s.points().iter().flat_map(|p| *p).collect();
        for r in &good {
            let value: f64 = r.terms.iter().map(|&(c, a)| a * x[c]).sum();
            assert!(value.abs() < 1e-14, "{}: {value}", r.name);
        }
        // The angle rule there asks equal lengths: violated on this net.
        let angle_rule = rows(Vec::new()).unwrap();
        let worst = angle_rule
            .iter()
            .map(|r| r.terms.iter().map(|&(c, a)| a * x[c]).sum::<f64>().abs())
            .fold(0.0, f64::max);
        assert!(worst > 0.1, "{worst}");
        // The same with the apex numbered last (3) and the boundary's
        // middle first (0): the apex's rule, with its weight −3 on the
        // spoke, is now at the edge's end B (e₁ + f₁ + g₁ = 3 given exactly).
        let relabelled = [v[2], v[1], v[3], v[0]];
        let s2 = TriSurface::new(&relabelled, &[[3, 1, 0], [3, 0, 2]], 3);
        let rules2 = |spoke: f64| {
            Continuity {
                boundary_rules: vec![
                    (0, [(1, 2.0), (2, 1.0), (3, 0.0)]),
                    (3, [(1, 2.0), (2, 1.0), (0, spoke)]),
                ],
                ..Continuity::default()
            }
            .rows(&s2)
            .unwrap()
        };
        let x2: Vec<f64> = s2.points().iter().flat_map(|p| *p).collect();
        let worst2 = |rows: &[Row]| {
            rows.iter()
                .map(|r| r.terms.iter().map(|&(c, a)| a * x2[c]).sum::<f64>().abs())
                .fold(0.0, f64::max)
        };
        assert_eq!(rules2(-3.0).len(), good.len());
        assert!(worst2(&rules2(-3.0)) < 1e-14);
        // A wrong sign on the spoke breaks the apex's rows.
        assert!(worst2(&rules2(3.0)) > 0.1);
        let twice = vec![
            (2, [(1, 2.0), (3, 1.0), (0, 0.0)]),
            (2, [(1, 2.0), (3, 1.0), (0, 0.0)]),
        ];
        for bad in [
            twice,
            vec![(1, [(0, 1.0), (2, 1.0), (3, 1.0)])], // vertex 1: on one patch
            vec![(2, [(1, 1.0), (0, 1.0), (0, 0.0)])], // not its three neighbours
            vec![(2, [(1, -1.0), (3, 1.0), (0, 0.0)])], // negative along the boundary
            vec![(2, [(1, f64::NAN), (3, 1.0), (0, 0.0)])],
            vec![(9, [(1, 1.0), (3, 1.0), (0, 0.0)])],
        ] {
            let e = rows(bad.clone()).unwrap_err().to_string();
            assert!(e.contains("boundary rule at vertex"), "{bad:?}: {e}");
        }
    }
}
