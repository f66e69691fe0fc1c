//! The |H| statistics and the largest normal turn of a Bézier patch in one
//! pass over the report's grid, a row at a time: the derivatives of a row
//! come coordinates apart ([`TensorPatch::grid_rows`]), the per-point
//! curvature runs as one vectorizable loop over the row, and the normal turn
//! compares each row with the one before — no grid of derivatives or
//! normals is kept. The same operations in the same order as
//! [`super::abs_mean_curvature`] and [`super::largest_normal_turn`] on that
//! grid, so the same bits (a test holds them equal).

use super::curvature::{is_regular, unit_grid, AbsMeanCurvature, HStats, PointForms};
use super::folds::NormalTurn;
use crate::tensor::{chunk3, GridRows, GRID_LANES};
use crate::vec3::{angle, dot, normalize_with_norm, sub, Vec3};
use crate::TensorPatch;

/// [`super::abs_mean_curvature`] and [`super::largest_normal_turn`] of a
/// patch on the (k+1)×(k+1) uniform grid of [0, 1]².
pub(crate) fn curvature_and_turn(
    patch: &TensorPatch,
    k: usize,
) -> (AbsMeanCurvature, Option<NormalTurn>) {
    const ORDERS: [(usize, usize); 5] = [(1, 0), (0, 1), (2, 0), (1, 1), (0, 2)];
    let k = k.max(1);
    let ts = unit_grid(k);
    let mut scan = Scan {
        k,
        ts: &ts,
        stats: HStats::default(),
        turn: Turn::default(),
        point: PointRow::new((k + 1).next_multiple_of(GRID_LANES)),
        prev: vec![None; k + 1],
        cur: vec![None; k + 1],
    };
    patch.grid_rows(&ts, &ts, ORDERS, &mut scan);
    scan.turn.row_pairs(&scan.prev, None, ts[k], &ts);
    (scan.stats.finish(), scan.turn.finish())
}

/// The pass's state: the statistics and turn so far, the row's per-point
/// values, the unit normals of the row before and of this one.
struct Scan<'a> {
    k: usize,
    ts: &'a [f64],
    stats: HStats,
    turn: Turn,
    point: PointRow,
    prev: Vec<Option<Vec3>>,
    cur: Vec<Option<Vec3>>,
}

impl GridRows<5> for Scan<'_> {
    #[inline(always)]
    fn row(&mut self, a: usize, rows: &[[Vec<f64>; 3]; 5]) {
        let k = self.k;
        self.point.compute(rows);
        let wa = if a == 0 || a == k { 0.5 } else { 1.0 };
        for b in 0..=k {
            self.cur[b] = self.point.normal(b);
            if self.point.singular(b) {
                self.stats.singular += 1;
                continue;
            }
            let wb = if b == 0 || b == k { 0.5 } else { 1.0 };
            self.stats.add(self.point.h[b], wa * wb * self.point.l[b]);
        }
        // The pairs whose first sample is in the row before, in the order
        // of a u-major sweep: down, then right.
        if a > 0 {
            self.turn
                .row_pairs(&self.prev, Some(&self.cur), self.ts[a - 1], self.ts);
        }
        std::mem::swap(&mut self.prev, &mut self.cur);
    }
}

/// Per point of a row: ñ = R_u × R_v, |ñ|, the first fundamental form's
/// E and G, EG − F², and |H| as [`super::curvature_from`] computes it.
struct PointRow {
    n: [Vec<f64>; 3],
    l: Vec<f64>,
    e: Vec<f64>,
    g: Vec<f64>,
    det: Vec<f64>,
    h: Vec<f64>,
}

impl PointRow {
    fn new(nv: usize) -> Self {
        let z = || vec![0.0; nv];
        PointRow {
            n: [z(), z(), z()],
            l: z(),
            e: z(),
            g: z(),
            det: z(),
            h: z(),
        }
    }

    /// A chunk of [`GRID_LANES`] points at a time, the chunk copied into
    /// local arrays: one branch-free loop that vectorizes (inside
    /// [`TensorPatch::grid_rows`]'s target-feature context).
    #[inline(always)]
    fn compute(&mut self, rows: &[[Vec<f64>; 3]; 5]) {
        const L: usize = GRID_LANES;
        for k in 0..self.l.len() / L {
            let [du, dv, duu, duv, dvv] = [
                chunk3(&rows[0], k),
                chunk3(&rows[1], k),
                chunk3(&rows[2], k),
                chunk3(&rows[3], k),
                chunk3(&rows[4], k),
            ];
            let mut out = [[0.0; L]; 8];
            for t in 0..L {
                let lane = |c: [&[f64; L]; 3]| [c[0][t], c[1][t], c[2][t]];
                let f = PointForms::at(lane(du), lane(dv), lane(duu), lane(duv), lane(dvv));
                let [n0, n1, n2] = f.nn;
                for (o, x) in out
                    .iter_mut()
                    .zip([n0, n1, n2, f.l, f.e, f.g, f.det, f.h.abs()])
                {
                    o[t] = x;
                }
            }
            let [n0, n1, n2, l, e, g, det, h] = &out;
            let st = |to: &mut Vec<f64>, x: &[f64; L]| to[k * L..][..L].copy_from_slice(x);
            st(&mut self.n[0], n0);
            st(&mut self.n[1], n1);
            st(&mut self.n[2], n2);
            st(&mut self.l, l);
            st(&mut self.e, e);
            st(&mut self.g, g);
            st(&mut self.det, det);
            st(&mut self.h, h);
        }
    }

    /// Where [`super::curvature_from`] gives no curvature.
    #[inline(always)]
    fn singular(&self, b: usize) -> bool {
        !is_regular(self.det[b], self.e[b], self.g[b], self.l[b])
    }

    /// The unit normal, as [`crate::vec3::normalize`] gives it.
    #[inline(always)]
    fn normal(&self, b: usize) -> Option<Vec3> {
        normalize_with_norm([self.n[0][b], self.n[1][b], self.n[2][b]], self.l[b])
    }
}

/// The longest chord |n − m| between neighbouring unit normals so far (the
/// first of equal ones), with its pair and where.
#[derive(Default)]
struct Turn {
    best: Option<(f64, Vec3, Vec3, (f64, f64))>,
}

impl Turn {
    /// The pairs whose first sample is in `row` (at u): each sample with
    /// the one below it in `next` (if any), then with its right neighbour.
    #[inline(always)]
    fn row_pairs(
        &mut self,
        row: &[Option<Vec3>],
        next: Option<&[Option<Vec3>]>,
        u: f64,
        ts: &[f64],
    ) {
        for (b, n) in row.iter().enumerate() {
            let Some(n) = *n else { continue };
            let down = next.and_then(|r| r[b]);
            let right = row.get(b + 1).copied().flatten();
            for m in [down, right].into_iter().flatten() {
                let chord = dot(sub(n, m), sub(n, m));
                if self.best.is_none_or(|t| chord > t.0) {
                    self.best = Some((chord, n, m, (u, ts[b])));
                }
            }
        }
    }

    fn finish(self) -> Option<NormalTurn> {
        self.best.map(|(_, n, m, at)| NormalTurn {
            angle: angle(n, m),
            at,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{abs_mean_curvature, largest_normal_turn};

    fn wavy(n: usize, m: usize) -> TensorPatch {
        TensorPatch::from_fn(n, m, |i, j| {
            let (u, v) = (i as f64 / n as f64, j as f64 / m as f64);
            [
                u + 0.1 * v * v,
                v - 0.05 * u,
                0.3 * (3.0 * u).sin() * (2.0 * v).cos(),
            ]
        })
    }

    fn collapsed() -> TensorPatch {
        let mut p = wavy(3, 3);
        p.set_point(1, 0, p.point(0, 0));
        p.set_point(0, 1, p.point(0, 0));
        p
    }

    /// A fold: the middle control rows pulled back past each other.
    fn fold() -> TensorPatch {
        TensorPatch::from_fn(3, 2, |i, j| {
            let x = [0.0, 1.5, -0.5, 1.0][i];
            [x, j as f64 / 2.0, 0.2 * (i * j) as f64]
        })
    }

    /// The one pass gives bit for bit what the per-point definitions give
    /// on the stored grid of derivatives: rows that are and are not whole
    /// chunks, a collapsed corner (no normal, no curvature there) and a
    /// fold.
    #[test]
    fn the_pass_is_the_per_point_definitions() {
        for (p, k) in [
            (wavy(4, 3), 16),
            (wavy(5, 5), 64),
            (wavy(7, 2), 7),
            (collapsed(), 8),
            (fold(), 15),
        ] {
            let (stats, turn) = curvature_and_turn(&p, k);
            assert_eq!(stats, abs_mean_curvature(&p, k), "degree {:?}", p.degree());
            assert_eq!(turn, largest_normal_turn(&p, k), "degree {:?}", p.degree());
        }
        assert_eq!(curvature_and_turn(&collapsed(), 8).0.singular, 1);
        assert!(curvature_and_turn(&fold(), 15).1.unwrap().is_fold());
    }
}
