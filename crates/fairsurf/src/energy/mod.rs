//! Energy terms as exact quadratic forms over the control points.
//!
//! Every term of Wu & Yang 2015 (eq. 1, 2 and the sampled eq. 5) has the form
//!
//! ```text
//! E_t(P) = ½ (x − s)ᵀ H_t (x − s)
//! ```
//!
//! with x the control points of the patch, H_t symmetric positive
//! semi-definite and s a centre (zero except for the guide surface, where it
//! is the guide's control net). Terms that treat x, y and z alike
//! (stretch, bend, guide) have a per-coordinate (n+1)(m+1)-square Hessian; the
//! normal-field term couples the coordinates and has a 3(n+1)(m+1)-square one,
//! ordered point-major (x of P_00, y of P_00, z of P_00, x of P_01, …).
//!
//! Integrals are exact (closed-form Bernstein product integrals, see
//! [`crate::basis::product_integral`]); sampled terms are exact sums.

mod bend;
mod guide_surface;
mod kron;
mod normal_field;
mod space;
mod stretch;

pub use bend::Bend;
pub use guide_surface::{Guide, GuideSurface};
pub(crate) use normal_field::unit_samples;
pub use normal_field::{NormalField, NormalGuide};
pub use space::Space;
pub use stretch::Stretch;

pub(crate) use space::Basis1d;

pub(crate) use kron::{
    coupled_form, derivative_net, form, pairs, pattern_value, Axis, PatternForm,
};

use crate::vec3::Vec3;
use crate::{Error, Result};
use faer::Mat;
use std::fmt::Debug;
use std::hash::{Hash, Hasher};

/// A term of the total energy: contributes one quadratic form.
pub trait EnergyTerm: Debug + Send + Sync {
    /// The term's name in reports: "stretch", "bend", "normal_field", …
    fn name(&self) -> &'static str;

    /// The term's Hessian and centre over a space of polynomials, or an
    /// error naming what in the term is invalid (negative weight, wrong size…).
    /// Centres are given only in the Bernstein space.
    fn form_in(&self, space: &Space) -> Result<TermForm>;

    /// The term's Hessian and centre over the Bernstein basis of a patch of
    /// the given degree.
    fn form(&self, degree: (usize, usize)) -> Result<TermForm> {
        self.form_in(&Space::bernstein(degree))
    }

    /// The term's value for a patch. The default evaluates the assembled
    /// form; the built-in terms evaluate from derivative nets instead, which
    /// stays accurate to ~1e-15 relative at high degree.
    fn value(&self, patch: &crate::TensorPatch) -> Result<f64> {
        Ok(self.form(patch.degree())?.value(patch.points()))
    }

    /// A 64-bit key of everything the term's Hessian depends on (not its
    /// centre), equal for two terms whose Hessians are equal at every
    /// degree; `None` when the term cannot tell (the default). A
    /// [`crate::Factored`] system is reused for a problem only when all its
    /// terms' keys match. Built-in terms hash their name and the bits of
    /// their numbers ([`HessianKey`]): cheap even for large sampled fields,
    /// and two different terms collide with probability about 2⁻⁶⁴.
    fn hessian_key(&self) -> Option<u64> {
        None
    }

    /// The centre s at the given degree (`None` for the origin). The
    /// default assembles the whole form; terms with a centre override it
    /// when the centre is cheaper alone.
    fn center(&self, degree: (usize, usize)) -> Result<Option<Vec<Vec3>>> {
        Ok(self.form(degree)?.center)
    }

    /// What the term integrates, for the independent check of every solve
    /// (energy and gradient recomputed in double-double by quadrature on the
    /// written net, see [`crate::Check`]). `None` (the default) when the
    /// check cannot evaluate the term; the report then has no check.
    fn integrand(&self) -> Option<Integrand<'_>> {
        None
    }
}

/// A term's integrand in a form the independent check evaluates without the
/// term's own code: [`EnergyTerm::integrand`].
#[derive(Clone, Copy, Debug)]
pub enum Integrand<'a> {
    /// `w · ½ Σ_patterns c · ∫ |∂ᵘʳ∂ᵛˢ R|²` for patterns ((r, s), c).
    Fairness {
        /// w.
        weight: f64,
        /// Exact integral or sample sum.
        measure: &'a Measure,
        /// ((r, s), c) per derivative pattern.
        patterns: &'static [((usize, usize), f64)],
    },
    /// `½ λ ∫ (R_u·N)² + (R_v·N)²` or its sampled form (normals normalized).
    NormalField {
        /// λ.
        weight: f64,
        /// The guiding normals.
        guide: &'a NormalGuide,
    },
    /// `½ γ ∫ |R − S|²` or its sampled form, S at its own degree.
    GuideSurface {
        /// γ.
        weight: f64,
        /// S.
        surface: &'a crate::TensorPatch,
        /// Exact integral or sample sum.
        measure: &'a Measure,
        /// Per-sample γ_ij (multiplied with γ).
        sample_weights: Option<&'a [f64]>,
    },
    /// `½ γ ∫ |R − S|²` with S a B-spline surface on its own knots
    /// (B-spline surfaces only: their solve's check integrates it span by
    /// span; a Bézier patch's check has no road for it).
    GuideSpline {
        /// γ.
        weight: f64,
        /// S.
        surface: &'a crate::bspline::BSplineSurface,
        /// Exact integral or sample sum (B-spline surfaces take the exact
        /// one only).
        measure: &'a Measure,
        /// Per-sample γ_ij.
        sample_weights: Option<&'a [f64]>,
    },
}

/// |R_u|² + |R_v|²: the stretch (membrane) integrand's patterns.
pub(crate) const STRETCH_PATTERNS: &[((usize, usize), f64)] = &[((1, 0), 1.0), ((0, 1), 1.0)];

/// |R_uu|² + 2|R_uv|² + |R_vv|²: the bend (thin-plate) integrand's patterns.
pub(crate) const BEND_PATTERNS: &[((usize, usize), f64)] =
    &[((2, 0), 1.0), ((1, 1), 2.0), ((0, 2), 1.0)];

/// The Hessian of a quadratic energy term.
#[derive(Clone, Debug)]
pub enum Hessian {
    /// The same (n+1)(m+1)-square matrix acts on x, y and z separately.
    PerCoordinate(Mat<f64>),
    /// One 3(n+1)(m+1)-square matrix over all coordinates, point-major.
    Coupled(Mat<f64>),
}

/// `E(x) = ½ (x − s)ᵀ H (x − s)`: one term, assembled.
#[derive(Clone, Debug)]
pub struct TermForm {
    /// H.
    pub hessian: Hessian,
    /// s, one point per control point; `None` for the origin.
    pub center: Option<Vec<Vec3>>,
}

impl TermForm {
    /// The term's value at the control points `x` (row-major net).
    ///
    /// Evaluated as ½ dᵀHd with d = x − s (never expanded), so a small value
    /// keeps its relative accuracy.
    pub fn value(&self, x: &[Vec3]) -> f64 {
        let d: Vec<Vec3> = match &self.center {
            None => x.to_vec(),
            Some(s) => x
                .iter()
                .zip(s)
                .map(|(a, b)| crate::vec3::sub(*a, *b))
                .collect(),
        };
        match &self.hessian {
            Hessian::PerCoordinate(h) => (0..3)
                .map(|c| {
                    let v: Vec<f64> = d.iter().map(|p| p[c]).collect();
                    0.5 * quad(h, &v)
                })
                .sum(),
            Hessian::Coupled(h) => {
                let v: Vec<f64> = d.iter().flat_map(|p| p.iter().copied()).collect();
                0.5 * quad(h, &v)
            }
        }
    }
}

/// vᵀ H v.
pub(crate) fn quad(h: &Mat<f64>, v: &[f64]) -> f64 {
    let mut s = 0.0;
    for j in 0..v.len() {
        if v[j] == 0.0 {
            continue;
        }
        let col: f64 = (0..v.len()).map(|i| h[(i, j)] * v[i]).sum();
        s += col * v[j];
    }
    s
}

/// Builds an [`EnergyTerm::hessian_key`]: the term's name, then its numbers
/// bit for bit (lists with their length), hashed.
#[derive(Debug)]
pub struct HessianKey(std::hash::DefaultHasher);

impl HessianKey {
    /// A key of the term called `name`.
    pub fn new(name: &str) -> Self {
        let mut h = std::hash::DefaultHasher::new();
        name.hash(&mut h);
        Self(h)
    }

    /// Adds a number.
    pub fn number(mut self, x: f64) -> Self {
        x.to_bits().hash(&mut self.0);
        self
    }

    /// Adds a list of numbers (and its length).
    pub fn numbers(mut self, xs: &[f64]) -> Self {
        xs.len().hash(&mut self.0);
        for x in xs {
            x.to_bits().hash(&mut self.0);
        }
        self
    }

    /// Adds a list of points (and its length).
    pub fn points(self, ps: &[Vec3]) -> Self {
        self.numbers(ps.as_flattened())
    }

    /// Adds anything hashable (sizes, a measure, a tag).
    pub fn with(mut self, x: &impl Hash) -> Self {
        x.hash(&mut self.0);
        self
    }

    /// The key.
    pub fn finish(self) -> u64 {
        self.0.finish()
    }
}

/// How a term is measured over the parameter square.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Measure {
    /// ∫∫ over [0, 1]², exactly (Wu & Yang eq. 1–2).
    Exact,
    /// Σ over a uniform sample grid (Wu & Yang eq. 5).
    Grid(SampleGrid),
}

/// The uniform grid `u_ip = ip/np`, `v_jp = jp/mp` of Wu & Yang §4, with
/// (np+1)(mp+1) samples numbered row-major: sample `ip·(mp+1) + jp`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SampleGrid {
    np: usize,
    mp: usize,
}

impl SampleGrid {
    /// The grid with np+1 by mp+1 samples.
    ///
    /// # Panics
    /// If np or mp is 0; see [`SampleGrid::try_new`].
    pub fn new(np: usize, mp: usize) -> Self {
        Self::try_new(np, mp).expect("SampleGrid::new")
    }

    /// The grid, or an error when np or mp is 0 (one sample per direction has
    /// no spacing).
    pub fn try_new(np: usize, mp: usize) -> Result<Self> {
        if np == 0 || mp == 0 {
            return Err(Error::Mismatch {
                what: "sample grid".into(),
                expected: "np ≥ 1 and mp ≥ 1".into(),
                got: format!("[{np}, {mp}]"),
            });
        }
        Ok(Self { np, mp })
    }

    /// (np, mp).
    pub fn size(&self) -> (usize, usize) {
        (self.np, self.mp)
    }

    /// Number of samples, (np+1)(mp+1).
    pub fn len(&self) -> usize {
        (self.np + 1) * (self.mp + 1)
    }

    /// Always false.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// u_0 … u_np.
    pub fn us(&self) -> Vec<f64> {
        (0..=self.np).map(|i| i as f64 / self.np as f64).collect()
    }

    /// v_0 … v_mp.
    pub fn vs(&self) -> Vec<f64> {
        (0..=self.mp).map(|j| j as f64 / self.mp as f64).collect()
    }

    /// (u, v) of sample k.
    pub fn param(&self, k: usize) -> (f64, f64) {
        let (i, j) = (k / (self.mp + 1), k % (self.mp + 1));
        (i as f64 / self.np as f64, j as f64 / self.mp as f64)
    }

    pub(crate) fn axes(&self) -> (Axis, Axis) {
        (Axis::Samples(self.us()), Axis::Samples(self.vs()))
    }

    /// The (np+1)×(mp+1) weight table from per-sample weights (or all ones).
    pub(crate) fn weight_table(&self, weights: Option<&[f64]>) -> Mat<f64> {
        Mat::from_fn(self.np + 1, self.mp + 1, |i, j| {
            weights.map_or(1.0, |w| w[i * (self.mp + 1) + j])
        })
    }

    /// Checks a per-sample list's length.
    pub(crate) fn check_len(&self, what: &str, got: usize) -> Result<()> {
        if got != self.len() {
            return Err(Error::Mismatch {
                what: what.into(),
                expected: format!(
                    "{} samples ((np+1)(mp+1) for grid [{}, {}])",
                    self.len(),
                    self.np,
                    self.mp
                ),
                got: got.to_string(),
            });
        }
        Ok(())
    }
}

impl Measure {
    /// The axes and unit weight table for an unweighted term.
    pub(crate) fn unit(&self) -> ((Axis, Axis), Mat<f64>) {
        match self {
            Measure::Exact => (
                (Axis::Bernstein(0), Axis::Bernstein(0)),
                Mat::from_fn(1, 1, |_, _| 1.0),
            ),
            Measure::Grid(g) => (g.axes(), g.weight_table(None)),
        }
    }
}

/// Checks that a weight is finite and ≥ 0.
pub(crate) fn check_weight(what: &str, w: f64) -> Result<()> {
    if !w.is_finite() {
        return Err(Error::NotFinite { what: what.into() });
    }
    if w < 0.0 {
        return Err(Error::NegativeWeight {
            what: what.into(),
            value: w,
        });
    }
    Ok(())
}

/// Checks every per-sample weight.
pub(crate) fn check_weights(what: &str, ws: &[f64]) -> Result<()> {
    ws.iter()
        .enumerate()
        .try_for_each(|(k, &w)| check_weight(&format!("{what}[{k}]"), w))
}

/// `w · ½ Σ_patterns c · Σ_coords pattern_value` for an unweighted measure,
/// from the derivative nets of `points` (see [`pattern_value`]).
pub(crate) fn fairness_value(
    degree: (usize, usize),
    measure: &Measure,
    patterns: &[((usize, usize), f64)],
    weight: f64,
    points: &[Vec3],
) -> f64 {
    let ((au, av), w) = measure.unit();
    let mut total = 0.0;
    for &(pattern, c) in patterns {
        // The pattern's product tables once for the three coordinates.
        let form = PatternForm::new(degree, pattern, (&au, &av));
        for coord in 0..3 {
            let d = derivative_net(points, degree, pattern, coord);
            total += c * form.value(&w, &d, &d);
        }
    }
    0.5 * weight * total
}

/// The Hessian key of a fairness term: its name, weight and measure.
pub(crate) fn fairness_key(name: &str, weight: f64, measure: &Measure) -> u64 {
    HessianKey::new(name).number(weight).with(measure).finish()
}

/// Sum of derivative patterns `Σ c · form(pattern)` for an unweighted measure.
pub(crate) fn fairness(
    space: &Space,
    measure: &Measure,
    patterns: &[((usize, usize), f64)],
    weight: f64,
) -> Mat<f64> {
    let ((au, av), w) = measure.unit();
    let scaled: Vec<_> = patterns.iter().map(|&(p, c)| (p, weight * c)).collect();
    form(space, &scaled, (&au, &av), &w)
}
