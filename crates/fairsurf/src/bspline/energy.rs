//! Exact energies of B-spline surfaces (Wu & Yang eq. 1–2 without the
//! guidance terms): the membrane ½∫∫|R_u|² + |R_v|² and the thin plate
//! ½∫∫|R_uu|² + 2|R_uv|² + |R_vv|² over the parameter rectangle.
//!
//! Every term is a sum of derivative patterns ∫∫ (∂_u^r ∂_v^s R)², and on
//! a tensor-product basis each pattern's matrix is the Kronecker product
//! M_r^u ⊗ M_s^v of one-dimensional matrices M_r[i][k] = ∫ N_i^(r) N_k^(r) du.
//! Those are integrals of piecewise polynomials of degree ≤ 2p, computed
//! span by span with the (p + 1)-point Gauss–Legendre rule, which is exact
//! for them; they are banded (|i − k| ≤ p) and their condition does not grow
//! with the number of spans as a Bernstein basis's does with the degree.

use super::{BSplineSurface, BezierPiece, KnotVector};
use crate::basis::GaussLegendre;
use crate::energy::{derivative_net, Measure, PatternForm};
use crate::Vec3;

/// The one-dimensional matrices M_0, M_1, M_2 of a knot vector (dense
/// storage; nonzero within the band |i − k| ≤ p).
#[derive(Clone, Debug)]
pub(crate) struct Gram1d {
    count: usize,
    degree: usize,
    m: [Vec<f64>; 3],
}

impl Gram1d {
    pub(crate) fn new(k: &KnotVector) -> Self {
        let (c, p) = (k.count(), k.degree());
        let gl = GaussLegendre::new(p + 1);
        let mut m = [vec![0.0; c * c], vec![0.0; c * c], vec![0.0; c * c]];
        let mut d = vec![0.0; 3 * (p + 1)];
        for (span, a, b) in k.spans() {
            let h = b - a;
            for (&x, &w) in gl.nodes.iter().zip(&gl.weights) {
                let t = a + h * x;
                k.basis_derivatives_into(span, t, 2, &mut d);
                for (r, mr) in m.iter_mut().enumerate() {
                    let dr = &d[r * (p + 1)..(r + 1) * (p + 1)];
                    for i in 0..=p {
                        for l in 0..=p {
                            mr[(span - p + i) * c + span - p + l] += w * h * dr[i] * dr[l];
                        }
                    }
                }
            }
        }
        Self {
            count: c,
            degree: p,
            m,
        }
    }

    /// The number of basis functions.
    pub(crate) fn count(&self) -> usize {
        self.count
    }

    /// M_r[i][k].
    pub(crate) fn at(&self, r: usize, i: usize, k: usize) -> f64 {
        self.m[r][i * self.count + k]
    }

    /// The columns k with a possibly nonzero M_r[i][k].
    pub(crate) fn band(&self, i: usize) -> std::ops::Range<usize> {
        i.saturating_sub(self.degree)..(i + self.degree + 1).min(self.count)
    }
}

/// (coefficient, r, s) of the derivative patterns of `stretch`·membrane +
/// `bend`·thin plate (zero weights left out).
pub(crate) fn patterns(stretch: f64, bend: f64) -> Vec<(f64, usize, usize)> {
    let mut out = Vec::new();
    if stretch != 0.0 {
        out.extend([(stretch, 1, 0), (stretch, 0, 1)]);
    }
    if bend != 0.0 {
        out.extend([(bend, 2, 0), (2.0 * bend, 1, 1), (bend, 0, 2)]);
    }
    out
}

impl BSplineSurface {
    /// The Dirichlet functional ½∫∫|R_u|² + |R_v|² over the domain, exact.
    pub fn dirichlet(&self) -> f64 {
        energy_by_pieces(&self.bezier_pieces(), self.degree(), &patterns(1.0, 0.0))
    }

    /// The thin-plate functional ½∫∫|R_uu|² + 2|R_uv|² + |R_vv|², exact.
    pub fn biharmonic(&self) -> f64 {
        energy_by_pieces(&self.bezier_pieces(), self.degree(), &patterns(0.0, 1.0))
    }
}

/// The energy ½ Σ c ∫∫ (∂_u^r ∂_v^s R)² from each Bézier piece's
/// derivative nets against the Bernstein products' closed forms (whose
/// entries are all ≥ 0: no cancellation, unlike xᵀHx, which loses 1e-9 of
/// a 47 × 47-span thin plate to the planar part's cancellation, measured),
/// scaled from the piece's local parameters to the surface's:
/// ∫∫ (∂_u^r ∂_v^s R)² du dv = h_u^(1−2r) h_v^(1−2s) ∫∫ (∂_s^r ∂_t^s R)² ds dt.
pub(crate) fn energy_by_pieces(
    pieces: &[BezierPiece],
    degree: (usize, usize),
    patterns: &[(f64, usize, usize)],
) -> f64 {
    let ((au, av), w) = Measure::Exact.unit();
    let forms: Vec<_> = patterns
        .iter()
        .map(|&(_, r, s)| PatternForm::new(degree, (r, s), (&au, &av)))
        .collect();
    let mut total = 0.0;
    for piece in pieces {
        let (hu, hv) = (piece.u.1 - piece.u.0, piece.v.1 - piece.v.0);
        for (&(c, r, s), form) in patterns.iter().zip(&forms) {
            let scale = hu.powi(1 - 2 * r as i32) * hv.powi(1 - 2 * s as i32);
            for coord in 0..3 {
                let d = derivative_net(piece.patch.points(), degree, (r, s), coord);
                total += c * scale * form.value(&w, &d, &d);
            }
        }
    }
    0.5 * total
}

/// The same energy by Gauss–Legendre quadrature of the integrand span by
/// span: (p + 1) × (q + 1) nodes, exact for its degree 2p × 2q, from the
/// pieces' derivatives at the nodes (the check's second road).
pub(crate) fn energy_by_quadrature(
    pieces: &[BezierPiece],
    (p, q): (usize, usize),
    patterns: &[(f64, usize, usize)],
) -> f64 {
    let (gu, gv) = (GaussLegendre::new(p + 1), GaussLegendre::new(q + 1));
    let mut total = 0.0;
    for piece in pieces {
        let (hu, hv) = (piece.u.1 - piece.u.0, piece.v.1 - piece.v.0);
        let d = piece.patch.derivatives_on(&gu.nodes, &gv.nodes);
        for (a, wa) in gu.weights.iter().enumerate() {
            for (b, wb) in gv.weights.iter().enumerate() {
                let x = &d[a * gv.nodes.len() + b];
                let sq = |v: Vec3| v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
                let value: f64 = patterns
                    .iter()
                    .map(|&(c, r, s)| {
                        let part = match (r, s) {
                            (1, 0) => x.du,
                            (0, 1) => x.dv,
                            (2, 0) => x.duu,
                            (1, 1) => x.duv,
                            (0, 2) => x.dvv,
                            _ => unreachable!("patterns of order 1 and 2"),
                        };
                        c * sq(part) / (hu.powi(2 * r as i32) * hv.powi(2 * s as i32))
                    })
                    .sum();
                total += wa * wb * hu * hv * value;
            }
        }
    }
    0.5 * total
}
