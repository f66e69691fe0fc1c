//! A 4-sided hole's boundary data from its neighbours: the sides grouped
//! into four, the strips (positions and cross derivatives) along them, α per
//! side, the two outer rings of the fill's net and the sides brought to
//! common knots.

use super::*;

/// Whether a fill whose normal along side 0 is P′ × D (its strip `s0`,
/// D into the hole) faces the way side 0's neighbour does.
pub(super) fn faces_like_side_0(faces: &[BSplineSurface], hole: &Hole, s0: &Strip) -> bool {
    let side0 = hole.sides[0];
    facing(&faces[side0.face], side0, s0)
}

/// Whether `face` faces along `side` the way a fill whose normal there is
/// P′ × D (the side's strip `s`, D into the hole) does.
fn facing(face: &BSplineSurface, side: Side, s: &Strip) -> bool {
    let (u, v) = surface_param(face, side.edge, side.boundary_t(0.5));
    let nb = face.derivatives(u, v);
    let mid = s.at(0.5);
    dot(cross(mid.dpos, mid.der), cross(nb.du, nb.dv)) >= 0.0
}

/// Whether the neighbour `face` of `side` faces the way the fill does: a
/// fill's normal along each of its sides is P′ × D of that side's strip
/// (a patch's R_u × R_v, a fan's patches' likewise), and the fill faces
/// like side 0's neighbour ([`faces_like_side_0`]); the other neighbours
/// of a JSON scene or a Python caller may face either way (a STEP shell's
/// are oriented alike when read). A side's normal angle is measured
/// against its neighbour's normal turned the fill's way, so that a G¹
/// fill measures 0 and a fill that folds onto its neighbour 180°.
pub(super) fn faces_like(face: &BSplineSurface, side: Side) -> bool {
    Strip::of_side(face, side).map_or(true, |s| facing(face, side, &s))
}

/// The face of the hole's side k, or an error naming it.
pub(super) fn side_face<'a>(
    faces: &'a [BSplineSurface],
    hole: &Hole,
    k: usize,
) -> Result<&'a BSplineSurface> {
    let face = hole.sides[k].face;
    faces.get(face).ok_or_else(|| Error::Fill {
        why: format!("side {k} names face {face}, but there are {}", faces.len()),
    })
}

/// The hole's edges grouped into sides: a new side starts where the
/// boundary turns (tangent directions further apart than [`CONTINUES`]),
/// the hole rotated so that its first edge starts one. Errors: a smooth
/// loop without corners.
pub(super) fn grouped(faces: &[BSplineSurface], hole: &Hole) -> Result<(Hole, Vec<Range<usize>>)> {
    let n = hole.sides.len();
    let strips: Vec<Strip> = (0..n)
        .map(|k| Strip::of_side(side_face(faces, hole, k)?, hole.sides[k]))
        .collect::<Result<_>>()?;
    let corner: Vec<bool> = (0..n)
        .map(|k| {
            let (end, start) = (strips[(k + n - 1) % n].at(1.0), strips[k].at(0.0));
            let turn = crate::vec3::angle(end.dpos, start.dpos);
            turn.is_nan() || turn > CONTINUES
        })
        .collect();
    let Some(first) = corner.iter().position(|&c| c) else {
        return Err(Error::Fill {
            why: "the hole's boundary turns nowhere: a smooth closed loop has no sides to fill \
                  between"
                .into(),
        });
    };
    let mut hole = hole.clone();
    hole.sides.rotate_left(first);
    let starts: Vec<usize> = (0..n).filter(|&k| corner[(k + first) % n]).collect();
    let groups = starts
        .iter()
        .enumerate()
        .map(|(g, &a)| a..starts.get(g + 1).copied().unwrap_or(n))
        .collect();
    Ok((hole, groups))
}

/// The four sides' boundary data in the fill's frame: the u-sides (0, 2)
/// and v-sides (3, 1) as strips along increasing u resp. v, D pointing
/// into the hole (not yet scaled by α); and each side's breakpoints
/// between its edges, along the hole's traversal.
pub(super) fn frame(
    faces: &[BSplineSurface],
    hole: &Hole,
    groups: &[Range<usize>],
) -> Result<([Strip; 4], [Vec<f64>; 4])> {
    let strip = |k: usize| -> Result<(Strip, Vec<f64>)> {
        let pieces: Vec<Strip> = groups[k]
            .clone()
            .map(|e| Strip::of_side(side_face(faces, hole, e)?, hole.sides[e]))
            .collect::<Result<_>>()?;
        let (st, breaks) = concat(&pieces).map_err(|e| match e {
            Error::Fill { why } => Error::Fill {
                why: format!("side {k}: {why}"),
            },
            e => e,
        })?;
        // Sides 2 and 3 run against the fill's u resp. v.
        Ok((if k >= 2 { st.reversed() } else { st }, breaks))
    };
    let [a, b, c, d] = [strip(0)?, strip(1)?, strip(2)?, strip(3)?];
    Ok(([a.0, b.0, c.0, d.0], [a.1, b.1, c.1, d.1]))
}

/// α for side k from its two corners: the least-squares c with
/// c·D ≈ the corner tangent it must equal, averaged over both ends.
pub(super) fn alphas(s: &[Strip; 4]) -> Result<[f64; 4]> {
    // (side, its t, sign of D in the fill, the tangent it must equal)
    let ends = |k: usize| -> [(f64, f64, Vec3); 2] {
        match k {
            // ∂F/∂v(u, 0) = α₀ D₀(u): at u = 0 it is side 3's P′(0), at u = 1 side 1's P′(0).
            0 => [(0.0, 1.0, s[3].at(0.0).dpos), (1.0, 1.0, s[1].at(0.0).dpos)],
            // ∂F/∂u(1, v) = −α₁ D₁(v).
            1 => [
                (0.0, -1.0, s[0].at(1.0).dpos),
                (1.0, -1.0, s[2].at(1.0).dpos),
            ],
            // ∂F/∂v(u, 1) = −α₂ D₂(u).
            2 => [
                (0.0, -1.0, s[3].at(1.0).dpos),
                (1.0, -1.0, s[1].at(1.0).dpos),
            ],
            // ∂F/∂u(0, v) = α₃ D₃(v).
            _ => [(0.0, 1.0, s[0].at(0.0).dpos), (1.0, 1.0, s[2].at(0.0).dpos)],
        }
    };
    let mut out = [0.0; 4];
    for (k, a) in out.iter_mut().enumerate() {
        let mut sum = 0.0;
        for (t, sign, tangent) in ends(k) {
            let d = scale(s[k].at(t).der, sign);
            let c = dot(d, tangent) / dot(d, d);
            if !(c > 0.0 && c.is_finite()) {
                return Err(Error::Fill {
                    why: format!(
                        "at the corner where side {k} {} (t = {t}), its neighbour's cross-boundary \
                         derivative does not point into the hole along the adjacent side (the \
                         faces fold over there, or the side is not a boundary facing the hole)",
                        if t == 0.0 { "starts" } else { "ends" }
                    ),
                });
            }
            sum += c;
        }
        *a = sum / 2.0;
    }
    Ok(out)
}

/// The two rings of the fill and the corner mismatches: the net (None
/// inside) on the knot vectors of the unified sides. A side whose `across`
/// is false gives only its boundary points (a blend's made sides: position,
/// no tangent plane).
pub(super) fn rings(
    s: &[Strip; 4],
    across: [bool; 4],
) -> (KnotVector, KnotVector, Vec<Option<Vec3>>, CornerMismatch) {
    let (ku, kv) = (s[0].knots.clone(), s[3].knots.clone());
    let (p, q) = (ku.degree(), kv.degree());
    let (cu, cv) = (ku.count(), kv.count());
    // candidates[i][j]: (priority 0 position / 1 derivative row, point)
    let mut cand: Vec<Vec<(u8, Vec3)>> = vec![Vec::new(); cu * cv];
    let (hu0, hu1) = (ku.knots()[p + 1], 1.0 - ku.knots()[cu - 1]);
    let (hv0, hv1) = (kv.knots()[q + 1], 1.0 - kv.knots()[cv - 1]);
    let ring = |x: Vec3, d: Vec3, h: f64, p: usize| add(x, scale(d, h / p as f64));
    for i in 0..cu {
        cand[i * cv].push((0, s[0].pos[i]));
        cand[i * cv + cv - 1].push((0, s[2].pos[i]));
        if across[0] {
            cand[i * cv + 1].push((1, ring(s[0].pos[i], s[0].der[i], hv0, q)));
        }
        if across[2] {
            cand[i * cv + cv - 2].push((1, ring(s[2].pos[i], s[2].der[i], hv1, q)));
        }
    }
    for j in 0..cv {
        cand[j].push((0, s[3].pos[j]));
        cand[(cu - 1) * cv + j].push((0, s[1].pos[j]));
        if across[3] {
            cand[cv + j].push((1, ring(s[3].pos[j], s[3].der[j], hu0, p)));
        }
        if across[1] {
            cand[(cu - 2) * cv + j].push((1, ring(s[1].pos[j], s[1].der[j], hu1, p)));
        }
    }
    let mut m = CornerMismatch::default();
    let net = cand
        .into_iter()
        .map(|c| {
            let best = c.iter().map(|x| x.0).min()?;
            let top: Vec<Vec3> = c.iter().filter(|x| x.0 == best).map(|x| x.1).collect();
            let mean = scale(
                top.iter().fold([0.0; 3], |a, &b| add(a, b)),
                1.0 / top.len() as f64,
            );
            for x in &c {
                let d = dist(x.1, mean);
                match (best, x.0) {
                    (0, 0) => m.position = m.position.max(2.0 * d),
                    (0, _) => m.tangent = m.tangent.max(d),
                    _ => m.twist = m.twist.max(2.0 * d),
                }
            }
            Some(mean)
        })
        .collect();
    (ku, kv, net, m)
}

/// Control points along a pair of opposite sides (the larger count) from
/// which the fill is not elevated in that direction: they leave at least
/// eight free rows already, and elevating a side of many spans (a
/// rational face's stand-in) only raises its knots' multiplicities — on
/// the fillet example 29 instead of 13 control points across the
/// cylinders for the same W to 1e-6, at three times the cost.
pub const RICH_SIDES: usize = 12;

/// The most control points one fill patch may have (128 × 128): its
/// sparse solve takes seconds and its factor hundreds of megabytes there
/// (a 27 × 42 patch took 0.28 s); a loft's strips cut in 512 pieces each
/// asked for 69,144 free points, and the factorization was killed for its
/// memory (over 5 GB).
pub const MAX_FILL_POINTS: usize = 128 * 128;

/// Sides on one degree and knot vector per direction (at least the larger
/// degree of opposite sides, plus `elevate` unless they have
/// [`RICH_SIDES`] control points — then at least 3), with at least
/// `min_points` (≥ 5) control points each way: two rings each side and a
/// free row.
pub(super) fn unified(s: &[Strip; 4], options: &FillOptions) -> Result<[Strip; 4]> {
    let min_points = options.min_points.max(5);
    let degree = |a: &Strip, b: &Strip| {
        let (d, rich) = (
            a.degree().max(b.degree()),
            a.knots.count().max(b.knots.count()) >= RICH_SIDES,
        );
        // Rich sides keep their degree, but at least cubic: below that the
        // thin plate does not see kinks at the knots.
        if rich {
            d.max(3)
        } else {
            d + options.elevate
        }
    };
    let (mut du, mut dv) = (degree(&s[0], &s[2]), degree(&s[1], &s[3]));
    loop {
        let (s0, s2) = unify(&s[0], &s[2], du)?;
        let (s3, s1) = unify(&s[3], &s[1], dv)?;
        let (cu, cv) = (s0.knots.count(), s3.knots.count());
        if cu * cv > MAX_FILL_POINTS {
            return Err(Error::Fill {
                why: format!(
                    "one patch over the hole would need {cu} × {cv} control points (its sides \
                     brought to common knots: {} and {} knot spans), more than the {} a fill \
                     takes; the neighbours' edges are cut in many pieces (a strip fitted to a \
                     tight tolerance, or edges of many knots): a looser position tolerance, \
                     or fewer pieces in the neighbours, lets it be filled",
                    s0.knots.spans().len(),
                    s3.knots.spans().len(),
                    MAX_FILL_POINTS
                ),
            });
        }
        if cu >= min_points && cv >= min_points {
            return Ok([s0, s1, s2, s3]);
        }
        du += usize::from(cu < min_points);
        dv += usize::from(cv < min_points);
    }
}
