//! Extremals of the Dirichlet and biharmonic functionals (Monterde & Ugail
//! §4.1) and the comparison table of §4.
//!
//! The extremals are assembled from fairsurf's exact energies (the
//! [`Stretch`] and [`Bend`] terms) rather than from eq. (15), which as
//! printed holds only for n = m.

use super::surface::ConstructOptions;
use super::{biharmonic_with, harmonic_mask, Construction};
use crate::{Bend, Problem, Result, Solution, Stretch, SurfaceMeasures, TensorPatch};

/// A functional to extremize with the boundary fixed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Functional {
    /// D = ½ ∫∫ |x_u|² + |x_v|² (eq. 2).
    Dirichlet,
    /// B = ½ ∫∫ |x_uu|² + 2|x_uv|² + |x_vv|² (eq. 3).
    Biharmonic,
}

/// The Bézier surface with the boundary ring of `net` extremal for `f`: the
/// unique minimizer over the inner control points (both functionals are
/// positive definite there).
///
/// ```
/// use fairsurf::{harmonic::{extremal, Functional}, TensorPatch};
/// let net = TensorPatch::from_fn(3, 3, |i, j| [i as f64, j as f64, if i % 3 == 0 { 1.0 } else { 0.0 }]);
/// let e = extremal(&net, Functional::Dirichlet).unwrap();
/// assert!(e.report.relative_gradient < 1e-14);
/// ```
pub fn extremal(net: &TensorPatch, f: Functional) -> Result<Solution> {
    let p = Problem::new(net.degree()).with_fixed_rings(net, 1);
    match f {
        Functional::Dirichlet => p.with_term(Stretch::new(1.0)),
        Functional::Biharmonic => p.with_term(Bend::new(1.0)),
    }
    .solve()
}

/// One column of the comparison: a surface and its measures.
#[derive(Clone, Debug)]
pub struct Column {
    /// The surface.
    pub patch: TensorPatch,
    /// Area (±error), Dirichlet and biharmonic functionals, curvature.
    pub measures: SurfaceMeasures,
    /// Whether the construction's equations hold (false: a least-squares
    /// biharmonic net, the exact one does not exist for this boundary).
    pub exact: bool,
    /// The construction's residual (0 for the extremals, whose gradient is
    /// reported instead).
    pub residual: f64,
}

/// Monterde & Ugail §4: four surfaces with one boundary — harmonic extremal,
/// harmonic mask, biharmonic surface, biharmonic extremal.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// Minimizer of the Dirichlet functional.
    pub harmonic_extremal: Column,
    /// The harmonic (Coons) mask.
    pub harmonic_mask: Column,
    /// The biharmonic Bézier surface (least squares when it does not exist).
    pub biharmonic_surface: Column,
    /// Minimizer of the biharmonic functional.
    pub biharmonic_extremal: Column,
}

impl Comparison {
    /// The columns with their names, in the paper's order.
    pub fn columns(&self) -> [(&'static str, &Column); 4] {
        [
            ("harmonic_extremal", &self.harmonic_extremal),
            ("harmonic_mask", &self.harmonic_mask),
            ("biharmonic_surface", &self.biharmonic_surface),
            ("biharmonic_extremal", &self.biharmonic_extremal),
        ]
    }
}

/// Builds the four surfaces for the boundary ring of `net` (n, m ≥ 2).
pub fn compare(net: &TensorPatch) -> Result<Comparison> {
    let from_solution = |s: Solution| Column {
        measures: s.report.measures.expect("analysis is on by default"),
        patch: s.surface,
        exact: true,
        residual: 0.0,
    };
    let from_construction = |c: Construction| Column {
        measures: c.report.measures.expect("analysis is on by default"),
        patch: c.patch,
        exact: c.report.exact,
        residual: c.report.residual,
    };
    let lsq = ConstructOptions {
        least_squares: true,
        ..ConstructOptions::default()
    };
    Ok(Comparison {
        harmonic_extremal: from_solution(extremal(net, Functional::Dirichlet)?),
        harmonic_mask: from_construction(harmonic_mask(net)?),
        biharmonic_surface: from_construction(biharmonic_with(net, &lsq)?),
        biharmonic_extremal: from_solution(extremal(net, Functional::Biharmonic)?),
    })
}
