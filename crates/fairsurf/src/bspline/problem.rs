//! A B-spline problem: the core's [`Problem`] over a B-spline surface,
//! its terms read for the sparse assembly, its operators placed and its
//! constraints' rows (`solve.rs` minimizes).

use super::guidance::NormalTerm;
use super::{BSplineSurface, KnotVector};
use crate::check;
use crate::check::dd::Dd;
use crate::constraint::{ConstraintOutcome, Row};
use crate::energy::{check_weight, Integrand, Measure, NormalGuide};
use crate::operator::bspline::Nodes;
use crate::operator::Residual;
use crate::surface::ParamSurface;
use crate::{Error, Problem, Result, TensorPatch, Vec3};

/// A B-spline surface to fair: the core's [`Problem`] over a
/// [`BSplineSurface`] (which control points are free, the energy terms,
/// constraints and operators), solved sparse and banded.
pub type BSplineProblem = Problem<BSplineSurface>;

/// What a sampled guide on a B-spline surface is refused for.
const SAMPLED_GUIDE: &str = "the exact integral (B-spline surfaces integrate the guide exactly)";

/// The energy terms read for the B-spline assembly from their integrands
/// ([`BSplineProblem::energies`]).
#[derive(Clone, Debug)]
pub(super) struct Energies {
    /// Per term, in the problem's order: its name and what it adds.
    pub(super) parts: Vec<(&'static str, Part)>,
    /// The normal-field term (at most one).
    pub(super) normal: Option<NormalTerm>,
    /// γ and the guide's net on the surface's knots (at most one guide).
    pub(super) guide: Option<(f64, Vec<Vec3>)>,
    /// A guide on other knots or degrees, with ∫|S − PS|² dA (the part of
    /// the guide term no surface of this space changes).
    pub(super) guide_source: Option<(BSplineSurface, f64)>,
}

/// What one term adds.
#[derive(Clone, Debug)]
pub(super) enum Part {
    /// Derivative patterns (coefficient with the weight, r, s).
    Fairness(Vec<(f64, usize, usize)>),
    /// The normal field.
    Normal,
    /// The guide surface.
    Guide,
}

impl Energies {
    /// (coefficient, r, s) of every fairness term's derivative patterns,
    /// the term's weight multiplied in (zero ones left out): Σ c · M_r^u ⊗
    /// M_s^v.
    pub(super) fn pats(&self) -> Vec<(f64, usize, usize)> {
        self.parts
            .iter()
            .filter_map(|(_, part)| match part {
                Part::Fairness(p) => Some(p),
                _ => None,
            })
            .flatten()
            .filter(|p| p.0 != 0.0)
            .copied()
            .collect()
    }

    /// ½γ∫|S − PS|² for a guide on other knots (0 otherwise).
    pub(super) fn guide_rest(&self) -> f64 {
        match (&self.guide, &self.guide_source) {
            (Some((g, _)), Some((_, rest))) => 0.5 * g * rest,
            _ => 0.0,
        }
    }
}

impl BSplineProblem {
    /// The outer `k` rings fixed, every other point free (k = 2: position
    /// and tangent plane along the boundary, G1 hole filling).
    pub fn with_fixed_rings(self, k: usize) -> Self {
        self.fix_rings(k)
    }

    /// The terms as the B-spline assembly takes them, from each term's
    /// [`crate::EnergyTerm::integrand`]: exact fairness terms (stretch, bend, any
    /// derivative patterns of order ≤ 2), one normal field (a Bézier field
    /// over the knot domain mapped onto [0, 1]², a B-spline field over the
    /// knot domain, or samples), one exact guide surface (a B-spline on any
    /// knots over the domain, or a Bézier patch over the domain mapped onto
    /// [0, 1]²). Refused, naming the term: a negative or non-finite weight,
    /// a term without an integrand, a sampled fairness or guide term, a
    /// second normal field or guide, a field or guide over another domain.
    pub(super) fn energies(&self) -> Result<Energies> {
        let mut out = Energies {
            parts: Vec::new(),
            normal: None,
            guide: None,
            guide_source: None,
        };
        let refuse = |name: &str, expected: &str, got: &str| Error::Mismatch {
            what: format!("energy term {name} on a B-spline surface"),
            expected: expected.into(),
            got: got.into(),
        };
        for t in &self.terms {
            let name = t.name();
            let part = match t.integrand() {
                None => {
                    return Err(refuse(
                        name,
                        "a term with an integrand (the B-spline assembly builds terms from it)",
                        "a term without one",
                    ))
                }
                Some(Integrand::Fairness {
                    weight,
                    measure,
                    patterns,
                }) => {
                    check_weight(&format!("{name} weight"), weight)?;
                    if *measure != Measure::Exact {
                        return Err(refuse(
                            name,
                            "the exact integral (sampled terms are for the normal field)",
                            "a sampled one",
                        ));
                    }
                    if let Some(((r, s), _)) = patterns.iter().find(|&&((r, s), _)| r > 2 || s > 2)
                    {
                        return Err(refuse(
                            name,
                            "derivative patterns of order at most 2 per direction",
                            &format!("∂u^{r} ∂v^{s}"),
                        ));
                    }
                    let pats: Vec<_> = patterns
                        .iter()
                        .map(|&((r, s), c)| (weight * c, r, s))
                        .collect();
                    Part::Fairness(pats)
                }
                Some(Integrand::NormalField { weight, guide }) => {
                    check_weight(&format!("{name} weight"), weight)?;
                    if out.normal.is_some() {
                        return Err(refuse(name, "one normal field", "a second one"));
                    }
                    out.normal = Some(self.normal_term(weight, guide)?);
                    Part::Normal
                }
                Some(Integrand::GuideSurface {
                    weight,
                    surface,
                    measure,
                    sample_weights,
                }) => {
                    let [du, dv] = self.surface.domain();
                    let spline = bezier_over(surface, du, dv)?;
                    let sampled = *measure != Measure::Exact || sample_weights.is_some();
                    self.add_guide(&mut out, name, (weight, sampled), &spline)?;
                    Part::Guide
                }
                Some(Integrand::GuideSpline {
                    weight,
                    surface,
                    measure,
                    sample_weights,
                }) => {
                    let sampled = *measure != Measure::Exact || sample_weights.is_some();
                    self.add_guide(&mut out, name, (weight, sampled), surface)?;
                    Part::Guide
                }
            };
            out.parts.push((name, part));
        }
        Ok(out)
    }

    /// The normal-field term from a field's guide: a sampled one's normals
    /// normalized (a zero, non-finite or missing one, or a weight list of
    /// the wrong length or with a negative entry, is an error), a B-spline
    /// field over the surface's domain.
    fn normal_term(&self, weight: f64, guide: &NormalGuide) -> Result<NormalTerm> {
        let guide = match guide {
            NormalGuide::Samples {
                grid,
                normals,
                weights,
            } => NormalGuide::Samples {
                grid: *grid,
                normals: crate::energy::unit_samples(*grid, normals, weights.as_deref())?,
                weights: weights.clone(),
            },
            NormalGuide::Spline(field) => {
                self.surface.check_domain(field, "normal field")?;
                guide.clone()
            }
            NormalGuide::Field(_) => guide.clone(),
        };
        Ok(NormalTerm { weight, guide })
    }

    /// The guide S with weight γ (refused when sampled): its net when it has the surface's knots
    /// and degrees, else its L² projection PS onto this space and the
    /// constant ∫|S − PS|² (their difference is orthogonal to the space).
    fn add_guide(
        &self,
        out: &mut Energies,
        name: &str,
        (weight, sampled): (f64, bool),
        guide: &BSplineSurface,
    ) -> Result<()> {
        if sampled {
            return Err(Error::Mismatch {
                what: format!("energy term {name} on a B-spline surface"),
                expected: SAMPLED_GUIDE.into(),
                got: "a sampled guide".into(),
            });
        }
        check_weight(&format!("{name} weight"), weight)?;
        if out.guide.is_some() {
            return Err(Error::Mismatch {
                what: format!("energy term {name} on a B-spline surface"),
                expected: "one guide surface".into(),
                got: "a second one".into(),
            });
        }
        let same = guide.knots() == self.surface.knots();
        if same {
            out.guide = Some((weight, guide.points().to_vec()));
        } else {
            let (net, rest) = super::project::project(&self.surface, guide)?;
            out.guide = Some((weight, net));
            out.guide_source = Some((guide.clone(), rest));
        }
        Ok(())
    }

    /// Each operator's quadrature nodes and residuals on the surface.
    pub(super) fn place_operators(&self) -> Result<Vec<(Nodes, Vec<Residual>)>> {
        self.operators
            .iter()
            .map(|op| {
                op.validate_on(&self.surface)?;
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
        en: &Energies,
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
            .chain(en.guide.as_ref().map(|(_, s)| max_abs(s)))
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

/// A Bézier patch as a B-spline surface over [u₀, u₁] × [v₀, v₁] (its
/// [0, 1]² mapped onto the rectangle; no interior knots).
fn bezier_over(
    patch: &TensorPatch,
    (u0, u1): (f64, f64),
    (v0, v1): (f64, f64),
) -> Result<BSplineSurface> {
    let (n, m) = patch.degree();
    let clamped =
        |p: usize, a: f64, b: f64| KnotVector::new(p, [vec![a; p + 1], vec![b; p + 1]].concat());
    BSplineSurface::new(
        clamped(n, u0, u1)?,
        clamped(m, v0, v1)?,
        patch.points().to_vec(),
    )
}
