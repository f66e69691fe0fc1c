//! Where external energy operators act on a triangular surface
//! (Veltkamp & Wesselink §5, §6.1): a point, convex regions of patches, a
//! region of the mesh's (x, y) plane, or a mesh edge; the shared energy
//! terms are in [`crate::operator`].
//!
//! Regions are measured like the internal energy (§6.1, eq. 25): over the
//! unit-side equilateral triangle, so dA = (√3/2) du dv, and the director
//! uses orthonormal directions of that triangle, so it does not depend on
//! the corners' order.

use super::{NodeBasis, Operator, OperatorOutcome, Residual, Tally, Target};
use crate::basis::polygon::{clip_to_triangle, convex, signed_area, trapezoid_rule, Uv};
use crate::triangle::refine::check_point;
use crate::triangle::{
    multi_indices, tri_bernstein_all, Bary, DomainPoint, Refinement, TriSurface, EQUILATERAL_AREA,
};
use crate::vec3::Vec3;
use crate::{BezierCurve, Error, Result};

/// √3/2: du dv on the barycentric (u, v) triangle to area on the unit-side
/// equilateral triangle.
const AREA_FACTOR: f64 = 2.0 * EQUILATERAL_AREA;
const INV_SQRT3: f64 = 0.577_350_269_189_625_8;
/// Unit directions x and y of the equilateral domain (V₁V₂ and its normal)
/// as barycentric differences.
const DIR_X: Bary = [-1.0, 1.0, 0.0];
const DIR_Y: Bary = [-INV_SQRT3, -INV_SQRT3, 2.0 * INV_SQRT3];

/// Where an operator acts.
#[derive(Clone, Debug, PartialEq)]
pub enum Place {
    /// One surface point (u₀, v₀, w₀) of one patch.
    Point(DomainPoint),
    /// Convex polygons in the (u, v) barycentric plane of single patches
    /// (w = 1 − u − v), e.g. a region split across patches by hand.
    Patches(Vec<RegionPiece>),
    /// One convex polygon in the (x, y) plane of the mesh as given (its
    /// vertices' x and y): split per patch automatically, each piece
    /// measured in its own patch's parameters like [`Place::Patches`].
    Domain(Vec<Uv>),
    /// The mesh edge from vertex a to vertex b.
    Edge([usize; 2]),
}

/// A convex polygon in one patch's (u, v) plane.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionPiece {
    /// The patch (triangle).
    pub triangle: usize,
    /// Its vertices (u, v), either orientation.
    pub polygon: Vec<Uv>,
}

/// Quadrature nodes of an operator on the (refined) surface: per node the
/// patch, barycentrics, weight (area on the equilateral domain, or length
/// along an edge) and, for a surface target, the barycentrics in T.
#[derive(Clone, Debug)]
pub(crate) struct Located {
    nodes: Vec<Node>,
    /// For an edge: its global points, a to b.
    edge: Option<Vec<usize>>,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    triangle: usize,
    bary: Bary,
    weight: f64,
    target_bary: Bary,
}

impl Operator<Place> {
    /// Checks the operator against the surface it will act on: strength,
    /// target, place, and that they fit together; errors name the operator.
    pub fn validate(&self, surface: &TriSurface) -> Result<()> {
        self.check_target()?;
        let bad = |what: &str, expected: &str, got: String| self.bad(what, expected, got);
        if matches!(self.target, Target::TensorSurface(_)) {
            return Err(bad(
                "surface",
                "a triangular patch (a tensor-product attractor surface is for tensor patches)",
                "a tensor-product patch".into(),
            ));
        }
        match (&self.place, &self.target) {
            (Place::Edge(_), Target::Curve(_)) => {}
            (_, Target::Curve(_)) => {
                return Err(bad(
                    "place",
                    "an edge (edge-to-curve attractor)",
                    "not an edge".into(),
                ))
            }
            (Place::Edge(_), _) => {
                return Err(bad("place", "a point or a region", "an edge".into()))
            }
            (Place::Patches(p), Target::Surface(_)) if p.len() == 1 && p[0].polygon.len() == 3 => {}
            (_, Target::Surface(_)) => {
                return Err(bad(
                    "region",
                    "a triangular region in one patch (its corners match the attractor surface's)",
                    "another place".into(),
                ))
            }
            _ => {}
        }
        match &self.place {
            Place::Point(p) => check_point(surface, *p, &format!("{}: point", self.name))?,
            Place::Patches(pieces) => {
                if pieces.is_empty() {
                    return Err(bad("region", "at least one piece", "none".into()));
                }
                for (k, piece) in pieces.iter().enumerate() {
                    if piece.triangle >= surface.patch_count() {
                        return Err(bad(
                            &format!("region[{k}].triangle"),
                            &format!("a triangle index < {}", surface.patch_count()),
                            piece.triangle.to_string(),
                        ));
                    }
                    let p = convex(&piece.polygon, &format!("{}: region[{k}]", self.name))?;
                    for uv in &p {
                        let w = 1.0 - uv[0] - uv[1];
                        if uv[0] < -1e-12 || uv[1] < -1e-12 || w < -1e-12 {
                            return Err(bad(
                                &format!("region[{k}]"),
                                "vertices (u, v) with u, v ≥ 0 and u + v ≤ 1",
                                format!("{uv:?}"),
                            ));
                        }
                    }
                }
            }
            Place::Domain(polygon) => {
                convex(polygon, &format!("{}: region", self.name))?;
            }
            Place::Edge([a, b]) => {
                if surface.edge_between(*a, *b).is_none() || a == b {
                    return Err(bad(
                        "edge",
                        "two vertices joined by a mesh edge",
                        format!("[{a}, {b}]"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// A [`Place::Domain`] region as the per-patch pieces it is split into
    /// on `surface` (None for the other places): what a result file keeps,
    /// since the solved mesh's (x, y) differ from the chart's.
    pub fn domain_pieces(&self, surface: &TriSurface) -> Result<Option<Vec<RegionPiece>>> {
        match &self.place {
            Place::Domain(polygon) => split_domain(surface, polygon, &self.name).map(Some),
            _ => Ok(None),
        }
    }

    /// A region operator's pieces on the refined surface `r.surface` (None
    /// for points and edges): each piece clipped to the children of its
    /// patch, in the children's own (u, v). What a result file of a scene
    /// refined by curve constraints keeps.
    pub fn refined_region(
        &self,
        original: &TriSurface,
        r: &Refinement,
    ) -> Result<Option<Vec<RegionPiece>>> {
        let pieces = match &self.place {
            Place::Patches(p) => p.clone(),
            Place::Domain(polygon) => split_domain(original, polygon, &self.name)?,
            _ => return Ok(None),
        };
        let mut out = Vec::new();
        for piece in pieces {
            let poly = convex(&piece.polygon, &self.name)?;
            for c in clip_to_children(piece.triangle, &poly, r) {
                let polygon = c
                    .part
                    .iter()
                    .map(|&p| {
                        let b = child_bary(c.uv, c.order, p);
                        [b[0], b[1]]
                    })
                    .collect();
                out.push(RegionPiece {
                    triangle: c.child,
                    polygon,
                });
            }
        }
        Ok(Some(out))
    }

    /// The quadrature nodes on the refined surface `r.surface`, from the
    /// place on the `original` surface (validated).
    pub(crate) fn locate(&self, original: &TriSurface, r: &Refinement) -> Result<Located> {
        let surface = &r.surface;
        let n = surface.degree();
        let degree = 2 * match &self.target {
            Target::Surface(t) => n.max(t.degree()),
            _ => n,
        };
        let mut nodes = Vec::new();
        let mut region = |pieces: Vec<RegionPiece>| {
            for piece in pieces {
                let poly = convex(&piece.polygon, &self.name)?;
                // Its corners, for a surface target: T is over this triangle.
                let corners = (poly.len() == 3).then(|| [poly[0], poly[1], poly[2]]);
                for Clipped {
                    child,
                    part,
                    uv,
                    order,
                } in clip_to_children(piece.triangle, &poly, r)
                {
                    // The child's own parameters: its (u, v) triangle has
                    // area ½, so the piece's measure scales by ½/area.
                    let scale = AREA_FACTOR / (2.0 * signed_area(&uv).abs());
                    for (p, w) in trapezoid_rule(&part, degree) {
                        let original_bary = [p[0], p[1], 1.0 - p[0] - p[1]];
                        // Barycentrics in the child (corners in `order`).
                        let bary = child_bary(uv, order, p);
                        let target_bary = match corners {
                            Some(c) => bary_in(c, p),
                            None => original_bary,
                        };
                        nodes.push(Node {
                            triangle: child,
                            bary,
                            weight: w * scale,
                            target_bary,
                        });
                    }
                }
            }
            Ok::<_, Error>(())
        };
        let mut edge = None;
        match &self.place {
            Place::Point(p) => {
                let at = r.locate(*p).ok_or_else(|| Error::Mismatch {
                    what: format!("{}: point", self.name),
                    expected: "a point of the surface".into(),
                    got: format!("{p:?}"),
                })?;
                nodes.push(Node {
                    triangle: at.triangle,
                    bary: at.bary,
                    weight: 1.0,
                    target_bary: p.bary,
                });
            }
            Place::Patches(pieces) => region(pieces.clone())?,
            Place::Domain(polygon) => region(split_domain(original, polygon, &self.name)?)?,
            Place::Edge([a, b]) => {
                let e = surface
                    .edge_between(*a, *b)
                    .ok_or_else(|| Error::Mismatch {
                        what: format!("{}: edge [{a}, {b}]", self.name),
                        expected: "an edge that curve constraints did not split".into(),
                        got: "a split edge".into(),
                    })?;
                let mut pts = surface.edge_points(e);
                if a > b {
                    pts.reverse();
                }
                edge = Some(pts);
            }
        }
        if nodes.is_empty() && edge.is_none() {
            return Err(Error::Mismatch {
                what: format!("{}: region", self.name),
                expected: "a region overlapping the surface".into(),
                got: "no overlap with any patch".into(),
            });
        }
        Ok(Located { nodes, edge })
    }

    /// The scalar residuals on `surface` (global coordinates 3g + c).
    pub(crate) fn residuals(&self, at: &Located, surface: &TriSurface) -> Vec<Residual> {
        let n = surface.degree();
        let mut out = Vec::new();
        if let Some(pts) = &at.edge {
            self.edge_residuals(pts, &mut out);
            return out;
        }
        for node in &at.nodes {
            let idx = surface.patch_indices(node.triangle);
            let values = tri_bernstein_all(n, node.bary);
            let (dx, dy) = match self.target {
                Target::Direction(_) => (
                    derivative_basis(n, node.bary, DIR_X),
                    derivative_basis(n, node.bary, DIR_Y),
                ),
                _ => (Vec::new(), Vec::new()),
            };
            let basis = NodeBasis {
                points: idx,
                values: &values,
                dx: &dx,
                dy: &dy,
            };
            let t = self.surface_point(node);
            self.node_residuals(node.weight, &basis, t, &mut out);
        }
        out
    }

    /// T at the node, for a surface target.
    fn surface_point(&self, node: &Node) -> Option<Vec3> {
        match &self.target {
            Target::Surface(t) => Some(t.eval(node.target_bary)),
            _ => None,
        }
    }

    /// Its outcome on the solved surface, given its [`Self::residuals`]
    /// (they depend on the mesh only).
    pub(crate) fn outcome(
        &self,
        at: &Located,
        residuals: &[Residual],
        surface: &TriSurface,
        x: &[f64],
    ) -> OperatorOutcome {
        let mut tally = Tally::new(self);
        if let Some(pts) = &at.edge {
            let edge = BezierCurve::new(pts.iter().map(|&g| surface.points()[g]).collect());
            tally.edge(self, &edge);
        }
        for node in &at.nodes {
            let patch = surface.patch(node.triangle);
            tally.node(
                self,
                node.weight,
                patch.eval(node.bary),
                patch.normal(node.bary),
                self.surface_point(node),
            );
        }
        tally.finish(self, self.energy(residuals, x))
    }
}

/// A region clipped to one child of its patch in a refinement.
struct Clipped {
    child: usize,
    /// The clipped polygon in the original patch's (u, v).
    part: Vec<Uv>,
    /// The child's corners in the original (u, v), counter-clockwise.
    uv: [Uv; 3],
    /// Which of the child's corners each of `uv` is.
    order: [usize; 3],
}

/// The convex polygon `poly` of the original patch `triangle`, clipped to
/// each of its children in `r`.
fn clip_to_children(triangle: usize, poly: &[Uv], r: &Refinement) -> Vec<Clipped> {
    let mut out = Vec::new();
    for (child, (t, tri)) in r.origin.iter().enumerate() {
        if *t != triangle {
            continue;
        }
        let mut uv: [Uv; 3] = std::array::from_fn(|k| [tri[k][0], tri[k][1]]);
        let mut order = [0, 1, 2];
        if signed_area(&uv) < 0.0 {
            uv.swap(1, 2);
            order.swap(1, 2);
        }
        if let Some(part) = clip_to_triangle(poly, uv) {
            out.push(Clipped {
                child,
                part,
                uv,
                order,
            });
        }
    }
    out
}

/// The barycentrics in the child of the original (u, v) point p.
fn child_bary(uv: [Uv; 3], order: [usize; 3], p: Uv) -> Bary {
    let s = bary_in(uv, p);
    let mut bary = [0.0; 3];
    for k in 0..3 {
        bary[order[k]] = s[k];
    }
    bary
}

/// ∂_d B^n_λ(b) for all λ: n Σ_m d_m B^{n−1}_{λ−e_m}(b).
fn derivative_basis(n: usize, b: Bary, d: Bary) -> Vec<f64> {
    if n == 0 {
        return vec![0.0];
    }
    let lower = tri_bernstein_all(n - 1, b);
    let index = |l: [usize; 3]| crate::triangle::linear_index(n - 1, l[0], l[1], l[2]);
    multi_indices(n)
        .map(|lam| {
            (0..3)
                .filter(|&m| lam[m] > 0)
                .map(|m| {
                    let mut l = lam;
                    l[m] -= 1;
                    d[m] * lower[index(l)]
                })
                .sum::<f64>()
                * n as f64
        })
        .collect()
}

/// The barycentrics of p in the (u, v) triangle c.
fn bary_in(c: [Uv; 3], p: Uv) -> Bary {
    let det = (c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1]);
    let s1 =
        ((p[0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (p[1] - c[0][1])) / det;
    let s2 =
        ((c[1][0] - c[0][0]) * (p[1] - c[0][1]) - (p[0] - c[0][0]) * (c[1][1] - c[0][1])) / det;
    [1.0 - s1 - s2, s1, s2]
}

/// A polygon in the mesh's (x, y) plane split into pieces per patch, in
/// each patch's (u, v): u, v, w are the barycentrics of the point in the
/// triangle of the patch's corner points (the mesh as given).
fn split_domain(surface: &TriSurface, polygon: &[Uv], name: &str) -> Result<Vec<RegionPiece>> {
    let poly = convex(polygon, &format!("{name}: region"))?;
    let mut pieces = Vec::new();
    for (t, tri) in surface.triangles().iter().enumerate() {
        let xy: [Uv; 3] = std::array::from_fn(|k| {
            let p = surface.points()[tri[k]];
            [p[0], p[1]]
        });
        let mut ccw = xy;
        let flipped = signed_area(&xy) < 0.0;
        if flipped {
            ccw.swap(1, 2);
        }
        if signed_area(&ccw) <= 1e-14 * scale_of(&ccw) {
            continue; // edge-on in (x, y): no area to cover there
        }
        let Some(part) = clip_to_triangle(&poly, ccw) else {
            continue;
        };
        let polygon = part
            .iter()
            .map(|&p| {
                let b = bary_in(xy, p);
                [b[0], b[1]]
            })
            .collect();
        pieces.push(RegionPiece {
            triangle: t,
            polygon,
        });
    }
    Ok(pieces)
}

fn scale_of(t: &[Uv; 3]) -> f64 {
    let s = t.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    s * s
}
