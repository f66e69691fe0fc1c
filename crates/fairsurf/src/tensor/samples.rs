//! A Bézier patch sampled on a grid for meshes: positions alone
//! ([`TensorPatch::eval_on`]), or positions, unit normals and curvatures
//! ([`TensorPatch::samples_on`]) — a row at a time from
//! [`TensorPatch::grid_rows`], the per-point work as one vectorizable loop
//! over the row, the same operations as [`Sample::of`] so the same bits.

use super::patch::{chunk3, GridRows, GRID_LANES};
use crate::analysis::PointForms;
use crate::surface::Sample;
use crate::vec3::{normalize_with_norm, Vec3};
use crate::TensorPatch;

impl TensorPatch {
    /// R on the grid `us` × `vs`, u-major (entry a·|vs| + b at (`us[a]`,
    /// `vs[b]`)): the points of [`TensorPatch::derivatives_on`] — to
    /// rounding where there are more u's than v's: then the patch is
    /// contracted in v first (one pass per v, not per u: a boundary curve
    /// v = const costs one row).
    pub fn eval_on(&self, us: &[f64], vs: &[f64]) -> Vec<Vec3> {
        if us.len() > vs.len() {
            let t = self.transposed().eval_on(vs, us);
            return (0..us.len() * vs.len())
                .map(|q| t[(q % vs.len()) * us.len() + q / vs.len()])
                .collect();
        }
        /// The rows' points one after the other.
        struct Points(Vec<Vec3>, usize);
        impl GridRows<1> for Points {
            #[inline(always)]
            fn row(&mut self, _: usize, [p]: &[[Vec<f64>; 3]; 1]) {
                let nv = self.1;
                let (x, y, z) = (&p[0][..nv], &p[1][..nv], &p[2][..nv]);
                self.0.extend((0..nv).map(|b| [x[b], y[b], z[b]]));
            }
        }
        let mut points = Points(Vec::with_capacity(us.len() * vs.len()), vs.len());
        self.grid_rows(us, vs, [(0, 0)], &mut points);
        points.0
    }

    /// [`Sample`]s on the grid `us` × `vs`, u-major: bit for bit
    /// [`Sample::of`] of [`TensorPatch::derivatives_on`], without the grid
    /// of derivatives.
    pub fn samples_on(&self, us: &[f64], vs: &[f64]) -> Vec<Sample> {
        const ORDERS: [(usize, usize); 6] = [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)];
        let mut sink = Samples {
            out: Vec::with_capacity(us.len() * vs.len()),
            nv: vs.len(),
            row: [(); COLUMNS].map(|_| vec![0.0; vs.len().next_multiple_of(GRID_LANES)]),
        };
        self.grid_rows(us, vs, ORDERS, &mut sink);
        sink.out
    }
}

/// Per point of a row: x, y, z, ñ = R_u × R_v (3), |ñ|, E, G, EG − F², K,
/// H and √(max(H² − K, 0)).
const COLUMNS: usize = 13;

struct Samples {
    out: Vec<Sample>,
    nv: usize,
    row: [Vec<f64>; COLUMNS],
}

impl GridRows<6> for Samples {
    #[inline(always)]
    fn row(&mut self, _: usize, rows: &[[Vec<f64>; 3]; 6]) {
        const L: usize = GRID_LANES;
        for k in 0..self.row[0].len() / L {
            let [p, du, dv, duu, duv, dvv] = [
                chunk3(&rows[0], k),
                chunk3(&rows[1], k),
                chunk3(&rows[2], k),
                chunk3(&rows[3], k),
                chunk3(&rows[4], k),
                chunk3(&rows[5], k),
            ];
            let mut out = [[0.0; L]; COLUMNS];
            for t in 0..L {
                let lane = |c: [&[f64; L]; 3]| [c[0][t], c[1][t], c[2][t]];
                let f = PointForms::at(lane(du), lane(dv), lane(duu), lane(duv), lane(dvv));
                let [x, y, z] = lane(p);
                let [n0, n1, n2] = f.nn;
                let values = [x, y, z, n0, n1, n2, f.l, f.e, f.g, f.det, f.k, f.h, f.s];
                for (o, v) in out.iter_mut().zip(values) {
                    o[t] = v;
                }
            }
            for (to, from) in self.row.iter_mut().zip(&out) {
                to[k * L..][..L].copy_from_slice(from);
            }
        }
        let [x, y, z, n0, n1, n2, l, e, g, det, k, h, s] = &self.row;
        for b in 0..self.nv {
            let f = PointForms {
                nn: [n0[b], n1[b], n2[b]],
                l: l[b],
                e: e[b],
                g: g[b],
                det: det[b],
                k: k[b],
                h: h[b],
                s: s[b],
            };
            self.out.push(Sample {
                point: [x[b], y[b], z[b]],
                normal: normalize_with_norm(f.nn, f.l),
                curvature: f.curvature(),
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ParamSurface;

    /// Bit for bit the samples of the stored derivatives, and the points
    /// those of the derivatives: rows that are and are not whole chunks,
    /// a collapsed corner (no normal, no curvature there).
    #[test]
    fn samples_are_those_of_the_derivatives() {
        let wavy = TensorPatch::from_fn(10, 7, |i, j| {
            let (u, v) = (i as f64 / 10.0, j as f64 / 7.0);
            [u + 0.1 * v * v, v, 0.3 * (3.0 * u).sin() * (2.0 * v).cos()]
        });
        let mut collapsed = TensorPatch::from_fn(3, 3, |i, j| [i as f64, j as f64, (i * j) as f64]);
        collapsed.set_point(1, 0, collapsed.point(0, 0));
        collapsed.set_point(0, 1, collapsed.point(0, 0));
        for (p, k) in [(&wavy, 48), (&wavy, 5), (&collapsed, 8)] {
            let (us, vs) = p.uniform_grid(k, k + 3);
            let d = p.derivatives_on(&us, &vs);
            let want: Vec<Sample> = d.iter().map(Sample::of).collect();
            assert_eq!(p.samples_on(&us, &vs), want);
            let points: Vec<Vec3> = d.iter().map(|d| d.point).collect();
            assert_eq!(p.eval_on(&us, &vs), points);
            // More u's than v's: contracted the other way, to rounding.
            let d = p.derivatives_on(&vs, &us);
            let e = p.eval_on(&vs, &us);
            assert_eq!(e.len(), d.len());
            for (x, y) in e.iter().zip(&d) {
                assert!(
                    crate::vec3::dist(*x, y.point) < 1e-14,
                    "{x:?} vs {:?}",
                    y.point
                );
            }
        }
        let (us, vs) = collapsed.uniform_grid(8, 11);
        let s = collapsed.samples_on(&us, &vs);
        assert_eq!(s.iter().filter(|s| s.curvature.is_none()).count(), 1);
        assert!(s[0].normal.is_none() && s[0].curvature.is_none());
    }
}
