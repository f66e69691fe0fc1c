//! Surface area by adaptive Gauss–Legendre quadrature.
//!
//! `A = ∫∫ |R_u × R_v| du dv` has no closed form (a square root of a
//! polynomial). The integrand is analytic on regular patches, so tensor Gauss
//! rules converge fast there; where the patch is not regular (a collapsed
//! corner, boundary curves meeting tangentially as in Monterde & Ugail's
//! Fig. 7, or a fold where R_u × R_v changes sign) the integrand has a kink
//! and Gauss rules converge slowly. So the domain is a quadtree of panels,
//! each compared with the sum over its four children; the panel with the
//! largest disagreement is split until the sum of disagreements (reported
//! as the error estimate) is below 1e-13 relative, or the panel budget runs
//! out.

use crate::basis::GaussLegendre;
use crate::tensor::{chunk3, GridRows, GRID_LANES};
use crate::vec3::{cross, norm};
use crate::TensorPatch;

/// An area with its estimated absolute error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Area {
    /// The area.
    pub value: f64,
    /// Sum over the quadtree leaves of |rule on the leaf − rule on its four
    /// children| (the value uses the children): a conservative estimate of
    /// the quadrature error.
    pub error: f64,
}

/// Relative tolerance of [`area`].
pub const AREA_TOLERANCE: f64 = 1e-13;

/// Most panels evaluated by [`area`] before it stops refining and reports
/// the error it has reached.
pub const AREA_MAX_PANELS: usize = 4_000;

/// The area of a patch.
///
/// ```
/// use fairsurf::{analysis::area, TensorPatch};
/// // A flat 2×3 rectangle written at degree (3, 2).
/// let r = TensorPatch::from_fn(3, 2, |i, j| [2.0 * i as f64 / 3.0, 3.0 * j as f64 / 2.0, 0.0]);
/// assert!((area(&r).value - 6.0).abs() < 1e-13);
/// ```
pub fn area(patch: &TensorPatch) -> Area {
    let (n, m) = patch.degree();
    let gl = GaussLegendre::new(n.max(m) + 4);
    // A leaf: the panel, its rule on its four children, and |split − whole|.
    let leaf = |q: (f64, f64, f64), whole: f64, vals: [f64; 4]| -> Leaf {
        let sum: f64 = vals.iter().sum();
        Leaf {
            error: (sum - whole).abs(),
            value: sum,
            kids: children(q),
            kid_values: vals,
        }
    };
    // A panel's four children from one grid of their nodes, in the order
    // of `children`.
    let split = |q, whole| {
        let p = panels(patch, &gl, q, 2);
        leaf(q, whole, [p[0], p[2], p[1], p[3]])
    };
    // Start from a uniform 2×2 grid of panels with their 4×4 children (two
    // tensor grids of nodes, evaluated a row at a time), then always split
    // the leaf with the largest error (global adaptivity: cheap on kinks
    // along curves as well as at points).
    let k = 2;
    let h = 1.0 / k as f64;
    let unit = (0.0, 0.0, 1.0);
    let (whole, kids) = (panels(patch, &gl, unit, k), panels(patch, &gl, unit, 2 * k));
    let mut heap = std::collections::BinaryHeap::new();
    for p in 0..k * k {
        let (i, j) = (p / k, p % k);
        let q = (i as f64 * h, j as f64 * h, h);
        let kid = |di: usize, dj: usize| kids[(2 * i + di) * 2 * k + 2 * j + dj];
        heap.push(leaf(
            q,
            whole[p],
            [kid(0, 0), kid(1, 0), kid(0, 1), kid(1, 1)],
        ));
    }
    let total = |heap: &std::collections::BinaryHeap<Leaf>| -> (f64, f64) {
        heap.iter()
            .fold((0.0, 0.0), |(v, e), l| (v + l.value, e + l.error))
    };
    let (mut value, mut error) = total(&heap);
    while error > AREA_TOLERANCE * value.abs()
        && heap.len() * 4 < AREA_MAX_PANELS
        && !crate::budget::cancelled()
    {
        let worst = heap.pop().expect("never empty");
        for (q, v) in worst.kids.into_iter().zip(worst.kid_values) {
            heap.push(split(q, v));
        }
        // Re-summing keeps the totals free of cancellation drift.
        (value, error) = total(&heap);
    }
    Area { value, error }
}

/// The four quarters of the panel (u0, v0, side h), in the order the
/// uniform start lists them: (0, 0), (1, 0), (0, 1), (1, 1).
fn children((u0, v0, h): (f64, f64, f64)) -> [(f64, f64, f64); 4] {
    let c = h / 2.0;
    [
        (u0, v0, c),
        (u0 + c, v0, c),
        (u0, v0 + c, c),
        (u0 + c, v0 + c, c),
    ]
}

struct Leaf {
    error: f64,
    value: f64,
    kids: [(f64, f64, f64); 4],
    kid_values: [f64; 4],
}

impl PartialEq for Leaf {
    fn eq(&self, other: &Self) -> bool {
        self.error == other.error
    }
}
impl Eq for Leaf {}
impl PartialOrd for Leaf {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Leaf {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.error.total_cmp(&other.error)
    }
}

/// The rule on each panel of the k × k partition of the square (u0, v0,
/// side h) (u-major: entry i·k + j at (u0 + i·h/k, v0 + j·h/k)), from one
/// tensor grid of all the panels' nodes evaluated a row at a time: per
/// panel of side c, c² Σ_a w_a Σ_b w_b |R_u × R_v| at the nodes
/// (u0 + i·c + s_a·c, v0 + j·c + s_b·c).
fn panels(
    patch: &TensorPatch,
    gl: &GaussLegendre,
    (u0, v0, h): (f64, f64, f64),
    k: usize,
) -> Vec<f64> {
    let c = h / k as f64;
    let q = gl.nodes.len();
    let nodes = |o: f64| -> Vec<f64> {
        (0..k)
            .flat_map(|i| gl.nodes.iter().map(move |&s| o + i as f64 * c + s * c))
            .collect()
    };
    let mut sums = Sums {
        gl,
        k,
        dn: vec![0.0; (k * q).next_multiple_of(GRID_LANES)],
        totals: vec![0.0; k * k],
    };
    patch.grid_rows(&nodes(u0), &nodes(v0), [(1, 0), (0, 1)], &mut sums);
    sums.totals.iter().map(|t| t * c * c).collect()
}

/// [`panels`]' running sums: per panel Σ_a w_a Σ_b w_b |R_u × R_v|.
struct Sums<'a> {
    gl: &'a GaussLegendre,
    k: usize,
    /// |R_u × R_v| along the row.
    dn: Vec<f64>,
    totals: Vec<f64>,
}

impl GridRows<2> for Sums<'_> {
    #[inline(always)]
    fn row(&mut self, a: usize, [du, dv]: &[[Vec<f64>; 3]; 2]) {
        for (c, dn) in self.dn.chunks_exact_mut(GRID_LANES).enumerate() {
            let ([u0, u1, u2], [v0, v1, v2]) = (chunk3(du, c), chunk3(dv, c));
            for t in 0..GRID_LANES {
                let n = cross([u0[t], u1[t], u2[t]], [v0[t], v1[t], v2[t]]);
                dn[t] = norm(n);
            }
        }
        let q = self.gl.nodes.len();
        let (i, wa) = (a / q, self.gl.weights[a % q]);
        for j in 0..self.k {
            let row: f64 = (0..q)
                .map(|b| self.gl.weights[b] * self.dn[j * q + b])
                .sum();
            self.totals[i * self.k + j] += wa * row;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule on the square panel (u0, v0, side h) by the point-by-point
    /// grid loop: the reference the row-wise panels are held to.
    fn panel(patch: &TensorPatch, gl: &GaussLegendre, (u0, v0, h): (f64, f64, f64)) -> f64 {
        let us: Vec<f64> = gl.nodes.iter().map(|&s| u0 + s * h).collect();
        let vs: Vec<f64> = gl.nodes.iter().map(|&s| v0 + s * h).collect();
        let d = patch.grid_tangents(&us, &vs);
        let q = gl.nodes.len();
        let mut total = 0.0;
        for a in 0..q {
            let row: f64 = (0..q)
                .map(|b| {
                    let (du, dv) = d[a * q + b];
                    gl.weights[b] * norm(cross(du, dv))
                })
                .sum();
            total += gl.weights[a] * row;
        }
        total * h * h
    }

    /// The uniform start's panels and a split's children, evaluated from
    /// one tensor grid a row at a time, are bit for bit the panels
    /// evaluated one by one.
    #[test]
    fn uniform_panels_are_the_single_panels() {
        for (n, m) in [(5, 5), (3, 7), (1, 2)] {
            let p = TensorPatch::from_fn(n, m, |i, j| {
                let (u, v) = (i as f64 / n as f64, j as f64 / m as f64);
                [u + 0.2 * v * v, v, 0.4 * (3.0 * u).sin() * (2.0 * v).cos()]
            });
            let gl = GaussLegendre::new(n.max(m) + 4);
            for k in [1, 2, 4, 3] {
                let h = 1.0 / k as f64;
                let one_by_one: Vec<f64> = (0..k * k)
                    .map(|q| panel(&p, &gl, ((q / k) as f64 * h, (q % k) as f64 * h, h)))
                    .collect();
                assert_eq!(
                    panels(&p, &gl, (0.0, 0.0, 1.0), k),
                    one_by_one,
                    "({n}, {m}), k = {k}"
                );
            }
            // A split inside the square: its four children, in order.
            let q = (0.25, 0.5, 0.25);
            let split = panels(&p, &gl, q, 2);
            let kids = children(q).map(|c| panel(&p, &gl, c));
            assert_eq!([split[0], split[2], split[1], split[3]], kids, "({n}, {m})");
        }
    }

    /// A hemisphere-like patch has no closed-form area, but the paraboloid
    /// z = x² + y² over [0,1]² has: compare with a 1D closed form reduced
    /// integral computed by a much finer independent rule.
    #[test]
    fn paraboloid_area_matches_fine_quadrature() {
        // z = x² + y² exactly as a degree (2,2) patch (x = u, y = v).
        let p = TensorPatch::from_fn(2, 2, |i, j| {
            let zi = [0.0, 0.0, 1.0][i];
            let zj = [0.0, 0.0, 1.0][j];
            [i as f64 / 2.0, j as f64 / 2.0, zi + zj]
        });
        let a = area(&p);
        // Independent: 400×400 midpoint-free Gauss on √(1 + 4x² + 4y²).
        let gl = GaussLegendre::new(40);
        let fine: f64 =
            gl.integrate(|x| gl.integrate(|y| (1.0 + 4.0 * x * x + 4.0 * y * y).sqrt()));
        assert!(
            (a.value - fine).abs() < 1e-12 * fine,
            "{} vs {fine}",
            a.value
        );
        assert!(a.error < 1e-10 * fine);
    }
}
