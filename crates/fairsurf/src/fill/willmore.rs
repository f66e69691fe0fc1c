//! Lowering W = ∫∫ κ₁² + κ₂² dA of a fill with its two outer rings fixed.
//!
//! With position and tangent plane fixed along the boundary, ∫∫ K dA is
//! fixed too (Gauss–Bonnet: 2π minus the boundary's geodesic curvature and
//! turning angles), so W = ∫∫ 4H² dA − 2∫∫ K dA is lowered exactly when the
//! Willmore energy ∫∫ 4H² dA is. On a surface, Δ_g R = 2H n (Δ_g the
//! Laplace–Beltrami operator of its metric g), so ∫∫ 4H² dA = ∫∫ |Δ_g R|² dA_g.
//! With g (and the Christoffel symbols Γ^k_ij = g^kl R_ij·R_l) frozen at a
//! reference surface this is a quadratic form in R,
//!
//! ```text
//! E(R) = ∫∫ |g^ij (R_ij − Γ^k_ij R_k)|² √det g du dv
//! ```
//!
//! one scalar operator for x, y and z; its minimizer over the free control
//! points becomes the next reference (a linearized Willmore flow taken to
//! its fixed point). The integrand is rational: Gauss–Legendre with
//! p + q + 4 nodes per span and direction.
//!
//! That fixed point is not W's minimum: the frozen metric drops how W
//! changes through g. [`descend`] then minimizes W itself by L-BFGS, with
//! W's exact gradient (the integrand (4H² − 2K)|R_u × R_v| differentiated
//! by the chain rule in R_u, R_v, R_uu, R_uv, R_vv at each Gauss node) and
//! the frozen-metric operator as the first inverse Hessian — first by a
//! coarse Gauss rule, then by W's own ([`Lbfgs::coarse_then_main`]). The
//! fill takes no linearized steps by default: the descent alone reaches
//! the same W.

use crate::basis::GaussLegendre;
use crate::bspline::BSplineSurface;
use crate::solve::dense::{SpdFactor, SpdOptions};
use crate::vec3::{cross, dot, norm};
use crate::{Error, Result, Vec3};
use faer::Mat;

/// One step: the surface on `reference`'s knots that minimizes E with g
/// and Γ from `reference`, the points where `free` is false kept.
pub(crate) fn step(reference: &BSplineSurface, free: &[bool]) -> Result<BSplineSurface> {
    let (h, b, slot) = system(reference, free, &Rule::of(reference), true);
    let x = factor(&h).ok_or_else(not_definite)?.apply(&b);
    let points = reference
        .points()
        .iter()
        .zip(&slot)
        .map(|(&pt, s)| s.map_or(pt, |r| [x[(r, 0)], x[(r, 1)], x[(r, 2)]]))
        .collect();
    Ok(reference.with_points(points))
}

/// The Cholesky factor of the SPD matrix `h` (on this thread, equilibrated;
/// None when not positive definite).
fn factor(h: &Mat<f64>) -> Option<SpdFactor> {
    let options = SpdOptions {
        estimate_condition: false,
        singular_condition: f64::INFINITY,
    };
    SpdFactor::new(h, options, "", None).ok()
}

fn not_definite() -> Error {
    Error::Fill {
        why: "the linearized Willmore system is not positive definite".into(),
    }
}

/// Each control point's row among the free ones.
fn slots(free: &[bool]) -> Vec<Option<usize>> {
    let mut k = 0;
    free.iter()
        .map(|&f| {
            f.then(|| {
                k += 1;
                k - 1
            })
        })
        .collect()
}

/// Gauss nodes of every knot span in one direction: the spans and at each
/// node (span by span, `rule`'s count each) its span and the basis
/// functions with their first two derivatives (computed once per node).
struct Axis {
    spans: Vec<(usize, f64, f64)>,
    basis: crate::bspline::Bases,
}

impl Axis {
    fn new(knots: &crate::bspline::KnotVector, rule: &GaussLegendre) -> Self {
        let spans = knots.spans();
        let mut basis =
            crate::bspline::Bases::new(knots.degree() + 1, spans.len() * rule.nodes.len());
        for &(k, a, b) in &spans {
            for &x in &rule.nodes {
                basis.push(knots, k, a + (b - a) * x);
            }
        }
        Self { spans, basis }
    }
}

/// A Gauss–Legendre rule with `order` nodes per knot span and direction
/// on a surface's knots, its basis functions computed once: W, its
/// gradient and the frozen-metric operator of every surface on these knots
/// (a descent's candidates) read them.
pub(crate) struct Rule {
    rule: GaussLegendre,
    u: Axis,
    v: Axis,
}

impl Rule {
    /// The rule of `order` nodes on `s`'s knots (W's: p + q + 4).
    pub(crate) fn new(s: &BSplineSurface, order: usize) -> Self {
        let rule = GaussLegendre::new(order);
        let (ku, kv) = s.knots();
        Self {
            u: Axis::new(ku, &rule),
            v: Axis::new(kv, &rule),
            rule,
        }
    }

    /// The descent's coarse rule for `s`: (p + q + 4)/2 + 1 nodes (the
    /// error estimate's, [`super::measure::with_error`]).
    pub(crate) fn coarse(s: &BSplineSurface) -> Self {
        let (p, q) = s.degree();
        Self::new(s, (p + q + 4) / 2 + 1)
    }

    /// W's rule for `s`: p + q + 4 nodes.
    pub(crate) fn of(s: &BSplineSurface) -> Self {
        let (p, q) = s.degree();
        Self::new(s, p + q + 4)
    }

    /// `s`'s derivatives at the nodes of u-span `a` (u-major) × every v
    /// node.
    fn row(&self, s: &BSplineSurface, a: usize) -> Vec<crate::SurfaceDerivatives> {
        let n = self.rule.nodes.len();
        s.derivatives_from(self.u.basis.view().sub(a * n, n), self.v.basis.view())
    }

    /// W = ∫∫ (4H² − 2K) |R_u × R_v| du dv of `s` (on the rule's knots) by
    /// the rule; points where the surface is not regular are skipped.
    pub(crate) fn w(&self, s: &BSplineSurface) -> f64 {
        let n = self.rule.nodes.len();
        let (g, nv) = (&self.rule, self.v.basis.len());
        let mut sum = 0.0;
        for (a, &(_, u0, u1)) in self.u.spans.iter().enumerate() {
            let grid = self.row(s, a);
            for (bs, &(_, v0, v1)) in self.v.spans.iter().enumerate() {
                let area = (u1 - u0) * (v1 - v0);
                for (x, &wx) in g.weights.iter().enumerate() {
                    for (y, &wy) in g.weights.iter().enumerate() {
                        let d = &grid[x * nv + bs * n + y];
                        if let Some(f) = weighted_integrand(d, wx * wy * area) {
                            sum += f;
                        }
                    }
                }
            }
        }
        sum
    }
}

/// W's integrand (4H² − 2K)|R_u × R_v| at a point times the node's weight
/// `w`, `None` where the surface is not regular (W skips it) — one
/// definition for W and the descent's W ([`Integrand`]).
fn weighted_integrand(d: &crate::SurfaceDerivatives, w: f64) -> Option<f64> {
    Integrand::at(d).map(|i| w * i.value())
}

/// W's integrand f = (4H² − 2K)|N| at a point in the scalars its value
/// and its gradient share: with N = R_u × R_v, E, F, G the first
/// fundamental form, Δ = EG − F² (= |N|²), l = R_uu·N, m = R_uv·N,
/// n = R_vv·N (the second form times |N|) and X = E n − 2F m + G l,
/// 4H² = X²/Δ³ and K = (l n − m²)/Δ², so f = X² Δ^(−5/2) − 2(l n − m²)
/// Δ^(−3/2).
#[derive(Clone, Copy)]
struct Integrand {
    nn: Vec3,
    e: f64,
    f: f64,
    g: f64,
    det: f64,
    l: f64,
    m: f64,
    n: f64,
    x: f64,
    /// Δ^(−3/2) and Δ^(−5/2).
    d3: f64,
    d5: f64,
}

impl Integrand {
    /// None where the surface is not regular (the test of
    /// [`crate::analysis::curvature_from`]).
    #[inline(always)]
    fn at(d: &crate::SurfaceDerivatives) -> Option<Self> {
        let (ru, rv) = (d.du, d.dv);
        let (e, f, g) = (dot(ru, ru), dot(ru, rv), dot(rv, rv));
        let nn = cross(ru, rv);
        let det = e * g - f * f;
        if !crate::analysis::is_regular(det, e, g, norm(nn)) {
            return None;
        }
        let (l, m, n) = (dot(d.duu, nn), dot(d.duv, nn), dot(d.dvv, nn));
        let x = e * n - 2.0 * f * m + g * l;
        let s = det.sqrt();
        let (d3, d5) = ((det * s).recip(), (det * det * s).recip());
        Some(Self {
            nn,
            e,
            f,
            g,
            det,
            l,
            m,
            n,
            x,
            d3,
            d5,
        })
    }

    #[inline(always)]
    fn value(&self) -> f64 {
        self.x * self.x * self.d5 - 2.0 * (self.l * self.n - self.m * self.m) * self.d3
    }
}

/// E's matrix over the free points (one for x, y and z) and, when `rhs`,
/// its right-hand sides from the fixed ones (else zero: then only the free
/// points' columns of L are formed), g and Γ from `reference`; each
/// point's row.
#[allow(clippy::type_complexity)]
fn system(
    reference: &BSplineSurface,
    free: &[bool],
    nodes: &Rule,
    rhs: bool,
) -> (Mat<f64>, Mat<f64>, Vec<Option<usize>>) {
    let ((p, q), (_, cv)) = (reference.degree(), reference.counts());
    let slot = slots(free);
    let nf = free.iter().filter(|&&f| f).count();
    let mut h = Mat::<f64>::zeros(nf, nf);
    let mut b = Mat::<f64>::zeros(nf, 3);
    let (gu, gv) = (&nodes.rule, &nodes.rule);
    let size = (p + 1) * (q + 1);
    // Per span: the rows √w·L(B_a) at every node (the span's points a, or
    // its free ones), and LᵀL by one product.
    let (au, av) = (&nodes.u, &nodes.v);
    let (n, m) = (gu.nodes.len(), gv.nodes.len());
    let point = |su: usize, sv: usize, a: usize| (su - p + a / (q + 1)) * cv + sv - q + a % (q + 1);
    for (a, &(su, u0, u1)) in au.spans.iter().enumerate() {
        // The surface at this u-span's nodes and every v node.
        let grid = nodes.row(reference, a);
        for (bs, &(sv, v0, v1)) in av.spans.iter().enumerate() {
            let cols: Vec<usize> = (0..size)
                .filter(|&a| rhs || slot[point(su, sv, a)].is_some())
                .collect();
            if cols.is_empty() {
                continue;
            }
            let mut lm = Mat::<f64>::zeros(n * m, cols.len());
            for (x, &wx) in gu.weights.iter().enumerate() {
                let nu = au.basis.at(a * n + x).1;
                for (y, &wy) in gv.weights.iter().enumerate() {
                    let nv = av.basis.at(bs * m + y).1;
                    let d = &grid[x * av.basis.len() + bs * m + y];
                    let (e, f, g) = (dot(d.du, d.du), dot(d.du, d.dv), dot(d.dv, d.dv));
                    let det = e * g - f * f;
                    if det.is_nan() || det <= 0.0 {
                        continue;
                    }
                    // g^ij and Γ^k_ij = g^kl (R_ij · R_l) for ij = uu, uv, vv.
                    let gi = [g / det, -f / det, e / det];
                    let gamma = |rij: Vec3| {
                        let (a, c) = (dot(rij, d.du), dot(rij, d.dv));
                        (gi[0] * a + gi[1] * c, gi[1] * a + gi[2] * c)
                    };
                    let (guu, guv, gvv) = (gamma(d.duu), gamma(d.duv), gamma(d.dvv));
                    // L(B) = g^uu (B_uu − Γ·B′) + 2 g^uv (B_uv − Γ·B′) + g^vv (B_vv − Γ·B′).
                    let cu = gi[0] * guu.0 + 2.0 * gi[1] * guv.0 + gi[2] * gvv.0;
                    let cvv = gi[0] * guu.1 + 2.0 * gi[1] * guv.1 + gi[2] * gvv.1;
                    let sw = (wx * wy * (u1 - u0) * (v1 - v0) * det.sqrt()).sqrt();
                    let row = x * m + y;
                    for (col, &c) in cols.iter().enumerate() {
                        let (i, j) = (c / (q + 1), c % (q + 1));
                        lm[(row, col)] = sw
                            * (gi[0] * nu[2][i] * nv[0][j]
                                + 2.0 * gi[1] * nu[1][i] * nv[1][j]
                                + gi[2] * nu[0][i] * nv[2][j]
                                - cu * nu[1][i] * nv[0][j]
                                - cvv * nu[0][i] * nv[1][j]);
                    }
                }
            }
            let local = crate::solve::dense::gram(lm.as_ref());
            for (la, &a) in cols.iter().enumerate() {
                let Some(ra) = slot[point(su, sv, a)] else {
                    continue;
                };
                for (lc, &c) in cols.iter().enumerate() {
                    let kc = point(su, sv, c);
                    let hac = local[(la, lc)];
                    match slot[kc] {
                        Some(rc) => h[(ra, rc)] += hac,
                        None => {
                            let pt = reference.points()[kc];
                            for k in 0..3 {
                                b[(ra, k)] -= hac * pt[k];
                            }
                        }
                    }
                }
            }
        }
    }
    (h, b, slot)
}

/// A descent's end ([`descend`]).
pub(crate) struct Descent {
    /// The surface after the last accepted step.
    pub surface: BSplineSurface,
    /// W at the start by the main rule ([`Rule::w`]'s sum).
    pub start: f64,
    /// W after each accepted step: the main rule's after the last step of
    /// the coarse phase and after every step of the polish, the coarse
    /// rule's after the coarse phase's earlier steps.
    pub steps: Vec<f64>,
    /// W of `surface` by [`Rule::coarse`] when the descent knows it (its
    /// last accepted step was a coarse one): the error estimate's second
    /// W ([`super::measure::with_coarse`]).
    pub coarse: Option<f64>,
}

/// Minimizes W itself (not its frozen-metric model) over the free points
/// by L-BFGS ([`Lbfgs`]) whose initial inverse Hessian is (2A)⁻¹, A the
/// frozen-metric operator of E at the start (E's Hessian is 2A, and E
/// models W near the surface): the first step is the linearized one, the
/// pairs learn what the frozen metric misses. Once a step has to be cut
/// (the frozen metric far from W's: an octant of a torus filled from its
/// thin plate, W 12.59 → 8.99, took steps of 1e-3 after ten halvings
/// each), H0 is rescaled by each latest pair ([`Lbfgs::rescale_once_cut`]):
/// there 60 steps took 252 evaluations instead of 683 and reached a lower
/// W (9.69 against 9.92).
///
/// In two phases: W, its gradient and A by [`Rule::coarse`] (about a
/// third of the nodes) until that descent stops, then the same L-BFGS
/// ([`Lbfgs::coarse_then_main`]: its pairs kept) on W by
/// the main rule `nodes` ([`Rule::of`] the surface's knots, the rule of
/// [`super::total_curvature`]): its gradient is exact for the W that is
/// reported, and the descent stops only when the main rule's W says so.
/// The coarse rule integrates the thin-plate part of W (degree 2p − 4 in
/// u) exactly, so the two minima are near: on the bench's six holes the
/// polish took no step (its first model promised less than `rel`), and
/// the coarse phase's last W was within 6e-11 of the main rule's.
/// `steps` bounds both phases together.
pub(crate) fn descend(
    start: BSplineSurface,
    nodes: &Rule,
    free: &[bool],
    steps: usize,
    rel: f64,
) -> Descent {
    let coarse = Rule::coarse(&start);
    descend_by(start, [&coarse, nodes], free, steps, rel)
}

/// [`descend`] with the coarse rule `rules[0]` and the main one
/// `rules[1]`.
fn descend_by(
    start: BSplineSurface,
    rules: [&Rule; 2],
    free: &[bool],
    steps: usize,
    rel: f64,
) -> Descent {
    let [coarse, nodes] = rules;
    let w0 = nodes.w(&start);
    // A by the coarse rule (it only shapes the steps); by the main one
    // where that is not positive definite.
    let factored = rules.into_iter().find_map(|rule| {
        let (a, _, slot) = system(&start, free, rule, false);
        factor(&a).map(|llt| (a, slot, llt))
    });
    let Some((a, slot, llt)) = factored else {
        return Descent {
            surface: start,
            start: w0,
            steps: Vec::new(),
            coarse: None,
        };
    };
    let nf = a.nrows();
    // The free points' coordinates, point by point (3r + k).
    let at = |x: &[f64]| {
        let points = start
            .points()
            .iter()
            .zip(&slot)
            .map(|(&pt, sl)| sl.map_or(pt, |r| std::array::from_fn(|k| x[3 * r + k])))
            .collect();
        start.with_points(points)
    };
    let flat = |m: &Mat<f64>| -> Vec<f64> {
        (0..m.nrows())
            .flat_map(|r| (0..3).map(move |k| m[(r, k)]))
            .collect()
    };
    let h0 = |q: &[f64]| -> Option<Vec<f64>> {
        let q = Mat::<f64>::from_fn(nf, 3, |r, k| q[3 * r + k]);
        let mut x = llt.apply(&q);
        x *= faer::Scale(0.5);
        Some(flat(&x))
    };
    let x0: Vec<f64> = start
        .points()
        .iter()
        .zip(&slot)
        .filter(|(_, sl)| sl.is_some())
        .flat_map(|(pt, _)| *pt)
        .collect();
    // sᵀ H0⁻¹ s = 2 sᵀ A s, coordinate by coordinate.
    let curvature = |s: &[f64]| -> f64 {
        let m = Mat::<f64>::from_fn(nf, 3, |r, k| s[3 * r + k]);
        let am = &a * &m;
        2.0 * (0..nf)
            .flat_map(|r| (0..3).map(move |k| (r, k)))
            .map(|(r, k)| m[(r, k)] * am[(r, k)])
            .sum::<f64>()
    };
    let descent = Lbfgs {
        steps,
        rel,
        rescale: Some(&curvature),
        rescale_once_cut: true,
    };
    let (x, steps, coarse) = descent.coarse_then_main(x0, w0, [coarse, nodes], h0, |rule, x| {
        let (w, g) = w_and_gradient(&at(x), &slot, rule);
        (w, flat(&g))
    });
    Descent {
        surface: at(&x),
        start: w0,
        steps,
        coarse,
    }
}

/// L-BFGS (Nocedal & Wright, Alg. 7.4, ten pairs) on a function given with
/// its gradient, from an initial inverse Hessian H0. Each step is halved
/// until the function falls by at least 1e-4 of the predicted amount
/// (Armijo), at most 20 times (60 while a rescaled H0,
/// [`Lbfgs::rescale`] without [`Lbfgs::rescale_once_cut`], has not been
/// scaled yet: the fan's thin plate is off W's curvature by the model's
/// size squared, and a sphere 0.004 across needed more than 20), and not
/// below a step that leaves x as it is in doubles.
/// Stops after `steps` steps, after three steps in a row that
/// lower it by less than `rel` of itself, after one such step when the
/// next step's quadratic model (−½ gᵀd, with at least one curvature pair)
/// promises less than `rel` too, or
/// when no step lowers it (along the L-BFGS direction nor, the pairs
/// forgotten, along −H0 g). [`Lbfgs::resume`] carries the pairs, H0's
/// scale, the cut flag and the run of small steps from one run to the
/// next ([`Memory`]).
pub(crate) struct Lbfgs<'a> {
    pub steps: usize,
    pub rel: f64,
    /// For an H0 of the right shape but not the right size: s ↦ sᵀH0⁻¹s,
    /// and H0 is scaled by γ = sᵀH0⁻¹s / sᵀy of the latest pair, so that
    /// (γH0)⁻¹ has the function's curvature along s (the s-side
    /// counterpart of Nocedal & Wright's eq. 7.20). None: H0 as it is.
    pub rescale: Option<&'a Curvature<'a>>,
    /// With `rescale`: H0 is scaled only from the first step that had to
    /// be cut (t < 1) on; until then it is taken as it is (an H0 of the
    /// right size — the frozen-metric operator near W's minimum — keeps
    /// its steps whole, and γ from a pair would only blur it).
    pub rescale_once_cut: bool,
}

/// s ↦ sᵀH0⁻¹s ([`Lbfgs::rescale`]).
pub(crate) type Curvature<'a> = dyn Fn(&[f64]) -> f64 + 'a;

impl Lbfgs<'_> {
    /// From `x` where the function is `w` with gradient `g`: the last
    /// accepted point and the value after each accepted step. `h0` applies
    /// H0 (None: it failed, the descent ends); `eval` gives the value and
    /// gradient at a point.
    #[cfg(test)]
    pub(crate) fn run(
        &self,
        x: Vec<f64>,
        w: f64,
        g: Vec<f64>,
        h0: impl Fn(&[f64]) -> Option<Vec<f64>>,
        eval: impl FnMut(&[f64]) -> (f64, Vec<f64>),
    ) -> (Vec<f64>, Vec<f64>) {
        self.resume(&mut Memory::default(), x, w, g, h0, eval)
    }

    /// W lowered in two phases from `x0` (where W by the main rule is
    /// `w0`): by `rules[0]` (coarse) until that run stops — at gains below
    /// `rel` or below the coarse rule's error at `x0`, |W₀ − W₀'| / W₀ —
    /// then [`Lbfgs::resume`]d by `rules[1]` (the main
    /// rule, whose W is reported) — `eval(rule, x)` gives W and its
    /// gradient by `rule`. `self.steps` bounds both together. Returns the
    /// last accepted point, W after each accepted step (the coarse rule's
    /// W for the coarse phase's steps but its last, whose W is replaced by
    /// the main rule's) and W at that point by the coarse rule when the
    /// last accepted step was a coarse one (else None). The polish counts
    /// its run of small steps anew (but for the coarse phase's last: its
    /// first model test may end it at once); where the coarse steps raised
    /// the main rule's W above `w0` (NaN included) it starts over from
    /// `x0` by the main rule alone, so the W reported never exceeds `w0`.
    pub(crate) fn coarse_then_main(
        &self,
        x0: Vec<f64>,
        w0: f64,
        rules: [&Rule; 2],
        h0: impl Fn(&[f64]) -> Option<Vec<f64>>,
        eval: impl Fn(&Rule, &[f64]) -> (f64, Vec<f64>),
    ) -> (Vec<f64>, Vec<f64>, Option<f64>) {
        let mut memory = Memory::default();
        let (wc, gc) = eval(rules[0], &x0);
        // Gains below the coarse rule's own error are its noise: the
        // coarse phase stops there (the main rule goes on).
        let error = if w0 > 0.0 { (wc - w0).abs() / w0 } else { 0.0 };
        let coarse = Lbfgs {
            rel: self.rel.max(error),
            ..*self
        };
        let (x, mut history) =
            coarse.resume(&mut memory, x0.clone(), wc, gc, &h0, |x| eval(rules[0], x));
        let last_coarse = history.last().copied().unwrap_or(wc);
        let mut x = x;
        let (mut w, mut g) = eval(rules[1], &x);
        if let Some(last) = history.last_mut() {
            *last = w;
        }
        let restarted = w.is_nan() || w > w0;
        if restarted {
            // The coarse steps raised the main rule's W: the main rule
            // alone from the start.
            history.clear();
            memory = Memory::default();
            (w, g) = eval(rules[1], &x0);
            x = x0;
        }
        // The polish's run of small steps counts the main rule's: at most
        // the coarse phase's last (its first model test may end it at once).
        memory.small = memory.small.min(1);
        let polish = Lbfgs {
            steps: self.steps - history.len(),
            ..*self
        };
        let (x, steps) = polish.resume(&mut memory, x, w, g, &h0, |x| eval(rules[1], x));
        let coarse = (steps.is_empty() && !restarted).then_some(last_coarse);
        history.extend(steps);
        (x, history, coarse)
    }

    /// [`Lbfgs::run`] with what an earlier run learnt (`memory`: its
    /// curvature pairs, H0's scale, its run of small steps), left in
    /// `memory` for a later one.
    pub(crate) fn resume(
        &self,
        memory: &mut Memory,
        mut x: Vec<f64>,
        mut w: f64,
        mut g: Vec<f64>,
        h0: impl Fn(&[f64]) -> Option<Vec<f64>>,
        mut eval: impl FnMut(&[f64]) -> (f64, Vec<f64>),
    ) -> (Vec<f64>, Vec<f64>) {
        let dot = |a: &[f64], b: &[f64]| -> f64 { a.iter().zip(b).map(|(x, y)| x * y).sum() };
        let mut history = Vec::new();
        let Memory {
            pairs,
            gamma,
            small,
            cut,
        } = memory;
        for _ in 0..self.steps {
            // The two-loop recursion: d = −H g; when no step along it lowers
            // the function (or it is not a descent direction) the pairs are
            // forgotten and −H0 g tried before stopping.
            let mut taken = None;
            let mut d = Vec::new();
            let mut t = 1.0;
            while taken.is_none() {
                let mut q = g.clone();
                let mut alphas = Vec::with_capacity(pairs.len());
                for (sk, yk, rho) in pairs.iter().rev() {
                    let al = rho * dot(sk, &q);
                    q.iter_mut().zip(yk).for_each(|(a, b)| *a -= al * b);
                    alphas.push(al);
                }
                let Some(mut r) = h0(&q) else {
                    return (x, history);
                };
                if *gamma != 1.0 {
                    r.iter_mut().for_each(|v| *v *= *gamma);
                }
                for ((sk, yk, rho), al) in pairs.iter().zip(alphas.iter().rev()) {
                    let be = rho * dot(yk, &r);
                    r.iter_mut().zip(sk).for_each(|(a, b)| *a += (al - be) * b);
                }
                d = r.iter().map(|v| -v).collect();
                let slope = dot(&g, &d);
                if slope.is_nan() || slope >= 0.0 {
                    if pairs.is_empty() {
                        break;
                    }
                    pairs.clear();
                    continue;
                }
                // Converged: the last step gained less than rel, and the
                // quadratic model along d (its least at t = 1 for the
                // Newton-like step: −slope/2), with at least one curvature
                // pair in it (H0 alone may be off in scale), promises less
                // than rel too.
                if *small > 0 && !pairs.is_empty() && -0.5 * slope <= self.rel * w {
                    return (x, history);
                }
                t = 1.0;
                // A rescaled H0 (the fan's thin plate, off W's curvature by
                // the model's size squared) before a pair has scaled it:
                // more halvings; none once the step would not move x in
                // doubles (an unchanged W would pass the test).
                let halvings = if *gamma == 1.0 && self.rescale.is_some() && !self.rescale_once_cut
                {
                    60
                } else {
                    20
                };
                let (x_inf, d_inf) = (inf_norm(&x), inf_norm(&d));
                for _ in 0..halvings {
                    if t * d_inf <= f64::EPSILON * x_inf {
                        break;
                    }
                    let cand: Vec<f64> = x.iter().zip(&d).map(|(a, b)| a + t * b).collect();
                    // Value and gradient at once: the first candidate is
                    // almost always taken, and then its gradient is the next.
                    let (wc, gc) = eval(&cand);
                    if wc <= w + 1e-4 * t * slope {
                        taken = Some((cand, wc, gc));
                        break;
                    }
                    t *= 0.5;
                }
                if taken.is_none() {
                    if pairs.is_empty() {
                        break;
                    }
                    pairs.clear();
                }
            }
            let Some((next, wn, gn)) = taken else {
                break;
            };
            // Converged after three steps in a row that gain less than rel.
            *small = if w - wn <= self.rel * w {
                *small + 1
            } else {
                0
            };
            let done = *small >= 3;
            let sk: Vec<f64> = d.iter().map(|v| t * v).collect();
            let yk: Vec<f64> = gn.iter().zip(&g).map(|(a, b)| a - b).collect();
            let sy = dot(&sk, &yk);
            *cut |= t < 1.0;
            if sy > 0.0 {
                if let Some(curvature) = self.rescale.filter(|_| *cut || !self.rescale_once_cut) {
                    let shs = curvature(&sk);
                    if shs > 0.0 && shs.is_finite() {
                        *gamma = shs / sy;
                    }
                }
                if pairs.len() == 10 {
                    pairs.remove(0);
                }
                pairs.push((sk, yk, 1.0 / sy));
            }
            (x, w, g) = (next, wn, gn);
            history.push(w);
            if done {
                break;
            }
        }
        (x, history)
    }
}

/// What an L-BFGS run has learnt ([`Lbfgs::resume`]).
pub(crate) struct Memory {
    /// The curvature pairs (s, y, 1/sᵀy), oldest first.
    pairs: Vec<(Vec<f64>, Vec<f64>, f64)>,
    /// H0's scale (1 until [`Lbfgs::rescale`] sets it).
    gamma: f64,
    /// Steps in a row that gained less than `rel`.
    small: usize,
    /// Whether a step has been cut.
    cut: bool,
}

impl Default for Memory {
    fn default() -> Self {
        Self {
            pairs: Vec::new(),
            gamma: 1.0,
            small: 0,
            cut: false,
        }
    }
}

/// max |v_i|.
fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, a| m.max(a.abs()))
}

/// ∂W/∂P over the free points ([`w_and_gradient`]'s).
#[cfg(test)]
fn gradient(s: &BSplineSurface, slot: &[Option<usize>], nodes: &Rule) -> Mat<f64> {
    w_and_gradient(s, slot, nodes).1
}

/// W by `nodes` ([`Rule::w`]: the same sum in the same order) and ∂W/∂P
/// over the free points (rows as `slot`, columns x, y, z) from one
/// evaluation of the surface at the nodes; points where W skips the
/// integrand (not regular) contribute nothing to either. By sum
/// factorization: per u node the v sums acc_r[j] = Σ_y Σ_s N_j^(s)(v_y) w
/// ∂f/∂R_(r,s) for each u-derivative order r (R_u, R_v, R_uu, R_uv, R_vv
/// are (r, s) = (1,0), (0,1), (2,0), (1,1), (0,2)), then Σ_r N_i^(r)(u_x)
/// acc_r[j] into the span's points.
pub(crate) fn w_and_gradient(
    s: &BSplineSurface,
    slot: &[Option<usize>],
    nodes: &Rule,
) -> (f64, Mat<f64>) {
    let ((p, q), (_, cv)) = (s.degree(), s.counts());
    let mut sum = 0.0;
    let mut g = Mat::<f64>::zeros(slot.iter().flatten().count(), 3);
    let (rule, au, av) = (&nodes.rule, &nodes.u, &nodes.v);
    let n = rule.nodes.len();
    let (wu, wv) = (p + 1, q + 1);
    let mut local = vec![[0.0f64; 3]; wu * wv];
    let mut acc = vec![[0.0f64; 3]; 3 * wv];
    for (a, &(su, u0, u1)) in au.spans.iter().enumerate() {
        let grid = nodes.row(s, a);
        for (bs, &(sv, v0, v1)) in av.spans.iter().enumerate() {
            let area = (u1 - u0) * (v1 - v0);
            local.fill([0.0; 3]);
            for (x, &wx) in rule.weights.iter().enumerate() {
                acc.fill([0.0; 3]);
                for (y, &wy) in rule.weights.iter().enumerate() {
                    let d = &grid[x * av.basis.len() + bs * n + y];
                    let Some(at) = Integrand::at(d) else {
                        continue;
                    };
                    let w = wx * wy * area;
                    sum += w * at.value();
                    let df = integrand_gradient(d, &at).map(|x| w * x);
                    add_v_sums(&mut acc, &df, av.basis.at(bs * n + y).1);
                }
                add_u_sums(&mut local, &acc, au.basis.at(a * n + x).1);
            }
            for (k, l) in local.iter().enumerate() {
                let point = (su - p + k / wv) * cv + sv - q + k % wv;
                if let Some(r) = slot[point] {
                    for (e, &x) in l.iter().enumerate() {
                        g[(r, e)] += x;
                    }
                }
            }
        }
    }
    (sum, g)
}

/// acc_r[j] += Σ_s N_j^(s) ∂f/∂R_(r,s) at one node (`nv` the v basis
/// functions and their derivatives, `df` the weighted integrand gradient).
fn add_v_sums(acc: &mut [[f64; 3]], df: &[f64; 15], nv: [&[f64]; 3]) {
    let wv = acc.len() / 3;
    let part = |k: usize| [df[3 * k], df[3 * k + 1], df[3 * k + 2]];
    let (ru, rv, ruu, ruv, rvv) = (part(0), part(1), part(2), part(3), part(4));
    let (a0, rest) = acc.split_at_mut(wv);
    let (a1, a2) = rest.split_at_mut(wv);
    for j in 0..wv {
        let (n0, n1, n2) = (nv[0][j], nv[1][j], nv[2][j]);
        for e in 0..3 {
            a0[j][e] += n1 * rv[e] + n2 * rvv[e];
            a1[j][e] += n0 * ru[e] + n1 * ruv[e];
            a2[j][e] += n0 * ruu[e];
        }
    }
}

/// The span's points' sums += Σ_r N_i^(r)(u) acc_r[j] at one u node.
fn add_u_sums(local: &mut [[f64; 3]], acc: &[[f64; 3]], nu: [&[f64]; 3]) {
    let wv = acc.len() / 3;
    for (k, l) in local.iter_mut().enumerate() {
        let (i, j) = (k / wv, k % wv);
        let c = [nu[0][i], nu[1][i], nu[2][i]];
        for e in 0..3 {
            l[e] += c[0] * acc[j][e] + c[1] * acc[wv + j][e] + c[2] * acc[2 * wv + j][e];
        }
    }
}

/// ∂f/∂(R_u, R_v, R_uu, R_uv, R_vv) of W's integrand f = (4H² − 2K)|N|:
/// with N = R_u × R_v, E, F, G the first fundamental form, Δ = EG − F²
/// (= |N|²), l = R_uu·N, m = R_uv·N, n = R_vv·N and X = E n − 2F m + G l,
/// f = X² Δ^(−5/2) − 2(l n − m²) Δ^(−3/2). By the chain rule through the
/// scalars (f_X, f_Δ, then l, m, n, E, F, G) and, for N, the triple
/// product: with V = f_l R_uu + f_m R_uv + f_n R_vv, ∂(V·N)/∂R_u = R_v × V
/// and ∂(V·N)/∂R_v = V × R_u. (Tested against forward-mode
/// differentiation of the same formula.)
fn integrand_gradient(d: &crate::SurfaceDerivatives, at: &Integrand) -> [f64; 15] {
    let (ru, rv) = (d.du, d.dv);
    let Integrand {
        nn,
        e,
        f,
        g,
        det,
        l,
        m,
        n,
        x,
        d3,
        d5,
    } = *at;
    // f_X, f_Δ; then the totals through X = E n − 2F m + G l, Δ = EG − F².
    let fx = 2.0 * x * d5;
    let fd = -2.5 * x * x * d5 / det + 3.0 * (l * n - m * m) * d3 / det;
    let (gl, gm, gn) = (
        fx * g - 2.0 * n * d3,
        -2.0 * fx * f + 4.0 * m * d3,
        fx * e - 2.0 * l * d3,
    );
    let (ge, gf, gg) = (
        fx * n + fd * g,
        -2.0 * fx * m - 2.0 * fd * f,
        fx * l + fd * e,
    );
    let v: Vec3 = std::array::from_fn(|k| gl * d.duu[k] + gm * d.duv[k] + gn * d.dvv[k]);
    let (a, b) = (cross(rv, v), cross(v, ru));
    let mut out = [0.0; 15];
    for k in 0..3 {
        out[k] = 2.0 * ge * ru[k] + gf * rv[k] + a[k];
        out[3 + k] = 2.0 * gg * rv[k] + gf * ru[k] + b[k];
        out[6 + k] = gl * nn[k];
        out[9 + k] = gm * nn[k];
        out[12 + k] = gn * nn[k];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bspline::KnotVector;

    /// A number with its derivatives by the 15 coordinates of R_u, R_v, R_uu,
    /// R_uv, R_vv (forward-mode differentiation).
    #[derive(Clone, Copy)]
    struct Dual {
        v: f64,
        d: [f64; 15],
    }

    impl Dual {
        fn var(v: f64, k: usize) -> Self {
            let mut d = [0.0; 15];
            d[k] = 1.0;
            Self { v, d }
        }
        fn add(self, o: Self) -> Self {
            Self {
                v: self.v + o.v,
                d: std::array::from_fn(|k| self.d[k] + o.d[k]),
            }
        }
        fn sub(self, o: Self) -> Self {
            Self {
                v: self.v - o.v,
                d: std::array::from_fn(|k| self.d[k] - o.d[k]),
            }
        }
        fn mul(self, o: Self) -> Self {
            Self {
                v: self.v * o.v,
                d: std::array::from_fn(|k| self.d[k] * o.v + self.v * o.d[k]),
            }
        }
        fn scale(self, c: f64) -> Self {
            Self {
                v: self.v * c,
                d: self.d.map(|x| x * c),
            }
        }
        /// self^(−n/2) for self > 0, by one square root and a division (libm's
        /// `pow` was a fifth of the gradient's time).
        fn inv_half_power(self, n: i32) -> Self {
            let v = self.v.sqrt().powi(n).recip();
            let c = -0.5 * f64::from(n) * v / self.v;
            Self {
                v,
                d: self.d.map(|x| x * c),
            }
        }
    }

    type DVec = [Dual; 3];

    fn ddot(a: &DVec, b: &DVec) -> Dual {
        a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]))
    }

    fn dcross(a: &DVec, b: &DVec) -> DVec {
        [
            a[1].mul(b[2]).sub(a[2].mul(b[1])),
            a[2].mul(b[0]).sub(a[0].mul(b[2])),
            a[0].mul(b[1]).sub(a[1].mul(b[0])),
        ]
    }

    /// ∂f/∂(R_u, R_v, R_uu, R_uv, R_vv) of W's integrand f = (4H² − 2K)|N|:
    /// with N = R_u × R_v, a = |N|, l = R_uu·N, m = R_uv·N, n = R_vv·N and
    /// X = E n − 2F m + G l, f = X²/a⁵ − 2(l n − m²)/a³.
    fn integrand_gradient_forward(d: &crate::SurfaceDerivatives) -> [f64; 15] {
        let var = |v: Vec3, at: usize| -> DVec { std::array::from_fn(|c| Dual::var(v[c], at + c)) };
        let (ru, rv) = (var(d.du, 0), var(d.dv, 3));
        let (ruu, ruv, rvv) = (var(d.duu, 6), var(d.duv, 9), var(d.dvv, 12));
        let (e, f, g) = (ddot(&ru, &ru), ddot(&ru, &rv), ddot(&rv, &rv));
        let n = dcross(&ru, &rv);
        let det = e.mul(g).sub(f.mul(f));
        let (l, m, nn) = (ddot(&ruu, &n), ddot(&ruv, &n), ddot(&rvv, &n));
        let x = e.mul(nn).sub(f.mul(m).scale(2.0)).add(g.mul(l));
        // a^-5 = det^-2.5, a^-3 = det^-1.5.
        let w = x.mul(x).mul(det.inv_half_power(5)).sub(
            l.mul(nn)
                .sub(m.mul(m))
                .mul(det.inv_half_power(3))
                .scale(2.0),
        );
        w.d
    }

    /// The chain-rule gradient of the integrand is forward-mode
    /// differentiation's of the same formula, at points of a wavy sheet.
    #[test]
    fn the_integrand_gradient_is_forward_differentiation() {
        let (s, _) = sheet();
        let us = [0.3, 1.1, 2.7, 3.9];
        let vs = [0.2, 1.5, 2.4];
        for d in s.derivatives_on(&us, &vs) {
            let at = Integrand::at(&d).unwrap();
            let (a, b) = (integrand_gradient(&d, &at), integrand_gradient_forward(&d));
            let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for k in 0..15 {
                assert!(
                    (a[k] - b[k]).abs() <= 1e-12 * scale,
                    "component {k}: {} vs {}",
                    a[k],
                    b[k]
                );
            }
        }
    }

    /// A bicubic sheet of 4 × 3 spans, wavy, its two outer rings fixed.
    fn sheet() -> (BSplineSurface, Vec<bool>) {
        let (u, v) = (KnotVector::uniform(3, 4), KnotVector::uniform(3, 3));
        let (cu, cv) = (u.count(), v.count());
        let points = (0..cu * cv)
            .map(|k| {
                let (i, j) = ((k / cv) as f64, (k % cv) as f64);
                [
                    i,
                    j + 0.1 * i,
                    0.3 * (0.9 * i).sin() * (0.7 * j).cos() + 0.05 * i * j,
                ]
            })
            .collect();
        let free = (0..cu * cv)
            .map(|k| {
                let (i, j) = (k / cv, k % cv);
                i >= 2 && j >= 2 && i + 2 < cu && j + 2 < cv
            })
            .collect();
        (BSplineSurface::new(u, v, points).unwrap(), free)
    }

    /// The gradient is W's: central differences of the reported W agree.
    #[test]
    fn the_gradient_is_the_derivative_of_w() {
        let (s, free) = sheet();
        let slot = slots(&free);
        let g = gradient(&s, &slot, &Rule::of(&s));
        let h = 1e-6;
        for (k, r) in slot.iter().enumerate() {
            let Some(r) = *r else { continue };
            for c in 0..3 {
                let moved = |e: f64| {
                    let mut pts = s.points().to_vec();
                    pts[k][c] += e;
                    super::super::total_curvature(&s.with_points(pts)).value
                };
                let fd = (moved(h) - moved(-h)) / (2.0 * h);
                assert!(
                    (fd - g[(r, c)]).abs() <= 1e-6 * (1.0 + fd.abs()),
                    "point {k} coordinate {c}: {fd} vs {}",
                    g[(r, c)]
                );
            }
        }
    }

    /// Descent lowers W to a stationary point: the gradient falls by
    /// orders of magnitude, and no small move of a free point lowers W.
    #[test]
    fn descent_reaches_a_minimum_of_w() {
        let (s, free) = sheet();
        let w0 = super::super::total_curvature(&s).value;
        let slot = slots(&free);
        let norm = |m: &Mat<f64>| m.norm_l2();
        let g0 = norm(&gradient(&s, &slot, &Rule::of(&s)));
        let d = descend(s.clone(), &Rule::of(&s), &free, 400, 1e-13);
        let (m, history) = (d.surface, d.steps);
        assert_eq!(d.start, w0);
        let w = *history.last().unwrap();
        assert!(w < w0, "{w} {w0}");
        // The last W is the main rule's on the surface returned, and the
        // coarse rule's W, when given, is the coarse rule's there.
        assert_eq!(w, Rule::of(&m).w(&m));
        if let Some(c) = d.coarse {
            assert_eq!(c, Rule::coarse(&m).w(&m));
        }
        let g = norm(&gradient(&m, &slot, &Rule::of(&m)));
        assert!(
            g < 1e-4 * g0,
            "gradient {g} from {g0} after {} steps",
            history.len()
        );
        for (k, f) in free.iter().enumerate() {
            if !f {
                continue;
            }
            for c in 0..3 {
                for e in [1e-4, -1e-4] {
                    let mut pts = m.points().to_vec();
                    pts[k][c] += e;
                    let wm = super::super::total_curvature(&m.with_points(pts)).value;
                    assert!(wm >= w - 1e-14 * w, "point {k}: {wm} < {w}");
                }
            }
        }
    }

    /// The coarse phase descends, the main rule decides: from the sheet,
    /// the descent by the main rule alone (both phases), by the coarse
    /// rule then the main one, and by a rule far too coarse (2 nodes a
    /// span: its W is off by more than 1e-3 of W; descended to its own
    /// minimum, without the stop at its error, it had fallen to 0.70 where
    /// the main rule's W was 4.3) then the main one
    /// end within 1e-8 of one W (the sheet's descent is slow, 200+ steps:
    /// the stop rule's rel of 1e-11 per step leaves W that far apart), each
    /// last W the main rule's at the surface returned, the coarse rule's W
    /// given only when the polish took no step.
    #[test]
    fn the_coarse_phase_descends_and_the_main_rule_decides() {
        let (s, free) = sheet();
        let main = Rule::of(&s);
        let by = |coarse: &Rule| descend_by(s.clone(), [coarse, &main], &free, 400, 1e-11);
        let (coarse, rough) = (Rule::coarse(&s), Rule::new(&s, 2));
        let (alone, two, far) = (by(&main), by(&coarse), by(&rough));
        let last = |d: &Descent| *d.steps.last().unwrap();
        for (d, rule) in [(&alone, &main), (&two, &coarse), (&far, &rough)] {
            assert_eq!(last(d), main.w(&d.surface));
            assert!(
                (last(d) - last(&alone)).abs() <= 1e-8 * last(&alone),
                "{} vs {}",
                last(d),
                last(&alone)
            );
            assert!(d.steps.len() < 400, "{} steps", d.steps.len());
            if let Some(c) = d.coarse {
                assert_eq!(c, rule.w(&d.surface));
            }
        }
        let gap = (rough.w(&s) - main.w(&s)).abs();
        assert!(
            gap > 1e-3 * main.w(&s),
            "the 2-node rule's W is off by {gap}"
        );
        assert_eq!(far.coarse, None);
    }

    /// L-BFGS's stops on f(x) = 1 + ½ xᵀAx (A diagonal, condition 100,
    /// H0 = I): it runs until a step gains less than rel of f and the next
    /// step's quadratic model promises less too — one or two such steps at
    /// the end, not the three that stop it without the model's word — and
    /// ends within rel of the minimum.
    #[test]
    fn lbfgs_stops_when_gain_and_model_are_below_rel() {
        let a = [1.0, 3.0, 10.0, 100.0];
        let f = |x: &[f64]| {
            let w = 1.0 + 0.5 * x.iter().zip(&a).map(|(x, a)| a * x * x).sum::<f64>();
            (
                w,
                x.iter().zip(&a).map(|(x, a)| a * x).collect::<Vec<f64>>(),
            )
        };
        let x0 = vec![1.0, -2.0, 0.5, 0.3];
        let (w0, g0) = f(&x0);
        let run = |steps: usize, rel: f64| {
            let descent = Lbfgs {
                steps,
                rel,
                rescale: None,
                rescale_once_cut: false,
            };
            descent.run(x0.clone(), w0, g0.clone(), |q| Some(q.to_vec()), f)
        };
        let rel = 1e-8;
        let (_, history) = run(200, rel);
        let w = *history.last().unwrap();
        let gains: Vec<bool> = std::iter::once(w0)
            .chain(history.iter().copied())
            .collect::<Vec<_>>()
            .windows(2)
            .map(|p| p[0] - p[1] <= rel * p[0])
            .collect();
        let trailing = gains.iter().rev().take_while(|&&small| small).count();
        assert!(
            (1..3).contains(&trailing) && history.len() < 200,
            "{} steps, the last {trailing} small",
            history.len()
        );
        assert!(w - 1.0 <= 10.0 * rel, "W {w}");
    }

    /// Rescaling once a step is cut, on f(x) = 1 + ½ xᵀAx + ¼ Σ x⁴ (A
    /// diagonal, condition 1000 over 40 unknowns): with H0 = A⁻¹ (the
    /// quadratic part's inverse: the frozen-metric operator's role) steps
    /// are taken whole and the run is the same as without rescaling, step
    /// for step; with H0 = 300 A⁻¹ (300 times too long, as the torus
    /// octant's operator was: steps of 1e-3 accepted after ten halvings
    /// each) it reaches the same f in a quarter of the evaluations or
    /// fewer (21 against 213 here).
    #[test]
    fn lbfgs_rescales_only_once_a_step_was_cut() {
        let n = 40;
        let a: Vec<f64> = (0..n)
            .map(|i| 10f64.powf(3.0 * i as f64 / (n - 1) as f64))
            .collect();
        let f = |x: &[f64]| {
            let w = 1.0
                + x.iter()
                    .zip(&a)
                    .map(|(x, a)| 0.5 * a * x * x + 0.25 * x.powi(4))
                    .sum::<f64>();
            let g = x
                .iter()
                .zip(&a)
                .map(|(x, a)| a * x + x.powi(3))
                .collect::<Vec<f64>>();
            (w, g)
        };
        let x0: Vec<f64> = (0..n).map(|i| ((i * 7 % 11) as f64 - 5.0) / 5.0).collect();
        let (w0, g0) = f(&x0);
        let run = |scale: f64, once_cut: Option<bool>| {
            // s ↦ sᵀH0⁻¹s.
            let curvature =
                |s: &[f64]| s.iter().zip(&a).map(|(s, a)| a * s * s).sum::<f64>() / scale;
            let evals = std::cell::Cell::new(0usize);
            let descent = Lbfgs {
                steps: 2000,
                rel: 1e-12,
                rescale: once_cut.map(|_| &curvature as &Curvature),
                rescale_once_cut: once_cut.unwrap_or(false),
            };
            let h0 = |q: &[f64]| Some(q.iter().zip(&a).map(|(q, a)| scale * q / a).collect());
            let (_, history) = descent.run(x0.clone(), w0, g0.clone(), h0, |x| {
                evals.set(evals.get() + 1);
                f(x)
            });
            (history, evals.get())
        };
        let (plain, _) = run(1.0, None);
        let (rescaled, _) = run(1.0, Some(true));
        assert_eq!(plain, rescaled, "an H0 of the right size: the same run");
        let (long, long_evals) = run(300.0, None);
        let (cut, cut_evals) = run(300.0, Some(true));
        let (wl, wc) = (*long.last().unwrap(), *cut.last().unwrap());
        assert!(
            (wl - 1.0).abs() < 1e-9 && (wc - 1.0).abs() < 1e-9,
            "{wl} {wc}"
        );
        assert!(
            4 * cut_evals < long_evals,
            "{cut_evals} evaluations rescaled, {long_evals} not"
        );
    }
}
