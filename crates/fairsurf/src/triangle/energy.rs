//! The internal energy of a triangular Bézier patch, α·stretch + β·bend
//! (Veltkamp & Wesselink §3, eq. (6)–(7)), integrated exactly over an
//! **equilateral** domain triangle (§6.1, eq. (25)–(27)) so that the energy
//! does not depend on how the patch's corners are labelled.
//!
//! The derivation, the convention (½∫, unit-side equilateral domain) and
//! the comparison with eq. (27) are on [`InternalEnergy`].

use super::index::{index_of, multi_indices, point_count};
use super::integral::tri_gram_matrix;
use super::patch::TriPatch;
use crate::energy::check_weight;
use crate::vec3::Vec3;
use crate::Result;
use faer::Mat;

/// The corners V₁, V₂, V₃ of the unit-side equilateral domain triangle in
/// (x, y) (Veltkamp & Wesselink eq. (25)): (0, 0), (1, 0), (½, √3/2).
pub const EQUILATERAL: [[f64; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.5, 0.866_025_403_784_438_6]];

/// The area √3/4 of the unit-side equilateral domain triangle.
pub const EQUILATERAL_AREA: f64 = 0.433_012_701_892_219_3;

/// The three edges of the domain as corner pairs (a, b): direction V_b − V_a.
const EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// A linear map from a degree-n net to the degree-(n − order) net
/// `Q_λ = Σ c · P_{λ+shift}` (a difference operator without its factor
/// n!/(n − order)!).
#[derive(Clone, Debug)]
pub(crate) struct Stencil {
    pub order: usize,
    pub terms: Vec<([usize; 3], f64)>,
}

impl Stencil {
    /// D along V_b − V_a: P_{λ+e_b} − P_{λ+e_a}.
    fn edge(a: usize, b: usize) -> Self {
        let (mut sa, mut sb) = ([0; 3], [0; 3]);
        sa[a] = 1;
        sb[b] = 1;
        Self {
            order: 1,
            terms: vec![(sb, 1.0), (sa, -1.0)],
        }
    }

    /// The composition (both are shift-invariant, so they commute).
    fn then(&self, other: &Stencil) -> Self {
        let mut terms = Vec::with_capacity(self.terms.len() * other.terms.len());
        for &(s, c) in &self.terms {
            for &(t, d) in &other.terms {
                terms.push(([s[0] + t[0], s[1] + t[1], s[2] + t[2]], c * d));
            }
        }
        Self {
            order: self.order + other.order,
            terms,
        }
    }

    /// For each term, the positions of P_{λ+shift} in the degree-n net, λ
    /// over the degree-(n − order) net in storage order.
    pub fn positions(&self, n: usize) -> Vec<Vec<usize>> {
        let m = n - self.order;
        self.terms
            .iter()
            .map(|&(s, _)| {
                multi_indices(m)
                    .map(|l| index_of(n, [l[0] + s[0], l[1] + s[1], l[2] + s[2]]))
                    .collect()
            })
            .collect()
    }
}

/// `(weight, D)` pairs with |∇T|² = Σ (weight/9) |D T|² (up to
/// n!/(n−1)!); weights in ninths so that the check can take them exactly.
pub(crate) fn stretch_stencils() -> Vec<(u32, Stencil)> {
    EDGES
        .iter()
        .map(|&(a, b)| (6, Stencil::edge(a, b)))
        .collect()
}

/// `(weight, D)` pairs with ‖Hess T‖²_F = Σ (weight/9) |D T|² (up to
/// n!/(n−2)!): the 9 ordered edge pairs, the 6 off-diagonal ones merged.
pub(crate) fn bend_stencils() -> Vec<(u32, Stencil)> {
    let mut out = Vec::with_capacity(6);
    for (p, &(a, b)) in EDGES.iter().enumerate() {
        for &(c, d) in &EDGES[p..] {
            let w = if (a, b) == (c, d) { 4 } else { 8 };
            out.push((w, Stencil::edge(a, b).then(&Stencil::edge(c, d))));
        }
    }
    out
}

/// A stencil weight in double precision: ninths/9, correctly rounded (6/9
/// is the double nearest ⅔).
fn ninths(w: u32) -> f64 {
    f64::from(w) / 9.0
}

/// n!/(n − r)!.
pub(crate) fn falling(n: usize, r: usize) -> f64 {
    (0..r).map(|i| (n - i) as f64).product()
}

/// `A (n!/(n−r)!)² Σ weight · Dᵀ G D` with G the Gram matrix of degree n − r.
fn form(n: usize, stencils: &[(u32, Stencil)]) -> Mat<f64> {
    let size = point_count(n);
    let mut k = Mat::<f64>::zeros(size, size);
    let Some(order) = stencils.first().map(|s| s.1.order) else {
        return k;
    };
    if n < order {
        return k;
    }
    let m = n - order;
    let gram = tri_gram_matrix(m, m);
    let scale = EQUILATERAL_AREA * falling(n, order).powi(2);
    for (w, st) in stencils {
        let pos = st.positions(n);
        for l in 0..point_count(m) {
            for q in 0..point_count(m) {
                let g = scale * ninths(*w) * gram[(l, q)];
                for (s, &(_, cs)) in st.terms.iter().enumerate() {
                    for (t, &(_, ct)) in st.terms.iter().enumerate() {
                        k[(pos[s][l], pos[t][q])] += g * cs * ct;
                    }
                }
            }
        }
    }
    symmetrize(&mut k);
    k
}

/// Replaces K by (K + Kᵀ)/2, removing the rounding asymmetry of the sums.
fn symmetrize(k: &mut Mat<f64>) {
    for i in 0..k.nrows() {
        for j in 0..i {
            let avg = 0.5 * (k[(i, j)] + k[(j, i)]);
            k[(i, j)] = avg;
            k[(j, i)] = avg;
        }
    }
}

/// `A (n!/(n−r)!)² Σ_c Σ weight · d_cᵀ G d_c` with d_c = D P_c, from the
/// difference nets (no matrix of size (n+1)(n+2)/2 is formed).
fn form_value(n: usize, points: &[Vec3], stencils: &[(u32, Stencil)]) -> f64 {
    let Some(order) = stencils.first().map(|s| s.1.order) else {
        return 0.0;
    };
    if n < order {
        return 0.0;
    }
    let m = n - order;
    let gram = tri_gram_matrix(m, m);
    let mut total = 0.0;
    for (w, st) in stencils {
        let pos = st.positions(n);
        for c in 0..3 {
            let d: Vec<f64> = (0..point_count(m))
                .map(|l| {
                    st.terms
                        .iter()
                        .zip(&pos)
                        .map(|(&(_, cs), p)| cs * points[p[l]][c])
                        .sum()
                })
                .collect();
            total += ninths(*w) * crate::energy::quad(&gram, &d);
        }
    }
    EQUILATERAL_AREA * falling(n, order).powi(2) * total
}

/// The stretch matrix of a degree-n patch over the equilateral domain,
/// `K_s[i][j] = ∫∫_Δ ∇B_i·∇B_j dx dy` (Veltkamp & Wesselink eq. (26)), in
/// the storage order of [`super::linear_index`]:
/// stretch = ½ Σ_{c ∈ x,y,z} P_cᵀ K_s P_c. Symmetric positive semidefinite
/// with the constants as null space; zero for n = 0.
///
/// ```
/// use fairsurf::triangle::{stretch_matrix, EQUILATERAL_AREA};
/// // Degree 1: B_a = u_a, ∇u_a·∇u_b = 4/3 (a = b) or −2/3, times the area.
/// let k = stretch_matrix(1);
/// assert!((k[(0, 0)] - 4.0 / 3.0 * EQUILATERAL_AREA).abs() < 1e-15);
/// assert!((k[(0, 1)] + 2.0 / 3.0 * EQUILATERAL_AREA).abs() < 1e-15);
/// ```
pub fn stretch_matrix(n: usize) -> Mat<f64> {
    form(n, &stretch_stencils())
}

/// The bend matrix of a degree-n patch over the equilateral domain,
/// `K_b[i][j] = ∫∫_Δ B_i,xx B_j,xx + 2 B_i,xy B_j,xy + B_i,yy B_j,yy dx dy`
/// (Veltkamp & Wesselink eq. (7) in the parameters of eq. (25)):
/// bend = ½ Σ_c P_cᵀ K_b P_c. Symmetric positive semidefinite with the
/// affine functions (dimension 3) as null space; zero for n ≤ 1.
///
/// ```
/// use fairsurf::triangle::bend_matrix;
/// let k = bend_matrix(3);
/// assert_eq!(k.nrows(), 10);
/// // Rows sum to zero: constants have no bend.
/// assert!((0..10).all(|i| (0..10).map(|j| k[(i, j)]).sum::<f64>().abs() < 1e-12));
/// ```
pub fn bend_matrix(n: usize) -> Mat<f64> {
    form(n, &bend_stencils())
}

/// `½ ∫∫_Δ |T_x|² + |T_y|² dx dy` over the unit-side equilateral domain
/// (Veltkamp & Wesselink eq. (6), (25)), from the difference nets of the
/// patch: equal to ½ Σ_c P_cᵀ K_s P_c ([`stretch_matrix`]) but without
/// forming K_s.
///
/// ```
/// use fairsurf::triangle::{stretch_value, EQUILATERAL, EQUILATERAL_AREA};
/// use fairsurf::TriPatch;
/// // The domain itself, flat: T = (x, y, 0), |T_x|² + |T_y|² = 2.
/// let t = TriPatch::from_fn(1, |i, j, k| {
///    let c = EQUILATERAL[[i, j, k].iter().position(|&e| e == 1).unwrap()];
///    [c[0], c[1], 0.0]
/// });
/// assert!((stretch_value(&t) - EQUILATERAL_AREA).abs() < 1e-15);
/// ```
pub fn stretch_value(patch: &TriPatch) -> f64 {
    0.5 * form_value(patch.degree(), patch.points(), &stretch_stencils())
}

/// `½ ∫∫_Δ |T_xx|² + 2|T_xy|² + |T_yy|² dx dy` over the unit-side
/// equilateral domain (Veltkamp & Wesselink eq. (7), (25)), from the second
/// difference nets: ½ Σ_c P_cᵀ K_b P_c ([`bend_matrix`]) without forming
/// K_b.
///
/// ```
/// use fairsurf::triangle::{bend_value, EQUILATERAL, EQUILATERAL_AREA};
/// use fairsurf::TriPatch;
/// // z = x² over the domain: T_xx = (0, 0, 2), so bend = ½ · 4 · A.
/// let t = TriPatch::from_fn(2, |i, j, k| {
///    let [v1, v2, v3] = EQUILATERAL;
///    // Blossom of x²: x(a)·x(b) at the two corners each index picks.
///    let picks: Vec<[f64; 2]> = [(i, v1), (j, v2), (k, v3)]
///        .iter()
///        .flat_map(|&(c, v)| std::iter::repeat(v).take(c))
///        .collect();
///    [0.0, 0.0, picks[0][0] * picks[1][0]]
/// });
/// assert!((bend_value(&t) - 2.0 * EQUILATERAL_AREA).abs() < 1e-15);
/// ```
pub fn bend_value(patch: &TriPatch) -> f64 {
    0.5 * form_value(patch.degree(), patch.points(), &bend_stencils())
}

/// The internal energy `α·stretch + β·bend` of Veltkamp & Wesselink §3
/// (E_int, eq. (6)–(7)) over the unit-side equilateral domain (eq. (25)),
/// with the tensor terms' convention `½∫`:
///
/// ```text
/// E(T) = α · ½∫∫|T_x|² + |T_y|² + β · ½∫∫|T_xx|² + 2|T_xy|² + |T_yy|²
///     = ½ Σ_{c ∈ x,y,z} P_cᵀ (α K_s + β K_b) P_c.
/// ```
///
/// Every patch of a given degree has the same matrix (the domain is the same
/// equilateral triangle for all), and it is invariant under permuting the
/// patch's corners.
///
/// # The domain (eq. 25)
///
/// The patch is parameterized by the Cartesian coordinates (x, y) of the
/// equilateral triangle of unit side
///
/// ```text
/// (x, y) = u V₁ + v V₂ + w V₃,   V₁ = (0, 0),  V₂ = (1, 0),  V₃ = (½, √3/2),   area A = √3/4.
/// ```
///
/// # The integrands (eq. 6, 7 in (x, y), as in eq. 26)
///
/// The barycentric coordinates are affine in (x, y) with |∇u_a|² = 4/3 and
/// ∇u_a·∇u_b = −2/3 (a ≠ b), i.e. the Gram matrix of their gradients is
/// 2(I − 𝟙𝟙ᵀ/3) = ⅔ Σ_edges e eᵀ, where e = e_b − e_a is the barycentric
/// direction of the unit edge vector V_b − V_a. By the chain rule, with D_e
/// the directional derivative along e:
///
/// ```text
/// |T_x|² + |T_y|²                 = ⅔ Σ_{e ∈ edges} |D_e T|²
/// |T_xx|² + 2|T_xy|² + |T_yy|²    = 4/9 Σ_{e, f ∈ edges} |D_e D_f T|²      (9 ordered pairs)
/// ```
///
/// (the second is the squared Frobenius norm of the Hessian, tr(G H G H)).
/// Every corner permutation maps the three edge directions to ± themselves,
/// so both sums, and K_s and K_b below, are invariant — the symmetry the
/// paper asks of eq. (26); the plain (u, v) parameterization lacks it.
///
/// D_e T = n Σ_{|λ|=n−1} (P_{λ+e_b} − P_{λ+e_a}) B_λ^{n−1} and D_e D_f T a
/// degree-(n−2) net of second differences times n(n−1); their products are
/// integrated exactly by [`super::tri_product_integral`].
///
/// # Convention (the same as the tensor terms' `½∫`)
///
/// ```text
/// stretch(T) = ½ ∫∫_Δ |T_x|² + |T_y|² dx dy                 = ½ Σ_{c ∈ x,y,z} P_cᵀ K_s P_c
/// bend(T)    = ½ ∫∫_Δ |T_xx|² + 2|T_xy|² + |T_yy|² dx dy    = ½ Σ_c P_cᵀ K_b P_c
/// K_s[i][j]  = ∫∫_Δ ∇B_i·∇B_j dx dy                              (the paper's a_ij, eq. 26)
/// K_b[i][j]  = ∫∫_Δ B_i,xx B_j,xx + 2 B_i,xy B_j,xy + B_i,yy B_j,yy dx dy
/// ```
///
/// The paper writes E = Pᵀ A P with A = K (eq. 6–7 and §6.1 carry no ½), so
/// its energies are twice these; the minimizers are the same.
///
/// **Scale.** The stretch (Dirichlet) energy does not change when the domain
/// triangle is scaled; the bend energy scales as 1/s² with the side s. The
/// paper does not fix s; fairsurf uses s = 1, the edge length of the tensor
/// patches' unit square.
///
/// **Eq. (27).** In the parameters (u, v), w = 1 − u − v, the same matrix is
/// `∫∫ [β₀ B_i,u B_j,u + β₁ (B_i,u B_j,v + B_i,v B_j,u) + β₂ B_i,v B_j,v] J du dv`
/// with β₀ = β₂ = 4/3, β₁ = −2/3 and J = √3/2. The paper prints a single cross
/// term β₁ B_i,u B_j,v, which is not symmetric in i, j; in the quadratic form
/// it is equivalent with β₁ = −4/3.
///
/// # Example
///
/// ```
/// use fairsurf::triangle::InternalEnergy;
/// use fairsurf::TriPatch;
/// let t = TriPatch::from_fn(3, |i, j, k| [i as f64, j as f64, (i * j * k) as f64]);
/// let e = InternalEnergy::new(1.0, 0.5);
/// let k = e.matrix(3).unwrap();
/// let direct = e.value(&t).unwrap();
/// let from_k: f64 = (0..3)
///    .map(|c| {
///        let p: Vec<f64> = t.points().iter().map(|q| q[c]).collect();
///        0.5 * (0..10).flat_map(|i| (0..10).map(move |j| (i, j)))
///            .map(|(i, j)| p[i] * k[(i, j)] * p[j])
///            .sum::<f64>()
///    })
///    .sum();
/// assert!((direct - from_k).abs() < 1e-13 * direct);
/// // Relabelling the corners changes nothing.
/// let q = t.permute_corners([2, 0, 1]);
/// assert!((e.value(&q).unwrap() - direct).abs() < 1e-13 * direct);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InternalEnergy {
    /// α, the weight of the stretch (membrane) energy, ≥ 0.
    pub stretch: f64,
    /// β, the weight of the bend (thin-plate) energy, ≥ 0.
    pub bend: f64,
}

impl InternalEnergy {
    /// α·stretch + β·bend.
    pub fn new(stretch: f64, bend: f64) -> Self {
        Self { stretch, bend }
    }

    /// Checks that both weights are finite and ≥ 0
    /// ([`crate::Error::NotFinite`], [`crate::Error::NegativeWeight`]).
    pub fn validate(&self) -> Result<()> {
        check_weight("stretch weight α", self.stretch)?;
        check_weight("bend weight β", self.bend)
    }

    /// The per-coordinate matrix `α K_s + β K_b` of a degree-n patch, so
    /// that E = ½ Σ_c P_cᵀ K P_c; or an error for a bad weight.
    pub fn matrix(&self, n: usize) -> Result<Mat<f64>> {
        self.validate()?;
        let size = point_count(n);
        let mut k = Mat::<f64>::zeros(size, size);
        if self.stretch != 0.0 {
            k += faer::Scale(self.stretch) * stretch_matrix(n);
        }
        if self.bend != 0.0 {
            k += faer::Scale(self.bend) * bend_matrix(n);
        }
        Ok(k)
    }

    /// E(T) of one patch, from its difference nets ([`stretch_value`],
    /// [`bend_value`]); or an error for a bad weight.
    pub fn value(&self, patch: &TriPatch) -> Result<f64> {
        self.validate()?;
        let mut e = 0.0;
        if self.stretch != 0.0 {
            e += self.stretch * stretch_value(patch);
        }
        if self.bend != 0.0 {
            e += self.bend * bend_value(patch);
        }
        Ok(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wavy(n: usize) -> TriPatch {
        TriPatch::from_fn(n, |i, j, k| {
            let (x, y, z) = (i as f64, j as f64, k as f64);
            [x + 0.3 * y * z, y - 0.2 * x, (x - 2.0 * y + 0.5 * z).sin()]
        })
    }

    fn quad_value(k: &Mat<f64>, t: &TriPatch) -> f64 {
        (0..3)
            .map(|c| {
                let p: Vec<f64> = t.points().iter().map(|q| q[c]).collect();
                0.5 * crate::energy::quad(k, &p)
            })
            .sum()
    }

    #[test]
    fn the_constants_are_what_they_say() {
        assert_eq!(EQUILATERAL_AREA, 3f64.sqrt() / 4.0);
        assert_eq!(EQUILATERAL[2][1], 3f64.sqrt() / 2.0);
    }

    #[test]
    fn value_from_nets_equals_the_matrix_form() {
        for n in 0..7 {
            let t = wavy(n);
            let (s, b) = (stretch_value(&t), bend_value(&t));
            assert!((s - quad_value(&stretch_matrix(n), &t)).abs() <= 1e-13 * s.max(1e-300));
            assert!((b - quad_value(&bend_matrix(n), &t)).abs() <= 1e-13 * b.max(1e-300));
        }
    }

    #[test]
    fn matrices_are_symmetric_and_low_degrees_vanish() {
        let k = bend_matrix(4);
        for i in 0..k.nrows() {
            for j in 0..k.ncols() {
                assert_eq!(k[(i, j)], k[(j, i)]);
            }
        }
        assert_eq!(stretch_matrix(0)[(0, 0)], 0.0);
        let b1 = bend_matrix(1);
        assert!((0..3).all(|i| (0..3).all(|j| b1[(i, j)] == 0.0)));
        assert_eq!(bend_value(&wavy(1)), 0.0);
    }

    #[test]
    fn bad_weights_are_errors() {
        let t = wavy(2);
        assert!(InternalEnergy::new(-1.0, 0.0).value(&t).is_err());
        assert!(InternalEnergy::new(1.0, f64::NAN).matrix(2).is_err());
        assert!(InternalEnergy::new(0.0, 0.0).value(&t).unwrap() == 0.0);
    }
}
