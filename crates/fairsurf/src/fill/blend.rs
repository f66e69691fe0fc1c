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
//! 4. **Fair inside**, as a fill: thin plate guided by the normals of the
//!    Hermite–Coons patch of the four sides (the made sides' cross
//!    derivatives the Hermite interpolants of the corner tangents and
//!    twists), then linearized Willmore steps kept only where W falls.
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
    /// W after the solve and after each linearized Willmore step tried.
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
            options.fill.rational(0),
            sides[0],
            false,
        ),
        side_fit_facing(
            &faired.surface,
            2,
            b,
            options.fill.rational(1),
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
            normal_weight: options.fill.normal_weight,
            seconds: FillSeconds {
                setup: faired.setup,
                solve: faired.solve_seconds,
                measure: faired.improve_seconds + measure,
            },
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bspline::BSplineProblem;

    /// S(u, v) = a(u) + v·b(u) on [0, 2] × [0, 3], a and b cubics
    /// (knots inserted at 0.5 and 1.3: three uneven spans): ruled, and
    /// biharmonic (Δ²S = 0, with no jumps of S_uuu at the knots).
    fn ruled() -> BSplineSurface {
        let u = KnotVector::new(3, vec![0., 0., 0., 0., 2., 2., 2., 2.]).unwrap();
        let v = KnotVector::new(1, vec![0., 0., 3., 3.]).unwrap();
        let pts = (0..4)
            .flat_map(|i| {
                let x = i as f64 * 0.7;
                let a = [x, 0.1 * x * x, 0.3 * (1.7 * x).sin()];
                let b = [0.2 * x, 1.0 + 0.1 * x, 0.4 * (1.1 * x).cos()];
                [a, add(a, scale(b, 3.0))]
            })
            .collect();
        let s = BSplineSurface::new(u, v, pts).unwrap();
        s.insert_knot_u(0.5).unwrap().insert_knot_u(1.3).unwrap()
    }

    /// The ruled surface cut at v = 1 and v = 2: (A, middle, B).
    fn ruled_in_three() -> (BSplineSurface, BSplineSurface, BSplineSurface) {
        let (a, rest) = ruled().split_v(1.0).unwrap();
        let (m, b) = rest.split_v(2.0).unwrap();
        (a, m, b)
    }

    fn plain() -> FillOptions {
        FillOptions {
            normal_weight: 0.0,
            willmore_steps: 0,
            descent_steps: 0,
            ..FillOptions::default()
        }
    }

    /// The blend's normal against a surface's at the same points,
    /// evaluated afresh (not through the report's sampling).
    fn largest_angle(blend: &Blend, k: usize, face: &BSplineSurface, flip: bool) -> f64 {
        let side = blend.sides[k / 2];
        (0..=40)
            .map(|i| {
                let t = i as f64 / 40.0;
                let (u, v) = super::super::fill_param(k, t);
                let d = blend.surface.derivatives(u, v);
                let tt = if side.reversed { 1.0 - t } else { t };
                let mut n = normal_at(face, side.edge, tt);
                if flip {
                    n = scale(n, -1.0);
                }
                let p = super::super::edge_point(face, side.edge, tt);
                assert!(dist(p, d.point) < 1e-12, "gap at t = {t}");
                crate::vec3::angle(cross(d.du, d.dv), n)
            })
            .fold(0.0, f64::max)
    }

    /// Clamped on all four sides, the blend of a ruled bicubic cut in three
    /// is the missing middle piece (α = 1 exactly, the made sides are its
    /// straight sides), with the plain thin plate and with the Coons normal
    /// field (the Hermite–Coons patch reproduces the piece, so its normals
    /// are the piece's).
    #[test]
    fn a_clamped_blend_of_a_ruled_surface_is_the_missing_piece() {
        let (a, m, b) = ruled_in_three();
        for weight in [0.0, 100.0] {
            let options = BlendOptions {
                fill: FillOptions {
                    normal_weight: weight,
                    ..plain()
                },
                bulge: Bulge::Fixed([1.0, 1.0]),
                clamp_sides: true,
            };
            let bl = blend(&a, Edge::V1, &b, Edge::V0, &options).unwrap();
            assert!(!bl.report.flipped);
            assert!(!bl.sides[0].reversed);
            for x in bl.report.alpha {
                assert!((x - 1.0).abs() < 1e-13, "{x}");
            }
            for i in 0..=10 {
                for j in 0..=10 {
                    let (u, v) = (i as f64 / 10.0, j as f64 / 10.0);
                    let want = m.eval(2.0 * u, 1.0 + v);
                    let got = bl.surface.eval(u, v);
                    assert!(
                        dist(want, got) < 1e-11,
                        "λ {weight} ({u}, {v}): {got:?} {want:?}"
                    );
                }
            }
        }
    }

    /// Free sides: the blend is G¹ to both surfaces to rounding — checked
    /// by fresh evaluation — and the thin plate's minimizer: any free
    /// point moved raises the energy.
    #[test]
    fn a_free_blend_is_g1_and_minimal() {
        let (a, _, b) = ruled_in_three();
        let options = BlendOptions {
            fill: plain(),
            bulge: Bulge::Fixed([1.0, 1.0]),
            ..BlendOptions::default()
        };
        let bl = blend(&a, Edge::V1, &b, Edge::V0, &options).unwrap();
        for (k, face) in [(0, &a), (2, &b)] {
            assert!(largest_angle(&bl, k, face, false).to_degrees() < 1e-9);
        }
        for f in &bl.report.sides {
            assert!(f.gap < 1e-12 && f.angle.to_degrees() < 1e-9, "{f:?}");
        }
        let c = bl.report.corners;
        assert!(c.position < 1e-13 && c.tangent < 1e-13, "{c:?}");
        let (cu, cv) = bl.surface.counts();
        let free: Vec<bool> = (0..cu * cv)
            .map(|k| {
                let (i, j) = (k / cv, k % cv);
                i > 0 && i + 1 < cu && j > 1 && j + 2 < cv
            })
            .collect();
        let problem = BSplineProblem::new(bl.surface.clone())
            .with_free(free.clone())
            .unwrap()
            .with_bend(1.0);
        let e0 = problem.energy_at(&bl.surface);
        let mut raised = 0;
        for k in (0..cu * cv).filter(|&k| free[k]) {
            for c in 0..3 {
                for h in [1e-4, -1e-4] {
                    let mut pts = bl.surface.points().to_vec();
                    pts[k][c] += h;
                    let (ku, kv) = bl.surface.knots();
                    let moved = BSplineSurface::new(ku.clone(), kv.clone(), pts).unwrap();
                    assert!(
                        problem.energy_at(&moved) > e0,
                        "point {k} coordinate {c} by {h}"
                    );
                    raised += 1;
                }
            }
        }
        assert!(raised >= 6 * 2 * 4, "{raised}");
        // Free sides are fairer than clamped ones.
        let clamped = blend(
            &a,
            Edge::V1,
            &b,
            Edge::V0,
            &BlendOptions {
                clamp_sides: true,
                ..options
            },
        )
        .unwrap();
        assert!(e0 < problem.energy_at(&clamped.surface));
    }

    /// Between faces of other degrees and knots, B given with its edge
    /// the other way round and its normal facing the other way: corners
    /// still pair, G¹ holds to rounding with B's turned normal, W falls
    /// with the default steps.
    #[test]
    fn a_blend_pairs_corners_and_turns_a_flipped_neighbour() {
        let (a, _, b) = ruled_in_three();
        // B with u reversed: its V0 edge runs the other way and its
        // normal S_u × S_v turns.
        let (ku, kv) = b.knots();
        let (cu, cv) = b.counts();
        let mirrored: Vec<f64> = ku.knots().iter().rev().map(|&t| 2.0 - t).collect();
        let pts = (0..cu * cv)
            .map(|k| b.point(cu - 1 - k / cv, k % cv))
            .collect();
        let b2 = BSplineSurface::new(KnotVector::new(3, mirrored).unwrap(), kv.clone(), pts)
            .unwrap()
            .elevated(1, 2)
            .unwrap();
        let one = BlendOptions {
            bulge: Bulge::Fixed([1.0, 1.0]),
            ..BlendOptions::default()
        };
        let bl = blend(&a, Edge::V1, &b2, Edge::V0, &one).unwrap();
        assert!(bl.report.flipped);
        // B's edge runs along A's now: traversed along u (not against it,
        // a hole's convention for side 2) where the unmirrored one is not.
        assert_eq!((bl.sides[0].reversed, bl.sides[1].reversed), (false, false));
        assert!(largest_angle(&bl, 0, &a, false).to_degrees() < 1e-9);
        assert!(largest_angle(&bl, 2, &b2, true).to_degrees() < 1e-9);
        let w = &bl.report.willmore;
        // The steps lowered W, each kept one by itself.
        assert!(
            w.len() >= 2
                && w.iter().cloned().fold(f64::MAX, f64::min) < w[0]
                && w.windows(2).take(w.len() - 2).all(|x| x[1] < x[0]),
            "{w:?}"
        );
        assert!(
            (bl.report.curvature.value - w.iter().cloned().fold(f64::MAX, f64::min)).abs() < 1e-15
        );
        // B unmirrored: not flipped, its edge traversed against u.
        let same = blend(&a, Edge::V1, &b, Edge::V0, &one).unwrap();
        assert!(!same.report.flipped);
        assert_eq!(
            (same.sides[0].reversed, same.sides[1].reversed),
            (false, true)
        );
    }

    /// The default bulges are W's least: no lower than at (1, 1), and
    /// moving either by 5% does not lower W by more than the search's
    /// tolerance.
    #[test]
    fn the_default_bulges_have_the_least_w() {
        let (a, _, b) = ruled_in_three();
        // A bent B: the blend must turn, and W depends on the bulges.
        let (ku, kv) = b.knots();
        let pts = b
            .points()
            .iter()
            .map(|p| [p[0], p[1], p[2] + 0.6 * (p[1] - 2.0)])
            .collect();
        let b = BSplineSurface::new(ku.clone(), kv.clone(), pts).unwrap();
        // The search compares thin-plate blends: so do these.
        let opts = |bulge| BlendOptions {
            fill: FillOptions {
                willmore_steps: 0,
                descent_steps: 0,
                ..FillOptions::default()
            },
            bulge,
            clamp_sides: false,
        };
        let least = blend(&a, Edge::V1, &b, Edge::V0, &opts(Bulge::Least)).unwrap();
        let r = &least.report;
        let search = r.bulge_search.unwrap();
        let w = r.curvature.value;
        assert!(search.evaluations >= 4 && search.evaluations <= BULGE_EVALUATIONS);
        assert!(w <= search.w_at_one, "{w} {}", search.w_at_one);
        assert!(
            w < 0.999 * search.w_at_one,
            "the search found nothing: {w} {search:?}"
        );
        for (k, f) in [(0, 1.05), (0, 0.95), (1, 1.05), (1, 0.95)] {
            let mut moved = r.bulge;
            moved[k] *= f;
            let other = blend(&a, Edge::V1, &b, Edge::V0, &opts(Bulge::Fixed(moved))).unwrap();
            let wo = other.report.curvature.value;
            assert!(wo >= w * (1.0 - 1e-6), "bulge {moved:?}: W {wo} < {w}");
        }
        // G1 holds whatever the bulges.
        for f in &r.sides {
            assert!(f.gap < 1e-12 && f.angle.to_degrees() < 1e-9, "{f:?}");
        }
    }

    #[test]
    fn bad_blends_are_refused() {
        let (a, m, b) = ruled_in_three();
        let bad_bulge = BlendOptions {
            bulge: Bulge::Fixed([1.0, 0.0]),
            ..BlendOptions::default()
        };
        let e = blend(&a, Edge::V1, &b, Edge::V0, &bad_bulge).unwrap_err();
        assert!(e.to_string().contains("bulge 1 is 0"), "{e}");
        // A and the middle piece touch along the whole edge.
        let e = blend(&a, Edge::V1, &m, Edge::V0, &BlendOptions::default()).unwrap_err();
        assert!(e.to_string().contains("meet at their first corner"), "{e}");
        // An edge collapsed to a point (a cone's apex row) is no edge.
        let u = KnotVector::bezier(2);
        let pts = (0..9)
            .map(|k| {
                let (i, j) = ((k / 3) as f64, (k % 3) as f64);
                if i == 0.0 {
                    [0.0, 0.0, 5.0]
                } else {
                    [i, j, 5.0]
                }
            })
            .collect();
        let cone = BSplineSurface::new(u.clone(), u, pts).unwrap();
        let e = blend(&cone, Edge::U0, &b, Edge::V0, &BlendOptions::default()).unwrap_err();
        assert!(
            e.to_string().contains("surface A's edge U0 is collapsed"),
            "{e}"
        );
        let e = blend(&b, Edge::V0, &cone, Edge::U0, &BlendOptions::default()).unwrap_err();
        assert!(
            e.to_string().contains("surface B's edge U0 is collapsed"),
            "{e}"
        );
    }
}
