//! Gauss–Legendre quadrature on [0, 1]: exact for polynomials of degree ≤ 2q−1.
//! fairsurf uses it to check the closed-form integrals and to integrate what
//! has no closed form (area, curvature).

/// A q-point Gauss–Legendre rule mapped to [0, 1].
#[derive(Clone, Debug)]
pub struct GaussLegendre {
    /// Nodes in (0, 1), increasing.
    pub nodes: Vec<f64>,
    /// Positive weights summing to 1.
    pub weights: Vec<f64>,
}

impl GaussLegendre {
    /// The q-point rule (q ≥ 1). Nodes are the roots of the Legendre
    /// polynomial P_q, found by Newton's method from Tricomi's estimate;
    /// accurate to a few ulps.
    ///
    /// # Panics
    /// If q is 0.
    pub fn new(q: usize) -> Self {
        assert!(q > 0, "a quadrature rule needs at least one node");
        let mut nodes = vec![0.0; q];
        let mut weights = vec![0.0; q];
        let qf = q as f64;
        for k in 0..q.div_ceil(2) {
            // k-th root of P_q in (−1, 1), largest first.
            let mut x = (std::f64::consts::PI * (k as f64 + 0.75) / (qf + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(q, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre(q, x);
            if d.is_finite() {
                dp = d;
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            // Map [−1, 1] → [0, 1]: t = (1 ± x)/2, weight w/2.
            nodes[k] = 0.5 * (1.0 - x);
            nodes[q - 1 - k] = 0.5 * (1.0 + x);
            weights[k] = 0.5 * w;
            weights[q - 1 - k] = 0.5 * w;
        }
        Self { nodes, weights }
    }

    /// ∫₀¹ f(t) dt by this rule.
    pub fn integrate(&self, mut f: impl FnMut(f64) -> f64) -> f64 {
        self.nodes
            .iter()
            .zip(&self.weights)
            .map(|(&t, &w)| w * f(t))
            .sum()
    }

    /// ∫ over [a, b] by this rule.
    pub fn integrate_on(&self, a: f64, b: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
        let h = b - a;
        h * self.integrate(|t| f(a + h * t))
    }
}

/// (P_q(x), P_q'(x)) by the three-term recurrence.
fn legendre(q: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=q {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    if q == 0 {
        return (1.0, 0.0);
    }
    let d = q as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_for_monomials_up_to_degree_2q_minus_1() {
        for q in 1..40 {
            let gl = GaussLegendre::new(q);
            let s: f64 = gl.weights.iter().sum();
            assert!((s - 1.0).abs() < 1e-14, "q={q}");
            for d in 0..2 * q {
                let v = gl.integrate(|t| t.powi(d as i32));
                assert!((v - 1.0 / (d + 1) as f64).abs() < 1e-14, "q={q} d={d}");
            }
        }
    }

    #[test]
    fn nodes_are_sorted_and_inside() {
        let gl = GaussLegendre::new(17);
        assert!(gl.nodes.windows(2).all(|w| w[0] < w[1]));
        assert!(gl.nodes.iter().all(|&t| t > 0.0 && t < 1.0));
        assert!((gl.nodes[8] - 0.5).abs() < 1e-16);
    }
}
