//! Constrained variational design of a triangular surface (Veltkamp &
//! Wesselink §6, eq. 32–33):
//!
//! ```text
//! minimize   E(P) = α·E_stretch + β·E_bend = ½ Σ_c P_cᵀ K P_c     (eq. 6–7, 25–27)
//! subject to F P = G                                             (eq. 31)
//! ```
//!
//! In order: curve constraints refine the mesh so that chains of patch
//! edges interpolate the curves (§4.2) and fix those edges' control points;
//! fixed control points (the user's and the curves') are eliminated; the
//! remaining rows — the user's interpolation constraints first, then the
//! default continuity conditions (§4.3) — are classified by sparse
//! elimination, so dependent rows are reduced and a continuity condition
//! that contradicts an interpolation constraint gives way (reported as
//! dropped); the independent rows and the energy form a KKT system solved
//! by regularized sparse LDLᵀ with iterative refinement.
//!
//! The report says how good the result is: energies, the stationarity
//! residual (the gradient of the Lagrangian), every constraint's violation,
//! what was reduced, dropped or found inconsistent, the largest normal
//! angle across interior edges, and timings.

use super::constraint::{Constraint, NamedConstraint};
use super::continuity::{max_edge_normal_angle, Continuity};
use super::energy::InternalEnergy;
use super::operator::Located;
use super::reduce::{classify, SparseRow, Verdict};
use super::refine::{check_point, embed_curve, DomainPoint, Refinement};
use super::surface::TriSurface;
use crate::analysis::{largest_tri_normal_turn, TriNormalTurn};
use crate::check::triangle::{TriEnergy, Verify};
use crate::check::Check;
use crate::constraint::{ConstraintOutcome, Row};
use crate::operator::newton::{add_quadratic, newton, FreeResiduals, NewtonReport};
use crate::operator::{Operator, OperatorOutcome, Residual};
use crate::solve::kkt::{same_terms, try_kkt, KktFactor, KktInfo, KktOutcome};
use crate::vec3::{norm, sub, Vec3};
use crate::{BezierCurve, Error, Result};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use std::time::Instant;

/// The relative pivot tolerances tried, in order, when classifying the
/// continuity rows (see step 5 of [`TriProblem::solve`]).
const ROW_TOLERANCES: [f64; 3] = [1e-9, 1e-6, 1e-3];

/// A curve the surface must pass through (§4.2): patch edges are made to
/// interpolate it ([`super::embed_curve`]).
#[derive(Clone, Debug, PartialEq)]
pub struct CurveConstraint {
    /// How reports call it.
    pub name: String,
    /// The curve, of degree at most the surface's.
    pub curve: BezierCurve,
    /// Where in the (original) domain it starts.
    pub from: DomainPoint,
    /// Where it ends.
    pub to: DomainPoint,
    /// The triangles it runs through, first to last (None: a shortest
    /// path). Indices of the surface as refined by the curves before it; a
    /// split triangle's index stays with its first child.
    pub through: Option<Vec<usize>>,
}

/// A triangular surface, its energy weights and its constraints.
#[derive(Clone, Debug)]
pub struct TriProblem {
    surface: TriSurface,
    energy: InternalEnergy,
    constraints: Vec<NamedConstraint>,
    curves: Vec<CurveConstraint>,
    continuity: Continuity,
    operators: Vec<Operator>,
}

/// The factored KKT matrix of a solve, kept to solve problems that differ
/// only in the right-hand side: the values of fixed points, point targets,
/// plane offsets, operator targets (see [`crate::FactorCache`]).
pub struct TriFactored {
    kkt: KktFactor,
    /// The continuity rows' pivot tolerance that classified them.
    tolerance: f64,
    /// Every constraint row's coefficients over the free coordinates (the
    /// kept rows' and the others'), user rows first.
    rows: Vec<Vec<(usize, f64)>>,
    /// How many of them are the user's.
    user_rows: usize,
}

impl TriFactored {
    /// About how many bytes it holds.
    pub fn bytes(&self) -> usize {
        self.kkt.bytes() + 16 * self.rows.iter().map(Vec::len).sum::<usize>()
    }

    /// Whether both are of the same KKT matrix: the same H and rows (the
    /// kept rows follow from the rows at the same tolerance).
    pub(crate) fn same_as(&self, other: &TriFactored) -> bool {
        self.tolerance == other.tolerance
            && self.made_for(
                &other.kkt.h,
                other.rows.iter().map(Vec::as_slice),
                other.user_rows,
            )
    }

    /// Whether H and every row's coefficients are those it was made for,
    /// value for value (H first: the cheap refusal).
    fn made_for<'r>(
        &self,
        h: &SparseColMat<usize, f64>,
        rows: impl ExactSizeIterator<Item = &'r [(usize, f64)]>,
        user_rows: usize,
    ) -> bool {
        self.kkt.h_is(h) && self.rows_match(rows, user_rows)
    }

    /// Whether every row's coefficients are those it was made for.
    fn rows_match<'r>(
        &self,
        rows: impl ExactSizeIterator<Item = &'r [(usize, f64)]>,
        user_rows: usize,
    ) -> bool {
        user_rows == self.user_rows
            && rows.len() == self.rows.len()
            && rows.zip(&self.rows).all(|(a, b)| same_terms(a, b))
    }
}

impl std::fmt::Debug for TriFactored {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TriFactored")
            .field("bytes", &self.bytes())
            .field("tolerance", &self.tolerance)
            .finish_non_exhaustive()
    }
}

/// Which factorization solved a problem.
pub(crate) enum Factor {
    /// None (nothing was free).
    None,
    /// The kept one at this index.
    Reused(usize),
    /// A new one.
    New(Box<TriFactored>),
}

/// A constraint row left out of the solve.
#[derive(Clone, Debug, PartialEq)]
pub struct DroppedRow {
    /// The row's name (constraint, equation, coordinate).
    pub name: String,
    /// How far the constraints kept force it off (its reduced right-hand
    /// side over its largest coefficient).
    pub residual: f64,
}

/// How good a solve is.
#[derive(Clone, Debug, PartialEq)]
pub struct TriReport {
    /// α·E_stretch of the result (½∫ convention, equilateral domain of side 1).
    pub stretch: f64,
    /// β·E_bend of the result.
    pub bend: f64,
    /// The external operators' energy terms (Veltkamp & Wesselink §5).
    pub external: f64,
    /// stretch + bend + external: the total energy (eq. 1, 30).
    pub total: f64,
    /// The independent check of the written net: energies recomputed in
    /// double-double (the figures above are those), how far above the
    /// minimum over the constraints it lies ([`crate::Check`]). `None` when
    /// nothing was free.
    pub check: Option<Check>,
    /// Each operator's energy and how far its target is met.
    pub operators: Vec<OperatorOutcome>,
    /// The Newton iterations for repellors (eq. 30), if any.
    pub newton: Option<NewtonReport>,
    /// Patches, mesh vertices and global control points of the result
    /// (curves refine the mesh).
    pub patches: usize,
    /// Mesh vertices.
    pub vertices: usize,
    /// Global control points.
    pub points: usize,
    /// Free coordinates solved for.
    pub unknowns: usize,
    /// Coordinates fixed (user fixed points and curve edges).
    pub fixed_coordinates: usize,
    /// Constraint rows considered (user and continuity).
    pub rows: usize,
    /// Rows kept (independent).
    pub independent_rows: usize,
    /// Rows implied by earlier ones (reduced).
    pub dependent_rows: usize,
    /// Continuity rows that contradicted the interpolation constraints and
    /// gave way.
    pub dropped: Vec<DroppedRow>,
    /// User rows that contradict earlier user constraints; the surface
    /// cannot meet them (their violations say by how much).
    pub inconsistent: Vec<DroppedRow>,
    /// Each user constraint's violation on the result.
    pub constraints: Vec<ConstraintOutcome>,
    /// The largest violation among the user constraints (0 if none).
    pub max_violation: f64,
    /// The largest |row residual| of the kept continuity rows.
    pub continuity_residual: f64,
    /// The largest |row residual| of the continuity rows left out (reduced
    /// as dependent or dropped) on the result: about 1e-15 when they are
    /// truly implied, larger when they were only nearly so (a loose
    /// [`Self::row_tolerance`]) or gave way.
    pub unenforced_residual: f64,
    /// The relative pivot tolerance that classified the continuity rows:
    /// 1e-9, or 1e-6 / 1e-3 when the stricter one left the KKT system
    /// singular to working precision (nearly dependent conditions).
    pub row_tolerance: f64,
    /// The largest angle (radians) between the two patches' normals along
    /// any interior edge (65 samples per edge), with the edge's vertices.
    pub max_edge_normal_angle: Option<(f64, [usize; 2])>,
    /// The largest turn of the unit normal between neighbouring samples
    /// inside a patch (a barycentric grid of step 1/(2n + 2) for degree n);
    /// above 90° the surface folds there.
    pub normal_turn: Option<TriNormalTurn>,
    /// ‖H x + b + Fᵀλ‖∞ over the free coordinates: the gradient of the
    /// Lagrangian at the solution.
    pub gradient_norm: f64,
    /// The same over ‖H‖∞‖x‖∞ + ‖b‖∞ (scale-free).
    pub relative_gradient: f64,
    /// The KKT solve.
    pub kkt: Option<KktInfo>,
    /// Whether the KKT factorization of an earlier solve was reused (only
    /// the right-hand side was new: fixed values, targets; see
    /// [`crate::FactorCache::solve_triangular`]).
    pub reused: bool,
    /// Seconds spent refining for curves, assembling, classifying rows,
    /// solving the KKT system, and in total.
    pub seconds: TriTimings,
}

/// Wall-clock seconds per phase.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriTimings {
    /// Mesh refinement for curve constraints.
    pub refine: f64,
    /// Energy matrix and constraint rows.
    pub assemble: f64,
    /// Row classification (dependent / inconsistent).
    pub classify: f64,
    /// KKT factorization and refinement.
    pub solve: f64,
    /// Everything, measurement included.
    pub total: f64,
}

/// The solved surface and its report.
#[derive(Clone, Debug)]
pub struct TriSolution {
    /// The result (refined by curve constraints, if any).
    pub surface: TriSurface,
    /// Where its triangles lie in the original domain.
    pub origin: Vec<(usize, [[f64; 3]; 3])>,
    /// The global control points of the result that were held fixed
    /// (fixed constraints, the boundary if fixed, the curves' chain edges).
    pub fixed: Vec<usize>,
    /// How good it is.
    pub report: TriReport,
}

impl TriProblem {
    /// The surface (its points are the initial net), the energy weights, no
    /// constraints and the default continuity ([`Continuity::default`]).
    pub fn new(surface: TriSurface, energy: InternalEnergy) -> Self {
        Self {
            surface,
            energy,
            constraints: Vec::new(),
            curves: Vec::new(),
            continuity: Continuity::default(),
            operators: Vec::new(),
        }
    }

    /// Adds a constraint.
    pub fn with_constraint(mut self, name: impl Into<String>, constraint: Constraint) -> Self {
        self.constraints.push(NamedConstraint {
            name: name.into(),
            constraint,
        });
        self
    }

    /// Fixes every boundary control point at its current value.
    pub fn with_fixed_boundary(mut self) -> Self {
        for g in self.surface.boundary_points() {
            let value = self.surface.points()[g];
            self.constraints.push(NamedConstraint {
                name: format!("boundary point {g}"),
                constraint: Constraint::Fixed { point: g, value },
            });
        }
        self
    }

    /// Adds a curve constraint.
    pub fn with_curve(mut self, curve: CurveConstraint) -> Self {
        self.curves.push(curve);
        self
    }

    /// Sets the continuity conditions.
    pub fn with_continuity(mut self, continuity: Continuity) -> Self {
        self.continuity = continuity;
        self
    }

    /// Adds an external energy operator (§5).
    pub fn with_operator(mut self, operator: Operator) -> Self {
        self.operators.push(operator);
        self
    }

    /// The surface as given.
    pub fn surface(&self) -> &TriSurface {
        &self.surface
    }

    /// Solves; errors name the bad constraint or say why the system has no
    /// unique solution.
    pub fn solve(&self) -> Result<TriSolution> {
        Ok(self.solve_kept(&[])?.0)
    }

    /// Solves with the first of the factorizations `kept` (of earlier
    /// solves) that is of this problem's KKT matrix (see
    /// [`crate::FactorCache`]); returns the solution and which was used, or
    /// the new factorization.
    pub(crate) fn solve_kept(
        &self,
        kept_factors: &[&TriFactored],
    ) -> Result<(TriSolution, Factor)> {
        let start = Instant::now();
        self.energy.validate()?;
        for c in &self.constraints {
            c.constraint.validate(&self.surface, &c.name)?;
        }
        for op in &self.operators {
            op.validate(&self.surface)?;
        }
        let mut seconds = TriTimings::default();

        // 1. Curves refine the mesh.
        let (refinement, chains) = self.embed_curves()?;
        let mut surface = refinement.surface.clone();
        crate::budget::reserve(
            &format!(
                "the system of {} degree-{} patches",
                surface.patch_count(),
                surface.degree()
            ),
            memory_estimate(&surface),
        )?;
        crate::budget::checkpoint()?;
        let placed: Vec<Located> = self
            .operators
            .iter()
            .map(|op| op.locate(&self.surface, &refinement))
            .collect::<Result<_>>()?;
        seconds.refine = start.elapsed().as_secs_f64();

        // 2. Known coordinates: curve edges, then the user's fixed points.
        let t = Instant::now();
        let coords = 3 * surface.point_count();
        let mut known: Vec<Option<f64>> = vec![None; coords];
        let mut inconsistent = Vec::new();
        for (name, chain) in &chains {
            for (g, p) in chain_points(&surface, chain, name)? {
                for c in 0..3 {
                    known[3 * g + c] = Some(p[c]);
                }
            }
        }
        let mut located: Vec<(NamedConstraint, Constraint)> = Vec::new();
        for nc in &self.constraints {
            let c = match nc.constraint {
                Constraint::Fixed { point, value } => {
                    let g = map_global(&self.surface, &refinement, point).ok_or_else(|| {
                        Error::Mismatch {
                            what: format!("{}: control point {point}", nc.name),
                            expected:
                                "a control point that survives the curve constraints' refinement"
                                    .into(),
                            got: "a point of a patch split by a curve constraint".into(),
                        }
                    })?;
                    for c in 0..3 {
                        match known[3 * g + c] {
                            Some(v) if (v - value[c]).abs() > 1e-12 * (1.0 + v.abs()) => {
                                inconsistent.push(DroppedRow {
                                    name: format!("{}, {}", nc.name, ["x", "y", "z"][c]),
                                    residual: (v - value[c]).abs(),
                                })
                            }
                            Some(_) => {}
                            None => known[3 * g + c] = Some(value[c]),
                        }
                    }
                    Constraint::Fixed { point: g, value }
                }
                ref other => {
                    let at = other.at().expect("not fixed");
                    let moved = refinement.locate(at).expect("validated domain point");
                    other.moved_to(moved)
                }
            };
            located.push((nc.clone(), c));
        }
        let mut points = surface.points().to_vec();
        for (g, p) in points.iter_mut().enumerate() {
            for c in 0..3 {
                if let Some(v) = known[3 * g + c] {
                    p[c] = v;
                }
            }
        }
        surface.set_points(points)?;

        crate::budget::checkpoint()?;
        // 3. Rows: the user's, then continuity.
        let mut rows: Vec<Row> = Vec::new();
        for (nc, c) in &located {
            rows.extend(c.rows(&surface, &nc.name));
        }
        let user_rows = rows.len();
        rows.extend(self.continuity.rows(&surface)?);

        crate::budget::checkpoint()?;
        // 4. Eliminate known coordinates.
        let mut free_index = vec![usize::MAX; coords];
        let mut free = Vec::new();
        for (i, k) in known.iter().enumerate() {
            if k.is_none() {
                free_index[i] = free.len();
                free.push(i);
            }
        }
        let x0: Vec<f64> = surface.points().iter().flat_map(|p| *p).collect();
        let reduced: Vec<(Vec<(usize, f64)>, f64)> = rows
            .iter()
            .map(|r| {
                let mut rhs = r.rhs;
                let mut terms = Vec::with_capacity(r.terms.len());
                for &(i, a) in &r.terms {
                    match known[i] {
                        Some(v) => rhs -= a * v,
                        None => terms.push((free_index[i], a)),
                    }
                }
                (terms, rhs)
            })
            .collect();
        let size = bounding_size(surface.points());
        let (h, mut b) = self.hessian(&surface, &known, &free_index, free.len())?;
        // Operators: attractors and directors join the quadratic energy,
        // repellors wait for the Newton iterations.
        let residuals: Vec<Vec<Residual>> = self
            .operators
            .iter()
            .zip(&placed)
            .map(|(op, at)| op.residuals(at, &surface))
            .collect();
        let mut quadratic = Vec::new();
        let mut repellors = Vec::new();
        for (op, res) in self.operators.iter().zip(&residuals) {
            let f = FreeResiduals::new(op.strength, res, &known, &free_index);
            if op.repel {
                repellors.push(f);
            } else {
                quadratic.push(f);
            }
        }
        let h = add_quadratic(h, &mut b, &quadratic)?;
        seconds.assemble = t.elapsed().as_secs_f64();
        let pinning = rows.iter().map(|r| &r.terms[..]).chain(
            self.operators
                .iter()
                .zip(&residuals)
                .filter(|(op, _)| !op.repel)
                .flat_map(|(_, res)| res.iter().map(|r| &r.terms[..])),
        );
        if let Some(d) = free_translation(&known, pinning) {
            return Err(Error::Singular {
                unknowns: free.len(),
                condition: f64::INFINITY,
                hint: format!(
                    "nothing holds the surface in place along ({:.3}, {:.3}, {:.3}): the internal \
                     energy does not change when every point moves that way; fix the boundary \
                     (\"fix_boundary\": true), fix or constrain a point, or add an attractor",
                    d[0], d[1], d[2]
                ),
            });
        }

        crate::budget::checkpoint()?;
        // 5–6. Classify rows and solve. Continuity conditions near
        // dependence (F nearly rank-deficient) make the KKT system singular
        // to working precision although every kept pivot is far from 0: on
        // a failed or inaccurate solve the continuity rows are classified
        // again with a looser tolerance, so nearly dependent ones are
        // reduced or dropped instead (measured: exact cubic G1 on 1,000
        // patches needs 1e-3). The user's rows keep the strict one.
        let classify_rows = |tol: f64, seconds: &mut TriTimings| {
            let t = Instant::now();
            let sparse: Vec<SparseRow<'_>> = reduced
                .iter()
                .enumerate()
                .map(|(r, (terms, rhs))| SparseRow {
                    terms,
                    rhs: *rhs,
                    tol: if r < user_rows {
                        ROW_TOLERANCES[0]
                    } else {
                        tol
                    },
                })
                .collect();
            let verdicts = classify(&sparse, free.len(), 1e-9 * size);
            seconds.classify += t.elapsed().as_secs_f64();
            let kept: Vec<usize> = (0..rows.len())
                .filter(|&r| verdicts[r] == Verdict::Independent)
                .collect();
            (verdicts, kept)
        };
        let system = |kept: &[usize]| {
            let f: Vec<&[(usize, f64)]> = kept.iter().map(|&r| reduced[r].0.as_slice()).collect();
            let g: Vec<f64> = kept.iter().map(|&r| reduced[r].1).collect();
            (f, g)
        };
        // A kept factorization serves when H and every row's coefficients
        // (the kept rows' and the others') are, value for value, those it
        // was made for: the rows then classify as they did at every
        // tolerance (independence depends on the coefficients only), so the
        // fresh solve would come to the same tolerance and factorization.
        // The right-hand side is new, and with it which rows are dependent
        // or inconsistent.
        let mut factor = Factor::None;
        // (tolerance, (verdicts, kept rows)) per tolerance classified.
        type Classified = (f64, (Vec<Verdict>, Vec<usize>));
        let mut classified: Vec<Classified> = Vec::new();
        let mut classified_at = |tol: f64, seconds: &mut TriTimings| {
            if let Some((_, c)) = classified.iter().find(|(t, _)| *t == tol) {
                return c.clone();
            }
            let c = classify_rows(tol, seconds);
            classified.push((tol, c.clone()));
            c
        };
        let mut reuse = None;
        for (which, k) in kept_factors.iter().enumerate() {
            if free.is_empty()
                || !k.made_for(&h, reduced.iter().map(|(t, _)| t.as_slice()), user_rows)
            {
                continue;
            }
            let (verdicts, kept_rows) = classified_at(k.tolerance, &mut seconds);
            let (f, g) = system(&kept_rows);
            if !k.kkt.is_for(&h, &f) {
                continue;
            }
            let t = Instant::now();
            let sol = k.kkt.solve(&b, &g).ok();
            seconds.solve += t.elapsed().as_secs_f64();
            if let Some(sol) = sol.filter(|s| s.info.relative_residual <= 1e-12) {
                factor = Factor::Reused(which);
                reuse = Some((verdicts, k.tolerance, Some((kept_rows, sol))));
                break;
            }
        }
        let reused = reuse.is_some();
        // A new factorization, and whether to keep it for later solves.
        let mut fresh: Option<(Box<KktFactor>, bool)> = None;
        // A kept one of the same pattern and rows (a weight changed): its
        // symbolic analysis serves, only the numbers are factored again.
        for k in kept_factors {
            if reuse.is_some()
                || free.is_empty()
                || !k.rows_match(reduced.iter().map(|(t, _)| t.as_slice()), user_rows)
                || !k.kkt.same_pattern(&h)
            {
                continue;
            }
            let (verdicts, kept_rows) = classified_at(k.tolerance, &mut seconds);
            let (f, g) = system(&kept_rows);
            if !k.kkt.rows_are(&f) {
                continue;
            }
            let t = Instant::now();
            let solved = k
                .kkt
                .refactored(&h)
                .and_then(|kkt| Some((kkt.solve(&b, &g).ok()?, kkt)));
            seconds.solve += t.elapsed().as_secs_f64();
            if let Some((sol, kkt)) = solved.filter(|(s, _)| s.info.relative_residual <= 1e-12) {
                fresh = Some((Box::new(kkt), true));
                reuse = Some((verdicts, k.tolerance, Some((kept_rows, sol))));
            }
        }
        let (verdicts, row_tolerance, sol) = match reuse {
            Some(done) => done,
            None => {
                let mut attempt = 0;
                // Whether every looser attempt so far failed for want of a
                // factorization (not for this right-hand side's sake).
                let mut matrix_bound = true;
                loop {
                    let tol = ROW_TOLERANCES[attempt];
                    let (verdicts, kept) = classified_at(tol, &mut seconds);
                    if free.is_empty() {
                        break (verdicts, tol, None);
                    }
                    let t = Instant::now();
                    let (f, g) = system(&kept);
                    let result = try_kkt(&h, &f, &b, &g);
                    seconds.solve += t.elapsed().as_secs_f64();
                    let last = attempt + 1 == ROW_TOLERANCES.len() || kept.len() <= user_rows;
                    match result {
                        KktOutcome::Solved {
                            factor: kkt,
                            solution,
                            first_choice,
                        } if last || solution.info.relative_residual <= 1e-12 => {
                            // Kept only when a fresh solve of another
                            // right-hand side would come to it too.
                            let keep = first_choice
                                && matrix_bound
                                && solution.info.relative_residual <= 1e-12;
                            fresh = Some((kkt, keep));
                            break (verdicts, tol, Some((kept, solution)));
                        }
                        KktOutcome::Unfactorable(e) | KktOutcome::Failed(e) if last => {
                            return Err(e)
                        }
                        KktOutcome::Unfactorable(_) => attempt += 1,
                        _ => {
                            matrix_bound = false;
                            attempt += 1;
                        }
                    }
                }
            }
        };
        let mut dropped = Vec::new();
        let mut dependent = 0;
        for (r, v) in verdicts.iter().enumerate() {
            match *v {
                Verdict::Independent => {}
                Verdict::Dependent => dependent += 1,
                Verdict::Inconsistent { residual } => {
                    let d = DroppedRow {
                        name: rows[r].name.clone(),
                        residual,
                    };
                    if r < user_rows {
                        inconsistent.push(d);
                    } else {
                        dropped.push(d);
                    }
                }
            }
        }

        let t = Instant::now();
        let mut x = x0.clone();
        let mut kkt = None;
        let mut kept = Vec::new();
        let mut newton_report = None;
        let (mut gradient_norm, mut relative_gradient) = (0.0, 0.0);
        let mut verified = None;
        if let Some((kept_rows, sol)) = sol {
            kept = kept_rows;
            let f: Vec<&[(usize, f64)]> = kept.iter().map(|&r| reduced[r].0.as_slice()).collect();
            let (mut xf, lambda) = (sol.x, sol.lambda);
            kkt = Some(sol.info);
            if !repellors.is_empty() {
                let (x_newton, report) = newton(&h, &b, &f, &repellors, xf)?;
                xf = x_newton;
                newton_report = Some(report);
            }
            seconds.solve += t.elapsed().as_secs_f64();
            let t = Instant::now();
            let factor = match (&factor, &fresh) {
                (Factor::Reused(which), _) => &kept_factors[*which].kkt,
                (_, Some((f, _))) => f,
                _ => unreachable!("a solution comes with its factorization"),
            };
            let data = known
                .iter()
                .flatten()
                .chain(rows.iter().map(|r| &r.rhs))
                .chain(residuals.iter().flatten().map(|r| &r.target))
                .fold(0.0f64, |m, v| m.max(v.abs()));
            let max_diagonal = (0..free.len())
                .map(|j| {
                    h.row_idx_of_col(j)
                        .zip(h.val_of_col(j))
                        .find(|(i, _)| *i == j)
                        .map_or(0.0, |(_, v)| *v)
                })
                .fold(0.0, f64::max);
            let v = Verify {
                energy: TriEnergy::new(
                    &self.energy,
                    surface.degree(),
                    self.operators
                        .iter()
                        .zip(&residuals)
                        .map(|(op, r)| (op.strength, op.repel, &r[..]))
                        .collect(),
                ),
                free: &free,
                factor,
                rows: &f,
                rhs: &kept.iter().map(|&r| reduced[r].1).collect::<Vec<_>>(),
                rounding: max_diagonal * free.len() as f64 * data * data,
                correct: repellors.is_empty(),
            };
            let checked = v.run(&surface, xf, lambda)?;
            let (xf, lambda) = (&checked.xf, &checked.lambda);
            for (k, &i) in free.iter().enumerate() {
                x[i] = xf[k];
            }
            (gradient_norm, relative_gradient) = match &newton_report {
                Some(r) if checked.corrections == 0 => (r.gradient_norm, r.relative_gradient),
                _ => lagrangian_gradient(&h, &b, &f, xf, lambda),
            };
            verified = Some((checked, t));
        }
        if verified.is_none() {
            seconds.solve += t.elapsed().as_secs_f64();
        }
        let pts: Vec<Vec3> = x.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        surface.set_points(pts)?;

        // 7. Measure.
        let continuity_residual = kept
            .iter()
            .filter(|&&r| r >= user_rows)
            .map(|&r| rows[r].residual(&x).abs())
            .fold(0.0f64, f64::max);
        let unenforced_residual = (user_rows..rows.len())
            .filter(|&r| verdicts[r] != Verdict::Independent)
            .map(|r| rows[r].residual(&x).abs())
            .fold(0.0f64, f64::max);
        // The written net must meet the user's rows (but those found
        // inconsistent) as well as it is a minimum: a miss above the
        // check's tolerance of the data's size (fixed coordinates, the
        // rows' right-hand sides) is refused, not reported as met.
        let mut is_free = vec![false; coords];
        for &i in &free {
            is_free[i] = true;
        }
        let data = (0..coords)
            .filter(|&i| !is_free[i])
            .map(|i| x[i])
            .chain(rows[..user_rows].iter().map(|r| r.rhs))
            .chain(self.operators.iter().map(|o| o.target.size()))
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        let unmet = (0..user_rows)
            .filter(|&r| !matches!(verdicts[r], Verdict::Inconsistent { .. }))
            .map(|r| (r, rows[r].residual(&x).abs() / data))
            .filter(|&(_, miss)| miss.is_nan() || miss > crate::check::TOLERANCE)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((r, miss)) = unmet {
            return Err(Error::Unmet {
                degree: surface.degree().to_string(),
                row: rows[r].name.clone(),
                miss,
                tolerance: crate::check::TOLERANCE,
            });
        }
        let mut outcomes: Vec<ConstraintOutcome> = located
            .iter()
            .map(|(nc, c)| ConstraintOutcome {
                name: nc.name.clone(),
                kind: c.kind(),
                violation: c.violation(&surface),
            })
            .collect();
        for (curve, (name, chain)) in self.curves.iter().zip(&chains) {
            outcomes.push(ConstraintOutcome {
                name: name.clone(),
                kind: "curve",
                violation: curve_distance(&surface, chain, &curve.curve),
            });
        }
        let max_violation = outcomes
            .iter()
            .map(|o| {
                if o.violation.is_nan() {
                    f64::INFINITY
                } else {
                    o.violation
                }
            })
            .fold(0.0f64, f64::max);
        let operators: Vec<OperatorOutcome> = self
            .operators
            .iter()
            .zip(placed.iter().zip(&residuals))
            .map(|(op, (at, res))| op.outcome(at, res, &surface, &x))
            .collect();
        let mut external = operators.iter().map(|o| o.energy).sum::<f64>();
        let mut stretch = InternalEnergy::new(self.energy.stretch, 0.0).surface_value(&surface)?;
        let mut bend = InternalEnergy::new(0.0, self.energy.bend).surface_value(&surface)?;
        let mut total = stretch + bend + external;
        let check = match verified {
            None => None,
            Some((v, t)) => {
                // The closed forms in double precision give way to the
                // recomputed values.
                let closed_form = total;
                (stretch, bend, external) = (
                    v.at.stretch.to_f64(),
                    v.at.bend.to_f64(),
                    v.at.external.to_f64(),
                );
                total = v.at.total.to_f64();
                let check = Check {
                    energy: total,
                    energy_error: (closed_form - total).abs() / v.scale,
                    excess: v.excess / v.scale,
                    scale: v.scale,
                    corrections: v.corrections,
                    tolerance: crate::check::TOLERANCE,
                    seconds: t.elapsed().as_secs_f64(),
                };
                if !check.passed() {
                    return Err(Error::Unverified {
                        degree: surface.degree().to_string(),
                        checked: total,
                        excess: check.excess,
                        tolerance: check.tolerance,
                        hint: "A triangular net of this degree cannot hold this minimizer to that \
                               accuracy: use a lower degree, with more triangles for more freedom."
                            .into(),
                    });
                }
                Some(check)
            }
        };
        if let Some((kkt, true)) = fresh {
            factor = Factor::New(Box::new(TriFactored {
                kkt: *kkt,
                tolerance: row_tolerance,
                rows: reduced.iter().map(|(terms, _)| terms.clone()).collect(),
                user_rows,
            }));
        }
        let report = TriReport {
            stretch,
            bend,
            external,
            total,
            check,
            operators,
            newton: newton_report,
            patches: surface.patch_count(),
            vertices: surface.vertex_count(),
            points: surface.point_count(),
            unknowns: free.len(),
            fixed_coordinates: coords - free.len(),
            rows: rows.len(),
            independent_rows: kept.len(),
            dependent_rows: dependent,
            dropped,
            inconsistent,
            constraints: outcomes,
            max_violation,
            continuity_residual,
            unenforced_residual,
            row_tolerance,
            max_edge_normal_angle: max_edge_normal_angle(&surface, 65),
            normal_turn: largest_tri_normal_turn(&surface, 2 * surface.degree() + 2),
            gradient_norm,
            relative_gradient,
            kkt,
            reused,
            seconds: TriTimings {
                total: start.elapsed().as_secs_f64(),
                ..seconds
            },
        };
        let fixed = (0..surface.point_count())
            .filter(|g| (0..3).all(|c| known[3 * g + c].is_some()))
            .collect();
        let solution = TriSolution {
            surface,
            origin: refinement.origin,
            fixed,
            report,
        };
        Ok((solution, factor))
    }

    /// Embeds the curves one after another; returns the composed
    /// refinement and each curve's chain of vertices.
    fn embed_curves(&self) -> Result<(Refinement, Vec<Chain>)> {
        let mut r = Refinement::identity(&self.surface);
        let mut chains = Vec::new();
        for c in &self.curves {
            let locate = |p: DomainPoint, which: &str| {
                check_point(&self.surface, p, &format!("{}: `{which}` point", c.name))?;
                Ok::<_, Error>(r.locate(p).expect("checked"))
            };
            let (from, to) = (locate(c.from, "from")?, locate(c.to, "to")?);
            let path = embed_curve(&r.surface, &c.curve, from, to, c.through.as_deref())
                .map_err(|e| named(e, &c.name))?;
            r = compose(&r, path.refinement);
            chains.push((c.name.clone(), path.vertices));
        }
        Ok((r, chains))
    }

    /// H over the free coordinates (both triangles) and b = H_fk x_k.
    /// H is written column by column: the free coordinates 3i + c are
    /// numbered in increasing order and K's row indices are sorted, so each
    /// column's rows come sorted without a triplet sort.
    fn hessian(
        &self,
        surface: &TriSurface,
        known: &[Option<f64>],
        free_index: &[usize],
        free: usize,
    ) -> Result<(SparseColMat<usize, f64>, Vec<f64>)> {
        let k = self.energy.surface_matrix(surface)?;
        let mut b = vec![0.0; free];
        for j in 0..k.ncols() {
            for (i, v) in k.row_idx_of_col(j).zip(k.val_of_col(j)) {
                for c in 0..3 {
                    let (ci, cj) = (3 * i + c, 3 * j + c);
                    if let (None, Some(xj)) = (known[ci], known[cj]) {
                        b[free_index[ci]] += v * xj;
                    }
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(free + 1);
        let mut rows = Vec::with_capacity(3 * k.compute_nnz());
        let mut values = Vec::with_capacity(3 * k.compute_nnz());
        col_ptr.push(0);
        for cj in (0..known.len()).filter(|&cj| known[cj].is_none()) {
            let (j, c) = (cj / 3, cj % 3);
            for (i, v) in k.row_idx_of_col(j).zip(k.val_of_col(j)) {
                let ci = 3 * i + c;
                if known[ci].is_none() {
                    rows.push(free_index[ci]);
                    values.push(*v);
                }
            }
            col_ptr.push(rows.len());
        }
        let symbolic = SymbolicSparseColMat::new_checked(free, free, col_ptr, None, rows);
        Ok((SparseColMat::new(symbolic, values), b))
    }
}

/// ‖H x + b + Fᵀλ‖∞ over the free coordinates (the gradient of the
/// Lagrangian) and the same over ‖H‖∞‖x‖∞ + ‖b‖∞, the size of the terms
/// that cancel.
fn lagrangian_gradient(
    h: &SparseColMat<usize, f64>,
    b: &[f64],
    f: &[&[(usize, f64)]],
    x: &[f64],
    lambda: &[f64],
) -> (f64, f64) {
    let mut grad = b.to_vec();
    let mut row_sums = vec![0.0f64; x.len()];
    for (j, xj) in x.iter().enumerate() {
        for (i, v) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
            grad[i] += v * xj;
            row_sums[i] += v.abs();
        }
    }
    for (row, lam) in f.iter().zip(lambda) {
        for &(i, a) in row.iter() {
            grad[i] += a * lam;
        }
    }
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = inf(&row_sums) * inf(x) + inf(b);
    let norm = inf(&grad);
    (norm, if scale > 0.0 { norm / scale } else { norm })
}

/// A curve's name and its chain of mesh vertices.
type Chain = (String, Vec<usize>);

/// Prefixes an error's description with the constraint's name.
fn named(e: Error, name: &str) -> Error {
    match e {
        Error::Mismatch {
            what,
            expected,
            got,
        } if !what.starts_with(name) => Error::Mismatch {
            what: format!("{name}: {what}"),
            expected,
            got,
        },
        other => other,
    }
}

/// outer: original → A; inner: A → B; result: original → B.
fn compose(outer: &Refinement, inner: Refinement) -> Refinement {
    let origin = inner
        .origin
        .iter()
        .map(|&(a, corners)| {
            let (o, oc) = outer.origin[a];
            let mapped = corners.map(|b| {
                let mut p = [0.0; 3];
                for m in 0..3 {
                    for q in 0..3 {
                        p[q] += b[m] * oc[m][q];
                    }
                }
                p
            });
            (o, mapped)
        })
        .collect();
    Refinement {
        surface: inner.surface,
        origin,
    }
}

/// The global point of the refined surface that is original point g, if
/// it survived: a vertex keeps its index, an edge point stays if its edge
/// was not split, an interior point if its triangle was not split.
fn map_global(original: &TriSurface, r: &Refinement, g: usize) -> Option<usize> {
    if g < original.vertex_count() {
        return Some(g);
    }
    let refined = &r.surface;
    let n = original.degree();
    let edge_points = original.edges().len() * (n - 1);
    let local = g - original.vertex_count();
    if local < edge_points {
        let (e, pos) = (local / (n - 1), local % (n - 1) + 1);
        let [a, b] = original.edges()[e].vertices;
        let e2 = refined.edge_between(a, b)?;
        return Some(refined.edge_points(e2)[pos]);
    }
    let per = (n - 1) * (n - 2) / 2;
    let t = (local - edge_points) / per;
    let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let t2 = (0..refined.patch_count()).find(|&x| r.origin[x] == (t, identity))?;
    let at = original.patch_indices(t).iter().position(|&x| x == g)?;
    Some(refined.patch_indices(t2)[at])
}

/// The globals (with values) along a chain of vertices.
fn chain_points(surface: &TriSurface, chain: &[usize], name: &str) -> Result<Vec<(usize, Vec3)>> {
    let mut out = Vec::new();
    for w in chain.windows(2) {
        let e = surface
            .edge_between(w[0], w[1])
            .ok_or_else(|| Error::Mismatch {
                what: format!("{name}: chain edge {}–{}", w[0], w[1]),
                expected: "an edge of the refined mesh".into(),
                got: "an edge split by a later curve (curves that cross are not supported)".into(),
            })?;
        for g in surface.edge_points(e) {
            out.push((g, surface.points()[g]));
        }
    }
    Ok(out)
}

/// The largest distance between the chain edges of the surface and the
/// curve at matching parameters (the chain's edge i covers t ∈ [i/m, (i+1)/m]).
fn curve_distance(surface: &TriSurface, chain: &[usize], curve: &BezierCurve) -> f64 {
    let m = chain.len().saturating_sub(1).max(1);
    let mut worst = 0.0f64;
    for (i, w) in chain.windows(2).enumerate() {
        let Some(e) = surface.edge_between(w[0], w[1]) else {
            return f64::INFINITY;
        };
        let pts: Vec<Vec3> = surface
            .edge_points(e)
            .iter()
            .map(|&g| surface.points()[g])
            .collect();
        let edge = BezierCurve::new(if surface.edges()[e].vertices[0] == w[0] {
            pts
        } else {
            pts.into_iter().rev().collect()
        });
        for s in 0..=16 {
            let u = s as f64 / 16.0;
            let t = (i as f64 + u) / m as f64;
            worst = worst.max(norm(sub(edge.eval(u), curve.eval(t))));
        }
    }
    worst
}

fn bounding_size(points: &[Vec3]) -> f64 {
    crate::vec3::bounding_diagonal(points).max(1.0)
}

/// A direction in which every free control point can move together without
/// changing the internal energy (translation invariant) or any constraint
/// row or attractor residual: `None` when known coordinates, rows and
/// residuals pin all three. A known coordinate pins its axis (the mesh
/// couples it to every free point); a row or residual Σ a_i x_i pins the
/// direction (Σ_{i: x} a_i, Σ_{i: y} a_i, Σ_{i: z} a_i) over its free
/// coordinates i = 3g + c.
fn free_translation<'a>(
    known: &[Option<f64>],
    pinning: impl Iterator<Item = &'a [(usize, f64)]>,
) -> Option<Vec3> {
    let axes = (0..3)
        .filter(|&c| (0..known.len() / 3).any(|g| known[3 * g + c].is_some()))
        .map(|c| std::array::from_fn(|k| if k == c { 1.0 } else { 0.0 }));
    let directions = pinning.map(|terms| {
        let mut v = [0.0; 3];
        let mut scale: f64 = 0.0;
        for &(i, a) in terms {
            if known[i].is_none() {
                v[i % 3] += a;
                scale = scale.max(a.abs());
            }
        }
        // Coefficients that cancel to rounding pin nothing.
        v.map(|x| if x.abs() > 1e-9 * scale { x } else { 0.0 })
    });
    // Gram–Schmidt: an orthonormal basis of the pinned directions.
    let mut basis: Vec<Vec3> = Vec::new();
    for mut v in axes.chain(directions) {
        if basis.len() == 3 {
            return None;
        }
        for q in &basis {
            let d = crate::vec3::dot(v, *q);
            v = crate::vec3::sub(v, crate::vec3::scale(*q, d));
        }
        if let Some(u) = crate::vec3::normalize(v).filter(|_| crate::vec3::norm(v) > 1e-9) {
            basis.push(u);
        }
    }
    if basis.len() == 3 {
        return None;
    }
    // A unit vector orthogonal to the basis.
    let mut free =
        (0..3).map(|c| -> Vec3 { std::array::from_fn(|k| if k == c { 1.0 } else { 0.0 }) });
    free.find_map(|mut v| {
        for q in &basis {
            v = crate::vec3::sub(v, crate::vec3::scale(*q, crate::vec3::dot(v, *q)));
        }
        crate::vec3::normalize(v).filter(|_| crate::vec3::norm(v) > 0.5)
    })
}

/// Estimated peak bytes of a triangular solve: x, y and z of every patch's
/// (d+1)(d+2)/2 points coupled in one sparse KKT system, k² entries a patch
/// and coordinate pair block, 16 bytes an entry (value and indices), four
/// times for the matrix, its ordering and the factor's fill. Measured: 200
/// degree-20 patches took 2.0–2.3 GB (estimate 2.0 GB); 10,000 cubic
/// patches with C0 0.3 GB (estimate 0.2 GB).
pub(crate) fn memory_estimate(surface: &TriSurface) -> f64 {
    let d = surface.degree() as f64;
    let k = (d + 1.0) * (d + 2.0) / 2.0;
    64.0 * 3.0 * surface.patch_count() as f64 * k * k
}
