//! Tensor-product B-spline surfaces `R(u, v) = Σ N_i^p(u) N_j^q(v) P_ij`:
//! evaluation and derivatives (de Boor), knot insertion, and the Bézier
//! patches they consist of.

use super::{BasesView, KnotVector};
use crate::vec3::{is_finite, Vec3};
use crate::{Error, Result, SurfaceDerivatives, TensorPatch};

/// A tensor-product B-spline surface: clamped knot vectors in u and v and
/// a net of `count_u × count_v` control points, row i with u (as
/// [`TensorPatch`]). A Bézier patch is the case without interior knots.
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineSurface {
    u: KnotVector,
    v: KnotVector,
    points: Vec<Vec3>,
}

/// One Bézier piece of a B-spline surface: its parameter rectangle and the
/// patch over it (in local parameters s = (u − u0)/(u1 − u0), t likewise).
#[derive(Clone, Debug, PartialEq)]
pub struct BezierPiece {
    /// [u0, u1].
    pub u: (f64, f64),
    /// [v0, v1].
    pub v: (f64, f64),
    /// The patch over the rectangle.
    pub patch: TensorPatch,
}

impl crate::surface::ControlNet for BSplineSurface {
    fn counts(&self) -> (usize, usize) {
        BSplineSurface::counts(self)
    }

    fn points(&self) -> &[Vec3] {
        &self.points
    }

    fn points_mut(&mut self) -> &mut [Vec3] {
        &mut self.points
    }
}

impl BSplineSurface {
    /// The surface with knot vectors `u`, `v` and `points` (row-major,
    /// `u.count() × v.count()`); errors name a wrong count or a point that
    /// is not finite.
    pub fn new(u: KnotVector, v: KnotVector, points: Vec<Vec3>) -> Result<Self> {
        let (cu, cv) = (u.count(), v.count());
        if points.len() != cu * cv {
            return Err(Error::Mismatch {
                what: "B-spline control points".into(),
                expected: format!("{cu} × {cv} = {} (the knot vectors' counts)", cu * cv),
                got: points.len().to_string(),
            });
        }
        if let Some(k) = points.iter().position(|p| !is_finite(*p)) {
            return Err(Error::NotFinite {
                what: format!("control point ({}, {})", k / cv, k % cv),
            });
        }
        Ok(Self { u, v, points })
    }

    /// The Bézier patch as a B-spline without interior knots.
    pub fn from_bezier(patch: &TensorPatch) -> Self {
        let (n, m) = patch.degree();
        Self {
            u: KnotVector::bezier(n),
            v: KnotVector::bezier(m),
            points: patch.points().to_vec(),
        }
    }

    /// The knot vectors (u, v).
    pub fn knots(&self) -> (&KnotVector, &KnotVector) {
        (&self.u, &self.v)
    }

    /// The degrees (p, q).
    pub fn degree(&self) -> (usize, usize) {
        (self.u.degree(), self.v.degree())
    }

    /// Control points in u and in v.
    pub fn counts(&self) -> (usize, usize) {
        (self.u.count(), self.v.count())
    }

    /// The control points, row-major.
    pub fn points(&self) -> &[Vec3] {
        &self.points
    }

    /// P_ij.
    pub fn point(&self, i: usize, j: usize) -> Vec3 {
        self.points[i * self.v.count() + j]
    }

    /// The same surface with other control points (same count).
    pub(crate) fn with_points(&self, points: Vec<Vec3>) -> Self {
        debug_assert_eq!(points.len(), self.points.len());
        Self {
            points,
            ..self.clone()
        }
    }

    /// R(u, v).
    pub fn eval(&self, u: f64, v: f64) -> Vec3 {
        self.partials(u, v, 0)[0][0]
    }

    /// R and its first and second partial derivatives at (u, v).
    pub fn derivatives(&self, u: f64, v: f64) -> SurfaceDerivatives {
        let d = self.partials(u, v, 2);
        SurfaceDerivatives {
            point: d[0][0],
            du: d[1][0],
            dv: d[0][1],
            duu: d[2][0],
            duv: d[1][1],
            dvv: d[0][2],
        }
    }

    /// The unit normal R_u × R_v / |R_u × R_v|, `None` where not regular.
    pub fn normal(&self, u: f64, v: f64) -> Option<Vec3> {
        self.derivatives(u, v).normal()
    }

    /// R and its first and second derivatives on the grid `us` × `vs`
    /// (u-major: entry i·|vs| + j at (`us[i]`, `vs[j]`)): each direction's
    /// basis functions computed once per parameter, no allocation per point.
    pub fn derivatives_on(&self, us: &[f64], vs: &[f64]) -> Vec<SurfaceDerivatives> {
        self.derivatives_from(self.u.basis_at(us).view(), self.v.basis_at(vs).view())
    }

    /// [`derivatives_on`](Self::derivatives_on) from each direction's
    /// spans and basis functions at the parameters
    /// ([`KnotVector::basis_at`]): computed once, they serve every surface
    /// on these knots (a descent's candidates).
    pub(crate) fn derivatives_from(&self, bu: BasesView, bv: BasesView) -> Vec<SurfaceDerivatives> {
        let (p, q) = self.degree();
        let cv = self.v.count();
        // Two stages: per u, the columns' partial sums
        // T_r[c] = Σ_i N_i^(r)(u) P_{ku−p+i, c} over the columns the v's
        // need; per (u, v), Σ_j N_j^(s)(v) T_r[kv−q+j] — (q+1)·6 products
        // per point instead of (p+1)(q+1)·6.
        let Some(first) = bv.spans().first().map(|k| k - q) else {
            return Vec::new();
        };
        let (c0, c1) = bv
            .spans()
            .iter()
            .fold((first, 0), |(a, b), kv| (a.min(kv - q), b.max(*kv)));
        let width = c1 + 1 - c0;
        let mut t = vec![[0.0f64; 3]; 3 * width];
        let mut out = Vec::with_capacity(bu.len() * bv.len());
        for (ku, nu) in (0..bu.len()).map(|i| bu.at(i)) {
            t.fill([0.0; 3]);
            for i in 0..=p {
                let row = &self.points[(ku - p + i) * cv + c0..][..width];
                for (r, tr) in t.chunks_exact_mut(width).enumerate() {
                    let w = nu[r][i];
                    for (tc, pt) in tr.iter_mut().zip(row) {
                        tc[0] += w * pt[0];
                        tc[1] += w * pt[1];
                        tc[2] += w * pt[2];
                    }
                }
            }
            let (t0, rest) = t.split_at(width);
            let (t1, t2) = rest.split_at(width);
            for (kv, nv) in (0..bv.len()).map(|j| bv.at(j)) {
                let off = kv - q - c0;
                let mut d = [[0.0f64; 3]; 6];
                for j in 0..=q {
                    let (a, b, c) = (t0[off + j], t1[off + j], t2[off + j]);
                    let (n0, n1, n2) = (nv[0][j], nv[1][j], nv[2][j]);
                    for k in 0..3 {
                        d[0][k] += n0 * a[k];
                        d[1][k] += n0 * b[k];
                        d[2][k] += n1 * a[k];
                        d[3][k] += n0 * c[k];
                        d[4][k] += n1 * b[k];
                        d[5][k] += n2 * a[k];
                    }
                }
                out.push(SurfaceDerivatives {
                    point: d[0],
                    du: d[1],
                    dv: d[2],
                    duu: d[3],
                    duv: d[4],
                    dvv: d[5],
                });
            }
        }
        out
    }

    /// R, R_u and R_v on the grid `us` × `vs` (u-major, as
    /// [`derivatives_on`](Self::derivatives_on)), for lines of constant u
    /// or v (the sides of a fill, compared with its neighbours): the net is
    /// first summed along the direction with fewer parameters (per such
    /// parameter, the rows' or columns' values and first derivatives), then
    /// each point takes 3(p + 1) products of those sums.
    pub(crate) fn tangents_on(&self, us: &[f64], vs: &[f64]) -> Vec<[Vec3; 3]> {
        let (p, q) = self.degree();
        let (cu, cv) = self.counts();
        let (nu, nv) = (us.len(), vs.len());
        let mut out = vec![[[0.0; 3]; 3]; nu * nv];
        // Summed first along u when there are fewer u's (the roles of the
        // directions swap: "few" is the summed one, "many" the other).
        let few_u = nu < nv;
        let (few, many) = if few_u { (us, vs) } else { (vs, us) };
        let (kf, km) = if few_u {
            (&self.u, &self.v)
        } else {
            (&self.v, &self.u)
        };
        let (df, dm) = if few_u { (p, q) } else { (q, p) };
        let lines = if few_u { cv } else { cu };
        let point = |fi: usize, mi: usize| {
            if few_u {
                self.points[fi * cv + mi]
            } else {
                self.points[mi * cv + fi]
            }
        };
        let mut bf = vec![0.0; 2 * (df + 1)];
        let mut bm = vec![0.0; 2 * (dm + 1)];
        let (mut s0, mut s1) = (vec![[0.0; 3]; lines], vec![[0.0; 3]; lines]);
        for (a, &t) in few.iter().enumerate() {
            let k = kf.span(t);
            kf.basis_derivatives_into(k, t, 1, &mut bf);
            // s_r[m] = Σ_i N_i^(r)(t) P along the few direction, per line m.
            for m in 0..lines {
                let (mut x0, mut x1) = ([0.0; 3], [0.0; 3]);
                for i in 0..=df {
                    let pt = point(k - df + i, m);
                    let (n0, n1) = (bf[i], bf[df + 1 + i]);
                    for c in 0..3 {
                        x0[c] += n0 * pt[c];
                        x1[c] += n1 * pt[c];
                    }
                }
                (s0[m], s1[m]) = (x0, x1);
            }
            for (b, &t) in many.iter().enumerate() {
                let k = km.span(t);
                km.basis_derivatives_into(k, t, 1, &mut bm);
                let (mut r, mut dmany, mut dfew) = ([0.0; 3], [0.0; 3], [0.0; 3]);
                for j in 0..=dm {
                    let (x0, x1) = (s0[k - dm + j], s1[k - dm + j]);
                    let (n0, n1) = (bm[j], bm[dm + 1 + j]);
                    for c in 0..3 {
                        r[c] += n0 * x0[c];
                        dmany[c] += n1 * x0[c];
                        dfew[c] += n0 * x1[c];
                    }
                }
                let (at, du, dv) = if few_u {
                    (b + a * nv, dfew, dmany)
                } else {
                    (a + b * nv, dmany, dfew)
                };
                out[at] = [r, du, dv];
            }
        }
        out
    }

    /// `out[r][s]` = ∂^(r+s)R/∂u^r∂v^s for r + s ≤ `order` ≤ 2 (A3.6; the
    /// others 0), without allocating for degrees below 8.
    fn partials(&self, u: f64, v: f64, order: usize) -> [[Vec3; 3]; 3] {
        debug_assert!(order <= 2, "partials of order {order} > 2");
        let (p, q) = self.degree();
        let (ku, kv) = (self.u.span(u), self.v.span(v));
        let (wu, wv) = (p + 1, q + 1);
        let mut small = [0.0; 2 * 3 * 8];
        let mut large = Vec::new();
        let (nu, nv) = if wu.max(wv) <= 8 {
            small.split_at_mut(3 * 8)
        } else {
            large.resize(3 * (wu + wv), 0.0);
            large.split_at_mut(3 * wu)
        };
        self.u.basis_derivatives_into(ku, u, order, nu);
        self.v.basis_derivatives_into(kv, v, order, nv);
        let cv = self.v.count();
        let mut out = [[[0.0; 3]; 3]; 3];
        let mut small_cols = [[0.0; 3]; 8];
        let mut large_cols = Vec::new();
        let cols: &mut [Vec3] = if wv <= 8 {
            &mut small_cols[..wv]
        } else {
            large_cols.resize(wv, [0.0; 3]);
            &mut large_cols
        };
        for (r, row) in out.iter_mut().enumerate().take(order + 1) {
            let nur = &nu[r * wu..(r + 1) * wu];
            // cols[j] = Σ_i N_i^(r)(u) P_{ku−p+i, kv−q+j}
            for (j, col) in cols.iter_mut().enumerate() {
                *col = nur.iter().enumerate().fold([0.0; 3], |acc, (i, &a)| {
                    let pt = self.points[(ku - p + i) * cv + kv - q + j];
                    [acc[0] + a * pt[0], acc[1] + a * pt[1], acc[2] + a * pt[2]]
                });
            }
            for (s, o) in row.iter_mut().enumerate().take(order + 1 - r) {
                let nvs = &nv[s * wv..(s + 1) * wv];
                *o = cols.iter().zip(nvs).fold([0.0; 3], |acc, (c, &b)| {
                    [acc[0] + b * c[0], acc[1] + b * c[1], acc[2] + b * c[2]]
                });
            }
        }
        out
    }

    /// The same surface with `t` inserted into the u-knots (one more row
    /// of control points).
    pub fn insert_knot_u(&self, t: f64) -> Result<Self> {
        let (cu, cv) = self.counts();
        // Columns as coefficients of dimension 3·cv (row i is coefficient i).
        let flat: Vec<f64> = self.points.iter().flatten().copied().collect();
        let (u, out) = self.u.insert(t, &flat, 3 * cv)?;
        debug_assert_eq!(out.len(), (cu + 1) * cv * 3);
        Ok(Self {
            u,
            v: self.v.clone(),
            points: out.chunks(3).map(|c| [c[0], c[1], c[2]]).collect(),
        })
    }

    /// The same surface one degree higher in u (degree elevation: every
    /// distinct u-knot's multiplicity rises by one, so the continuity at
    /// each knot is kept; [`KnotVector::elevate`]).
    pub fn elevate_u(&self) -> Result<Self> {
        let cv = self.counts().1;
        let flat: Vec<f64> = self.points.iter().flatten().copied().collect();
        let (u, out) = self.u.elevate(&flat, 3 * cv)?;
        Ok(Self {
            u,
            v: self.v.clone(),
            points: out.chunks(3).map(|c| [c[0], c[1], c[2]]).collect(),
        })
    }

    /// The same surface one degree higher in v.
    pub fn elevate_v(&self) -> Result<Self> {
        Ok(self.transposed().elevate_u()?.transposed())
    }

    /// The same surface with its degrees raised by `a` in u and `b` in v.
    pub fn elevated(&self, a: usize, b: usize) -> Result<Self> {
        let mut s = self.clone();
        for _ in 0..a {
            s = s.elevate_u()?;
        }
        for _ in 0..b {
            s = s.elevate_v()?;
        }
        Ok(s)
    }

    /// The same surface with `t` inserted into the v-knots.
    pub fn insert_knot_v(&self, t: f64) -> Result<Self> {
        Ok(self.transposed().insert_knot_u(t)?.transposed())
    }

    /// The surface cut at u = t (inside the domain) into the parts over
    /// [u_min, t] and [t, u_max], each clamped: t inserted up to
    /// multiplicity p (exact), the rows split there.
    pub fn split_u(&self, t: f64) -> Result<(Self, Self)> {
        let p = self.u.degree();
        let (a, b) = self.u.domain();
        if !(t > a && t < b) {
            return Err(Error::Knots {
                why: format!("cannot split at {t}: outside the open domain ({a}, {b})"),
            });
        }
        let mut s = self.clone();
        while s.u.multiplicity(t) < p {
            s = s.insert_knot_u(t)?;
        }
        let k = s.u.knots();
        let r = k.iter().position(|&x| x == t).expect("t was inserted");
        let cv = s.v.count();
        let mut left = k[..r + p].to_vec();
        left.push(t);
        let mut right = vec![t];
        right.extend_from_slice(&k[r..]);
        let lu = KnotVector::new(p, left)?;
        let ru = KnotVector::new(p, right)?;
        let (nl, nr) = (lu.count(), ru.count());
        let lp = s.points[..nl * cv].to_vec();
        let rp = s.points[(s.u.count() - nr) * cv..].to_vec();
        Ok((
            Self::new(lu, s.v.clone(), lp)?,
            Self::new(ru, s.v.clone(), rp)?,
        ))
    }

    /// The part over u ∈ [a, b] of the domain, cut exactly
    /// ([`split_u`](Self::split_u) at an end inside the domain; an end at
    /// or beyond the domain's is left as it is).
    pub fn restricted_u(&self, a: f64, b: f64) -> Result<Self> {
        let (lo, hi) = self.u.domain();
        let mut s = self.clone();
        if a > lo {
            s = s.split_u(a)?.1;
        }
        if b < hi {
            s = s.split_u(b)?.0;
        }
        Ok(s)
    }

    /// [`restricted_u`](Self::restricted_u) in v.
    pub fn restricted_v(&self, a: f64, b: f64) -> Result<Self> {
        Ok(self.transposed().restricted_u(a, b)?.transposed())
    }

    /// The surface cut at v = t ([`BSplineSurface::split_u`] in v).
    pub fn split_v(&self, t: f64) -> Result<(Self, Self)> {
        let (a, b) = self.transposed().split_u(t)?;
        Ok((a.transposed(), b.transposed()))
    }

    /// Checks that `other` lies over this surface's knot domain (to 1e-12
    /// of its size); the error ([`Error::Mismatch`]) names it as `what`.
    pub fn check_domain(&self, other: &BSplineSurface, what: &str) -> Result<()> {
        let (a, b) = (self.knots(), other.knots());
        let same = |x: (f64, f64), y: (f64, f64)| {
            let tol = 1e-12 * (x.1 - x.0).abs().max(1.0);
            (x.0 - y.0).abs() <= tol && (x.1 - y.1).abs() <= tol
        };
        if same(a.0.domain(), b.0.domain()) && same(a.1.domain(), b.1.domain()) {
            return Ok(());
        }
        Err(Error::Mismatch {
            what: what.into(),
            expected: format!(
                "the surface's domain {:?} × {:?}",
                a.0.domain(),
                a.1.domain()
            ),
            got: format!("{:?} × {:?}", b.0.domain(), b.1.domain()),
        })
    }

    /// u and v exchanged.
    pub fn transposed(&self) -> Self {
        let (cu, cv) = self.counts();
        Self {
            u: self.v.clone(),
            v: self.u.clone(),
            points: (0..cv)
                .flat_map(|j| (0..cu).map(move |i| (i, j)))
                .map(|(i, j)| self.points[i * cv + j])
                .collect(),
        }
    }

    /// The same surface with every knot of `us` inserted in u and of `vs`
    /// in v (knot refinement).
    pub fn refined(&self, us: &[f64], vs: &[f64]) -> Result<Self> {
        let mut s = self.clone();
        for &t in us {
            s = s.insert_knot_u(t)?;
        }
        for &t in vs {
            s = s.insert_knot_v(t)?;
        }
        Ok(s)
    }

    /// The Bézier patches the surface consists of, span by span, u-major
    /// (interior knots raised to multiplicity p, resp. q).
    pub fn bezier_pieces(&self) -> Vec<BezierPiece> {
        let (p, q) = self.degree();
        let (eu, ev) = (self.u.extraction().1, self.v.extraction().1);
        let (su, sv) = (self.u.spans(), self.v.spans());
        let mut out = Vec::with_capacity(su.len() * sv.len());
        for (a, &(ku, u0, u1)) in su.iter().enumerate() {
            for (b, &(kv, v0, v1)) in sv.iter().enumerate() {
                // Span (ku, kv)'s pieces depend on P_kl, ku − p ≤ k ≤ ku,
                // kv − q ≤ l ≤ kv only.
                let patch = TensorPatch::from_fn(p, q, |i, j| {
                    let (ru, rv) = (&eu[a * p + i], &ev[b * q + j]);
                    let mut acc = [0.0; 3];
                    for k in ku - p..=ku {
                        for l in kv - q..=kv {
                            let (pt, w) = (self.point(k, l), ru[k] * rv[l]);
                            acc = [acc[0] + w * pt[0], acc[1] + w * pt[1], acc[2] + w * pt[2]];
                        }
                    }
                    acc
                });
                out.push(BezierPiece {
                    u: (u0, u1),
                    v: (v0, v1),
                    patch,
                });
            }
        }
        out
    }
}

impl BSplineSurface {
    /// The area: the sum of the Bézier pieces' areas (adaptive
    /// Gauss–Legendre, [`crate::analysis::area`]; area does not depend on
    /// the parameterization).
    pub fn area(&self) -> f64 {
        self.bezier_pieces()
            .iter()
            .map(|p| crate::analysis::area(&p.patch).value)
            .sum()
    }

    /// The largest turn of the unit normal between neighbouring samples of
    /// a (k + 1) × (k + 1) grid on every Bézier piece, k = 64 / (the larger
    /// number of spans), at least 4 (a single span is sampled as a Bézier
    /// patch's measures sample it, 65 × 65), with `at` in the surface's
    /// parameters (see [`crate::analysis::largest_normal_turn`]).
    pub fn largest_normal_turn(&self) -> Option<crate::analysis::NormalTurn> {
        let spans = self.u.spans().len().max(self.v.spans().len()).max(1);
        self.largest_normal_turn_by((crate::analysis::CURVATURE_GRID / spans).max(4))
    }

    /// [`Self::largest_normal_turn`] on a (k + 1) × (k + 1) grid on every
    /// Bézier piece.
    pub fn largest_normal_turn_by(&self, k: usize) -> Option<crate::analysis::NormalTurn> {
        self.bezier_pieces()
            .iter()
            .filter_map(|p| {
                crate::analysis::largest_normal_turn(&p.patch, k).map(|t| {
                    let (s, r) = t.at;
                    crate::analysis::NormalTurn {
                        angle: t.angle,
                        at: (p.u.0 + s * (p.u.1 - p.u.0), p.v.0 + r * (p.v.1 - p.v.0)),
                    }
                })
            })
            .max_by(|a, b| a.angle.total_cmp(&b.angle))
    }

    /// Area (with its error estimate), both functionals and the |H|
    /// statistics, as [`crate::analysis::measures`] gives them for a Bézier
    /// patch: the area summed over the Bézier pieces (adaptive
    /// Gauss–Legendre on each), the Dirichlet and thin-plate functionals
    /// exact over the knot domain, |H| on the 65 × 65 uniform grid of the
    /// domain, and the normal turn of [`Self::largest_normal_turn`]. A
    /// surface without interior knots over [0, 1]² gives its Bézier patch's
    /// measures.
    pub fn measures(&self) -> crate::analysis::SurfaceMeasures {
        let pieces = self.bezier_pieces();
        let (mut area, mut area_error) = (0.0, 0.0);
        for p in &pieces {
            let a = crate::analysis::area(&p.patch);
            area += a.value;
            area_error += a.error;
        }
        let degree = self.degree();
        let part = |stretch, bend| {
            super::energy::energy_by_pieces(
                &pieces,
                degree,
                &super::energy::patterns(stretch, bend),
            )
        };
        crate::analysis::SurfaceMeasures {
            area,
            area_error,
            dirichlet: part(1.0, 0.0),
            biharmonic: part(0.0, 1.0),
            abs_mean_curvature: crate::analysis::abs_mean_curvature(
                self,
                crate::analysis::CURVATURE_GRID,
            ),
            normal_turn: self.largest_normal_turn(),
        }
    }
}
