//! The fill made fair inside its fixed rings: the thin plate (guided by the
//! boundary's normal field when no descent follows), then W lowered
//! (linearized Willmore steps if asked, then the descent on W itself).

use super::*;
use crate::{Bend, NormalField, Stretch};

/// A patch made fair inside fixed boundary rows: the solve, then the steps
/// that lower W.
pub(super) struct Faired {
    pub(super) surface: BSplineSurface,
    pub(super) solve: SolveReport,
    pub(super) corners: CornerMismatch,
    pub(super) curvature: TotalCurvature,
    pub(super) willmore: Vec<f64>,
    pub(super) setup: f64,
    pub(super) solve_seconds: f64,
    /// W and the steps that lower it.
    pub(super) improve_seconds: f64,
}

/// The patch of the unified sides `s` (their D already scaled: the
/// patch's cross derivative) with the rows [`rings`] fixes, every other point
/// free, made fair by `options` (see the module documentation, steps 2–3).
pub(super) fn fair(
    s: &[Strip; 4],
    across: [bool; 4],
    options: &FillOptions,
    t0: Instant,
) -> Result<Faired> {
    if options.samples == 0 {
        return Err(Error::Fill {
            why: "samples must be at least 1".into(),
        });
    }
    let (ku, kv, net, corners) = rings(s, across);
    let (cu, cv) = (ku.count(), kv.count());
    let patch = coons::Coons::new(s);
    let greville = |k: &KnotVector, i: usize| {
        let p = k.degree();
        k.knots()[i + 1..=i + p].iter().sum::<f64>() / p as f64
    };
    let free: Vec<bool> = net.iter().map(Option::is_none).collect();
    let points: Vec<Vec3> = net
        .iter()
        .enumerate()
        .map(|(k, p)| p.unwrap_or_else(|| patch.at(greville(&ku, k / cv), greville(&kv, k % cv)).0))
        .collect();
    let surface = BSplineSurface::new(ku, kv, points)?;
    let mut problem = BSplineProblem::from_surface(surface).with_free(free)?;
    // A zero weight is no term (the report lists the fill's terms).
    if options.stretch != 0.0 {
        problem = problem.with_term(Stretch::new(options.stretch));
    }
    if options.bend != 0.0 {
        problem = problem.with_term(Bend::new(options.bend));
    }
    // The normal field guides the solve unless the descent on W follows
    // (then the plain thin plate: the same W, see `guide_with_descent`).
    let lambda = options.guiding_weight();
    if lambda > 0.0 {
        let grid = SampleGrid::try_new(options.samples * cu, options.samples * cv)?;
        let normals = patch
            .on_grid(&grid.us(), &grid.vs())
            .into_iter()
            .map(|(_, fu, fv)| cross(fu, fv))
            .collect();
        let weight = lambda / grid.len() as f64;
        problem = problem.with_term(NormalField::sampled(weight, grid, normals, None));
    }
    let setup = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let solved = problem.solve()?;
    let solve_seconds = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    let mut surface = solved.surface;
    let free = problem.free().to_vec();
    // W's rule on the fill's knots (every candidate below keeps them). The
    // descent's last accepted step's W is the fill's, and when that step
    // was one of its coarse phase it knows the coarse rule's W too (the
    // error estimate's other W).
    let nodes = willmore::Rule::of(&surface);
    // W of `surface` when known.
    let mut w = (options.willmore_steps > 0).then(|| nodes.w(&surface));
    let mut history: Vec<f64> = w.into_iter().collect();
    for _ in 0..options.willmore_steps {
        let now = w.expect("W before the steps");
        // A step whose system is not positive definite ends the steps; the
        // surface so far stands (its W and side fits are measured after).
        let Ok(next) = willmore::step(&surface, &free) else {
            break;
        };
        let wn = nodes.w(&next);
        history.push(wn);
        if wn.is_nan() || wn >= now {
            break;
        }
        let done = now - wn <= 1e-6 * now;
        surface = next;
        w = Some(wn);
        if done {
            break;
        }
    }
    // W by the coarse rule at `surface`, when the descent knows it.
    let mut coarse = None;
    if options.descent_steps > 0 {
        let d = willmore::descend(surface, &nodes, &free, options.descent_steps, 1e-8);
        surface = d.surface;
        // The same sum in the same order (NaN included).
        debug_assert!(w.is_none_or(|w| w.to_bits() == d.start.to_bits()));
        if history.is_empty() {
            history.push(d.start);
        }
        w = Some(d.steps.last().copied().unwrap_or(d.start));
        history.extend(d.steps);
        coarse = d.coarse;
    }
    let w = w.unwrap_or_else(|| nodes.w(&surface));
    if history.is_empty() {
        history.push(w);
    }
    let curvature = match coarse {
        Some(c) => measure::with_coarse(w, c),
        None => measure::with_error(&surface, w),
    };
    Ok(Faired {
        surface,
        solve: solved.report,
        corners,
        curvature,
        willmore: history,
        setup,
        solve_seconds,
        improve_seconds: t2.elapsed().as_secs_f64(),
    })
}
