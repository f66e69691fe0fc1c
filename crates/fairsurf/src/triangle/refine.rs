//! Refining a triangular surface without changing its shape: splitting a
//! patch at an interior point (1 → 3) or an edge at a point (2 → 4, or 1 → 2
//! on the boundary), and embedding a chain of mesh edges along which a curve
//! is interpolated (Veltkamp & Wesselink §4.2, Fig. 3).
//!
//! Each split replaces one corner of a triangle by the new vertex: a 1 → 3
//! split at p gives the children with corner 0, 1 and 2 replaced by p
//! ([`TriPatch::subdivide_interior`]), an edge split at q gives, in each
//! incident triangle, the two children with one end of the edge replaced by
//! q ([`TriPatch::subdivide_edge`]). The children keep the parent's corner
//! order, hence its orientation, and their patches are exact pieces of the
//! parent's (Goldman 1983), so the surface does not change.
//!
//! ```
//! use fairsurf::triangle::{DomainPoint, Refinement};
//! use fairsurf::TriSurface;
//! let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
//! let s = TriSurface::new(&v, &[[0, 1, 2]], 3);
//! let (r, vertex) = Refinement::identity(&s).split_triangle(0, [0.2, 0.3, 0.5]).unwrap();
//! assert_eq!((r.surface.patch_count(), vertex), (3, 3));
//! // The point (0.2, 0.3, 0.5) of the original triangle is corner 0 of child 0.
//! let p = r.locate(DomainPoint { triangle: 0, bary: [0.2, 0.3, 0.5] }).unwrap();
//! assert_eq!(r.surface.triangles()[p.triangle], [3, 1, 2]);
//! assert!((p.bary[0] - 1.0).abs() < 1e-15);
//! ```

use super::bernstein::Bary;
use super::patch::TriPatch;
use super::surface::TriSurface;
use crate::vec3::{add, cross, dot, is_finite, scale, Vec3};
use crate::{BezierCurve, Error, Result};
use std::collections::VecDeque;

/// Barycentrics at or below this count as zero when a point is placed on
/// the mesh: such a point lies on an edge (one zero) or at a vertex (two).
const SNAP: f64 = 1e-9;

/// How far below zero a barycentric of a point of a triangle may be.
const NEGATIVE: f64 = 1e-12;

/// How far from 1 the barycentrics of a point may sum.
const SUM: f64 = 1e-9;

/// The corners of a triangle in its own barycentrics.
const CORNERS: [Bary; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// A point of a surface's domain: triangle (patch) index and barycentrics
/// (u, v, w) in it, u + v + w = 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DomainPoint {
    /// The triangle (patch) index.
    pub triangle: usize,
    /// Barycentrics in that triangle.
    pub bary: Bary,
}

/// A refined surface and where its triangles came from.
///
/// Splits keep the triangle order: a split triangle's index goes to its
/// first child, the other children are appended. So triangle t < T of the
/// refinement of a surface with T triangles always lies in original
/// triangle t.
#[derive(Clone, Debug)]
pub struct Refinement {
    /// The refined surface, the same shape as the original.
    pub surface: TriSurface,
    /// For each triangle of `surface`: the triangle of the original surface
    /// it lies in, and its three corners in that original triangle's
    /// barycentrics.
    pub origin: Vec<(usize, [Bary; 3])>,
}

/// One child of a split: triangle `parent` with its `corner` replaced by
/// the new vertex, which lies at `at` in the parent's barycentrics; `patch`
/// is the parent's patch over the child.
struct Child {
    parent: usize,
    corner: usize,
    at: Bary,
    patch: TriPatch,
}

impl Refinement {
    /// The identity refinement of a surface: every triangle its own origin.
    pub fn identity(surface: &TriSurface) -> Self {
        let origin = (0..surface.patch_count()).map(|t| (t, CORNERS)).collect();
        Self {
            surface: surface.clone(),
            origin,
        }
    }

    /// Where a point of the original domain lies in the refined one: the
    /// child triangle containing it, with barycentrics in that child. On an
    /// edge shared by children the one containing it most (largest smallest
    /// barycentric) is chosen. `None` if the triangle index is out of range
    /// or the barycentrics are not those of a point of the triangle (one
    /// below −1e-12, or a sum off 1 by more than 1e-9).
    pub fn locate(&self, p: DomainPoint) -> Option<DomainPoint> {
        if !in_triangle(p.bary) {
            return None;
        }
        let mut best: Option<DomainPoint> = None;
        for (t, (o, corners)) in self.origin.iter().enumerate() {
            if *o != p.triangle {
                continue;
            }
            let bary = bary_in(*corners, p.bary);
            if best.is_none_or(|b| min(bary) > min(b.bary)) {
                best = Some(DomainPoint { triangle: t, bary });
            }
        }
        best
    }

    /// Splits triangle t of the refined surface at its interior point b
    /// (every barycentric > 0) into three (1 → 3); returns the refinement
    /// and the new vertex (the last one). The origins compose.
    ///
    /// Errors ([`Error::Mismatch`]): t out of range, b not strictly inside.
    pub fn split_triangle(&self, t: usize, b: Bary) -> Result<(Refinement, usize)> {
        check_point(
            &self.surface,
            DomainPoint {
                triangle: t,
                bary: b,
            },
            "triangle split: point",
        )?;
        if min(b) <= 0.0 {
            return Err(mismatch(
                format!("triangle split: point (triangle {t})"),
                "a point strictly inside (every barycentric > 0; split an edge instead)",
                format!("{b:?}"),
            ));
        }
        let children = self.surface.patch(t).subdivide_interior(b);
        let children = children.into_iter().enumerate().map(|(m, patch)| Child {
            parent: t,
            corner: m,
            at: b,
            patch,
        });
        self.with_children(children.collect())
    }

    /// Splits edge e of the refined surface at parameter s ∈ (0, 1),
    /// measured from `edges()[e].vertices[0]`: each incident triangle
    /// splits in two, the new vertex joined to its corner opposite e.
    /// Returns the refinement and the new vertex (the last one).
    ///
    /// Errors ([`Error::Mismatch`]): e out of range, s not in (0, 1).
    pub fn split_edge(&self, e: usize, s: f64) -> Result<(Refinement, usize)> {
        let count = self.surface.edges().len();
        let edge = *self.surface.edges().get(e).ok_or_else(|| {
            mismatch(
                "edge split: edge index",
                format!("< {count} (the number of edges)"),
                e,
            )
        })?;
        if !(s > 0.0 && s < 1.0) {
            return Err(mismatch(
                format!("edge split: parameter s of edge {e}"),
                "0 < s < 1",
                s,
            ));
        }
        let mut children = Vec::with_capacity(4);
        for t in edge.triangles.into_iter().flatten() {
            let tri = self.surface.triangles()[t];
            let k = edge_position(&self.surface, t, e);
            let (a, b) = ((k + 1) % 3, (k + 2) % 3);
            // Patch edge k runs from corner a to corner b.
            let along = if tri[a] == edge.vertices[0] {
                s
            } else {
                1.0 - s
            };
            let mut at = [0.0; 3];
            at[a] = 1.0 - along;
            at[b] = along;
            let [first, second] = self.surface.patch(t).subdivide_edge(k, along);
            for (corner, patch) in [(b, first), (a, second)] {
                children.push(Child {
                    parent: t,
                    corner,
                    at,
                    patch,
                });
            }
        }
        self.with_children(children)
    }

    /// Makes the point p of the original domain a mesh vertex: the vertex
    /// it is at, else a split of the edge it is on, else a split of the
    /// triangle it is in (barycentrics ≤ 1e-9 in the refined triangle count
    /// as zero). Returns the refinement and the vertex.
    ///
    /// Errors ([`Error::Mismatch`]): p not a point of the original domain.
    pub fn insert_point(&self, p: DomainPoint) -> Result<(Refinement, usize)> {
        let q = self.locate(p).ok_or_else(|| {
            mismatch(
                format!("point insertion: point (triangle {})", p.triangle),
                "a point of a triangle of the original surface",
                format!("{:?}", p.bary),
            )
        })?;
        let (t, b) = (q.triangle, q.bary);
        let tri = self.surface.triangles()[t];
        let zero: Vec<usize> = (0..3).filter(|&m| b[m] <= SNAP).collect();
        match zero[..] {
            [x, y] => Ok((self.clone(), tri[3 - x - y])),
            [k] => {
                let (a, c) = ((k + 1) % 3, (k + 2) % 3);
                let e = self.surface.triangle_edges(t)[k];
                let along = b[c] / (b[a] + b[c]);
                let first = self.surface.edges()[e].vertices[0];
                self.split_edge(e, if tri[a] == first { along } else { 1.0 - along })
            }
            _ => self.split_triangle(t, b),
        }
    }

    /// The refinement with the given children in place of their parents:
    /// a parent's first child takes its index, the others are appended. All
    /// control points come from the patches, so the shape is kept exactly.
    fn with_children(&self, children: Vec<Child>) -> Result<(Refinement, usize)> {
        let old = &self.surface;
        let vertex = old.vertex_count();
        let mut vertices = old.points()[..vertex].to_vec();
        vertices.push(children[0].patch.corner(children[0].corner));
        let mut triangles = old.triangles().to_vec();
        let mut patches: Vec<TriPatch> = old.patches().collect();
        let mut origin = self.origin.clone();
        let mut replaced = Vec::new();
        for c in children {
            let mut tri = old.triangles()[c.parent];
            tri[c.corner] = vertex;
            let (o, mut corners) = self.origin[c.parent];
            corners[c.corner] = combine(self.origin[c.parent].1, c.at);
            if replaced.contains(&c.parent) {
                triangles.push(tri);
                patches.push(c.patch);
                origin.push((o, corners));
            } else {
                replaced.push(c.parent);
                triangles[c.parent] = tri;
                patches[c.parent] = c.patch;
                origin[c.parent] = (o, corners);
            }
        }
        let mut surface = TriSurface::try_new(&vertices, &triangles, old.degree())?;
        let mut points = vec![[0.0; 3]; surface.point_count()];
        for (t, patch) in patches.iter().enumerate() {
            for (&g, &x) in surface.patch_indices(t).iter().zip(patch.points()) {
                points[g] = x;
            }
        }
        surface.set_points(points)?;
        Ok((Refinement { surface, origin }, vertex))
    }
}

impl TriSurface {
    /// The edge joining vertices a and b (in either order), if any.
    pub fn edge_between(&self, a: usize, b: usize) -> Option<usize> {
        let key = [a.min(b), a.max(b)];
        self.edges().binary_search_by(|e| e.vertices.cmp(&key)).ok()
    }
}

/// Result of embedding a curve in a surface's mesh ([`embed_curve`];
/// Veltkamp & Wesselink §4.2, Fig. 3).
#[derive(Clone, Debug)]
pub struct CurvePath {
    /// The refined surface, its chain edges interpolating the curve.
    pub refinement: Refinement,
    /// The chain of mesh vertices from the curve's start to its end (in the
    /// refined surface), consecutive ones joined by a mesh edge.
    pub vertices: Vec<usize>,
    /// Global control points fixed to the curve (the vertex and edge points
    /// of every chain edge) with their values, each global once, in chain
    /// order.
    pub fixed: Vec<(usize, Vec3)>,
}

/// Makes mesh edges interpolate the Bézier curve C (Veltkamp & Wesselink
/// §4.2, Fig. 3). The curve runs through the domain from `from` to `to`
/// through the triangles `through` (a path of original triangles, each
/// sharing an edge with the next, the first containing `from`, the last
/// `to`, none twice) or, if `None`, through a shortest such path (breadth
/// first on the dual graph).
///
/// The chain of vertices is made by [`Refinement::insert_point`] at `from`,
/// at the middle of each crossed edge in path order, and at `to`: both ends
/// in one patch give a 1 → 3 split at `from` and another in the child
/// containing `to` (five triangles, the chain one edge); ends in different
/// patches add an edge split per crossed edge, which joins the new vertex to
/// the previous one. A `from` or `to` on an edge splits that edge, at a
/// vertex it uses the vertex.
///
/// C, of degree ≤ n, is elevated to n and split into m pieces at t = i/m
/// (m chain edges); piece i's control points become those of chain edge i
/// (reversed where the edge is stored the other way) and are set on the
/// refined surface, which is otherwise unchanged.
///
/// Errors ([`Error::Mismatch`], `what` naming the value; [`Error::NotFinite`]
/// for a curve point): the curve's degree above n; `from` or `to` not a point
/// of the domain; `from` = `to`; a `through` that is empty, has a triangle
/// out of range or twice, two consecutive triangles without a common edge,
/// or does not contain the ends; no path (separate components); a chain
/// whose consecutive vertices are not joined (such a path crosses an edge
/// at an end point).
///
/// ```
/// use fairsurf::triangle::{embed_curve, DomainPoint};
/// use fairsurf::{BezierCurve, TriSurface};
/// let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
/// let s = TriSurface::new(&v, &[[0, 1, 2], [0, 2, 3]], 3);
/// let c = BezierCurve::new(vec![[0.6, 0.2, 0.0], [0.4, 0.5, 0.3], [0.2, 0.6, 0.0]]);
/// let from = DomainPoint { triangle: 0, bary: [0.4, 0.4, 0.2] };
/// let to = DomainPoint { triangle: 1, bary: [0.4, 0.2, 0.4] };
/// let path = embed_curve(&s, &c, from, to, None).unwrap();
/// assert_eq!(path.vertices.len(), 3); // from, the middle of the diagonal, to
/// assert_eq!(path.refinement.surface.points()[path.vertices[0]], c.eval(0.0));
/// ```
pub fn embed_curve(
    surface: &TriSurface,
    curve: &BezierCurve,
    from: DomainPoint,
    to: DomainPoint,
    through: Option<&[usize]>,
) -> Result<CurvePath> {
    check_curve(surface, curve)?;
    check_point(surface, from, "curve interpolation: `from` point")?;
    check_point(surface, to, "curve interpolation: `to` point")?;
    let same = rebase(surface, to, from.triangle)
        .is_some_and(|b| (0..3).all(|m| (b[m] - from.bary[m]).abs() <= SNAP));
    if same {
        return Err(mismatch(
            format!("curve interpolation: `to` point (triangle {})", to.triangle),
            "a point other than `from`",
            "the `from` point",
        ));
    }
    let path = match through {
        Some(p) => check_path(surface, p, from, to).map(|()| p.to_vec())?,
        None => shortest_path(surface, from, to)?,
    };
    let mut stops = vec![from];
    stops.extend(path.windows(2).map(|w| edge_middle(surface, w[0], w[1])));
    stops.push(to);
    let mut refinement = Refinement::identity(surface);
    let mut vertices: Vec<usize> = Vec::with_capacity(stops.len());
    for p in stops {
        let (next, v) = refinement.insert_point(p)?;
        refinement = next;
        if vertices.last() != Some(&v) {
            vertices.push(v);
        }
    }
    let edges = chain_edges(&refinement.surface, &vertices)?;
    let fixed = fix_to_curve(&mut refinement.surface, curve, &vertices, &edges);
    Ok(CurvePath {
        refinement,
        vertices,
        fixed,
    })
}

/// Sets the control points of the chain edges to the pieces of the curve
/// elevated to the surface's degree; returns them, each global once.
fn fix_to_curve(
    surface: &mut TriSurface,
    curve: &BezierCurve,
    chain: &[usize],
    edges: &[usize],
) -> Vec<(usize, Vec3)> {
    let m = edges.len();
    let mut rest = curve.elevate(surface.degree() - curve.degree());
    let mut fixed = Vec::new();
    for (i, &e) in edges.iter().enumerate() {
        let piece = if i + 1 < m {
            let (left, right) = rest.subdivide(1.0 / (m - i) as f64);
            rest = right;
            left
        } else {
            rest.clone()
        };
        let mut globals = surface.edge_points(e);
        if surface.edges()[e].vertices[0] != chain[i] {
            globals.reverse();
        }
        // A piece's first point is the previous piece's last.
        let skip = usize::from(i > 0);
        fixed.extend(
            globals
                .into_iter()
                .zip(piece.points().iter().copied())
                .skip(skip),
        );
    }
    for &(g, p) in &fixed {
        surface.set_point(g, p);
    }
    fixed
}

/// The mesh edges joining consecutive chain vertices, or why there are none.
fn chain_edges(surface: &TriSurface, chain: &[usize]) -> Result<Vec<usize>> {
    let distinct = (1..chain.len()).all(|i| !chain[..i].contains(&chain[i]));
    if chain.len() < 2 || !distinct {
        return Err(mismatch(
            "curve interpolation: chain of mesh vertices",
            "at least two vertices, all distinct",
            format!("{chain:?}"),
        ));
    }
    let edge = |(i, w): (usize, &[usize])| {
        surface.edge_between(w[0], w[1]).ok_or_else(|| {
            mismatch(
                format!("curve interpolation: chain edge {i} (vertices {} → {})", w[0], w[1]),
                "a mesh edge joining consecutive chain vertices (the path's edges crossed in order)",
                "no edge joins them",
            )
        })
    };
    chain.windows(2).enumerate().map(edge).collect()
}

/// The curve is finite and of degree ≤ n.
fn check_curve(surface: &TriSurface, curve: &BezierCurve) -> Result<()> {
    let n = surface.degree();
    if curve.degree() > n {
        return Err(mismatch(
            "curve interpolation: degree of the curve",
            format!("≤ {n}, the degree of the surface"),
            curve.degree(),
        ));
    }
    match curve.points().iter().position(|&p| !is_finite(p)) {
        Some(i) => Err(Error::NotFinite {
            what: format!("curve interpolation: curve control point {i}"),
        }),
        None => Ok(()),
    }
}

/// `through` is a path of distinct adjacent triangles from `from` to `to`.
fn check_path(
    surface: &TriSurface,
    path: &[usize],
    from: DomainPoint,
    to: DomainPoint,
) -> Result<()> {
    let count = surface.patch_count();
    let (Some(&first), Some(&last)) = (path.first(), path.last()) else {
        return Err(mismatch(
            "curve interpolation: `through`",
            "a path of at least one triangle",
            "[]",
        ));
    };
    for (i, &t) in path.iter().enumerate() {
        let what = format!("curve interpolation: `through[{i}]`");
        if t >= count {
            return Err(mismatch(what, format!("a triangle index < {count}"), t));
        }
        if path[..i].contains(&t) {
            let why = "a triangle not crossed before (a path crosses each triangle once)";
            return Err(mismatch(what, why, format!("triangle {t} again")));
        }
        if i > 0 && shared_edge(surface, path[i - 1], t).is_none() {
            let why = format!("a triangle sharing an edge with `through[{}]`", i - 1);
            return Err(mismatch(
                what,
                why,
                format!("triangles {} and {t}", path[i - 1]),
            ));
        }
    }
    for (end, t, p, i) in [("from", first, from, 0), ("to", last, to, path.len() - 1)] {
        if rebase(surface, p, t).is_none() {
            return Err(mismatch(
                format!("curve interpolation: `through[{i}]`"),
                format!(
                    "a triangle containing the `{end}` point (in triangle {})",
                    p.triangle
                ),
                format!("triangle {t}"),
            ));
        }
    }
    Ok(())
}

/// A shortest path of triangles from one containing `from` to one
/// containing `to`, breadth first across interior edges.
fn shortest_path(surface: &TriSurface, from: DomainPoint, to: DomainPoint) -> Result<Vec<usize>> {
    let count = surface.patch_count();
    let mut parent: Vec<Option<usize>> = vec![None; count];
    let mut seen = vec![false; count];
    let mut queue = VecDeque::new();
    for t in std::iter::once(from.triangle).chain(0..count) {
        if !seen[t] && rebase(surface, from, t).is_some() {
            seen[t] = true;
            queue.push_back(t);
        }
    }
    while let Some(t) = queue.pop_front() {
        if rebase(surface, to, t).is_some() {
            let mut path: Vec<usize> = std::iter::successors(Some(t), |&x| parent[x]).collect();
            path.reverse();
            return Ok(path);
        }
        for e in surface.triangle_edges(t) {
            for nb in surface.edges()[e].triangles.into_iter().flatten() {
                if !seen[nb] {
                    seen[nb] = true;
                    parent[nb] = Some(t);
                    queue.push_back(nb);
                }
            }
        }
    }
    Err(mismatch(
        format!("curve interpolation: `to` point (triangle {})", to.triangle),
        "a point reachable from `from` across interior edges",
        "a point in another component of the mesh",
    ))
}

/// The middle of the edge shared by triangles a and b, as a point of a.
fn edge_middle(surface: &TriSurface, a: usize, b: usize) -> DomainPoint {
    // check_path and shortest_path only give adjacent triangles.
    let e = shared_edge(surface, a, b).expect("consecutive path triangles share an edge");
    let k = edge_position(surface, a, e);
    let mut bary = [0.5; 3];
    bary[k] = 0.0;
    DomainPoint { triangle: a, bary }
}

/// The edge triangles a and b have in common, if any.
fn shared_edge(surface: &TriSurface, a: usize, b: usize) -> Option<usize> {
    let theirs = surface.triangle_edges(b);
    surface
        .triangle_edges(a)
        .into_iter()
        .find(|e| theirs.contains(e))
}

/// The corner of triangle t opposite its edge e.
fn edge_position(surface: &TriSurface, t: usize, e: usize) -> usize {
    let edges = surface.triangle_edges(t);
    (0..3).find(|&k| edges[k] == e).expect("e is an edge of t")
}

/// p in the barycentrics of triangle t when it lies in t: p's triangle
/// itself, or a triangle sharing all its vertices with a nonzero
/// barycentric (> 1e-9; the others count as zero).
fn rebase(surface: &TriSurface, p: DomainPoint, t: usize) -> Option<Bary> {
    if t == p.triangle {
        return Some(p.bary);
    }
    let (from, to) = (surface.triangles()[p.triangle], surface.triangles()[t]);
    let mut b = [0.0; 3];
    for m in (0..3).filter(|&m| p.bary[m] > SNAP) {
        b[to.iter().position(|&v| v == from[m])?] = p.bary[m];
    }
    let sum: f64 = b.iter().sum();
    Some(b.map(|x| x / sum))
}

/// p's triangle is in range and its barycentrics are a point of it.
/// Checks that p names a triangle of the surface and lies in it; the
/// error's `what` starts with `what`.
impl TriSurface {
    /// Checks that `p` is a point of the surface's domain: a triangle of
    /// the mesh and barycentrics ≥ 0 (to 1e-12) summing to 1 (to 1e-9);
    /// the error names `what`.
    pub fn check_point(&self, p: DomainPoint, what: &str) -> Result<()> {
        check_point(self, p, what)
    }
}

pub(crate) fn check_point(surface: &TriSurface, p: DomainPoint, what: &str) -> Result<()> {
    let count = surface.patch_count();
    let what = format!("{what} (triangle {})", p.triangle);
    if p.triangle >= count {
        return Err(mismatch(
            what,
            format!("a triangle index < {count}"),
            p.triangle,
        ));
    }
    if !in_triangle(p.bary) {
        let why = "barycentrics ≥ 0 summing to 1 (a point of the triangle)";
        return Err(mismatch(what, why, format!("{:?}", p.bary)));
    }
    Ok(())
}

/// Each barycentric ≥ −1e-12 and the sum within 1e-9 of 1 (false for NaN).
fn in_triangle(b: Bary) -> bool {
    b.iter().all(|&x| x >= -NEGATIVE) && (b.iter().sum::<f64>() - 1.0).abs() <= SUM
}

/// The barycentrics s of x in the triangle with corners [A, B, C] (all in
/// one triangle's barycentrics): x = s₀A + s₁B + s₂C, by Cramer's rule.
fn bary_in([a, b, c]: [Bary; 3], x: Bary) -> Bary {
    let det = dot(a, cross(b, c));
    [
        dot(x, cross(b, c)) / det,
        dot(a, cross(x, c)) / det,
        dot(a, cross(b, x)) / det,
    ]
}

/// s₀A + s₁B + s₂C.
fn combine(corners: [Bary; 3], s: Bary) -> Bary {
    (0..3).fold([0.0; 3], |x, m| add(x, scale(corners[m], s[m])))
}

fn min(b: Bary) -> f64 {
    b[0].min(b[1]).min(b[2])
}

fn mismatch(what: impl Into<String>, expected: impl Into<String>, got: impl ToString) -> Error {
    Error::Mismatch {
        what: what.into(),
        expected: expected.into(),
        got: got.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> TriSurface {
        let v = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        TriSurface::new(&v, &[[0, 1, 2], [0, 2, 3]], 2)
    }

    #[test]
    fn bary_in_inverts_combine() {
        let corners = [[0.2, 0.3, 0.5], [0.7, 0.1, 0.2], [0.1, 0.8, 0.1]];
        let s = [0.25, 0.6, 0.15];
        let back = bary_in(corners, combine(corners, s));
        assert!((0..3).all(|m| (back[m] - s[m]).abs() < 1e-15));
    }

    #[test]
    fn rebase_moves_edge_and_vertex_points_only() {
        let s = square();
        // The middle of the diagonal 0–2: corners 0 and 2 of triangle 0,
        // corners 0 and 1 of triangle 1.
        let mid = DomainPoint {
            triangle: 0,
            bary: [0.5, 0.0, 0.5],
        };
        assert_eq!(rebase(&s, mid, 1), Some([0.5, 0.5, 0.0]));
        let inside = DomainPoint {
            triangle: 0,
            bary: [0.2, 0.3, 0.5],
        };
        assert_eq!(rebase(&s, inside, 1), None);
    }

    #[test]
    fn edge_middle_and_shared_edge() {
        let s = square();
        let e = shared_edge(&s, 0, 1).unwrap();
        assert_eq!(s.edges()[e].vertices, [0, 2]);
        assert_eq!(edge_middle(&s, 1, 0).bary, [0.5, 0.5, 0.0]);
        assert_eq!(s.edge_between(2, 0), Some(e));
        assert_eq!(s.edge_between(1, 3), None);
    }

    #[test]
    fn in_triangle_rejects_nan_and_outside() {
        assert!(in_triangle([0.0, 0.0, 1.0]));
        assert!(!in_triangle([f64::NAN, 0.5, 0.5]));
        assert!(!in_triangle([-1e-9, 0.5, 0.5 + 1e-9]));
        assert!(!in_triangle([0.5, 0.5, 0.1]));
    }
}
