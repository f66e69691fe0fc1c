//! Clamped knot vectors and their B-spline basis (de Boor; Piegl & Tiller,
//! *The NURBS Book*, A2.1–A2.3 and A5.1).

use crate::{Error, Result};

/// Up to this many basis functions per span (degree 7) the basis
/// derivatives are computed in stack buffers.
const SMALL: usize = 8;

/// A clamped knot vector `U = (u₀ ≤ u₁ ≤ … ≤ u_{c+p})` of degree p for c
/// basis functions: the first and last knots repeated exactly p + 1 times,
/// interior knots at most p times (so every basis function is continuous),
/// nondecreasing and finite. The domain is [u_p, u_c].
#[derive(Clone, Debug, PartialEq)]
pub struct KnotVector {
    degree: usize,
    knots: Vec<f64>,
}

/// The error for a knot vector.
fn bad(why: String) -> Error {
    Error::Knots { why }
}

impl KnotVector {
    /// Checks and wraps `knots` of `degree` p ≥ 1. Errors say which rule
    /// fails and at which knot: length at least 2(p + 1), finite,
    /// nondecreasing, end multiplicity exactly p + 1, interior multiplicity
    /// at most p.
    pub fn new(degree: usize, knots: Vec<f64>) -> Result<Self> {
        let p = degree;
        if p == 0 {
            return Err(bad("the degree must be at least 1".into()));
        }
        if knots.len() < 2 * (p + 1) {
            return Err(bad(format!(
                "a clamped knot vector of degree {p} has at least {} knots (p + 1 at each end), got {}",
                2 * (p + 1),
                knots.len()
            )));
        }
        if let Some(i) = knots.iter().position(|u| !u.is_finite()) {
            return Err(bad(format!("knot {i} is not finite")));
        }
        if let Some(i) = (1..knots.len()).find(|&i| knots[i] < knots[i - 1]) {
            return Err(bad(format!(
                "knot {i} ({}) is below knot {} ({}): knots must not decrease",
                knots[i],
                i - 1,
                knots[i - 1]
            )));
        }
        let (first, last) = (knots[0], knots[knots.len() - 1]);
        let start = knots.iter().take_while(|&&u| u == first).count();
        let end = knots.iter().rev().take_while(|&&u| u == last).count();
        if first == last {
            return Err(bad(format!(
                "every knot is {first}: the domain [u_p, u_c] is empty"
            )));
        }
        for (what, m) in [("first", start), ("last", end)] {
            if m != p + 1 {
                return Err(bad(format!(
                    "the {what} knot is repeated {m} times; a clamped knot vector of degree {p} \
                     repeats it exactly {} times",
                    p + 1
                )));
            }
        }
        let mut i = start;
        while i < knots.len() - end {
            let m = knots[i..].iter().take_while(|&&u| u == knots[i]).count();
            if m > p {
                return Err(bad(format!(
                    "knot {i} ({}) is repeated {m} times; interior knots may repeat at most \
                     {p} times (the degree) or the surface tears there",
                    knots[i]
                )));
            }
            i += m;
        }
        Ok(Self { degree, knots })
    }

    /// No interior knots on [0, 1]: the Bernstein basis of degree p.
    pub fn bezier(degree: usize) -> Self {
        let mut knots = vec![0.0; degree + 1];
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        Self { degree, knots }
    }

    /// `spans` equal spans on [0, 1], interior knots simple.
    pub fn uniform(degree: usize, spans: usize) -> Self {
        let spans = spans.max(1);
        let mut knots = vec![0.0; degree + 1];
        knots.extend((1..spans).map(|k| k as f64 / spans as f64));
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        Self { degree, knots }
    }

    /// The Greville abscissae (t_{i+1} + … + t_{i+p}) / p, one per basis
    /// function: where interpolation is well posed (Schoenberg–Whitney).
    pub fn greville(&self) -> Vec<f64> {
        let p = self.degree().max(1);
        let t = self.knots();
        (0..self.count())
            .map(|i| t[i + 1..=i + p].iter().sum::<f64>() / p as f64)
            .collect()
    }

    /// The collocation matrix N_j(x_i) (row i, column j).
    pub fn collocation(&self, xs: &[f64]) -> Vec<Vec<f64>> {
        let (n, p) = (self.count(), self.degree());
        xs.iter()
            .map(|&x| {
                let mut row = vec![0.0; n];
                let span = self.span(x);
                let basis = self.basis_derivatives(span, x, 0);
                for (i, b) in basis[0].iter().enumerate().take(p + 1) {
                    row[span - p + i] = *b;
                }
                row
            })
            .collect()
    }

    /// The degree p.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knots.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The number of basis functions (control points in this direction).
    pub fn count(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// The domain [u_p, u_c].
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.count()])
    }

    /// The span k (p ≤ k < c) with u_k ≤ t < u_{k+1}; t is clamped to the
    /// domain and its right end belongs to the last span (A2.1).
    pub fn span(&self, t: f64) -> usize {
        let (p, c) = (self.degree, self.count());
        let (a, b) = self.domain();
        if t >= b {
            return c - 1;
        }
        let t = t.max(a);
        // The last k in [p, c) with u_k ≤ t.
        p + self.knots[p + 1..c].partition_point(|&u| u <= t)
    }

    /// The spans with nonzero length, in order: (k, u_k, u_{k+1}).
    pub fn spans(&self) -> Vec<(usize, f64, f64)> {
        (self.degree..self.count())
            .filter(|&k| self.knots[k] < self.knots[k + 1])
            .map(|k| (k, self.knots[k], self.knots[k + 1]))
            .collect()
    }

    /// How many times `t` occurs among the knots.
    pub fn multiplicity(&self, t: f64) -> usize {
        self.knots.iter().filter(|&&u| u == t).count()
    }

    /// `out[r][j]` = the r-th derivative of N_{k−p+j} at t, for r ≤ `order`
    /// and j = 0..=p, in span k (A2.3; derivatives above p are 0).
    pub fn basis_derivatives(&self, k: usize, t: f64, order: usize) -> Vec<Vec<f64>> {
        let w = self.degree + 1;
        let mut flat = vec![0.0; (order + 1) * w];
        self.basis_derivatives_into(k, t, order, &mut flat);
        flat.chunks_exact(w).map(<[f64]>::to_vec).collect()
    }

    /// At each parameter its span k ([`Self::span`]) and the basis
    /// functions there with their first two derivatives
    /// ([`Self::basis_derivatives`]), in one buffer.
    pub(crate) fn basis_at(&self, ts: &[f64]) -> Bases {
        let mut b = Bases::new(self.degree + 1, ts.len());
        for &t in ts {
            b.push(self, self.span(t), t);
        }
        b
    }

    /// [`Self::basis_derivatives`] written row by row into `out`
    /// (`out[r·(p+1) + j]`, at least (order + 1)(p + 1) long) without
    /// allocating for degrees below 8: the evaluation loops of meshes,
    /// Gram matrices and quadrature call it per node.
    ///
    /// On a span whose ends both have multiplicity p (a Bézier piece, as a
    /// fill's patch and most of its neighbours are) the basis functions are
    /// the Bernstein polynomials of (t − a)/(b − a): N_{k−p+i}(t) =
    /// B_i^p((t − a)/(b − a)), derivatives by (b − a)⁻ʳ: one division for
    /// the parameter (and the scaling's where b − a ≠ 1) where A2.3 takes
    /// about (p + 1)(p + 2).
    pub(crate) fn basis_derivatives_into(&self, k: usize, t: f64, order: usize, out: &mut [f64]) {
        let (p, u) = (self.degree, &self.knots);
        let w = p + 1;
        let (a, b) = (u[k], u[k + 1]);
        if p >= 1
            && b > a
            && u[k + 1 - p..k].iter().all(|&x| x == a)
            && u[k + 2..=k + p].iter().all(|&x| x == b)
        {
            let h = b - a;
            let out = &mut out[..(order + 1) * w];
            crate::basis::bernstein_derivatives_into(p, (t - a) / h, out);
            if h != 1.0 {
                for (r, row) in out.chunks_exact_mut(w).enumerate().skip(1) {
                    let f = h.powi(r as i32);
                    row.iter_mut().for_each(|x| *x /= f);
                }
            }
            return;
        }
        if w <= SMALL {
            let mut ndu = [0.0; SMALL * SMALL];
            let mut work = [0.0; 4 * SMALL];
            self.ders_with(k, t, order, out, &mut ndu, &mut work);
        } else {
            let mut ndu = vec![0.0; w * w];
            let mut work = vec![0.0; 4 * w];
            self.ders_with(k, t, order, out, &mut ndu, &mut work);
        }
    }

    /// A2.3 with the triangle `ndu` (row stride p + 1) and `work` (left,
    /// right, and the two rows of a) given.
    fn ders_with(
        &self,
        k: usize,
        t: f64,
        order: usize,
        ders: &mut [f64],
        ndu: &mut [f64],
        work: &mut [f64],
    ) {
        let p = self.degree;
        let w = p + 1;
        let u = &self.knots;
        let (left, rest) = work.split_at_mut(w);
        let (right, rest) = rest.split_at_mut(w);
        let (a0, a1) = rest.split_at_mut(w);
        let a = [a0, a1];
        // ndu[j][r]: basis functions (upper triangle) and knot differences.
        let at = |j: usize, r: usize| j * w + r;
        ndu[0] = 1.0;
        for j in 1..=p {
            left[j] = t - u[k + 1 - j];
            right[j] = u[k + j] - t;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[at(j, r)] = right[r + 1] + left[j - r];
                let temp = ndu[at(r, j - 1)] / ndu[at(j, r)];
                ndu[at(r, j)] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[at(j, j)] = saved;
        }
        ders[..(order + 1) * w].fill(0.0);
        for j in 0..=p {
            ders[j] = ndu[at(j, p)];
        }
        for r in 0..=p {
            let (mut s1, mut s2) = (0, 1);
            a[0][0] = 1.0;
            for kk in 1..=order.min(p) {
                let mut d = 0.0;
                let rk = r as isize - kk as isize;
                let pk = p - kk;
                if r >= kk {
                    a[s2][0] = a[s1][0] / ndu[at(pk + 1, r - kk)];
                    d = a[s2][0] * ndu[at(r - kk, pk)];
                }
                let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
                let j2 = if r <= pk + 1 { kk - 1 } else { p - r };
                for j in j1..=j2 {
                    let idx = (rk + j as isize) as usize;
                    a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[at(pk + 1, idx)];
                    d += a[s2][j] * ndu[at(idx, pk)];
                }
                if r <= pk {
                    a[s2][kk] = -a[s1][kk - 1] / ndu[at(pk + 1, r)];
                    d += a[s2][kk] * ndu[at(r, pk)];
                }
                ders[kk * w + r] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        let mut factor = p as f64;
        for kk in 1..=order.min(p) {
            for x in &mut ders[kk * w..(kk + 1) * w] {
                *x *= factor;
            }
            factor *= (p - kk) as f64;
        }
    }

    /// Inserts `t` once (Boehm; A5.1): the new knot vector and the new
    /// coefficients, `dim` numbers per coefficient in `coefficients` (the
    /// same spline, exactly up to rounding). Refused outside the open
    /// domain or where `t` already has multiplicity p.
    pub fn insert(
        &self,
        t: f64,
        coefficients: &[f64],
        dim: usize,
    ) -> Result<(KnotVector, Vec<f64>)> {
        let p = self.degree;
        let (a, b) = self.domain();
        if !(t > a && t < b) {
            return Err(bad(format!(
                "cannot insert {t}: knots are inserted inside the domain ({a}, {b})"
            )));
        }
        let s = self.multiplicity(t);
        if s >= p {
            return Err(bad(format!(
                "cannot insert {t}: it is already a knot of multiplicity {s}, the most a \
                 degree-{p} spline keeps continuous"
            )));
        }
        let k = self.span(t);
        let u = &self.knots;
        let c = self.count();
        let mut out = Vec::with_capacity((c + 1) * dim);
        for i in 0..=c {
            let row = |i: usize| &coefficients[i * dim..(i + 1) * dim];
            if i + p <= k {
                out.extend_from_slice(row(i));
            } else if i > k - s {
                out.extend_from_slice(row(i - 1));
            } else {
                let alpha = (t - u[i]) / (u[i + p] - u[i]);
                let (pi, pm) = (row(i), row(i - 1));
                out.extend((0..dim).map(|d| alpha * pi[d] + (1.0 - alpha) * pm[d]));
            }
        }
        let mut knots = u.clone();
        knots.insert(k + 1, t);
        Ok((KnotVector { degree: p, knots }, out))
    }

    /// The same spline one degree higher (exact up to rounding): the knot
    /// vector with every distinct knot's multiplicity raised by one, and
    /// its coefficients, `dim` numbers per coefficient. The spline is split
    /// into its Bézier pieces (the extraction operator), each piece elevated
    /// (Q_i = i/(p+1) P_{i−1} + (1 − i/(p+1)) P_i, Farin), and the elevated
    /// B-spline coefficients are the solution of the consistent system
    /// Ē Q = (elevated pieces) with Ē the elevated knot vector's extraction
    /// (least squares by refined QR; the continuity at each knot is kept, so
    /// the system has an exact solution). One piece (no interior knot) is
    /// its own elevated coefficients.
    pub fn elevate(&self, coefficients: &[f64], dim: usize) -> Result<(KnotVector, Vec<f64>)> {
        let p = self.degree;
        let c = self.count();
        assert_eq!(
            coefficients.len(),
            c * dim,
            "{c} coefficients of {dim} numbers"
        );
        // The raised knot vector.
        let mut knots = Vec::with_capacity(self.knots.len() + self.spans().len() + 1);
        for (k, &t) in self.knots.iter().enumerate() {
            knots.push(t);
            if k + 1 == self.knots.len() || self.knots[k + 1] != t {
                knots.push(t);
            }
        }
        let raised = KnotVector::new(p + 1, knots)?;
        // The Bézier pieces, degree p: rows p·s + j of E · coefficients.
        let (_, e) = self.extraction();
        let spans = (e.len() - 1) / p;
        // E · coefficients once: row r, number d at r·dim + d.
        let bez_rows: Vec<f64> = e
            .iter()
            .flat_map(|row| {
                (0..dim).map(move |d| {
                    row.iter()
                        .enumerate()
                        .map(|(k, w)| w * coefficients[k * dim + d])
                        .sum::<f64>()
                })
            })
            .collect();
        let bez = |r: usize, d: usize| bez_rows[r * dim + d];
        let pieces = (p + 1) * spans + 1;
        let mut rhs = faer::Mat::<f64>::zeros(pieces, dim);
        for s in 0..spans {
            for i in 0..=p + 1 {
                let w = i as f64 / (p + 1) as f64;
                for d in 0..dim {
                    let lo = if i > 0 { bez(p * s + i - 1, d) } else { 0.0 };
                    let hi = if i <= p { bez(p * s + i, d) } else { 0.0 };
                    rhs[((p + 1) * s + i, d)] = w * lo + (1.0 - w) * hi;
                }
            }
        }
        if spans == 1 && self.knots.len() == 2 * (p + 1) {
            // One Bézier piece (no interior knot): its elevated
            // coefficients are the raised spline's.
            let out = (0..pieces)
                .flat_map(|k| (0..dim).map(move |d| (k, d)))
                .map(|(k, d)| rhs[(k, d)])
                .collect();
            return Ok((raised, out));
        }
        let (_, e2) = raised.extraction();
        debug_assert_eq!(e2.len(), pieces);
        let c2 = raised.count();
        let a = faer::Mat::from_fn(pieces, c2, |r, k| e2[r][k]);
        let x = crate::solve::lstsq::solve_lstsq(
            &a,
            &rhs,
            3,
            1e12,
            "the raised knot vector's extraction has dependent columns",
        )?
        .x;
        let out = (0..c2)
            .flat_map(|k| (0..dim).map(move |d| (k, d)))
            .map(|(k, d)| x[(k, d)])
            .collect();
        Ok((raised, out))
    }

    /// The interior knots each raised to multiplicity p: the knot vector of
    /// the Bézier pieces, and the matrix E (rows: Bézier coefficients
    /// p·s + j of span s, columns: B-spline coefficients) with
    /// bézier = E · coefficients.
    pub(crate) fn extraction(&self) -> (KnotVector, Vec<Vec<f64>>) {
        let c = self.count();
        // The identity as c coefficients of dimension c, refined.
        let mut coeffs: Vec<f64> = (0..c * c)
            .map(|k| if k / c == k % c { 1.0 } else { 0.0 })
            .collect();
        let mut kv = self.clone();
        let interior: Vec<f64> = self.spans().iter().skip(1).map(|&(_, a, _)| a).collect();
        for t in interior {
            while kv.multiplicity(t) < self.degree {
                let (k2, c2) = kv.insert(t, &coeffs, c).expect("an interior knot below p");
                kv = k2;
                coeffs = c2;
            }
        }
        let rows = coeffs.chunks(c).map(<[f64]>::to_vec).collect();
        (kv, rows)
    }
}

/// Spans and basis functions with their first two derivatives at a list of
/// parameters, in one buffer ((p + 1) values per derivative, three
/// derivatives per parameter): what [`KnotVector::basis_at`] computes
/// once for an evaluation grid or a quadrature rule.
#[derive(Clone, Debug)]
pub(crate) struct Bases {
    width: usize,
    spans: Vec<usize>,
    values: Vec<f64>,
}

impl Bases {
    /// Room for `count` parameters of `width` = p + 1 basis functions.
    pub(crate) fn new(width: usize, count: usize) -> Self {
        Self {
            width,
            spans: Vec::with_capacity(count),
            values: Vec::with_capacity(3 * width * count),
        }
    }

    /// Appends the span `k` and the basis functions of `knots` at t.
    pub(crate) fn push(&mut self, knots: &KnotVector, k: usize, t: f64) {
        let start = self.values.len();
        self.values.resize(start + 3 * self.width, 0.0);
        knots.basis_derivatives_into(k, t, 2, &mut self.values[start..]);
        self.spans.push(k);
    }

    /// All of them.
    pub(crate) fn view(&self) -> BasesView<'_> {
        BasesView {
            width: self.width,
            spans: &self.spans,
            values: &self.values,
        }
    }

    /// The number of parameters.
    pub(crate) fn len(&self) -> usize {
        self.spans.len()
    }

    /// The span and the rows N, N′, N″ at parameter `i`.
    pub(crate) fn at(&self, i: usize) -> (usize, [&[f64]; 3]) {
        self.view().at(i)
    }
}

/// Some consecutive parameters of a [`Bases`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct BasesView<'a> {
    width: usize,
    spans: &'a [usize],
    values: &'a [f64],
}

impl<'a> BasesView<'a> {
    /// The number of parameters.
    pub(crate) fn len(&self) -> usize {
        self.spans.len()
    }

    /// The spans.
    pub(crate) fn spans(&self) -> &'a [usize] {
        self.spans
    }

    /// Parameters `start .. start + len`.
    pub(crate) fn sub(&self, start: usize, len: usize) -> Self {
        let w3 = 3 * self.width;
        Self {
            width: self.width,
            spans: &self.spans[start..start + len],
            values: &self.values[start * w3..(start + len) * w3],
        }
    }

    /// The span and the rows N, N′, N″ at parameter `i`.
    pub(crate) fn at(&self, i: usize) -> (usize, [&'a [f64]; 3]) {
        let w = self.width;
        let v = &self.values[3 * w * i..3 * w * (i + 1)];
        (self.spans[i], [&v[..w], &v[w..2 * w], &v[2 * w..]])
    }
}
