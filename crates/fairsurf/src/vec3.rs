//! Small helpers for 3D points and vectors stored as `[f64; 3]`.
//!
//! Control points, normals and evaluated points are plain arrays: there is no
//! invariant to protect, and arrays serialize and index naturally.

/// A point or vector in ℝ³.
pub type Vec3 = [f64; 3];

/// a + b
#[inline]
pub fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// a − b
#[inline]
pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// s·a
#[inline]
pub fn scale(a: Vec3, s: f64) -> Vec3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// a·b
#[inline]
pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b
#[inline]
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// |a|
#[inline]
pub fn norm(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}

/// |a − b|
#[inline]
pub fn dist(a: Vec3, b: Vec3) -> f64 {
    norm(sub(a, b))
}

/// a / |a|, or `None` when a is zero or not finite. Any finite nonzero
/// vector has a direction, also when |a|² would overflow or underflow
/// (e.g. (−0.6, 1e300, 1)): then it is scaled by its largest coordinate
/// first.
#[inline]
pub fn normalize(a: Vec3) -> Option<Vec3> {
    normalize_with_norm(a, norm(a))
}

/// [`normalize`] of `a` with its norm `l = |a|` at hand (computed as
/// [`norm`] does): a · (1/l) in the usual case, the same bits.
#[inline(always)]
pub(crate) fn normalize_with_norm(a: Vec3, l: f64) -> Option<Vec3> {
    if l.is_finite() && l > 1e-150 {
        return Some(scale(a, 1.0 / l));
    }
    let m = a.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if !(m > 0.0 && is_finite(a)) {
        return None;
    }
    let b = scale(a, 1.0 / m);
    Some(scale(b, 1.0 / norm(b)))
}

/// Angle between two vectors in radians, in [0, π]; robust near 0 and π
/// (atan2 of |a×b| and a·b).
#[inline]
pub fn angle(a: Vec3, b: Vec3) -> f64 {
    norm(cross(a, b)).atan2(dot(a, b))
}

/// True when all three coordinates are finite.
#[inline]
pub fn is_finite(a: Vec3) -> bool {
    a.iter().all(|c| c.is_finite())
}

/// The diagonal of the points' axis-aligned bounding box (not finite for
/// no points; callers choose their fallback).
pub fn bounding_diagonal(points: &[Vec3]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    norm(sub(hi, lo))
}

/// The distance from p to the segment [a, b] (to a when the segment is a
/// point).
pub fn segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let d = sub(b, a);
    let l = dot(d, d);
    let t = if l > 0.0 {
        (dot(sub(p, a), d) / l).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, add(a, scale(d, t)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Inside the segment the distance is the perpendicular one, past its
    /// ends the distance to the nearer end.
    #[test]
    fn segment_distance_is_perpendicular_inside_and_to_the_ends_outside() {
        let (a, b) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
        assert_eq!(segment_distance([0.5, 3.0, 4.0], a, b), 5.0);
        assert_eq!(segment_distance([-3.0, 4.0, 0.0], a, b), 5.0);
        assert_eq!(segment_distance([5.0, 0.0, 4.0], a, b), 5.0);
        assert_eq!(segment_distance([3.0, 4.0, 0.0], a, a), 5.0);
    }

    /// Every finite nonzero vector has a direction, however large or small
    /// its coordinates (the fuzz found a director (−0.6, 1e300, 1) whose
    /// |d|² overflowed); zero and non-finite vectors have none.
    #[test]
    fn normalize_gives_every_finite_nonzero_vector_its_direction() {
        let n = normalize([-0.6, 1e300, 1.0]).unwrap();
        assert_eq!(n, [-0.6e-300, 1.0, 1e-300]);
        let n = normalize([3e-200, 0.0, -4e-200]).unwrap();
        assert!(
            (n[0] - 0.6).abs() < 1e-15 && (n[2] + 0.8).abs() < 1e-15,
            "{n:?}"
        );
        assert_eq!(normalize([0.0, 2.0, 0.0]), Some([0.0, 1.0, 0.0]));
        assert_eq!(normalize([0.0; 3]), None);
        assert_eq!(normalize([f64::NAN, 1.0, 0.0]), None);
        assert_eq!(normalize([f64::INFINITY, 1.0, 0.0]), None);
    }
}
