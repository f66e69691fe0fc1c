//! A transition surface between two surfaces along one edge of each (Wu &
//! Yang 2015, §5, Fig. 5: "a bi-quintic Bézier surface is used as the
//! transition surface between two given surfaces … two arrays of boundary
//! control points of the Bézier surface are given in advance" so that G¹
//! holds with both).
//!
//! The blend F(u, v) runs from surface A's edge (v = 0) to surface B's
//! (v = 1):
//!
//! 1. **The two given sides, exactly.** Along each edge the boundary curve
//!    P(u) and the cross derivative D(u) pointing away from the surface, as
//!    for a hole's sides ([`super::fill_hole`]); the blend's two outer rows
//!    on each are P and P + (h/q)·α·D, so F_v = α_A·D_A at v = 0 and
//!    F_v = −α_B·D_B at v = 1: G¹ along both edges up to rounding.
//! 2. **The two made sides** (u = 0 and u = 1) are the cubic Hermite curves
//!    from A's corner to B's with end tangents α_A·D_A and −α_B·D_B (the
//!    blend's own F_v there, so the corners agree); only their points are
//!    fixed (a made side has no neighbour to be tangent to), unless
//!    [`BlendOptions::clamp_sides`] fixes their cross derivatives too.
//! 3. **α** — the tangent length across, Rhino's "bulge": α_k = bulge_k ·
//!    mean over the edge of |B(t) − A(t)| / |D_k(t)| (nine t), so that
//!    with bulge 1 the crossing speed matches the gap the blend spans. By
//!    default the two bulges are those with the least W ([`Bulge::Least`]):
//!    W depends on them more than on anything else.
//!    For a ruled S(u, v) = a(u) + v·b(u) cut in three this is exactly the
//!    missing piece's speed, and the blend reproduces the piece.
//! 4. **Fair inside**, as a fill: the thin plate — guided by the normals of
//!    the Hermite–Coons patch of the four sides (the made sides' cross
//!    derivatives the Hermite interpolants of the corner tangents and
//!    twists) where no descent follows, as in the bulge search
//!    ([`FillOptions::guiding_weight`]) — then W lowered by the fill's
//!    descent on W.
//! 5. **Measured** on the returned surface: gap and normal angle against A
//!    and against B along their edges, W, and the corner agreement.

use super::holes::{surface_param, tolerance, Side};
use super::measure::{side_fit_facing, SideFit};
use super::strip::Strip;
use super::{fair, unified, CornerMismatch, FillOptions, FillSeconds, TotalCurvature};
use crate::analysis::Edge;
use crate::bspline::{BSplineSurface, KnotVector};
use crate::vec3::{add, cross, dist, dot, norm, scale, sub};
use crate::SolveReport;
use crate::{Error, Result, Vec3};
use std::time::Instant;

#[cfg(test)]
mod tests;

/// The tangent lengths across at A's and at B's edge (Rhino's "bulge"),
/// relative to the gap between the edges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bulge {
    /// These two (1: the gap); > 0.
    Fixed([f64; 2]),
    /// The pair with the least W = ∫∫ κ₁² + κ₂² dA of the thin-plate
    /// blend (before Willmore steps), each in [1/4, 4]: Nelder–Mead on
    /// their logarithms from (1, 1), until the simplex's W agree to 1e-6
    /// of W or after 60 blends.
    Least,
}

/// The bounds of [`Bulge::Least`]'s search.
const BULGE_RANGE: [f64; 2] = [0.25, 4.0];
/// Blends [`Bulge::Least`] makes at most.
const BULGE_EVALUATIONS: usize = 60;

/// How to blend: the fill's energy options and the bulges.
#[derive(Clone, Debug, PartialEq)]
pub struct BlendOptions {
    /// Degrees, elevation, energy weights, normal field, Willmore steps —
    /// as for a fill; `elevate` raises the across direction's cubic too.
    pub fill: FillOptions,
    /// The tangent lengths across; by default the pair with the least W.
    pub bulge: Bulge,
    /// Fix the made sides' cross derivatives too (the Hermite interpolants
    /// of the corner tangents and twists) instead of leaving them to the
    /// energy: a blend clamped on all four sides, as Wu & Yang's examples
    /// with four given borders. Off by default (free is fairer).
    pub clamp_sides: bool,
}

impl Default for BlendOptions {
    fn default() -> Self {
        Self {
            fill: FillOptions::default(),
            bulge: Bulge::Least,
            clamp_sides: false,
        }
    }
}

/// What a blend reports.
#[derive(Clone, Debug, PartialEq)]
pub struct BlendReport {
    /// The solve's own report.
    pub solve: SolveReport,
    /// Against A (the blend's v = 0, `side_fit` side 0) and against B (v =
    /// 1, side 2): gap and normal angle measured on the returned surface.
    pub sides: [SideFit; 2],
    /// B's normal faces against the blend's (and A's): its angle is
    /// measured against the turned normal. Not a fold: the blend leaves B
    /// the way B would continue.
    pub flipped: bool,
    /// Where A's and B's rows and the made sides meet at the corners (0 up
    /// to rounding: the made sides take their end tangents from the rows).
    pub corners: CornerMismatch,
    /// α of A and of B (the blend's cross derivative over the surface's).
    pub alpha: [f64; 2],
    /// The bulges used (given, or chosen by W).
    pub bulge: [f64; 2],
    /// When the bulges were chosen: the blends made, and the thin-plate
    /// blend's W at (1, 1) for comparison.
    pub bulge_search: Option<BulgeSearch>,
    /// W = ∫∫ κ₁² + κ₂² dA of the blend.
    pub curvature: TotalCurvature,
    /// W after the solve and after each step that lowered it (linearized
    /// Willmore steps if asked, then the descent).
    pub willmore: Vec<f64>,
    /// λ used (0: plain thin plate).
    pub normal_weight: f64,
    /// Where the time went.
    pub seconds: FillSeconds,
}

/// How [`Bulge::Least`] went.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BulgeSearch {
    /// Blends made (each a solve and its W).
    pub evaluations: usize,
    /// W of the thin-plate blend with both bulges 1.
    pub w_at_one: f64,
    /// Seconds the search took, every blend included (the report's
    /// `seconds` are the chosen blend's own).
    pub seconds: f64,
}

/// A blend.
#[derive(Clone, Debug)]
pub struct Blend {
    /// The transition surface, parameters on [0, 1]²: v = 0 on A's edge,
    /// v = 1 on B's; its normal R_u × R_v agrees with A's.
    pub surface: BSplineSurface,
    /// A's edge (`face` 0) as the blend's side 0, traversed along u; B's
    /// (`face` 1) as side 2, traversed against u (a hole's convention).
    pub sides: [Side; 2],
    /// How good it is.
    pub report: BlendReport,
}

/// A cubic Hermite curve (x₀, x₀′, x₁, x₁′ on [0, 1]) as Bézier points.
fn hermite(x0: Vec3, d0: Vec3, x1: Vec3, d1: Vec3) -> Vec<Vec3> {
    vec![
        x0,
        add(x0, scale(d0, 1.0 / 3.0)),
        sub(x1, scale(d1, 1.0 / 3.0)),
        x1,
    ]
}

/// The made side at u = `end` between the scaled rows' strips `a` (v = 0)
/// and `b` (v = 1, D pointing to −v), with its cross derivative pointing
/// into the blend (+u at u = 0, −u at u = 1).
fn made_side(a: &Strip, b: &Strip, end: f64) -> Strip {
    let (pa, pb) = (a.at(end), b.at(end));
    let s = if end == 0.0 { 1.0 } else { -1.0 };
    Strip {
        knots: KnotVector::bezier(3),
        pos: hermite(pa.pos, pa.der, pb.pos, scale(pb.der, -1.0)),
        // F_u at the corners is the rows' P′, its v-derivative (the twist)
        // their D′.
        der: hermite(
            scale(pa.dpos, s),
            scale(pa.dder, s),
            scale(pb.dpos, s),
            scale(pb.dder, -s),
        ),
    }
}

/// The unit normal direction of `face` at t of its boundary `edge`.
fn normal_at(face: &BSplineSurface, edge: Edge, t: f64) -> Vec3 {
    let (u, v) = surface_param(face, edge, t);
    let d = face.derivatives(u, v);
    cross(d.du, d.dv)
}

/// Blends surface `a` along its boundary `edge_a` with surface `b` along
/// `edge_b` (see the module documentation). B's edge is traversed so that
/// corners pair without crossing (the shorter two made sides).
///
/// Errors ([`Error::Fill`]): a bulge not > 0, edges that touch at a corner
/// (nothing to span there), a surface whose cross derivative vanishes on
/// the edge; and the solve's own refusals.
pub fn blend(
    a: &BSplineSurface,
    edge_a: Edge,
    b: &BSplineSurface,
    edge_b: Edge,
    options: &BlendOptions,
) -> Result<Blend> {
    let with = |o: &BlendOptions, bulge: [f64; 2]| blend_with(a, edge_a, b, edge_b, o, bulge);
    match options.bulge {
        Bulge::Fixed(bulge) => with(options, bulge),
        Bulge::Least => {
            // The search compares thin-plate blends; the Willmore steps
            // and the descent on W (each only where W falls) then polish
            // the chosen one.
            let t0 = Instant::now();
            let plain = BlendOptions {
                fill: FillOptions {
                    willmore_steps: 0,
                    descent_steps: 0,
                    ..options.fill.clone()
                },
                ..options.clone()
            };
            let found = least_w(|bulge| with(&plain, bulge))?;
            let mut search = found.report.bulge_search.expect("a search");
            let mut chosen = if options.fill.willmore_steps > 0 || options.fill.descent_steps > 0 {
                with(options, found.report.bulge)?
            } else {
                found
            };
            search.seconds = t0.elapsed().as_secs_f64();
            chosen.report.bulge_search = Some(search);
            Ok(chosen)
        }
    }
}

/// Nelder–Mead over x = ln(bulge) in the box ln [`BULGE_RANGE`]²: the
/// blend with the least W found.
fn least_w(with: impl Fn([f64; 2]) -> Result<Blend>) -> Result<Blend> {
    let t0 = Instant::now();
    let first = with([1.0, 1.0])?;
    let w_at_one = first.report.curvature.value;
    let (lo, hi) = (BULGE_RANGE[0].ln(), BULGE_RANGE[1].ln());
    let mut evaluations = 1;
    let mut best = first;
    // W at x; a blend that fails (e.g. a fold) counts as infinitely unfair.
    let eval = |x: [f64; 2], best: &mut Blend, evaluations: &mut usize| -> f64 {
        if *evaluations >= BULGE_EVALUATIONS {
            return f64::INFINITY; // the budget is spent: no more blends
        }
        let x = x.map(|c| c.clamp(lo, hi));
        *evaluations += 1;
        match with(x.map(f64::exp)) {
            Ok(b) => {
                let w = b.report.curvature.value;
                if w < best.report.curvature.value {
                    *best = b;
                }
                w
            }
            Err(_) => f64::INFINITY,
        }
    };
    let mut simplex: Vec<([f64; 2], f64)> = vec![([0.0, 0.0], w_at_one)];
    for x in [[0.25, 0.0], [0.0, 0.25]] {
        let w = eval(x, &mut best, &mut evaluations);
        simplex.push((x, w));
    }
    while evaluations < BULGE_EVALUATIONS {
        simplex.sort_by(|p, q| p.1.total_cmp(&q.1));
        let (b, w) = (simplex[0].1, simplex[2].1);
        if w - b <= 1e-6 * b.abs() {
            break;
        }
        let c = [
            0.5 * (simplex[0].0[0] + simplex[1].0[0]),
            0.5 * (simplex[0].0[1] + simplex[1].0[1]),
        ];
        let along = |t: f64| {
            [
                (c[0] + t * (simplex[2].0[0] - c[0])).clamp(lo, hi),
                (c[1] + t * (simplex[2].0[1] - c[1])).clamp(lo, hi),
            ]
        };
        let xr = along(-1.0);
        let wr = eval(xr, &mut best, &mut evaluations);
        if wr < simplex[0].1 {
            let xe = along(-2.0);
            let we = eval(xe, &mut best, &mut evaluations);
            simplex[2] = if we < wr { (xe, we) } else { (xr, wr) };
        } else if wr < simplex[1].1 {
            simplex[2] = (xr, wr);
        } else {
            let xc = along(0.5);
            let wc = eval(xc, &mut best, &mut evaluations);
            if wc < simplex[2].1 {
                simplex[2] = (xc, wc);
            } else {
                // Shrink towards the best.
                let x0 = simplex[0].0;
                for k in 1..3 {
                    let x = [
                        0.5 * (x0[0] + simplex[k].0[0]),
                        0.5 * (x0[1] + simplex[k].0[1]),
                    ];
                    simplex[k] = (x, eval(x, &mut best, &mut evaluations));
                }
            }
        }
    }
    best.report.bulge_search = Some(BulgeSearch {
        evaluations,
        w_at_one,
        seconds: t0.elapsed().as_secs_f64(),
    });
    Ok(best)
}

/// The blend with the bulges `bulge`.
fn blend_with(
    a: &BSplineSurface,
    edge_a: Edge,
    b: &BSplineSurface,
    edge_b: Edge,
    options: &BlendOptions,
    bulge: [f64; 2],
) -> Result<Blend> {
    let t0 = Instant::now();
    for (k, &x) in bulge.iter().enumerate() {
        if !(x > 0.0 && x.is_finite()) {
            return Err(Error::Fill {
                why: format!("bulge {k} is {x}; it must be a positive number"),
            });
        }
    }
    let strips = |ra: bool, rb: bool| -> Result<(Strip, Strip)> {
        Ok((
            Strip::from_side(a, edge_a, ra)?,
            Strip::from_side(b, edge_b, rb)?.reversed(),
        ))
    };
    let ends = |sa: &Strip, sb: &Strip| [0.0, 1.0].map(|t| dist(sa.at(t).pos, sb.at(t).pos));
    // Pair the corners without crossing, then orient the blend like A.
    let (mut ra, mut rb) = (false, false);
    let (s0, s2) = strips(ra, rb)?;
    let (t0b, t1b) = strips(ra, !rb)?;
    let (e, f) = (ends(&s0, &s2), ends(&t0b, &t1b));
    let (mut s0, mut s2) = if f[0] + f[1] < e[0] + e[1] {
        rb = true;
        (t0b, t1b)
    } else {
        (s0, s2)
    };
    let mid = s0.at(0.5);
    if dot(cross(mid.dpos, mid.der), normal_at(a, edge_a, 0.5)) < 0.0 {
        (ra, rb) = (!ra, !rb);
        (s0, s2) = strips(ra, rb)?;
    }
    let tol = tolerance(&[a.clone(), b.clone()]);
    for (s, name, edge) in [(&s0, "A", edge_a), (&s2, "B", edge_b)] {
        let length: f64 = (0..8)
            .map(|i| dist(s.at(i as f64 / 8.0).pos, s.at((i + 1) as f64 / 8.0).pos))
            .sum();
        if length <= tol {
            return Err(Error::Fill {
                why: format!("surface {name}'s edge {edge:?} is collapsed to a point"),
            });
        }
    }
    let gaps = ends(&s0, &s2);
    if let Some(k) = (0..2).find(|&k| gaps[k] <= tol) {
        return Err(Error::Fill {
            why: format!(
                "the two edges meet at their {} corner ({:.3e} apart): a blend spans a gap \
                 between two edges apart at both ends",
                ["first", "last"][k],
                gaps[k]
            ),
        });
    }
    // α: the gap over the cross derivative, averaged along the edge.
    let mut alpha = [0.0; 2];
    for (k, (s, name)) in [(&s0, "A"), (&s2, "B")].into_iter().enumerate() {
        let mut sum = 0.0;
        for i in 0..9 {
            let t = i as f64 / 8.0;
            let d = norm(s.at(t).der);
            if d.is_nan() || d <= 0.0 {
                return Err(Error::Fill {
                    why: format!(
                        "surface {name}'s cross-boundary derivative vanishes on its edge at t = {t}"
                    ),
                });
            }
            sum += dist(s0.at(t).pos, s2.at(t).pos) / d;
        }
        alpha[k] = bulge[k] * sum / 9.0;
    }
    let (s0, s2) = (s0.scaled(alpha[0]), s2.scaled(alpha[1]));
    let (s3, s1) = (made_side(&s0, &s2, 0.0), made_side(&s0, &s2, 1.0));
    let s = unified(&[s0, s1, s2, s3], &options.fill)?;
    let clamp = options.clamp_sides;
    let faired = fair(&s, [true, clamp, true, clamp], &options.fill, t0)?;
    let t2 = Instant::now();
    let mb = s[2].at(0.5);
    let flipped = dot(
        cross(mb.dpos, scale(mb.der, -1.0)),
        normal_at(b, edge_b, 0.5),
    ) < 0.0;
    let sides = [Side::whole(0, edge_a, ra), Side::whole(1, edge_b, rb)];
    let fits = [
        side_fit_facing(
            &faired.surface,
            0,
            a,
            options.fill.exact(0),
            sides[0],
            false,
        ),
        side_fit_facing(
            &faired.surface,
            2,
            b,
            options.fill.exact(1),
            sides[1],
            flipped,
        ),
    ];
    let measure = t2.elapsed().as_secs_f64();
    Ok(Blend {
        surface: faired.surface,
        sides,
        report: BlendReport {
            solve: faired.solve,
            sides: fits,
            flipped,
            corners: faired.corners,
            alpha,
            bulge,
            bulge_search: None,
            curvature: faired.curvature,
            willmore: faired.willmore,
            normal_weight: options.fill.guiding_weight(),
            seconds: FillSeconds {
                setup: faired.setup,
                solve: faired.solve_seconds,
                measure: faired.improve_seconds + measure,
            },
        },
    })
}
