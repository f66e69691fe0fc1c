//! The bicubically blended Hermite–Coons patch of the boundary data: the
//! four boundary curves and the four cross-boundary derivatives (Farin,
//! *Curves and Surfaces for CAGD*, §22.4). F = P₁ + P₂ − P₁₂ with
//!
//! ```text
//! P₁(u, v) = H₀(v) B₀(u) + H₁(v) B₁(u) + G₀(v) T₀(u) + G₁(v) T₁(u)
//! P₂(u, v) = H₀(u) C₀(v) + H₁(u) C₁(v) + G₀(u) S₀(v) + G₁(u) S₁(v)
//! P₁₂      = Σ_ab H_a(u)H_b(v) F_ab + G_a(u)H_b(v) F^u_ab + H_a(u)G_b(v) F^v_ab + G_a(u)G_b(v) F^uv_ab
//! ```
//!
//! (B_b the curves v = b, T_b their v-derivatives, C_a, S_a likewise in u;
//! H₀ = 2t³ − 3t² + 1, H₁ = 3t² − 2t³, G₀ = t³ − 2t² + t, G₁ = t³ − t²;
//! the corner twists F^uv the mean of the two sides' values). Only its
//! normals are used: they guide the fill.

use super::strip::{Strip, StripPoint};
use crate::vec3::{add, scale};
use crate::Vec3;

/// The patch of four strips in the fill's frame (scaled: D is the fill's
/// cross derivative into the hole).
pub(crate) struct Coons<'a> {
    s: &'a [Strip; 4],
    /// F, F_u, F_v, F_uv at corner (a, b).
    corner: [[[Vec3; 4]; 2]; 2],
}

/// (H₀, H₁, G₀, G₁) and their derivatives at t.
fn hermite(t: f64) -> ([f64; 4], [f64; 4]) {
    let (t2, t3) = (t * t, t * t * t);
    (
        [
            2.0 * t3 - 3.0 * t2 + 1.0,
            3.0 * t2 - 2.0 * t3,
            t3 - 2.0 * t2 + t,
            t3 - t2,
        ],
        [
            6.0 * t2 - 6.0 * t,
            6.0 * t - 6.0 * t2,
            3.0 * t2 - 4.0 * t + 1.0,
            3.0 * t2 - 2.0 * t,
        ],
    )
}

/// Σ w_k x_k.
fn comb(w: &[f64], x: &[Vec3]) -> Vec3 {
    w.iter()
        .zip(x)
        .fold([0.0; 3], |a, (&w, &x)| add(a, scale(x, w)))
}

impl<'a> Coons<'a> {
    pub fn new(s: &'a [Strip; 4]) -> Self {
        // B₀ = side 0 (v = 0), B₁ = side 2 (v = 1, its D points to −v);
        // C₀ = side 3 (u = 0), C₁ = side 1 (u = 1, D points to −u).
        let b = [s[0].at(0.0), s[0].at(1.0), s[2].at(0.0), s[2].at(1.0)];
        let c = [s[3].at(0.0), s[3].at(1.0), s[1].at(0.0), s[1].at(1.0)];
        let sign = [1.0, -1.0];
        let corner = std::array::from_fn(|a| {
            std::array::from_fn(|bb| {
                let along_u: StripPoint = b[2 * bb + a];
                let along_v: StripPoint = c[2 * a + bb];
                let twist = scale(
                    add(scale(along_u.dder, sign[bb]), scale(along_v.dder, sign[a])),
                    0.5,
                );
                [
                    along_u.pos,
                    along_u.dpos,
                    scale(along_u.der, sign[bb]),
                    twist,
                ]
            })
        });
        Self { s, corner }
    }

    /// F, F_u and F_v at (u, v).
    pub fn at(&self, u: f64, v: f64) -> (Vec3, Vec3, Vec3) {
        let s = self.s;
        self.at_with(u, v, [s[0].at(u), s[2].at(u)], [s[3].at(v), s[1].at(v)])
    }

    /// F, F_u and F_v on the grid `us` × `vs` (u-major), each side evaluated
    /// once per parameter.
    pub fn on_grid(&self, us: &[f64], vs: &[f64]) -> Vec<(Vec3, Vec3, Vec3)> {
        let s = self.s;
        let bu: Vec<[StripPoint; 2]> = us.iter().map(|&u| [s[0].at(u), s[2].at(u)]).collect();
        let bv: Vec<[StripPoint; 2]> = vs.iter().map(|&v| [s[3].at(v), s[1].at(v)]).collect();
        let mut out = Vec::with_capacity(us.len() * vs.len());
        for (&u, b) in us.iter().zip(&bu) {
            for (&v, c) in vs.iter().zip(&bv) {
                out.push(self.at_with(u, v, *b, *c));
            }
        }
        out
    }

    /// F, F_u, F_v at (u, v) from the sides there: B₀, B₁ at u and C₀, C₁
    /// at v.
    fn at_with(
        &self,
        u: f64,
        v: f64,
        b: [StripPoint; 2],
        c: [StripPoint; 2],
    ) -> (Vec3, Vec3, Vec3) {
        let (hu, dhu) = hermite(u);
        let (hv, dhv) = hermite(v);
        let [b0, b1] = b;
        let [c0, c1] = c;
        // P₁: curves in u, blends in v.
        let x1 = [b0.pos, b1.pos, b0.der, scale(b1.der, -1.0)];
        let x1u = [b0.dpos, b1.dpos, b0.dder, scale(b1.dder, -1.0)];
        let x2 = [c0.pos, c1.pos, c0.der, scale(c1.der, -1.0)];
        let x2v = [c0.dpos, c1.dpos, c0.dder, scale(c1.dder, -1.0)];
        let (mut f, mut fu, mut fv) = (
            add(comb(&hv, &x1), comb(&hu, &x2)),
            add(comb(&hv, &x1u), comb(&dhu, &x2)),
            add(comb(&dhv, &x1), comb(&hu, &x2v)),
        );
        // − P₁₂: blends index (value H_a, H_b; u-derivative G_a; v-derivative G_b).
        for a in 0..2 {
            for b in 0..2 {
                let [p, pu, pv, puv] = self.corner[a][b];
                let terms = [
                    (hu[a], dhu[a], hv[b], dhv[b], p),
                    (hu[2 + a], dhu[2 + a], hv[b], dhv[b], pu),
                    (hu[a], dhu[a], hv[2 + b], dhv[2 + b], pv),
                    (hu[2 + a], dhu[2 + a], hv[2 + b], dhv[2 + b], puv),
                ];
                for (wu, dwu, wv, dwv, x) in terms {
                    f = add(f, scale(x, -wu * wv));
                    fu = add(fu, scale(x, -dwu * wv));
                    fv = add(fv, scale(x, -wu * dwv));
                }
            }
        }
        (f, fu, fv)
    }
}
