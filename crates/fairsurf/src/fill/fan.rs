//! N-sided holes: a fan of N triangular Bézier patches of degree n around
//! a free centre (Veltkamp & Wesselink's triangular surfaces, §4.3 for the
//! G¹ conditions between them).
//!
//! Patch k has corners (C, V_k, V_{k+1}): the centre and the ends of side
//! k. With its points P_ijk (i for C, j for V_k, l for V_{k+1}):
//!
//! 1. **Row 0** (the side, P_{0,n−m,m}) is the neighbour's boundary curve
//!    raised to degree n.
//! 2. **Row 1** (P_{1,n−1−m,m} = P_{0,n−m,m} + W_m/n) makes the derivative
//!    towards C along the side W(t) = α(t)·D(t) + β(t)·P′(t), D the
//!    neighbour's cross derivative into the hole, P′ the side's tangent,
//!    α > 0 and β linear: W lies in the neighbour's tangent plane at every
//!    t, so the fill is G¹ to it exactly, up to rounding (n ≥ p + 2 holds
//!    the degree-(p + 1) W).
//! 3. **The spokes' first points.** At a corner V_k the two patches share
//!    the spoke V_k → C; its first point V_k + d is fixed by both rows 1,
//!    and d is chosen so §4.3's boundary-vertex rule holds there:
//!    d_a + d_b − 2cos(γ/2)·d = 0 for the sides' first control-point
//!    differences d_a, d_b at V_k and their angle γ (the rule the solver
//!    enforces). α and β at each end of a side are read off W there (a
//!    2 × 2 least-squares fit in the tangent plane; its residual, non-zero
//!    when the two neighbours disagree on the tangent plane at the corner,
//!    is reported).
//! 4. **Fair inside**: the free points minimize the thin plate (membrane
//!    if asked) subject to §4.3's G¹ conditions across the spokes and at
//!    the centre; conditions the fixed rows contradict give way and are
//!    counted. Then W itself is lowered along the kept conditions (the
//!    module `fan_willmore`). Measured on the result: gap and normal angle
//!    against each neighbour, the largest normal angle between the fan's
//!    patches, W.
//!
//! **Sides with knots.** A side of several Bézier pieces (a B-spline
//! neighbour with knots inside the side, or several edges that continue
//! each other) is cut at its knots: each piece is a side of the fan, and
//! the hole's boundary runs straight on (γ = π) through the cuts. §4.3's
//! rule would ask the two tangents there to be of one length; the fan
//! asks instead w_a·d_a + w_b·d_b = 0 with (w_a, w_b) ∝ (|d_b|, |d_a|)
//! (opposite tangents, which the neighbour's continuity gives:
//! [`crate::triangle::Continuity::boundary_rules`]), and chooses the spoke's
//! first point there so that the G¹ condition next to the corner — which
//! then holds only fixed points — is met (a least-squares fit, exact for a
//! neighbour with continuous curvature across the knot). Tested: G¹ to
//! rounding inside and out, W within 2e-5 of the uncut fan's after the
//! descent, fans of up to 21 patches at degrees 5–8. With many pieces the
//! patches are thin and the thin plate is poor (W 1.8 against 0.59 with
//! one knot a side, 36 with six): the descent mends W but takes 60–200
//! steps (a triangle with one knot a side 42 ms, five 0.7 s; the rounded
//! box's corner through its cylinders' 8-span stand-ins, 24 patches,
//! 0.7 s and W 3.141677 where the one-span stand-ins give 3 patches,
//! 36 ms and 3.141579).
//!
//! **Round holes.** A boundary with no real corner (C¹ arcs all round: a
//! round hole, or one edge or two cut at their middles) has only straight
//! corners, and there the spokes the rule above finds shrink to a quarter
//! to a half of their natural length and the patches open their seams
//! (0.1–110° with every condition held). A round hole takes its spokes
//! instead from the corners towards the mean of the corners, 1/n of the
//! way, in the neighbour's tangent plane, and makes α and β of the rows 1
//! cubic along each piece (n ≥ p + 4), their end slopes the least changes
//! from linear that meet the condition next to each corner
//! ([`round_slopes`]). Tested on round holes of 2, 3, 4 and 6 C¹ arcs in
//! the graph of a cubic: G¹ to rounding inside and out, no condition
//! dropped, W 0.8% below the graph's own over the disk (four arcs).
//!
//! **Few real corners.** Where the rule at the straight corners fails (a
//! boundary with one to three real corners and straight ones between:
//! the seams opened by 0.01–150°), and first where a real corner turns by
//! less than 30° (there §4.3's spoke (d_a + d_b)/(2cos(γ/2)) runs along
//! the longer side: W 175–1276 before the descent), every spoke is
//! natural: at the straight corners as for a round hole, at the real ones
//! the corner's rule x·d_a + y·d_b − d = 0 takes the weights x, y > 0
//! that the natural spoke d meets. A corner turning by less than 0.01 rad
//! is then taken as straight (its fitted weights grew to 3000 at 1e-4
//! rad, and W to 1900): the conditions its rule contradicts are dropped
//! and reported, the seams next to it open by about 0.2% of its turn. A
//! boundary of four pieces is cut into five at the middle of the longest:
//! at a centre of four patches (rule d_{i−1} + d_{i+1} = 0) the straight
//! and real corners' conditions left two opposite spokes without a first
//! derivative, a singular point (so did four real corners of different
//! angles under §4.3's rule: a 4-sided hole's fan, tried where one tensor
//! patch misses its neighbours, is cut into five too). Tested on round holes of three and four
//! arcs with one to three corners turned by 1e-4 to 1 rad: G¹ to rounding
//! to the neighbours, between the patches too unless a corner was taken
//! as straight, W 1.08–1.30 against the graph's 1.3141 over the disk.
//!
//! A 3-sided hole can also be one triangular patch ([`fill_triangle`]):
//! the same rows from all three sides, meeting at the corners. On a
//! triangle in the graph of a cubic its thin plate measured W 0.5914
//! against the fan's 0.7545 (MakeFilling 0.5911): the fan's 120° centre
//! angles make the thin plate in the patches' own parameters far from W.
//! After the descent on W both come to 0.59082.

use super::fan_willmore;
use super::holes::Hole;
use super::holes::Side;
use super::measure::{
    compare, neighbour_tangents, side_parameters, total_curvature, Exact, SideFit, TotalCurvature,
};
use super::strip::{Strip, KNOT_SNAP};
use super::{faces_like_side_0, side_face, CornerMismatch, FillOptions, FillSeconds};
use crate::analysis::largest_tri_normal_turn;
use crate::basis::binomial;
use crate::bspline::BSplineSurface;
use crate::constraint::Constraint;
use crate::curve::elevate_points;
use crate::solve::SolveReport;
use crate::triangle::{
    max_edge_normal_angle, BoundaryRule, Continuity, TriFactored, TriProblem, TriSurface,
};
use crate::vec3::{add, angle, dist, dot, norm, scale, sub};
use crate::{Bend, Stretch};
use crate::{Error, Result, Vec3};
use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

/// What a fan fill reports.
#[derive(Clone, Debug, PartialEq)]
pub struct FanReport {
    /// The triangular thin-plate solve's report (the surface the descent
    /// on W starts from): its energy, its check, the G¹ rows kept and
    /// dropped with their residuals there; its geometric figures (the
    /// largest normal angle across the patches' edges, the largest normal
    /// turn) measured again on the surface returned.
    pub solve: SolveReport,
    /// Per side, in the hole's order: gap and normal angle measured on the
    /// returned surface against the neighbour.
    pub sides: Vec<SideFit>,
    /// Disagreements at the corners: `position` between the two sides'
    /// corner points, `tangent` between the spoke's first point as the two
    /// sides' tangent planes give it (0 when the neighbours share the
    /// tangent plane at the corner), or between a row 1 and the next
    /// side's boundary (which wins); `twist` only for one triangular patch
    /// ([`fill_triangle`]): between the corner twist points two rows 1
    /// give (a fan's rows 2 are free).
    pub corners: CornerMismatch,
    /// The largest normal angle (radians) between two patches of the fan,
    /// along the spokes (65 samples each), measured on the returned fan.
    pub inner_angle: f64,
    /// W = ∫∫ κ₁² + κ₂² dA of the whole fan.
    pub curvature: TotalCurvature,
    /// W of the thin-plate fill, then after each step of the descent on W
    /// (one entry: no descent); the descent's coarse-phase steps but its
    /// last are measured by the coarse rule (as [`super::FillReport::willmore`]).
    pub willmore: Vec<f64>,
    /// Seconds: rows, solve, measurements.
    pub seconds: FillSeconds,
    /// The candidates tried and not kept ([`super::HoleFill::new`] tries a
    /// fan, and for three sides one triangle too, without descent steps
    /// each at two degrees; for four sides one patch first), with their
    /// measures or refusals and time.
    pub others: Vec<super::Candidate>,
    /// Why W was not lowered though descent steps were asked for (no kept
    /// factorization, or the descent opened the seams between the
    /// patches), None otherwise.
    pub descent_note: Option<String>,
}

/// A hole filled by a fan of triangular patches.
#[derive(Clone, Debug)]
pub struct FanFill {
    /// The fan: vertex 0 the centre, vertex k + 1 the hole's corner k;
    /// triangle k = (centre, corner k, corner k + 1) over side k.
    pub surface: TriSurface,
    /// The hole as filled (possibly traversed the other way than given, to
    /// agree with the neighbours' orientation).
    pub hole: Hole,
    /// How good it is.
    pub report: FanReport,
    /// The thin-plate solve's KKT factorization until the descent on W
    /// has used it.
    pub(super) factor: Option<Arc<TriFactored>>,
}

impl FanFill {
    /// The patches as tensor-product B-spline surfaces of degree n × n
    /// with the side u = 1 collapsed to the centre (exact; for CAD, which
    /// has no triangular patches): patch k's v = 0 … 1 at u = 0 runs along
    /// side k backwards, from corner k + 1 to corner k.
    pub fn patches(&self) -> Vec<BSplineSurface> {
        self.surface
            .patches()
            .map(|p| BSplineSurface::from_bezier(&p.to_tensor()))
            .collect()
    }
}

/// Bézier coefficients of f(t)·g(t), f of degree a (its a + 1
/// coefficients), g of degree b: of degree a + b.
fn times(f: &[f64], g: &[Vec3]) -> Vec<Vec3> {
    let (a, b) = (f.len() - 1, g.len() - 1);
    (0..=a + b)
        .map(|m| {
            let mut x = [0.0; 3];
            for i in m.saturating_sub(b)..=m.min(a) {
                let c = binomial(a, i) * binomial(b, m - i) / binomial(a + b, m);
                x = add(x, scale(g[m - i], c * f[i]));
            }
            x
        })
        .collect()
}

/// (a, b) with a·x + b·y nearest to w, and the distance left.
fn decompose(w: Vec3, x: Vec3, y: Vec3) -> (f64, f64, f64) {
    let (xx, xy, yy) = (dot(x, x), dot(x, y), dot(y, y));
    let (wx, wy) = (dot(w, x), dot(w, y));
    let det = xx * yy - xy * xy;
    let a = (wx * yy - wy * xy) / det;
    let b = (wy * xx - wx * xy) / det;
    let r = norm(sub(w, add(scale(x, a), scale(y, b))));
    (a, b, r)
}

/// Fills the N-sided `hole` (N ≥ 3) of `faces` with a fan of triangular
/// patches (see the module documentation). `options.elevate` raises the
/// degree above the least (the sides' largest + 2, at least 5) when that
/// is below [`RICH_DEGREE`]; the
/// energy is `options.stretch` and `options.bend` (a 4-sided fill's normal
/// field and linearized Willmore steps are not applied to fans), then W is
/// lowered by at most `options.descent_steps` steps along the kept G¹
/// conditions ([`FAN_DESCENT_REL`]; the report's `willmore` lists W before
/// and after each step).
///
/// Sides of several Bézier pieces (interior knots, edges that continue
/// each other) are cut into pieces that meet at straight corners (see the
/// module documentation); error messages then number the pieces.
///
/// A hole without a real corner (a round hole) takes the construction of
/// the module documentation's "Round holes"; one with few real corners
/// or one turning by less than 30° that of "Few real corners".
///
/// Errors ([`Error::Fill`]): a corner where two sides fold back or one
/// that is concave, a
/// neighbour whose cross derivative does not point into the hole at a
/// corner, a fan cut at knots whose construction at the straight corners
/// fails (no spoke into the hole, or seams opened beyond 0.01° with every
/// G¹ condition held: the message names a corner where the neighbours'
/// tangent planes disagree when there is one, else the construction that
/// failed: the round hole's, or both at the straight corners), a round hole
/// whose rows' α turns non-positive inside a side, natural spokes whose
/// centre lies outside the hole (not star-shaped around it), a fan that
/// folds over (its normal turning by more than 90° between neighbouring
/// samples, or against a neighbour's along a side); and the solve's own
/// refusals.
pub fn fill_fan(faces: &[BSplineSurface], hole: &Hole, options: &FillOptions) -> Result<FanFill> {
    Ok(fan_candidate(faces, hole, options)?.completed(options))
}

/// [`fill_fan`]'s fan solved, its W and its sides measured
/// ([`FanFill::completed`] lowers W and measures the rest).
pub(super) fn fan_candidate(
    faces: &[BSplineSurface],
    hole: &Hole,
    options: &FillOptions,
) -> Result<FanFill> {
    let t0 = Instant::now();
    let rule = prepare(faces, hole, options, 5, true, false)?;
    // Two constructions of the spokes. §4.3's rule at the real corners,
    // the spokes at straight ones solved for (the networks' knots, the
    // rounded box), is tried first; natural spokes everywhere (their rule
    // weights fitted at real corners, the rows' slopes solved at straight
    // ones) where it fails, and first where a real corner turns by less
    // than 30°: there the rule's spoke d = (d_a + d_b)/(2cos(γ/2)) leans
    // along the longer side by up to 1/cos(γ/2) of its length (a 174°
    // corner: W 175–1276 before the descent, 0.8 s to mend).
    let turns = |c: &(Vec3, Vec3, f64)| c.2 >= NEAR_STRAIGHT;
    let other = !rule.round && rule.corner_sides.iter().any(turns);
    let near = other && rule.corner_sides.iter().any(|c| turns(c) && c.2 < STRAIGHT);
    let natural =
        || prepare(faces, hole, options, 5, true, true).and_then(|p| fan_of(p, faces, options, t0));
    if near {
        // The rule as a fallback; a refusal is natural spokes' (the more
        // general construction).
        return match natural() {
            Err(e) => fan_of(rule, faces, options, t0).map_err(|_| e),
            r => r,
        };
    }
    match fan_of(rule, faces, options, t0) {
        Err(Error::Fill { .. }) if other => natural(),
        r => r,
    }
}

/// The inside angle (radians) of a real corner above which a fan takes
/// natural spokes first ([`fan_candidate`]): 150°, a boundary turning by
/// less than 30°.
const NEAR_STRAIGHT: f64 = 150.0 * std::f64::consts::PI / 180.0;

/// With natural spokes, a corner turning by less than this (π − 1e-2 rad:
/// 0.57°) is taken as straight.
const ALMOST_STRAIGHT: f64 = std::f64::consts::PI - 1e-2;

/// The inside angle from which a fan's corner is straight: [`STRAIGHT`],
/// with natural spokes [`ALMOST_STRAIGHT`].
fn straight_from(natural: bool) -> f64 {
    if natural {
        ALMOST_STRAIGHT
    } else {
        STRAIGHT
    }
}

/// The fan of a prepared hole ([`fan_candidate`]): spokes, rows 1, the
/// solve, the seams checked.
fn fan_of(
    prepared: Prepared,
    faces: &[BSplineSurface],
    options: &FillOptions,
    t0: Instant,
) -> Result<FanFill> {
    let Prepared {
        hole,
        strips: s,
        rows0,
        n,
        corner_sides,
        mut corners,
        round,
        natural,
    } = prepared;
    let count = hole.sides.len();
    // The spoke's first difference d at each corner V_k (start of side k):
    // by §4.3's rule d_a + d_b − 2cos(γ/2)·d = 0 at a corner. Where the
    // boundary runs straight on (γ = π) that rule would ask |d_a| = |d_b|
    // and leave d free; there the rule is w_a·d_a + w_b·d_b = 0 with
    // (w_a, w_b) = 2(|d_b|, |d_a|)/(|d_a| + |d_b|) (the tangents opposite,
    // as the neighbour's continuity makes them), and d is chosen so that
    // the G¹ condition next to the corner, which then holds only fixed
    // points, is met ([`straight_spokes`]).
    let nf = n as f64;
    let vertex = |c: usize| c % count + 1;
    let mut straight = Vec::new();
    let mut spoke: Vec<Vec3> = corner_sides
        .iter()
        .enumerate()
        .map(|(k, &(da, db, gamma))| {
            if gamma < straight_from(natural) {
                return scale(add(da, db), 1.0 / (2.0 * (gamma / 2.0).cos()));
            }
            let (la, lb) = (norm(da), norm(db));
            let w = [2.0 * lb / (la + lb), 2.0 * la / (la + lb)];
            // A start: the neighbour's cross direction, square to the side.
            let along = scale(db, 1.0 / lb);
            let d = s[k].at(0.0).der;
            let across = sub(d, scale(along, dot(d, along)));
            let across = scale(across, 1.0 / norm(across));
            straight.push(Straight {
                k,
                w,
                basis: [across, along],
            });
            scale(across, 0.5 * (la + lb))
        })
        .collect();
    // Rows 1: W = α D + β P′ through the spokes' first points, α and β
    // linear along each side; for a round hole cubic, their end slopes
    // the linear ones plus `bend` (per side, at its start and end).
    type Slopes = [(f64, f64); 2];
    let rows1 = |spoke: &[Vec3],
                 bend: Option<&[Slopes]>,
                 corners: &mut CornerMismatch|
     -> Result<Vec<Vec<Vec3>>> {
        (0..count)
            .map(|k| {
                let row = &rows0[k];
                let w0 = scale(spoke[k], nf);
                let w1 = add(
                    scale(spoke[(k + 1) % count], nf),
                    scale(sub(row[n], row[n - 1]), nf),
                );
                let ends = end_coefficients(&s[k], [w0, w1], n, corners)
                    .map_err(|e| fold_error(e, k, hole.sides[k].face))?;
                second_row(&s[k], row, ends, bend.map(|b| b[k]), n)
                    .map_err(|e| fold_error(e, k, hole.sides[k].face))
            })
            .collect()
    };
    let mut bend: Option<Vec<Slopes>> = None;
    // Real corners whose spokes are natural too, with the weights of their
    // rule x·d_a + y·d_b − d = 0.
    let mut fitted: Vec<(usize, [f64; 2])> = Vec::new();
    if natural {
        // No real corner to anchor the spokes at the straight ones (a
        // round hole, or too few real corners for the rule): each starts
        // towards the mean of the corners, 1/n of the way, in the
        // neighbour's tangent plane; the rows' slopes then make the G¹
        // condition next to each corner hold ([`round_slopes`]).
        let centre = scale(
            rows0.iter().fold([0.0; 3], |a, r| add(a, r[0])),
            1.0 / count as f64,
        );
        for c in &straight {
            let to = scale(sub(centre, rows0[c.k][0]), 1.0 / nf);
            let [a, b] = c.basis;
            let inward = dot(to, a);
            if inward.is_nan() {
                return Err(Error::Fill {
                    why: format!(
                        "at corner {k} the neighbour's cross-boundary derivative runs along the \
                         side or vanishes: no direction into the hole (sides numbered as cut)",
                        k = c.k
                    ),
                });
            }
            if inward <= 0.0 {
                // The centre behind the boundary's tangent line: a spoke to
                // it would leave the hole.
                return Err(Error::Fill {
                    why: format!(
                        "the hole is not star-shaped around the fan's centre (the mean of its \
                         corners): at corner {k} the centre lies behind the boundary's tangent, \
                         outside the hole (sides numbered as cut)",
                        k = c.k
                    ),
                });
            }
            spoke[c.k] = add(scale(a, dot(to, a)), scale(b, dot(to, b)));
        }
        for (k, &(da, db, gamma)) in corner_sides.iter().enumerate() {
            if gamma >= straight_from(natural) {
                continue;
            }
            let (x, y, _) = decompose(scale(sub(centre, rows0[k][0]), 1.0 / nf), da, db);
            if !(x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite()) {
                // The natural spoke leaves the corner's angle: no rule
                // with positive weights along the boundary holds it.
                return Err(Error::Fill {
                    why: format!(
                        "the fan's natural spoke at corner {k} (towards the mean of the \
                         corners) lies outside the corner's angle: the hole is not star-shaped \
                         around that centre (sides numbered as cut)"
                    ),
                });
            }
            spoke[k] = add(scale(da, x), scale(db, y));
            fitted.push((k, [x, y]));
        }
        if !straight.is_empty() {
            bend = Some(round_slopes(
                &straight,
                &spoke,
                &rows0,
                n,
                |b: &[Slopes]| rows1(&spoke, Some(b), &mut CornerMismatch::default()),
            )?);
        }
    } else if !straight.is_empty() {
        straight_spokes(&mut spoke, &straight, &rows0, n, |sp: &[Vec3]| {
            rows1(sp, None, &mut CornerMismatch::default())
        })?;
    }
    let rules: Vec<BoundaryRule> = straight
        .iter()
        .map(|c| (c.k, c.w, 0.0))
        .chain(fitted.iter().map(|&(k, w)| (k, w, -1.0)))
        .map(|(k, w, centre)| {
            (
                vertex(k),
                [
                    (vertex(k + count - 1), w[0]),
                    (vertex(k + 1), w[1]),
                    (0, centre),
                ],
            )
        })
        .collect();
    let rows1 = rows1(&spoke, bend.as_deref(), &mut corners)?;
    let mut fixed: BTreeMap<usize, Vec<(bool, Vec3)>> = BTreeMap::new();
    let mut vertices = vec![[0.0; 3]; count + 1];
    for k in 0..count {
        vertices[k + 1] = rows0[k][0];
    }
    vertices[0] = scale(
        vertices[1..].iter().fold([0.0; 3], |a, &b| add(a, b)),
        1.0 / count as f64,
    );
    let triangles: Vec<[usize; 3]> = (0..count)
        .map(|k| [0, k + 1, (k + 1) % count + 1])
        .collect();
    let surface = TriSurface::try_new(&vertices, &triangles, n)?;
    for k in 0..count {
        for (m, &x) in rows0[k].iter().enumerate() {
            let g = surface.global_index(k, 0, n - m, m);
            fixed.entry(g).or_default().push((false, x));
        }
        for (m, &x) in rows1[k].iter().enumerate() {
            let g = surface.global_index(k, 1, n - 1 - m, m);
            fixed.entry(g).or_default().push((true, x));
        }
    }
    let problem = fixed_problem(
        surface,
        &fixed,
        options,
        Continuity {
            boundary_rules: rules,
            ..Continuity::default()
        },
        &mut corners,
        false,
    );
    // Corner 0 is C: T_u × T_v is the normal of (C, V_k, V_{k+1}).
    let rational = if hole
        .sides
        .iter()
        .any(|s| options.rational(s.face).is_some())
    {
        " (a rational face's stand-in can be one span along the side: \
         RationalSurface::polynomial_spans, as `fairsurf fill` makes it)"
    } else {
        ""
    };
    let cut = |why: String| Error::Fill {
        why: if straight.is_empty() {
            format!("the fan of {count} patches (natural spokes){why}")
        } else {
            format!(
                "the fan of {count} patches (the hole's sides cut at {} straight corners: their \
                 knots, a hole of one or two sides at their middles, one of four pieces at the \
                 longest's middle){why}",
                straight.len()
            )
        },
    };
    let fan = finish(problem, hole, corners, t0).map_err(|e| {
        if straight.is_empty() && !natural {
            e
        } else {
            // A fill error's own words, without the error's prefix again.
            let e = match e {
                Error::Fill { why } => why,
                e => e.to_string(),
            };
            cut(format!(" could not be solved{rational}: {e}"))
        }
    })?;
    let fan = unfolded(fan, faces, options)?;
    // Where the G¹ construction at straight corners does not hold (few
    // real corners, a boundary that bends back), the patches open their
    // seams while every condition holds (found: spokes without a first
    // derivative at the centre, a singular point whose normals are noise):
    // refused, not returned. Natural spokes are checked the same way.
    let seam = fan
        .report
        .solve
        .triangular
        .as_ref()
        .and_then(|f| f.max_edge_normal_angle)
        .map_or(0.0, |a| a.0);
    if (natural || !straight.is_empty()) && (seam > CUT_SEAM_LIMIT || seam.is_nan()) {
        // Two causes were met: neighbours that disagree on the tangent
        // plane at a corner (faces sampled, not cut from one surface), and
        // a boundary with too few real corners for the construction.
        let (plane, at) = corner_planes(&s);
        let why = if plane.is_nan() {
            format!("a neighbour's normal is undefined at corner {at} (sides numbered as cut)")
        } else if plane > CORNER_PLANES {
            format!(
                "the neighbours' tangent planes disagree by {:.2e}° at corner {at} (sides \
                 numbered as cut): the fan's G¹ needs one tangent plane at each corner",
                plane.to_degrees()
            )
        } else if round {
            "the round hole's construction (spokes towards the mean of its corners, the rows' \
             slopes solved) fails on this boundary"
                .to_string()
        } else if natural && straight.is_empty() {
            "the construction with natural spokes (the corners' rule weights fitted to them) \
             fails on this boundary, and §4.3's rule did too"
                .to_string()
        } else if natural {
            "the construction at the straight corners fails on this boundary, with their \
             spokes solved for and with natural spokes and the rows' slopes solved"
                .to_string()
        } else {
            "the construction at the straight corners fails on this boundary: too few real \
             corners"
                .to_string()
        };
        return Err(cut(format!(
            " opens its seams by {:.2e}° with every G¹ condition held (above {:.0e}°; {why})\
             {rational}",
            seam.to_degrees(),
            CUT_SEAM_LIMIT.to_degrees()
        )));
    }
    Ok(fan)
}

/// The largest normal angle (radians; 0.01°, the default angle tolerance)
/// between the thin-plate patches of a fan cut at knots before it is
/// refused: on the tested holes it is 1e-10° (exact data) and 7e-5° (the
/// rounded box through 8-span stand-ins); where the construction fails it
/// was 0.1–110°.
const CUT_SEAM_LIMIT: f64 = 0.01 * std::f64::consts::PI / 180.0;

/// The angle (radians) between the neighbours' tangent planes at a corner
/// above which a fan's opened seams are blamed on them: 1e-6°. Exact data
/// (faces cut from one surface) give 1e-14°, faces sampled from one at
/// their control points 1e-2°.
const CORNER_PLANES: f64 = 1e-6 * std::f64::consts::PI / 180.0;

/// The largest angle (radians) between the tangent planes the two sides
/// meeting at a corner give (their neighbours' normals P′ × D, D into the
/// hole), and that corner (the start of side k).
fn corner_planes(s: &[Strip]) -> (f64, usize) {
    let count = s.len();
    let normal = |k: usize, t: f64| {
        let x = s[k].at(t);
        crate::vec3::cross(x.dpos, x.der)
    };
    (0..count)
        .map(|k| {
            (
                angle(normal((k + count - 1) % count, 1.0), normal(k, 0.0)),
                k,
            )
        })
        .fold(
            (0.0, 0),
            |a, b| if b.0 > a.0 || b.0.is_nan() { b } else { a },
        )
}

/// A straight corner of a fan: the corner k, its rule's weights on the
/// previous and the next side's tangent, and a basis of the neighbour's
/// tangent plane there (square to the side, along it).
struct Straight {
    k: usize,
    w: [f64; 2],
    basis: [Vec3; 2],
}

/// The spokes' first differences d at straight corners such that the G¹
/// condition across each such spoke next to its corner holds. With the
/// corner's rule f·d_L + g·d_R = 0 (c = 0: e₁ + f₁ + g₁ = 0, see
/// `triangle::continuity`) the condition's coefficient m = n − 1 no longer
/// holds the spoke's second point; it reads, in the fixed points only,
///
/// ```text
/// (2cos(2π/N) − 2)·d + d_a + d_b + (n − 1)·(f·(L − V − d) + g·(R − V − d)) = 0
/// ```
///
/// (N the fan's patches, L and R the rows 1's points next to the spoke's
/// first point V + d on either side). Rows 1 are affine in the spokes, so
/// the conditions are too: least squares over d in the neighbours'
/// tangent planes (two numbers per corner, three equations: for a
/// neighbour with continuous curvature across the corner the normal part
/// holds by itself). What the data leave is the G¹ rows' residual, dropped
/// and reported by the solve like any contradiction.
fn straight_spokes(
    spoke: &mut [Vec3],
    straight: &[Straight],
    rows0: &[Vec<Vec3>],
    n: usize,
    rows1: impl Fn(&[Vec3]) -> Result<Vec<Vec<Vec3>>>,
) -> Result<()> {
    let residual = |spoke: &[Vec3]| -> Result<Vec<f64>> {
        let r1 = rows1(spoke)?;
        Ok(straight
            .iter()
            .flat_map(|c| straight_condition(c, spoke, rows0, &r1, n))
            .collect())
    };
    // The map is affine: one Gauss–Newton step solves it, a second mends
    // the rounding of the differences (steps of 1e-6 of the spoke).
    let unknowns = 2 * straight.len();
    for _ in 0..2 {
        let r0 = residual(spoke)?;
        let mut jac = vec![vec![0.0; unknowns]; r0.len()];
        for (i, c) in straight.iter().enumerate() {
            let h = 1e-6 * norm(spoke[c.k]);
            for (b, dir) in c.basis.iter().enumerate() {
                let mut trial = spoke.to_vec();
                trial[c.k] = add(trial[c.k], scale(*dir, h));
                let r = residual(&trial)?;
                for (row, (x, y)) in jac.iter_mut().zip(r.iter().zip(&r0)) {
                    row[2 * i + b] = (x - y) / h;
                }
            }
        }
        // Normal equations (a few unknowns), columns scaled to unit length.
        let norms: Vec<f64> = (0..unknowns)
            .map(|j| {
                jac.iter()
                    .map(|r| r[j] * r[j])
                    .sum::<f64>()
                    .sqrt()
                    .max(f64::MIN_POSITIVE)
            })
            .collect();
        let Some(x) = normal_step(&jac, &r0, &norms, 0.0) else {
            break; // degenerate: the spokes stand, the solve reports the rows
        };
        let start: Vec<f64> = straight.iter().map(|c| norm(spoke[c.k])).collect();
        for (i, c) in straight.iter().enumerate() {
            for (b, dir) in c.basis.iter().enumerate() {
                spoke[c.k] = add(spoke[c.k], scale(*dir, x[2 * i + b] / norms[2 * i + b]));
            }
            // The condition's d must still point into the hole: between
            // straight corners only (a boundary with few real corners) it
            // shrinks towards nothing.
            let into = dot(spoke[c.k], c.basis[0]);
            if into <= 1e-3 * start[i] || into.is_nan() {
                return Err(Error::Fill {
                    why: format!(
                        "at corner {} (sides numbered as cut at their knots or middles), where the \
                         hole's boundary runs straight on, G¹ between the fan's patches leaves \
                         no spoke into the hole (the boundary has too few corners for a fan)",
                        c.k
                    ),
                });
            }
        }
    }
    Ok(())
}

/// The G¹ condition across the spoke of the straight corner `c` next to
/// the corner (m = n − 1), in the fixed points only: rows 0, the rows 1
/// `r1`, the spoke's first difference (see [`straight_spokes`]).
fn straight_condition(
    c: &Straight,
    spoke: &[Vec3],
    rows0: &[Vec<Vec3>],
    r1: &[Vec<Vec3>],
    n: usize,
) -> Vec3 {
    let count = spoke.len();
    let centre = 2.0 * (2.0 * std::f64::consts::PI / count as f64).cos() - 2.0;
    let k = c.k;
    let prev = &rows0[(k + count - 1) % count];
    let v = rows0[k][0];
    let (da, db) = (sub(prev[n - 1], prev[n]), sub(rows0[k][1], v));
    let m = add(v, spoke[k]);
    let l = sub(r1[(k + count - 1) % count][n - 2], m);
    let r = sub(r1[k][1], m);
    add(
        add(scale(spoke[k], centre), add(da, db)),
        scale(add(scale(l, c.w[0]), scale(r, c.w[1])), (n - 1) as f64),
    )
}

/// One Gauss–Newton step for the least squares ‖J·x + r‖ (a few
/// unknowns) by its normal equations: the columns of J divided by `norms`,
/// `ridge` times the mean diagonal added (Tikhonov) when positive. The
/// step in the scaled unknowns, None when the system is singular.
fn normal_step(jac: &[Vec<f64>], r0: &[f64], norms: &[f64], ridge: f64) -> Option<Vec<f64>> {
    let unknowns = norms.len();
    let mut a: Vec<Vec<f64>> = (0..unknowns)
        .map(|i| {
            (0..unknowns)
                .map(|j| jac.iter().map(|r| r[i] * r[j]).sum::<f64>() / (norms[i] * norms[j]))
                .collect()
        })
        .collect();
    if ridge > 0.0 {
        let mean = (0..unknowns).map(|i| a[i][i]).sum::<f64>() / unknowns as f64;
        for (i, row) in a.iter_mut().enumerate() {
            row[i] += ridge * mean;
        }
    }
    let b: Vec<[f64; 1]> = (0..unknowns)
        .map(|i| [-jac.iter().zip(r0).map(|(r, e)| r[i] * e).sum::<f64>() / norms[i]])
        .collect();
    crate::bspline::solve_dense(a, b).map(|x| x.into_iter().map(|v| v[0]).collect())
}

/// A round hole's rows 1: the changes of α′ and β′ (in t) at both ends of
/// each side, beyond the slopes of linear α and β, that make the G¹
/// condition next to each corner hold with the spokes given
/// ([`straight_condition`]; per corner two changes on either side, four
/// unknowns for its three equations). The least changes (Tikhonov, 1e-10
/// of the normal matrix's mean diagonal); the map is affine, so one step
/// solves it and a second mends the rounding.
///
/// Why: with spokes chosen to meet the condition instead
/// ([`straight_spokes`]) a fan of a boundary without real corners found
/// spokes of a quarter to a half of their natural length and opened its
/// seams by 0.1–110°; with natural spokes and linear α, β the condition
/// was 0.1 away and dropped, the seams opened by 0.17°. With the slopes
/// free, a round hole of four arcs closed them to rounding (1.7e-10°
/// between the patches of fill_round.json).
fn round_slopes(
    straight: &[Straight],
    spoke: &[Vec3],
    rows0: &[Vec<Vec3>],
    n: usize,
    rows1: impl Fn(&[[(f64, f64); 2]]) -> Result<Vec<Vec<Vec3>>>,
) -> Result<Vec<[(f64, f64); 2]>> {
    let count = spoke.len();
    let slopes = |x: &[f64]| -> Vec<[(f64, f64); 2]> {
        let mut b = vec![[(0.0, 0.0); 2]; count];
        for (i, c) in straight.iter().enumerate() {
            let j = (c.k + count - 1) % count;
            b[c.k][0] = (x[4 * i], x[4 * i + 1]);
            b[j][1] = (x[4 * i + 2], x[4 * i + 3]);
        }
        b
    };
    let residual = |x: &[f64]| -> Result<Vec<f64>> {
        let r1 = rows1(&slopes(x))?;
        Ok(straight
            .iter()
            .flat_map(|c| straight_condition(c, spoke, rows0, &r1, n))
            .collect())
    };
    let unknowns = 4 * straight.len();
    let mut x = vec![0.0; unknowns];
    for _ in 0..2 {
        let r0 = residual(&x)?;
        // Affine: unit steps give the Jacobian's columns exactly (up to
        // rounding).
        let mut jac = vec![vec![0.0; unknowns]; r0.len()];
        for u in 0..unknowns {
            let mut t = x.clone();
            t[u] += 1.0;
            for (row, (a, b)) in jac.iter_mut().zip(residual(&t)?.iter().zip(&r0)) {
                row[u] = a - b;
            }
        }
        let Some(step) = normal_step(&jac, &r0, &vec![1.0; unknowns], 1e-10) else {
            break; // degenerate: the solve reports the rows it drops
        };
        for (x, s) in x.iter_mut().zip(&step) {
            *x += s;
        }
    }
    Ok(slopes(&x))
}

/// What a fan and a single triangle share: the hole oriented like its
/// neighbours, the sides' strips (each one Bézier piece), the degree n,
/// the rows 0 at degree n, per corner the two sides' first control-point
/// differences there and their angle (checked: below 180°, above 0).
struct Prepared {
    hole: Hole,
    strips: Vec<Strip>,
    rows0: Vec<Vec<Vec3>>,
    n: usize,
    corner_sides: Vec<(Vec3, Vec3, f64)>,
    corners: CornerMismatch,
    /// No real corner: the boundary runs straight on through every corner
    /// (a round hole; fans only).
    round: bool,
    /// Natural spokes: towards the mean of the corners, at real corners
    /// with their rule's weights fitted, at straight ones with the rows'
    /// slopes solved ([`round_slopes`]): a round hole, or asked for
    /// (`prepare`'s `natural`) where a corner is straight or turns by less
    /// than 30°.
    natural: bool,
}

/// Whether the hole's boundary runs straight on through corner k (turns by
/// at most 1e-6 rad there: the test that groups edges into sides): a knot
/// inside a side, or two edges that continue each other.
pub(super) const STRAIGHT: f64 = std::f64::consts::PI - 1e-6;

/// The hole with each side cut at its boundary's interior knots (sides of
/// several Bézier pieces become several sides meeting at straight
/// corners, each one piece); a hole of one or two one-piece sides has
/// them cut in three or two at their parameters' middle (a lens of two
/// sides: four patches, 0.115376 against six's 0.115372 in W, in half the
/// time).
fn split_at_knots(faces: &[BSplineSurface], hole: &Hole) -> Result<Hole> {
    let mut sides = Vec::with_capacity(hole.sides.len());
    for (k, side) in hole.sides.iter().enumerate() {
        let whole = Strip::from_side(side_face(faces, hole, k)?, side.edge, false)?;
        let [a, b] = side.range;
        let mut cuts: Vec<f64> = vec![a];
        for &t in whole.knots.knots() {
            let last = *cuts.last().expect("a cut");
            if t > last + KNOT_SNAP && t < b - KNOT_SNAP {
                cuts.push(t);
            }
        }
        cuts.push(b);
        // A hole of one or two sides (a teardrop, a lens) has too few
        // corners for a fan: its sides are halved (thirded) at their
        // parameters' middle, the new corners straight.
        if hole.sides.len() < 3 && cuts.len() == 2 {
            let parts = 3usize.div_ceil(hole.sides.len());
            cuts = (0..=parts)
                .map(|i| a + (b - a) * i as f64 / parts as f64)
                .collect();
        }
        let mut pieces: Vec<Side> = cuts
            .windows(2)
            .map(|w| Side {
                range: [w[0], w[1]],
                ..*side
            })
            .collect();
        if side.reversed {
            pieces.reverse();
        }
        sides.extend(pieces);
    }
    Ok(Hole {
        sides,
        length: hole.length,
    })
}

/// `fan`: the sides cut at their knots, a one- or two-sided hole's also
/// at their middles ([`split_at_knots`]), and straight
/// corners allowed (a fan's spoke there takes an explicit rule); else
/// (one triangle) each side must be one piece and every corner a corner.
fn prepare(
    faces: &[BSplineSurface],
    hole: &Hole,
    options: &FillOptions,
    min_degree: usize,
    fan: bool,
    natural: bool,
) -> Result<Prepared> {
    let strips = |hole: &Hole| -> Result<Vec<Strip>> {
        (0..hole.sides.len())
            .map(|k| Strip::of_side(side_face(faces, hole, k)?, hole.sides[k]))
            .collect()
    };
    let hole_sides = hole.sides.len();
    let mut hole = if fan {
        split_at_knots(faces, hole)?
    } else {
        hole.clone()
    };
    let count = hole.sides.len();
    if count < 3 {
        return Err(Error::Fill {
            why: format!("a hole has at least 3 sides, this one {count}"),
        });
    }
    // Pieces, not the hole's sides, are numbered in what follows.
    let numbered = if fan && count != hole_sides {
        " (sides numbered as cut at their knots or middles)"
    } else {
        ""
    };
    // Orientation: the patches' normal along side k is P′ × D; it must
    // agree with side 0's neighbour.
    let mut s = strips(&hole)?;
    if !faces_like_side_0(faces, &hole, &s[0]) {
        hole = hole.reversed();
        s = strips(&hole)?;
    }
    for (k, st) in s.iter().enumerate() {
        let spans = st.knots.spans().len();
        if spans != 1 {
            let face = hole.sides[k].face;
            let stand_in = if options.rational(face).is_some() {
                " (the stand-in of a rational face: where its weights vary along the side it \
                 can stand in as one span, RationalSurface::polynomial_spans, as `fairsurf \
                 fill` makes it)"
            } else {
                ""
            };
            return Err(Error::Fill {
                why: format!(
                    "side {k} (face {face}) is a B-spline of {spans} spans{stand_in}; one \
                     triangular patch is filled along sides that are one Bézier piece (a fan \
                     cuts them at their knots)"
                ),
            });
        }
    }
    let p_max = s.iter().map(Strip::degree).max().unwrap_or(1);
    // Sides already of high degree (one-span stand-ins of rational faces)
    // give the patches freedom enough: no elevation (the rounded corner
    // of a box: W 3.141579 at degree 12, 3.141581 at 14, in 60% of the
    // time).
    let least = p_max + 2;
    let elevate = if least >= RICH_DEGREE {
        0
    } else {
        options.elevate
    };
    let mut n = (least + elevate).max(min_degree);
    // Rows 0 at degree n, and per corner the two sides' first differences
    // and their angle (errors: folded, concave; for one triangle a corner
    // where the boundary runs straight on).
    type Corners = (Vec<Vec<Vec3>>, Vec<(Vec3, Vec3, f64)>, CornerMismatch);
    let at_degree = |n: usize| -> Result<Corners> {
        let rows0: Vec<Vec<Vec3>> = s
            .iter()
            .map(|st| elevate_points(&st.pos, n - st.degree()))
            .collect();
        let mut corners = CornerMismatch::default();
        let mut corner_sides = Vec::with_capacity(count);
        for k in 0..count {
            let prev = &rows0[(k + count - 1) % count];
            let v = rows0[k][0];
            corners.position = corners.position.max(dist(prev[n], v));
            let (da, db) = (sub(prev[n - 1], prev[n]), sub(rows0[k][1], v));
            let gamma = angle(da, db);
            // A fan's natural spokes take a corner turning by less than
            // 0.01 rad as straight, whichever way it turns (CAD's G¹ joins
            // bend either way by up to 1e-4 rad).
            if gamma >= STRAIGHT || (fan && gamma >= ALMOST_STRAIGHT) {
                if fan {
                    // The boundary runs on: the spoke's rule is the fan's own.
                    corner_sides.push((da, db, gamma));
                    continue;
                }
                return Err(Error::Fill {
                    why: format!(
                        "sides {} and {k} of the hole continue each other at corner {k} \
                         ({:.4}°): one triangular patch needs three corners (a fan takes it)",
                        (k + count - 1) % count,
                        gamma.to_degrees()
                    ),
                });
            }
            if gamma <= 1e-9 {
                return Err(Error::Fill {
                    why: format!(
                        "the hole's sides {} and {k} fold back on each other at corner \
                         {k}{numbered}",
                        (k + count - 1) % count
                    ),
                });
            }
            // The bisector of da and db points into the hole at a convex
            // corner; at a concave one (inside angle above 180°) out of it.
            // Of the unit tangents: da + db leans towards the longer one,
            // and at a corner turning by 5.7° between a side and half a
            // side it pointed out of the hole.
            let bisector = add(scale(da, 1.0 / norm(da)), scale(db, 1.0 / norm(db)));
            if dot(bisector, s[k].at(0.0).der) <= 0.0 {
                return Err(Error::Fill {
                    why: format!(
                        "corner {k} of the hole is concave (its inside angle is above 180°): a \
                         fan around a centre cannot fill it{numbered}"
                    ),
                });
            }
            corner_sides.push((da, db, gamma));
        }
        Ok((rows0, corner_sides, corners))
    };
    let (mut rows0, mut corner_sides, mut corners) = at_degree(n)?;
    // A round hole (no real corner; fans only): its rows 1 are cubic in α
    // and β along each piece ([`round_slopes`]), W of degree p + 3.
    let round = corner_sides.iter().all(|c| c.2 >= STRAIGHT);
    let straight = corner_sides.iter().any(|c| c.2 >= straight_from(natural));
    let asked = natural;
    let natural = fan && (round || (natural && corner_sides.iter().any(|c| c.2 >= NEAR_STRAIGHT)));
    let real = corner_sides.iter().all(|c| c.2 < STRAIGHT);
    if fan && !round && count == 4 && (natural || real) {
        // Four patches meet at the centre with its rule d_{i−1} + d_{i+1}
        // = 0 (2cos(2π/4) = 0); the straight corners' conditions and the
        // real ones' differ between opposite spokes, and the only solution
        // left two spokes without a first derivative at the centre (a
        // singular point; the patches' normals there were noise, 0.05–73°
        // apart; with four real corners of different angles, §4.3's rule
        // at each, too: the fan folded there). Three, five or six patches
        // do not: the longest piece is halved (by its control polygon's
        // length; of equal ones the first), five patches.
        let length = |r: &[Vec3]| r.windows(2).map(|w| dist(w[0], w[1])).sum::<f64>();
        let k = (1..count).fold(0, |best, k| {
            if length(&rows0[k]) > length(&rows0[best]) {
                k
            } else {
                best
            }
        });
        let side = hole.sides[k];
        let [a, b] = side.range;
        let mid = 0.5 * (a + b);
        let mut halves = [
            Side {
                range: [a, mid],
                ..side
            },
            Side {
                range: [mid, b],
                ..side
            },
        ];
        if side.reversed {
            halves.reverse();
        }
        let mut cut = hole.clone();
        cut.sides.splice(k..=k, halves);
        // As asked: the cut's straight corner may make the spokes natural.
        return prepare(faces, &cut, options, min_degree, fan, asked);
    }
    if natural && straight && n < p_max + 4 {
        n = p_max + 4;
        (rows0, corner_sides, corners) = at_degree(n)?;
    }
    Ok(Prepared {
        hole,
        strips: s,
        rows0,
        n,
        corner_sides,
        corners,
        round,
        natural,
    })
}

/// The error of a side whose neighbour folds over, naming it.
fn fold_error(e: Error, k: usize, face: usize) -> Error {
    match e {
        Error::Fill { why } => Error::Fill {
            why: format!("side {k}'s neighbour (face {face}): {why}"),
        },
        e => e,
    }
}

/// α and β at the ends of a side (see [`second_row`]): W(0) = `w[0]` and
/// W(1) = `w[1]` as nearly as the tangent plane allows (the distances left
/// go to `corners.tangent`); an error if α is not positive at an end.
fn end_coefficients(
    st: &Strip,
    w: [Vec3; 2],
    n: usize,
    corners: &mut CornerMismatch,
) -> Result<[(f64, f64); 2]> {
    let nf = n as f64;
    let (s0, s1) = (st.at(0.0), st.at(1.0));
    let (a0, b0, r0) = decompose(w[0], s0.der, s0.dpos);
    let (a1, b1, r1) = decompose(w[1], s1.der, s1.dpos);
    corners.tangent = corners.tangent.max(r0 / nf).max(r1 / nf);
    if !(a0 > 0.0 && a1 > 0.0 && a0.is_finite() && a1.is_finite()) {
        return Err(Error::Fill {
            why: "its cross-boundary derivative does not point into the hole at a corner (the \
                  faces fold over there, or the side is not a boundary facing the hole)"
                .into(),
        });
    }
    Ok([(a0, b0), (a1, b1)])
}

/// Row 1 of a side (points P_{1,n−1−m,m}, m = 0 … n − 1, in the side's own
/// corner order): row 0 plus W/n with W = α(t)·D + β(t)·P′, α and β taking
/// the values `ends` ([`end_coefficients`]) at t = 0 and 1: linear, or
/// with `bend` cubic, their slopes at the two ends the linear ones plus
/// `bend` (then n ≥ p + 4). An error when α is not positive along the
/// side (its Bézier coefficients).
fn second_row(
    st: &Strip,
    row: &[Vec3],
    ends: [(f64, f64); 2],
    bend: Option<[(f64, f64); 2]>,
    n: usize,
) -> Result<Vec<Vec3>> {
    let p = st.degree();
    let nf = n as f64;
    let [(a0, b0), (a1, b1)] = ends;
    let (alpha, beta) = match bend {
        None => (vec![a0, a1], vec![b0, b1]),
        Some([(da0, db0), (da1, db1)]) => {
            // Cubic Bézier coefficients from end values and slopes.
            let (sa0, sa1) = (a1 - a0 + da0, a1 - a0 + da1);
            let (sb0, sb1) = (b1 - b0 + db0, b1 - b0 + db1);
            (
                vec![a0, a0 + sa0 / 3.0, a1 - sa1 / 3.0, a1],
                vec![b0, b0 + sb0 / 3.0, b1 - sb1 / 3.0, b1],
            )
        }
    };
    // α > 0 all along keeps W pointing into the hole (positive Bézier
    // coefficients: sufficient; linear α is positive at both ends already).
    if alpha.iter().any(|a| a.is_nan() || *a <= 0.0) {
        return Err(Error::Fill {
            why: "the weight of its cross-boundary derivative in the row next to it turns \
                  non-positive inside the side (the rows' slopes solved for a round hole \
                  would fold the fill over the boundary)"
                .into(),
        });
    }
    // P′ of degree p − 1 raised to p, then both products.
    let dp: Vec<Vec3> = st
        .pos
        .windows(2)
        .map(|w| scale(sub(w[1], w[0]), p as f64))
        .collect();
    let dp = elevate_points(&dp, 1);
    let wa = times(&alpha, &st.der);
    let wb = times(&beta, &dp);
    let wsum: Vec<Vec3> = wa.iter().zip(&wb).map(|(&x, &y)| add(x, y)).collect();
    let wn = elevate_points(&wsum, n - wsum.len());
    Ok((0..n)
        .map(|m| add(row[m], scale(wn[m], 1.0 / nf)))
        .collect())
}

/// The problem of `surface` with the points `fixed` holds and the energy.
/// A point given by a boundary row (rows 0: `false`) takes that row's
/// value — the position wins, so the fill stays on its neighbours — the
/// mean when two boundary rows give it (their distance goes to
/// `corners.position`), and a row 1 that disagrees goes to
/// `corners.tangent`; a point only rows 1 give takes their mean, the
/// disagreement going to `corners.twist` when `twist` (the triangle's
/// corner twists), else to `corners.tangent` (a fan's spoke points, given
/// by two sides' tangent planes).
fn fixed_problem(
    mut surface: TriSurface,
    fixed: &BTreeMap<usize, Vec<(bool, Vec3)>>,
    options: &FillOptions,
    continuity: Continuity,
    corners: &mut CornerMismatch,
    twist: bool,
) -> TriProblem {
    let mean = |v: &[Vec3]| {
        scale(
            v.iter().fold([0.0; 3], |a, &b| add(a, b)),
            1.0 / v.len() as f64,
        )
    };
    let mut held = Vec::with_capacity(fixed.len());
    for (&g, values) in fixed {
        let boundary: Vec<Vec3> = values.iter().filter(|v| !v.0).map(|v| v.1).collect();
        let rows1: Vec<Vec3> = values.iter().filter(|v| v.0).map(|v| v.1).collect();
        let value = if boundary.is_empty() {
            let m = mean(&rows1);
            for &x in &rows1 {
                let d = dist(x, m);
                if twist && rows1.len() > 1 {
                    corners.twist = corners.twist.max(2.0 * d);
                } else {
                    corners.tangent = corners.tangent.max(d);
                }
            }
            m
        } else {
            let m = mean(&boundary);
            for &x in &boundary {
                corners.position = corners.position.max(2.0 * dist(x, m));
            }
            for &x in &rows1 {
                corners.tangent = corners.tangent.max(dist(x, m));
            }
            m
        };
        surface.set_point(g, value);
        held.push((g, value));
    }
    let mut problem = TriProblem::from_mesh(surface)
        .with_term(Stretch::new(options.stretch))
        .with_term(Bend::new(options.bend))
        .with_continuity(continuity);
    for (g, value) in held {
        problem = problem.with_constraint(
            format!("fill row point {g}"),
            Constraint::Fixed { point: g, value },
        );
    }
    problem
}

/// Where side k of the hole lies on a fan's or one triangle's `surface`:
/// its patch and the barycentric point of its parameter t (normal T_u ×
/// T_v facing like the neighbours). A fan (N ≥ 3 patches) has side k on
/// patch k from corner 1 to corner 2 (corner 0 the centre); one triangle
/// has side k from its corner k to corner k + 1.
fn side_point(surface: &TriSurface, k: usize, t: f64) -> (usize, [f64; 3]) {
    if surface.patch_count() == 1 {
        let mut b = [0.0; 3];
        b[k] = 1.0 - t;
        b[(k + 1) % 3] = t;
        (0, b)
    } else {
        (k, [0.0, 1.0 - t, t])
    }
}

/// Solves and measures W (a candidate).
fn finish(
    problem: TriProblem,
    hole: Hole,
    corners: CornerMismatch,
    t0: Instant,
) -> Result<FanFill> {
    let setup = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let (solved, factor) = problem.solve_factored()?;
    let solve = t1.elapsed().as_secs_f64();
    let mut fill = FanFill {
        surface: solved.surface,
        hole,
        report: FanReport {
            solve: solved.report,
            sides: Vec::new(),
            corners,
            inner_angle: 0.0,
            curvature: TotalCurvature {
                value: 0.0,
                error: 0.0,
            },
            willmore: Vec::new(),
            seconds: FillSeconds {
                setup,
                solve,
                measure: 0.0,
            },
            others: Vec::new(),
            descent_note: None,
        },
        factor: factor.map(Arc::from),
    };
    fill.measure_w();
    fill.report.willmore.push(fill.report.curvature.value);
    Ok(fill)
}

impl FanFill {
    /// W of the surface as it is.
    fn measure_w(&mut self) {
        let t = Instant::now();
        let r = &mut self.report;
        r.curvature = TotalCurvature {
            value: 0.0,
            error: 0.0,
        };
        for p in self.surface.patches() {
            let w = total_curvature(&BSplineSurface::from_bezier(&p.to_tensor()));
            r.curvature.value += w.value;
            r.curvature.error += w.error;
        }
        r.seconds.measure += t.elapsed().as_secs_f64();
    }

    /// A candidate made whole: W lowered by at most `options.descent_steps`
    /// steps along the kept G¹ rows, the rows 0 and 1 fixed
    /// ([`fan_willmore`]), until three steps in a row gain less than
    /// [`FAN_DESCENT_REL`] of W, or one when the next step's model promises
    /// less too (along the rows the solve kept, with its factorization,
    /// at whichever row tolerance it took; without one — nothing free — no
    /// steps);
    /// then measured: the largest normal angle between the patches (the
    /// sides, measured by the candidate, stay: the descent keeps rows 0
    /// and 1).
    pub(super) fn completed(mut self, options: &FillOptions) -> Self {
        let t = Instant::now();
        // The factorization is used here or dropped (it may be large).
        let factor = self.factor.take();
        // The thin plate's seams, as its solve measured them.
        let thin_plate = self
            .report
            .solve
            .triangular
            .as_ref()
            .and_then(|f| f.max_edge_normal_angle);
        let angle = |a: Option<(f64, [usize; 2])>| a.map_or(0.0, |a| a.0);
        match factor {
            _ if options.descent_steps == 0 => {}
            None => {
                self.report.descent_note = Some(
                    "no descent on W: the thin plate's solve left no KKT factorization (no \
                     point was free)"
                        .into(),
                );
            }
            Some(factor) => {
                let (surface, history) = fan_willmore::descend_tri(
                    self.surface.clone(),
                    &factor,
                    options.descent_steps,
                    FAN_DESCENT_REL,
                );
                // Steps keep the kept G¹ rows; rows dropped as inconsistent
                // may drift. Seams between the patches opened beyond twice
                // the thin plate's (and 1e-9°) are not worth the W.
                let after = max_edge_normal_angle(&surface, 65);
                let turn = largest_tri_normal_turn(&surface, 2 * surface.degree() + 2);
                let folds = turn.is_some_and(|t| t.is_fold());
                if angle(after) <= 2.0 * angle(thin_plate) + 1e-9f64.to_radians() && !folds {
                    // The solve's geometric figures, of the surface returned.
                    if let Some(tri) = self.report.solve.triangular.as_mut() {
                        tri.max_edge_normal_angle = after;
                        tri.normal_turn = turn;
                    }
                    self.surface = surface;
                    self.report.willmore = history;
                    self.report.seconds.measure += t.elapsed().as_secs_f64();
                    self.measure_w();
                } else if folds {
                    self.report.descent_note = Some(format!(
                        "the thin plate is kept: the descent on W (to {:.6}) folded the fill \
                         (its normal turned by {:.1}° between neighbouring samples)",
                        history.last().copied().unwrap_or(f64::NAN),
                        turn.map_or(f64::NAN, |t| t.angle.to_degrees())
                    ));
                    self.report.seconds.measure += t.elapsed().as_secs_f64();
                } else {
                    self.report.descent_note = Some(format!(
                        "the thin plate is kept: the descent on W (to {:.6}) opened the seams \
                         between the patches from {:.1e}° to {:.1e}°",
                        history.last().copied().unwrap_or(f64::NAN),
                        angle(thin_plate).to_degrees(),
                        angle(after).to_degrees()
                    ));
                    self.report.seconds.measure += t.elapsed().as_secs_f64();
                }
            }
        }
        let r = &mut self.report;
        r.inner_angle = angle(
            r.solve
                .triangular
                .as_ref()
                .and_then(|f| f.max_edge_normal_angle),
        );
        debug_assert!(!r.sides.is_empty(), "the candidate measured its sides");
        self
    }

    /// Per side, gap and normal angle against the neighbour. The descent
    /// on W keeps rows 0 and 1, so a candidate's sides, measured before
    /// it, are the returned fill's.
    pub(super) fn measure_sides(&mut self, faces: &[BSplineSurface], options: &FillOptions) {
        let t = Instant::now();
        let (surface, hole, r) = (&self.surface, &self.hole, &mut self.report);
        r.sides = (0..hole.sides.len())
            .map(|k| {
                let side = hole.sides[k];
                patch_side_fit(
                    surface,
                    &|t| side_point(surface, k, t),
                    &faces[side.face],
                    options.exact(side.face),
                    side,
                )
            })
            .collect();
        r.seconds.measure += t.elapsed().as_secs_f64();
    }
}

/// A fan's descent on W stops after three steps in a row that each gain
/// less than this part of W (or after one, when the next step's model —
/// with a curvature pair — promises less too). Looser than a 4-sided fill's 1e-8: the thin
/// plate in barycentric parameters is a poor model of W's Hessian, and
/// the last 5e-6 of W took ten times the steps (the pentagon of
/// `examples/cad/fill_pentagon.json` at degree 7: W 1.0313881 after 10
/// steps, 1.0313836 after 115).
pub const FAN_DESCENT_REL: f64 = 1e-6;

/// A fan or triangle whose least degree (the sides' largest + 2) is at
/// least this is not elevated by [`FillOptions::elevate`].
pub const RICH_DEGREE: usize = 9;

/// Fills a 3-sided `hole` with one triangular patch with corners (V₀, V₁, V₂): rows
/// 0 and 1 of every side from its neighbour; at each corner W(0) is the
/// previous side's tangent turned back and W(1) the next side's tangent
/// plus this side's, so the rows meet the neighbouring sides' boundary
/// points exactly; where a row 1 and a neighbouring side's boundary give
/// the same point the boundary wins (the fill stays on the neighbour);
/// the corner "twist" points, which two rows 1 give, take the mean (their
/// disagreement is reported). The inside points (all three
/// indices ≥ 2; degree ≥ 6) minimize the thin plate. Errors as
/// [`fill_fan`]'s.
pub fn fill_triangle(
    faces: &[BSplineSurface],
    hole: &Hole,
    options: &FillOptions,
) -> Result<FanFill> {
    Ok(triangle_candidate(faces, hole, options)?.completed(options))
}

/// [`fill_triangle`]'s patch solved, its W and its sides measured.
pub(super) fn triangle_candidate(
    faces: &[BSplineSurface],
    hole: &Hole,
    options: &FillOptions,
) -> Result<FanFill> {
    let t0 = Instant::now();
    if hole.sides.len() != 3 {
        return Err(Error::Fill {
            why: format!(
                "the hole has {} sides; one triangular patch fills a 3-sided hole",
                hole.sides.len()
            ),
        });
    }
    let Prepared {
        hole,
        strips: s,
        rows0,
        n,
        mut corners,
        ..
    } = prepare(faces, hole, options, 6, false, false)?;
    let nf = n as f64;
    let vertices: Vec<Vec3> = (0..3).map(|k| rows0[k][0]).collect();
    let surface = TriSurface::try_new(&vertices, &[[0, 1, 2]], n)?;
    // Side k's local index (a at V_k, b at V_{k+1}, c at the third) in the
    // patch's (i, j, l).
    let global = |k: usize, a: usize, b: usize, c: usize| {
        let mut x = [0; 3];
        x[k] = a;
        x[(k + 1) % 3] = b;
        x[(k + 2) % 3] = c;
        surface.global_index(0, x[0], x[1], x[2])
    };
    let mut fixed: BTreeMap<usize, Vec<(bool, Vec3)>> = BTreeMap::new();
    for k in 0..3 {
        let (prev, row, next) = (&rows0[(k + 2) % 3], &rows0[k], &rows0[(k + 1) % 3]);
        let w0 = scale(sub(prev[n - 1], prev[n]), nf);
        let w1 = add(
            scale(sub(next[1], next[0]), nf),
            scale(sub(row[n], row[n - 1]), nf),
        );
        let ends = end_coefficients(&s[k], [w0, w1], n, &mut corners)
            .map_err(|e| fold_error(e, k, hole.sides[k].face))?;
        let row1 = second_row(&s[k], row, ends, None, n)?;
        for m in 0..=n {
            fixed
                .entry(global(k, n - m, m, 0))
                .or_default()
                .push((false, row[m]));
        }
        for (m, &x) in row1.iter().enumerate() {
            fixed
                .entry(global(k, n - 1 - m, m, 1))
                .or_default()
                .push((true, x));
        }
    }
    let problem = fixed_problem(
        surface,
        &fixed,
        options,
        Continuity::none(),
        &mut corners,
        true,
    );
    unfolded(finish(problem, hole, corners, t0)?, faces, options)
}

/// `fill` with its sides measured ([`FanFill::measure_sides`]), or its
/// refusal when it folds over: its normal turning by more than 90° between
/// neighbouring samples (a fold flips it), or against a neighbour's along
/// a side ([`super::seam_fold`]).
fn unfolded(mut fill: FanFill, faces: &[BSplineSurface], options: &FillOptions) -> Result<FanFill> {
    let count = fill.surface.patch_count();
    let what = if count > 1 {
        format!("the fan of {count} patches")
    } else {
        "the triangular patch".to_string()
    };
    let solve = fill.report.solve.triangular.as_ref();
    if let Some(turn) = solve.and_then(|t| t.normal_turn).filter(|t| t.is_fold()) {
        return Err(Error::Fill {
            why: format!(
                "{what} folds over{}: its normal turns by {:.1}° between neighbouring samples \
                 near barycentric ({:.3}, {:.3}, {:.3}){}",
                if count > 1 {
                    format!(" in patch {} (over side {} as cut)", turn.patch, turn.patch)
                } else {
                    String::new()
                },
                turn.angle.to_degrees(),
                turn.at[0],
                turn.at[1],
                turn.at[2],
                if count > 1 {
                    " (a fan can fold where the hole is far from convex, or not star-shaped \
                     around its centre, the mean of its corners)"
                } else {
                    ""
                }
            ),
        });
    }
    fill.measure_sides(faces, options);
    if let Some(e) = super::seam_fold(&what, &fill.report.sides) {
        return Err(e);
    }
    Ok(fill)
}

/// A side of the surface (its patch and barycentric point at the side's
/// parameter t: `at`) against the neighbour, at the parameters of
/// [`super::side_fit`].
fn patch_side_fit(
    surface: &TriSurface,
    at: &dyn Fn(f64) -> (usize, [f64; 3]),
    face: &BSplineSurface,
    exact: Option<Exact>,
    side: super::Side,
) -> SideFit {
    let patch = surface.patch(at(0.5).0);
    let ts = side_parameters();
    let da: Vec<_> = ts.iter().map(|&t| patch.tangents(at(t).1)).collect();
    let db = neighbour_tangents(face, exact, side, &ts);
    compare(
        &da,
        &db,
        side,
        !super::faces_like(face, side),
        exact.is_none(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bspline::KnotVector;

    /// A round hole's rows: with slopes that take α through zero inside a
    /// side, row 1 is refused (the fill would fold over the boundary);
    /// linear α positive at both ends, and gentle slopes, give rows whose
    /// derivative rows W/n at the ends are α·D + β·P′ as asked.
    #[test]
    fn a_rows_weight_through_zero_is_refused() {
        // A straight cubic side along x, D = (0, 1, 0) into the hole.
        let st = Strip {
            knots: KnotVector::bezier(3),
            pos: (0..4).map(|i| [i as f64 / 3.0, 0.0, 0.0]).collect(),
            der: vec![[0.0, 1.0, 0.0]; 4],
        };
        let n = 8;
        let row = elevate_points(&st.pos, n - 3);
        let ends = [(0.5, 0.0), (0.5, 0.0)];
        let linear = second_row(&st, &row, ends, None, n).unwrap();
        let gentle = second_row(&st, &row, ends, Some([(0.3, 0.0), (-0.3, 0.0)]), n).unwrap();
        for r in [&linear, &gentle] {
            // W(0)/n = α(0)·D/n = (0, 0.5/8, 0) at both ends.
            assert!(dist(r[0], add(row[0], [0.0, 0.5 / 8.0, 0.0])) < 1e-15);
            assert!(dist(r[n - 1], add(row[n - 1], [0.0, 0.5 / 8.0, 0.0])) < 1e-15);
        }
        // Slopes ±3: α's Bézier coefficients 0.5, 0.5 − 1, 0.5 − 1, 0.5.
        let e = second_row(&st, &row, ends, Some([(-3.0, 0.0), (3.0, 0.0)]), n)
            .unwrap_err()
            .to_string();
        assert!(e.contains("turns non-positive inside the side"), "{e}");
    }
}
