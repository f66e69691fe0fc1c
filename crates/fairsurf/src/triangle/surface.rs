//! Surfaces of triangular Bézier patches over a triangle mesh (Veltkamp &
//! Wesselink §2: "a continuous piecewise Bézier surface consists of a
//! collection of abutting Bézier triangles" whose control points on common
//! edges coincide).
//!
//! The global numbering of the control points is documented on
//! [`TriSurface`].

use super::index::{checked_point_count, linear_index, multi_indices, point_count};
use super::patch::TriPatch;
use crate::vec3::{add, is_finite, scale, Vec3};
use crate::{Error, Result};
use std::collections::HashMap;

/// An undirected edge of the mesh of a [`TriSurface`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshEdge {
    /// The two vertices, smaller first.
    pub vertices: [usize; 2],
    /// The incident triangles: `[0]` runs the edge from `vertices[0]` to
    /// `vertices[1]` (in its corner order, counter-clockwise), `[1]` the
    /// other way. A consistently oriented manifold mesh has at most one of
    /// each; a boundary edge has exactly one.
    pub triangles: [Option<usize>; 2],
}

impl MeshEdge {
    /// True when the edge has one incident triangle.
    pub fn is_boundary(&self) -> bool {
        self.triangles[0].is_none() || self.triangles[1].is_none()
    }
}

/// A C0 surface of triangular Bézier patches of degree n ≥ 1 over a
/// consistently oriented manifold triangle mesh, the patches sharing their
/// control points along common edges and at vertices. Any number of
/// triangles, vertices of any valence, holes and N-sided regions.
///
/// # Global numbering
///
/// Patches share control points, so C0 holds by construction. With V mesh
/// vertices, E undirected mesh edges, T triangles and degree n:
///
/// ```text
/// 0 … V−1                      one point per mesh vertex (point v is vertex v)
/// V + e(n−1) + r − 1           edge e's points r = 1 … n−1, counted from its smaller vertex
/// V + E(n−1) + t·I + l         triangle t's interior points, I = (n−1)(n−2)/2,
///                              l = linear_index(n−3, i−1, j−1, k−1)
/// ```
///
/// Edges are numbered by their sorted vertex pairs (a, b), a < b, in
/// lexicographic order. In patch t with corners (a, b, c) = `triangles[t]`, the
/// point P_ijk belongs to vertex a, b or c when i, j or k is n; to the mesh
/// edge opposite corner m when only the m-th index is 0, at position r = the
/// entry of (i, j, k) belonging to the corner that is the edge's larger
/// vertex; otherwise to the triangle's interior. Both patches along an edge thus name the same
/// globals in the same order.
///
/// # Example
///
/// ```
/// use fairsurf::TriSurface;
/// // A square split into two triangles, as cubics.
/// let vertices = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
/// let s = TriSurface::try_new(&vertices, &[[0, 1, 2], [0, 2, 3]], 3).unwrap();
/// // 4 vertices + 5 edges × 2 + 2 triangles × 1 interior point.
/// assert_eq!(s.point_count(), 16);
/// // The diagonal 0–2 is shared: both patches see the same control points.
/// let (a, b) = (s.patch(0), s.patch(1));
/// assert_eq!(a.edge(1).points()[1], b.edge(2).points()[2]);
/// assert_eq!(s.boundary_vertices(), vec![0, 1, 2, 3]);
/// assert_eq!(s.boundary_edges().len(), 4);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct TriSurface {
    degree: usize,
    vertex_count: usize,
    triangles: Vec<[usize; 3]>,
    edges: Vec<MeshEdge>,
    /// Edge of triangle t opposite its corner m.
    triangle_edges: Vec<[usize; 3]>,
    /// Global index of P_ijk of patch t at `map[t·N + linear_index(n, i, j, k)]`.
    map: Vec<usize>,
    points: Vec<Vec3>,
}

impl TriSurface {
    /// The control net's edges as pairs of global point indices (i < j),
    /// each once: in every patch, each control point joined to its
    /// neighbours of the Bézier triangle (the lines a net is drawn with).
    pub fn net_edges(&self) -> Vec<[usize; 2]> {
        let n = self.degree();
        let mut edges = std::collections::BTreeSet::new();
        for t in 0..self.patch_count() {
            let idx = self.patch_indices(t);
            for [i, j, k] in super::multi_indices(n) {
                let at = |i: usize, j: usize, k: usize| idx[super::linear_index(n, i, j, k)];
                let a = at(i, j, k);
                let mut add = |b: usize| {
                    edges.insert([a.min(b), a.max(b)]);
                };
                if i > 0 {
                    add(at(i - 1, j + 1, k));
                    add(at(i - 1, j, k + 1));
                }
                if j > 0 {
                    add(at(i, j - 1, k + 1));
                }
            }
        }
        edges.into_iter().collect()
    }

    /// The surface over a mesh; see [`TriSurface::try_new`].
    ///
    /// # Panics
    /// If the mesh or degree is invalid.
    pub fn new(vertices: &[Vec3], triangles: &[[usize; 3]], degree: usize) -> Self {
        Self::try_new(vertices, triangles, degree).expect("TriSurface::new")
    }

    /// The degree-n surface over the mesh (`vertices`, `triangles`), each
    /// triangle's corners in counter-clockwise order about its normal; the
    /// control points are those of the flat triangles raised to degree n:
    /// P_ijk = (i V_a + j V_b + k V_c)/n.
    ///
    /// Errors ([`Error::Mismatch`] unless said otherwise; `what` names the
    /// triangle, vertex or edge): degree 0; no triangles; a non-finite vertex
    /// ([`Error::NotFinite`]); a vertex index out of range; a degenerate
    /// triangle (a repeated vertex); an edge with more than two triangles
    /// (non-manifold); two triangles running a shared edge the same way
    /// (inconsistent orientation); a vertex used by no triangle.
    pub fn try_new(vertices: &[Vec3], triangles: &[[usize; 3]], degree: usize) -> Result<Self> {
        check_inputs(vertices, triangles, degree)?;
        let (edges, triangle_edges) = build_edges(triangles)?;
        check_all_used(vertices.len(), triangles)?;
        let per = checked_point_count(degree)
            .filter(|&p| p.checked_mul(triangles.len()).is_some())
            .ok_or_else(|| too_large(degree, triangles.len()))?;
        let mut surface = Self {
            degree,
            vertex_count: vertices.len(),
            triangles: triangles.to_vec(),
            edges,
            triangle_edges,
            map: Vec::with_capacity(per * triangles.len()),
            points: Vec::new(),
        };
        for t in 0..triangles.len() {
            for m in multi_indices(degree) {
                let g = surface.locate(t, m);
                surface.map.push(g);
            }
        }
        surface.points = surface.flat_points(vertices);
        Ok(surface)
    }

    /// The degree n of every patch.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Number of patches (mesh triangles).
    pub fn patch_count(&self) -> usize {
        self.triangles.len()
    }

    /// Number of mesh vertices; global points 0 … V−1 are the vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// The mesh triangles, corners in the order of the patches' V₁, V₂, V₃.
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// The undirected mesh edges, sorted by their vertex pairs.
    pub fn edges(&self) -> &[MeshEdge] {
        &self.edges
    }

    /// The edges of triangle t: entry m is the edge opposite corner m, which
    /// is the patch's edge m ([`TriPatch::edge`]).
    ///
    /// # Panics
    /// If t is out of range.
    pub fn triangle_edges(&self, t: usize) -> [usize; 3] {
        self.triangle_edges[t]
    }

    /// Number of global control points: V + E(n−1) + T(n−1)(n−2)/2.
    pub fn point_count(&self) -> usize {
        self.points.len()
    }

    /// All global control points.
    pub fn points(&self) -> &[Vec3] {
        &self.points
    }

    /// Replaces global control point g; every patch using it moves.
    ///
    /// # Panics
    /// If g is out of range or p is not finite.
    pub fn set_point(&mut self, g: usize, p: Vec3) {
        assert!(is_finite(p), "control points must be finite");
        self.points[g] = p;
    }

    /// Replaces all global control points, or an error naming a wrong count
    /// ([`Error::Mismatch`]) or the first non-finite point ([`Error::NotFinite`]).
    pub fn set_points(&mut self, points: Vec<Vec3>) -> Result<()> {
        if points.len() != self.points.len() {
            return Err(Error::Mismatch {
                what: "global control points of a triangular surface".into(),
                expected: self.points.len().to_string(),
                got: points.len().to_string(),
            });
        }
        if let Some(g) = points.iter().position(|&p| !is_finite(p)) {
            return Err(Error::NotFinite {
                what: format!("global control point {g}"),
            });
        }
        self.points = points;
        Ok(())
    }

    /// The global indices of patch t's control points in the patch's storage
    /// order ([`super::linear_index`]), (n+1)(n+2)/2 of them.
    ///
    /// # Panics
    /// If t is out of range.
    pub fn patch_indices(&self, t: usize) -> &[usize] {
        let per = point_count(self.degree);
        &self.map[t * per..(t + 1) * per]
    }

    /// The global index of P_ijk of patch t.
    ///
    /// # Panics
    /// If t is out of range or i + j + k ≠ n.
    pub fn global_index(&self, t: usize, i: usize, j: usize, k: usize) -> usize {
        self.patch_indices(t)[linear_index(self.degree, i, j, k)]
    }

    /// Patch t assembled from the global control points.
    ///
    /// # Panics
    /// If t is out of range.
    pub fn patch(&self, t: usize) -> TriPatch {
        let pts = self.patch_indices(t).iter().map(|&g| self.points[g]);
        TriPatch::new(self.degree, pts.collect())
    }

    /// Every patch, in triangle order.
    pub fn patches(&self) -> impl Iterator<Item = TriPatch> + '_ {
        (0..self.patch_count()).map(|t| self.patch(t))
    }

    /// The n + 1 global indices along edge e, from `vertices[0]` to
    /// `vertices[1]` (both included).
    ///
    /// # Panics
    /// If e is out of range.
    pub fn edge_points(&self, e: usize) -> Vec<usize> {
        let [a, b] = self.edges[e].vertices;
        let first = self.vertex_count + e * (self.degree - 1);
        let mut out = Vec::with_capacity(self.degree + 1);
        out.push(a);
        out.extend(first..first + self.degree - 1);
        out.push(b);
        out
    }

    /// The boundary edges (one incident triangle), ascending.
    pub fn boundary_edges(&self) -> Vec<usize> {
        (0..self.edges.len())
            .filter(|&e| self.edges[e].is_boundary())
            .collect()
    }

    /// The vertices on a boundary edge, ascending.
    pub fn boundary_vertices(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self
            .boundary_edges()
            .into_iter()
            .flat_map(|e| self.edges[e].vertices)
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// The global control points on the boundary (boundary vertices and the
    /// points of boundary edges), ascending.
    pub fn boundary_points(&self) -> Vec<usize> {
        let mut g: Vec<usize> = self
            .boundary_edges()
            .into_iter()
            .flat_map(|e| self.edge_points(e))
            .collect();
        g.sort_unstable();
        g.dedup();
        g
    }

    /// True when no edge is a boundary edge.
    pub fn is_closed(&self) -> bool {
        self.edges.iter().all(|e| !e.is_boundary())
    }

    /// The global index of the multi-index `m` of patch t (see the module
    /// documentation).
    fn locate(&self, t: usize, m: [usize; 3]) -> usize {
        let (n, tri, v) = (self.degree, self.triangles[t], self.vertex_count);
        if let Some(c) = m.iter().position(|&x| x == n) {
            return tri[c];
        }
        if let Some(c) = m.iter().position(|&x| x == 0) {
            let e = self.triangle_edges[t][c];
            let larger = self.edges[e].vertices[1];
            let at = (0..3).find(|&x| tri[x] == larger).expect("edge of t");
            return v + e * (n - 1) + m[at] - 1;
        }
        let interior = point_count(n - 3);
        let l = linear_index(n - 3, m[0] - 1, m[1] - 1, m[2] - 1);
        v + self.edges.len() * (n - 1) + t * interior + l
    }

    /// The degree-raised flat triangles: each global point from one patch
    /// that uses it, P_ijk = (i V_a + j V_b + k V_c)/n (vertices copied).
    fn flat_points(&self, vertices: &[Vec3]) -> Vec<Vec3> {
        let total = self.map.iter().max().map_or(0, |&g| g + 1);
        let mut pts = vec![[0.0; 3]; total];
        pts[..vertices.len()].copy_from_slice(vertices);
        let n = self.degree as f64;
        for (t, tri) in self.triangles.iter().enumerate() {
            for (l, m) in multi_indices(self.degree).enumerate() {
                let g = self.patch_indices(t)[l];
                if g >= self.vertex_count {
                    let p = (0..3).fold([0.0; 3], |s, c| {
                        add(s, scale(vertices[tri[c]], m[c] as f64))
                    });
                    pts[g] = scale(p, 1.0 / n);
                }
            }
        }
        pts
    }
}

fn too_large(degree: usize, triangles: usize) -> Error {
    Error::Mismatch {
        what: "size of a triangular surface".into(),
        expected: "a control-point count that fits in usize".into(),
        got: format!("degree {degree} with {triangles} triangles"),
    }
}

/// Degree, triangle count, finite vertices, indices in range, no repeats.
fn check_inputs(vertices: &[Vec3], triangles: &[[usize; 3]], degree: usize) -> Result<()> {
    if degree == 0 {
        return Err(Error::Mismatch {
            what: "degree of a triangular surface".into(),
            expected: "n ≥ 1 (patches share their edges)".into(),
            got: "0".into(),
        });
    }
    if triangles.is_empty() {
        return Err(Error::Mismatch {
            what: "triangles of a triangular surface".into(),
            expected: "at least one".into(),
            got: "none".into(),
        });
    }
    if let Some(v) = vertices.iter().position(|&p| !is_finite(p)) {
        return Err(Error::NotFinite {
            what: format!("mesh vertex {v}"),
        });
    }
    for (t, tri) in triangles.iter().enumerate() {
        if tri.iter().any(|&v| v >= vertices.len()) {
            return Err(Error::Mismatch {
                what: format!("vertex indices of triangle {t}"),
                expected: format!("< {} (the number of vertices)", vertices.len()),
                got: format!("{tri:?}"),
            });
        }
        if tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0] {
            return Err(Error::Mismatch {
                what: format!("triangle {t}"),
                expected: "three distinct vertices (a repeated vertex is degenerate)".into(),
                got: format!("{tri:?}"),
            });
        }
    }
    Ok(())
}

/// Every vertex is a corner of some triangle.
fn check_all_used(vertex_count: usize, triangles: &[[usize; 3]]) -> Result<()> {
    let mut used = vec![false; vertex_count];
    triangles.iter().flatten().for_each(|&v| used[v] = true);
    match used.iter().position(|&u| !u) {
        Some(v) => Err(Error::Mismatch {
            what: format!("mesh vertex {v}"),
            expected: "a corner of at least one triangle".into(),
            got: "used by no triangle".into(),
        }),
        None => Ok(()),
    }
}

/// The sorted undirected edges with their incident triangles, and each
/// triangle's edge opposite each corner; errors for non-manifold edges and
/// inconsistent orientation.
fn build_edges(triangles: &[[usize; 3]]) -> Result<(Vec<MeshEdge>, Vec<[usize; 3]>)> {
    // (a, b) with a < b → incident (triangle, runs a → b).
    let mut incident: HashMap<[usize; 2], Vec<(usize, bool)>> = HashMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        for m in 0..3 {
            let (p, q) = (tri[(m + 1) % 3], tri[(m + 2) % 3]);
            let key = [p.min(q), p.max(q)];
            incident.entry(key).or_default().push((t, p < q));
        }
    }
    let mut keys: Vec<[usize; 2]> = incident.keys().copied().collect();
    keys.sort_unstable();
    let mut edges = Vec::with_capacity(keys.len());
    let mut id = HashMap::with_capacity(keys.len());
    for key in keys {
        let inc = &incident[&key];
        edges.push(mesh_edge(key, inc)?);
        id.insert(key, edges.len() - 1);
    }
    let triangle_edges = triangles
        .iter()
        .map(|tri| {
            [0, 1, 2].map(|m| {
                let (p, q) = (tri[(m + 1) % 3], tri[(m + 2) % 3]);
                id[&[p.min(q), p.max(q)]]
            })
        })
        .collect();
    Ok((edges, triangle_edges))
}

/// One edge from its incident (triangle, forward) list, or why it is invalid.
fn mesh_edge(key: [usize; 2], inc: &[(usize, bool)]) -> Result<MeshEdge> {
    let [a, b] = key;
    if inc.len() > 2 {
        let ts: Vec<usize> = inc.iter().map(|x| x.0).collect();
        return Err(Error::Mismatch {
            what: format!("mesh edge ({a}, {b})"),
            expected: "at most two incident triangles (a manifold mesh)".into(),
            got: format!("{} triangles {ts:?} (non-manifold)", inc.len()),
        });
    }
    let mut triangles = [None, None];
    for &(t, forward) in inc {
        let slot = usize::from(!forward);
        if let Some(other) = triangles[slot] {
            let (from, to) = if forward { (a, b) } else { (b, a) };
            return Err(Error::Mismatch {
                what: format!("mesh edge ({a}, {b})"),
                expected: "opposite directions in its two triangles (consistent orientation)"
                    .into(),
                got: format!(
                    "{from} → {to} in both triangles {other} and {t} (inconsistent orientation)"
                ),
            });
        }
        triangles[slot] = Some(t);
    }
    Ok(MeshEdge {
        vertices: key,
        triangles,
    })
}
