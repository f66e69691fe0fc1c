//! A B-spline problem: the surface, which control points are free, and
//! the terms, constraints and operators to minimize over them (built
//! here; `solve.rs` minimizes).

use super::guidance::NormalTerm;
use super::BSplineSurface;
use crate::basis::polygon::Uv;
use crate::check;
use crate::check::dd::Dd;
use crate::constraint::{ConstraintOutcome, NamedConstraint, Row};
use crate::energy::{check_weight, NormalGuide};
use crate::operator::bspline::Nodes;
use crate::operator::{Residual, TensorOperator};
use crate::{Error, Result, TensorConstraint, TensorPatch, Vec3};

/// A B-spline surface to fair: which control points are free, and Wu &
/// Yang's E1/E2 terms: membrane, thin plate, normal field, guide surface.
#[derive(Clone, Debug)]
pub struct BSplineProblem {
    pub(super) surface: BSplineSurface,
    pub(super) free: Vec<bool>,
    pub(super) stretch: f64,
    pub(super) bend: f64,
    pub(super) normal: Option<NormalTerm>,
    /// γ and the guide's net on the same knots (for a guide on other knots
    /// or degrees: its L² projection onto this space).
    pub(super) guide: Option<(f64, Vec<Vec3>)>,
    /// A guide given on other knots or degrees, with ∫|S − PS|² dA (the
    /// part of the guide term no surface of this space changes).
    pub(super) guide_source: Option<(BSplineSurface, f64)>,
    /// Linear constraints at points (u, v) of the knot domain.
    pub(super) constraints: Vec<NamedConstraint<Uv>>,
    /// External energy operators at points or regions of the knot domain.
    pub(super) operators: Vec<TensorOperator>,
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
    pub(super) fn guide_rest(&self) -> f64 {
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
    pub(super) fn place_operators(&self) -> Result<Vec<(Nodes, Vec<Residual>)>> {
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
    pub(super) fn external(&self, placed: &[(Nodes, Vec<Residual>)], x: &[f64]) -> (f64, f64) {
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
    pub(super) fn constraint_rows(&self) -> Result<Vec<Row>> {
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
    pub(super) fn outcomes(
        &self,
        surface: &BSplineSurface,
    ) -> Result<(Vec<ConstraintOutcome>, f64)> {
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
}
