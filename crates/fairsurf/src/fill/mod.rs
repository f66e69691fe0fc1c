//! Filling a hole between neighbouring faces (Wu & Yang 2015, §5 and
//! Fig. 4: "a hole with a set of surrounding patches"; the two outer rings
//! of control points "are given in advance based on the border curves and
//! the tangent planes at the borders").
//!
//! The neighbours are B-spline surfaces (a Bézier patch is one without
//! interior knots). A hole is a closed loop of their free edges
//! ([`find_holes`]); a 4-sided hole whose sides are whole boundaries of
//! neighbours is filled by one B-spline patch ([`fill_hole`]):
//!
//! 1. **Boundary data, exactly.** Along each side, the neighbour's boundary
//!    curve P(t) and its cross-boundary derivative D(t) (turned to point
//!    into the hole) as B-splines of t ∈ [0, 1]; opposite sides brought to
//!    one degree and one knot vector by degree elevation and knot
//!    insertion, which do not change the curves.
//! 2. **Two rings.** The fill's outer ring is P; its second ring is
//!    P + (h/p)·α·D (h the first knot span, p the degree across), so the
//!    fill's cross derivative is α·D: G¹ — with the same tangent plane —
//!    along the whole side, exactly up to rounding. α > 0 is one number per
//!    side, chosen so the corners agree (the fill's derivative along one
//!    side at a corner is the cross derivative of the next); for neighbours
//!    cut from one C¹ B-spline this reproduces the missing piece's rings
//!    exactly. Where two sides prescribe the same control point (the 2 × 2
//!    corner blocks) and disagree — neighbours that are not C¹ at a
//!    corner, or incompatible twists — the position wins over the
//!    derivative, twists are averaged, and the disagreement is reported.
//! 3. **Fair inside.** The free points minimize the thin plate (Wu & Yang
//!    eq. 2) — guided, when no descent on W follows or when asked, by a
//!    normal field from the boundary data: the normals of the bicubically
//!    blended Hermite–Coons patch of P and α·D, sampled (Wu & Yang eq. 5)
//!    with weight λ per unit area (λ over the number of samples each) — see
//!    [`FillOptions::guide_with_descent`]. Then W is lowered: with the
//!    boundary's tangent planes fixed, ∫∫ K dA is fixed (Gauss–Bonnet), so
//!    W falls exactly as ∫∫ 4H² dA does, and ∫∫ |Δ_g R|² dA with the metric
//!    frozen is quadratic (linearized Willmore steps minimize it, on
//!    request). Its minimizer is not W's (the frozen metric drops W's
//!    variation through the metric), so L-BFGS on W itself does the
//!    lowering, its exact gradient by the chain rule through the integrand
//!    at the Gauss nodes, the frozen-metric operator as its first inverse
//!    Hessian.
//! 4. **Measured.** Every side's gap and normal angle on the returned
//!    surface against the neighbour, at 129 parameters clustered towards
//!    the corners (Chebyshev–Lobatto), and W = ∫∫ κ₁² + κ₂² dA of the fill
//!    ([`total_curvature`]).
//!
//! A hole of 3, 5 or more sides (sides of several Bézier pieces cut at
//! their knots, each piece a side) is
//! filled by a fan of triangular patches around a free centre
//! ([`fill_fan`]: G¹ to the neighbours exactly by the same two rows, G¹
//! between the fan's patches by Veltkamp & Wesselink's conditions), a
//! 3-sided one also by a single triangular patch ([`fill_triangle`]), and
//! then W is lowered along those conditions by the same L-BFGS;
//! [`HoleFill::new`] picks by the number of sides and, for three, by W.
//!
//! A rational neighbour (a cylinder, a NURBS face) enters through a
//! polynomial stand-in within a tolerance ([`RationalSurface::polynomial`],
//! [`FillOptions::rational_faces`]): the fill is G¹ to the stand-in
//! exactly and its sides there are measured against the rational surface
//! itself and reported as not exact ([`SideFit::exact`]). A face known
//! only along an edge (a trimmed face) enters the same way through a strip
//! along the edge ([`strip_stand_in`], [`FillOptions::edge_faces`]; its
//! side V0 the only boundary, [`find_holes_where`]), measured against the
//! edge and the face's normal there.
//!
//! The same rings and fairing make a transition surface between two
//! surfaces along one edge of each ([`blend`], Wu & Yang Fig. 5): two sides
//! from the surfaces, two made as cubic Hermite curves.

mod blend;
mod boundary;
mod coons;
mod fair;
mod fan;
mod fan_willmore;
mod holes;
mod measure;
mod strip;
#[cfg(test)]
mod tests;
mod willmore;

pub use blend::{blend, Blend, BlendOptions, BlendReport, Bulge, BulgeSearch};
pub use fan::{fill_fan, fill_triangle, FanFill, FanReport, FAN_DESCENT_REL, RICH_DEGREE};
pub use holes::{
    edge_point, find_holes, find_holes_where, find_holes_within, surface_param, tolerance, Hole,
    Side, RING_HEADING,
};
pub(crate) use measure::side_parameters as measure_side_parameters;
pub use measure::{
    largest_angle, side_fit, total_curvature, Exact, SideFit, TotalCurvature, SIDE_SAMPLES,
};

#[cfg(doc)]
use crate::bspline::strip_stand_in;
use crate::bspline::{
    BSplineProblem, BSplineSurface, FitTolerance, KnotVector, RationalSurface, TrueEdge,
};
use crate::energy::SampleGrid;
use crate::vec3::{add, cross, dist, dot, scale};
use crate::SolveReport;
use crate::{Error, Result, Vec3};
use boundary::*;
pub use boundary::{MAX_FILL_POINTS, RICH_SIDES};
use fair::*;
use std::ops::Range;
use std::sync::Arc;
use std::time::Instant;
use strip::{concat, unify, Strip, CONTINUES};

/// λ of the normal field that guides a fill's thin plate (by default only
/// when no descent on W follows: [`FillOptions::guiding_weight`]), per
/// unit parameter area. On the
/// test holes (a C¹ bi-quintic network, a bicubic B-spline sheet) W of the
/// fill varied by 2e-4 over λ ∈ [0, 1e5] and elevations 0–4; 100 gave the
/// lowest W on the B-spline sheet and stays below the cut-out piece's W on
/// both.
pub const DEFAULT_NORMAL_WEIGHT: f64 = 100.0;

/// The default budget of steps on W itself ([`FillOptions::descent_steps`]).
pub const DESCENT_STEPS: usize = 200;

/// How to fill.
#[derive(Clone, Debug, PartialEq)]
pub struct FillOptions {
    /// Degrees added to the fill over its sides' largest degree (in u and
    /// in v); more freedom for the same boundary data. A direction whose
    /// sides already have [`RICH_SIDES`] control points is not elevated
    /// (elevation would only raise its knots' multiplicities); nor are
    /// triangular patches whose least degree is [`RICH_DEGREE`] or more.
    pub elevate: usize,
    /// At least this many control points in u and in v (more elevation
    /// when the sides have fewer), at least 5: two rings on each side and
    /// one free row.
    pub min_points: usize,
    /// Membrane weight (Wu & Yang eq. 1); 0 by default.
    pub stretch: f64,
    /// Thin-plate weight (eq. 2); 1 by default.
    pub bend: f64,
    /// λ of the Hermite–Coons normal field per unit area; 0: the plain
    /// thin plate. It guides the solve of a 4-sided patch or a blend when
    /// no descent on W follows, or when [`FillOptions::guide_with_descent`]
    /// says so ([`FillOptions::guiding_weight`]).
    pub normal_weight: f64,
    /// Whether the normal field guides the solve also when the descent on
    /// W ([`FillOptions::descent_steps`]) follows. false (the default): the
    /// solve is then the plain thin plate, and the descent, which minimizes
    /// W itself, reaches the same W as from the guided solve (within 4e-9
    /// of W, below the descent's 1e-8 stopping rule, on the benchmark's six
    /// holes and the bundled STEP files' patches, session 42) in 1.5–2.2×
    /// less fill time: the normal field couples x, y and z (one system of
    /// 3n unknowns instead of three of n sharing one factor). Where the
    /// descent stops at its step budget before converging the starts
    /// differ (a torus octant, 200 steps: W 9.242 guided, 9.304 plain). true:
    /// guided either way (a λ the user gives: `--lambda`, the scene's
    /// `normal_weight`).
    pub guide_with_descent: bool,
    /// Normal samples per control point and direction (the grid has
    /// `samples · count` intervals each way).
    pub samples: usize,
    /// Linearized Willmore steps after the solve (see the module
    /// `willmore`): at most this many, each kept only if it lowers W,
    /// stopping once one lowers it by less than 1e-6 of itself; 0 (the
    /// default) for none: the descent that follows starts from the same
    /// frozen-metric operator and reached the same W without them (to 1e-8
    /// of W, its stopping rule, on the bundled and benchmark holes) in
    /// 30–40% less time.
    pub willmore_steps: usize,
    /// Then at most this many steps that lower W itself: L-BFGS on W whose
    /// first inverse Hessian is, for a 4-sided patch, the frozen-metric
    /// operator's (the module `willmore`), stopping after three steps in a
    /// row that each lower W by less than 1e-8 of itself, or after one when
    /// the next step's model promises less too; for triangular patches the
    /// thin plate's under the kept G¹ rows (the module `fan_willmore`),
    /// stopping at [`FAN_DESCENT_REL`] the same way. 0 for none.
    pub descent_steps: usize,
    /// The normal angle to the neighbours (radians) within which a fill
    /// counts as G¹ when [`HoleFill::new`] chooses between candidates
    /// (0.01° by default, [`FitTolerance`]'s): one within it is kept before
    /// a fairer one beyond it, and one 4-sided patch beyond it has a fan
    /// tried too.
    pub angle_tolerance: f64,
    /// Per face index, the rational surface that face is a polynomial
    /// stand-in for ([`RationalSurface::polynomial`]): the fill takes its
    /// boundary data from the stand-in and measures its sides against the
    /// rational surface (reported as not exact). Empty, or `None` for a
    /// face: the face is exact.
    pub rational_faces: Vec<Option<Arc<RationalSurface>>>,
    /// Per face index, the edge of a trimmed face that face is a strip
    /// stand-in along ([`strip_stand_in`]; the edge is the strip's side
    /// V0, its only boundary): the fill takes its boundary data from the
    /// strip and measures its sides against the edge (reported as not
    /// exact). Empty, or `None` for a face: not a strip.
    pub edge_faces: Vec<Option<TrueEdge>>,
}

impl FillOptions {
    /// λ the solve of a 4-sided patch or a blend uses: `normal_weight` when
    /// no descent on W follows or [`FillOptions::guide_with_descent`], else
    /// 0 (the plain thin plate; the descent minimizes W itself).
    pub fn guiding_weight(&self) -> f64 {
        if self.descent_steps == 0 || self.guide_with_descent {
            self.normal_weight
        } else {
            0.0
        }
    }

    /// A λ the user gives: the normal field of that weight guides the
    /// solve whether or not the descent on W follows.
    pub fn guide_with(&mut self, lambda: f64) {
        self.normal_weight = lambda;
        self.guide_with_descent = true;
    }

    /// The rational surface face `face` stands in for, if any.
    pub fn rational(&self, face: usize) -> Option<&RationalSurface> {
        self.rational_faces.get(face).and_then(|r| r.as_deref())
    }

    /// The trimmed face's edge face `face` is a strip along, if any.
    pub fn edge(&self, face: usize) -> Option<&TrueEdge> {
        self.edge_faces.get(face).and_then(Option::as_ref)
    }

    /// What face `face` stands in for, if anything: its sides are measured
    /// against that.
    pub fn exact(&self, face: usize) -> Option<Exact<'_>> {
        self.rational(face)
            .map(Exact::Rational)
            .or_else(|| self.edge(face).map(Exact::Edge))
    }
}

impl Default for FillOptions {
    fn default() -> Self {
        Self {
            elevate: 2,
            min_points: 8,
            stretch: 0.0,
            bend: 1.0,
            normal_weight: DEFAULT_NORMAL_WEIGHT,
            guide_with_descent: false,
            samples: 3,
            willmore_steps: 0,
            descent_steps: DESCENT_STEPS,
            angle_tolerance: FitTolerance::default().angle,
            rational_faces: Vec::new(),
            edge_faces: Vec::new(),
        }
    }
}

/// Where two sides prescribe the same control point of a corner block and
/// disagree (distances; 0 up to rounding for neighbours cut from one C¹
/// surface).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CornerMismatch {
    /// Between the two sides' corner points (the hole is not closed there).
    pub position: f64,
    /// Between a side's boundary point next to a corner and the next
    /// side's derivative row there (the neighbours are not C¹ at the
    /// corner; the fill is G¹ there only if this is 0).
    pub tangent: f64,
    /// Between the two sides' twist points (averaged in the fill).
    pub twist: f64,
}

/// What a fill reports.
#[derive(Clone, Debug, PartialEq)]
pub struct FillReport {
    /// The solve's own report (energy, its check, gradient, timings).
    pub solve: SolveReport,
    /// Per edge of the hole, in its order: gap and normal angle measured
    /// on the returned surface against the neighbour.
    pub sides: Vec<SideFit>,
    /// The corner blocks' disagreements.
    pub corners: CornerMismatch,
    /// α per side (the fill's cross derivative over the neighbour's).
    pub alpha: [f64; 4],
    /// W = ∫∫ κ₁² + κ₂² dA of the fill.
    pub curvature: TotalCurvature,
    /// W after the solve, after each linearized Willmore step tried (the
    /// last one tried is dropped when it did not lower W; none by default)
    /// and after each descent step — by the main rule, but for the descent's
    /// coarse phase: its steps before its last are measured by the coarse
    /// rule (`fill::willmore::Rule::coarse`, within about the error
    /// estimate of the main rule's W).
    pub willmore: Vec<f64>,
    /// λ used (0: plain thin plate).
    pub normal_weight: f64,
    /// Seconds: boundary data and rings, solve, measurements.
    pub seconds: FillSeconds,
    /// The candidates tried and not kept ([`HoleFill::new`]: a fan, where
    /// this patch missed its neighbours beyond the angle tolerance and the
    /// fan did not come closer).
    pub others: Vec<Candidate>,
}

/// A fill [`HoleFill::new`] tried for a hole and did not keep.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    /// `"patch"` (one tensor patch), `"fan"` or `"triangle"` (one
    /// triangular patch).
    pub kind: &'static str,
    /// Its largest normal angle to the neighbours (radians) and W (a fan's
    /// or a triangle's before the descent on W), or its refusal.
    pub outcome: std::result::Result<(f64, f64), String>,
    /// Seconds it took.
    pub seconds: f64,
}

impl Candidate {
    /// A candidate of `kind` with its measures ([`preferred`]'s) or its
    /// refusal, and the seconds it took.
    fn new(
        kind: &'static str,
        outcome: std::result::Result<(f64, f64), impl ToString>,
        seconds: f64,
    ) -> Self {
        Candidate {
            kind,
            outcome: outcome.map_err(|e| e.to_string()),
            seconds,
        }
    }
}

/// The seconds the candidates not kept took.
pub fn other_seconds(others: &[Candidate]) -> f64 {
    // From +0 (an empty `sum` of f64 is −0, printed "-0.0").
    others.iter().fold(0.0, |s, c| s + c.seconds)
}

/// Where a fill's time goes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FillSeconds {
    /// Boundary data, rings and the normal field.
    pub setup: f64,
    /// The solve, its check included.
    pub solve: f64,
    /// W, the Willmore steps and the side fits.
    pub measure: f64,
}

impl FillSeconds {
    /// Setup, solve and measurements together.
    pub fn total(&self) -> f64 {
        self.setup + self.solve + self.measure
    }

    /// [`Self::total`] and the candidates not kept ([`other_seconds`]):
    /// the time the hole took.
    pub fn total_with(&self, others: &[Candidate]) -> f64 {
        self.total() + other_seconds(others)
    }
}

/// A filled hole.
#[derive(Clone, Debug)]
pub struct Fill {
    /// The fill, parameters on [0, 1]²; its v = 0, u = 1, v = 1, u = 0
    /// boundaries are the hole's sides 0, 1, 2, 3 (sides 2 and 3
    /// traversed backwards; a side is one edge or several that continue
    /// each other, see `groups`), and its normal R_u × R_v agrees with side
    /// 0's neighbour.
    pub surface: BSplineSurface,
    /// The hole as filled (possibly traversed the other way than given, to
    /// agree with the neighbours' orientation, and starting at a corner).
    pub hole: Hole,
    /// The hole's edges making each of the fill's four sides (one each
    /// unless edges continue each other).
    pub groups: Vec<Range<usize>>,
    /// How good it is.
    pub report: FillReport,
}

/// Whether [`HoleFill::new`] fills `hole` with one patch: four sides, each
/// one edge or several that continue each other (else triangular patches,
/// whose sides must each be one polynomial piece).
pub fn is_four_sided(faces: &[BSplineSurface], hole: &Hole) -> bool {
    grouped(faces, hole).is_ok_and(|(_, groups)| groups.len() == 4)
}

/// A filled hole of any number of sides: one patch for four sides
/// ([`fill_hole`]), a fan of triangular patches otherwise ([`fill_fan`]).
#[derive(Clone, Debug)]
// Both variants are large and made once per hole: no boxing.
#[allow(clippy::large_enum_variant)]
pub enum HoleFill {
    /// A 4-sided hole's B-spline patch.
    Patch(Fill),
    /// An N-sided hole's fan.
    Fan(FanFill),
}

impl HoleFill {
    /// Fills `hole`: [`fill_hole`] for four sides (each one edge or several
    /// that continue each other; a fan too where that patch misses the
    /// neighbours beyond the angle tolerance or is refused, see
    /// `four_sided`); otherwise
    /// [`fill_fan`] (and for three
    /// sides [`fill_triangle`]). With descent steps (the default) each at
    /// the asked degree, their thin plates compared by their normal angle
    /// to the neighbours, then by W (`preferred`), and the one kept has its
    /// W lowered (after the descent more degree is more freedom: the
    /// pentagon of `examples/cad/fill_pentagon.json` came to W 1.03144 at
    /// degree 5, 1.03138 at 7 and 8; the one triangle's thin plate was 22%
    /// below the fan of three's, after the descent 3e-6 above it).
    /// The least degree is tried too when none at the asked degree
    /// solves. Without descent steps, at the asked degree and at the least
    /// (the thin plate in barycentric parameters is not W: more degree can
    /// raise W), keeping the one with the lowest W among those within the
    /// angle tolerance.
    pub fn new(faces: &[BSplineSurface], hole: &Hole, options: &FillOptions) -> Result<Self> {
        // A strip's sides other than V0 lie inside its trimmed face.
        if let Some((k, s)) =
            hole.sides.iter().enumerate().find(|(_, s)| {
                options.edge(s.face).is_some() && s.edge != crate::analysis::Edge::V0
            })
        {
            return Err(Error::Fill {
                why: format!(
                    "side {k} runs along side {:?} of face {}, a strip stand-in along a trimmed \
                     face's edge whose only boundary is its side V0 (find the holes with \
                     find_holes_where)",
                    s.edge, s.face
                ),
            });
        }
        if is_four_sided(faces, hole) {
            return Self::four_sided(faces, hole, options);
        }
        // Triangular patches: a fan, and for three sides one triangle; the
        // one `preferred` keeps, the others reported.
        let mut degrees = vec![options.clone()];
        if options.elevate > 0 && options.descent_steps == 0 {
            degrees.push(FillOptions {
                elevate: 0,
                ..options.clone()
            });
        }
        let mut tried: Vec<(&'static str, Result<FanFill>, f64)> = Vec::new();
        let mut k = 0;
        while k < degrees.len() {
            let o = &degrees[k];
            let timed = |kind, f: &dyn Fn() -> Result<FanFill>| {
                let t = Instant::now();
                let r = f();
                (kind, r, t.elapsed().as_secs_f64())
            };
            tried.push(timed("fan", &|| fan::fan_candidate(faces, hole, o)));
            if hole.sides.len() == 3 {
                tried.push(timed("triangle", &|| {
                    fan::triangle_candidate(faces, hole, o)
                }));
            }
            // With descent steps the least degree is a fallback only.
            if k == 0 && degrees.len() == 1 && o.elevate > 0 && tried.iter().all(|t| t.1.is_err()) {
                degrees.push(FillOptions {
                    elevate: 0,
                    ..options.clone()
                });
            }
            k += 1;
        }
        let measured = |f: &FanFill| measures(&f.report.sides, &f.report.curvature);
        let solved: Vec<(usize, (f64, f64))> = tried
            .iter()
            .enumerate()
            .filter_map(|(k, t)| t.1.as_ref().ok().map(|f| (k, measured(f))))
            .collect();
        let measures: Vec<(f64, f64)> = solved.iter().map(|s| s.1).collect();
        let Some(kept) = preferred(&measures, options.angle_tolerance).map(|k| solved[k].0) else {
            let first = tried.into_iter().find_map(|t| t.1.err());
            return Err(first.expect("a candidate"));
        };
        let mut others = Vec::new();
        let mut fill = None;
        for (k, (kind, r, seconds)) in tried.into_iter().enumerate() {
            match r {
                Ok(f) if k == kept => fill = Some(f),
                r => others.push(Candidate::new(kind, r.map(|f| measured(&f)), seconds)),
            }
        }
        let mut f = fill.expect("the kept candidate");
        f.report.others = others;
        Ok(Self::Fan(f.completed(options)))
    }

    /// A 4-sided hole: one patch ([`fill_hole`]); where that patch misses
    /// its neighbours beyond the angle tolerance (their cross directions
    /// at a corner not along the adjacent sides, which one patch cannot
    /// follow: its corner block takes one) or is refused, a fan too
    /// ([`fill_fan`], cut into five patches), the one kept by
    /// `preferred`. The patch's refusal is returned when both fail.
    fn four_sided(faces: &[BSplineSurface], hole: &Hole, options: &FillOptions) -> Result<Self> {
        let t = Instant::now();
        let patch = fill_hole(faces, hole, options);
        let patch_seconds = t.elapsed().as_secs_f64();
        if let Ok(p) = &patch {
            if largest_angle(&p.report.sides) <= options.angle_tolerance {
                return patch.map(Self::Patch);
            }
        }
        if let Err(e) = &patch {
            if !matches!(e, Error::Fill { .. }) {
                // Options or arithmetic, not the hole's shape.
                return patch.map(Self::Patch);
            }
        }
        let t = Instant::now();
        let fan = fan::fan_candidate(faces, hole, options);
        let fan_seconds = t.elapsed().as_secs_f64();
        let patch_measures = patch
            .as_ref()
            .map(|p| measures(&p.report.sides, &p.report.curvature));
        let fan_measures = fan
            .as_ref()
            .map(|f| measures(&f.report.sides, &f.report.curvature));
        let fan_kept = match (&patch_measures, &fan_measures) {
            (_, Err(_)) => false,
            (Err(_), Ok(_)) => true,
            (Ok(p), Ok(f)) => preferred(&[*p, *f], options.angle_tolerance) == Some(1),
        };
        if fan_kept {
            let mut fan = fan.expect("a fan");
            fan.report.others = vec![Candidate::new("patch", patch_measures, patch_seconds)];
            Ok(Self::Fan(fan.completed(options)))
        } else {
            let mut p = patch?;
            p.report.others = vec![Candidate::new("fan", fan_measures, fan_seconds)];
            Ok(Self::Patch(p))
        }
    }

    /// The fill as tensor-product B-spline surfaces (a fan's triangles
    /// with one side collapsed), for CAD and pictures.
    pub fn patches(&self) -> Vec<BSplineSurface> {
        match self {
            Self::Patch(f) => vec![f.surface.clone()],
            Self::Fan(f) => f.patches(),
        }
    }

    /// The hole as filled.
    pub fn hole(&self) -> &Hole {
        match self {
            Self::Patch(f) => &f.hole,
            Self::Fan(f) => &f.hole,
        }
    }

    /// Per side, gap and normal angle against the neighbour.
    pub fn sides(&self) -> &[SideFit] {
        match self {
            Self::Patch(f) => &f.report.sides,
            Self::Fan(f) => &f.report.sides,
        }
    }

    /// The disagreements at the hole's corners.
    pub fn corners(&self) -> CornerMismatch {
        match self {
            Self::Patch(f) => f.report.corners,
            Self::Fan(f) => f.report.corners,
        }
    }

    /// W of the fill.
    pub fn curvature(&self) -> TotalCurvature {
        match self {
            Self::Patch(f) => f.report.curvature,
            Self::Fan(f) => f.report.curvature,
        }
    }
}

/// What [`preferred`] compares a candidate by: its largest normal angle
/// to the neighbours and its W.
fn measures(sides: &[SideFit], w: &TotalCurvature) -> (f64, f64) {
    (largest_angle(sides), w.value)
}

/// Which candidate fill [`HoleFill::new`] keeps, given each one's largest
/// normal angle to the neighbours (radians) and its W: the lowest W among
/// those within `tolerance` ([`FillOptions::angle_tolerance`]), or, when
/// none is, among those as close as the closest. G¹ to the neighbours
/// comes first: at the rounded box's corners one triangular patch (its
/// corner twists incompatible, conditions dropped) misses the cylinders by
/// 0.19° where the fan of three is within 9e-4°, and after the descent on
/// W (which a candidate has not had yet) its W is 0.5% lower (3.1259
/// against 3.14158): lower because it is not tangent to them. A NaN angle
/// (no side measured) is never within; when every angle is NaN, W alone
/// decides; a W that is not finite counts as +∞. None when there is no
/// candidate.
fn preferred(candidates: &[(f64, f64)], tolerance: f64) -> Option<usize> {
    let closest = candidates.iter().map(|c| c.0).fold(f64::INFINITY, f64::min);
    let within = closest.max(tolerance);
    let w = |c: &(f64, f64)| if c.1.is_finite() { c.1 } else { f64::INFINITY };
    let lowest = |eligible: &dyn Fn(f64) -> bool| {
        candidates
            .iter()
            .enumerate()
            .filter(|(_, c)| eligible(c.0))
            .min_by(|a, b| w(a.1).total_cmp(&w(b.1)))
            .map(|(k, _)| k)
    };
    lowest(&|angle| angle <= within).or_else(|| lowest(&|_| true))
}

/// The fill's (u, v) at parameter t of its side k (t along the hole's
/// traversal).
pub fn fill_param(k: usize, t: f64) -> (f64, f64) {
    match k {
        0 => (t, 0.0),
        1 => (1.0, t),
        2 => (1.0 - t, 1.0),
        _ => (0.0, 1.0 - t),
    }
}

/// The refusal of a fill (`what`: "the patch", "the fan of 5 patches")
/// whose normal turns by more than 90° against a neighbour's along a side
/// (it folds onto the neighbour at the seam), naming the worst such side
/// by its face (the fill's own numbering of the sides starts where the
/// hole's turned); None when there is none. Samples where either normal
/// does not exist are not in the angle.
fn seam_fold(what: &str, sides: &[SideFit]) -> Option<Error> {
    let s = sides
        .iter()
        .filter(|s| s.angle > std::f64::consts::FRAC_PI_2)
        .max_by(|a, b| a.angle.total_cmp(&b.angle))?;
    Some(Error::Fill {
        why: format!(
            "{what} folds over along its side on face {}: its normal turns by {:.1}° against \
             the neighbour's",
            s.side.face,
            s.angle.to_degrees()
        ),
    })
}

/// Fills the 4-sided `hole` of `faces` (see the module documentation).
///
/// Errors ([`Error::Fill`]) name what does not fit: a hole with other than
/// four sides ([`fill_fan`] fills those), a side naming no face,
/// neighbours whose cross derivatives fold over at a corner, opposite sides
/// whose knots cannot be merged, a fill that folds over (its normal turning
/// by more than 90° between neighbouring samples, 2·degree + 2 intervals
/// per span, or against a neighbour's along a side); and the solve's own
/// refusals.
pub fn fill_hole(faces: &[BSplineSurface], hole: &Hole, options: &FillOptions) -> Result<Fill> {
    let t0 = Instant::now();
    let (mut hole, mut groups) = grouped(faces, hole)?;
    if groups.len() != 4 {
        return Err(Error::Fill {
            why: format!(
                "the hole has {} sides ({} edges); one patch fills a 4-sided hole (a fan of \
                 triangular patches fills others: fill_fan)",
                groups.len(),
                hole.sides.len()
            ),
        });
    }
    // Orientation: the fill's normal R_u × R_v at side 0 agrees with the
    // neighbour's; else traverse the loop the other way.
    let (mut s, mut breaks) = frame(faces, &hole, &groups)?;
    if !faces_like_side_0(faces, &hole, &s[0]) {
        (hole, groups) = grouped(faces, &hole.reversed())?;
        (s, breaks) = frame(faces, &hole, &groups)?;
    }
    let alpha = alphas(&s)?;
    let s: [Strip; 4] = std::array::from_fn(|k| s[k].scaled(alpha[k]));
    let s = unified(&s, options)?;
    let faired = fair(&s, [true; 4], options, t0)?;
    let t2 = Instant::now();
    let surface = faired.surface;
    // Folds, on a grid of 2·degree + 2 intervals per span as a fan's
    // patches are checked (a fold flips the normal between neighbours).
    let (p, q) = surface.degree();
    let turn = surface.largest_normal_turn_by(2 * p.max(q) + 2);
    if let Some(turn) = turn.filter(|t| t.is_fold()) {
        return Err(Error::Fill {
            why: format!(
                "the patch folds over: its normal turns by {:.1}° between neighbouring samples \
                 near (u, v) = ({:.3}, {:.3})",
                turn.angle.to_degrees(),
                turn.at.0,
                turn.at.1,
            ),
        });
    }
    let mut sides: Vec<SideFit> = Vec::with_capacity(hole.sides.len());
    for (k, g) in groups.iter().enumerate() {
        for (j, e) in g.clone().enumerate() {
            let side = hole.sides[e];
            let span = [breaks[k][j], breaks[k][j + 1]];
            sides.push(measure::piece_fit(
                &surface,
                k,
                span,
                &faces[side.face],
                options.exact(side.face),
                side,
                !faces_like(&faces[side.face], side),
            ));
        }
    }
    if let Some(e) = seam_fold("the patch", &sides) {
        return Err(e);
    }
    let measure = t2.elapsed().as_secs_f64();
    Ok(Fill {
        surface,
        hole,
        groups,
        report: FillReport {
            solve: faired.solve,
            sides,
            corners: faired.corners,
            alpha,
            curvature: faired.curvature,
            willmore: faired.willmore,
            normal_weight: options.guiding_weight(),
            seconds: FillSeconds {
                setup: faired.setup,
                solve: faired.solve_seconds,
                measure: faired.improve_seconds + measure,
            },
            others: Vec::new(),
        },
    })
}
