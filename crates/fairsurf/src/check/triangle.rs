//! The energy of a triangular problem and its gradient at a written net, in
//! double-double and by quadrature: independent of the solve, which
//! assembles the closed-form triangular Gram matrices in double precision.
//!
//! The internal energy (Veltkamp & Wesselink eq. 6–7 over the equilateral
//! domain of eq. 25) is a weighted sum of squared difference nets,
//! E = ½ Σ (w/9)·(n!/(n−r)!)²·∫_Δ (D P)² dA ([`crate::triangle::InternalEnergy`]).
//! Each difference net D P is a degree-m polynomial on the triangle,
//! integrated here by the collapsed (Duffy) Gauss rule: with
//! u = s, v = (1 − s) t, w = (1 − s)(1 − t),
//!
//! ```text
//! B^m_{ijk}(u, v, w) = B^m_i(s) · B^{m−i}_j(t),    dA = 2A (1 − s) ds dt,
//! ```
//!
//! so a square has degree 2m + 1 in s and 2m in t, and m + 1 Gauss nodes in
//! each direction integrate it exactly. The difference nets are
//! differences of doubles (exact in double-double) and the Bernstein values
//! come from the positive recurrence, so nothing cancels beyond what the
//! integrand itself does. The gradient is the adjoint of the same maps.

use super::dd::Dd;
use super::nodes::{add_products, Nodes, Table};
use crate::operator::Residual;
use crate::solve::compensated::with_fma;
use crate::solve::kkt::KktFactor;
use crate::triangle::energy::{bend_stencils, falling, stretch_stencils, Stencil};
use crate::triangle::{linear_index, point_count, InternalEnergy, TriSurface};
use crate::Result;
use std::cell::RefCell;
use std::sync::Arc;

/// The internal and external energies and ∂E/∂x over the flattened
/// coordinates 3g + c of the global control points.
pub(crate) struct TriEnergyAt {
    /// α·stretch.
    pub stretch: Dd,
    /// β·bend.
    pub bend: Dd,
    /// The operators' terms.
    pub external: Dd,
    pub total: Dd,
    pub gradient: Vec<Dd>,
}

/// The collapsed Gauss rule exact for the square of a degree-m polynomial
/// on the triangle, with the Bernstein values at its nodes.
struct Rule {
    m: usize,
    /// B^m_i(s_a): rows a, columns i.
    s: Table,
    /// For each i = 0…m, B^{m−i}_j(t_b): rows b, columns j.
    t: Vec<Table>,
    /// 2A (1 − s_a) W_a W_b at node (a, b), row-major in a.
    omega: Vec<Dd>,
}

impl Rule {
    fn new(m: usize) -> Self {
        let nodes = Nodes::gauss(m + 1);
        // 2A = √3/2, the Jacobian of the reference triangle to the
        // equilateral one of side 1.
        let two_area = Dd::new(3.0).sqrt() * 0.5;
        let omega = nodes
            .t
            .iter()
            .zip(&nodes.w)
            .flat_map(|(&s, &ws)| {
                let outer = two_area * (Dd::new(1.0) - s) * ws;
                nodes.w.iter().map(move |&wt| outer * wt)
            })
            .collect();
        Self {
            m,
            s: (*nodes.bernstein(m, false)).clone(),
            t: (0..=m)
                .map(|i| (*nodes.bernstein(m - i, false)).clone())
                .collect(),
            omega,
        }
    }

    fn nodes(&self) -> usize {
        self.s.rows
    }

    /// The degree-m net `d` (storage order) at every node (a, b).
    fn eval(&self, d: &[Dd]) -> Vec<Dd> {
        let q = self.nodes();
        // inner[i][b] = Σ_j d_{i,j,m−i−j} B^{m−i}_j(t_b)
        let mut inner = Table::zeros(self.m + 1, q);
        for i in 0..=self.m {
            for j in 0..=self.m - i {
                let c = d[linear_index(self.m, i, j, self.m - i - j)];
                if c.hi == 0.0 {
                    continue;
                }
                for b in 0..q {
                    inner.v[i * q + b] += c * self.t[i].at(b, j);
                }
            }
        }
        self.s.mul(&inner).v
    }

    /// The adjoint of [`Rule::eval`]: ∂/∂d of Σ_ab y_ab f_ab.
    fn adjoint(&self, y: &[Dd]) -> Vec<Dd> {
        let q = self.nodes();
        let y = Table {
            rows: q,
            cols: q,
            v: y.to_vec(),
        };
        let h = self.s.transpose().mul(&y); // (m+1) × q
        let mut out = vec![Dd::new(0.0); point_count(self.m)];
        for i in 0..=self.m {
            for j in 0..=self.m - i {
                let mut acc = Dd::new(0.0);
                for b in 0..q {
                    acc += h.at(i, b) * self.t[i].at(b, j);
                }
                out[linear_index(self.m, i, j, self.m - i - j)] = acc;
            }
        }
        out
    }
}

/// One weighted set of stencils (stretch or bend) of a degree-n surface.
struct Form {
    /// The energy weight times (n!/(n−r)!)², and per stencil its w/9.
    scale: Dd,
    stencils: Vec<(Dd, Stencil, Vec<Vec<usize>>)>,
    rule: Rule,
}

impl Form {
    /// None when the weight is 0 or the degree is below the order.
    fn new(weight: f64, n: usize, stencils: Vec<(u32, Stencil)>) -> Option<Self> {
        let order = stencils.first()?.1.order;
        if weight == 0.0 || n < order {
            return None;
        }
        let f = falling(n, order);
        Some(Self {
            scale: Dd::new(weight) * f * f,
            stencils: stencils
                .into_iter()
                .map(|(w, st)| {
                    let pos = st.positions(n);
                    (Dd::new(f64::from(w)) / Dd::new(9.0), st, pos)
                })
                .collect(),
            rule: Rule::new(n - order),
        })
    }

    /// ∂/∂p of ½ Σ_stencils scale·(w/9)·∫(D p)² for one coordinate's
    /// local net p: the column K p of the form's matrix.
    fn gradient(&self, p: &[Dd]) -> Vec<Dd> {
        let mut out = vec![Dd::new(0.0); p.len()];
        for (w, st, pos) in &self.stencils {
            let k = self.scale * *w;
            let d: Vec<Dd> = (0..pos[0].len())
                .map(|l| {
                    st.terms
                        .iter()
                        .zip(pos)
                        .fold(Dd::new(0.0), |acc, (t, q)| acc + p[q[l]] * t.1)
                })
                .collect();
            let mut f = self.rule.eval(&d);
            for (v, &o) in f.iter_mut().zip(&self.rule.omega) {
                *v = o * *v * k;
            }
            let gd = self.rule.adjoint(&f);
            for (t, q) in st.terms.iter().zip(pos) {
                for (l, g) in gd.iter().enumerate() {
                    out[q[l]] += *g * t.1;
                }
            }
        }
        out
    }

    /// The form's matrix K of a degree-n patch (both halves), column by
    /// column from unit nets, by the quadrature above: E = ½ pᵀ K p per
    /// coordinate.
    fn matrix(&self, n: usize) -> Vec<Dd> {
        let size = point_count(n);
        let mut k = Vec::with_capacity(size * size);
        let mut unit = vec![Dd::new(0.0); size];
        for j in 0..size {
            unit[j] = Dd::new(1.0);
            k.extend(self.gradient(&unit));
            unit[j] = Dd::new(0.0);
        }
        k
    }
}

/// ½ Σ_c p_cᵀ K p_c over every patch for each matrix K of `ks` (one
/// patch's matrix in double-double, column-major, size × size), and the sum
/// of their gradients. Each patch's net is taken relative to its first
/// control point (exact in double-double; K annihilates constants), so
/// far-off surfaces lose nothing to the position; the net is made once per
/// patch and coordinate for all the matrices. The products K p are
/// compensated sums (each product's and each addition's rounding error
/// gathered in a second double, as [`super::nodes::Table`]'s products),
/// with fused multiply-adds where the CPU has them.
fn quadratics(ks: &[&[Dd]], surface: &TriSurface, x: &[Dd], gradient: &mut [Dd]) -> Vec<Dd> {
    // One of the two runs: both may hold the gradient.
    let gradient = std::cell::RefCell::new(gradient);
    with_fma(
        #[inline(always)]
        || quadratics_with::<true>(ks, surface, x, &mut gradient.borrow_mut()),
        || quadratics_with::<false>(ks, surface, x, &mut gradient.borrow_mut()),
    )
}

#[inline(always)]
fn quadratics_with<const FMA: bool>(
    ks: &[&[Dd]],
    surface: &TriSurface,
    x: &[Dd],
    gradient: &mut [Dd],
) -> Vec<Dd> {
    let size = point_count(surface.degree());
    let mut e = vec![Dd::new(0.0); ks.len()];
    let mut p = vec![Dd::new(0.0); size];
    let (mut s, mut c) = (vec![0.0; size], vec![0.0; size]);
    for t in 0..surface.patch_count() {
        let map = surface.patch_indices(t);
        for coord in 0..3 {
            let origin = x[3 * map[0] + coord];
            for (pl, &g) in p.iter_mut().zip(map) {
                *pl = x[3 * g + coord] - origin;
            }
            for (k, ek) in ks.iter().zip(e.iter_mut()) {
                s.iter_mut().for_each(|v| *v = 0.0);
                c.iter_mut().for_each(|v| *v = 0.0);
                for (j, &pj) in p.iter().enumerate() {
                    if pj.hi == 0.0 {
                        continue;
                    }
                    add_products::<FMA>(&mut s, &mut c, pj, &k[j * size..(j + 1) * size]);
                }
                for ((&g, &pl), (&si, &ci)) in map.iter().zip(&p).zip(s.iter().zip(&c)) {
                    let yl = Dd::new(si) + ci;
                    *ek += pl * yl * 0.5;
                    gradient[3 * g + coord] += yl;
                }
            }
        }
    }
    e
}

/// A form matrix's key: the weight's bits, the degree, bend or stretch.
type FormKey = (u64, usize, bool);

/// The most form matrices [`form_matrix`] keeps per thread.
const KEPT_FORMS: usize = 8;

thread_local! {
    /// Form matrices by (weight's bits, degree, bend or stretch), latest
    /// last: a fill solves the same energy at one degree many times.
    static FORMS: RefCell<Vec<(FormKey, Arc<Vec<Dd>>)>> =
        const { RefCell::new(Vec::new()) };
}

/// [`Form::matrix`] of the thin plate (`bend`) or the membrane at
/// `weight` and degree n, kept per thread (it depends on nothing else,
/// and a degree-12 patch's takes ~1 ms in double-double); None as
/// [`Form::new`].
fn form_matrix(weight: f64, n: usize, bend: bool) -> Option<Arc<Vec<Dd>>> {
    let key = (weight.to_bits(), n, bend);
    if let Some(k) = FORMS.with_borrow(|f| f.iter().find(|e| e.0 == key).map(|e| e.1.clone())) {
        return Some(k);
    }
    let stencils = if bend {
        bend_stencils()
    } else {
        stretch_stencils()
    };
    let k = Arc::new(Form::new(weight, n, stencils)?.matrix(n));
    FORMS.with_borrow_mut(|f| {
        if f.len() == KEPT_FORMS {
            f.remove(0);
        }
        f.push((key, k.clone()));
    });
    Some(k)
}

/// E and ∂E/∂x of a triangular problem at `surface`'s control points: the
/// internal energy and the operators (each a strength, whether it repels,
/// and its residuals over the flattened coordinates).
pub(crate) struct TriEnergy<'a> {
    stretch: Option<Arc<Vec<Dd>>>,
    bend: Option<Arc<Vec<Dd>>>,
    operators: Vec<(f64, bool, &'a [Residual])>,
}

impl<'a> TriEnergy<'a> {
    /// The patch matrices of a degree-n surface's energy, by quadrature.
    pub fn new(
        energy: &InternalEnergy,
        n: usize,
        operators: Vec<(f64, bool, &'a [Residual])>,
    ) -> Self {
        Self {
            stretch: form_matrix(energy.stretch, n, false),
            bend: form_matrix(energy.bend, n, true),
            operators,
        }
    }

    /// E and ∂E/∂x at `surface`'s control points.
    pub fn at(&self, surface: &TriSurface) -> TriEnergyAt {
        let x: Vec<Dd> = surface
            .points()
            .iter()
            .flatten()
            .map(|&v| Dd::new(v))
            .collect();
        let mut gradient = vec![Dd::new(0.0); x.len()];
        let ks: Vec<&[Dd]> = [&self.stretch, &self.bend]
            .into_iter()
            .flatten()
            .map(|k| &k[..])
            .collect();
        let mut values = quadratics(&ks, surface, &x, &mut gradient).into_iter();
        let mut value = |k: &Option<Arc<Vec<Dd>>>| match k {
            Some(_) => values.next().unwrap_or(Dd::new(0.0)),
            None => Dd::new(0.0),
        };
        let stretch = value(&self.stretch);
        let bend = value(&self.bend);
        let mut external = Dd::new(0.0);
        for &(strength, repel, residuals) in &self.operators {
            external += super::operator_energy(strength, repel, residuals, &x, |i, g| {
                gradient[i] += g;
            });
        }
        TriEnergyAt {
            stretch,
            bend,
            external,
            total: stretch + bend + external,
            gradient,
        }
    }
}

/// What the check needs of a solved triangular problem.
pub(crate) struct Verify<'a> {
    pub energy: TriEnergy<'a>,
    /// The free coordinates (flattened indices 3g + c) in solve order.
    pub free: &'a [usize],
    /// The solve's factorization of [H Fᵀ; F 0] over the free coordinates
    /// and the kept rows.
    pub factor: &'a KktFactor,
    /// The kept rows F x = g over the free coordinates.
    pub rows: &'a [&'a [(usize, f64)]],
    pub rhs: &'a [f64],
    /// max H_ii · #free · (max |data|)²: see [`super::scale`].
    pub rounding: f64,
    /// Whether to take Newton corrections (not with repellors: the
    /// factor is of the quadratic part only).
    pub correct: bool,
}

/// The written net after the check and its corrections.
pub(crate) struct Verified {
    /// The free coordinates.
    pub xf: Vec<f64>,
    /// The multipliers of the kept rows (corrected with the net).
    pub lambda: Vec<f64>,
    pub at: TriEnergyAt,
    /// Estimated E(x) − min E over the rows (absolute).
    pub excess: f64,
    pub scale: f64,
    pub corrections: usize,
}

impl Verify<'_> {
    /// E and ∂E/∂x at the free coordinates `xf` (the rest of `surface`'s
    /// points as they are).
    fn at(&self, surface: &TriSurface, xf: &[f64]) -> Result<TriEnergyAt> {
        let mut x: Vec<f64> = surface.points().iter().flatten().copied().collect();
        for (&i, &v) in self.free.iter().zip(xf) {
            x[i] = v;
        }
        let mut s = surface.clone();
        s.set_points(x.chunks(3).map(|c| [c[0], c[1], c[2]]).collect())
            .map_err(|_| crate::Error::NotFinite {
                what: "the solution (the system overflowed)".into(),
            })?;
        Ok(self.energy.at(&s))
    }

    /// The kept rows' residuals F x − g at the free coordinates `xf`, in
    /// double-double, each over its size Σ|a x| + |g|.
    fn row_residuals(&self, xf: &[f64]) -> Vec<f64> {
        self.rows
            .iter()
            .zip(self.rhs)
            .map(|(row, &g)| {
                let r = row
                    .iter()
                    .fold(Dd::new(-g), |acc, &(i, a)| acc + Dd::new(xf[i]) * a);
                let size = row.iter().map(|&(i, a)| (a * xf[i]).abs()).sum::<f64>() + g.abs();
                if size > 0.0 {
                    r.to_f64().abs() / size
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// The gradient of the Lagrangian g + Fᵀλ at the free coordinates, in
    /// double-double from the exact energy gradient g: about zero at a
    /// solution, so the steps below are solved for small right-hand sides
    /// (the multipliers' large part cancels exactly, not in the solve).
    fn lagrangian(&self, at: &TriEnergyAt, lambda: &[f64]) -> Vec<f64> {
        let mut g: Vec<Dd> = self.free.iter().map(|&i| at.gradient[i]).collect();
        for (row, &l) in self.rows.iter().zip(lambda) {
            for &(i, a) in row.iter() {
                g[i] += Dd::new(a) * l;
            }
        }
        g.iter().map(|v| v.to_f64()).collect()
    }

    /// The step y of [H Fᵀ; F 0][y; μ] = [g_L; 0]: x − y is stationary
    /// for the multipliers λ − μ and moves along the rows.
    fn step(&self, g: &[f64]) -> Result<(Vec<f64>, Vec<f64>)> {
        let b: Vec<f64> = g.iter().map(|v| -v).collect();
        let sol = self.factor.solve(&b, &vec![0.0; self.rhs.len()])?;
        Ok((sol.x, sol.lambda))
    }

    /// Checks `xf` (with the solve's multipliers `lambda`) and corrects it
    /// by the steps y while the excess is above [`super::GOAL`], the step
    /// moves the net by more than its rounding ([`super::NET_ROUNDING`]) and
    /// lowers the energy (compared in double-double) without moving off the
    /// rows. The excess is ½ g_Lᵀy: what the energy would drop by at
    /// the minimizer of the quadratic over the rows' null space
    /// (g_Lᵀy = gᵀy as F y = 0).
    pub fn run(
        &self,
        surface: &TriSurface,
        mut xf: Vec<f64>,
        mut lambda: Vec<f64>,
    ) -> Result<Verified> {
        let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let mut at = self.at(surface, &xf)?;
        let mut r = self.row_residuals(&xf);
        let mut corrections = 0;
        loop {
            crate::budget::checkpoint()?;
            let g = self.lagrangian(&at, &lambda);
            let (y, mu) = self.step(&g)?;
            let excess = (0.5 * g.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>()).abs();
            let scale = super::scale(at.total.to_f64(), self.rounding);
            let done = !excess.is_finite()
                || excess <= super::GOAL * scale
                || inf(&y) <= super::NET_ROUNDING * inf(&xf);
            let finish = |xf, lambda, at| Verified {
                xf,
                lambda,
                at,
                excess,
                scale,
                corrections,
            };
            if done || !self.correct || corrections == super::MAX_CORRECTIONS {
                return Ok(finish(xf, lambda, at));
            }
            let next: Vec<f64> = xf.iter().zip(&y).map(|(a, b)| a - b).collect();
            let next_at = self.at(surface, &next)?;
            let next_r = self.row_residuals(&next);
            let lower = (next_at.total - at.total).to_f64() < 0.0;
            if !lower || inf(&next_r) > inf(&r).max(super::ROW_ROUNDING) {
                return Ok(finish(xf, lambda, at));
            }
            lambda = lambda.iter().zip(&mu).map(|(l, m)| l - m).collect();
            (xf, at, r) = (next, next_at, next_r);
            corrections += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::triangle::{Continuity, EdgeContinuity, TriProblem};
    use crate::Stretch;

    fn wavy_surface(n: usize) -> TriSurface {
        let v = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.1],
            [0.4, 0.9, -0.2],
            [1.2, 1.0, 0.3],
        ];
        let mut s = TriSurface::new(&v, &[[0, 1, 2], [1, 3, 2]], n);
        let pts: Vec<_> = s
            .points()
            .iter()
            .enumerate()
            .map(|(g, p)| {
                let f = g as f64;
                [p[0] + 0.01 * f.sin(), p[1], p[2] + 0.3 * (1.7 * f).cos()]
            })
            .collect();
        s.set_points(pts).unwrap();
        s
    }

    /// A kept form matrix is the one a fresh quadrature gives, value for
    /// value; the same key gives the same matrix, another weight another.
    #[test]
    fn kept_form_matrices_are_the_fresh_ones() {
        let a = form_matrix(1.0, 5, true).unwrap();
        let b = form_matrix(1.0, 5, true).unwrap();
        assert!(Arc::ptr_eq(&a, &b));
        let fresh = Form::new(1.0, 5, bend_stencils()).unwrap().matrix(5);
        assert!(a
            .iter()
            .zip(&fresh)
            .all(|(x, y)| x.hi == y.hi && x.lo == y.lo));
        let c = form_matrix(2.0, 5, true).unwrap();
        assert!(!Arc::ptr_eq(&a, &c) && (c[0].hi - 2.0 * a[0].hi).abs() <= 1e-15 * c[0].hi.abs());
        assert!(form_matrix(0.0, 5, false).is_none());
    }

    #[test]
    fn energy_and_gradient_equal_the_closed_forms() {
        for n in [1, 2, 3, 6, 11] {
            let s = wavy_surface(n);
            let e = InternalEnergy::new(0.7, 1.3);
            let at = TriEnergy::new(&e, n, Vec::new()).at(&s);
            let closed = e.surface_value(&s).unwrap();
            assert!(
                (at.total.to_f64() - closed).abs() <= 1e-13 * closed,
                "n = {n}: {} vs {closed}",
                at.total.to_f64()
            );
            let sep = InternalEnergy::new(0.7, 0.0).surface_value(&s).unwrap();
            assert!((at.stretch.to_f64() - sep).abs() <= 1e-13 * sep);
            // ∂E/∂x = K x per coordinate.
            let k = e.surface_matrix(&s).unwrap();
            for c in 0..3 {
                // (K x, Σ|K||x|): the size of the terms that cancel.
                let mut kx = vec![0.0; s.point_count()];
                let mut size = 0.0f64;
                for j in 0..k.ncols() {
                    for (i, v) in k.row_idx_of_col(j).zip(k.val_of_col(j)) {
                        kx[i] += v * s.points()[j][c];
                        size += (v * s.points()[j][c]).abs();
                    }
                }
                let scale = size / s.point_count() as f64;
                for (g, want) in kx.iter().enumerate() {
                    let got = at.gradient[3 * g + c].to_f64();
                    assert!(
                        (got - want).abs() <= 1e-12 * scale,
                        "n = {n}, point {g}, coordinate {c}: {got} vs {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_solved_problem_is_stationary_in_double_double() {
        // Flat boundary, fixed; stretch: every interior gradient entry of
        // the solved net vanishes to rounding.
        let s = wavy_surface(4);
        let sol = TriProblem::from_mesh(s)
            .with_term(Stretch::new(1.0))
            .with_fixed_boundary()
            .with_continuity(Continuity {
                vertices: false,
                edges: EdgeContinuity::Off,
                boundary_angles: Vec::new(),
                boundary_rules: Vec::new(),
            })
            .solve()
            .unwrap();
        let at = TriEnergy::new(&InternalEnergy::new(1.0, 0.0), 4, Vec::new()).at(&sol.surface);
        let fixed: std::collections::HashSet<_> = sol.figures().fixed.iter().copied().collect();
        for (i, g) in at.gradient.iter().enumerate() {
            if !fixed.contains(&(i / 3)) {
                assert!(g.to_f64().abs() < 1e-12, "coordinate {i}: {}", g.to_f64());
            }
        }
    }
}
