//! Continuity across a boundary shared by two patches, sampled densely:
//! the gap (C0), the angle between the normals (G1) and the jump of the mean
//! curvature (G2).

use super::curvature::curvature_from;
use crate::vec3::{cross, dot, norm, sub};
use crate::TensorPatch;

/// One boundary curve of a tensor patch, parametrized by t ∈ [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Edge {
    /// u = 0, v = t.
    U0,
    /// u = 1, v = t.
    U1,
    /// v = 0, u = t.
    V0,
    /// v = 1, u = t.
    V1,
}

impl Edge {
    /// (u, v) of the edge point with parameter t.
    pub fn param(self, t: f64) -> (f64, f64) {
        match self {
            Edge::U0 => (0.0, t),
            Edge::U1 => (1.0, t),
            Edge::V0 => (t, 0.0),
            Edge::V1 => (t, 1.0),
        }
    }
}

/// Max and mean of one measure along the boundary.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stat {
    /// Largest value.
    pub max: f64,
    /// Mean over the samples where it is defined.
    pub mean: f64,
}

/// How well two patches join along an edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Continuity {
    /// |A(t) − B(t)| (C0).
    pub gap: Stat,
    /// Unoriented angle between the unit normals, radians (G1): orientation
    /// depends on which edges meet, so a normal and its opposite count as
    /// equal.
    pub normal_angle: Stat,
    /// |H_A − H_B| with H_B's sign taken for A's orientation (G2).
    pub mean_curvature_jump: Stat,
    /// Samples along the edge.
    pub samples: usize,
    /// Samples where a normal or curvature did not exist (collapsed corner).
    pub singular: usize,
}

/// Compares patch `a` along `ea` with patch `b` along `eb` at k+1 equally
/// spaced parameters; `reversed` pairs t on A with 1 − t on B.
///
/// ```
/// use fairsurf::analysis::{continuity, Edge};
/// use fairsurf::TensorPatch;
/// let p = TensorPatch::from_fn(3, 3, |i, j| [i as f64, j as f64, ((i * j) as f64).sin()]);
/// let (left, right) = p.subdivide_u(0.4);
/// let c = continuity(&left, Edge::U1, &right, Edge::U0, false, 64);
/// assert!(c.gap.max < 1e-12 && c.normal_angle.max < 1e-12);
/// ```
pub fn continuity(
    a: &TensorPatch,
    ea: Edge,
    b: &TensorPatch,
    eb: Edge,
    reversed: bool,
    k: usize,
) -> Continuity {
    let k = k.max(1);
    let (mut gap, mut ang, mut jump) = (Stat::default(), Stat::default(), Stat::default());
    let (mut n_geo, mut singular) = (0usize, 0usize);
    for s in 0..=k {
        let t = s as f64 / k as f64;
        let tb = if reversed { 1.0 - t } else { t };
        let (ua, va) = ea.param(t);
        let (ub, vb) = eb.param(tb);
        let (da, db) = (a.derivatives(ua, va), b.derivatives(ub, vb));
        let g = norm(sub(da.point, db.point));
        gap.max = gap.max.max(g);
        gap.mean += g;
        let (Some(na), Some(nb), Some(ca), Some(cb)) = (
            da.normal(),
            db.normal(),
            curvature_from(&da),
            curvature_from(&db),
        ) else {
            singular += 1;
            continue;
        };
        let c = dot(na, nb);
        let angle = norm(cross(na, nb)).atan2(c.abs());
        let hb = if c < 0.0 { -cb.mean } else { cb.mean };
        let j = (ca.mean - hb).abs();
        ang.max = ang.max.max(angle);
        ang.mean += angle;
        jump.max = jump.max.max(j);
        jump.mean += j;
        n_geo += 1;
    }
    gap.mean /= (k + 1) as f64;
    if n_geo > 0 {
        ang.mean /= n_geo as f64;
        jump.mean /= n_geo as f64;
    }
    Continuity {
        gap,
        normal_angle: ang,
        mean_curvature_jump: jump,
        samples: k + 1,
        singular,
    }
}
