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

use super::builder::Problem;
use super::dense::{SpdFactor, SpdOptions};
use super::factored::Factored;
use super::jacobi::TensorBasis;
use super::report::SolveReport;
use super::rows::FreeRows;
use crate::budget;
use crate::constraint::Row;
use crate::energy::Integrand;
use crate::energy::Space;
use crate::energy::{Hessian, TermForm};
use crate::operator::tensor::TensorLocated;
use crate::operator::{Residual, TensorOperator};
use crate::vec3::{is_finite, Vec3};
use crate::{Error, Result, TensorPatch};
use faer::Mat;
use std::time::Instant;

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
    /// Let the check's Newton corrections polish the written net to
    /// double-double's resolution (relative excess 1e-32, or until a
    /// correction would move the net by less than its rounding, 4ε;
    /// default true).
    /// Off, the net as solved is kept once its excess meets the check's
    /// tolerance (1e-10) and the correction would move no free coordinate
    /// by more than 1e-6 of the net's size; otherwise it is corrected as
    /// with polishing (from degree ~15 a net can meet the energy tolerance
    /// while off in nearly energy-free directions). For the editor's quick
    /// answers: the degree-10 example's solve leaves the net ~2e-25 above
    /// its minimum and ~1e-8 off, and the second double-double evaluation
    /// is skipped. The report's `check.excess` and `check.corrections` say
    /// what was met; Bézier patches only.
    pub polish: bool,
}

impl Default for SolveOptions {
    fn default() -> Self {
        Self {
            max_refinement_steps: 30,
            estimate_condition: true,
            singular_condition: 1e15,
            analyse: true,
            tensor_basis: true,
            polish: true,
        }
    }
}

impl SolveOptions {
    /// Sets [`SolveOptions::analyse`].
    pub fn with_analyse(mut self, on: bool) -> Self {
        self.analyse = on;
        self
    }

    /// Sets [`SolveOptions::polish`].
    pub fn with_polish(mut self, on: bool) -> Self {
        self.polish = on;
        self
    }

    /// Sets [`SolveOptions::estimate_condition`].
    pub fn with_condition_estimate(mut self, on: bool) -> Self {
        self.estimate_condition = on;
        self
    }
}

/// A solved problem: the surface and how good it is — `Solution` for a
/// Bézier patch ([`Problem`]), `Solution<BSplineSurface>`
/// ([`crate::bspline::BSplineSolution`]) for a B-spline surface
/// ([`crate::bspline::BSplineProblem`]), `Solution<TriSurface>`
/// ([`crate::triangle::TriSolution`]) for a triangular surface.
#[derive(Clone, Debug)]
pub struct Solution<S = TensorPatch> {
    /// The surface with every control point filled.
    pub surface: S,
    /// Energies, gradient, residual, conditioning, timings: one report for
    /// every kind.
    pub report: SolveReport,
}

impl Problem {
    /// A problem of degree (n, m) with every control point free and no terms.
    pub fn new(degree: (usize, usize)) -> Self {
        let n = (degree.0 + 1) * (degree.1 + 1);
        let zero = TensorPatch::new(degree.0, degree.1, vec![[0.0; 3]; n]);
        Self::over(zero, vec![true; n])
    }

    /// (n, m).
    pub fn degree(&self) -> (usize, usize) {
        self.surface.degree()
    }

    /// Known control points (`None` = free), row-major.
    pub fn known(&self) -> Vec<Option<Vec3>> {
        (0..self.free.len()).map(|k| self.known_at(k)).collect()
    }

    /// Control point k (row-major) when it is known.
    pub(crate) fn known_at(&self, k: usize) -> Option<Vec3> {
        (!self.free[k]).then(|| self.surface.points()[k])
    }

    /// Fixes P_ij at p.
    ///
    /// # Panics
    /// If (i, j) is outside the net.
    pub fn fix(&mut self, i: usize, j: usize, p: Vec3) -> &mut Self {
        let (n, m) = self.degree();
        assert!(i <= n && j <= m, "control point ({i}, {j}) outside the net");
        self.hold(i * (m + 1) + j, p);
        self
    }

    /// Sets the known points all at once (`None` = free), row-major.
    pub fn with_known(mut self, known: Vec<Option<Vec3>>) -> Result<Self> {
        if known.len() != self.free.len() {
            return Err(Error::ControlPointCount {
                degree: self.degree(),
                expected: self.free.len(),
                got: known.len(),
            });
        }
        for (k, p) in known.into_iter().enumerate() {
            match p {
                Some(p) => self.hold(k, p),
                None => self.free[k] = true,
            }
        }
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
        assert_eq!(net.degree(), self.degree(), "net degree");
        self.surface = net.clone();
        self.fix_rings(k)
    }

    /// A patch of this degree with every control point at the origin: what
    /// the constraints' weights need (they depend on the degree only).
    fn blank(&self) -> TensorPatch {
        TensorPatch::new(
            self.degree().0,
            self.degree().1,
            vec![[0.0; 3]; self.free.len()],
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
        let free = self.free_list();
        if free.is_empty() {
            return Err(Error::NoFreePoints {
                why: "every control point is known".into(),
            });
        }
        for k in 0..self.free.len() {
            if self.known_at(k).is_some_and(|p| !is_finite(p)) {
                let m = self.degree().1;
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
                let at = op.locate(self.degree())?;
                let res = op.residuals(&at, self.degree());
                Ok((at, res))
            })
            .collect()
    }

    pub(super) fn factor_prepared(&self, opts: &SolveOptions, prep: &Prepared) -> Result<Factored> {
        let (free, placed) = (&prep.free, &prep.placed[..]);
        budget::reserve(
            &format!("the degree {:?} system", self.degree()),
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
        let (system, pre) = if self.free.len() >= PARALLEL_ASSEMBLY {
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
        let basis = if pre.is_some() { "jacobi" } else { "bernstein" };
        let factor = SpdFactor::new(&h_ff, spd, &self.hint(), pre)?;
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
            degree: self.degree(),
            free: free.clone(),
            known: self.free.iter().map(|f| !f).collect(),
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
            basis,
            factor,
            rows,
            assemble_seconds,
        })
    }

    /// The terms' forms, whether they couple the coordinates, the system H
    /// over all control points (with the attractors' and directors'
    /// quadratic terms) and its free block H_FF.
    fn bernstein_system(&self, free: &[usize], placed: &[Placed]) -> Result<BernsteinSystem> {
        let mut forms = self
            .terms
            .iter()
            .map(|t| {
                budget::checkpoint()?;
                t.form(self.degree())
            })
            .collect::<Result<Vec<_>>>()?;
        // Operators and constraints couple the coordinates.
        let coupled = !self.operators.is_empty()
            || !self.constraints.is_empty()
            || forms
                .iter()
                .any(|f| matches!(f.hessian, Hessian::Coupled(_)));
        let mut h = hessian_sum(&mut forms, self.free.len(), coupled);
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
        let space = Space::jacobi(self.degree(), ru, rv);
        let mut forms = self
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
        let h = hessian_sum(&mut forms, space.len(), coupled);
        Ok(TensorBasis::from_space(&space, if coupled { 3 } else { 1 }).map(|q| (h, q)))
    }

    /// Estimated peak bytes of a solve: the dense system over all control
    /// points (3 per point when a term or operator may couple the
    /// coordinates), one such matrix per term's form, H, H_FF, the factor
    /// and the basis change: 8 · dim² · (terms + 4).
    pub fn memory_estimate(&self) -> f64 {
        let np = self.free.len() as f64;
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
        let (n, m) = self.degree();
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

    pub(super) fn hint(&self) -> String {
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
pub(super) fn add_hessian(h: &mut Mat<f64>, term: &Hessian, coupled: bool) {
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
pub(super) fn gather(h: &Mat<f64>, rows: &[usize]) -> Mat<f64> {
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
pub(super) fn center_rhs(term: &Hessian, s: &[Vec3], coupled: bool) -> Mat<f64> {
    let np = s.len();
    match term {
        Hessian::PerCoordinate(m) => {
            let r = super::dense::product(m.as_ref(), Mat::from_fn(np, 3, |p, c| s[p][c]).as_ref());
            if coupled {
                Mat::from_fn(3 * np, 1, |i, _| r[(i / 3, i % 3)])
            } else {
                r
            }
        }
        Hessian::Coupled(m) => super::dense::product(
            m.as_ref(),
            Mat::from_fn(3 * np, 1, |i, _| s[i / 3][i % 3]).as_ref(),
        ),
    }
}

/// Σ of the terms' Hessians in the system's layout. The first centre-less
/// form already in that layout is taken over as the sum (its place left an
/// empty 0 × 0 matrix): only the centred forms are read afterwards.
pub(super) fn hessian_sum(forms: &mut [TermForm], np: usize, coupled: bool) -> Mat<f64> {
    let dim = if coupled { 3 * np } else { np };
    // A form already in the system's layout whose matrix nothing else reads
    // (no centre) becomes the sum: no second system-sized matrix to zero and
    // add (at degree 20 with a normal field, 14 MB of fresh pages).
    let own = forms.iter().position(|f| {
        f.center.is_none()
            && match &f.hessian {
                Hessian::Coupled(m) => coupled && m.nrows() == dim,
                Hessian::PerCoordinate(m) => !coupled && m.nrows() == dim,
            }
    });
    let mut h = match own {
        Some(k) => match std::mem::replace(
            &mut forms[k].hessian,
            Hessian::PerCoordinate(Mat::zeros(0, 0)),
        ) {
            Hessian::Coupled(m) | Hessian::PerCoordinate(m) => m,
        },
        None => Mat::<f64>::zeros(dim, dim),
    };
    for (k, f) in forms.iter().enumerate() {
        if Some(k) != own {
            add_hessian(&mut h, &f.hessian, coupled);
        }
    }
    h
}

/// An operator's place on the patch and its residuals.
pub(super) type Placed = (TensorLocated, Vec<Residual>);

/// Forms, coupled, H, H_FF ([`Problem::bernstein_system`]).
pub(super) type BernsteinSystem = (Vec<TermForm>, bool, Mat<f64>, Mat<f64>);

/// From this many control points on, the Bernstein system and the Jacobi
/// preconditioner are assembled on two threads (degree 9×9 and up: below,
/// a thread costs more than it saves).
const PARALLEL_ASSEMBLY: usize = 100;

/// A problem checked, its operators placed and its terms' Hessian keys
/// taken ([`Problem::prepare`]).
pub(crate) struct Prepared {
    pub(super) free: Vec<usize>,
    pub(super) placed: Vec<Placed>,
    /// The constraints' rows over all coordinates (3p + c).
    pub(super) rows: Vec<Row>,
    pub(super) keys: Vec<Option<u64>>,
}

/// (2 s w, r) for each residual r of the attractors and directors: their
/// quadratic energy s Σ w (a·x − t)² adds 2 s w a aᵀ to H and 2 s w t a to
/// b. Repellors wait for Newton's method.
pub(super) fn quadratic_residuals<'a>(
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
pub(super) type ResidualShape = (f64, Vec<(usize, f64)>);

/// Row indices of the free unknowns in the system's layout.
pub(super) fn free_rows(free: &[usize], coupled: bool) -> Vec<usize> {
    if coupled {
        free.iter()
            .flat_map(|&p| (0..3).map(move |c| 3 * p + c))
            .collect()
    } else {
        free.to_vec()
    }
}
