//! Subdivision of triangular Bézier patches (Goldman 1983, "Subdivision
//! algorithms for Bézier triangles"; Veltkamp & Wesselink §2 use the splits
//! into three and into two).
//!
//! Running de Casteljau's algorithm at a point p keeps every level:
//! Pʳ_ijk = b(pʳ, V₁ⁱ, V₂ʲ, V₃ᵏ), i + j + k = n − r, a tetrahedron of points
//! whose three side faces are the control nets of the patches over the
//! triangles (p, V₂, V₃), (V₁, p, V₃) and (V₁, V₂, p):
//!
//! ```text
//! sub-patch 0 (corner V₁ replaced by p):  Q_rjk = Pʳ_0jk
//! sub-patch 1 (corner V₂ replaced by p):  Q_irk = Pʳ_i0k
//! sub-patch 2 (corner V₃ replaced by p):  Q_ijr = Pʳ_ij0
//! ```
//!
//! Two sub-patches read their common edge from the same points of the
//! tetrahedron, so they share those control points bitwise, and each keeps
//! the original control points on its outer edge. For p on an edge only two
//! of the three are proper triangles: that is the split into two.

use super::bernstein::Bary;
use super::index::{index_of, multi_indices, point_count};
use super::patch::{de_casteljau_step, TriPatch};
use crate::vec3::Vec3;

impl TriPatch {
    /// Splits at the interior point p = (u, v, w) into three patches; patch m
    /// is the part over the triangle with corner m replaced by p, with its
    /// corners in the original order (so its normals point the same way):
    /// patch 0 over (p, V₂, V₃), patch 1 over (V₁, p, V₃), patch 2 over
    /// (V₁, V₂, p). Patch m evaluated at its own barycentrics s equals the
    /// original at s_m·p + Σ_{a≠m} s_a·V_a.
    ///
    /// A p outside the triangle still gives patches that reproduce the
    /// (extrapolated) polynomial; a p on an edge degenerates one of them.
    ///
    /// ```
    /// use fairsurf::TriPatch;
    /// let t = TriPatch::from_fn(3, |i, j, k| [i as f64, j as f64, (i * j + k) as f64]);
    /// let p = [0.2, 0.3, 0.5];
    /// let [a, b, c] = t.subdivide_interior(p);
    /// assert_eq!(a.corner(0), t.eval(p));
    /// assert_eq!(a.edge(1).points()[0], b.edge(0).points()[3]); // the shared point p–V₃
    /// ```
    pub fn subdivide_interior(&self, p: Bary) -> [TriPatch; 3] {
        let levels = self.pyramid(p);
        [0, 1, 2].map(|m| face(&levels, self.degree(), m))
    }

    /// Splits at the point of edge k with edge parameter t (the point
    /// `self.edge(k).eval(t)`, see [`TriPatch::edge`]) into two patches, both
    /// keeping corner k: the first covers the part of edge k on [0, t] (its
    /// corner k+2 is replaced by the split point q), the second the part on
    /// [t, 1] (its corner k+1 is replaced by q), indices mod 3. Their
    /// edge k are the two halves of `self.edge(k).subdivide(t)`, and they
    /// share the edge from q to corner k.
    ///
    /// # Panics
    /// If k > 2.
    ///
    /// ```
    /// use fairsurf::TriPatch;
    /// let t = TriPatch::from_fn(2, |i, j, k| [i as f64, j as f64, (i * k) as f64]);
    /// let [a, b] = t.subdivide_edge(2, 0.25);
    /// assert_eq!(a.corner(1), t.eval([0.75, 0.25, 0.0]));
    /// assert_eq!(b.corner(0), t.eval([0.75, 0.25, 0.0]));
    /// ```
    pub fn subdivide_edge(&self, k: usize, t: f64) -> [TriPatch; 2] {
        assert!(k < 3, "a triangle has edges 0, 1 and 2, not {k}");
        let (s, e) = ((k + 1) % 3, (k + 2) % 3);
        let mut q = [0.0; 3];
        q[s] = 1.0 - t;
        q[e] = t;
        let levels = self.pyramid(q);
        [
            face(&levels, self.degree(), e),
            face(&levels, self.degree(), s),
        ]
    }

    /// The same surface over another triangle of the domain: the patch Q
    /// with Q(s) = T(s₀a + s₁b + s₂c) for the corners [a, b, c] given in this
    /// patch's barycentrics (each summing to 1). Its control points are the
    /// blossom values Q_ijk = b(aⁱ, bʲ, cᵏ) (Goldman 1983), computed level by
    /// level in O(n⁵) operations (fine for the low degrees patches use). This is how a patch is cut along a segment
    /// that is not a split of the kinds above.
    ///
    /// ```
    /// use fairsurf::TriPatch;
    /// let t = TriPatch::from_fn(2, |i, j, k| [i as f64, (j * j) as f64, k as f64]);
    /// let (a, b, c) = ([0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.5, 0.0, 0.5]);
    /// let mid = t.restrict([a, b, c]); // the middle quarter
    /// let x = mid.eval([1.0 / 3.0; 3]);
    /// let y = t.eval([1.0 / 3.0; 3]);
    /// assert!((0..3).all(|d| (x[d] - y[d]).abs() < 1e-15));
    /// ```
    pub fn restrict(&self, corners: [Bary; 3]) -> TriPatch {
        let n = self.degree();
        let [a, b, c] = corners;
        let mut out = vec![[0.0; 3]; point_count(n)];
        // After i levels at a, the net na (degree n − i) has blossom
        // b(aⁱ, ·); after j more at b, nb (degree n − i − j) has b(aⁱ, bʲ, ·).
        let mut na = self.points().to_vec();
        for i in 0..=n {
            let mut nb = na.clone();
            for j in 0..=n - i {
                let k = n - i - j;
                out[index_of(n, [i, j, k])] = eval_net(nb.clone(), k, c);
                if k > 0 {
                    nb = de_casteljau_step(&nb, k, b);
                }
            }
            if i < n {
                na = de_casteljau_step(&na, n - i, a);
            }
        }
        TriPatch::new(n, out)
    }

    /// Every de Casteljau level at p: `levels[r]` is the degree-(n − r) net
    /// Pʳ in storage order.
    fn pyramid(&self, p: Bary) -> Vec<Vec<Vec3>> {
        let n = self.degree();
        let mut levels = Vec::with_capacity(n + 1);
        levels.push(self.points().to_vec());
        for r in 1..=n {
            let next = de_casteljau_step(&levels[r - 1], n - r + 1, p);
            levels.push(next);
        }
        levels
    }
}

/// The side face of the de Casteljau tetrahedron opposite corner m: the
/// patch with Q_λ = P^{λ_m}_μ, μ = λ with μ_m = 0.
fn face(levels: &[Vec<Vec3>], n: usize, m: usize) -> TriPatch {
    let points = multi_indices(n)
        .map(|lambda| {
            let r = lambda[m];
            let mut mu = lambda;
            mu[m] = 0;
            levels[r][index_of(n - r, mu)]
        })
        .collect();
    TriPatch::new(n, points)
}

/// De Casteljau evaluation of a degree-m net at x.
fn eval_net(mut net: Vec<Vec3>, m: usize, x: Bary) -> Vec3 {
    for deg in (1..=m).rev() {
        net = de_casteljau_step(&net, deg, x);
    }
    net[0]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vec3::{add, norm, scale, sub};

    fn sample(n: usize) -> TriPatch {
        TriPatch::from_fn(n, |i, j, k| {
            let (x, y, z) = (i as f64, j as f64, k as f64);
            [
                x - 0.2 * y,
                y + 0.1 * z * z,
                (x * 0.7 - z * 0.4 + y * y * 0.1).sin(),
            ]
        })
    }

    fn at(corners: [Bary; 3], s: Bary) -> Bary {
        let mut x = [0.0; 3];
        for (c, w) in corners.iter().zip(s) {
            x = add(x, scale(*c, w));
        }
        x
    }

    #[test]
    fn restrict_to_the_whole_triangle_is_the_identity() {
        let t = sample(4);
        let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert_eq!(t.restrict(id), t);
    }

    #[test]
    fn restrict_agrees_with_the_three_way_split() {
        let t = sample(5);
        let p = [0.3, 0.45, 0.25];
        let (v1, v2, v3) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        let subs = t.subdivide_interior(p);
        let tris = [[p, v2, v3], [v1, p, v3], [v1, v2, p]];
        for (s, c) in subs.iter().zip(tris) {
            let r = t.restrict(c);
            for (x, y) in s.points().iter().zip(r.points()) {
                assert!(norm(sub(*x, *y)) < 1e-14);
            }
        }
    }

    #[test]
    fn restrict_reproduces_over_a_flipped_triangle() {
        let t = sample(3);
        let corners = [[0.1, 0.1, 0.8], [0.6, 0.3, 0.1], [0.2, 0.7, 0.1]];
        let r = t.restrict(corners);
        for s in [[0.2, 0.3, 0.5], [1.0, 0.0, 0.0], [0.05, 0.9, 0.05]] {
            assert!(norm(sub(r.eval(s), t.eval(at(corners, s)))) < 1e-14);
        }
    }

    #[test]
    fn edge_split_halves_the_edge_curve() {
        let t = sample(4);
        for k in 0..3 {
            let [a, b] = t.subdivide_edge(k, 0.35);
            let (l, r) = t.edge(k).subdivide(0.35);
            for (x, y) in a.edge(k).points().iter().zip(l.points()) {
                assert!(norm(sub(*x, *y)) < 1e-15);
            }
            for (x, y) in b.edge(k).points().iter().zip(r.points()) {
                assert!(norm(sub(*x, *y)) < 1e-15);
            }
            assert_eq!(a.corner(k), t.corner(k));
            assert_eq!(b.corner(k), t.corner(k));
        }
    }
}
