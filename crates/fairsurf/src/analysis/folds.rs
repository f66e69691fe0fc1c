//! Folds: where the surface's unit normal turns by more than 90° between
//! neighbouring samples of a parameter grid — the surface doubles back on
//! itself there (a very large λ with a normal field the boundary cannot
//! follow does this). Reports say so instead of presenting the surface as
//! fair.

use super::curvature::unit_grid;
use crate::triangle::{multi_indices, tri_bernstein_all};
use crate::vec3::{angle, cross, dot, normalize, sub, Vec3};
use crate::{ParamSurface, SurfaceDerivatives, TriSurface};

/// The largest turn of the unit normal between neighbouring grid samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalTurn {
    /// The angle in radians (π/2 and more is a fold).
    pub angle: f64,
    /// Parameters of the first sample of the pair.
    pub at: (f64, f64),
}

impl NormalTurn {
    /// Whether the turn is a fold (more than 90°).
    pub fn is_fold(&self) -> bool {
        self.angle > std::f64::consts::FRAC_PI_2
    }
}

/// The largest angle between the unit normals of horizontally or vertically
/// neighbouring samples of the (k+1)×(k+1) grid; samples where the normal
/// is undefined (a collapsed corner) are skipped. `None` when no pair has
/// two normals. The grid is uniform over the surface's domain, and `at` is
/// in its parameters.
pub fn largest_normal_turn(surface: &impl ParamSurface, k: usize) -> Option<NormalTurn> {
    let k = k.max(1);
    let (us, vs) = surface.uniform_grid(k, k);
    let turn = largest_normal_turn_on(&surface.derivatives_on(&us, &vs), k)?;
    let [(a, b), (c, d)] = surface.domain();
    let (s, t) = turn.at;
    Some(NormalTurn {
        at: (a + (b - a) * s, c + (d - c) * t),
        ..turn
    })
}

/// [`largest_normal_turn`] from the derivatives on that grid (u-major).
pub(crate) fn largest_normal_turn_on(d: &[SurfaceDerivatives], k: usize) -> Option<NormalTurn> {
    let normals: Vec<_> = d.iter().map(|d| normalize(cross(d.du, d.dv))).collect();
    largest_normal_turn_of(&normals, k)
}

/// [`largest_normal_turn`] from the unit normals on that grid (u-major,
/// `None` where there is none).
pub(crate) fn largest_normal_turn_of(normals: &[Option<Vec3>], k: usize) -> Option<NormalTurn> {
    let ts = unit_grid(k);
    // The largest angle between unit normals is the longest chord |n − m|
    // (2 sin(θ/2), increasing on [0, π], and exact for small angles too):
    // compared by chords, the angle taken once, for the winner.
    let mut best: Option<(f64, Vec3, Vec3, (f64, f64))> = None;
    for a in 0..=k {
        for b in 0..=k {
            let Some(n) = normals[a * (k + 1) + b] else {
                continue;
            };
            let neighbours = [(a + 1, b), (a, b + 1)];
            for (c, d) in neighbours {
                if c > k || d > k {
                    continue;
                }
                if let Some(m) = normals[c * (k + 1) + d] {
                    let chord = dot(sub(n, m), sub(n, m));
                    if best.is_none_or(|t| chord > t.0) {
                        best = Some((chord, n, m, (ts[a], ts[b])));
                    }
                }
            }
        }
    }
    best.map(|(_, n, m, at)| NormalTurn {
        angle: angle(n, m),
        at,
    })
}

/// The largest turn of the unit normal inside the patches of a triangular
/// surface (across their edges: [`crate::triangle::max_edge_normal_angle`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriNormalTurn {
    /// The angle in radians (π/2 and more is a fold).
    pub angle: f64,
    /// The patch.
    pub patch: usize,
    /// Barycentric coordinates of the first sample of the pair.
    pub at: [f64; 3],
}

impl TriNormalTurn {
    /// Whether the turn is a fold (more than 90°).
    pub fn is_fold(&self) -> bool {
        self.angle > std::f64::consts::FRAC_PI_2
    }
}

/// The largest angle between the unit normals of neighbouring samples of
/// each patch's barycentric grid (i/k, j/k, (k−i−j)/k), neighbours along
/// the grid's three directions; samples without a normal are skipped.
pub fn largest_tri_normal_turn(surface: &TriSurface, k: usize) -> Option<TriNormalTurn> {
    let k = k.max(1);
    let kf = k as f64;
    let grid: Vec<[usize; 2]> = (0..=k)
        .flat_map(|i| (0..=k - i).map(move |j| [i, j]))
        .collect();
    // Row i holds j = 0…k−i and starts at i(k+1) − i(i−1)/2.
    let index =
        |i: usize, j: usize| (i + j <= k).then(|| i * (k + 1) - i * i.saturating_sub(1) / 2 + j);
    let neighbours: Vec<Vec<usize>> = grid
        .iter()
        .map(|&[i, j]| {
            let mut n = vec![index(i + 1, j), index(i, j + 1)];
            if j > 0 {
                n.push(index(i + 1, j - 1));
            }
            n.into_iter().flatten().collect()
        })
        .collect();
    let bary = |[i, j]: [usize; 2]| [i as f64 / kf, j as f64 / kf, (k - i - j) as f64 / kf];
    // T_u and T_v (up to the factor n, which the unit normal drops) are the
    // degree-(n−1) patches of the differences P_(i+1)jk − P_ij(k+1) and
    // P_i(j+1)k − P_ij(k+1) (E_U, E_V): their Bernstein polynomials at the
    // grid's points, once for every patch.
    let n = surface.degree();
    if n == 0 {
        return None;
    }
    let m = n - 1;
    let terms: Vec<[usize; 3]> = multi_indices(m).collect();
    let bernstein: Vec<Vec<f64>> = grid
        .iter()
        .map(|&g| tri_bernstein_all(m, bary(g)))
        .collect();
    // The longest chord |n − m|² between neighbouring unit normals, one
    // angle at the end (as the tensor scan does).
    let mut best: Option<(f64, Vec3, Vec3, usize, usize)> = None;
    for (t, patch) in surface.patches().enumerate() {
        let diff = |e: [usize; 3]| -> Vec<Vec3> {
            terms
                .iter()
                .map(|&[a, b, c]| {
                    sub(
                        patch.point(a + e[0], b + e[1], c + e[2]),
                        patch.point(a, b, c + 1),
                    )
                })
                .collect()
        };
        let (du, dv) = (diff([1, 0, 0]), diff([0, 1, 0]));
        let sum = |basis: &[f64], d: &[Vec3]| {
            basis.iter().zip(d).fold([0.0; 3], |acc, (w, p)| {
                [acc[0] + w * p[0], acc[1] + w * p[1], acc[2] + w * p[2]]
            })
        };
        let normals: Vec<_> = bernstein
            .iter()
            .map(|basis| normalize(cross(sum(basis, &du), sum(basis, &dv))))
            .collect();
        for (a, near) in neighbours.iter().enumerate() {
            let Some(n) = normals[a] else { continue };
            for &b in near {
                let Some(m) = normals[b] else { continue };
                let d = sub(n, m);
                let chord = dot(d, d);
                if best.is_none_or(|x| chord > x.0) {
                    best = Some((chord, n, m, t, a));
                }
            }
        }
    }
    best.map(|(_, n, m, patch, a)| TriNormalTurn {
        angle: angle(n, m),
        patch,
        at: bary(grid[a]),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TensorPatch;

    /// A flat patch turns by 0; a patch folded back over itself (its middle
    /// column of control points pulled past the far side) turns by more
    /// than 90° somewhere; a gently curved one by little.
    #[test]
    fn folds_are_found_and_fair_surfaces_are_not_folds() {
        let flat = TensorPatch::from_fn(3, 3, |i, j| [i as f64, j as f64, 0.0]);
        assert!(largest_normal_turn(&flat, 16).unwrap().angle < 1e-12);
        let bump = TensorPatch::from_fn(3, 3, |i, j| {
            [
                i as f64,
                j as f64,
                if (1..3).contains(&i) && (1..3).contains(&j) {
                    0.5
                } else {
                    0.0
                },
            ]
        });
        let t = largest_normal_turn(&bump, 32).unwrap();
        assert!(!t.is_fold() && t.angle > 0.01, "{t:?}");
        // x goes 0, 3, −2, 1: the surface runs forward, back past its start
        // and forward again; with almost no rise its normal flips between
        // two samples where x turns (at u = 1/4 and 3/4, between samples of
        // the 30-step grid).
        let xs = [0.0, 3.0, -2.0, 1.0];
        let folded = TensorPatch::from_fn(3, 3, |i, j| [xs[i], j as f64, 0.001 * i as f64]);
        let t = largest_normal_turn(&folded, 30).unwrap();
        assert!(t.is_fold(), "{t:?}");
    }

    /// The triangular version: a flat surface turns by 0, a patch whose
    /// middle edge points are pulled past the far corner folds.
    #[test]
    fn triangular_folds_are_found() {
        let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let mut s = TriSurface::new(&v, &[[0, 1, 2]], 3);
        assert!(largest_tri_normal_turn(&s, 8).unwrap().angle < 1e-12);
        // Edge w = 0 runs 0, 3, −2, 1 in x: forward, back, forward.
        let xs = [0.0, 3.0, -2.0, 1.0];
        let mut pts = s.points().to_vec();
        for (i, x) in xs.iter().enumerate() {
            let g = s.global_index(0, 3 - i, i, 0);
            pts[g] = [*x, 0.0, 0.001 * i as f64];
        }
        s.set_points(pts).unwrap();
        let t = largest_tri_normal_turn(&s, 24).unwrap();
        assert!(t.is_fold(), "{t:?}");
        // The scan's normals (Bernstein sums of the derivative nets) are the
        // patch's own (de Casteljau): the same largest turn from those.
        let k = 24;
        let patch = s.patch(0);
        let at = |i: usize, j: usize| {
            let b = [
                i as f64 / k as f64,
                j as f64 / k as f64,
                (k - i - j) as f64 / k as f64,
            ];
            patch.normal(b)
        };
        let mut largest = 0.0f64;
        for i in 0..=k {
            for j in 0..=k - i {
                let near = [(i + 1, j), (i, j + 1), (i + 1, j.wrapping_sub(1))];
                for (a, b) in near.into_iter().filter(|&(a, b)| b <= k && a + b <= k) {
                    if let (Some(x), Some(y)) = (at(i, j), at(a, b)) {
                        largest = largest.max(angle(x, y));
                    }
                }
            }
        }
        assert!((largest - t.angle).abs() < 1e-9, "{largest} {t:?}");
        assert_eq!(t.patch, 0);
    }
}
