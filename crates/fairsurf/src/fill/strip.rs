//! Boundary data along one side of a hole: the neighbour's boundary curve
//! P(t) and its cross-boundary derivative D(t) pointing into the hole, one
//! B-spline of t ∈ [0, 1] with six numbers per coefficient, brought to a
//! common degree and knot vector with the opposite side exactly (degree
//! elevation and knot insertion, [`KnotVector::elevate`] /
//! [`KnotVector::insert`]).

use crate::analysis::Edge;
use crate::bspline::{BSplineSurface, KnotVector};
use crate::vec3::{add, norm, scale, sub};
use crate::{Error, Result, Vec3};

/// Knots closer than this (on [0, 1]) are one knot when two sides meet.
pub(crate) const KNOT_SNAP: f64 = 1e-12;

/// P(t) and D(t) on one knot vector over [0, 1].
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Strip {
    pub knots: KnotVector,
    pub pos: Vec<Vec3>,
    pub der: Vec<Vec3>,
}

/// P, P′, D and D′ at one parameter.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StripPoint {
    pub pos: Vec3,
    pub dpos: Vec3,
    pub der: Vec3,
    pub dder: Vec3,
}

/// A knot vector's knots mapped affinely onto [0, 1] (the ends exactly).
fn unit_knots(k: &KnotVector) -> Result<KnotVector> {
    let (a, b) = k.domain();
    let unit: Vec<f64> = k.knots().iter().map(|&t| (t - a) / (b - a)).collect();
    // Interior knots must stay inside (0, 1) both ways round (a strip may
    // be reversed, t → 1 − t): one closer to an end than rounding is not.
    let p = k.degree();
    let interior = &unit[p + 1..unit.len() - p - 1];
    if let Some(t) = interior
        .iter()
        .find(|&&t| !(t > 0.0 && t < 1.0 && 1.0 - t > 0.0 && 1.0 - t < 1.0))
    {
        return Err(Error::Fill {
            why: format!(
                "a boundary's interior knot at {t:e} of its domain is closer to an end than \
                 double precision resolves"
            ),
        });
    }
    KnotVector::new(p, unit)
}

impl Strip {
    /// The boundary `edge` of `surface` (its parameter t ∈ [0, 1] mapped
    /// onto the knot domain, reversed when `reversed`) and the derivative
    /// across it, with respect to the neighbour's parameter mapped onto
    /// [0, 1], turned to point away from the neighbour: the derivative a
    /// C¹ continuation would have.
    ///
    /// At u = u_min, ∂R/∂ũ = (b − a)·p/(u_{p+1} − a)·(P₁ − P₀) (the clamped
    /// end's derivative, ũ = (u − a)/(b − a)); at u = u_max likewise with
    /// the last two rows; D is minus the one pointing into the neighbour.
    pub fn from_side(surface: &BSplineSurface, edge: Edge, reversed: bool) -> Result<Self> {
        let (s, at_end) = match edge {
            Edge::U0 => (surface.clone(), false),
            Edge::U1 => (surface.clone(), true),
            Edge::V0 => (surface.transposed(), false),
            Edge::V1 => (surface.transposed(), true),
        };
        let (ku, kv) = s.knots();
        let (p, (cu, cv)) = (ku.degree(), s.counts());
        let (a, b) = ku.domain();
        let (row0, row1, h) = if at_end {
            (cu - 1, cu - 2, b - ku.knots()[cu - 1])
        } else {
            (0, 1, ku.knots()[p + 1] - a)
        };
        let c = (b - a) * p as f64 / h;
        let pos: Vec<Vec3> = (0..cv).map(|j| s.point(row0, j)).collect();
        let der = (0..cv)
            .map(|j| scale(sub(s.point(row0, j), s.point(row1, j)), c))
            .collect();
        let strip = Self {
            knots: unit_knots(kv)?,
            pos,
            der,
        };
        Ok(if reversed { strip.reversed() } else { strip })
    }

    /// The strip of a hole's side: its face's boundary, the part
    /// `side.range` of it (cut exactly), as the hole runs.
    pub fn of_side(surface: &BSplineSurface, side: super::Side) -> Result<Self> {
        let whole = Self::from_side(surface, side.edge, false)?;
        let part = whole.part(side.range)?;
        Ok(if side.reversed { part.reversed() } else { part })
    }

    /// The part over [a, b] ⊆ [0, 1], its parameter mapped onto [0, 1]:
    /// the curve cut exactly by knot insertion (a cut within
    /// [`KNOT_SNAP`] of a knot is made at the knot).
    pub fn part(&self, [a, b]: [f64; 2]) -> Result<Self> {
        if a == 0.0 && b == 1.0 {
            return Ok(self.clone());
        }
        let snap = |t: f64| {
            self.knots
                .knots()
                .iter()
                .copied()
                .find(|k| (k - t).abs() <= KNOT_SNAP)
                .unwrap_or(t)
        };
        let (a, b) = (snap(a), snap(b));
        // P and D as the two columns of a surface linear in v, cut in u.
        let net = BSplineSurface::new(
            self.knots.clone(),
            KnotVector::bezier(1),
            self.pos
                .iter()
                .zip(&self.der)
                .flat_map(|(p, d)| [*p, *d])
                .collect(),
        )?;
        let cut = net.restricted_u(a, b)?;
        let cu = cut.counts().0;
        Ok(Self {
            knots: unit_knots(cut.knots().0)?,
            pos: (0..cu).map(|i| cut.point(i, 0)).collect(),
            der: (0..cu).map(|i| cut.point(i, 1)).collect(),
        })
    }

    /// The same data with t → 1 − t.
    pub fn reversed(&self) -> Self {
        let mut knots: Vec<f64> = self.knots.knots().iter().map(|&t| 1.0 - t).collect();
        knots.reverse();
        let rev = |v: &[Vec3]| v.iter().rev().copied().collect();
        Self {
            knots: KnotVector::new(self.knots.degree(), knots)
                .expect("interior knots inside (0, 1) both ways round (unit_knots)"),
            pos: rev(&self.pos),
            der: rev(&self.der),
        }
    }

    /// D multiplied by `c`.
    pub fn scaled(&self, c: f64) -> Self {
        Self {
            der: self.der.iter().map(|&d| scale(d, c)).collect(),
            ..self.clone()
        }
    }

    /// The degree.
    pub fn degree(&self) -> usize {
        self.knots.degree()
    }

    fn flat(&self) -> Vec<f64> {
        self.pos
            .iter()
            .zip(&self.der)
            .flat_map(|(p, d)| [p[0], p[1], p[2], d[0], d[1], d[2]])
            .collect()
    }

    fn from_flat(knots: KnotVector, flat: &[f64]) -> Self {
        let (pos, der) = flat
            .chunks(6)
            .map(|c| ([c[0], c[1], c[2]], [c[3], c[4], c[5]]))
            .unzip();
        Self { knots, pos, der }
    }

    /// The same curves at degree `p` ≥ the current one (exact).
    pub fn elevated_to(&self, p: usize) -> Result<Self> {
        let mut s = self.clone();
        while s.degree() < p {
            let (k, flat) = s.knots.elevate(&s.flat(), 6)?;
            s = Self::from_flat(k, &flat);
        }
        Ok(s)
    }

    /// The distinct interior knots with their multiplicities.
    fn interior(&self) -> Vec<(f64, usize)> {
        let mut out: Vec<(f64, usize)> = Vec::new();
        let p = self.degree();
        let k = self.knots.knots();
        for &t in &k[p + 1..k.len() - p - 1] {
            match out.last_mut() {
                Some((u, m)) if *u == t => *m += 1,
                _ => out.push((t, 1)),
            }
        }
        out
    }

    /// The same curves with every knot of `target` (value, multiplicity)
    /// present at least that often: this strip's knots within
    /// [`KNOT_SNAP`] of a target value are moved onto it first, then the
    /// missing ones inserted (exact).
    fn refined_to(&self, target: &[(f64, usize)]) -> Result<Self> {
        let p = self.degree();
        let snapped: Vec<f64> = self
            .knots
            .knots()
            .iter()
            .map(|&t| {
                target
                    .iter()
                    .find(|(u, _)| (u - t).abs() <= KNOT_SNAP)
                    .map_or(t, |(u, _)| *u)
            })
            .collect();
        let mut s = Self {
            knots: KnotVector::new(p, snapped)?,
            ..self.clone()
        };
        for &(u, m) in target {
            let have = s.knots.multiplicity(u);
            for _ in have..m {
                let (k, flat) = s.knots.insert(u, &s.flat(), 6)?;
                s = Self::from_flat(k, &flat);
            }
        }
        Ok(s)
    }

    /// P, P′, D, D′ at t ∈ [0, 1].
    pub fn at(&self, t: f64) -> StripPoint {
        let p = self.degree();
        let k = self.knots.span(t);
        let n = self.knots.basis_derivatives(k, t, 1);
        let mut out = StripPoint {
            pos: [0.0; 3],
            dpos: [0.0; 3],
            der: [0.0; 3],
            dder: [0.0; 3],
        };
        for i in 0..=p {
            let idx = k - p + i;
            out.pos = add(out.pos, scale(self.pos[idx], n[0][i]));
            out.dpos = add(out.dpos, scale(self.pos[idx], n[1][i]));
            out.der = add(out.der, scale(self.der[idx], n[0][i]));
            out.dder = add(out.dder, scale(self.der[idx], n[1][i]));
        }
        out
    }
}

/// Tangent directions closer than this (radians) continue each other: two
/// hole edges meeting so are one side of the fill, and their neighbours'
/// cross derivatives must agree in direction as closely.
pub(crate) const CONTINUES: f64 = 1e-6;

/// Consecutive edges of one side of a hole as one strip on [0, 1]: each
/// piece on [t_j, t_{j+1}] with lengths making P′ continuous at the
/// junctions (L_{j+1}/L_j = |P′_{j+1}(0)|/|P′_j(1)|: pieces of one C¹
/// surface get their original parameter back), each D scaled to meet the
/// previous one (the neighbours must agree on the cross direction there),
/// joined with a knot of multiplicity p (C⁰, exact). Returns the strip and
/// the breakpoints t_0 = 0 … t_m = 1.
pub(crate) fn concat(pieces: &[Strip]) -> Result<(Strip, Vec<f64>)> {
    if pieces.len() == 1 {
        return Ok((pieces[0].clone(), vec![0.0, 1.0]));
    }
    let p = pieces.iter().map(Strip::degree).max().unwrap_or(1);
    let pieces: Vec<Strip> = pieces
        .iter()
        .map(|s| s.elevated_to(p))
        .collect::<Result<_>>()?;
    let mut lengths = vec![1.0];
    let mut scales = vec![1.0];
    for j in 1..pieces.len() {
        let (end, start) = (pieces[j - 1].at(1.0), pieces[j].at(0.0));
        let (de, ds) = (norm(end.der), norm(start.der));
        let turn = crate::vec3::angle(end.der, start.der);
        if !(turn <= CONTINUES && de > 0.0 && ds > 0.0) {
            return Err(Error::Fill {
                why: format!(
                    "where edges {} and {j} of a side meet, their faces' cross-boundary \
                     derivatives differ in direction by {:.2e}°: a side made of such edges is not \
                     filled yet",
                    j - 1,
                    turn.to_degrees()
                ),
            });
        }
        lengths.push(lengths[j - 1] * norm(start.dpos) / norm(end.dpos));
        scales.push(scales[j - 1] * de / ds);
    }
    let total: f64 = lengths.iter().sum();
    let mut breaks = vec![0.0];
    for l in &lengths {
        let last = *breaks.last().expect("a break");
        breaks.push(last + l / total);
    }
    *breaks.last_mut().expect("a break") = 1.0;
    let mut knots = vec![0.0; p + 1];
    let (mut pos, mut der): (Vec<Vec3>, Vec<Vec3>) = (Vec::new(), Vec::new());
    for (j, piece) in pieces.iter().enumerate() {
        let (a, b) = (breaks[j], breaks[j + 1]);
        let k = piece.knots.knots();
        knots.extend(k[p + 1..k.len() - p - 1].iter().map(|&t| a + (b - a) * t));
        knots.extend(std::iter::repeat_n(
            b,
            if j + 1 == pieces.len() { p + 1 } else { p },
        ));
        let d: Vec<Vec3> = piece.der.iter().map(|&x| scale(x, scales[j])).collect();
        if j == 0 {
            pos.extend(&piece.pos);
            der.extend(&d);
        } else {
            // The junction's point once: the two pieces' agree (their
            // mean, to rounding).
            let (lp, ld) = (pos.len() - 1, der.len() - 1);
            pos[lp] = scale(add(pos[lp], piece.pos[0]), 0.5);
            der[ld] = scale(add(der[ld], d[0]), 0.5);
            pos.extend(&piece.pos[1..]);
            der.extend(&d[1..]);
        }
    }
    let mut strip = Strip {
        knots: KnotVector::new(p, knots)?,
        pos,
        der,
    };
    // Each junction's knot as rarely as the curves allow: pieces of one
    // C^(p−1) surface join with a simple knot, so the fill stays smooth
    // across the line from the junction.
    for &b in &breaks[1..breaks.len() - 1] {
        strip = strip.with_fewer(b);
    }
    Ok((strip, breaks))
}

impl Strip {
    /// The same curves with the knot `b` of the fewest multiplicity (≥ 1)
    /// that still holds them: interpolation at the Greville abscissae of
    /// the smaller knot vector, kept when it reproduces both curves to
    /// 1e-12 of their size at 8 points per span (exact up to rounding when
    /// the curves are that smooth there).
    fn with_fewer(&self, b: f64) -> Strip {
        let p = self.degree();
        let have = self.knots.multiplicity(b);
        let size = self
            .pos
            .iter()
            .chain(&self.der)
            .map(|&x| norm(x))
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        let samples: Vec<f64> = self
            .knots
            .spans()
            .iter()
            .flat_map(|&(_, a, z)| (0..=8).map(move |i| a + (z - a) * i as f64 / 8.0))
            .collect();
        let want: Vec<StripPoint> = samples.iter().map(|&t| self.at(t)).collect();
        for m in 1..have {
            let mut knots = self.knots.knots().to_vec();
            let at = knots.iter().position(|&t| t == b).expect("the knot");
            knots.drain(at..at + (have - m));
            let Ok(k) = KnotVector::new(p, knots) else {
                continue;
            };
            let Some(fit) = interpolate(&k, self) else {
                continue;
            };
            let good = samples.iter().zip(&want).all(|(&t, w)| {
                let x = fit.at(t);
                norm(sub(x.pos, w.pos)) <= 1e-12 * size && norm(sub(x.der, w.der)) <= 1e-12 * size
            });
            if good {
                return fit;
            }
        }
        self.clone()
    }
}

/// The strip on `knots` through `s`'s points at the Greville abscissae of
/// `knots` (a square, well-conditioned collocation system), or None when
/// it is singular.
fn interpolate(knots: &KnotVector, s: &Strip) -> Option<Strip> {
    let t = knots.greville();
    let a = knots.collocation(&t);
    let rhs: Vec<[f64; 6]> = t
        .iter()
        .map(|&x| {
            let q = s.at(x);
            [q.pos[0], q.pos[1], q.pos[2], q.der[0], q.der[1], q.der[2]]
        })
        .collect();
    let x = crate::bspline::solve_dense(a, rhs)?;
    let (pos, der) = x
        .iter()
        .map(|c| ([c[0], c[1], c[2]], [c[3], c[4], c[5]]))
        .unzip();
    Some(Strip {
        knots: knots.clone(),
        pos,
        der,
    })
}

/// Two opposite sides on one degree (at least `min_degree`) and one knot
/// vector: the larger degree, then the union of their knots (the larger
/// multiplicity of each).
pub(crate) fn unify(a: &Strip, b: &Strip, min_degree: usize) -> Result<(Strip, Strip)> {
    let p = a.degree().max(b.degree()).max(min_degree);
    let (a, b) = (a.elevated_to(p)?, b.elevated_to(p)?);
    let mut target: Vec<(f64, usize)> = a.interior();
    for (t, m) in b.interior() {
        match target.iter_mut().find(|(u, _)| (*u - t).abs() <= KNOT_SNAP) {
            Some((_, mm)) => *mm = (*mm).max(m),
            None => target.push((t, m)),
        }
    }
    target.sort_by(|x, y| x.0.total_cmp(&y.0));
    if let Some(&(t, m)) = target.iter().find(|(_, m)| *m > p) {
        return Err(Error::Fill {
            why: format!("the opposite sides' knot {t} would have multiplicity {m} > degree {p}"),
        });
    }
    Ok((a.refined_to(&target)?, b.refined_to(&target)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wavy(u: KnotVector, v: KnotVector) -> BSplineSurface {
        let (cu, cv) = (u.count(), v.count());
        let pts = (0..cu * cv)
            .map(|k| {
                let (i, j) = ((k / cv) as f64, (k % cv) as f64);
                [i, j * 1.3, (0.7 * i).sin() * (0.4 * j).cos() + 0.1 * i * j]
            })
            .collect();
        BSplineSurface::new(u, v, pts).unwrap()
    }

    /// The strip's P and D are the surface's boundary and minus its
    /// inward derivative, checked against de Boor derivatives.
    #[test]
    fn a_strip_is_the_boundary_and_the_outward_derivative() {
        let u = KnotVector::new(3, vec![0., 0., 0., 0., 0.4, 1., 2., 2., 2., 2.]).unwrap();
        let v = KnotVector::new(2, vec![1., 1., 1., 1.5, 3., 3., 3.]).unwrap();
        let s = wavy(u, v);
        for (edge, rev) in [
            (Edge::U0, false),
            (Edge::U1, true),
            (Edge::V0, true),
            (Edge::V1, false),
        ] {
            let strip = Strip::from_side(&s, edge, rev).unwrap();
            for t in [0.0, 0.23, 0.5, 0.91, 1.0] {
                let tt = if rev { 1.0 - t } else { t };
                let (uu, vv) = edge.param(tt);
                let (uu, vv) = (uu * 2.0, 1.0 + vv * 2.0);
                let d = s.derivatives(uu, vv);
                let at = strip.at(t);
                let (cross, sign) = match edge {
                    Edge::U0 => (scale(d.du, 2.0), -1.0),
                    Edge::U1 => (scale(d.du, 2.0), 1.0),
                    Edge::V0 => (scale(d.dv, 2.0), -1.0),
                    Edge::V1 => (scale(d.dv, 2.0), 1.0),
                };
                for c in 0..3 {
                    assert!((at.pos[c] - d.point[c]).abs() < 1e-12, "{edge:?} {t}");
                    assert!((at.der[c] - sign * cross[c]).abs() < 1e-11, "{edge:?} {t}");
                }
            }
        }
    }

    /// Unifying two sides of different degrees and knots keeps both curves
    /// (1e-13) and gives them one knot vector.
    #[test]
    fn unify_keeps_the_curves() {
        let a = Strip::from_side(
            &wavy(KnotVector::uniform(3, 3), KnotVector::uniform(2, 2)),
            Edge::V0,
            false,
        )
        .unwrap();
        let b = Strip::from_side(
            &wavy(KnotVector::uniform(3, 3), KnotVector::uniform(4, 3)),
            Edge::V1,
            true,
        )
        .unwrap();
        let (a2, b2) = unify(&a, &b, 5).unwrap();
        assert_eq!(a2.knots, b2.knots);
        assert_eq!(a2.degree(), 5);
        for t in [0.0, 0.1, 1.0 / 3.0, 0.5, 0.77, 1.0] {
            for (x, y) in [(a.at(t), a2.at(t)), (b.at(t), b2.at(t))] {
                for c in 0..3 {
                    assert!((x.pos[c] - y.pos[c]).abs() < 1e-13);
                    assert!((x.der[c] - y.der[c]).abs() < 1e-12);
                }
            }
        }
    }
}
