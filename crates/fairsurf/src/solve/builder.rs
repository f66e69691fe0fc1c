//! One problem type for every surface kind: the surface (its basis, the
//! known points' values, where the free ones start), which control points
//! are free, the energy terms, the constraints at points of the domain and
//! the external energy operators. What the kinds share is built here once;
//! each kind adds its constructors and its solve (a Bézier patch's dense
//! solve in `problem.rs`, a B-spline's sparse one in `crate::bspline`, a
//! triangular surface's KKT solve in `crate::triangle`).

use crate::bspline::BSplineSurface;
use crate::constraint::NamedConstraint;
use crate::energy::{EnergyTerm, Integrand, NormalField};
use crate::operator::{Operator, TensorPlace};
use crate::surface::ControlNet;
use crate::tensor::{TensorConstraint, Uv};
use crate::{Error, Result, TensorPatch};
use std::sync::Arc;

mod sealed {
    /// Only the crate's surface kinds are [`super::SurfaceKind`]s: each
    /// needs a solve of its own.
    pub trait Sealed {}
    impl Sealed for crate::TensorPatch {}
    impl Sealed for crate::bspline::BSplineSurface {}
    impl Sealed for crate::TriSurface {}
}

/// A surface kind a [`Problem`] is posed on: where its constraints sit,
/// where its operators act, and what only its problems hold. Bézier
/// patches, B-spline surfaces and triangular surfaces are the kinds.
pub trait SurfaceKind: Clone + std::fmt::Debug + sealed::Sealed {
    /// A point of the surface's domain: (u, v) of a tensor surface, a
    /// triangle and barycentric coordinates of a triangular one.
    type At: Clone + std::fmt::Debug + PartialEq;
    /// Where an operator acts ([`Operator`]).
    type Place: Clone + std::fmt::Debug + PartialEq;
    /// What only this kind's problems hold (a triangular surface's curve
    /// constraints and continuity; nothing for the tensor kinds).
    type Extra: Clone + std::fmt::Debug + Default;
}

impl SurfaceKind for TensorPatch {
    type At = Uv;
    type Place = TensorPlace;
    type Extra = ();
}

impl SurfaceKind for BSplineSurface {
    type At = Uv;
    type Place = TensorPlace;
    type Extra = ();
}

/// A variational problem over a surface of kind `S`: a Bézier patch
/// (`Problem`, the default), a B-spline surface
/// (`Problem<BSplineSurface>`, [`crate::bspline::BSplineProblem`]) or a
/// triangular surface (`Problem<TriSurface>`,
/// [`crate::triangle::TriProblem`]).
///
/// The same energy terms ([`crate::Stretch`], [`crate::Bend`],
/// [`crate::NormalField`], [`crate::GuideSurface`]) and operators
/// ([`Operator`]) serve every kind, and constraints at a point of the
/// domain ([`crate::constraint::Constraint`] at (u, v) or at a triangle's
/// barycentric point); the kinds differ in how a problem is made (a
/// degree, a B-spline surface with its knots, a triangle mesh with curves
/// and continuity), in which terms their assembly can integrate (a
/// triangular surface: stretch and bend), and in how it is solved (dense
/// in the Jacobi basis, sparse and banded, sparse KKT).
///
/// ```
/// use fairsurf::{Problem, Stretch, TensorPatch};
/// // A 3×3 net with a lifted middle: fix the boundary, free the centre.
/// let net = TensorPatch::from_fn(2, 2, |i, j| [i as f64, j as f64, if (i, j) == (1, 1) { 5.0 } else { 0.0 }]);
/// let sol = Problem::new((2, 2)).with_fixed_rings(&net, 1).with_term(Stretch::new(1.0)).solve().unwrap();
/// // The Dirichlet extremal of a planar boundary is planar.
/// assert!(sol.surface.point(1, 1)[2].abs() < 1e-14);
/// assert!(sol.report.relative_gradient < 1e-14);
/// ```
#[derive(Clone, Debug)]
pub struct Problem<S: SurfaceKind = TensorPatch> {
    /// The basis and every control point: the known points' values, and
    /// where the free ones start (a quadratic energy ignores it; Newton's
    /// method for repellors starts from the quadratic solution).
    pub(crate) surface: S,
    /// One flag per control point, row-major (a triangular surface's
    /// points are held by `Fixed` constraints instead: all true there).
    pub(crate) free: Vec<bool>,
    /// Shared, so a problem clones cheaply (the editor's drags, sweeps).
    pub(crate) terms: Vec<Arc<dyn EnergyTerm>>,
    pub(crate) operators: Vec<Operator<S::Place>>,
    pub(crate) constraints: Vec<NamedConstraint<S::At>>,
    /// What only this kind's problems hold.
    pub(crate) extra: S::Extra,
}

impl<S: SurfaceKind> Problem<S> {
    /// The surface: its basis, the known points' values and the free
    /// points' starting values.
    pub fn surface(&self) -> &S {
        &self.surface
    }

    /// Adds an energy term: [`crate::Stretch`], [`crate::Bend`],
    /// [`crate::NormalField`], [`crate::GuideSurface`] or one of your own
    /// (a Bézier patch's solve takes any [`EnergyTerm`]; a B-spline's and a
    /// triangular surface's assemble the terms from their
    /// [`EnergyTerm::integrand`] and refuse, naming it, one they cannot
    /// integrate).
    pub fn with_term(mut self, term: impl EnergyTerm + 'static) -> Self {
        self.terms.push(Arc::new(term));
        self
    }

    /// Adds a boxed energy term.
    pub fn push_term(&mut self, term: Box<dyn EnergyTerm>) {
        self.terms.push(Arc::from(term));
    }

    /// The energy terms.
    pub fn terms(&self) -> &[Arc<dyn EnergyTerm>] {
        &self.terms
    }

    /// The (first) normal-field term's λ and guide, when there is one (the
    /// normals a report's deviation is measured against; a triangular
    /// surface's solve refuses such a term).
    pub fn normal_field(&self) -> Option<NormalField> {
        self.terms.iter().find_map(|t| match t.integrand() {
            Some(Integrand::NormalField { weight, guide }) => Some(NormalField {
                weight,
                guide: guide.clone(),
            }),
            _ => None,
        })
    }

    /// Adds an external energy operator (Veltkamp & Wesselink §5) at a point
    /// or a region of the domain: a director, or a point, plane, line or
    /// surface attractor join the quadratic energy; a repellor makes the
    /// solve nonlinear (Newton's method from the quadratic solution). The
    /// solve refuses an invalid one, naming it.
    pub fn with_operator(mut self, operator: Operator<S::Place>) -> Self {
        self.operators.push(operator);
        self
    }

    /// The external energy operators.
    pub fn operators(&self) -> &[Operator<S::Place>] {
        &self.operators
    }

    /// The constraints at points of the domain.
    pub fn constraints(&self) -> &[NamedConstraint<S::At>] {
        &self.constraints
    }

    /// A problem over `surface` with the given free flags and nothing else.
    pub(crate) fn over(surface: S, free: Vec<bool>) -> Self {
        Self {
            surface,
            free,
            terms: Vec::new(),
            operators: Vec::new(),
            constraints: Vec::new(),
            extra: S::Extra::default(),
        }
    }
}

impl<S: ControlNet + SurfaceKind<At = Uv>> Problem<S> {
    /// A problem over `surface` with every control point held at its value
    /// and no energy yet: free points with [`Self::with_free`] (or a kind's
    /// `with_fixed_rings`), then terms, constraints and operators.
    pub fn from_surface(surface: S) -> Self {
        let n = surface.points().len();
        Self::over(surface, vec![false; n])
    }

    /// The free flags, one per control point (row-major).
    pub fn free(&self) -> &[bool] {
        &self.free
    }

    /// Sets which control points are free (row-major, one flag per point).
    /// The others are held at the surface's values: for a problem made by
    /// `Problem::new(degree)`, the origin — give their values with `fix`,
    /// `with_known` or [`Self::from_surface`].
    pub fn with_free(mut self, free: Vec<bool>) -> Result<Self> {
        if free.len() != self.free.len() {
            let (a, b) = self.surface.counts();
            return Err(Error::Mismatch {
                what: format!("free flags of the {a} × {b} net"),
                expected: self.free.len().to_string(),
                got: free.len().to_string(),
            });
        }
        self.free = free;
        Ok(self)
    }

    /// The outer `k` rings of the surface's net held at their values and
    /// every other point freed.
    pub(crate) fn fix_rings(mut self, k: usize) -> Self {
        let (cu, cv) = self.surface.counts();
        for i in 0..cu {
            for j in 0..cv {
                let ring = i.min(j).min(cu - 1 - i).min(cv - 1 - j);
                self.free[i * cv + j] = ring >= k;
            }
        }
        self
    }

    /// Holds control point `k` (row-major) at `p`.
    pub(crate) fn hold(&mut self, k: usize, p: crate::Vec3) {
        self.surface.points_mut()[k] = p;
        self.free[k] = false;
    }

    /// Adds a linear constraint at a point (u, v) of the parameter domain
    /// (Veltkamp & Wesselink eq. 31 on a tensor surface): the surface
    /// passes through a point, has a normal, lies in a plane or on a line
    /// there. The solve meets it exactly (to rounding) and reports its
    /// violation. A [`crate::constraint::Constraint::Fixed`] one holds the
    /// control point of that row-major index at its value instead.
    pub fn with_constraint(
        mut self,
        name: impl Into<String>,
        constraint: TensorConstraint,
    ) -> Self {
        if let TensorConstraint::Fixed { point, value } = constraint {
            if point < self.free.len() {
                self.hold(point, value);
                return self;
            }
        }
        self.constraints.push(NamedConstraint {
            name: name.into(),
            constraint,
        });
        self
    }

    /// The indices of the free control points, in order.
    pub(crate) fn free_list(&self) -> Vec<usize> {
        (0..self.free.len()).filter(|&k| self.free[k]).collect()
    }
}
