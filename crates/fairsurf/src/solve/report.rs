//! What a solve says about its result: every number needed to judge it.

/// The value of one energy term at the solution.
#[derive(Clone, Debug, PartialEq)]
pub struct TermEnergy {
    /// The term's name ("stretch", "bend", "normal_field", "guide_surface", …).
    pub name: String,
    /// Its value, weights included.
    pub value: f64,
}

/// Wall-clock seconds spent in each stage (for a B-spline surface see
/// [`crate::bspline::BSplineProblem::solve`] for what each holds; for a
/// triangular surface `assemble` is the energy matrix and constraint rows,
/// `factor` 0 (the KKT factorization is in `solve`, with its refinement),
/// `analyse` the check on the written net with its corrections and the
/// outcomes, energies and edge angles measured on the result, and the mesh
/// refinement and row classification are [`TriFigures`]' own phases).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// Building every term's quadratic form and the system.
    pub assemble: f64,
    /// Cholesky factorization.
    pub factor: f64,
    /// Triangular solves, refinement and condition estimate.
    pub solve: f64,
    /// Area, functionals and other measures of the result.
    pub analyse: f64,
    /// Everything.
    pub total: f64,
}

/// Everything a solve knows about its answer: one report for every surface
/// kind (a Bézier patch's [`crate::Problem`], a B-spline surface's
/// [`crate::bspline::BSplineProblem`], a triangular surface's
/// [`crate::triangle::TriProblem`]), every figure defined once; what only a
/// triangular surface has (its mesh, continuity rows, edge angles) in
/// [`SolveReport::triangular`].
#[derive(Clone, Debug, PartialEq)]
pub struct SolveReport {
    /// Each term's energy at the solution.
    pub terms: Vec<TermEnergy>,
    /// Their sum and the operators': the minimized energy (a Bézier patch's
    /// as the check recomputed it, a B-spline surface's from the closed
    /// forms, which its check confirms).
    pub energy: f64,
    /// The independent check of the written net ([`crate::Check`]: for a
    /// Bézier patch energy and gradient recomputed in double-double, for a
    /// B-spline surface the energy by Gauss quadrature span by span and the
    /// excess from the assembled system in compensated arithmetic, for a
    /// triangular surface energy and gradient in double-double); `None`
    /// when a term does not describe its integrand
    /// ([`crate::EnergyTerm::integrand`]) or, for a triangular surface,
    /// when nothing was free. A report is returned only when its check
    /// passed.
    pub check: Option<crate::Check>,
    /// The external operators' energy (Veltkamp & Wesselink §5), in `energy`.
    pub external: f64,
    /// Each operator's energy and how far its target is met.
    pub operators: Vec<crate::operator::OperatorOutcome>,
    /// Each constraint's violation on the result (met to rounding).
    pub constraints: Vec<crate::constraint::ConstraintOutcome>,
    /// The largest of them (0 without constraints).
    pub max_violation: f64,
    /// With repellors: how Newton's method went (then `gradient_norm` and
    /// `relative_gradient` are those of the total, nonlinear energy).
    pub newton: Option<crate::operator::NewtonReport>,
    /// ‖∂E/∂x‖∞ over the free coordinates (of the Lagrangian ∂E/∂x + Fᵀλ
    /// with constraints), computed in twice-working precision.
    pub gradient_norm: f64,
    /// Normwise backward error ‖g‖∞ / (‖H‖∞‖x‖∞ + ‖b‖∞) (rows of the free
    /// coordinates): how far the energy would have to be perturbed for the
    /// result to be its exact minimizer. About ε means as good as double allows.
    pub relative_gradient: f64,
    /// ‖rhs − H x‖∞ / ‖rhs‖∞ of the reduced system solved (the absolute
    /// figure when the right-hand side is 0; NaN for a triangular surface
    /// with nothing free, which solved nothing).
    pub residual: f64,
    /// Estimated condition number of the matrix actually factored: for a
    /// Bézier patch the 2-norm one of the equilibrated reduced system, in
    /// the basis named by `basis`; for a B-spline surface Hager's
    /// ‖H‖₁‖H⁻¹‖₁ (of the KKT matrix with constraints); for a triangular
    /// surface its KKT solve's (`kkt`; NaN when nothing was solved).
    pub condition_estimate: f64,
    /// The basis the system was factored in: "jacobi" (tensor block of free
    /// points: orthogonal Jacobi-weighted polynomials, refinement on the
    /// Bernstein system), "bernstein" (any other free set of a Bézier
    /// patch), "b-spline" (a B-spline surface's own basis, sparse) or
    /// "triangular" (the triangular Bernstein basis of the patches' global
    /// control points, sparse KKT).
    pub basis: String,
    /// Iterative refinement steps taken.
    pub refinement_steps: usize,
    /// Number of scalar unknowns solved for.
    pub unknowns: usize,
    /// Number of free control points (of a triangular surface: those with
    /// a free coordinate).
    pub free_points: usize,
    /// Whether the coordinates were coupled (a normal-field term, operators,
    /// constraints that mix x, y and z) or solved as three systems with one
    /// matrix.
    pub coupled: bool,
    /// Whether the factorization came from an earlier solve. A Bézier
    /// patch ([`crate::Factored::solve`]): only the right-hand side was
    /// rebuilt, `timings.factor` is then 0 and `timings.assemble` is the
    /// right-hand side's. A B-spline surface
    /// ([`crate::FactorCache::solve_bspline`]): the system was assembled
    /// anew and found equal, value for value, to the kept factor's;
    /// `timings.factor` is then building and comparing the sparse matrix.
    /// A triangular surface ([`crate::FactorCache::solve_triangular`]): the
    /// KKT matrix was assembled and found equal to the kept one's. With
    /// repellors Newton's method still factors its own steps.
    pub reused: bool,
    /// Whether the factorization of an earlier solve with the same
    /// pattern lent its ordering and elimination tree (a weight changed;
    /// only the numbers were factored): B-spline surfaces through
    /// [`crate::FactorCache::solve_bspline`], triangular ones' KKT
    /// factorizations; always false for the dense Bézier solve, which has
    /// no ordering.
    pub reused_symbolic: bool,
    /// Area and functionals of the result (`None` when analysis was off,
    /// and for a triangular surface, whose measures are in
    /// [`Self::triangular`] and the analysis functions).
    pub measures: Option<crate::analysis::SurfaceMeasures>,
    /// Nonzeros of the sparse factor (a B-spline surface without
    /// constraints; with them, and for a triangular surface, the KKT
    /// factor's, also in `kkt`); `None` for the dense solve.
    pub factor_nonzeros: Option<usize>,
    /// The sparse KKT solve of a B-spline surface with constraints or of a
    /// triangular surface (which factorization, its size, residual and
    /// condition; `residual` and `condition_estimate` are then its
    /// figures); `None` otherwise.
    pub kkt: Option<crate::solve::kkt::KktInfo>,
    /// Time per stage.
    pub timings: Timings,
    /// What only a triangular surface's solve has: `None` for the tensor
    /// kinds.
    pub triangular: Option<Box<TriFigures>>,
}

/// The figures of a triangular surface's solve that the tensor kinds do
/// not have (Veltkamp & Wesselink: a mesh of patches joined by continuity
/// conditions, refined along curve constraints).
#[derive(Clone, Debug, PartialEq)]
pub struct TriFigures {
    /// Patches of the result (curves refine the mesh).
    pub patches: usize,
    /// Mesh vertices.
    pub vertices: usize,
    /// Global control points.
    pub points: usize,
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
    pub dropped: Vec<crate::triangle::DroppedRow>,
    /// User rows that contradict earlier user constraints; the surface
    /// cannot meet them (their violations say by how much).
    pub inconsistent: Vec<crate::triangle::DroppedRow>,
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
    pub normal_turn: Option<crate::analysis::TriNormalTurn>,
    /// Seconds refining the mesh for curve constraints (a phase of its
    /// own, before `timings.assemble`; in `timings.total`).
    pub refine_seconds: f64,
    /// Seconds classifying the rows as independent, dependent or
    /// inconsistent (a phase of its own between `timings.assemble` and
    /// `timings.solve`; in `timings.total`).
    pub classify_seconds: f64,
    /// How many times the rows were classified: once per row tolerance
    /// tried (a kept factorization's tolerance too: the right-hand side
    /// decides which rows are dependent or inconsistent), except that one
    /// classification serves every tolerance it would come to the same at
    /// (no row's reduced coefficient between them).
    pub classifications: usize,
    /// How many KKT systems were factored: once per tolerance tried,
    /// except that a tolerance keeping the same rows as the one before
    /// takes its outcome; 0 when a kept factorization solved it as it is.
    pub factorizations: usize,
    /// Per patch of the result, the problem's triangle it came from and its
    /// corners there in barycentric coordinates (curve constraints split
    /// patches; otherwise each patch its own triangle).
    pub origin: Vec<(usize, [[f64; 3]; 3])>,
    /// The global control points of the result that were held (fixed
    /// constraints, the boundary if fixed, the curves' chain edges).
    pub fixed: Vec<usize>,
}

impl SolveReport {
    /// The energy of the terms named `name` ("stretch", "bend",
    /// "normal_field", "guide_surface", …), weights included; 0 when the
    /// problem has no such term.
    pub fn term(&self, name: &str) -> f64 {
        self.terms
            .iter()
            .filter(|t| t.name == name)
            .map(|t| t.value)
            .sum()
    }
}
