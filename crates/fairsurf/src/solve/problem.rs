//! A variational problem over one tensor-product Bézier patch: which control
//! points are known, which terms make the energy, and the solve.
//!
//! Minimizing `E(x) = Σ_t ½ (x − s_t)ᵀ H_t (x − s_t)` over the free control
//! points x_F with the known ones x_K held is the linear system
//! `H_FF x_F = b_F − H_FK x_K`, `b = Σ_t H_t s_t` — Wu & Yang 2015, eq. (3)
//! for E1 and eq. (4) for E2, here assembled from the exact forms rather than
//! written out coefficient by coefficient.
//!
//! Linear constraints at (u, v) (point, normal, in plane, on line:
//! [`crate::constraint`]) add rows F x = c, solved on the same factor by the
//! range-space method (`rows.rs`).

use super::dense::{norm_max, SpdFactor, SpdOptions};
use super::jacobi::TensorBasis;
use super::report::{SolveReport, TermEnergy, Timings};
use super::rows::RowSystem;
use crate::analysis::measures;
use crate::budget;
use crate::check::{self, dd::Dd, tensor::EnergyAt, Check};
use crate::constraint::{ConstraintOutcome, NamedConstraint, Row};
use crate::energy::Integrand;
use crate::energy::Space;
use crate::energy::{EnergyTerm, Hessian, TermForm};
use crate::operator::newton::{newton, sparse, FreeResiduals};
use crate::operator::tensor::TensorLocated;
use crate::operator::{OperatorOutcome, Residual, TensorOperator};
use crate::tensor::{TensorConstraint, Uv};
use crate::vec3::{is_finite, Vec3};
use crate::{Error, Result, TensorPatch};
use faer::sparse::Triplet;
use faer::Mat;
use std::time::Instant;

/// A problem: degree, known control points, and energy terms.
///
/// ```
/// use fairsurf::{Problem, Stretch, TensorPatch};
/// // A 3×3 net with a lifted middle: fix the boundary, free the centre.
/// let net = TensorPatch::from_fn(2, 2, |i, j| [i as f64, j as f64, if (i, j) == (1, 1) { 5.0 } else { 0.0 }]);
/// let sol = Problem::new((2, 2)).with_fixed_rings(&net, 1).with_term(Stretch::new(1.0)).solve().unwrap();
/// // The Dirichlet extremal of a planar boundary is planar.
/// assert!(sol.patch.point(1, 1)[2].abs() < 1e-14);
/// assert!(sol.report.relative_gradient < 1e-14);
/// ```
#[derive(Debug)]
pub struct Problem {
    degree: (usize, usize),
    known: Vec<Option<Vec3>>,
    terms: Vec<Box<dyn EnergyTerm>>,
    operators: Vec<TensorOperator>,
    constraints: Vec<NamedConstraint<Uv>>,
}

/// Options for [`Problem::solve_with`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// At most this many steps of iterative refinement (default 30).
    pub max_refinement_steps: usize,
    /// Estimate the condition number (default true; costs ~60 mat-vecs).
    pub estimate_condition: bool,
    /// Above this estimated condition number the system is reported
    /// singular instead of solved (default 1e15).
    pub singular_condition: f64,
    /// Compute area and functionals of the result (default true).
    pub analyse: bool,
    /// Factor in the orthogonal Jacobi-weighted basis when the free points
    /// form a tensor block (default true; see the `basis` of the report).
    pub tensor_basis: bool,
}

impl Default for SolveOptions {
    fn default() -> Self {
        Self {
            max_refinement_steps: 30,
            estimate_condition: true,
            singular_condition: 1e15,
            analyse: true,
            tensor_basis: true,
        }
    }
}

impl SolveOptions {
    /// Sets [`SolveOptions::analyse`].
    pub fn with_analyse(mut self, on: bool) -> Self {
        self.analyse = on;
        self
    }

    /// Sets [`SolveOptions::estimate_condition`].
    pub fn with_condition_estimate(mut self, on: bool) -> Self {
        self.estimate_condition = on;
        self
    }
}

/// A solved problem: the surface and how good it is.
#[derive(Clone, Debug)]
pub struct Solution {
    /// The patch with every control point filled.
    pub patch: TensorPatch,
    /// Energies, gradient, residual, conditioning, timings.
    pub report: SolveReport,
}

impl Problem {
    /// A problem of degree (n, m) with every control point free and no terms.
    pub fn new(degree: (usize, usize)) -> Self {
        let n = (degree.0 + 1) * (degree.1 + 1);
        Self {
            degree,
            known: vec![None; n],
            terms: Vec::new(),
            operators: Vec::new(),
            constraints: Vec::new(),
        }
    }

    /// (n, m).
    pub fn degree(&self) -> (usize, usize) {
        self.degree
    }

    /// Known control points (`None` = free), row-major.
    pub fn known(&self) -> &[Option<Vec3>] {
        &self.known
    }

    /// The energy terms.
    pub fn terms(&self) -> &[Box<dyn EnergyTerm>] {
        &self.terms
    }

    /// Fixes P_ij at p.
    ///
    /// # Panics
    /// If (i, j) is outside the net.
    pub fn fix(&mut self, i: usize, j: usize, p: Vec3) -> &mut Self {
        let m = self.degree.1;
        assert!(
            i <= self.degree.0 && j <= m,
            "control point ({i}, {j}) outside the net"
        );
        self.known[i * (m + 1) + j] = Some(p);
        self
    }

    /// Sets the known points all at once (`None` = free), row-major.
    pub fn with_known(mut self, known: Vec<Option<Vec3>>) -> Result<Self> {
        if known.len() != self.known.len() {
            return Err(Error::ControlPointCount {
                degree: self.degree,
                expected: self.known.len(),
                got: known.len(),
            });
        }
        self.known = known;
        Ok(self)
    }

    /// Fixes the outer k rings of control points at their values in `net`
    /// and frees every other point. k = 1 fixes the boundary curves (C0 to
    /// the surroundings); k = 2 also the cross-boundary derivatives (G1 hole
    /// filling and blending, Wu & Yang §3.2).
    ///
    /// # Panics
    /// If `net` has another degree.
    pub fn with_fixed_rings(mut self, net: &TensorPatch, k: usize) -> Self {
        assert_eq!(net.degree(), self.degree, "net degree");
        let (n, m) = self.degree;
        for i in 0..=n {
            for j in 0..=m {
                let ring = i.min(j).min(n - i).min(m - j);
                self.known[i * (m + 1) + j] = (ring < k).then(|| net.point(i, j));
            }
        }
        self
    }

    /// Adds an energy term.
    pub fn with_term(mut self, term: impl EnergyTerm + 'static) -> Self {
        self.terms.push(Box::new(term));
        self
    }

    /// Adds a boxed energy term.
    pub fn push_term(&mut self, term: Box<dyn EnergyTerm>) {
        self.terms.push(term);
    }

    /// Adds an external energy operator (Veltkamp & Wesselink §5):
    /// attractors and directors join the quadratic energy; repellors make
    /// the solve nonlinear (Newton's method from the quadratic solution).
    pub fn with_operator(mut self, operator: TensorOperator) -> Self {
        self.operators.push(operator);
        self
    }

    /// The external energy operators.
    pub fn operators(&self) -> &[TensorOperator] {
        &self.operators
    }

    /// Adds a linear constraint at a point (u, v) of the patch (Veltkamp &
    /// Wesselink eq. 31 on a tensor patch): the surface passes through a
    /// point, has a normal, lies in a plane or on a line there. The solve
    /// meets it exactly (to rounding) and reports its violation. A
    /// [`crate::constraint::Constraint::Fixed`] one fixes the control point
    /// of index i·(m+1) + j instead.
    pub fn with_constraint(
        mut self,
        name: impl Into<String>,
        constraint: TensorConstraint,
    ) -> Self {
        if let TensorConstraint::Fixed { point, value } = constraint {
            if point < self.known.len() {
                self.known[point] = Some(value);
                return self;
            }
        }
        self.constraints.push(NamedConstraint {
            name: name.into(),
            constraint,
        });
        self
    }

    /// The constraints at points of the patch.
    pub fn constraints(&self) -> &[NamedConstraint<Uv>] {
        &self.constraints
    }

    /// A patch of this degree with every control point at the origin: what
    /// the constraints' weights need (they depend on the degree only).
    fn blank(&self) -> TensorPatch {
        TensorPatch::new(
            self.degree.0,
            self.degree.1,
            vec![[0.0; 3]; self.known.len()],
        )
    }

    /// Solves with default options.
    pub fn solve(&self) -> Result<Solution> {
        self.solve_with(&SolveOptions::default())
    }

    /// Minimizes the energy over the free control points.
    pub fn solve_with(&self, opts: &SolveOptions) -> Result<Solution> {
        Ok(self.factor_and_solve(opts)?.1)
    }

    /// [`Problem::solve_with`] that keeps the factorization for later
    /// [`Factored::solve`]s.
    pub fn factor_and_solve(&self, opts: &SolveOptions) -> Result<(Factored, Solution)> {
        let t_total = Instant::now();
        self.factor_and_solve_prepared(&self.prepare()?, opts, t_total)
    }

    pub(crate) fn factor_and_solve_prepared(
        &self,
        prep: &Prepared,
        opts: &SolveOptions,
        t_total: Instant,
    ) -> Result<(Factored, Solution)> {
        let factored = self.factor_prepared(opts, prep)?;
        let solution =
            factored.finish(self, &prep.placed, &factored.centers, opts, t_total, false)?;
        Ok((factored, solution))
    }

    /// Assembles and factors the system without solving it: the expensive
    /// half of a solve. [`Factored::solve`] then solves this problem, and any
    /// problem that differs from it only where the matrix does not depend,
    /// in a fraction of the time.
    pub fn factor(&self, opts: &SolveOptions) -> Result<Factored> {
        self.factor_prepared(opts, &self.prepare()?)
    }

    /// The checks, the operators' places and the terms' Hessian keys: what
    /// both a factorization and the test whether one fits need, once.
    pub(crate) fn prepare(&self) -> Result<Prepared> {
        let free = self.check()?;
        let placed = self.place_operators()?;
        let blank = self.blank();
        let rows = self
            .constraints
            .iter()
            .flat_map(|c| c.constraint.rows(&blank, &c.name))
            .collect();
        Ok(Prepared {
            free,
            placed,
            rows,
            keys: self.terms.iter().map(|t| t.hessian_key()).collect(),
        })
    }

    /// The free control points, after checking that the problem can be
    /// solved at all: some point free, known points finite, an energy,
    /// valid operators.
    fn check(&self) -> Result<Vec<usize>> {
        let free: Vec<usize> = (0..self.known.len())
            .filter(|&k| self.known[k].is_none())
            .collect();
        if free.is_empty() {
            return Err(Error::NoFreePoints {
                why: "every control point is known".into(),
            });
        }
        for (k, p) in self.known.iter().enumerate() {
            if p.is_some_and(|p| !is_finite(p)) {
                let m = self.degree.1;
                return Err(Error::NotFinite {
                    what: format!("known control point ({}, {})", k / (m + 1), k % (m + 1)),
                });
            }
        }
        if self.terms.is_empty() {
            return Err(Error::NoEnergy);
        }
        for op in &self.operators {
            op.validate()?;
        }
        let blank = self.blank();
        for c in &self.constraints {
            c.constraint.validate(&blank, &c.name)?;
        }
        Ok(free)
    }

    /// Each operator's place on the patch and its residuals.
    fn place_operators(&self) -> Result<Vec<Placed>> {
        self.operators
            .iter()
            .map(|op| {
                let at = op.locate(self.degree)?;
                let res = op.residuals(&at, self.degree);
                Ok((at, res))
            })
            .collect()
    }

    fn factor_prepared(&self, opts: &SolveOptions, prep: &Prepared) -> Result<Factored> {
        let (free, placed) = (&prep.free, &prep.placed[..]);
        budget::reserve(
            &format!("the degree {:?} system", self.degree),
            self.memory_estimate(),
        )?;
        let t = Instant::now();
        // The Jacobi basis carries the internal energies only.
        let block = if opts.tensor_basis && self.operators.is_empty() {
            self.free_block(free)
        } else {
            None
        };
        // The system in the Bernstein basis and the preconditioner in the
        // Jacobi basis are independent: large ones are assembled side by
        // side on two threads.
        let bernstein = || self.bernstein_system(free, placed);
        let jacobi = || self.jacobi_system(block, !self.constraints.is_empty());
        let (system, pre) = if self.known.len() >= PARALLEL_ASSEMBLY {
            budget::join(bernstein, jacobi)
        } else {
            (bernstein(), jacobi())
        };
        let (forms, coupled, h, h_ff) = system?;
        let pre = pre?;
        let spd = SpdOptions {
            estimate_condition: opts.estimate_condition,
            singular_condition: opts.singular_condition,
        };
        let assemble_seconds = t.elapsed().as_secs_f64();
        budget::checkpoint()?;
        let factor = SpdFactor::new(&h_ff, spd, &self.hint(), pre.as_ref().map(|(h, q)| (h, q)))?;
        let rows = FreeRows::new(&prep.rows, free, &factor, &h_ff, opts)?;
        let attractors = self
            .operators
            .iter()
            .zip(placed)
            .filter(|(op, _)| !op.repel)
            .map(|(op, (_, res))| {
                let shape = res.iter().map(|r| (r.weight, r.terms.clone())).collect();
                (op.strength, shape)
            })
            .collect();
        let mut centers = Vec::with_capacity(forms.len());
        let mut centred = Vec::with_capacity(forms.len());
        for f in forms {
            centred.push(f.center.is_some().then_some(f.hessian));
            centers.push(f.center);
        }
        Ok(Factored {
            degree: self.degree,
            free: free.clone(),
            known: self.known.iter().map(Option::is_some).collect(),
            coupled,
            keys: prep.keys.clone(),
            names: self.terms.iter().map(|t| t.name()).collect(),
            centred,
            centers,
            attractors,
            h_row_norm: free_rows(free, coupled)
                .iter()
                .map(|&r| h.col_as_slice(r).iter().map(|v| v.abs()).sum::<f64>())
                .fold(0.0, f64::max),
            h,
            h_ff,
            basis: if pre.is_some() { "jacobi" } else { "bernstein" },
            factor,
            rows,
            assemble_seconds,
        })
    }

    /// The terms' forms, whether they couple the coordinates, the system H
    /// over all control points (with the attractors' and directors'
    /// quadratic terms) and its free block H_FF.
    fn bernstein_system(&self, free: &[usize], placed: &[Placed]) -> Result<BernsteinSystem> {
        let forms = self
            .terms
            .iter()
            .map(|t| {
                budget::checkpoint()?;
                t.form(self.degree)
            })
            .collect::<Result<Vec<_>>>()?;
        // Operators and constraints couple the coordinates.
        let coupled = !self.operators.is_empty()
            || !self.constraints.is_empty()
            || forms
                .iter()
                .any(|f| matches!(f.hessian, Hessian::Coupled(_)));
        let mut h = hessian_sum(&forms, self.known.len(), coupled);
        for (c, r) in quadratic_residuals(&self.operators, placed) {
            for &(i, a) in &r.terms {
                for &(j, b) in &r.terms {
                    h[(i, j)] += c * a * b;
                }
            }
        }
        let h_ff = gather(&h, &free_rows(free, coupled));
        Ok((forms, coupled, h, h_ff))
    }

    /// The preconditioner: the free block's system in the Jacobi basis
    /// (rows a..=n−b, columns c..=m−d for `block` ((a, b), (c, d))) and the
    /// basis change.
    fn jacobi_system(
        &self,
        block: Option<((usize, usize), (usize, usize))>,
        force_coupled: bool,
    ) -> Result<Option<(Mat<f64>, TensorBasis)>> {
        let Some((ru, rv)) = block else {
            return Ok(None);
        };
        let space = Space::jacobi(self.degree, ru, rv);
        let forms = self
            .terms
            .iter()
            .map(|t| {
                budget::checkpoint()?;
                t.form_in(&space)
            })
            .collect::<Result<Vec<_>>>()?;
        let coupled = force_coupled
            || forms
                .iter()
                .any(|f| matches!(f.hessian, Hessian::Coupled(_)));
        let h = hessian_sum(&forms, space.len(), coupled);
        Ok(TensorBasis::from_space(&space, if coupled { 3 } else { 1 }).map(|q| (h, q)))
    }

    /// Estimated peak bytes of a solve: the dense system over all control
    /// points (3 per point when a term or operator may couple the
    /// coordinates), one such matrix per term's form, H, H_FF, the factor
    /// and the basis change: 8 · dim² · (terms + 4).
    pub fn memory_estimate(&self) -> f64 {
        let np = self.known.len() as f64;
        let per_coordinate = self.operators.is_empty()
            && self.constraints.is_empty()
            && self.terms.iter().all(|t| {
                matches!(
                    t.integrand(),
                    Some(Integrand::Fairness { .. } | Integrand::GuideSurface { .. })
                )
            });
        let dim = if per_coordinate { np } else { 3.0 * np };
        8.0 * dim * dim * (self.terms.len() as f64 + 4.0)
    }

    /// When the free points are exactly a block of contiguous rows ×
    /// contiguous columns, its margins ((a, b), (c, d)): rows a..=n−b,
    /// columns c..=m−d.
    fn free_block(&self, free: &[usize]) -> Option<((usize, usize), (usize, usize))> {
        let (n, m) = self.degree;
        let (mut i0, mut i1, mut j0, mut j1) = (usize::MAX, 0, usize::MAX, 0);
        for &p in free {
            let (i, j) = (p / (m + 1), p % (m + 1));
            (i0, i1, j0, j1) = (i0.min(i), i1.max(i), j0.min(j), j1.max(j));
        }
        if free.len() != (i1 - i0 + 1) * (j1 - j0 + 1) {
            return None;
        }
        Some(((i0, n - i1), (j0, m - j1)))
    }

    fn hint(&self) -> String {
        let names: Vec<&str> = self.terms.iter().map(|t| t.name()).collect();
        format!(
            "the energy ({}) does not determine the free control points; a stretch or bend \
             weight > 0, or a guide_surface weight > 0, makes it positive definite",
            names.join(" + ")
        )
    }
}

/// Adds one term's Hessian into `h` in the system's layout: a per-coordinate
/// block stays np×np, or is spread over the three coordinates of a coupled
/// 3np×3np system. In place: no per-term copy of a system-sized matrix.
fn add_hessian(h: &mut Mat<f64>, term: &Hessian, coupled: bool) {
    match term {
        Hessian::PerCoordinate(m) if coupled => {
            for q in 0..m.ncols() {
                let src = m.col_as_slice(q);
                for c in 0..3 {
                    let dst = h.col_as_slice_mut(3 * q + c);
                    for (d, &v) in dst[c..].iter_mut().step_by(3).zip(src) {
                        *d += v;
                    }
                }
            }
        }
        Hessian::PerCoordinate(m) | Hessian::Coupled(m) => *h += m,
    }
}

/// The submatrix H[rows, rows], column by column.
fn gather(h: &Mat<f64>, rows: &[usize]) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(rows.len(), rows.len());
    for (j, &rj) in rows.iter().enumerate() {
        let src = h.col_as_slice(rj);
        for (d, &ri) in out.col_as_slice_mut(j).iter_mut().zip(rows) {
            *d = src[ri];
        }
    }
    out
}

/// H_t s for a term with centre s, in the system's layout.
fn center_rhs(term: &Hessian, s: &[Vec3], coupled: bool) -> Mat<f64> {
    let np = s.len();
    match term {
        Hessian::PerCoordinate(m) => {
            let r = m * Mat::from_fn(np, 3, |p, c| s[p][c]);
            if coupled {
                Mat::from_fn(3 * np, 1, |i, _| r[(i / 3, i % 3)])
            } else {
                r
            }
        }
        Hessian::Coupled(m) => m * Mat::from_fn(3 * np, 1, |i, _| s[i / 3][i % 3]),
    }
}

/// Σ of the terms' Hessians in the system's layout.
fn hessian_sum(forms: &[TermForm], np: usize, coupled: bool) -> Mat<f64> {
    let dim = if coupled { 3 * np } else { np };
    let mut h = Mat::<f64>::zeros(dim, dim);
    for f in forms {
        add_hessian(&mut h, &f.hessian, coupled);
    }
    h
}

/// An operator's place on the patch and its residuals.
type Placed = (TensorLocated, Vec<Residual>);

/// Forms, coupled, H, H_FF ([`Problem::bernstein_system`]).
type BernsteinSystem = (Vec<TermForm>, bool, Mat<f64>, Mat<f64>);

/// From this many control points on, the Bernstein system and the Jacobi
/// preconditioner are assembled on two threads (degree 9×9 and up: below,
/// a thread costs more than it saves).
const PARALLEL_ASSEMBLY: usize = 100;

/// A problem checked, its operators placed and its terms' Hessian keys
/// taken ([`Problem::prepare`]).
pub(crate) struct Prepared {
    free: Vec<usize>,
    placed: Vec<Placed>,
    /// The constraints' rows over all coordinates (3p + c).
    rows: Vec<Row>,
    keys: Vec<Option<u64>>,
}

/// (2 s w, r) for each residual r of the attractors and directors: their
/// quadratic energy s Σ w (a·x − t)² adds 2 s w a aᵀ to H and 2 s w t a to
/// b. Repellors wait for Newton's method.
fn quadratic_residuals<'a>(
    operators: &'a [TensorOperator],
    placed: &'a [Placed],
) -> impl Iterator<Item = (f64, &'a Residual)> + 'a {
    operators
        .iter()
        .zip(placed)
        .filter(|(op, _)| !op.repel)
        .flat_map(|(op, (_, res))| res.iter().map(move |r| (2.0 * op.strength * r.weight, r)))
}

/// What of a residual enters H: its weight and coefficients.
type ResidualShape = (f64, Vec<(usize, f64)>);

/// Row indices of the free unknowns in the system's layout.
fn free_rows(free: &[usize], coupled: bool) -> Vec<usize> {
    if coupled {
        free.iter()
            .flat_map(|&p| (0..3).map(move |c| 3 * p + c))
            .collect()
    } else {
        free.to_vec()
    }
}

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
/// assert!((moved.patch.point(1, 1)[2] - fresh.patch.point(1, 1)[2]).abs() < 1e-14);
/// ```
#[derive(Debug)]
pub struct Factored {
    degree: (usize, usize),
    free: Vec<usize>,
    /// Whether each control point is known.
    known: Vec<bool>,
    coupled: bool,
    /// The terms' [`EnergyTerm::hessian_key`]s and names.
    keys: Vec<Option<u64>>,
    names: Vec<&'static str>,
    /// The Hessians of the terms with a centre (they make b = Σ H_t s_t).
    centred: Vec<Option<Hessian>>,
    /// The centres of the problem factored.
    centers: Vec<Option<Vec<Vec3>>>,
    /// Per attractor or director: strength and (weight, coefficients) of
    /// each residual: what of it enters H.
    attractors: Vec<(f64, Vec<ResidualShape>)>,
    /// H over all control points, operators included, and H_FF.
    h: Mat<f64>,
    h_ff: Mat<f64>,
    /// max over the free rows of Σ|H_row| (H's rows over all control
    /// points): the ‖H‖∞ of the backward error.
    h_row_norm: f64,
    basis: &'static str,
    factor: SpdFactor,
    /// The constraints' rows on the free unknowns, with S factored.
    rows: FreeRows,
    assemble_seconds: f64,
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
        if problem.degree != self.degree {
            return Some(format!(
                "degree {:?} instead of {:?}",
                problem.degree, self.degree
            ));
        }
        let m = self.degree.1;
        if let Some(k) =
            (0..self.known.len()).find(|&k| problem.known[k].is_some() != self.known[k])
        {
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
    fn rhs(&self, problem: &Problem, placed: &[Placed], centers: &[Option<Vec<Vec3>>]) -> Rhs {
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
        for (p, k) in problem.known.iter().enumerate() {
            if let Some(v) = k {
                for c in 0..3 {
                    let (r, col) = if coupled { (3 * p + c, 0) } else { (p, c) };
                    x[(r, col)] = v[c];
                }
            }
        }
        Rhs { b, x }
    }

    /// The solve proper: right-hand side, triangular solves with
    /// refinement, Newton's method for repellors, the report.
    fn finish(
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
        let free = &self.free;
        let rows = free_rows(free, self.coupled);
        // x has zeros at free rows, so H x = H_FK x_K on the free rows.
        let hx = &self.h * &sys.x;
        let rhs = Mat::from_fn(rows.len(), sys.b.ncols(), |i, c| {
            sys.b[(rows[i], c)] - hx[(rows[i], c)]
        });
        let rhs_seconds = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let h_ff = &self.h_ff;
        let mut sol = self.factor.solve(h_ff, &rhs, opts.max_refinement_steps);
        // Constraints: the rows on the same factor, refined on the whole
        // system; λ their multipliers.
        let mut lambda = Vec::new();
        // (Also checks the rows no free coordinate enters.)
        let c = self.rows.rhs(&sys.x)?;
        if let Some(system) = &self.rows.system {
            let x_u = std::mem::replace(&mut sol.x, Mat::zeros(0, 0));
            let (x, l, r, steps) =
                system.solve(&self.factor, h_ff, &rhs, &c, x_u, opts.max_refinement_steps);
            (sol.x, sol.residual, lambda) = (x, r, l);
            sol.refinement_steps += steps;
        }
        let f_rows: Vec<&[(usize, f64)]> = match &self.rows.system {
            Some(system) => system.rows().iter().map(|r| &r[..]).collect(),
            None => Vec::new(),
        };
        // Repellors: Newton's method on the total energy from the
        // quadratic solution (no constraints but the known points).
        // Per coordinate 3p + c: its known value, or its row among the unknowns.
        let known: Vec<Option<f64>> = (0..3 * problem.known.len())
            .map(|i| problem.known[i / 3].map(|p| p[i % 3]))
            .collect();
        let mut free_index = vec![usize::MAX; known.len()];
        for (k, &p) in free.iter().enumerate() {
            for c in 0..3 {
                free_index[3 * p + c] = 3 * k + c;
            }
        }
        let repellors: Vec<FreeResiduals> = problem
            .operators
            .iter()
            .zip(placed)
            .filter(|(op, _)| op.repel)
            .map(|(op, (_, res))| FreeResiduals::new(op.strength, res, &known, &free_index))
            .collect();
        let mut xf = sol.x.clone();
        let mut newton_report = None;
        let mut total_gradient = None;
        if !repellors.is_empty() {
            let nf = h_ff.nrows();
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
            let x0: Vec<f64> = (0..nf).map(|i| sol.x[(i, 0)]).collect();
            let (x, report) = newton(&h, &b, &f_rows, &repellors, x0)?;
            // ∇E = H x + b − Σ s ∇q / q², for the report.
            let mut g = b.clone();
            for j in 0..nf {
                for i in 0..nf {
                    g[i] += h_ff[(i, j)] * x[j];
                }
            }
            for r in &repellors {
                let (q, dq) = r.value_and_gradient(&x);
                for (i, d) in dq {
                    g[i] -= r.strength * d / (q * q);
                }
            }
            // With rows, ∇E is balanced by Fᵀλ: Newton's own figure is the
            // gradient of the Lagrangian.
            let norm = if f_rows.is_empty() {
                g.iter().map(|v| v * v).sum::<f64>().sqrt()
            } else {
                report.gradient_norm
            };
            total_gradient = Some((norm, report.relative_gradient));
            xf = Mat::from_fn(nf, 1, |i, _| x[i]);
            newton_report = Some(report);
        }
        let solve = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let checked = self.checked_net(
            problem,
            placed,
            &sys,
            &rows,
            (xf, lambda),
            repellors.is_empty(),
        )?;
        let patch = checked.patch;
        // The check's exact gradient when there is one (no second pass over
        // H), else H X − B in compensated arithmetic.
        let (gradient_norm, relative_gradient) = match (total_gradient, &checked.at) {
            (Some(t), _) => t,
            (None, Some((at, _, _))) => {
                self.exact_gradient(at, &checked.lambda, &sys, &rows, &patch)
            }
            (None, None) => sys.gradient(&self.h, &rows, &patch, self.coupled),
        };
        let rhs_norm = rhs.norm_l2();
        let residual_norm = match total_gradient {
            Some((g, _)) => g,
            None => sol.residual.norm_l2(),
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
        let constraints: Vec<ConstraintOutcome> = problem
            .constraints
            .iter()
            .map(|c| ConstraintOutcome {
                name: c.name.clone(),
                kind: c.constraint.kind(),
                violation: c.constraint.violation(&patch),
            })
            .collect();
        let max_violation = constraints.iter().map(|c| c.violation).fold(0.0, f64::max);
        // The written net must meet the rows as well as it is a minimum:
        // a high-degree net whose coefficients blow up misses them by its
        // rounding, which the energy check alone would not see.
        if let Some((row, miss)) = self.rows.unmet(problem, &patch) {
            return Err(Error::Unmet {
                degree: format!("({}, {})", self.degree.0, self.degree.1),
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
        let check = checked
            .at
            .map(|(at, excess, scale)| {
                for (t, v) in terms.iter_mut().zip(&at.terms) {
                    t.value = v.to_f64();
                }
                let recomputed = at.total.to_f64();
                let check = Check {
                    energy: recomputed,
                    energy_error: (closed_form - recomputed).abs() / scale,
                    excess: excess / scale,
                    scale,
                    corrections: checked.corrections,
                    tolerance: check::TOLERANCE,
                    seconds: t.elapsed().as_secs_f64(),
                };
                if check.passed() {
                    Ok(check)
                } else {
                    Err(Error::Unverified {
                        degree: format!("({}, {})", self.degree.0, self.degree.1),
                        checked: recomputed,
                        excess: check.excess,
                        tolerance: check.tolerance,
                        hint: "A Bernstein net of this degree cannot hold this minimizer to that \
                               accuracy: use a lower degree (the README's limits give the degrees \
                               that verify); B-spline surfaces are planned for more freedom at \
                               low degree."
                            .into(),
                    })
                }
            })
            .transpose()?;
        let energy = match &check {
            Some(c) => c.energy,
            None => closed_form,
        };
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
            newton: newton_report,
            gradient_norm,
            relative_gradient,
            residual,
            condition_estimate: self.factor.condition,
            basis: self.basis.to_string(),
            refinement_steps: sol.refinement_steps,
            unknowns: h_ff.nrows(),
            free_points: free.len(),
            coupled: self.coupled,
            reused,
            measures,
            timings: Timings {
                assemble,
                factor,
                solve,
                analyse,
                total: t_total.elapsed().as_secs_f64(),
            },
        };
        Ok(Solution { patch, report })
    }
}

/// The written net after the independent check and its corrections.
struct Checked {
    patch: TensorPatch,
    /// The recomputed energy and gradient, the estimated excess and the
    /// scale; `None` when a term cannot be checked.
    at: Option<(EnergyAt, f64, f64)>,
    /// The constraints' multipliers (corrected with the net).
    lambda: Vec<f64>,
    corrections: usize,
}

impl Factored {
    /// The net of the free values `xf`, checked on its f64 control points:
    /// energy and gradient in double-double ([`check::tensor`]), the excess
    /// ½ gᵀy with the factor, y = H_FF⁻¹g (with constraints: g the gradient
    /// of the Lagrangian g + Fᵀλ summed in double-double, y the step of
    /// [H Fᵀ; F 0][y; μ] = [g; 0], which moves along the rows). While the
    /// excess is above the tolerance and `correct` (no repellors), Newton
    /// corrections x ← x − y (λ ← λ − μ), kept only when they lower the
    /// recomputed energy and keep the rows to their rounding.
    fn checked_net(
        &self,
        problem: &Problem,
        placed: &[Placed],
        sys: &Rhs,
        rows: &[usize],
        (mut xf, mut lambda): (Mat<f64>, Vec<f64>),
        correct: bool,
    ) -> Result<Checked> {
        let integrands: Vec<_> = problem.terms.iter().map(|t| t.integrand()).collect();
        let operators: Vec<_> = problem
            .operators
            .iter()
            .zip(placed)
            .map(|(op, (_, res))| (op, &res[..]))
            .collect();
        // The rounding floor of the check's scale, from the data (known
        // points, guide surfaces), never from the solution itself.
        let max_diagonal = (0..self.h_ff.nrows())
            .map(|i| self.h_ff[(i, i)])
            .fold(0.0, f64::max);
        let data = problem
            .known
            .iter()
            .flatten()
            .chain(integrands.iter().flatten().flat_map(|i| match i {
                Integrand::GuideSurface { surface, .. } => surface.points(),
                _ => &[],
            }))
            .flatten()
            .fold(0.0, |r: f64, v| r.max(v.abs()));
        let rounding = max_diagonal * (self.h_ff.nrows() * 3 / xf.ncols()) as f64 * data * data;
        let net = |xf: &Mat<f64>| {
            TensorPatch::try_new(
                self.degree.0,
                self.degree.1,
                sys.fill(rows, xf, self.coupled),
            )
            .map_err(|_| Error::NotFinite {
                what: "the solution (the system overflowed)".into(),
            })
        };
        let mut patch = net(&xf)?;
        let mut corrections = 0;
        let Some(mut at) = check::tensor::energy_at(&integrands, &operators, &patch) else {
            return Ok(Checked {
                patch,
                at: None,
                lambda,
                corrections,
            });
        };
        let c = self.rows.rhs(&sys.x)?;
        let mut row_error = self.rows.relative_residuals(&xf, &c);
        loop {
            budget::checkpoint()?;
            let g = self.free_gradient(&at, &lambda);
            let (y, mu) = match &self.rows.system {
                Some(system) => system.apply(&self.factor, &g, &vec![0.0; c.len()]),
                None => (self.factor.apply(&g), Vec::new()),
            };
            let excess = 0.5 * (g.transpose() * &y).diagonal().column_vector().sum().abs();
            let scale = check::scale(at.total.to_f64(), rounding);
            let done = !excess.is_finite() || excess <= check::GOAL * scale;
            if done || !correct || corrections == check::MAX_CORRECTIONS {
                return Ok(Checked {
                    patch,
                    at: Some((at, excess, scale)),
                    lambda,
                    corrections,
                });
            }
            let next_xf = &xf - &y;
            let next = net(&next_xf)?;
            let Some(next_at) = check::tensor::energy_at(&integrands, &operators, &next) else {
                unreachable!("the integrands were evaluated before");
            };
            let next_row_error = self.rows.relative_residuals(&next_xf, &c);
            // Compared in double-double: near the minimum the energies
            // differ far below a double's resolution.
            if (next_at.total - at.total).to_f64() >= 0.0
                || next_row_error > row_error.max(ROW_ROUNDING)
            {
                return Ok(Checked {
                    patch,
                    at: Some((at, excess, scale)),
                    lambda,
                    corrections,
                });
            }
            lambda = lambda.iter().zip(&mu).map(|(l, m)| l - m).collect();
            (xf, patch, at, row_error) = (next_xf, next, next_at, next_row_error);
            corrections += 1;
        }
    }

    /// The recomputed gradient on the free rows, in the system's layout.
    /// (‖g‖₂, normwise backward error ‖g‖∞ / (‖H‖∞‖X‖∞ + ‖B‖∞)) of the
    /// check's exact gradient g at the free coordinates: the figures of
    /// [`Rhs::gradient`] without recomputing them.
    fn exact_gradient(
        &self,
        at: &EnergyAt,
        lambda: &[f64],
        sys: &Rhs,
        rows: &[usize],
        patch: &TensorPatch,
    ) -> (f64, f64) {
        let g = self.free_gradient(at, lambda);
        let (mut g2, mut g_inf) = (0.0, 0.0f64);
        for c in 0..g.ncols() {
            for &v in g.col_as_slice(c) {
                g2 += v * v;
                g_inf = g_inf.max(v.abs());
            }
        }
        let b_inf = rows
            .iter()
            .flat_map(|&r| (0..sys.b.ncols()).map(move |c| (r, c)))
            .fold(0.0f64, |m, (r, c)| m.max(sys.b[(r, c)].abs()));
        let x_inf = patch
            .points()
            .iter()
            .flatten()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let denom = self.h_row_norm * x_inf + b_inf;
        (g2.sqrt(), if denom > 0.0 { g_inf / denom } else { g_inf })
    }

    /// The gradient of the Lagrangian g + Fᵀλ on the free rows (g the
    /// recomputed one, in the system's layout), summed in double-double:
    /// about zero at a solution, its large parts cancel exactly.
    fn free_gradient(&self, at: &EnergyAt, lambda: &[f64]) -> Mat<f64> {
        let g = &at.gradient;
        if self.coupled {
            let mut sum: Vec<Dd> = (0..3 * self.free.len())
                .map(|r| g[r % 3].v[self.free[r / 3]])
                .collect();
            if let Some(system) = &self.rows.system {
                for (row, &l) in system.rows().iter().zip(lambda) {
                    for &(i, a) in row {
                        sum[i] += Dd::new(a) * l;
                    }
                }
            }
            Mat::from_fn(sum.len(), 1, |r, _| sum[r].to_f64())
        } else {
            Mat::from_fn(self.free.len(), 3, |i, c| g[c].v[self.free[i]].to_f64())
        }
    }
}

/// One solve's right-hand side over all control points: E = ½ XᵀHX − BᵀX + c
/// with X of one column per coordinate (per-coordinate layout) or one column
/// of all coordinates point-major (coupled).
struct Rhs {
    b: Mat<f64>,
    /// Known values (free entries 0), laid out like b.
    x: Mat<f64>,
}

impl Rhs {
    /// All control points: known ones as given, free ones (at `rows`) from
    /// the solution.
    fn fill(&self, rows: &[usize], xf: &Mat<f64>, coupled: bool) -> Vec<Vec3> {
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
    fn gradient(
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
        let mut g2 = 0.0;
        let mut g_inf: f64 = 0.0;
        let mut h_inf: f64 = 0.0;
        let mut b_inf: f64 = 0.0;
        for &r in rows {
            let hr = h.col_as_slice(r); // row r of symmetric H
            h_inf = h_inf.max(hr.iter().map(|v| v.abs()).sum());
            for c in 0..x.ncols() {
                let g = -super::dense::dot2_residual(self.b[(r, c)], hr, x.col_as_slice(c));
                g2 += g * g;
                g_inf = g_inf.max(g.abs());
                b_inf = b_inf.max(self.b[(r, c)].abs());
            }
        }
        let denom = h_inf * norm_max(&x) + b_inf;
        (g2.sqrt(), if denom > 0.0 { g_inf / denom } else { g_inf })
    }
}

/// A correction may leave a row's residual at this many units of its size
/// (the rounding of the written net), or where it was if larger.
const ROW_ROUNDING: f64 = 16.0 * f64::EPSILON;

/// The constraints' rows on the free unknowns (the coupled layout: the
/// free point k's coordinate c at 3k + c).
#[derive(Debug)]
struct FreeRows {
    /// Every row over all coordinates (3p + c), as prepared: for the
    /// mismatch test and the known part of each right-hand side.
    all: Vec<Row>,
    /// Per row of `all`: its terms on known coordinates, and whether a free
    /// one enters it (else the known points alone decide it).
    known_terms: Vec<(Vec<(usize, f64)>, bool)>,
    /// The rows with a free coordinate, S factored.
    system: Option<RowSystem>,
}

impl FreeRows {
    fn new(
        all: &[Row],
        free: &[usize],
        factor: &SpdFactor,
        h_ff: &Mat<f64>,
        opts: &SolveOptions,
    ) -> Result<Self> {
        let mut index = std::collections::HashMap::new();
        for (k, &p) in free.iter().enumerate() {
            for c in 0..3 {
                index.insert(3 * p + c, 3 * k + c);
            }
        }
        let (mut reduced, mut names, mut known_terms) = (Vec::new(), Vec::new(), Vec::new());
        for row in all {
            let (on_free, on_known): (Vec<_>, Vec<_>) =
                row.terms.iter().partition(|(i, _)| index.contains_key(i));
            known_terms.push((on_known, !on_free.is_empty()));
            if !on_free.is_empty() {
                reduced.push(on_free.iter().map(|&(i, a)| (index[&i], a)).collect());
                names.push(row.name.clone());
            }
        }
        let system = if reduced.is_empty() {
            None
        } else {
            budget::checkpoint()?;
            Some(RowSystem::new(
                factor,
                h_ff,
                reduced,
                &names,
                opts.max_refinement_steps,
            )?)
        };
        Ok(Self {
            all: all.to_vec(),
            known_terms,
            system,
        })
    }

    /// What makes `rows` differ from these (their right-hand sides may).
    fn mismatch(&self, rows: &[Row]) -> Option<String> {
        if rows.len() != self.all.len() {
            return Some(format!(
                "{} constraint equations instead of {}",
                rows.len(),
                self.all.len()
            ));
        }
        let k = rows
            .iter()
            .zip(&self.all)
            .position(|(a, b)| a.terms != b.terms)?;
        Some(format!(
            "constraint equation {} has another place or direction",
            rows[k].name
        ))
    }

    /// The right-hand sides c = rhs − Σ known a·x of the solved rows for
    /// the known values `x` (coupled layout, one column), compensated.
    /// An error when a row no free coordinate enters is not met.
    fn rhs(&self, x: &Mat<f64>) -> Result<Vec<f64>> {
        let mut c = Vec::new();
        for (row, (known, has_free)) in self.all.iter().zip(&self.known_terms) {
            let a: Vec<f64> = known.iter().map(|&(_, a)| a).collect();
            let xs: Vec<f64> = known.iter().map(|&(i, _)| x[(i, 0)]).collect();
            let r = super::dense::dot2_residual(row.rhs, &a, &xs);
            if *has_free {
                c.push(r);
                continue;
            }
            let size = row.rhs.abs() + a.iter().zip(&xs).map(|(a, x)| (a * x).abs()).sum::<f64>();
            if r.abs() > 1e-12 * size.max(f64::MIN_POSITIVE) && r != 0.0 {
                return Err(Error::Mismatch {
                    what: row.name.clone(),
                    expected: "an equation some free control point enters, or one the known \
                               control points meet"
                        .into(),
                    got: format!(
                        "one the known control points alone decide, missing it by {r:.3e}"
                    ),
                });
            }
        }
        Ok(c)
    }

    /// The worst row the written patch misses by more than the check's
    /// tolerance of the data's size (the largest known coordinate or
    /// right-hand side): its name and the miss over that size.
    fn unmet(&self, problem: &Problem, patch: &TensorPatch) -> Option<(String, f64)> {
        let x: Vec<f64> = patch.points().iter().flatten().copied().collect();
        // The data's size: known points, right-hand sides, operator
        // targets, guide surfaces.
        let max_abs = |v: &[Vec3]| v.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        let mut size = problem
            .known
            .iter()
            .flatten()
            .fold(0.0f64, |m, p| m.max(max_abs(&[*p])));
        for r in &self.all {
            size = size.max(r.rhs.abs());
        }
        for o in &problem.operators {
            size = size.max(o.target.size());
        }
        for t in &problem.terms {
            if let Some(Integrand::GuideSurface { surface, .. }) = t.integrand() {
                size = size.max(max_abs(surface.points()));
            }
        }
        let size = size.max(f64::MIN_POSITIVE);
        self.all
            .iter()
            .map(|row| {
                let a: Vec<f64> = row.terms.iter().map(|&(_, a)| a).collect();
                let xs: Vec<f64> = row.terms.iter().map(|&(i, _)| x[i]).collect();
                let miss = super::dense::dot2_residual(row.rhs, &a, &xs).abs() / size;
                (row.name.clone(), miss)
            })
            .filter(|(_, miss)| miss.is_nan() || *miss > check::TOLERANCE)
            .max_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// max over the solved rows of |c − F x| / (Σ|a x| + |c|) at the free
    /// values `xf` (0 without rows).
    fn relative_residuals(&self, xf: &Mat<f64>, c: &[f64]) -> f64 {
        let Some(system) = &self.system else {
            return 0.0;
        };
        let x = xf.col_as_slice(0);
        system
            .rows()
            .iter()
            .zip(c)
            .map(|(row, &ci)| {
                let a: Vec<f64> = row.iter().map(|&(_, a)| a).collect();
                let xs: Vec<f64> = row.iter().map(|&(i, _)| x[i]).collect();
                let r = super::dense::dot2_residual(ci, &a, &xs);
                let size = ci.abs() + a.iter().zip(&xs).map(|(a, x)| (a * x).abs()).sum::<f64>();
                if size > 0.0 {
                    r.abs() / size
                } else {
                    0.0
                }
            })
            .fold(0.0, f64::max)
    }
}
