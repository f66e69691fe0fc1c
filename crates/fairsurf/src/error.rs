//! The one error type of the math crate.

/// Everything that can go wrong in fairsurf's math: each variant carries the
/// offending data (which term, which index, expected against got).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A control net has the wrong number of points for its degree.
    #[error("a degree {degree:?} net needs {expected} control points, got {got}")]
    ControlPointCount {
        /// (n, m) of the net.
        degree: (usize, usize),
        /// (n+1)(m+1).
        expected: usize,
        /// What was given.
        got: usize,
    },
    /// A Bézier curve needs at least one control point.
    #[error("a Bézier curve needs at least one control point")]
    EmptyCurve,
    /// A knot vector breaks a rule of clamped B-splines (see
    /// [`crate::bspline::KnotVector::new`]).
    #[error("knots: {why}")]
    Knots {
        /// Which rule, at which knot.
        why: String,
    },
    /// A number that must be finite is NaN or infinite.
    #[error("{what} is not finite")]
    NotFinite {
        /// Which value, e.g. "control point (2, 3)".
        what: String,
    },
    /// A weight that must be ≥ 0 is negative.
    #[error("{what} must be ≥ 0, got {value}")]
    NegativeWeight {
        /// Which weight.
        what: String,
        /// Its value.
        value: f64,
    },
    /// A degree or size that must match another does not.
    #[error("{what}: expected {expected}, got {got}")]
    Mismatch {
        /// What is compared.
        what: String,
        /// What was needed.
        expected: String,
        /// What was given.
        got: String,
    },
    /// A prescribed normal is zero, so it has no direction.
    #[error("{what} is the zero vector and has no direction")]
    ZeroNormal {
        /// Which normal.
        what: String,
    },
    /// Nothing to solve for.
    #[error("no free control points: {why}")]
    NoFreePoints {
        /// Why (e.g. which rings are fixed at which degree).
        why: String,
    },
    /// The problem has no energy term to minimize.
    #[error("the problem has no energy term: add stretch, bend, normal_field or guide_surface")]
    NoEnergy,
    /// A free control point has no initial value but one is needed.
    #[error("{what}")]
    MissingValue {
        /// What is missing and why it is needed.
        what: String,
    },
    /// The energy does not determine the free control points.
    #[error(
        "the system for the {unknowns} free coordinates is not positive definite \
         (Cholesky pivot {pivot} failed): {hint}"
    )]
    NotPositiveDefinite {
        /// Number of unknowns.
        unknowns: usize,
        /// Index of the failing pivot.
        pivot: usize,
        /// What usually causes it for this problem.
        hint: String,
    },
    /// The system is numerically singular: its estimated condition number is
    /// beyond what double precision can resolve.
    #[error(
        "the system for the {unknowns} free coordinates is numerically singular \
         (condition number ≈ {condition:.2e}): {hint}"
    )]
    Singular {
        /// Number of unknowns.
        unknowns: usize,
        /// Estimated 2-norm condition number of the equilibrated system.
        condition: f64,
        /// What usually causes it.
        hint: String,
    },
    /// A construction's equations have no exact solution for the given data.
    #[error("{what} (least-squares residual {residual:.3e} relative to the net): {hint}")]
    Inconsistent {
        /// What does not exist.
        what: String,
        /// max |equation| / max |P| of the least-squares net.
        residual: f64,
        /// What to do instead.
        hint: String,
    },
    /// An iterative solve stopped before its tolerance.
    #[error(
        "{what} did not converge: relative gradient {relative_gradient:.2e} after \
         {iterations} iterations (tolerance {tolerance:.0e}); {hint}"
    )]
    NotConverged {
        /// Which solve.
        what: String,
        /// Iterations taken.
        iterations: usize,
        /// The scale-free stationarity residual reached.
        relative_gradient: f64,
        /// The tolerance asked for.
        tolerance: f64,
        /// What usually helps.
        hint: String,
    },
    /// The work would need more memory than its budget allows
    /// ([`crate::budget`]).
    #[error(
        "{what} would need about {:.2} GB, more than the limit of {:.2} GB; \
         lower the degree or the number of patches, or raise the limit \
         (fairsurf --max-memory-gb)",
        estimate / 1e9,
        limit / 1e9
    )]
    TooLarge {
        /// What was estimated.
        what: String,
        /// The estimate, in bytes.
        estimate: f64,
        /// The limit, in bytes.
        limit: f64,
    },
    /// The work was cancelled (a timeout, or the client went away).
    #[error("the solve was cancelled")]
    Cancelled,
    /// A constraint's equation is (nearly) a combination of the ones before
    /// it: a repeated constraint, or one the others already decide.
    #[error(
        "{row}: this equation depends on the constraints before it (a repeated constraint, \
         or one the others already decide); remove it or move it"
    )]
    DependentConstraint {
        /// The equation's name (constraint and which of its equations).
        row: String,
    },
    /// The solve's answer failed the independent check on the written net
    /// ([`crate::Check`]) even after Newton corrections with the exact
    /// gradient: double precision cannot deliver this problem's minimizer
    /// as a net of this degree.
    #[error(
        "the solution at degree {degree} cannot be verified in double precision: \
         recomputed in double-double on the written net, its energy {checked:.12e} lies \
         {excess:.1e} (relative) above the minimum, and the tolerance is {tolerance:.0e}. {hint}"
    )]
    Unverified {
        /// The patches' degree: `(n, m)` for a tensor patch, `n` for
        /// triangular ones.
        degree: String,
        /// The energy recomputed in double-double.
        checked: f64,
        /// Estimated excess over the minimum, relative to the energy.
        excess: f64,
        /// The tolerance.
        tolerance: f64,
        /// What to do.
        hint: String,
    },
    /// The written net misses a constraint by more than the check's
    /// tolerance: double precision cannot hold this constrained minimizer
    /// as a net of this degree.
    #[error(
        "the solution at degree {degree} cannot meet {row} in double precision: the written \
         net misses it by {miss:.1e} of the data's size (tolerance {tolerance:.0e}). Use a \
         lower degree (the README's limits give the degrees that verify)."
    )]
    Unmet {
        /// The patches' degree: `(n, m)` for a tensor patch, `n` for
        /// triangular ones.
        degree: String,
        /// The constraint equation missed the most.
        row: String,
        /// By how much, over the data's size.
        miss: f64,
        /// The tolerance.
        tolerance: f64,
    },
    /// A hole cannot be filled as asked (see [`crate::fill`]).
    #[error("cannot fill the hole: {why}")]
    Fill {
        /// What is wrong, and where.
        why: String,
    },
}

/// `Result` with fairsurf's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
