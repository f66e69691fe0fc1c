//! Trimmed faces: a B-spline or plane face bounded otherwise than by four
//! sides of its surface, or with holes. Kept as its surface and its loops,
//! each edge as it is ([`TrimEdge`]: the edge's curve and the face's normal
//! at its foot points), for fills to meet through strip stand-ins
//! ([`fairsurf::bspline::strip_stand_in`]).

use super::*;
use fairsurf::bspline::{EdgeFrame, TrueEdge};

/// An edge of a trimmed face's loop as the loop runs (the face on its left
/// seen from its normal's side).
#[derive(Clone, Debug, PartialEq)]
pub struct TrimEdge {
    /// The edge's point and tangent and the face's unit normal at
    /// t ∈ [0, 1] along it.
    pub edge: TrueEdge,
    /// Whether the edge is no other face's in the shell: a side of a hole
    /// (or of an open sheet's rim).
    pub free: bool,
    /// For a free edge whose ends each meet one other free edge: the
    /// directions a strip along it leaves its ends by — the other free
    /// edge there continued through the vertex, as a four-sided
    /// neighbour's cross derivative runs along the side it shares with the
    /// next neighbour ([`fairsurf::bspline::strip_stand_in_towards`]).
    pub ends: Option<[Vec3; 2]>,
    /// The length of a polygon through 33 points of the edge.
    pub length: f64,
    /// The largest distance of 33 points of the edge from the face's
    /// surface (CAD systems write a trimmed face's edges as curves that
    /// approximate its boundary: Open CASCADE's BuildCurves3d to 1e-5 by
    /// default); at most [`TRIM_TOLERANCE`] or 1e-7 of the loops' size.
    pub off_surface: f64,
}

/// How far a trimmed face's edges may lie from its surface (at least).
pub const TRIM_TOLERANCE: f64 = 1e-5;

/// A trimmed face's surface (the file's B-spline, or a bilinear patch of
/// the plane around the loops) and its loops, or why not. `loops` are the
/// face's edges with their shell indices.
pub(super) fn trimmed(
    face: &Face,
    loops: &[Vec<LoopEdge>],
) -> std::result::Result<(&'static str, FaceSurface, Vec<Vec<Frames>>), String> {
    let (kind, surface) = match &face.surface {
        StepSurface::BSplineSurface(_) | StepSurface::NurbsSurface(_) => {
            let (kind, s) = spline(&face.surface)?;
            let kind = if kind == "B-spline" {
                "trimmed B-spline"
            } else {
                "trimmed rational B-spline"
            };
            (kind, s)
        }
        StepSurface::ElementarySurface(e) if matches!(e.as_ref(), ElementarySurface::Plane(_)) => {
            ("trimmed plane", plane_around(&face.surface, loops)?)
        }
        _ => {
            return Err(
                "a trimmed face of this kind of surface: only B-spline and plane faces are \
                 filled around when trimmed so far"
                    .into(),
            )
        }
    };
    let all: Vec<Vec3> = loops.iter().flatten().map(|e| e.start).collect();
    let tol = (1e-7 * fairsurf::vector::bounding_diagonal(&all)).max(TRIM_TOLERANCE);
    let frames = loops
        .iter()
        .map(|l| {
            l.iter()
                .map(|e| Frames::new(&face.surface, e, tol))
                .collect::<std::result::Result<Vec<_>, String>>()
        })
        .collect::<std::result::Result<Vec<_>, String>>()?;
    Ok((kind, surface, frames))
}

/// A bilinear patch of a plane face's surface around its loops (their
/// points' bounding rectangle in the plane, 2% wider each way), its normal
/// the file's.
fn plane_around(
    file: &StepSurface,
    loops: &[Vec<LoopEdge>],
) -> std::result::Result<FaceSurface, String> {
    use fairsurf::vector::{add, cross, dot, norm, scale, sub};
    let points: Vec<Vec3> = loops
        .iter()
        .flatten()
        .flat_map(|e| (0..32).map(move |k| e.at(k as f64 / 32.0).0))
        .collect();
    let origin = points[0];
    let n = file.normal(0.0, 0.0);
    let n = [n.x, n.y, n.z];
    // An axis in the plane: the farthest point's direction.
    let far = points
        .iter()
        .map(|p| sub(*p, origin))
        .map(|d| sub(d, scale(n, dot(d, n))))
        .max_by(|a, b| norm(*a).total_cmp(&norm(*b)))
        .filter(|d| norm(*d) > 0.0)
        .ok_or("a plane face whose loop is one point")?;
    let e1 = scale(far, 1.0 / norm(far));
    let e2 = cross(n, e1);
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in &points {
        let d = sub(*p, origin);
        let x = [dot(d, e1), dot(d, e2)];
        for c in 0..2 {
            lo[c] = lo[c].min(x[c]);
            hi[c] = hi[c].max(x[c]);
        }
    }
    let margin = 0.02 * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let at = |a: f64, b: f64| add(origin, add(scale(e1, a), scale(e2, b)));
    let (a0, a1, b0, b1) = (
        lo[0] - margin,
        hi[0] + margin,
        lo[1] - margin,
        hi[1] + margin,
    );
    let net = BSplineSurface::new(
        KnotVector::bezier(1),
        KnotVector::bezier(1),
        vec![at(a0, b0), at(a0, b1), at(a1, b0), at(a1, b1)],
    )
    .map_err(|e| e.to_string())?;
    Ok(FaceSurface::Polynomial(net))
}

/// Foot points on a file's surface along one edge (33 parameters), where
/// the edge's frames start their Newton steps.
#[derive(Clone)]
pub(super) struct Frames {
    edge: LoopEdge,
    surface: StepSurface,
    hints: Vec<(f64, f64)>,
    /// The largest distance of the points from the surface.
    off: f64,
    /// Where along the edge (s ∈ (0, 1)) its curve has a knot or its foot
    /// points cross a knot line of the surface.
    breaks: Vec<f64>,
}

/// Parameters at which [`Frames`] keeps foot points.
const HINTS: usize = 32;

impl Frames {
    fn new(surface: &StepSurface, edge: &LoopEdge, tol: f64) -> std::result::Result<Self, String> {
        let mut hints = Vec::with_capacity(HINTS + 1);
        let mut largest = 0.0f64;
        for k in 0..=HINTS {
            let p = edge.at(k as f64 / HINTS as f64).0;
            let ((u, v), off) = file_foot(surface, p, hints.last().copied())
                .ok_or("the file's surface could not be evaluated near an edge of the face")?;
            if off > tol {
                return Err(format!(
                    "an edge of the face is {off:e} off its surface at ({}, {}, {}) (a trimmed \
                     face's edges are taken within {tol:e})",
                    p[0], p[1], p[2]
                ));
            }
            hints.push((u, v));
            largest = largest.max(off);
        }
        let mut frames = Self {
            edge: edge.clone(),
            surface: surface.clone(),
            hints,
            off: largest,
            breaks: Vec::new(),
        };
        frames.breaks = frames.find_breaks();
        Ok(frames)
    }

    /// Where the edge is less smooth: its curve's interior knots (a
    /// B-spline curve's, mapped onto s ∈ (0, 1); none through a seam),
    /// and where its foot points cross an interior knot line of a
    /// B-spline surface (bisection between the samples that straddle it).
    fn find_breaks(&self) -> Vec<f64> {
        let mut out = Vec::new();
        let (a, b) = self.edge.range;
        let knots: Option<Vec<f64>> = match &self.edge.curve {
            Curve3D::BSplineCurve(c) => Some(c.knot_vec().to_vec()),
            Curve3D::NurbsCurve(c) => Some(c.knot_vec().to_vec()),
            _ => None,
        };
        if let (Some(k), None) = (knots, self.edge.seam) {
            out.extend(k.iter().map(|t| (t - a) / (b - a)));
        }
        let lines: [Vec<f64>; 2] = match &self.surface {
            StepSurface::BSplineSurface(s) => [s.uknot_vec().to_vec(), s.vknot_vec().to_vec()],
            StepSurface::NurbsSurface(s) => {
                let s = s.non_rationalized();
                [s.uknot_vec().to_vec(), s.vknot_vec().to_vec()]
            }
            _ => return out,
        };
        let foot = |s: f64, hint: (f64, f64)| {
            let p = self.edge.at(s).0;
            file_foot(&self.surface, p, Some(hint)).map_or(hint, |f| f.0)
        };
        for (c, knots) in lines.iter().enumerate() {
            let (lo, hi) = (knots[0], knots[knots.len() - 1]);
            let inner: Vec<f64> = knots
                .iter()
                .copied()
                .filter(|&k| k > lo && k < hi)
                .collect();
            let at = |uv: (f64, f64)| if c == 0 { uv.0 } else { uv.1 };
            for k in 0..HINTS {
                let (h0, h1) = (self.hints[k], self.hints[k + 1]);
                let (x0, x1) = (at(h0), at(h1));
                for &kn in &inner {
                    if (x0 - kn) * (x1 - kn) >= 0.0 {
                        continue;
                    }
                    let (mut s0, mut s1) = (k as f64 / HINTS as f64, (k + 1) as f64 / HINTS as f64);
                    let mut hint = h0;
                    for _ in 0..40 {
                        let m = 0.5 * (s0 + s1);
                        let uv = foot(m, hint);
                        if (at(uv) - kn) * (x0 - kn) > 0.0 {
                            s0 = m;
                            hint = uv;
                        } else {
                            s1 = m;
                        }
                    }
                    out.push(0.5 * (s0 + s1));
                }
            }
        }
        out
    }

    /// The edge's point and tangent at s ∈ [0, 1] and the surface's unit
    /// normal at its foot point.
    fn frame(&self, s: f64) -> EdgeFrame {
        let (point, tangent) = self.edge.at(s);
        let hint = self.hints[((s.clamp(0.0, 1.0) * HINTS as f64).round()) as usize];
        let (u, v) = file_foot(&self.surface, point, Some(hint)).map_or(hint, |f| f.0);
        let n = self.surface.normal(u, v);
        EdgeFrame {
            point,
            tangent,
            normal: [n.x, n.y, n.z],
        }
    }

    pub(super) fn start(&self) -> Vec3 {
        self.edge.start
    }

    pub(super) fn end(&self) -> Vec3 {
        self.edge.end
    }

    /// The direction the edge leaves its start (`at_start`) or end by.
    pub(super) fn leaving(&self, at_start: bool) -> Vec3 {
        if at_start {
            self.edge.at(0.0).1
        } else {
            let d = self.edge.at(1.0).1;
            [-d[0], -d[1], -d[2]]
        }
    }

    /// The edge as a [`TrimEdge`] (`free`, `ends` as the shell says).
    pub(super) fn into_edge(self, free: bool, ends: Option<[Vec3; 2]>) -> TrimEdge {
        let pts: Vec<Vec3> = (0..=32).map(|k| self.edge.at(k as f64 / 32.0).0).collect();
        let length = pts.windows(2).map(|w| dist(w[0], w[1])).sum();
        let off_surface = self.off;
        let breaks = self.breaks.clone();
        TrimEdge {
            edge: TrueEdge::new(move |t| self.frame(t)).with_breaks(breaks),
            free,
            ends,
            length,
            off_surface,
        }
    }
}

/// The parameters of the point of a file's surface nearest to p, and the
/// distance: Newton steps on (S − p)·S_u = (S − p)·S_v = 0 from `hint`, or
/// from the surface's own search (a 33 × 33 grid of a bounded parameter
/// range where that fails: its sphere's at the seam gives NaN).
pub(super) fn file_foot(
    file: &StepSurface,
    p: Vec3,
    hint: Option<(f64, f64)>,
) -> Option<((f64, f64), f64)> {
    let q = Point3::new(p[0], p[1], p[2]);
    let uv = match hint {
        Some(uv) => uv,
        None => {
            let found = SearchNearestParameter::<D2>::search_nearest_parameter(file, q, None, 100)
                .filter(|uv| uv.0.is_finite() && uv.1.is_finite());
            match (found, file.try_range_tuple()) {
                (Some(uv), _) => uv,
                (None, (Some((u0, u1)), Some((v0, v1)))) => (0..=32)
                    .flat_map(|i| (0..=32).map(move |j| (i, j)))
                    .map(|(i, j)| {
                        (
                            u0 + (u1 - u0) * i as f64 / 32.0,
                            v0 + (v1 - v0) * j as f64 / 32.0,
                        )
                    })
                    .min_by(|x, y| {
                        dist(v3(file.subs(x.0, x.1)), p)
                            .total_cmp(&dist(v3(file.subs(y.0, y.1)), p))
                    })?,
                (None, _) => return None,
            }
        }
    };
    let w = |x: Vector3| [x.x, x.y, x.z];
    let derivatives = |u: f64, v: f64| fairsurf::SurfaceDerivatives {
        point: v3(file.subs(u, v)),
        du: w(file.uder(u, v)),
        dv: w(file.vder(u, v)),
        duu: w(file.uuder(u, v)),
        duv: w(file.uvder(u, v)),
        dvv: w(file.vvder(u, v)),
    };
    // A B-spline's parameters stay in its knot domain; an elementary
    // surface's run on (truck gives a plane the range [0, 1]² "as a
    // square").
    let all = (f64::MIN, f64::MAX);
    let domain = match (file, file.try_range_tuple()) {
        (StepSurface::BSplineSurface(_) | StepSurface::NurbsSurface(_), (Some(u), Some(v))) => {
            (u, v)
        }
        _ => (all, all),
    };
    let start = dist(v3(file.subs(uv.0, uv.1)), p);
    Some(foot(&derivatives, p, uv, start, domain))
}
