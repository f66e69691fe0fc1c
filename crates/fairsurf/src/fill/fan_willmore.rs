//! Lowering W = ∫∫ κ₁² + κ₂² dA of a fan of triangular patches (or one
//! triangle) with its rows 0 and 1 fixed and its G¹ conditions kept.
//!
//! Each patch is W-integrated as its exact tensor form (the degree n × n
//! patch with one side collapsed, [`crate::TriPatch::to_tensor`]) by the
//! 4-sided fill's Gauss rules — the coarse one first, then the main one,
//! whose W and gradient are those of [`super::total_curvature`] on the
//! patches the fill returns ([`super::willmore::Lbfgs::coarse_then_main`]); the
//! gradient with respect to the triangular points is the tensor one pulled
//! back through the conversion's weights (its transpose). The descent is
//! the 4-sided fill's L-BFGS ([`super::willmore::Lbfgs`]) with, as first
//! inverse Hessian, the thin plate's under the kept G¹ rows: r = Z(ZᵀHZ)⁻¹Zᵀq
//! from the solve's own KKT factorization ([`TriFactored::projected`]), so
//! every step moves along the rows (the patches stay G¹ to each other as
//! the conditions say) and never moves a fixed point (the fill stays G¹
//! to its neighbours). The thin plate is not W (its parameters are the
//! patches' barycentric ones), so H0 is rescaled by each latest pair to
//! W's curvature along the step (γ = sᵀHs / sᵀy).

use super::willmore::{w_and_gradient, Lbfgs, Rule};
use crate::bspline::BSplineSurface;
use crate::triangle::{tensor_weights, TriFactored, TriSurface};

/// W of every patch of `surface` by `rule` (the tensor forms' rule) and
/// ∂W/∂P for every coordinate of its points (3g + c); patch by patch in
/// order, so W sums as [`super::total_curvature`] over the patches does.
pub(crate) fn w_and_gradient_tri(surface: &TriSurface, rule: &Rule) -> (f64, Vec<f64>) {
    let n = surface.degree();
    let all: Vec<Option<usize>> = (0..(n + 1) * (n + 1)).map(Some).collect();
    let mut g = vec![0.0; 3 * surface.point_count()];
    let mut w = 0.0;
    for t in 0..surface.patch_count() {
        let tensor = BSplineSurface::from_bezier(&surface.patch(t).to_tensor());
        let (wt, gt) = w_and_gradient(&tensor, &all, rule);
        w += wt;
        for i in 0..=n {
            for l in 0..=n {
                for (j, c) in tensor_weights(n, i, l) {
                    let p = surface.global_index(t, i, j, n - i - j);
                    for e in 0..3 {
                        g[3 * p + e] += c * gt[(i * (n + 1) + l, e)];
                    }
                }
            }
        }
    }
    (w, g)
}

/// The rules for the patches of a degree-n triangular surface (their
/// tensor forms are all of degree n × n on [0, 1]²): the descent's coarse
/// one and W's.
fn rules(surface: &TriSurface) -> [Rule; 2] {
    let tensor = BSplineSurface::from_bezier(&surface.patch(0).to_tensor());
    [Rule::coarse(&tensor), Rule::of(&tensor)]
}

/// W of every patch of `surface` by `rule`, summed patch by patch.
fn w_tri(surface: &TriSurface, rule: &Rule) -> f64 {
    surface
        .patches()
        .map(|p| rule.w(&BSplineSurface::from_bezier(&p.to_tensor())))
        .sum()
}

/// Lowers W over the free coordinates of `factor` (the solve of `start`'s
/// thin plate under its kept rows), at most `steps` steps, stopping after
/// three in a row that gain less than `rel` of W, or after one when the
/// next step's model promises less too ([`Lbfgs`]); by the coarse rule,
/// then the main one ([`Lbfgs::coarse_then_main`]). Returns the surface and
/// W before the first step and after each accepted one (as
/// [`Lbfgs::coarse_then_main`] gives them: the coarse phase's steps but its
/// last by the coarse rule).
pub(crate) fn descend_tri(
    start: TriSurface,
    factor: &TriFactored,
    steps: usize,
    rel: f64,
) -> (TriSurface, Vec<f64>) {
    let [coarse, main] = rules(&start);
    let free = factor.free();
    let base: Vec<f64> = start.points().iter().flatten().copied().collect();
    let at = |x: &[f64]| -> Option<TriSurface> {
        let mut all = base.clone();
        for (&i, &v) in free.iter().zip(x) {
            all[i] = v;
        }
        let mut s = start.clone();
        s.set_points(all.chunks(3).map(|c| [c[0], c[1], c[2]]).collect())
            .ok()?;
        Some(s)
    };
    let on_free = |g: Vec<f64>| -> Vec<f64> { free.iter().map(|&i| g[i]).collect() };
    let w0 = w_tri(&start, &main);
    let x0: Vec<f64> = free.iter().map(|&i| base[i]).collect();
    let curvature = |s: &[f64]| factor.h_norm2(s);
    let descent = Lbfgs {
        steps,
        rel,
        rescale: Some(&curvature),
        rescale_once_cut: false,
    };
    let (x, steps, _) = descent.coarse_then_main(
        x0,
        w0,
        [&coarse, &main],
        |q| factor.projected(q),
        |rule, x| match at(x) {
            Some(s) => {
                let (w, g) = w_and_gradient_tri(&s, rule);
                (w, on_free(g))
            }
            None => (f64::INFINITY, Vec::new()),
        },
    );
    let mut history = vec![w0];
    history.extend(steps);
    (at(&x).unwrap_or(start), history)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fill::total_curvature;

    /// W of every patch by [`total_curvature`] (the fill's report).
    fn reported_w(s: &TriSurface) -> f64 {
        s.patches()
            .map(|p| total_curvature(&BSplineSurface::from_bezier(&p.to_tensor())).value)
            .sum()
    }

    /// Two wavy quartic patches sharing an edge.
    fn wavy() -> TriSurface {
        let v = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.2, 1.0, 0.0],
            [1.1, 0.9, 0.0],
        ];
        let mut s = TriSurface::new(&v, &[[0, 1, 2], [1, 3, 2]], 4);
        let points = s
            .points()
            .iter()
            .map(|p| {
                [
                    p[0],
                    p[1],
                    0.3 * (2.0 * p[0]).sin() * (1.5 * p[1] + 0.2).cos(),
                ]
            })
            .collect();
        s.set_points(points).unwrap();
        s
    }

    /// ∂W/∂P (every coordinate of every point, shared points summed over
    /// their patches) is the derivative of the W the fill reports: central
    /// differences agree.
    #[test]
    fn the_gradient_is_the_derivative_of_the_reported_w() {
        let s = wavy();
        let [_, rule] = rules(&s);
        let (w, g) = w_and_gradient_tri(&s, &rule);
        assert!((w - reported_w(&s)).abs() <= 1e-12 * w, "{w}");
        let h = 1e-6;
        let scale = g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (i, &gi) in g.iter().enumerate() {
            let moved = |e: f64| {
                let mut pts = s.points().to_vec();
                pts[i / 3][i % 3] += e;
                let mut m = s.clone();
                m.set_points(pts).unwrap();
                reported_w(&m)
            };
            let fd = (moved(h) - moved(-h)) / (2.0 * h);
            assert!(
                (fd - gi).abs() <= 1e-6 * scale,
                "coordinate {i}: {fd} vs {gi}"
            );
        }
    }
}
