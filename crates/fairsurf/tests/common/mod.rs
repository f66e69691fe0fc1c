//! Shared helpers for the integration tests (a tiny deterministic RNG, nets).
#![allow(dead_code, missing_docs)]

use fairsurf::{TensorPatch, Vec3};

/// xorshift64*: deterministic, dependency-free pseudo-random numbers.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// Uniform in [−1, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    pub fn vec3(&mut self) -> Vec3 {
        [self.uniform(), self.uniform(), self.uniform()]
    }
}

/// A wavy net over roughly the unit square with random perturbations.
pub fn random_net(n: usize, m: usize, seed: u64) -> TensorPatch {
    let mut r = Rng::new(seed);
    TensorPatch::from_fn(n, m, |i, j| {
        let (x, y) = (i as f64 / n as f64, j as f64 / m as f64);
        [
            x + 0.05 * r.uniform(),
            y + 0.05 * r.uniform(),
            0.3 * (3.0 * x).sin() * (2.0 * y + 0.5).cos() + 0.1 * r.uniform(),
        ]
    })
}

/// A smooth unit-ish normal field of degree (2, 2) tilting across the square.
pub fn tilted_field() -> TensorPatch {
    TensorPatch::from_fn(2, 2, |i, j| {
        [0.4 * (i as f64 - 1.0), 0.3 * (j as f64 - 1.0), 1.0]
    })
}

pub fn max_dist(a: &TensorPatch, b: &TensorPatch) -> f64 {
    a.points()
        .iter()
        .zip(b.points())
        .map(|(p, q)| fairsurf::vector::norm(fairsurf::vector::sub(*p, *q)))
        .fold(0.0, f64::max)
}

/// The unit square as an m × m grid of squares, each cut along its
/// diagonal into two counter-clockwise triangles: triangle 2(j·m + i) is
/// (i, j), (i+1, j), (i+1, j+1), the next one (i, j), (i+1, j+1), (i, j+1).
pub fn tri_grid(m: usize, n: usize) -> fairsurf::TriSurface {
    let id = |i: usize, j: usize| j * (m + 1) + i;
    let mut v = Vec::new();
    for j in 0..=m {
        for i in 0..=m {
            v.push([i as f64 / m as f64, j as f64 / m as f64, 0.0]);
        }
    }
    let mut t = Vec::new();
    for j in 0..m {
        for i in 0..m {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    fairsurf::TriSurface::new(&v, &t, n)
}
