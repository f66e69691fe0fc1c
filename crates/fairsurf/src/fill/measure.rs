//! Measures of a fill on the returned surface: how it meets each neighbour
//! (gap and normal angle along the side) and its fairness W = ∫∫ κ₁² + κ₂² dA.

use super::holes::{surface_param, Side};
use crate::bspline::{BSplineSurface, RationalSurface, TrueEdge};
use crate::tensor::regular_normal;
use crate::vec3::{angle, dist};
use crate::Vec3;

/// Parameters sampled per side: Chebyshev–Lobatto points, clustered at the
/// corners where the largest deviations of an approximate fill sit.
pub const SIDE_SAMPLES: usize = 129;

/// How a fill meets one neighbour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SideFit {
    /// The side.
    pub side: Side,
    /// Largest distance between the fill's and the neighbour's boundary
    /// points at the same parameter.
    pub gap: f64,
    /// Largest angle between their unit normals, radians (oriented: π
    /// would be a fill facing the other way).
    pub angle: f64,
    /// Parameters sampled.
    pub samples: usize,
    /// Samples where a normal did not exist (a collapsed corner).
    pub singular: usize,
    /// Whether the fill's boundary data came from the neighbour exactly (a
    /// polynomial neighbour: G¹ to rounding), or from a polynomial stand-in
    /// of a rational one ([`RationalSurface::polynomial`]) or of a trimmed
    /// face along its edge ([`crate::bspline::strip_stand_in`]): then the
    /// gap and angle above are measured against the rational surface or
    /// the edge itself and are as small as the stand-in's tolerance, not
    /// zero.
    pub exact: bool,
}

/// What a neighbour face stands in for: its sides are measured against
/// that ([`super::FillOptions::exact`]).
#[derive(Clone, Copy, Debug)]
pub enum Exact<'a> {
    /// A rational surface, at the same parameter.
    Rational(&'a RationalSurface),
    /// A trimmed face's edge along the face's side V0, at the same
    /// parameter: the edge's point and the face's normal there.
    Edge(&'a TrueEdge),
}

/// The largest normal angle (radians) of `sides` (0 for none); NaN when a
/// side had no sample with two normals (nothing measured there).
pub fn largest_angle(sides: &[SideFit]) -> f64 {
    if sides.iter().any(|s| s.singular >= s.samples) {
        return f64::NAN;
    }
    sides.iter().map(|s| s.angle).fold(0.0, f64::max)
}

/// A point with its two first derivatives: R, R_u, R_v.
pub(crate) type Tangents = [Vec3; 3];

/// A surface's [`Tangents`] on a grid of (u, v) (as
/// [`BSplineSurface::tangents_on`]).
type GridEval<'a> = &'a dyn Fn(&[f64], &[f64]) -> Vec<Tangents>;

/// `grid` at the points `at(t)` for the side parameters `ts`, which lie on
/// one line of constant u or v: one grid evaluation.
fn line(grid: GridEval, at: &dyn Fn(f64) -> (f64, f64), ts: &[f64]) -> Vec<Tangents> {
    let pts: Vec<(f64, f64)> = ts.iter().map(|&t| at(t)).collect();
    if pts.iter().all(|p| p.0 == pts[0].0) {
        let vs: Vec<f64> = pts.iter().map(|p| p.1).collect();
        grid(&[pts[0].0], &vs)
    } else {
        debug_assert!(pts.iter().all(|p| p.1 == pts[0].1), "a side on no line");
        let us: Vec<f64> = pts.iter().map(|p| p.0).collect();
        grid(&us, &[pts[0].1])
    }
}

/// Compares the fill's side `k` with the neighbour `face` along `side`.
pub fn side_fit(fill: &BSplineSurface, k: usize, face: &BSplineSurface, side: Side) -> SideFit {
    side_fit_facing(fill, k, face, None, side, false)
}

/// [`side_fit`], the neighbour's normal turned around when `flipped` (a
/// blend between faces whose parameterizations face opposite ways).
pub(crate) fn side_fit_facing(
    fill: &BSplineSurface,
    k: usize,
    face: &BSplineSurface,
    exact: Option<Exact>,
    side: Side,
    flipped: bool,
) -> SideFit {
    piece_fit(fill, k, [0.0, 1.0], face, exact, side, flipped)
}

/// The fill's side k on [span₀, span₁] of its parameter (along the hole's
/// traversal) against the neighbour `face` along the whole of `side`: one
/// edge of a side made of several; the neighbour's normal turned around
/// when `flipped`.
pub(crate) fn piece_fit(
    fill: &BSplineSurface,
    k: usize,
    span: [f64; 2],
    face: &BSplineSurface,
    exact: Option<Exact>,
    side: Side,
    flipped: bool,
) -> SideFit {
    let ts = side_parameters();
    let da = line(
        &|u, v| fill.tangents_on(u, v),
        &|t| super::fill_param(k, span[0] + (span[1] - span[0]) * t),
        &ts,
    );
    let db = neighbour_tangents(face, exact, side, &ts);
    compare(&da, &db, side, flipped, exact.is_none())
}

/// The neighbour's [`Tangents`] at parameters `ts` of the hole's side: of
/// what the face stands in for (`exact`) when it does.
pub(crate) fn neighbour_tangents(
    face: &BSplineSurface,
    exact: Option<Exact>,
    side: Side,
    ts: &[f64],
) -> Vec<Tangents> {
    let on = |t| neighbour_param(face, side, t);
    match exact {
        Some(Exact::Rational(r)) => line(&|u, v| r.tangents_on(u, v), &on, ts),
        // A strip's side V0 at u = the edge's parameter (its domain is
        // [0, 1]²; its other sides are no face's boundary).
        Some(Exact::Edge(e)) if side.edge == crate::analysis::Edge::V0 => {
            ts.iter().map(|&t| e.tangents(on(t).0)).collect()
        }
        _ => line(&|u, v| face.tangents_on(u, v), &on, ts),
    }
}

/// The [`SIDE_SAMPLES`] parameters on [0, 1] a side is compared at:
/// Chebyshev–Lobatto points, clustered at the corners, rounded to
/// multiples of 2⁻⁴⁰ and mirrored, so that t ↦ 1 − t maps the set onto
/// itself exactly: a side traversed the other way is measured at the same
/// parameters of its edge (whose frames a strip's fit has computed
/// already, [`crate::bspline::TrueEdge::frame`]).
pub(crate) fn side_parameters() -> Vec<f64> {
    let n = SIDE_SAMPLES - 1;
    let grid = (40f64).exp2();
    let half: Vec<f64> = (0..=n / 2)
        .map(|i| {
            let t = 0.5 - 0.5 * (std::f64::consts::PI * i as f64 / n as f64).cos();
            (t * grid).round() / grid
        })
        .collect();
    let mirrored = half[..n.div_ceil(2)].iter().rev().map(|t| 1.0 - t);
    half.iter().copied().chain(mirrored).collect()
}

/// The neighbour's (u, v) at parameter t of the hole's side.
pub(crate) fn neighbour_param(face: &BSplineSurface, side: Side, t: f64) -> (f64, f64) {
    surface_param(face, side.edge, side.boundary_t(t))
}

/// The fit of the fill's derivatives `da` against the neighbour's `db` at
/// the same side parameters.
pub(crate) fn compare(
    da: &[Tangents],
    db: &[Tangents],
    side: Side,
    flipped: bool,
    exact: bool,
) -> SideFit {
    let (mut gap, mut ang, mut singular) = (0.0f64, 0.0f64, 0usize);
    for (a, b) in da.iter().zip(db) {
        gap = gap.max(dist(a[0], b[0]));
        let (Some(na), Some(mut nb)) = (regular_normal(a[1], a[2]), regular_normal(b[1], b[2]))
        else {
            singular += 1;
            continue;
        };
        if flipped {
            nb = [-nb[0], -nb[1], -nb[2]];
        }
        ang = ang.max(angle(na, nb));
    }
    SideFit {
        side,
        gap,
        angle: ang,
        samples: da.len(),
        singular,
        exact,
    }
}

/// W = ∫∫ κ₁² + κ₂² dA = ∫∫ (4H² − 2K) |R_u × R_v| du dv, by Gauss–Legendre
/// quadrature span by span (the integrand is rational: no closed form).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TotalCurvature {
    /// W with p + q + 4 nodes per span and direction.
    pub value: f64,
    /// |W − W'| with W' from half as many nodes plus one (the descent's
    /// coarse rule): an error estimate.
    pub error: f64,
}

/// W of a surface ([`TotalCurvature`]); points where the surface is not
/// regular contribute nothing.
pub fn total_curvature(s: &BSplineSurface) -> TotalCurvature {
    with_error(s, super::willmore::Rule::of(s).w(s))
}

/// [`TotalCurvature`] of `s` whose W by the main rule (p + q + 4 nodes,
/// [`super::willmore::Rule::of`]) is `value`, known already: only the
/// coarse rule's W for the error estimate is evaluated.
pub(crate) fn with_error(s: &BSplineSurface, value: f64) -> TotalCurvature {
    with_coarse(value, super::willmore::Rule::coarse(s).w(s))
}

/// [`TotalCurvature`] from W of one surface by the main rule (`value`) and
/// by [`super::willmore::Rule::coarse`] (`coarse`).
pub(crate) fn with_coarse(value: f64, coarse: f64) -> TotalCurvature {
    TotalCurvature {
        value,
        error: (value - coarse).abs(),
    }
}
