//! Strip stand-ins: a face known only along an edge — a trimmed face,
//! whose boundary is not four sides of its surface, or a face with holes —
//! enters a fill through a polynomial strip along the edge,
//!
//! S(u, v) = C(u) + v·T(u),  u, v ∈ [0, 1],
//!
//! C a B-spline through the edge's points and T one through vectors in the
//! face's tangent plane across the edge, pointing into the face (a loop
//! runs with its face on the left): w·n × c′/|c′| (n the face's unit
//! normal, c′ the edge's tangent as the face's loop runs, w a width), or
//! turned from c′ by an angle, and as long as a length, that run linearly
//! between given vectors at the ends ([`strip_stand_in_towards`]). A
//! fill's corner takes the cross derivative of one side as the derivative
//! of the next side, so a strip that ends at a hole's corner is made to
//! leave it as the hole's next side continued through the corner — as a
//! four-sided neighbour's cross derivative runs along the side it shares
//! with the next neighbour. The strip's side v = 0 is the edge and its
//! normal there, S_u × S_v = C′ × T, is the face's: a fill G¹ to the strip
//! exactly is G¹ to the face within the strip's fit, which is measured
//! against the edge at the same parameter as
//! [`RationalSurface::polynomial`]'s stand-ins are against their rational
//! surfaces. Pieces put their knots at the edge's breaks
//! ([`TrueEdge::with_breaks`]).

use super::rational::{side_parameters, FitTolerance, StandIn};
use super::{solve_dense_wide, BSplineSurface, KnotVector, ONE_SPAN_DEGREE};
use crate::vec3::{angle, cross, dist, dot, norm, scale};
use crate::{Error, Result, Vec3};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// A point of a face's edge, the edge's tangent there (as the face's loop
/// runs) and the face's unit normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeFrame {
    /// The point.
    pub point: Vec3,
    /// dc/dt: the edge's derivative along its parameter t ∈ [0, 1], the
    /// way the face's loop runs (the face on its left seen from the
    /// normal's side).
    pub tangent: Vec3,
    /// The face's unit normal.
    pub normal: Vec3,
}

/// A face's edge as it is: t ∈ [0, 1] ↦ [`EdgeFrame`] (for a STEP face,
/// the edge's curve and the normal of the face's surface at its foot
/// point), with the parameters where it is less smooth (its breaks).
/// Compared by identity.
#[derive(Clone)]
pub struct TrueEdge(
    Arc<dyn Fn(f64) -> EdgeFrame + Send + Sync>,
    Arc<[Break]>,
    /// The frames computed so far, by t's bits: a strip's fits try several
    /// knot vectors at parameters that come back (Chebyshev–Lobatto ones,
    /// the ends of halved pieces), and a fill's side is measured at the
    /// parameters the fits checked already (a frame of a STEP edge is a
    /// foot-point search on its face).
    Arc<Mutex<HashMap<u64, EdgeFrame>>>,
);

/// A parameter t ∈ (0, 1) where an edge is less smooth: its points are
/// only C^`continuity` there (a knot of the edge's curve of degree p and
/// multiplicity m: C^(p − m); a knot line of the face's surface crossed,
/// likewise in that direction). The face's normal along the edge, and the
/// direction across it, are then one order less smooth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Break {
    /// Where, t ∈ (0, 1).
    pub at: f64,
    /// The order of continuity of the edge's points there.
    pub continuity: usize,
}

impl Break {
    /// The multiplicity of a strip's knot at the break (degree 5): 5 − k
    /// for C^k, k ≥ 1 (as smooth as the points there; the direction
    /// across, one order less, is within the tolerance on few pieces:
    /// measured). At a C⁰ break, 4 (C¹) for a strip across a free edge,
    /// whose C⁰ breaks are smooth in fact ([`corner_inside`] refuses a
    /// turn of the tangent or the normal): a fill takes the strip's knots,
    /// and a C⁰ knot would let it crease there at no cost in energy (its
    /// pieces' integrals do not see a kink between them), while a C¹ one
    /// keeps it in H², where the thin plate's integral is whole. C² there
    /// (3) was tried: a loft's C¹ knot lines 1000 across were then met only
    /// after 512 pieces, a fill of 69,144 free points. With `kinks` (the
    /// edge alone, [`edge_stand_in`], which no fill takes: a polyline two
    /// faces share) 5 down to C⁰, the kinks followed exactly.
    fn multiplicity(self, kinks: bool) -> usize {
        let exact = FIRST_DEGREE.saturating_sub(self.continuity).max(1);
        if kinks {
            exact
        } else {
            exact.min(FIRST_DEGREE - 1)
        }
    }
}

impl TrueEdge {
    /// The edge given by `frame`, a function of t alone: each t's frame
    /// is computed once and kept ([`Self::frame`]).
    pub fn new(frame: impl Fn(f64) -> EdgeFrame + Send + Sync + 'static) -> Self {
        Self(Arc::new(frame), Arc::new([]), Default::default())
    }

    /// The same edge with its breaks ([`Break`]; those outside (0, 1) or
    /// not finite dropped, those within 1e-9 of each other one, the least
    /// smooth). A strip of several pieces puts knots there
    /// ([`strip_stand_in`]).
    pub fn with_breaks(self, mut breaks: Vec<Break>) -> Self {
        breaks.retain(|b| b.at.is_finite() && b.at > 1e-9 && b.at < 1.0 - 1e-9);
        breaks.sort_by(|a, b| a.at.total_cmp(&b.at));
        breaks.dedup_by(|a, b| {
            let same = (a.at - b.at).abs() <= 1e-9;
            if same {
                b.continuity = b.continuity.min(a.continuity);
            }
            same
        });
        Self(self.0, breaks.into(), self.2)
    }

    /// The breaks ([`Self::with_breaks`]), in order.
    pub fn breaks(&self) -> &[Break] {
        &self.1
    }

    /// The edge's frame at t ∈ [0, 1] (computed once per t).
    pub fn frame(&self, t: f64) -> EdgeFrame {
        let seen = || self.2.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(f) = seen().get(&t.to_bits()) {
            return *f;
        }
        let f = (self.0)(t);
        let mut cache = seen();
        if cache.len() >= MAX_CACHED_FRAMES {
            cache.clear();
        }
        cache.insert(t.to_bits(), f);
        f
    }

    /// The tangents at t of a surface with the edge's point and normal
    /// there (R, R_u, R_v with R_u × R_v along the normal): what a side
    /// measurement compares a fill with.
    pub(crate) fn tangents(&self, t: f64) -> [Vec3; 3] {
        let f = self.frame(t);
        [f.point, f.tangent, cross(f.normal, f.tangent)]
    }
}

impl std::fmt::Debug for TrueEdge {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("TrueEdge(..)")
    }
}

impl PartialEq for TrueEdge {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// The most frames an edge keeps ([`TrueEdge::frame`]; it forgets them
/// all past that: ~6 MB, far more than a strip's fits and a fill's sides
/// ask, which stay well under 10,000).
const MAX_CACHED_FRAMES: usize = 65_536;

/// The most pieces a strip cuts its edge into.
const MAX_PIECES: usize = 512;
/// The first degree of a strip along its edge.
const FIRST_DEGREE: usize = 5;

/// The strip stand-in of `edge` (module doc): degree (d, 1) on [0, 1]²,
/// its side V0 the edge, T across it at right angles, `width` long.
/// Degree 5 on equal pieces, their number the least power of two with
/// which the strip is within `tolerance` (found in fewer fits than
/// doubling from one: predicted from each fit's errors, then bisected);
/// with `one_span` (a fan of triangular patches needs each side one
/// polynomial piece) one Bézier span of
/// degree 5 to [`ONE_SPAN_DEGREE`] instead. The pieces: the edge's breaks
/// ([`TrueEdge::breaks`], knots as smooth as the edge there) cut in equal
/// parts. Interpolates the edge's points and
/// inward directions at Chebyshev–Lobatto nodes (one span) or the
/// Greville abscissae; measured at Chebyshev–Lobatto parameters on every
/// span (at least 9 each, about 129 in all) and at the 129 a fill's side
/// is measured at ([`crate::fill::SIDE_SAMPLES`]): the largest distance to
/// the edge's point at the same parameter and the largest angle between
/// the strip's normal and the face's. Errors when 512 pieces (one span of
/// degree 15) are not enough, or the edge has no tangent or normal
/// somewhere.
pub fn strip_stand_in(
    edge: &TrueEdge,
    width: f64,
    tolerance: FitTolerance,
    one_span: bool,
) -> Result<StandIn> {
    if !(width.is_finite() && width > 0.0) {
        return Err(Error::Fill {
            why: format!("a strip stand-in needs a positive width, not {width}"),
        });
    }
    fit(edge, Across::Right(width), tolerance, one_span)
}

/// [`strip_stand_in`] with S_v leaving the edge's ends as `ends` (at t = 0
/// and t = 1; projected into the face's tangent plane there, each pointing
/// into the face): along the edge T is turned from the edge's tangent by
/// an angle, and is as long as a length, that run linearly from one end's
/// to the other's. A fill's corner takes the cross derivative of one side
/// as the derivative of the next: a strip whose ends leave as the next
/// sides of its hole do lets a patch's corners agree. Errors when an end
/// does not point into the face (within 0.1° of the edge's tangent line,
/// or across to the other side).
pub fn strip_stand_in_towards(
    edge: &TrueEdge,
    ends: [Vec3; 2],
    tolerance: FitTolerance,
    one_span: bool,
) -> Result<StandIn> {
    let mut turn = [(0.0, 0.0); 2];
    for (k, (e, t)) in ends.iter().zip([0.0, 1.0]).enumerate() {
        let f = edge.frame(t);
        let (along, across) = axes(&f).ok_or_else(|| no_frame(t))?;
        let (x, y) = (dot(*e, along), dot(*e, across));
        let b = y.atan2(x);
        let least = 0.1f64.to_radians();
        if !(b.is_finite() && b >= least && b <= std::f64::consts::PI - least) {
            return Err(Error::Fill {
                why: format!(
                    "a trimmed face's edge would leave its {} end along {e:?}, which does not \
                     point into the face (at {:.3}° from the edge's tangent)",
                    ["first", "last"][k],
                    b.to_degrees()
                ),
            });
        }
        turn[k] = (b, x.hypot(y));
    }
    fit(edge, Across::Towards(turn), tolerance, one_span)
}

/// The edge alone as a strip of no width (its sides V0 and V1 both the
/// edge, within `tolerance.position`; fitted as [`strip_stand_in`] fits,
/// without the face's normal): for an edge no fill meets — one two faces
/// share — whose curve the STEP writer and the matching of sides still
/// take, where the face has no normal to make a strip from (a seam edge
/// running into a pole, a collapsed side of the surface). Its angle is
/// not measured: 0.
pub fn edge_stand_in(edge: &TrueEdge, tolerance: FitTolerance) -> Result<StandIn> {
    fit(edge, Across::None, tolerance, false)
}

/// How a strip's T runs: across the edge at right angles, this long; or
/// turned from the edge's tangent by an angle and as long as a length
/// that run linearly from the first end's (angle, length) to the last's;
/// or not at all (the edge alone: [`edge_stand_in`]).
#[derive(Clone, Copy)]
enum Across {
    Right(f64),
    Towards([(f64, f64); 2]),
    None,
}

/// The strip (see [`strip_stand_in`]).
fn fit(
    edge: &TrueEdge,
    across: Across,
    tolerance: FitTolerance,
    one_span: bool,
) -> Result<StandIn> {
    if !matches!(across, Across::None) {
        if let Some(e) = corner_inside(edge, tolerance) {
            return Err(e);
        }
    }
    let normals = !matches!(across, Across::None);
    let mut best: Option<(usize, f64, f64, String)> = None;
    let mut attempt = |knots: KnotVector| -> Result<(StandIn, bool)> {
        let what = match knots.spans().len() {
            1 => format!("one span of degree {}", knots.degree()),
            n => format!("{n} pieces of degree {FIRST_DEGREE}"),
        };
        let surface = interpolate(edge, across, knots)?;
        let (position, angle) = deviation(edge, &surface, normals)?;
        let within = position <= tolerance.position && angle <= tolerance.angle;
        // The refusal names the failed fit of the most pieces (the last
        // tried of one span's degrees).
        let spans = surface.knots().0.spans().len();
        if !within && best.as_ref().is_none_or(|b| spans >= b.0) {
            best = Some((spans, position, angle, what));
        }
        let fit = StandIn {
            surface,
            position,
            angle,
        };
        Ok((fit, within))
    };
    if one_span {
        for degree in FIRST_DEGREE..=ONE_SPAN_DEGREE {
            if let (fit, true) = attempt(KnotVector::bezier(degree))? {
                return Ok(fit);
            }
        }
    } else if let Some(fit) = least_pieces(|n| {
        attempt(pieces(edge.breaks(), n, !normals)?).map(|(fit, within)| {
            let (p, a) = (fit.position, fit.angle);
            (fit, within, [p / tolerance.position, a / tolerance.angle])
        })
    })? {
        return Ok(fit);
    }
    let (_, position, angle, what) = best.expect("at least one fit");
    Err(Error::Fill {
        why: format!(
            "a trimmed face's edge could not be approximated by a polynomial strip within {:e} \
             in position and {:e}° in angle (reached {position:e} and {:e}° with {what})",
            tolerance.position,
            tolerance.angle.to_degrees(),
            angle.to_degrees(),
        ),
    })
}

/// The fit of the least power of two n ≤ [`MAX_PIECES`] of pieces per
/// interval between breaks that `fit(n)` finds within the tolerance (it
/// returns the fit, whether it is within, and its errors over the
/// tolerances in position and angle), None when 512 are not enough —
/// the first of 1, 2, 4, … that passes, as long as a fit of more pieces
/// is never worse, with fewer fits than trying each in turn: after a fit
/// that fails, the next n is predicted from its errors (position falls as
/// h⁶, the angle as h⁵, h the pieces' length: n·max(e_p^(1/6),
/// e_a^(1/5)) rounded up to a power of two, at least twice n and at most
/// 16 times), and once one passes the powers of two between the last
/// failure and it are bisected. A pipe's rim, a whole circle, took fits at
/// 1, 8 and 16 pieces instead of 1, 2, 4, 8 and 16. Should 512 fail where
/// errors grew with n (an edge's noise followed by more nodes), the
/// powers skipped are tried in turn before None: what passed doubling
/// from one still passes.
fn least_pieces<T>(mut fit: impl FnMut(usize) -> Result<(T, bool, [f64; 2])>) -> Result<Option<T>> {
    // Powers of two by their exponents: `failed` the largest known to
    // fail, `passed` the least known to pass.
    let most = MAX_PIECES.trailing_zeros();
    let mut failed: Option<u32> = None;
    let mut tried = Vec::new();
    let mut k = 0;
    let mut passed = loop {
        tried.push(k);
        let (f, within, [p, a]) = fit(1 << k)?;
        if within {
            break (k, f);
        }
        failed = Some(k);
        if k >= most {
            for j in (0..most).filter(|j| !tried.contains(j)) {
                if let (f, true, _) = fit(1 << j)? {
                    return Ok(Some(f));
                }
            }
            return Ok(None);
        }
        // Errors NaN count as 0 (`max`): then twice, as when infinite
        // (log2 of 0 and of infinity, clamped) 16 times.
        let ratio = p.max(0.0).powf(1.0 / 6.0).max(a.max(0.0).powf(0.2));
        let grow = ratio.log2().ceil().clamp(1.0, 4.0) as u32;
        k = (k + grow).min(most);
    };
    while let Some(lo) = failed {
        if passed.0 <= lo + 1 {
            break;
        }
        let mid = lo + (passed.0 - lo) / 2;
        let (f, within, _) = fit(1 << mid)?;
        if within {
            passed = (mid, f);
        } else {
            failed = Some(mid);
        }
    }
    Ok(Some(passed.1))
}

/// The refusal of a strip along an edge that turns inside (a break of its
/// points only C⁰ where its tangent, or the face's normal, turns by more
/// than the angle tolerance): the direction across the edge jumps there,
/// which no strip follows — a corner of the hole inside one edge, or a
/// crease of the face running into it, named by its point and turn. None
/// when there is none.
fn corner_inside(edge: &TrueEdge, tolerance: FitTolerance) -> Option<Error> {
    edge.breaks()
        .iter()
        .filter(|b| b.continuity == 0)
        .find_map(|b| {
            let (before, after) = (edge.frame(b.at - 1e-9), edge.frame(b.at + 1e-9));
            let turn = angle(before.tangent, after.tangent);
            let crease = angle(before.normal, after.normal);
            let (what, by) = if turn.is_nan() || turn > tolerance.angle {
                ("edge turns", turn)
            } else if crease > tolerance.angle {
                ("face creases across the edge", crease)
            } else {
                return None;
            };
            let p = edge.frame(b.at).point;
            Some(Error::Fill {
                why: format!(
                    "a trimmed face's {what} by {:.3}° at ({}, {}, {}), {:.1}% along it (its \
                     curve or surface has a kink there): a corner of a hole inside one edge is \
                     not followed by a strip; split the edge there",
                    by.to_degrees(),
                    p[0],
                    p[1],
                    p[2],
                    100.0 * b.at
                ),
            })
        })
}

/// Degree-5 knots on [0, 1]: the intervals between `breaks` (knots of
/// [`Break::multiplicity`] there, `kinks` as it says) each cut in `n`
/// equal pieces.
fn pieces(breaks: &[Break], n: usize, kinks: bool) -> Result<KnotVector> {
    let d = FIRST_DEGREE;
    let mut t = vec![0.0; d + 1];
    let mut a = 0.0;
    for b in breaks.iter().map(Some).chain([None]) {
        let end = b.map_or(1.0, |b| b.at);
        t.extend((1..n).map(|i| a + (end - a) * i as f64 / n as f64));
        if let Some(b) = b {
            t.extend(std::iter::repeat_n(b.at, b.multiplicity(kinks)));
        }
        a = end;
    }
    t.extend([1.0; FIRST_DEGREE + 1]);
    KnotVector::new(d, t)
}

/// The unit tangent and the unit inward direction n × c′/|c′| of a
/// frame (orthonormal, in the tangent plane), or None where the edge has
/// no tangent across the normal.
fn axes(f: &EdgeFrame) -> Option<(Vec3, Vec3)> {
    let across = cross(f.normal, f.tangent);
    let n = norm(across);
    let across = scale(across, 1.0 / n);
    let along = cross(across, f.normal);
    let m = norm(along);
    (n > 1e-300 && n.is_finite() && m > 0.5).then(|| (scale(along, 1.0 / m), across))
}

/// The strip on `knots` × Bézier(1) through the edge's points and its
/// T (`across`) at the interpolation nodes.
fn interpolate(edge: &TrueEdge, across: Across, knots: KnotVector) -> Result<BSplineSurface> {
    // One span: Chebyshev–Lobatto nodes (near-best polynomial
    // interpolation; equally spaced Greville abscissae of a high degree
    // amplify the edge's own approximation error, Runge); several spans:
    // the Greville abscissae.
    let g = if knots.spans().len() == 1 {
        let d = knots.degree();
        (0..=d)
            .map(|i| 0.5 - 0.5 * (std::f64::consts::PI * i as f64 / d as f64).cos())
            .collect()
    } else {
        knots.greville()
    };
    let n = g.len();
    let mut data = Vec::with_capacity(6 * n);
    for &t in &g {
        let f = edge.frame(t);
        let d = match across {
            Across::None => [0.0; 3],
            Across::Right(width) => {
                let (_, right) = axes(&f).ok_or_else(|| no_frame(t))?;
                scale(right, width)
            }
            Across::Towards([(a, la), (b, lb)]) => {
                let (along, right) = axes(&f).ok_or_else(|| no_frame(t))?;
                let (s, c) = (a + (b - a) * t).sin_cos();
                let l = la + (lb - la) * t;
                std::array::from_fn(|k| l * (c * along[k] + s * right[k]))
            }
        };
        data.extend(f.point);
        data.extend(d);
    }
    let x = solve_dense_wide(knots.collocation(&g), data, 6).ok_or_else(|| Error::Fill {
        why: "the collocation system of a strip stand-in is singular".into(),
    })?;
    let mut points = Vec::with_capacity(2 * n);
    for i in 0..n {
        let c = [x[6 * i], x[6 * i + 1], x[6 * i + 2]];
        let d = [x[6 * i + 3], x[6 * i + 4], x[6 * i + 5]];
        points.push(c);
        points.push(std::array::from_fn(|k| c[k] + d[k]));
    }
    BSplineSurface::new(knots, KnotVector::bezier(1), points)
}

fn no_frame(t: f64) -> Error {
    Error::Fill {
        why: format!(
            "a trimmed face's edge has no tangent across the face's normal at t = {t}: no strip \
             stand-in"
        ),
    }
}

/// Largest distance and normal angle between the strip's side V0 and the
/// edge at the same parameters (Chebyshev–Lobatto on every span, and
/// where a fill's side is measured); the angle 0 unless `normals`.
fn deviation(edge: &TrueEdge, s: &BSplineSurface, normals: bool) -> Result<(f64, f64)> {
    let mut ts = side_parameters(s.knots().0);
    ts.extend(crate::fill::measure_side_parameters());
    let (mut gap, mut ang) = (0.0f64, 0.0f64);
    for (t, d) in ts.iter().zip(s.derivatives_on(&ts, &[0.0])) {
        let f = edge.frame(*t);
        gap = gap.max(dist(f.point, d.point));
        if !normals {
            continue;
        }
        axes(&f).ok_or_else(|| no_frame(*t))?;
        // No normal on the strip counts as the worst.
        ang = ang.max(
            d.regular_normal()
                .map_or(std::f64::consts::PI, |m| angle(f.normal, m)),
        );
    }
    Ok((gap, ang))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ellipse where the plane z = k·x cuts the cylinder x² + y² = 1,
    /// run counter-clockwise seen from outside (+x at t = 0… a whole turn
    /// when `turn` = 1), with the cylinder's outward normal: a trimmed
    /// cylinder's edge.
    fn cylinder_cut(k: f64, turn: f64) -> TrueEdge {
        TrueEdge::new(move |t| {
            let a = 2.0 * std::f64::consts::PI * turn * t;
            let w = 2.0 * std::f64::consts::PI * turn;
            let (s, c) = a.sin_cos();
            // Seen from outside the cylinder (normal (c, s, 0)) with the
            // face below the cut on the left: the loop runs clockwise
            // about +z along the top edge.
            EdgeFrame {
                point: [c, -s, k * c],
                tangent: [-s * w, -c * w, -k * s * w],
                normal: [c, -s, 0.0],
            }
        })
    }

    /// An edge's frame is computed once per parameter, by the edge and
    /// the copies that share it (with its breaks too): after a strip's
    /// fit, a side measured at the fit's parameters (forwards or
    /// backwards: the set is closed under t ↦ 1 − t) computes none.
    #[test]
    fn an_edge_computes_each_frame_once() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let calls = Arc::new(AtomicUsize::new(0));
        let counted = calls.clone();
        let inner = cylinder_cut(0.5, 0.25);
        let edge = TrueEdge::new(move |t| {
            counted.fetch_add(1, Ordering::Relaxed);
            inner.frame(t)
        })
        .with_breaks(vec![Break {
            at: 0.5,
            continuity: 2,
        }]);
        let a = edge.frame(0.25);
        assert_eq!(edge.clone().frame(0.25), a);
        assert_eq!(calls.load(Ordering::Relaxed), 1);
        strip_stand_in(&edge, 0.3, FitTolerance::default(), false).unwrap();
        let fitted = calls.load(Ordering::Relaxed);
        for t in crate::fill::measure_side_parameters() {
            edge.frame(t);
            edge.frame(1.0 - t);
        }
        assert_eq!(calls.load(Ordering::Relaxed), fitted);
    }

    #[test]
    fn a_strip_meets_its_tolerance_along_the_edge_and_points_into_the_face() {
        let edge = cylinder_cut(0.5, 0.25);
        let tol = FitTolerance::default();
        let s = strip_stand_in(&edge, 0.3, tol, true).unwrap();
        assert!(s.position <= tol.position && s.angle <= tol.angle, "{s:?}");
        // A quarter of the ellipse is one span (a fan can take it).
        assert_eq!(s.surface.knots().0.spans().len(), 1);
        // Independently of the fit's own measure: at 1000 parameters the
        // strip's V0 is on the cylinder, its normal the cylinder's.
        for i in 0..=1000 {
            let t = i as f64 / 1000.0;
            let d = s.surface.derivatives(t, 0.0);
            let f = edge.frame(t);
            assert!(dist(d.point, f.point) <= 1.0001 * tol.position, "{t}");
            let r = (d.point[0].powi(2) + d.point[1].powi(2)).sqrt();
            assert!((r - 1.0).abs() <= 1.0001 * tol.position, "{t}: r = {r}");
            let n = d.regular_normal().unwrap();
            assert!(angle(n, f.normal) <= 1.0001 * tol.angle, "{t}");
            // S_v points into the face: below the cut (z < k·x at the
            // same x, y), along the cylinder.
            assert!(d.dv[2] < 0.0, "{t}: {:?}", d.dv);
            assert!(dot(d.dv, f.normal).abs() <= 1e-4 * norm(d.dv), "{t}");
            assert!((norm(d.dv) - 0.3).abs() <= 1e-4, "{t}: width");
        }
    }

    /// [`least_pieces`] on errors `e(n)` over the tolerance in position
    /// and angle (passing when both are at most 1): what it returns and
    /// the n it tried, in order.
    fn search(e: impl Fn(usize) -> [f64; 2]) -> (Option<usize>, Vec<usize>) {
        let mut tried = Vec::new();
        let got = least_pieces(|n| {
            tried.push(n);
            let [p, a] = e(n);
            Ok((n, p <= 1.0 && a <= 1.0, [p, a]))
        })
        .unwrap();
        (got, tried)
    }

    /// The search for the pieces per interval returns the least power of
    /// two that passes: on errors falling as h⁶ with fewer fits than
    /// trying 1, 2, 4, … in turn; where the prediction overshoots (the
    /// first fit's error far from the asymptote), bisecting back down.
    #[test]
    fn least_pieces_finds_the_least_power_of_two_that_passes() {
        // e(n) = c / n⁶ over the tolerance: passes from n ≥ c^(1/6).
        for c in [0.5, 3.0, 1e3, 1e6, 7e12, 1e17] {
            let (got, tried) = search(|n| [c / (n as f64).powi(6), 0.0]);
            let least = (0..=9)
                .map(|k| 1usize << k)
                .find(|&n| c / (n as f64).powi(6) <= 1.0);
            assert_eq!(got, least, "{c}: {tried:?}");
            let doubling = least.map_or(10, |n| n.trailing_zeros() as usize + 1);
            assert!(tried.len() <= doubling, "{c}: {tried:?}");
            if c >= 1e6 && least.is_some() {
                assert!(tried.len() < doubling, "{c}: {tried:?}");
            }
        }
        // A first error far above the rest: the jump to 16 passes, and
        // bisection finds 4 (2 fails).
        let (got, tried) = search(|n| {
            let e = match n {
                1 => 1e6,
                2 => 2.0,
                _ => 0.5,
            };
            [e, 0.0]
        });
        assert_eq!((got, tried.as_slice()), (Some(4), &[1, 16, 4, 2][..]));
        // In angle (h⁵) as in position, and NaN errors just double.
        let (got, tried) = search(|n| {
            let e = if n >= 8 { 0.5 } else { f64::NAN };
            [e, e]
        });
        assert_eq!((got, tried.as_slice()), (Some(8), &[1, 2, 4, 8][..]));
        // Errors that grow with n past the one that passes (2): the jump
        // skips it, 16 to 512 fail, and the powers skipped are tried in
        // turn before giving up: 2, as doubling from one finds.
        let (got, tried) = search(|n| {
            let e = match n {
                1 => 1e6,
                2 => 0.5,
                _ => 2.0,
            };
            [e, 0.0]
        });
        assert_eq!(
            (got, tried.as_slice()),
            (Some(2), &[1, 16, 32, 64, 128, 256, 512, 2][..])
        );
        // Nothing passes: every power tried, None.
        let (got, mut tried) = search(|_| [2.0, 0.0]);
        assert_eq!(got, None);
        tried.sort();
        assert_eq!(tried, (0..=9).map(|k| 1 << k).collect::<Vec<usize>>());
    }

    /// On a cut cylinder's edge, a whole turn or two, at tolerances from
    /// 1e-3 to 1e-11: the strip's pieces are a power of two, and half as
    /// many, fitted directly, miss the tolerance.
    #[test]
    fn a_strip_takes_the_least_power_of_two_of_pieces_that_meets_the_tolerance() {
        for (turn, position) in [(1.0, 1e-3), (1.0, 1e-6), (1.0, 1e-9), (2.0, 1e-11)] {
            let tol = FitTolerance {
                position,
                angle: 0.01f64.to_radians(),
            };
            let edge = cylinder_cut(0.5, turn);
            let s = strip_stand_in(&edge, 0.3, tol, false).unwrap();
            let n = s.surface.knots().0.spans().len();
            assert!(n.is_power_of_two(), "{n}");
            assert!(s.position <= tol.position && s.angle <= tol.angle);
            assert!(n > 1, "{turn} {position}");
            let half = pieces(&[], n / 2, false).unwrap();
            let strip = interpolate(&edge, Across::Right(0.3), half).unwrap();
            let (p, a) = deviation(&edge, &strip, true).unwrap();
            assert!(p > tol.position || a > tol.angle, "{n}: {p} {a}");
        }
    }

    #[test]
    fn a_tighter_tolerance_or_a_longer_edge_takes_more() {
        let tol = FitTolerance::default();
        let degree = |s: &StandIn| s.surface.knots().0.degree();
        let quarter = strip_stand_in(&cylinder_cut(0.5, 0.25), 0.3, tol, true).unwrap();
        let tight = FitTolerance {
            position: 1e-10,
            angle: 1e-8,
        };
        let fine = strip_stand_in(&cylinder_cut(0.5, 0.25), 0.3, tight, false).unwrap();
        assert!(fine.position <= 1e-10 && fine.angle <= 1e-8, "{fine:?}");
        assert!(degree(&fine) < degree(&quarter) && fine.surface.knots().0.spans().len() > 1);
        // A whole turn is more than one span of degree 15 can hold: in one
        // span it is refused, in pieces it is not.
        let e = strip_stand_in(&cylinder_cut(0.5, 1.0), 0.3, tol, true).unwrap_err();
        assert!(e.to_string().contains("with one span of degree 15"), "{e}");
        let whole = strip_stand_in(&cylinder_cut(0.5, 1.0), 0.3, tol, false).unwrap();
        assert!(whole.surface.knots().0.spans().len() > 1, "{whole:?}");
        assert!(whole.position <= tol.position && whole.angle <= tol.angle);
    }

    #[test]
    fn a_strip_towards_given_ends_leaves_them_as_given_and_without_one_span_takes_pieces() {
        let edge = cylinder_cut(0.5, 0.25);
        let tol = FitTolerance::default();
        // In the cylinder's tangent planes at the ends, into the face
        // (down), of different lengths, not at right angles to the edge.
        let (f0, f1) = (edge.frame(0.0), edge.frame(1.0));
        let (a0, r0) = axes(&f0).unwrap();
        let (a1, r1) = axes(&f1).unwrap();
        let e0: Vec3 = std::array::from_fn(|k| 0.4 * (0.5 * a0[k] + r0[k]));
        let e1: Vec3 = std::array::from_fn(|k| 0.9 * (-0.3 * a1[k] + r1[k]));
        for one_span in [true, false] {
            let s = strip_stand_in_towards(&edge, [e0, e1], tol, one_span).unwrap();
            assert!(s.position <= tol.position && s.angle <= tol.angle, "{s:?}");
            let spans = s.surface.knots().0.spans().len();
            assert_eq!(
                spans == 1 && s.surface.degree().0 > FIRST_DEGREE,
                one_span,
                "{spans}"
            );
            for (t, e) in [(0.0, e0), (1.0, e1)] {
                let dv = s.surface.derivatives(t, 0.0).dv;
                assert!(dist(dv, e) <= 1e-12, "{one_span} {t}: {dv:?} {e:?}");
            }
        }
        // An end pointing out of the face is refused by name.
        let out: Vec3 = std::array::from_fn(|k| -r1[k]);
        let e = strip_stand_in_towards(&edge, [e0, out], tol, true).unwrap_err();
        assert!(
            e.to_string().contains("does not point into the face"),
            "{e}"
        );
    }

    #[test]
    fn knots_at_the_edges_breaks_follow_it_in_few_pieces() {
        // y = (t − 0.3)₊³ in the plane z = 0: C² at t = 0.3, a cubic on
        // either side.
        let frame = |t: f64| {
            let x = (t - 0.3).max(0.0);
            EdgeFrame {
                point: [t, x.powi(3), 0.0],
                tangent: [1.0, 3.0 * x * x, 0.0],
                normal: [0.0, 0.0, 1.0],
            }
        };
        let tol = FitTolerance {
            position: 1e-9,
            angle: 1e-7,
        };
        let plain = strip_stand_in(&TrueEdge::new(frame), 0.5, tol, false).unwrap();
        let at = |at, continuity| Break { at, continuity };
        let broken = TrueEdge::new(frame).with_breaks(vec![
            at(0.3, 2),
            at(1.0, 0),
            at(-0.2, 0),
            at(f64::NAN, 0),
            at(0.3, 3),
        ]);
        assert_eq!(broken.breaks(), &[at(0.3, 2)]);
        let s = strip_stand_in(&broken, 0.5, tol, false).unwrap();
        // Quintic pieces joined C² at the break hold the cubics: C is
        // exact (T = n × c′/|c′| is no polynomial: within the tolerance);
        // equal pieces across the break only converge.
        let (ours, theirs) = (
            s.surface.knots().0.spans().len(),
            plain.surface.knots().0.spans().len(),
        );
        assert!(
            s.position <= 1e-14 && plain.position > 1e-12,
            "{s:?} {plain:?}"
        );
        assert!(4 * ours <= theirs, "{ours} {theirs}");
        let knots = s.surface.knots().0;
        assert_eq!(knots.multiplicity(0.3), 3);
    }

    #[test]
    fn a_straight_edge_on_a_plane_is_exact() {
        // The plane z = 0, the face on the left of the x axis (y > 0).
        let edge = TrueEdge::new(|t| EdgeFrame {
            point: [2.0 * t, 0.0, 0.0],
            tangent: [2.0, 0.0, 0.0],
            normal: [0.0, 0.0, 1.0],
        });
        let s = strip_stand_in(&edge, 1.0, FitTolerance::default(), true).unwrap();
        assert!(s.position <= 1e-15 && s.angle <= 1e-15, "{s:?}");
        assert_eq!(s.surface.knots().0.degree(), FIRST_DEGREE);
        let p = s.surface.eval(0.5, 1.0);
        assert!(dist(p, [1.0, 1.0, 0.0]) <= 1e-14, "{p:?}");
    }

    #[test]
    fn edges_it_cannot_follow_are_refused_by_name() {
        // The normal along the tangent: no direction across.
        let edge = TrueEdge::new(|t| EdgeFrame {
            point: [t, 0.0, 0.0],
            tangent: [1.0, 0.0, 0.0],
            normal: [1.0, 0.0, 0.0],
        });
        let e = strip_stand_in(&edge, 1.0, FitTolerance::default(), true).unwrap_err();
        assert!(e.to_string().contains("no tangent across"), "{e}");
        // A kink: a polygon's corner inside the edge is no polynomial.
        let kink = TrueEdge::new(|t| EdgeFrame {
            point: [t, (t - 0.3).abs(), 0.0],
            tangent: [1.0, (t - 0.3).signum(), 0.0],
            normal: [0.0, 0.0, 1.0],
        });
        let e = strip_stand_in(&kink, 1.0, FitTolerance::default(), false).unwrap_err();
        assert!(e.to_string().contains("could not be approximated"), "{e}");
        assert!(e.to_string().contains("512 pieces"), "{e}");
        assert!(strip_stand_in(&kink, 0.0, FitTolerance::default(), true).is_err());
        assert!(strip_stand_in(&kink, f64::NAN, FitTolerance::default(), true).is_err());
        // Nor can the edge's curve alone follow a kink.
        let e = edge_stand_in(&kink, FitTolerance::default()).unwrap_err();
        assert!(e.to_string().contains("could not be approximated"), "{e}");
    }

    /// A kink the edge declares (a break of continuity 0: a polyline's
    /// vertex): its curve alone is followed exactly, by pieces joined C⁰
    /// there (a knot of multiplicity 5); a strip across it is refused at
    /// once, naming the corner (the direction across jumps by the turn).
    #[test]
    fn a_declared_kink_is_followed_by_the_curve_and_refused_for_a_strip() {
        let kink = TrueEdge::new(|t| EdgeFrame {
            point: [t, (t - 0.3).abs(), 0.0],
            tangent: [1.0, (t - 0.3).signum(), 0.0],
            normal: [0.0, 0.0, 1.0],
        })
        .with_breaks(vec![Break {
            at: 0.3,
            continuity: 0,
        }]);
        let tol = FitTolerance::default();
        let s = edge_stand_in(&kink, tol).unwrap();
        assert!(s.position <= 1e-14, "{s:?}");
        let knots = s.surface.knots().0;
        assert_eq!((knots.spans().len(), knots.multiplicity(0.3)), (2, 5));
        for i in 0..=1000 {
            let t = i as f64 / 1000.0;
            assert!(
                dist(s.surface.eval(t, 0.0), kink.frame(t).point) <= 1e-14,
                "{t}"
            );
        }
        for e in [
            strip_stand_in(&kink, 0.5, tol, false).unwrap_err(),
            strip_stand_in_towards(&kink, [[0.0, 1.0, 0.0]; 2], tol, false).unwrap_err(),
        ] {
            let e = e.to_string();
            assert!(e.contains("turns by 90.000° at (0.3, 0"), "{e}");
            assert!(
                e.contains("30.0% along it") && e.contains("split the edge"),
                "{e}"
            );
        }
        // A smooth vertex of a C⁰-written curve (the tangent does not
        // turn): a strip follows it.
        let line = TrueEdge::new(|t| EdgeFrame {
            point: [t, 0.0, 0.0],
            tangent: [1.0, 0.0, 0.0],
            normal: [0.0, 0.0, 1.0],
        })
        .with_breaks(vec![Break {
            at: 0.3,
            continuity: 0,
        }]);
        let s = strip_stand_in(&line, 0.5, tol, false).unwrap();
        assert!(s.position <= 1e-15 && s.angle <= 1e-15, "{s:?}");
        // Its knot there is C¹, not C⁰: a fill taking it must not crease.
        assert_eq!(s.surface.knots().0.multiplicity(0.3), 4);
        // The face creasing across a straight edge (its normal turns by
        // 30° about the edge): refused alike, naming the crease.
        let crease = TrueEdge::new(|t| EdgeFrame {
            point: [t, 0.0, 0.0],
            tangent: [1.0, 0.0, 0.0],
            normal: if t < 0.3 {
                [0.0, 0.0, 1.0]
            } else {
                [0.0, -0.5, 0.75f64.sqrt()]
            },
        })
        .with_breaks(vec![Break {
            at: 0.3,
            continuity: 0,
        }]);
        let e = strip_stand_in(&crease, 0.5, tol, false)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("face creases across the edge by 30.000° at (0.3, 0, 0)"),
            "{e}"
        );
        assert!(edge_stand_in(&crease, tol).is_ok());
    }

    /// The knots at breaks: as smooth as the edge's points there from C¹
    /// up (5 − k); at C⁰, C¹ for a strip a fill takes (no crease), C⁰ for
    /// the edge alone (kinks followed).
    #[test]
    fn a_break_gets_the_knot_its_continuity_needs() {
        let m = |kinks| {
            move |continuity| {
                Break {
                    at: 0.5,
                    continuity,
                }
                .multiplicity(kinks)
            }
        };
        assert_eq!([0, 1, 2, 3, 4, 5, 9].map(m(true)), [5, 4, 3, 2, 1, 1, 1]);
        assert_eq!([0, 1, 2, 3, 4, 5, 9].map(m(false)), [4, 4, 3, 2, 1, 1, 1]);
        let breaks = [
            Break {
                at: 0.25,
                continuity: 0,
            },
            Break {
                at: 0.5,
                continuity: 3,
            },
        ];
        for (kinks, first) in [(true, 5), (false, 4)] {
            let k = pieces(&breaks, 2, kinks).unwrap();
            assert_eq!(
                (k.multiplicity(0.25), k.multiplicity(0.5), k.spans().len()),
                (first, 2, 6)
            );
        }
    }

    /// An edge whose face has no normal along it (NaN, as at a pole):
    /// no strip, but its curve alone, within the tolerance of the edge's
    /// points at 1000 parameters, both sides of no width the edge.
    #[test]
    fn an_edge_without_normals_stands_in_by_its_curve_alone() {
        let quarter = cylinder_cut(0.5, 0.25);
        let edge = TrueEdge::new(move |t| EdgeFrame {
            normal: [f64::NAN; 3],
            ..quarter.frame(t)
        });
        let tol = FitTolerance::default();
        let e = strip_stand_in(&edge, 0.3, tol, false).unwrap_err();
        assert!(e.to_string().contains("no tangent across"), "{e}");
        let s = edge_stand_in(&edge, tol).unwrap();
        assert!(s.position <= tol.position && s.angle == 0.0, "{s:?}");
        for i in 0..=1000 {
            let t = i as f64 / 1000.0;
            let f = edge.frame(t);
            let (v0, v1) = (s.surface.eval(t, 0.0), s.surface.eval(t, 1.0));
            assert!(dist(v0, f.point) <= 1.0001 * tol.position, "{t}");
            assert_eq!(v0, v1, "{t}");
        }
    }
}
