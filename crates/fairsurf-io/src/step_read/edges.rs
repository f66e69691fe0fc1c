//! The edges of a face's loop as the loop runs (curve, range, seam, ends),
//! and the tolerances their ends and straightness are judged by.

use super::*;

/// An edge of a face's loop, as the loop runs.
#[derive(Clone)]
pub(super) struct LoopEdge {
    pub(super) curve: Curve3D,
    /// The curve's parameters at the loop's start and end of the edge; on
    /// a closed curve, past the end of its domain when the edge runs
    /// through the curve's seam.
    pub(super) range: (f64, f64),
    /// The domain of a closed curve whose edge runs through its seam
    /// (parameters past its end wrap to its start).
    pub(super) seam: Option<(f64, f64)>,
    pub(super) start: Vec3,
    pub(super) end: Vec3,
    /// The larger distance of the file's two vertices from the curve's
    /// points taken for them.
    pub(super) vertex_off: f64,
}

impl LoopEdge {
    pub(super) fn new(shell: &Shell, e: CompressedEdgeIndex) -> std::result::Result<Self, String> {
        let edge = shell
            .edges
            .get(e.index)
            .ok_or("a loop names an edge the shell does not have")?;
        let (front, back) = (
            v3(shell.vertices[edge.vertices.0]),
            v3(shell.vertices[edge.vertices.1]),
        );
        let (r0, r1) = edge
            .curve
            .try_range_tuple()
            .ok_or("an edge whose curve is unbounded")?;
        // The reader turns a curve used against its sense: it runs from
        // the edge's front vertex to its back one.
        let mut whole = Self {
            curve: edge.curve.clone(),
            range: (r0, r1),
            seam: None,
            start: front,
            end: back,
            vertex_off: 0.0,
        };
        // The vertices lie on the curve as the file's precision allows:
        // 1e-7 of the curve's size (Open CASCADE's loft 1000 across had
        // vertices 1.6e-5 off their edges' curves, 1.6e-8 of its size at
        // every scale), at least EDGE_TOLERANCE.
        let mut along: Vec<Vec3> = (0..=8)
            .map(|k| whole.point(r0 + (r1 - r0) * k as f64 / 8.0))
            .collect();
        along.extend([front, back]);
        let size = fairsurf::vector::bounding_diagonal(&along);
        let tol = (1e-7 * size).max(EDGE_TOLERANCE);
        // The curve's parameters at the vertices: its ends, or where the
        // vertices lie on it when the curve runs further (a closed or
        // extended curve).
        let at = |p: Vec3, end: f64| -> std::result::Result<(f64, f64), String> {
            let off = dist(whole.point(end), p);
            if off <= tol {
                return Ok((end, off));
            }
            let (t, off) = whole.nearest(p);
            if off <= tol {
                Ok((t, off))
            } else {
                Err(format!(
                    "an edge whose vertex is {off:e} off its curve (taken within {tol:e}: 1e-7 of \
                     the curve's size, at least {EDGE_TOLERANCE:e})"
                ))
            }
        };
        let ((t0, off0), (t1, off1)) = (at(front, r0)?, at(back, r1)?);
        whole.vertex_off = off0.max(off1);
        let closed = dist(whole.point(r0), whole.point(r1)) <= tol;
        whole.range = if t0 < t1 {
            (t0, t1)
        } else if closed && t0 > t1 {
            // From the front vertex through the seam to the back one.
            whole.seam = Some((r0, r1));
            (t0, t1 + (r1 - r0))
        } else if t0 > t1 {
            return Err(format!(
                "an edge whose curve runs from its end vertex to its start vertex (parameters \
                 {t0} to {t1})"
            ));
        } else {
            return Err("an edge whose two vertices are one point of its curve".into());
        };
        if !e.orientation {
            whole = whole.reversed();
        }
        Ok(whole)
    }

    /// The same edge run the other way.
    pub(super) fn reversed(&self) -> Self {
        Self {
            curve: self.curve.clone(),
            range: (self.range.1, self.range.0),
            seam: self.seam,
            start: self.end,
            end: self.start,
            vertex_off: self.vertex_off,
        }
    }

    /// The curve's parameter for t (wrapped through the seam).
    pub(super) fn wrap(&self, t: f64) -> f64 {
        match self.seam {
            Some((lo, hi)) if t > hi => t - (hi - lo),
            _ => t,
        }
    }

    pub(super) fn point(&self, t: f64) -> Vec3 {
        v3(self.curve.subs(self.wrap(t)))
    }

    /// The point at s ∈ [0, 1] along the loop, and the derivative by s.
    pub(super) fn at(&self, s: f64) -> (Vec3, Vec3) {
        let (a, b) = self.range;
        let t = self.wrap(a + (b - a) * s);
        let d = self.curve.der(t);
        (
            v3(self.curve.subs(t)),
            [d.x * (b - a), d.y * (b - a), d.z * (b - a)],
        )
    }

    /// Whether the edge is a straight segment: points at seven parameters
    /// inside it within `tol` of its chord, whatever its parameterization.
    pub(super) fn straight(&self, tol: f64) -> bool {
        (1..8).all(|k| {
            let p = self.at(k as f64 / 8.0).0;
            fairsurf::vector::segment_distance(p, self.start, self.end) <= tol
        })
    }

    /// How far the edge's tangent turns (the sum of its turns between 17
    /// samples), and in how many pieces of at most 90° an arc of it is
    /// written.
    pub(super) fn turning(&self) -> (f64, usize) {
        let turning: f64 = (0..16)
            .map(|k| {
                let (a, b) = (self.at(k as f64 / 16.0).1, self.at((k + 1) as f64 / 16.0).1);
                fairsurf::vector::angle(a, b)
            })
            .sum();
        let pieces = ((turning / std::f64::consts::FRAC_PI_2) - 1e-9)
            .ceil()
            .max(1.0);
        (turning, pieces as usize)
    }

    /// The distance from p to the edge's curve (within the edge).
    pub(super) fn distance(&self, p: Vec3) -> f64 {
        self.nearest(p).1
    }

    /// The parameter of the point of the edge nearest to p, and the
    /// distance: the nearest of 33 samples, then Newton steps on
    /// (C(t) − p)·C′(t) = 0 kept in the edge.
    pub(super) fn nearest(&self, p: Vec3) -> (f64, f64) {
        let range = (
            self.range.0.min(self.range.1),
            self.range.0.max(self.range.1),
        );
        let curve = |t: f64| {
            let w = self.wrap(t);
            let (d1, d2) = (self.curve.der(w), self.curve.der2(w));
            [self.point(t), [d1.x, d1.y, d1.z], [d2.x, d2.y, d2.z]]
        };
        fairsurf::nearest_parameter(curve, range, p)
    }
}

/// How far a file's vertices and edge curves may lie from the faces they
/// bound (at least; 1e-8 of the face's size when larger): CAD systems write
/// edge curves that approximate their faces' boundaries (Open CASCADE's
/// edges of a rational face's iso-lines were 1.1e-7 off in a test).
pub(super) const EDGE_TOLERANCE: f64 = 1e-6;

/// [`EDGE_TOLERANCE`], or 1e-8 of the size of the loop's vertices.
pub(super) fn edge_tolerance(edges: &[LoopEdge]) -> f64 {
    let pts: Vec<Vec3> = edges.iter().map(|e| e.start).collect();
    (1e-8 * fairsurf::vector::bounding_diagonal(&pts)).max(EDGE_TOLERANCE)
}

/// 1e-9 of the size of the loop's vertices, at least 1e-7.
pub(super) fn loop_tolerance(edges: &[LoopEdge]) -> f64 {
    let pts: Vec<Vec3> = edges.iter().map(|e| e.start).collect();
    (1e-9 * fairsurf::vector::bounding_diagonal(&pts)).max(1e-7)
}
