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

/// a / |a|, or `None` when |a| is zero or not finite.
#[inline]
pub fn normalize(a: Vec3) -> Option<Vec3> {
    let l = norm(a);
    (l > 0.0 && l.is_finite()).then(|| scale(a, 1.0 / l))
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
