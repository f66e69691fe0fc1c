//! Triangular Bézier patches (Veltkamp & Wesselink, §2, eq. (2)):
//!
//! ```text
//! T(u, v, w) = Σ_{i+j+k=n} P_ijk B_ijk^n(u, v, w),   u + v + w = 1,  u, v, w ≥ 0,
//! ```
//!
//! evaluated by de Casteljau's algorithm (Farin 1993; Goldman 1983)
//!
//! ```text
//! P⁰_ijk = P_ijk,
//! Pʳ_ijk = u Pʳ⁻¹_{i+1,j,k} + v Pʳ⁻¹_{i,j+1,k} + w Pʳ⁻¹_{i,j,k+1},  i + j + k = n − r,
//! T(u, v, w) = Pⁿ_000,
//! ```
//!
//! or by the Bernstein form. Running the same recurrence with a different
//! triple at each level computes the blossom b(x₁, …, xₙ), the symmetric
//! multi-affine polar form of T with b(x, …, x) = T(x); derivatives and
//! subdivision are blossom values.

use super::bernstein::{tri_bernstein_all, Bary};
use super::index::{checked_point_count, index_of, multi_index, multi_indices, point_count};
use crate::vec3::{add, is_finite, scale, Vec3};
use crate::{BezierCurve, Error, Result};

/// A triangular Bézier patch of degree n with control points P_ijk,
/// i + j + k = n, over the domain triangle V₁V₂V₃ with barycentric
/// coordinates (u, v, w).
///
/// **Storage order** ([`super::linear_index`]): rows of constant k from
/// k = 0 to n, each by increasing j, so `points[k(2n+3−k)/2 + j] = P_ijk`.
///
/// **Corners**: corner 0 = V₁ = P_n00 (u = 1), corner 1 = V₂ = P_0n0 (v = 1),
/// corner 2 = V₃ = P_00n (w = 1).
///
/// **Edges**: edge k is the side opposite corner k, where the k-th
/// barycentric coordinate vanishes, run from corner k+1 to corner k+2
/// (mod 3): edge 0 (u = 0) from V₂ to V₃, edge 1 (v = 0) from V₃ to V₁,
/// edge 2 (w = 0) from V₁ to V₂. Seen from the side the normal
/// T_u × T_v points to, V₁ → V₂ → V₃ runs counter-clockwise.
///
/// ```
/// use fairsurf::TriPatch;
/// // The flat triangle (0,0,0), (1,0,0), (0,1,0) written as a cubic.
/// let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
/// let t = TriPatch::from_fn(3, |i, j, k| {
///     let (i, j, k) = (i as f64 / 3.0, j as f64 / 3.0, k as f64 / 3.0);
///     [0, 1, 2].map(|x| i * a[x] + j * b[x] + k * c[x])
/// });
/// let p = t.eval([0.2, 0.3, 0.5]);
/// assert!((p[0] - 0.3).abs() < 1e-15 && (p[1] - 0.5).abs() < 1e-15);
/// assert_eq!(t.normal([0.2, 0.3, 0.5]), Some([0.0, 0.0, 1.0]));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct TriPatch {
    degree: usize,
    points: Vec<Vec3>,
}

impl TriPatch {
    /// A patch of degree n from its (n+1)(n+2)/2 control points in storage
    /// order.
    ///
    /// # Panics
    /// If the count is wrong or a coordinate is not finite; see
    /// [`TriPatch::try_new`].
    pub fn new(n: usize, points: Vec<Vec3>) -> Self {
        Self::try_new(n, points).expect("TriPatch::new")
    }

    /// A patch of degree n, or an error naming the bad count
    /// ([`Error::Mismatch`]) or the first non-finite point
    /// ([`Error::NotFinite`], "control point (i, j, k)").
    ///
    /// ```
    /// use fairsurf::{Error, TriPatch};
    /// assert!(matches!(
    ///     TriPatch::try_new(2, vec![[0.0; 3]; 5]),
    ///     Err(Error::Mismatch { .. })
    /// ));
    /// ```
    pub fn try_new(n: usize, points: Vec<Vec3>) -> Result<Self> {
        let expected = checked_point_count(n);
        if expected != Some(points.len()) {
            return Err(Error::Mismatch {
                what: format!("control points of a degree-{n} triangular patch"),
                expected: match expected {
                    Some(e) => format!("{e} = (n+1)(n+2)/2"),
                    None => "more than usize::MAX".into(),
                },
                got: points.len().to_string(),
            });
        }
        if let Some(l) = points.iter().position(|&p| !is_finite(p)) {
            let [i, j, k] = multi_index(n, l);
            return Err(Error::NotFinite {
                what: format!("control point ({i}, {j}, {k})"),
            });
        }
        Ok(Self { degree: n, points })
    }

    /// A patch whose control point P_ijk is `f(i, j, k)`, called in storage
    /// order.
    ///
    /// # Panics
    /// If `f` returns a non-finite coordinate.
    pub fn from_fn(n: usize, mut f: impl FnMut(usize, usize, usize) -> Vec3) -> Self {
        let points = multi_indices(n).map(|[i, j, k]| f(i, j, k)).collect();
        Self::new(n, points)
    }

    /// The degree n.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Number of control points, (n+1)(n+2)/2.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Always false: a patch has at least one control point.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// All control points in storage order.
    pub fn points(&self) -> &[Vec3] {
        &self.points
    }

    /// Index of P_ijk in [`TriPatch::points`].
    ///
    /// # Panics
    /// If i + j + k ≠ n.
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        super::linear_index(self.degree, i, j, k)
    }

    /// P_ijk.
    ///
    /// # Panics
    /// If i + j + k ≠ n.
    pub fn point(&self, i: usize, j: usize, k: usize) -> Vec3 {
        self.points[self.index(i, j, k)]
    }

    /// Replaces P_ijk.
    ///
    /// # Panics
    /// If p is not finite or i + j + k ≠ n.
    pub fn set_point(&mut self, i: usize, j: usize, k: usize, p: Vec3) {
        assert!(is_finite(p), "control points must be finite");
        let l = self.index(i, j, k);
        self.points[l] = p;
    }

    /// The control point at corner m (0: P_n00, 1: P_0n0, 2: P_00n), which
    /// the patch interpolates.
    ///
    /// # Panics
    /// If m > 2.
    pub fn corner(&self, m: usize) -> Vec3 {
        let mut e = [0; 3];
        e[m] = self.degree;
        self.points[index_of(self.degree, e)]
    }

    /// T(u, v, w) by de Casteljau's algorithm: n levels of convex
    /// combinations when (u, v, w) is in the triangle, O(n³) work.
    pub fn eval(&self, b: Bary) -> Vec3 {
        reduce(self.points.clone(), self.degree, b, 0)[0]
    }

    /// T(u, v, w) by the Bernstein form Σ P_ijk B_ijk^n(u, v, w), with the
    /// basis from the explicit formula ([`super::tri_bernstein_all`]).
    pub fn eval_bernstein(&self, b: Bary) -> Vec3 {
        tri_bernstein_all(self.degree, b)
            .into_iter()
            .zip(&self.points)
            .fold([0.0; 3], |acc, (w, &p)| add(acc, scale(p, w)))
    }

    /// The blossom b(x₁, …, xₙ): de Casteljau's algorithm with xᵣ at level r.
    /// It is symmetric and affine in each argument, b(x, …, x) = T(x), and
    /// P_ijk = b(V₁ⁱ, V₂ʲ, V₃ᵏ) with V₁ = (1, 0, 0) etc. (Ramshaw's polar
    /// form; Goldman 1983 subdivides with it).
    ///
    /// # Panics
    /// If `args.len()` ≠ n.
    pub fn blossom(&self, args: &[Bary]) -> Vec3 {
        assert_eq!(
            args.len(),
            self.degree,
            "the blossom of a degree-{} patch takes {} arguments",
            self.degree,
            self.degree
        );
        let mut net = self.points.clone();
        for (level, &x) in args.iter().enumerate() {
            net = de_casteljau_step(&net, self.degree - level, x);
        }
        net[0]
    }

    /// Boundary edge k as a Bézier curve of degree n, from corner k+1 to
    /// corner k+2 (mod 3); C(t) = T at the barycentrics with coordinate k
    /// zero, 1 − t at corner k+1 and t at corner k+2 (Veltkamp & Wesselink
    /// eq. (3), which runs edge 2 the other way):
    ///
    /// ```text
    /// edge 0 (u = 0): P_{0, n−l, l}     edge 1 (v = 0): P_{l, 0, n−l}
    /// edge 2 (w = 0): P_{n−l, l, 0},    l = 0 … n
    /// ```
    ///
    /// # Panics
    /// If k > 2.
    pub fn edge(&self, k: usize) -> BezierCurve {
        assert!(k < 3, "a triangle has edges 0, 1 and 2, not {k}");
        let (s, e, n) = ((k + 1) % 3, (k + 2) % 3, self.degree);
        let pts = (0..=n)
            .map(|l| {
                let mut m = [0; 3];
                m[s] = n - l;
                m[e] = l;
                self.points[index_of(n, m)]
            })
            .collect();
        BezierCurve::new(pts)
    }

    /// The same surface with its corners relabelled: new corner m is old
    /// corner `perm[m]`, so
    ///
    /// ```text
    /// Q_λ = P_μ with μ[perm[m]] = λ[m],   Q(b) = T(b′) with b′[perm[m]] = b[m].
    /// ```
    ///
    /// An odd permutation flips the normal.
    ///
    /// ```
    /// use fairsurf::TriPatch;
    /// let t = TriPatch::from_fn(2, |i, j, k| [i as f64, j as f64, (j * k) as f64]);
    /// let q = t.permute_corners([1, 2, 0]); // corners (V₂, V₃, V₁)
    /// assert_eq!(q.corner(0), t.corner(1));
    /// let (a, b) = (q.eval([0.2, 0.3, 0.5]), t.eval([0.5, 0.2, 0.3]));
    /// assert!((0..3).all(|x| (a[x] - b[x]).abs() < 1e-15));
    /// ```
    ///
    /// # Panics
    /// If `perm` is not a permutation of 0, 1, 2.
    pub fn permute_corners(&self, perm: [usize; 3]) -> TriPatch {
        let mut sorted = perm;
        sorted.sort_unstable();
        assert_eq!(
            sorted,
            [0, 1, 2],
            "{perm:?} is not a permutation of 0, 1, 2"
        );
        let n = self.degree;
        TriPatch::from_fn(n, |i, j, k| {
            let lambda = [i, j, k];
            let mut mu = [0; 3];
            for m in 0..3 {
                mu[perm[m]] = lambda[m];
            }
            self.points[index_of(n, mu)]
        })
    }

    /// A copy with each control point mapped by `f`.
    ///
    /// # Panics
    /// If `f` returns a non-finite coordinate.
    pub fn map(&self, f: impl FnMut(&Vec3) -> Vec3) -> TriPatch {
        TriPatch::new(self.degree, self.points.iter().map(f).collect())
    }

    /// The net after the first n − `to` de Casteljau levels at b: a degree-`to`
    /// net whose blossom is b(·, …, ·, b, …, b).
    pub(super) fn reduce_to(&self, b: Bary, to: usize) -> Vec<Vec3> {
        reduce(self.points.clone(), self.degree, b, to)
    }
}

/// One de Casteljau level on a degree-m net (m ≥ 1) in storage order:
/// `Q_ijk = x₀ P_{i+1,j,k} + x₁ P_{i,j+1,k} + x₂ P_{i,j,k+1}`, i + j + k = m − 1.
pub(super) fn de_casteljau_step(net: &[Vec3], m: usize, x: Bary) -> Vec<Vec3> {
    debug_assert!(m >= 1 && net.len() == point_count(m));
    let mut out = Vec::with_capacity(point_count(m - 1));
    let mut row = 0; // start of row k in the degree-m net
    for k in 0..m {
        let next = row + m - k + 1; // start of row k + 1
        for j in 0..m - k {
            let p = add(scale(net[row + j], x[0]), scale(net[row + j + 1], x[1]));
            out.push(add(p, scale(net[next + j], x[2])));
        }
        row = next;
    }
    out
}

/// De Casteljau levels at b from degree m down to degree `to`, in place:
/// level m − 1's point (i, j, k) is stored at or before every point of
/// level m that a later one reads, so each level overwrites the last (no
/// allocation per level; the same arithmetic as [`de_casteljau_step`]).
fn reduce(mut net: Vec<Vec3>, m: usize, b: Bary, to: usize) -> Vec<Vec3> {
    for deg in (to + 1..=m).rev() {
        let mut out = 0;
        let mut row = 0;
        for k in 0..deg {
            let next = row + deg - k + 1;
            for j in 0..deg - k {
                let p = add(scale(net[row + j], b[0]), scale(net[row + j + 1], b[1]));
                net[out] = add(p, scale(net[next + j], b[2]));
                out += 1;
            }
            row = next;
        }
    }
    net.truncate(point_count(to));
    net
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vec3::{norm, sub};

    fn wavy(n: usize) -> TriPatch {
        TriPatch::from_fn(n, |i, j, k| {
            let (x, y, z) = (i as f64, j as f64, k as f64);
            [x + 0.3 * y, y - 0.1 * z * x, (x - 2.0 * y + z).sin()]
        })
    }

    #[test]
    fn corners_are_interpolated() {
        let t = wavy(4);
        assert_eq!(t.eval([1.0, 0.0, 0.0]), t.point(4, 0, 0));
        assert_eq!(t.eval([0.0, 1.0, 0.0]), t.point(0, 4, 0));
        assert_eq!(t.eval([0.0, 0.0, 1.0]), t.point(0, 0, 4));
        for m in 0..3 {
            let mut b = [0.0; 3];
            b[m] = 1.0;
            assert_eq!(t.corner(m), t.eval(b));
        }
    }

    #[test]
    fn blossom_on_the_diagonal_is_the_point_and_is_symmetric() {
        let t = wavy(3);
        let x = [0.2, 0.5, 0.3];
        assert_eq!(t.blossom(&[x, x, x]), t.eval(x));
        let (a, b, c) = ([0.7, 0.1, 0.2], [0.0, 0.4, 0.6], [1.5, -0.2, -0.3]);
        let abc = t.blossom(&[a, b, c]);
        for args in [[b, a, c], [c, b, a], [a, c, b]] {
            assert!(norm(sub(t.blossom(&args), abc)) < 1e-14);
        }
        // Control points are blossom values at the corners.
        let (v1, v2, v3) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        assert_eq!(t.blossom(&[v1, v2, v3]), t.point(1, 1, 1));
        assert_eq!(t.blossom(&[v3, v3, v1]), t.point(1, 0, 2));
    }

    #[test]
    fn edges_follow_the_documented_numbering() {
        let t = wavy(3);
        let e2 = t.edge(2);
        assert_eq!(e2.points()[0], t.corner(0));
        assert_eq!(e2.points()[3], t.corner(1));
        assert_eq!(e2.points()[1], t.point(2, 1, 0));
        assert_eq!(t.edge(0).points()[1], t.point(0, 2, 1));
        assert_eq!(t.edge(1).points()[1], t.point(1, 0, 2));
        for k in 0..3 {
            let c = t.edge(k);
            assert_eq!(c.points()[0], t.corner((k + 1) % 3));
            assert_eq!(c.points()[3], t.corner((k + 2) % 3));
            for &s in &[0.1, 0.5, 0.85] {
                let mut b = [0.0; 3];
                b[(k + 1) % 3] = 1.0 - s;
                b[(k + 2) % 3] = s;
                assert!(norm(sub(c.eval(s), t.eval(b))) < 1e-14);
            }
        }
    }

    #[test]
    fn degree_zero_is_a_constant() {
        let t = TriPatch::new(0, vec![[1.0, 2.0, 3.0]]);
        assert_eq!(t.eval([0.2, 0.2, 0.6]), [1.0, 2.0, 3.0]);
        assert_eq!(t.eval_bernstein([0.2, 0.2, 0.6]), [1.0, 2.0, 3.0]);
        assert_eq!(t.blossom(&[]), [1.0, 2.0, 3.0]);
        assert_eq!(t.edge(1).points(), &[[1.0, 2.0, 3.0]]);
    }

    #[test]
    fn set_point_and_map() {
        let mut t = wavy(2);
        t.set_point(0, 1, 1, [9.0, 9.0, 9.0]);
        assert_eq!(t.points()[4], [9.0, 9.0, 9.0]);
        let s = t.map(|p| scale(*p, 2.0));
        assert_eq!(s.point(0, 1, 1), [18.0, 18.0, 18.0]);
    }

    #[test]
    #[should_panic(expected = "not a permutation")]
    fn a_bad_permutation_panics() {
        wavy(2).permute_corners([0, 0, 1]);
    }

    #[test]
    #[should_panic(expected = "takes 3 arguments")]
    fn blossom_with_the_wrong_arity_panics() {
        wavy(3).blossom(&[[1.0, 0.0, 0.0]]);
    }
}
