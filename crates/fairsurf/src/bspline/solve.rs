//! Minimizing a B-spline surface's energy over its free control points:
//! the Hessian Σ c · M_r^u ⊗ M_s^v (+ γ M_0^u ⊗ M_0^v for a guide surface)
//! restricted to the free points — one sparse matrix for x, y and z, or,
//! with a normal field (which couples them), the interleaved 3n system with
//! the field's 3 × 3 blocks added — the fixed points moved to the
//! right-hand side, sparse Cholesky with AMD ordering, one step of
//! iterative refinement, and the energy on the written net by two roads:
//! closed forms (Bernstein products on the Bézier pieces, Gram matrices)
//! or Gauss quadrature from de Boor derivatives, against Gauss quadrature
//! on the pieces with more nodes.

use super::energy::{energy_by_pieces, energy_by_quadrature, patterns, Gram1d};
use super::guidance::{guide_value, guide_value_by_pieces, NormalTerm};
use super::project::guide_value_by_quadrature;
use super::BSplineSurface;
use crate::basis::polygon::Uv;
use crate::check;
use crate::check::dd::Dd;
use crate::constraint::{ConstraintOutcome, NamedConstraint, Row};
use crate::energy::{check_weight, NormalGuide};
use crate::operator::bspline::Nodes;
use crate::operator::newton::{newton, repellors};
use crate::operator::{NewtonReport, OperatorOutcome, Residual, TensorOperator};
use crate::solve::dense::dot2_residual;
use crate::solve::kkt::KktInfo;
use crate::solve::kkt::{hager, sparse_llt, LltFailure};
use crate::{Error, Result, TensorConstraint, TensorPatch, Timings, Vec3};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::LltRef;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par};
use std::time::Instant;

/// Relative agreement required between the two roads to the energy of the
/// written net.
pub const ENERGY_TOLERANCE: f64 = 1e-10;

/// A B-spline surface to fair: which control points are free, and Wu &
/// Yang's E1/E2 terms: membrane, thin plate, normal field, guide surface.
#[derive(Clone, Debug)]
pub struct BSplineProblem {
    surface: BSplineSurface,
    free: Vec<bool>,
    stretch: f64,
    bend: f64,
    normal: Option<NormalTerm>,
    /// γ and the guide's net on the same knots (for a guide on other knots
    /// or degrees: its L² projection onto this space).
    guide: Option<(f64, Vec<Vec3>)>,
    /// A guide given on other knots or degrees, with ∫|S − PS|² dA (the
    /// part of the guide term no surface of this space changes).
    guide_source: Option<(BSplineSurface, f64)>,
    /// Linear constraints at points (u, v) of the knot domain.
    constraints: Vec<NamedConstraint<Uv>>,
    /// External energy operators at points or regions of the knot domain.
    operators: Vec<TensorOperator>,
}

/// What a B-spline solve reports; the figures mean what they mean in
/// [`crate::SolveReport`].
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineReport {
    /// The minimized energy.
    pub energy: f64,
    /// The membrane part (weight included).
    pub stretch: f64,
    /// The thin-plate part (weight included).
    pub bend: f64,
    /// The normal-field part (λ included; 0 without one).
    pub normal_field: f64,
    /// The guide-surface part (γ included; 0 without one).
    pub guide_surface: f64,
    /// Whether x, y and z were solved together (a normal field couples them).
    pub coupled: bool,
    /// The energy recomputed on the written net by Gauss quadrature of the
    /// integrand span by span (`energy` comes from the pieces' closed forms).
    pub check_energy: f64,
    /// |energy − check_energy| / energy.
    pub energy_error: f64,
    /// E(x) − min E of the written net over `scale`: ½ gᵀH⁻¹g with the
    /// gradient g = H x − b in compensated (Dot2) arithmetic on the
    /// assembled system, through the solve's factor (the tensor check's
    /// figure; here H is the assembled one, not recomputed apart). With
    /// constraints, the minimum over them: ½ gᵀy with g = b − Hx − Fᵀλ and
    /// y the constrained Newton step through the KKT factor.
    pub excess: f64,
    /// The scale of `excess` ([`crate::Check::scale`]).
    pub scale: f64,
    /// Newton corrections x ← x + H⁻¹(b − Hx) taken by the check.
    pub corrections: usize,
    /// Free control points.
    pub free_points: usize,
    /// Scalar unknowns (3 per free point).
    pub unknowns: usize,
    /// ‖H x − b‖∞ over the free coordinates (compensated arithmetic); with
    /// constraints the Lagrangian's, ‖H x − b + Fᵀλ‖∞.
    pub gradient_norm: f64,
    /// That over ‖H‖∞‖x‖∞ + ‖b‖∞.
    pub relative_gradient: f64,
    /// ‖b − Hx‖∞ / ‖b‖∞ (the absolute figure when b = 0); with
    /// constraints the KKT solve's relative residual (`kkt`).
    pub residual: f64,
    /// ‖H‖₁‖H⁻¹‖₁ of the system factored (Hager's estimate). It grows like
    /// a stiffness matrix's with the number of spans (h⁻⁴ for the thin
    /// plate); the basis itself stays well conditioned (the Gram matrix of
    /// the B-splines, scaled, is bounded independently of the knots). With
    /// constraints, the KKT matrix's estimate (`kkt.condition`).
    pub condition_estimate: f64,
    /// Nonzeros of the Cholesky factor (of the KKT factor with
    /// constraints; 0 when the core's LU solved it).
    pub factor_nonzeros: usize,
    /// The external operators' energy (Veltkamp & Wesselink §5), in
    /// `energy`.
    pub external: f64,
    /// Each operator's energy and how far its target is met.
    pub operators: Vec<OperatorOutcome>,
    /// Each constraint's violation on the written net.
    pub constraints: Vec<ConstraintOutcome>,
    /// The largest of them (0 without constraints).
    pub max_violation: f64,
    /// With constraints: the solver core's KKT solve (which factorization,
    /// its residual and condition); `None` without.
    pub kkt: Option<KktInfo>,
    /// With repellors: how Newton's method on the total energy went (then
    /// `gradient_norm` and `relative_gradient` are those of the total,
    /// nonlinear energy, and `excess` is 0: not measured).
    pub newton: Option<NewtonReport>,
    /// Seconds by phase (`analyse` is the check's second road; with
    /// constraints the KKT factorization is in `solve`, `factor` is 0).
    pub timings: Timings,
}

/// The faired surface and its report.
#[derive(Clone, Debug)]
pub struct BSplineSolution {
    /// The surface with the free points solved.
    pub surface: BSplineSurface,
    /// How good it is.
    pub report: BSplineReport,
}

impl BSplineProblem {
    /// Every control point of `surface` fixed; no energy yet.
    pub fn new(surface: BSplineSurface) -> Self {
        let n = surface.points().len();
        Self {
            surface,
            free: vec![false; n],
            stretch: 0.0,
            bend: 0.0,
            normal: None,
            guide: None,
            guide_source: None,
            constraints: Vec::new(),
            operators: Vec::new(),
        }
    }

    /// The outer `k` rings fixed, every other point free (k = 2: position
    /// and tangent plane along the boundary, G1 hole filling).
    pub fn with_fixed_rings(mut self, k: usize) -> Self {
        let (cu, cv) = self.surface.counts();
        for i in 0..cu {
            for j in 0..cv {
                let inside = i >= k && j >= k && i + k < cu && j + k < cv;
                self.free[i * cv + j] = inside;
            }
        }
        self
    }

    /// Which control points are free (row-major, one flag per point).
    pub fn with_free(mut self, free: Vec<bool>) -> Result<Self> {
        if free.len() != self.free.len() {
            return Err(Error::Mismatch {
                what: "free flags of the B-spline net".into(),
                expected: self.free.len().to_string(),
                got: free.len().to_string(),
            });
        }
        self.free = free;
        Ok(self)
    }

    /// The surface: its knots, and the fixed points' values (free ones are
    /// where the solve starts, which a quadratic energy ignores).
    pub fn surface(&self) -> &BSplineSurface {
        &self.surface
    }

    /// The free flags (row-major).
    pub fn free(&self) -> &[bool] {
        &self.free
    }

    /// The normal-field term (λ and a Bézier field or samples over the knot
    /// domain mapped onto [0, 1]², or a B-spline field over the knot domain
    /// itself), when there is one.
    pub fn normal_field(&self) -> Option<crate::energy::NormalField> {
        self.normal.as_ref().map(|n| crate::energy::NormalField {
            weight: n.weight,
            guide: n.guide.clone(),
        })
    }

    /// γ and the guide's net, when there is a guide term.
    pub fn guide(&self) -> Option<(f64, &[Vec3])> {
        self.guide.as_ref().map(|(g, s)| (*g, s.as_slice()))
    }

    /// The membrane energy with weight `w` ≥ 0.
    pub fn with_stretch(mut self, w: f64) -> Self {
        self.stretch = w;
        self
    }

    /// The thin-plate energy with weight `w` ≥ 0.
    pub fn with_bend(mut self, w: f64) -> Self {
        self.bend = w;
        self
    }

    /// The normal-field term ½λ∫∫ (R_u·N)² + (R_v·N)² with λ = `weight` ≥ 0
    /// and N the Bézier field `field` over the knot domain mapped onto
    /// [0, 1]² (Wu & Yang eq. 1–2; N as given, not normalized).
    pub fn with_normal_field(mut self, weight: f64, field: TensorPatch) -> Self {
        self.normal = Some(NormalTerm {
            weight,
            guide: NormalGuide::Field(field),
        });
        self
    }

    /// The normal-field term ½λ∫∫ (R_u·N)² + (R_v·N)² with λ = `weight` ≥ 0
    /// and N a B-spline field on its own knots and degrees over the
    /// surface's knot domain (Wu & Yang eq. 1–2 with a piecewise field; N
    /// as given, not normalized): exact by Gauss rules on every piece
    /// between both surfaces' knot lines. A field over another domain (to
    /// 1e-12) is an error.
    pub fn with_normal_spline(mut self, weight: f64, field: BSplineSurface) -> Result<Self> {
        self.surface.check_domain(&field, "normal field")?;
        self.normal = Some(NormalTerm {
            weight,
            guide: NormalGuide::Spline(field),
        });
        Ok(self)
    }

    /// The sampled normal-field term (Wu & Yang eq. 5),
    /// ½λ Σ λ_k ((R_ũ·N_k)² + (R_ṽ·N_k)²), over the grid's samples of the
    /// knot domain mapped onto [0, 1]², with the derivatives with respect to the mapped parameters
    /// (a B-spline without interior knots on [0, 1] gets the tensor scene's
    /// energy). The normals are normalized; a zero, non-finite or missing
    /// one, or a weight list of the wrong length or with a negative entry, is
    /// an error.
    pub fn with_sampled_normals(
        mut self,
        weight: f64,
        grid: crate::energy::SampleGrid,
        normals: Vec<Vec3>,
        weights: Option<Vec<f64>>,
    ) -> Result<Self> {
        check_weight("normal field weight", weight)?;
        grid.check_len("normal_field samples", normals.len())?;
        if let Some(w) = &weights {
            grid.check_len("normal_field sample weights", w.len())?;
            crate::energy::check_weights("normal_field sample weight", w)?;
        }
        let normals = normals
            .into_iter()
            .enumerate()
            .map(|(k, n)| {
                if !crate::vec3::is_finite(n) {
                    return Err(Error::NotFinite {
                        what: format!("normal sample {k}"),
                    });
                }
                crate::vec3::normalize(n).ok_or(Error::ZeroNormal {
                    what: format!("normal sample {k}"),
                })
            })
            .collect::<Result<Vec<_>>>()?;
        self.normal = Some(NormalTerm {
            weight,
            guide: NormalGuide::Samples {
                grid,
                normals,
                weights,
            },
        });
        Ok(self)
    }

    /// The guide term ½γ∫∫ |R − S|² with γ = `weight` ≥ 0 and S the net
    /// `guide` on the same knots (`None`: the initial net).
    pub fn with_guide_surface(mut self, weight: f64, guide: Option<Vec<Vec3>>) -> Result<Self> {
        let s = guide.unwrap_or_else(|| self.surface.points().to_vec());
        if s.len() != self.free.len() {
            return Err(Error::Mismatch {
                what: "guide surface control points (the same knots as the surface)".into(),
                expected: self.free.len().to_string(),
                got: s.len().to_string(),
            });
        }
        self.guide = Some((weight, s));
        self.guide_source = None;
        Ok(self)
    }

    /// The guide term ½γ∫∫ |R − S|² with S any B-spline surface over the
    /// same domain — its own knots and degrees (a Bézier patch is one
    /// without interior knots): the same-knots term of S's L² projection PS
    /// onto this surface's space plus the constant ∫|S − PS|² (their
    /// difference is orthogonal to the space), exact by Gauss rules between
    /// both surfaces' knot lines. The check integrates |R − S|² directly.
    pub fn with_guide_spline(mut self, weight: f64, guide: BSplineSurface) -> Result<Self> {
        let (net, rest) = super::project::project(&self.surface, &guide)?;
        self.guide = Some((weight, net));
        self.guide_source = Some((guide, rest));
        Ok(self)
    }

    /// ½γ∫|S − PS|² for a guide on other knots (0 otherwise).
    fn guide_rest(&self) -> f64 {
        match (&self.guide, &self.guide_source) {
            (Some((g, _)), Some((_, rest))) => 0.5 * g * rest,
            _ => 0.0,
        }
    }

    /// Adds an external energy operator (Veltkamp & Wesselink §5) at a point
    /// or a convex region of the knot domain: a director, or a point, plane,
    /// line or surface attractor (a surface target is a Bézier patch over
    /// the knot domain mapped onto [0, 1]²), a repellor (Newton's method),
    /// or at a boundary edge an edge-to-curve attractor (the curve over the
    /// edge's parameter interval mapped onto [0, 1]). Refused, naming the
    /// operator: a place outside the knot domain, a repelling director, a
    /// curve off an edge or an edge without a curve, a triangular target.
    pub fn with_operator(mut self, op: TensorOperator) -> Result<Self> {
        op.validate_on(&self.surface)?;
        self.operators.push(op);
        Ok(self)
    }

    /// The external energy operators.
    pub fn operators(&self) -> &[TensorOperator] {
        &self.operators
    }

    /// Each operator's quadrature nodes and residuals on the surface.
    fn place_operators(&self) -> Result<Vec<(Nodes, Vec<Residual>)>> {
        self.operators
            .iter()
            .map(|op| {
                let nodes = op.locate_on(&self.surface)?;
                let residuals = op.residuals_on(&nodes, &self.surface);
                Ok((nodes, residuals))
            })
            .collect()
    }

    /// The operators' energy at the coordinates x (3g + c), in working
    /// precision and, for the check's second road, in double-double.
    fn external(&self, placed: &[(Nodes, Vec<Residual>)], x: &[f64]) -> (f64, f64) {
        let xd: Vec<Dd> = x.iter().map(|&v| Dd::new(v)).collect();
        self.operators
            .iter()
            .zip(placed)
            .map(|(op, (_, res))| {
                let dd = check::operator_energy(op.strength, op.repel, res, &xd, |_, _| {});
                (op.energy(res, x), dd.to_f64())
            })
            .fold((0.0, 0.0), |(a, b), (c, d)| (a + c, b + d))
    }

    /// Adds a linear constraint at a point (u, v) of the knot domain
    /// (Veltkamp & Wesselink eq. 31, as on a tensor patch): the surface
    /// passes through a point, has a normal, lies in a plane or on a line
    /// there, met exactly (to rounding) and reported with its violation. A
    /// [`crate::constraint::Constraint::Fixed`] one fixes the control point
    /// of index i·c_v + j at its value instead.
    pub fn with_constraint(
        mut self,
        name: impl Into<String>,
        constraint: TensorConstraint,
    ) -> Self {
        if let TensorConstraint::Fixed { point, value } = constraint {
            if point < self.free.len() {
                self.free[point] = false;
                let mut points = self.surface.points().to_vec();
                points[point] = value;
                self.surface = self.surface.with_points(points);
                return self;
            }
        }
        self.constraints.push(NamedConstraint {
            name: name.into(),
            constraint,
        });
        self
    }

    /// The constraints at points of the knot domain.
    pub fn constraints(&self) -> &[NamedConstraint<Uv>] {
        &self.constraints
    }

    /// The constraints checked and turned into rows over all coordinates
    /// (3·index + c).
    fn constraint_rows(&self) -> Result<Vec<Row>> {
        for c in &self.constraints {
            c.constraint.validate(&self.surface, &c.name)?;
        }
        Ok(self
            .constraints
            .iter()
            .flat_map(|c| c.constraint.rows(&self.surface, &c.name))
            .collect())
    }

    /// Each constraint's violation on the written net and the largest; an
    /// error when a row is missed beyond the check's tolerance.
    fn outcomes(&self, surface: &BSplineSurface) -> Result<(Vec<ConstraintOutcome>, f64)> {
        if self.constraints.is_empty() {
            return Ok((Vec::new(), 0.0));
        }
        let rows = self.constraint_rows()?;
        let max_abs = |v: &[Vec3]| v.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        let known = (0..self.free.len())
            .filter(|&k| !self.free[k])
            .fold(0.0f64, |m, k| m.max(max_abs(&surface.points()[k..=k])));
        let size = rows
            .iter()
            .map(|r| r.rhs.abs())
            .chain(self.guide.as_ref().map(|(_, s)| max_abs(s)))
            .chain(self.operators.iter().map(|o| o.target.size()))
            .fold(known, f64::max);
        if let Some((row, miss)) = super::constraint::unmet(&rows, surface, size) {
            return Err(Error::Unmet {
                degree: format!("{:?} (B-spline)", surface.degree()),
                row,
                miss,
                tolerance: check::TOLERANCE,
            });
        }
        Ok(crate::constraint::outcomes(&self.constraints, surface))
    }

    /// Minimizes; refuses no free point, no energy, a negative weight, a
    /// singular system, and an answer whose energy the second road does
    /// not confirm.
    pub fn solve(&self) -> Result<BSplineSolution> {
        check_weight("stretch weight", self.stretch)?;
        check_weight("bend weight", self.bend)?;
        let lambda = self.normal.as_ref().map_or(0.0, |n| n.weight);
        let gamma = self.guide.as_ref().map_or(0.0, |g| g.0);
        check_weight("normal field weight", lambda)?;
        check_weight("guide surface weight", gamma)?;
        let pats = patterns(self.stretch, self.bend);
        if pats.is_empty() && lambda == 0.0 && gamma == 0.0 {
            return Err(Error::NoEnergy);
        }
        let free: Vec<usize> = (0..self.free.len()).filter(|&k| self.free[k]).collect();
        if free.is_empty() {
            let (cu, cv) = self.surface.counts();
            return Err(Error::NoFreePoints {
                why: format!("every control point of the {cu} × {cv} net is fixed"),
            });
        }
        let t0 = Instant::now();
        let (ku, kv) = self.surface.knots();
        let (gu, gv) = (Gram1d::new(ku), Gram1d::new(kv));
        let normal = self.normal.as_ref().filter(|n| n.weight > 0.0);
        let placed = self.place_operators()?;
        // Attractors and directors: s Σ w (a·x − t)² adds 2sw a aᵀ to H and
        // 2sw t a to b.
        let quadratic: Vec<(f64, &Residual)> = self
            .operators
            .iter()
            .zip(&placed)
            .filter(|(op, _)| !op.repel)
            .flat_map(|(op, (_, res))| res.iter().map(move |r| (2.0 * op.strength * r.weight, r)))
            .collect();
        let coupled = normal.is_some() || !self.operators.is_empty();
        let sys = self.assemble(&free, &gu, &gv, &pats, (normal, coupled), &quadratic);
        let assemble = t0.elapsed().as_secs_f64();

        let mut solved = if self.constraints.is_empty() {
            unconstrained(&sys, coupled, free.len())?
        } else {
            let rows = self.constraint_rows()?;
            let mut slot = vec![usize::MAX; self.free.len()];
            for (s, &k) in free.iter().enumerate() {
                slot[k] = s;
            }
            let t1 = Instant::now();
            let c = super::constraint::solve(&sys, coupled, &rows, &slot, self.surface.points())?;
            let x: Vec<Vec3> = c.x.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
            let x_inf = c.x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let denom = sys.h_inf * x_inf + c.b_inf;
            Solved {
                xx: c.x.iter().map(|v| v * v).sum(),
                x,
                gradient_norm: c.gradient_norm,
                relative_gradient: if denom > 0.0 {
                    c.gradient_norm / denom
                } else {
                    c.gradient_norm
                },
                residual: c.kkt.relative_residual,
                excess: c.excess,
                corrections: c.corrections,
                condition_estimate: c.kkt.condition,
                factor_nonzeros: c.kkt.factor_nonzeros.unwrap_or(0),
                kkt: Some(c.kkt),
                factor: 0.0,
                solve: t1.elapsed().as_secs_f64(),
            }
        };
        let newton = self.repel(&sys, coupled, &free, &placed, &mut solved)?;
        let mut points: Vec<Vec3> = self.surface.points().to_vec();
        for (row, &k) in free.iter().enumerate() {
            points[k] = solved.x[row];
        }
        let surface = self.surface.with_points(points);
        let t3 = Instant::now();
        let (pieces, degree) = (surface.bezier_pieces(), surface.degree());
        let part = |pats: Vec<(f64, usize, usize)>| energy_by_pieces(&pieces, degree, &pats);
        let (stretch, bend) = (
            part(patterns(self.stretch, 0.0)),
            part(patterns(0.0, self.bend)),
        );
        let normal_field = normal.map_or(0.0, |n| n.value(&surface));
        let guide_surface = self
            .guide
            .as_ref()
            .map_or(0.0, |(g, s)| guide_value(&gu, &gv, *g, surface.points(), s))
            + self.guide_rest();
        let x_flat: Vec<f64> = surface.points().iter().flatten().copied().collect();
        let (external, external_check) = self.external(&placed, &x_flat);
        let total = stretch + bend + normal_field + guide_surface + external;
        let mut check_energy = energy_by_quadrature(&pieces, degree, &pats) + external_check;
        if let Some(n) = normal {
            check_energy += n.value_by_pieces(&surface, &pieces);
        }
        match (&self.guide, &self.guide_source) {
            (Some((g, _)), Some((source, _))) => {
                check_energy += guide_value_by_quadrature(&surface, source, *g);
            }
            (Some((g, s)), None) => {
                let guide = self.surface.with_points(s.clone()).bezier_pieces();
                check_energy += guide_value_by_pieces(&pieces, &guide, degree, *g);
            }
            _ => {}
        }
        let analyse = t3.elapsed().as_secs_f64();
        let energy_error = (total - check_energy).abs() / total.abs().max(f64::MIN_POSITIVE);
        // A zero energy (a reproduced linear surface) is confirmed when the
        // second road finds it at rounding level of the data.
        if energy_error > ENERGY_TOLERANCE && (total - check_energy).abs() > 1e-24 {
            return Err(Error::Unverified {
                degree: format!("{:?} (B-spline)", surface.degree()),
                checked: check_energy,
                excess: energy_error,
                tolerance: ENERGY_TOLERANCE,
                hint: "the closed forms and the quadrature of its energy disagree".into(),
            });
        }
        // Rounding the free points to doubles can change the energy by about
        // ε² · max H_ii · Σ x_i²: below that, the excess tells nothing.
        let scale = check::scale(total, sys.h_diag * solved.xx);
        // With repellors the energy is not quadratic: Newton's stationarity
        // (its relative gradient, ≤ 1e-10 or an error) stands for the excess.
        let excess = if newton.is_some() {
            0.0
        } else {
            solved.excess.max(0.0) / scale
        };
        if excess > check::TOLERANCE {
            return Err(Error::Unverified {
                degree: format!("{:?} (B-spline)", surface.degree()),
                checked: total,
                excess,
                tolerance: check::TOLERANCE,
                hint: "the written net is not the minimizer of the assembled system to the \
                       tolerance even after Newton corrections"
                    .into(),
            });
        }
        let (constraints, max_violation) = self.outcomes(&surface)?;
        let operators = self
            .operators
            .iter()
            .zip(&placed)
            .map(|(op, (nodes, res))| op.outcome_on(nodes, res, &surface, &x_flat))
            .collect();
        Ok(BSplineSolution {
            surface,
            report: BSplineReport {
                energy: total,
                stretch,
                bend,
                normal_field,
                guide_surface,
                coupled,
                check_energy,
                energy_error,
                excess,
                scale,
                corrections: solved.corrections,
                free_points: free.len(),
                unknowns: 3 * free.len(),
                gradient_norm: solved.gradient_norm,
                relative_gradient: solved.relative_gradient,
                residual: solved.residual,
                condition_estimate: solved.condition_estimate,
                factor_nonzeros: solved.factor_nonzeros,
                external,
                operators,
                constraints,
                max_violation,
                kkt: solved.kkt,
                newton,
                timings: Timings {
                    assemble,
                    factor: solved.factor,
                    solve: solved.solve,
                    analyse,
                    total: t0.elapsed().as_secs_f64(),
                },
            },
        })
    }

    /// With repellors (Veltkamp & Wesselink eq. 23, s/E_attr): Newton's
    /// method on the total energy from the quadratic solution, the rows
    /// kept (the core's `operator::newton`, as the tensor and triangular
    /// solves use it); the free points and gradient figures replaced.
    fn repel(
        &self,
        sys: &System,
        coupled: bool,
        free: &[usize],
        placed: &[(Nodes, Vec<Residual>)],
        solved: &mut Solved,
    ) -> Result<Option<NewtonReport>> {
        if !self.operators.iter().any(|op| op.repel) {
            return Ok(None);
        }
        let x0 = self.surface.points();
        let mut slot = vec![usize::MAX; self.free.len()];
        for (s, &k) in free.iter().enumerate() {
            slot[k] = s;
        }
        let known: Vec<Option<Vec3>> = x0
            .iter()
            .zip(&slot)
            .map(|(p, &s)| (s == usize::MAX).then_some(*p))
            .collect();
        let repellors = repellors(&self.operators, placed, &known, free);
        let system = super::constraint::interleaved(sys, coupled);
        let rows = if self.constraints.is_empty() {
            Vec::new()
        } else {
            super::constraint::reduced_rows(&self.constraint_rows()?, &slot, x0)?.0
        };
        let f: Vec<&[(usize, f64)]> = rows.iter().map(Vec::as_slice).collect();
        let minus_b: Vec<f64> = system.b.iter().map(|v| -v).collect();
        let start: Vec<f64> = solved.x.iter().flatten().copied().collect();
        let t = Instant::now();
        let (x, report) = newton(&system.h, &minus_b, &f, &repellors, start)?;
        solved.x = x.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
        solved.xx = x.iter().map(|v| v * v).sum();
        solved.gradient_norm = report.gradient_norm;
        solved.relative_gradient = report.relative_gradient;
        solved.solve += t.elapsed().as_secs_f64();
        Ok(Some(report))
    }

    /// The problem's energy at the net of `surface` (same knots): the sum
    /// of its terms as the report computes them.
    pub fn energy_at(&self, surface: &BSplineSurface) -> f64 {
        let (ku, kv) = surface.knots();
        let (pieces, degree) = (surface.bezier_pieces(), surface.degree());
        let mut e = energy_by_pieces(&pieces, degree, &patterns(self.stretch, self.bend));
        if let Some(n) = &self.normal {
            e += n.value(surface);
        }
        if let Some((g, s)) = &self.guide {
            e += guide_value(&Gram1d::new(ku), &Gram1d::new(kv), *g, surface.points(), s);
            e += self.guide_rest();
        }
        if let Ok(placed) = self.place_operators() {
            let x: Vec<f64> = surface.points().iter().flatten().copied().collect();
            e += self.external(&placed, &x).0;
        }
        e
    }

    /// The free block's lower triangle and right-hand side: one matrix for
    /// x, y and z (three columns) unless `coupled` (a normal field or
    /// operators), else the interleaved system (unknown 3·slot + c, one
    /// column).
    fn assemble(
        &self,
        free: &[usize],
        gu: &Gram1d,
        gv: &Gram1d,
        pats: &[(f64, usize, usize)],
        (normal, coupled): (Option<&NormalTerm>, bool),
        operators: &[(f64, &Residual)],
    ) -> System {
        let cv = gv.count();
        let mut slot = vec![usize::MAX; self.free.len()];
        for (s, &k) in free.iter().enumerate() {
            slot[k] = s;
        }
        let x0 = self.surface.points();
        let gamma = self.guide.as_ref().map_or(0.0, |g| g.0);
        let nf = free.len();
        let (dim, cols) = if coupled { (3 * nf, 1) } else { (nf, 3) };
        let mut sys = System {
            dim,
            lower: Vec::new(),
            b: Mat::zeros(dim, cols),
            h_inf: 0.0,
            h_diag: 0.0,
        };
        let mut row_sums = vec![0.0f64; dim];
        // (global row, coordinate) → the system's row and column.
        let at = |s: usize, c: usize| if coupled { (3 * s + c, 0) } else { (s, c) };
        let mut add = |sys: &mut System, k: usize, c: usize, l: usize, d: usize, h: f64| {
            let (row, rc) = at(slot[k], c);
            row_sums[row] += h.abs();
            match slot[l] {
                usize::MAX => sys.b[(row, rc)] -= h * x0[l][d],
                sl => {
                    let (col, _) = at(sl, d);
                    if col <= row {
                        sys.lower.push(Triplet::new(row, col, h));
                    }
                }
            }
        };
        for &k in free {
            let (i, j) = (k / cv, k % cv);
            for i2 in gu.band(i) {
                for j2 in gv.band(j) {
                    let (mu, mv) = (gu.at(0, i, i2), gv.at(0, j, j2));
                    let h: f64 = pats
                        .iter()
                        .map(|&(c, r, s)| c * gu.at(r, i, i2) * gv.at(s, j, j2))
                        .sum::<f64>()
                        + gamma * mu * mv;
                    let l = i2 * cv + j2;
                    if h != 0.0 {
                        for c in 0..3 {
                            if coupled || c == 0 {
                                add(&mut sys, k, c, l, c, h);
                            }
                        }
                        if !coupled && slot[l] == usize::MAX {
                            // Columns y and z of a fixed neighbour (x went above).
                            let (row, _) = at(slot[k], 0);
                            for c in 1..3 {
                                sys.b[(row, c)] -= h * x0[l][c];
                            }
                        }
                    }
                    // The guide's linear term: + γ M s.
                    if let Some((g, s)) = &self.guide {
                        for c in 0..3 {
                            let (row, rc) = at(slot[k], c);
                            sys.b[(row, rc)] += g * mu * mv * s[l][c];
                        }
                    }
                }
            }
        }
        if coupled {
            // The field's and the operators' 3 × 3 blocks, summed into a
            // band store (one per free point and neighbour offset) and then
            // emitted once: adding every span's blocks as triplets made 5 M
            // of them at 50 × 50 (and an operator's every node's).
            let (p, q) = self.surface.degree();
            let (wu, wv) = (2 * p + 1, 2 * q + 1);
            let mut band = vec![0.0f64; nf * wu * wv * 9];
            let size = (p + 1) * (q + 1);
            let m = 3 * size;
            for grid in normal.iter().flat_map(|n| n.spans(&self.surface)) {
                // Local Σ_nodes w (Y Yᵀ + Z Zᵀ), Y = ∂_u B ⊗ N, Z = ∂_v B ⊗ N.
                let local = grid.local();
                let (su, sv) = grid.span;
                let (i0, j0) = (su - p, sv - q);
                for a in 0..size {
                    let (ia, ja) = (i0 + a / (q + 1), j0 + a % (q + 1));
                    let sk = slot[ia * cv + ja];
                    if sk == usize::MAX {
                        continue;
                    }
                    for b in 0..size {
                        let (ib, jb) = (i0 + b / (q + 1), j0 + b % (q + 1));
                        let off = (ib + p - ia) * wv + (jb + q - ja);
                        let blk = &mut band[(sk * wu * wv + off) * 9..][..9];
                        for c in 0..3 {
                            for d in 0..3 {
                                blk[3 * c + d] += local[(3 * a + c) * m + 3 * b + d];
                            }
                        }
                    }
                }
            }
            // The operators' residuals w (a·x − t)²: w a aᵀ and w t a, over
            // coordinates 3g + c of one span's points.
            for &(w, r) in operators {
                for &(i, a) in &r.terms {
                    let (k, c) = (i / 3, i % 3);
                    let sk = slot[k];
                    if sk == usize::MAX {
                        continue;
                    }
                    let (row, rc) = at(sk, c);
                    sys.b[(row, rc)] += w * r.target * a;
                    let (ia, ja) = (k / cv, k % cv);
                    for &(j, b) in &r.terms {
                        let (l, d) = (j / 3, j % 3);
                        let off = (l / cv + p - ia) * wv + (l % cv + q - ja);
                        band[(sk * wu * wv + off) * 9 + 3 * c + d] += w * a * b;
                    }
                }
            }
            for (sk, &k) in free.iter().enumerate() {
                let (i, j) = (k / cv, k % cv);
                for di in 0..wu {
                    for dj in 0..wv {
                        let (Some(i2), Some(j2)) =
                            ((i + di).checked_sub(p), (j + dj).checked_sub(q))
                        else {
                            continue;
                        };
                        let blk = &band[(sk * wu * wv + di * wv + dj) * 9..][..9];
                        for c in 0..3 {
                            for d in 0..3 {
                                let h = blk[3 * c + d];
                                if h != 0.0 {
                                    add(&mut sys, k, c, i2 * cv + j2, d, h);
                                }
                            }
                        }
                    }
                }
            }
        }
        sys.h_inf = row_sums.iter().fold(0.0, |m, &v| m.max(v));
        // The diagonal arrives in several triplets (summed by the matrix).
        let mut diag = vec![0.0; sys.dim];
        for t in sys.lower.iter().filter(|t| t.row == t.col) {
            diag[t.row] += t.val;
        }
        sys.h_diag = diag.iter().fold(0.0, |m, &v| m.max(v));
        sys
    }
}

/// The assembled free block.
pub(super) struct System {
    pub(super) dim: usize,
    /// Lower triangle (duplicates are summed).
    pub(super) lower: Vec<Triplet<usize, usize, f64>>,
    /// Right-hand side, one column per coordinate or one.
    pub(super) b: Mat<f64>,
    /// ‖H‖∞ of the free block.
    pub(super) h_inf: f64,
    /// max H_ii of the free block.
    h_diag: f64,
}

impl System {
    /// Row by row, the (column, value) pairs of the whole symmetric H.
    fn rows(&self) -> Vec<Vec<(usize, f64)>> {
        let mut rows = vec![Vec::new(); self.dim];
        for t in &self.lower {
            rows[t.row].push((t.col, t.val));
            if t.row != t.col {
                rows[t.col].push((t.row, t.val));
            }
        }
        rows
    }

    /// b − H x with every row a compensated (Dot2) dot product: as if
    /// computed in twice the working precision, then rounded.
    fn residual_dot2(&self, rows: &[Vec<(usize, f64)>], x: &Mat<f64>) -> Mat<f64> {
        let mut a = Vec::new();
        let mut xs = Vec::new();
        Mat::from_fn(self.dim, x.ncols(), |i, c| {
            a.clear();
            xs.clear();
            for &(j, v) in &rows[i] {
                a.push(v);
                xs.push(x[(j, c)]);
            }
            dot2_residual(self.b[(i, c)], &a, &xs)
        })
    }

    /// b − H x, from the lower triangle.
    fn residual(&self, x: &Mat<f64>) -> Mat<f64> {
        let mut r = self.b.clone();
        for t in &self.lower {
            for c in 0..x.ncols() {
                r[(t.row, c)] -= t.val * x[(t.col, c)];
                if t.row != t.col {
                    r[(t.col, c)] -= t.val * x[(t.row, c)];
                }
            }
        }
        r
    }
}

/// The free points solved and the report's figures that depend on how.
struct Solved {
    /// The free points, in the order of the free list.
    x: Vec<Vec3>,
    /// Σ x_i² over the free coordinates.
    xx: f64,
    gradient_norm: f64,
    relative_gradient: f64,
    residual: f64,
    /// E(x) − min E, before scaling.
    excess: f64,
    corrections: usize,
    condition_estimate: f64,
    factor_nonzeros: usize,
    kkt: Option<KktInfo>,
    /// Seconds factoring and solving.
    factor: f64,
    solve: f64,
}

/// Sparse Cholesky of the free block (AMD ordering), one step of iterative
/// refinement, then the check's Newton corrections while the excess
/// ½ gᵀH⁻¹g (g = b − Hx in compensated products) falls.
fn unconstrained(sys: &System, coupled: bool, nf: usize) -> Result<Solved> {
    let t1 = Instant::now();
    let lower = SparseColMat::try_new_from_triplets(sys.dim, sys.dim, &sys.lower)
        .expect("the triplets index the free block");
    let (symbolic, values) = sparse_llt(&lower, None).map_err(|e| match e {
        LltFailure::NotPositive => Error::NotPositiveDefinite {
            unknowns: 3 * nf,
            pivot: 0,
            hint: "the energy does not determine the free control points: add bend or \
                   stretch, or fix more points"
                .into(),
        },
        LltFailure::Symbolic(why) => Error::Mismatch {
            what: "B-spline system".into(),
            expected: "a size that fits in memory".into(),
            got: format!("{nf} free points ({why})"),
        },
    })?;
    let factor = t1.elapsed().as_secs_f64();

    let t2 = Instant::now();
    let llt = LltRef::new(symbolic.as_ref(), &values);
    let par = Par::Seq;
    let cols = sys.b.ncols();
    let mut mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(cols, par));
    let mut solve = |rhs: &mut Mat<f64>| {
        llt.solve_in_place_with_conj(Conj::No, rhs.as_mut(), par, MemStack::new(&mut mem));
    };
    let mut x = sys.b.clone();
    solve(&mut x);
    // One step of iterative refinement: x += H⁻¹(b − Hx).
    let mut d = sys.residual(&x);
    solve(&mut d);
    x += &d;
    // The check's gradient, b − Hx with compensated products, and the
    // excess ½ gᵀH⁻¹g; Newton corrections while it falls.
    let rows = sys.rows();
    let excess_at = |x: &Mat<f64>, solve: &mut dyn FnMut(&mut Mat<f64>)| {
        let g = sys.residual_dot2(&rows, x);
        let mut d = g.clone();
        solve(&mut d);
        let e = 0.5 * dot(&g, &d);
        (e, g, d)
    };
    let (mut excess, mut r, mut d) = excess_at(&x, &mut solve);
    let mut corrections = 0;
    while corrections < check::MAX_CORRECTIONS && excess > 0.0 {
        let next = &x + &d;
        let (e2, r2, d2) = excess_at(&next, &mut solve);
        if e2.is_nan() || e2 >= excess {
            break;
        }
        (x, excess, r, d) = (next, e2, r2, d2);
        corrections += 1;
    }
    // ‖H‖₁‖H⁻¹‖₁ (H symmetric: its 1-norm is its ∞-norm), Hager's
    // estimate through the factor.
    let condition_estimate = sys.h_inf
        * hager(sys.dim, |v| {
            let mut m = Mat::from_fn(sys.dim, 1, |i, _| v[i]);
            let mut mem1 = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, par));
            llt.solve_in_place_with_conj(Conj::No, m.as_mut(), par, MemStack::new(&mut mem1));
            (0..sys.dim).map(|i| m[(i, 0)]).collect()
        });
    let solve_s = t2.elapsed().as_secs_f64();
    let x_free: Vec<Vec3> = (0..nf)
        .map(|row| {
            if coupled {
                [x[(3 * row, 0)], x[(3 * row + 1, 0)], x[(3 * row + 2, 0)]]
            } else {
                [x[(row, 0)], x[(row, 1)], x[(row, 2)]]
            }
        })
        .collect();
    let gradient_norm = inf(&r);
    let denom = sys.h_inf * inf(&x) + inf(&sys.b);
    let relative_gradient = if denom > 0.0 {
        gradient_norm / denom
    } else {
        gradient_norm
    };
    let residual = if inf(&sys.b) > 0.0 {
        gradient_norm / inf(&sys.b)
    } else {
        gradient_norm
    };
    Ok(Solved {
        x: x_free,
        xx: dot(&x, &x),
        gradient_norm,
        relative_gradient,
        residual,
        excess,
        corrections,
        condition_estimate,
        factor_nonzeros: values.len(),
        kkt: None,
        factor,
        solve: solve_s,
    })
}

/// Σ a_ij b_ij.
fn dot(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
    (0..a.ncols())
        .flat_map(|c| (0..a.nrows()).map(move |i| (i, c)))
        .map(|(i, c)| a[(i, c)] * b[(i, c)])
        .sum()
}

/// max |m_ij|.
fn inf(m: &Mat<f64>) -> f64 {
    (0..m.nrows())
        .flat_map(|i| (0..m.ncols()).map(move |c| (i, c)))
        .fold(0.0f64, |a, (i, c)| a.max(m[(i, c)].abs()))
}
