//! A tensor problem's system, assembled and factored: the solve proper
//! (right-hand side, triangular solves with refinement, the constraints'
//! rows, Newton's method for repellors) and the report, for a fresh solve
//! and for every later one that moves only what the matrix does not see.

use super::builder::Problem;
use super::dense::{norm_max, SpdFactor};
use super::problem::{
    center_rhs, free_rows, quadratic_residuals, Placed, Prepared, ResidualShape, Solution,
    SolveOptions,
};
use super::report::{SolveReport, TermEnergy, Timings};
use super::rows::FreeRows;
use crate::analysis::measures;
use crate::budget;
use crate::check::tensor::EnergyAt;
use crate::check::{self, Check};
use crate::energy::Hessian;
use crate::operator::newton::{newton, repellors, sparse, FreeResiduals, NewtonReport};
use crate::operator::OperatorOutcome;
use crate::vec3::Vec3;
use crate::{Error, Result, TensorPatch};
use faer::sparse::Triplet;
use faer::Mat;
use std::time::Instant;

/// A problem's system, assembled and factored ([`Problem::factor`]): solve
/// it again after moving known control points, the guide surface or
/// attractor targets, without assembling or factoring anything.
///
/// The reduced matrix H_FF of Wu & Yang's eq. (3)–(4) depends on the
/// degree, which points are free, the terms' Hessians (weights, measures,
/// the normal field N — not the guide surface S, which only enters b) and
/// the attractors' and directors' places, strengths and directions. It does
/// not depend on the known points' values, on S, on the attractors' target
/// points or planes' offsets, or on repellors (Newton's method starts from
/// the quadratic solution). When only those move, only the right-hand side
/// b_F − H_FK x_K changes; [`Factored::solve`] rebuilds that, then does the
/// triangular solves and the compensated iterative refinement of a full
/// solve, and reports the same measures of accuracy.
///
/// ```
/// use fairsurf::{Problem, SolveOptions, Stretch, TensorPatch};
/// let net = |h: f64| TensorPatch::from_fn(3, 3, |i, j| [i as f64, j as f64, h * (i * j) as f64]);
/// let opts = SolveOptions::default();
/// let problem = |h| Problem::new((3, 3)).with_fixed_rings(&net(h), 1).with_term(Stretch::new(1.0));
/// let factored = problem(0.1).factor(&opts).unwrap();
/// // Move the boundary: the same factorization solves the new problem.
/// let moved = factored.solve(&problem(0.5), &opts).unwrap();
/// assert!(moved.report.reused);
/// let fresh = problem(0.5).solve_with(&opts).unwrap();
/// assert!((moved.surface.point(1, 1)[2] - fresh.surface.point(1, 1)[2]).abs() < 1e-14);
/// ```
#[derive(Debug)]
pub struct Factored {
    pub(super) degree: (usize, usize),
    pub(super) free: Vec<usize>,
    /// Whether each control point is known.
    pub(super) known: Vec<bool>,
    pub(super) coupled: bool,
    /// The terms' [`EnergyTerm::hessian_key`]s and names.
    pub(super) keys: Vec<Option<u64>>,
    pub(super) names: Vec<&'static str>,
    /// The Hessians of the terms with a centre (they make b = Σ H_t s_t).
    pub(super) centred: Vec<Option<Hessian>>,
    /// The centres of the problem factored.
    pub(super) centers: Vec<Option<Vec<Vec3>>>,
    /// Per attractor or director: strength and (weight, coefficients) of
    /// each residual: what of it enters H.
    pub(super) attractors: Vec<(f64, Vec<ResidualShape>)>,
    /// H over all control points, operators included, and H_FF.
    pub(super) h: Mat<f64>,
    pub(super) h_ff: Mat<f64>,
    /// max over the free rows of Σ|H_row| (H's rows over all control
    /// points): the ‖H‖∞ of the backward error.
    pub(super) h_row_norm: f64,
    pub(super) basis: &'static str,
    pub(super) factor: SpdFactor,
    /// The constraints' rows on the free unknowns, with S factored.
    pub(super) rows: FreeRows,
    pub(super) assemble_seconds: f64,
}

impl Factored {
    /// Scalar unknowns (the order of H_FF).
    pub fn unknowns(&self) -> usize {
        self.h_ff.nrows()
    }

    /// About how many bytes it holds (H, H_FF and the factor).
    pub fn bytes(&self) -> usize {
        let (d, f) = (self.h.nrows(), self.h_ff.nrows());
        8 * (d * d + 2 * f * f + (f + 1) * self.rows.all.len())
    }

    /// Whether `problem` has this system's matrix, so that
    /// [`Factored::solve`] accepts it.
    pub fn fits(&self, problem: &Problem) -> bool {
        problem
            .prepare()
            .is_ok_and(|prep| self.mismatch(problem, &prep).is_none())
    }

    /// Solves `problem` with this factorization. An error when the problem
    /// is not solvable (as [`Problem::solve_with`]) or its matrix is not this
    /// one ([`Error::Mismatch`] saying what differs: degree, free points,
    /// a term's Hessian, an attractor's place or strength). `opts` sets the
    /// refinement steps and the analysis; the factorization's options were
    /// fixed by [`Problem::factor`].
    pub fn solve(&self, problem: &Problem, opts: &SolveOptions) -> Result<Solution> {
        let t_total = Instant::now();
        self.solve_prepared(problem, &problem.prepare()?, opts, t_total)
    }

    /// [`Factored::solve`] of a problem already prepared.
    pub(crate) fn solve_prepared(
        &self,
        problem: &Problem,
        prep: &Prepared,
        opts: &SolveOptions,
        t_total: Instant,
    ) -> Result<Solution> {
        if let Some(why) = self.mismatch(problem, prep) {
            return Err(Error::Mismatch {
                what: "the problem's system matrix".into(),
                expected: "the factored one (same degree, free points, term weights and \
                           measures, normal field, attractor places and strengths)"
                    .into(),
                got: why,
            });
        }
        let centers = problem
            .terms
            .iter()
            .zip(&self.centred)
            .map(|(t, h)| match h {
                Some(_) => t.center(self.degree),
                None => Ok(None),
            })
            .collect::<Result<Vec<_>>>()?;
        self.finish(problem, &prep.placed, &centers, opts, t_total, true)
    }

    /// What makes `problem`'s matrix differ from this one, if anything.
    pub(crate) fn mismatch(&self, problem: &Problem, prep: &Prepared) -> Option<String> {
        if problem.degree() != self.degree {
            return Some(format!(
                "degree {:?} instead of {:?}",
                problem.degree(),
                self.degree
            ));
        }
        let m = self.degree.1;
        if let Some(k) = (0..self.known.len()).find(|&k| problem.free[k] == self.known[k]) {
            return Some(format!(
                "control point ({}, {}) is {} here",
                k / (m + 1),
                k % (m + 1),
                if self.known[k] { "free" } else { "known" }
            ));
        }
        if problem.terms.len() != self.keys.len() {
            return Some(format!(
                "{} energy terms instead of {}",
                problem.terms.len(),
                self.keys.len()
            ));
        }
        for (k, ((t, new), key)) in problem
            .terms
            .iter()
            .zip(&prep.keys)
            .zip(&self.keys)
            .enumerate()
        {
            match (new, key) {
                (Some(a), Some(b)) if a == b => {}
                (None, _) | (_, None) => {
                    return Some(format!(
                        "term {k} ({}) cannot tell whether its Hessian is the same \
                         (EnergyTerm::hessian_key)",
                        t.name()
                    ))
                }
                _ => {
                    return Some(format!(
                    "term {k} ({}, was {}) has another Hessian (weight, measure or normal field)",
                    t.name(),
                    self.names[k]
                ))
                }
            }
        }
        if let Some(why) = self.rows.mismatch(&prep.rows) {
            return Some(why);
        }
        let attractors: Vec<_> = problem
            .operators
            .iter()
            .zip(&prep.placed)
            .filter(|(op, _)| !op.repel)
            .collect();
        if attractors.len() != self.attractors.len() {
            return Some(format!(
                "{} attractors and directors instead of {}",
                attractors.len(),
                self.attractors.len()
            ));
        }
        for (k, ((op, (_, res)), (strength, shape))) in
            attractors.iter().zip(&self.attractors).enumerate()
        {
            let same = op.strength == *strength
                && res.len() == shape.len()
                && res
                    .iter()
                    .zip(shape)
                    .all(|(r, (w, terms))| r.weight == *w && r.terms == *terms);
            if !same {
                return Some(format!(
                    "attractor or director {k} has another place, strength or direction"
                ));
            }
        }
        None
    }

    /// b = Σ_t H_t s_t + Σ_attractors 2 s w t a and the known values x,
    /// in the system's layout.
    pub(super) fn rhs(
        &self,
        problem: &Problem,
        placed: &[Placed],
        centers: &[Option<Vec<Vec3>>],
    ) -> Rhs {
        let np = self.known.len();
        let coupled = self.coupled;
        let (dim, cols) = if coupled { (3 * np, 1) } else { (np, 3) };
        let mut b = Mat::<f64>::zeros(dim, cols);
        for (h, s) in self.centred.iter().zip(centers) {
            if let (Some(h), Some(s)) = (h, s) {
                b += center_rhs(h, s, coupled);
            }
        }
        for (c, r) in quadratic_residuals(&problem.operators, placed) {
            for &(i, a) in &r.terms {
                b[(i, 0)] += c * r.target * a;
            }
        }
        let mut x = Mat::<f64>::zeros(dim, cols);
        for p in 0..problem.free.len() {
            if let Some(v) = problem.known_at(p) {
                for c in 0..3 {
                    let (r, col) = if coupled { (3 * p + c, 0) } else { (p, c) };
                    x[(r, col)] = v[c];
                }
            }
        }
        Rhs { b, x }
    }

    /// The solve proper: right-hand side, triangular solves with
    /// refinement, Newton's method for repellors, the check, the report.
    pub(super) fn finish(
        &self,
        problem: &Problem,
        placed: &[Placed],
        centers: &[Option<Vec<Vec3>>],
        opts: &SolveOptions,
        t_total: Instant,
        reused: bool,
    ) -> Result<Solution> {
        let t = Instant::now();
        let sys = self.rhs(problem, placed, centers);
        let rows = free_rows(&self.free, self.coupled);
        let rhs = self.free_rhs(&sys, &rows);
        let rhs_seconds = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let solved = self.solve_free(problem, placed, &sys, &rhs, opts)?;
        let solve = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let checked = self.checked_net(
            problem,
            placed,
            &sys,
            &rows,
            (solved.xf, solved.lambda),
            solved.newton.is_none(),
            opts.polish,
        )?;
        let patch = checked.patch;
        // The check's exact gradient when there is one (no second pass over
        // H), else H X − B in compensated arithmetic.
        let (gradient_norm, relative_gradient) = match (solved.total_gradient, &checked.at) {
            (Some(t), _) => t,
            (None, Some((at, _, _))) => {
                self.exact_gradient(at, &checked.lambda, &sys, &rows, &patch)
            }
            (None, None) => sys.gradient(&self.h, &rows, &patch, self.coupled),
        };
        let rhs_norm = norm_max(&rhs);
        let residual_norm = match solved.total_gradient {
            Some((g, _)) => g,
            None => norm_max(&solved.residual),
        };
        let residual = if rhs_norm > 0.0 {
            residual_norm / rhs_norm
        } else {
            residual_norm
        };
        let x: Vec<f64> = patch.points().iter().flatten().copied().collect();
        let operators: Vec<OperatorOutcome> = problem
            .operators
            .iter()
            .zip(placed)
            .map(|(op, (at, res))| op.outcome(at, res, &patch, &x))
            .collect();
        let (constraints, max_violation) =
            crate::constraint::outcomes(&problem.constraints, &patch);
        // The written net must meet the rows as well as it is a minimum:
        // a high-degree net whose coefficients blow up misses them by its
        // rounding, which the energy check alone would not see.
        if let Some((row, miss)) = self.rows.unmet(problem, &patch) {
            return Err(Error::Unmet {
                degree: self.degree_text(),
                row,
                miss,
                tolerance: check::TOLERANCE,
            });
        }
        let external: f64 = operators.iter().map(|o| o.energy).sum();
        let mut terms = problem
            .terms
            .iter()
            .map(|t| {
                Ok(TermEnergy {
                    name: t.name().to_string(),
                    value: t.value(&patch)?,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        // The closed forms in double precision; replaced by the recomputed
        // values, which stay exact where the closed forms lose digits.
        let closed_form = terms.iter().map(|t| t.value).sum::<f64>() + external;
        let check = match checked.at {
            Some(at) => Some(self.accepted(at, &mut terms, closed_form, checked.corrections, t)?),
            None => None,
        };
        let energy = check.as_ref().map_or(closed_form, |c| c.energy);
        let t = Instant::now();
        let measures = opts.analyse.then(|| measures(&patch));
        budget::checkpoint()?;
        let analyse = t.elapsed().as_secs_f64();
        let (assemble, factor) = if reused {
            (rhs_seconds, 0.0)
        } else {
            (
                self.assemble_seconds + rhs_seconds,
                self.factor.factor_seconds,
            )
        };
        let report = SolveReport {
            energy,
            check,
            terms,
            external,
            operators,
            constraints,
            max_violation,
            newton: solved.newton,
            gradient_norm,
            relative_gradient,
            residual,
            condition_estimate: self.factor.condition,
            basis: self.basis.to_string(),
            refinement_steps: solved.refinement_steps,
            unknowns: self.h_ff.nrows(),
            free_points: self.free.len(),
            coupled: self.coupled,
            reused,
            reused_symbolic: false,
            measures,
            factor_nonzeros: None,
            kkt: None,
            timings: Timings {
                assemble,
                factor,
                solve,
                analyse,
                total: t_total.elapsed().as_secs_f64(),
            },
            triangular: None,
        };
        Ok(Solution {
            surface: patch,
            report,
        })
    }

    /// "(m, n)".
    fn degree_text(&self) -> String {
        format!("({}, {})", self.degree.0, self.degree.1)
    }

    /// The free rows' right-hand side b_F − H_FK x_K. x has zeros at free
    /// rows, so H x = H_FK x_K on the free rows: only the known columns of
    /// H are read.
    fn free_rhs(&self, sys: &Rhs, rows: &[usize]) -> Mat<f64> {
        let mut hx = Mat::<f64>::zeros(self.h.nrows(), sys.x.ncols());
        for c in 0..sys.x.ncols() {
            let out = hx.col_as_slice_mut(c);
            for (j, &xj) in sys.x.col_as_slice(c).iter().enumerate() {
                if xj != 0.0 {
                    for (o, &hij) in out.iter_mut().zip(self.h.col_as_slice(j)) {
                        *o += hij * xj;
                    }
                }
            }
        }
        Mat::from_fn(rows.len(), sys.b.ncols(), |i, c| {
            sys.b[(rows[i], c)] - hx[(rows[i], c)]
        })
    }

    /// The free unknowns: the triangular solves with refinement, the
    /// constraints' rows on the same factor (refined on the whole system;
    /// λ their multipliers), then Newton's method for repellors.
    fn solve_free(
        &self,
        problem: &Problem,
        placed: &[Placed],
        sys: &Rhs,
        rhs: &Mat<f64>,
        opts: &SolveOptions,
    ) -> Result<FreeSolve> {
        let h_ff = &self.h_ff;
        let mut sol = self.factor.solve(h_ff, rhs, opts.max_refinement_steps);
        let mut lambda = Vec::new();
        // (Also checks the rows no free coordinate enters.)
        let c = self.rows.rhs(&sys.x)?;
        if let Some(system) = &self.rows.system {
            let x_u = std::mem::replace(&mut sol.x, Mat::zeros(0, 0));
            let (x, l, r, steps) =
                system.solve(&self.factor, h_ff, rhs, &c, x_u, opts.max_refinement_steps);
            (sol.x, sol.residual, lambda) = (x, r, l);
            sol.refinement_steps += steps;
        }
        let repellors = repellors(&problem.operators, placed, &problem.known(), &self.free);
        let (xf, newton, total_gradient) = if repellors.is_empty() {
            (sol.x, None, None)
        } else {
            let (x, report, gradient) = self.repel(rhs, &sol.x, &repellors)?;
            (x, Some(report), Some(gradient))
        };
        Ok(FreeSolve {
            xf,
            lambda,
            residual: sol.residual,
            refinement_steps: sol.refinement_steps,
            newton,
            total_gradient,
        })
    }

    /// Repellors: Newton's method on the total energy from the quadratic
    /// solution x (no constraints but the known points and the rows). The
    /// net, Newton's report and (‖∇E‖∞ or, with rows, the Lagrangian's,
    /// relative gradient).
    fn repel(
        &self,
        rhs: &Mat<f64>,
        x: &Mat<f64>,
        repellors: &[FreeResiduals],
    ) -> Result<(Mat<f64>, NewtonReport, (f64, f64))> {
        let h_ff = &self.h_ff;
        let nf = h_ff.nrows();
        let f_rows: Vec<&[(usize, f64)]> = match &self.rows.system {
            Some(system) => system.rows().iter().map(|r| &r[..]).collect(),
            None => Vec::new(),
        };
        let mut triplets = Vec::new();
        for j in 0..nf {
            for i in 0..nf {
                if h_ff[(i, j)] != 0.0 {
                    triplets.push(Triplet::new(i, j, h_ff[(i, j)]));
                }
            }
        }
        let h = sparse(nf, &triplets)?;
        let b: Vec<f64> = (0..nf).map(|i| -rhs[(i, 0)]).collect();
        let x0: Vec<f64> = (0..nf).map(|i| x[(i, 0)]).collect();
        let (x, report) = newton(&h, &b, &f_rows, repellors, x0)?;
        // ∇E = H x + b − Σ s ∇q / q², for the report.
        let mut g = b.clone();
        for j in 0..nf {
            for i in 0..nf {
                g[i] += h_ff[(i, j)] * x[j];
            }
        }
        for r in repellors {
            let (q, dq) = r.value_and_gradient(&x);
            for (i, d) in dq {
                g[i] -= r.strength * d / (q * q);
            }
        }
        // With rows, ∇E is balanced by Fᵀλ: Newton's own figure is the
        // gradient of the Lagrangian.
        let norm = if f_rows.is_empty() {
            g.iter().fold(0.0f64, |m, v| m.max(v.abs()))
        } else {
            report.gradient_norm
        };
        let gradient = (norm, report.relative_gradient);
        Ok((Mat::from_fn(nf, 1, |i, _| x[i]), report, gradient))
    }

    /// The check's figures, the terms' values replaced by the recomputed
    /// ones; an error when the excess does not meet the tolerance.
    fn accepted(
        &self,
        (at, excess, scale): (EnergyAt, f64, f64),
        terms: &mut [TermEnergy],
        closed_form: f64,
        corrections: usize,
        started: Instant,
    ) -> Result<Check> {
        for (t, v) in terms.iter_mut().zip(&at.terms) {
            t.value = v.to_f64();
        }
        let recomputed = at.total.to_f64();
        let check = Check {
            energy: recomputed,
            energy_error: (closed_form - recomputed).abs() / scale,
            excess: excess / scale,
            scale,
            corrections,
            tolerance: check::TOLERANCE,
            seconds: started.elapsed().as_secs_f64(),
        };
        if check.passed() {
            return Ok(check);
        }
        Err(Error::Unverified {
            degree: self.degree_text(),
            checked: recomputed,
            excess: check.excess,
            tolerance: check.tolerance,
            hint:
                "A Bernstein net of this degree cannot hold this minimizer to that accuracy: use \
                   a lower degree (the README's limits give the degrees that verify), or a \
                   B-spline surface (\"type\": \"bspline\"), which gains freedom by more spans at \
                   low degree."
                    .into(),
        })
    }
}

/// What [`Factored::solve_free`] leaves: the free unknowns (after Newton's
/// method when there are repellors), the rows' multipliers, the quadratic
/// solve's residual and refinement steps, Newton's report and gradient.
struct FreeSolve {
    xf: Mat<f64>,
    lambda: Vec<f64>,
    residual: Mat<f64>,
    refinement_steps: usize,
    newton: Option<NewtonReport>,
    total_gradient: Option<(f64, f64)>,
}

/// One solve's right-hand side over all control points: E = ½ XᵀHX − BᵀX + c
/// with X of one column per coordinate (per-coordinate layout) or one column
/// of all coordinates point-major (coupled).
pub(super) struct Rhs {
    pub(super) b: Mat<f64>,
    /// Known values (free entries 0), laid out like b.
    pub(super) x: Mat<f64>,
}

impl Rhs {
    /// All control points: known ones as given, free ones (at `rows`) from
    /// the solution.
    pub(super) fn fill(&self, rows: &[usize], xf: &Mat<f64>, coupled: bool) -> Vec<Vec3> {
        let mut x = self.x.clone();
        for (i, &r) in rows.iter().enumerate() {
            for c in 0..x.ncols() {
                x[(r, c)] = xf[(i, c)];
            }
        }
        let np = if coupled { x.nrows() / 3 } else { x.nrows() };
        (0..np)
            .map(|p| {
                if coupled {
                    [x[(3 * p, 0)], x[(3 * p + 1, 0)], x[(3 * p + 2, 0)]]
                } else {
                    [x[(p, 0)], x[(p, 1)], x[(p, 2)]]
                }
            })
            .collect()
    }

    /// (‖g‖₂, normwise backward error) of g = (H X − B) on the free `rows` at
    /// the patch's control points, each entry a compensated dot product.
    pub(super) fn gradient(
        &self,
        h: &Mat<f64>,
        rows: &[usize],
        patch: &TensorPatch,
        coupled: bool,
    ) -> (f64, f64) {
        let mut x = Mat::<f64>::zeros(self.x.nrows(), self.x.ncols());
        for (p, v) in patch.points().iter().enumerate() {
            for c in 0..3 {
                if coupled {
                    x[(3 * p + c, 0)] = v[c];
                } else {
                    x[(p, c)] = v[c];
                }
            }
        }
        let mut g_inf: f64 = 0.0;
        let mut h_inf: f64 = 0.0;
        let mut b_inf: f64 = 0.0;
        for &r in rows {
            let hr = h.col_as_slice(r); // row r of symmetric H
            h_inf = h_inf.max(hr.iter().map(|v| v.abs()).sum());
            for c in 0..x.ncols() {
                let g = -super::compensated::dot2_residual(self.b[(r, c)], hr, x.col_as_slice(c));
                g_inf = g_inf.max(g.abs());
                b_inf = b_inf.max(self.b[(r, c)].abs());
            }
        }
        let denom = h_inf * norm_max(&x) + b_inf;
        (g_inf, if denom > 0.0 { g_inf / denom } else { g_inf })
    }
}
