//! The energy of a tensor problem and its gradient at a written net, in
//! double-double and by quadrature: independent of the solve, which
//! assembles closed-form Bernstein integrals in double precision.
//!
//! Every integrand is a polynomial, so Gauss–Legendre with enough nodes is
//! exact; the sampled terms (Wu & Yang eq. 5) are sums at the grid. The net's
//! derivatives at the nodes come from its derivative nets (differences of
//! doubles, exact in double-double) against Bernstein values computed by a
//! recurrence of positive terms, so nothing cancels beyond what the integrand
//! itself does. The gradient is the adjoint of the same maps.

use super::dd::Dd;
use super::nodes::{Nodes, Table};
use crate::energy::{Integrand, Measure, NormalGuide};
use crate::operator::{Residual, TensorOperator};
use crate::TensorPatch;
use std::sync::Arc;

/// Energy (total and per term) and gradient ∂E/∂P at every control point.
pub(crate) struct EnergyAt {
    pub total: Dd,
    /// Each energy term's value, in the problem's order (operators not included).
    pub terms: Vec<Dd>,
    /// One table per coordinate, (n+1)×(m+1).
    pub gradient: [Table; 3],
}

/// The evaluation grid of one term: nodes in u and v and the weight of each
/// (u_a, v_b) pair, row-major.
struct Grid {
    u: Nodes,
    v: Nodes,
    omega: Vec<Dd>,
}

impl Grid {
    /// Gauss rules exact for an integrand of degree ≤ (du, dv).
    fn exact(du: usize, dv: usize) -> Self {
        let (u, v) = (Nodes::gauss(du / 2 + 1), Nodes::gauss(dv / 2 + 1));
        let omega =
            u.w.iter()
                .flat_map(|&a| v.w.iter().map(move |&b| a * b))
                .collect();
        Self { u, v, omega }
    }

    /// The sample grid of eq. 5 with per-sample weights (1 when `None`).
    fn samples(np: usize, mp: usize, weights: Option<&[f64]>) -> Self {
        let n = (np + 1) * (mp + 1);
        let omega = (0..n)
            .map(|k| Dd::new(weights.map_or(1.0, |w| w[k])))
            .collect();
        Self {
            u: Nodes::grid(np),
            v: Nodes::grid(mp),
            omega,
        }
    }

    fn for_measure(measure: &Measure, du: usize, dv: usize, weights: Option<&[f64]>) -> Self {
        match measure {
            Measure::Exact => Self::exact(du, dv),
            Measure::Grid(g) => {
                let (np, mp) = g.size();
                Self::samples(np, mp, weights)
            }
        }
    }
}

/// One coordinate net as a table.
fn coordinate(points: &[crate::Vec3], (n, m): (usize, usize), c: usize) -> Table {
    Table {
        rows: n + 1,
        cols: m + 1,
        v: points.iter().map(|p| Dd::new(p[c])).collect(),
    }
}

/// The (r, s) derivative of a net at the grid's nodes, and the map back.
struct Pattern {
    r: usize,
    s: usize,
    bu: Arc<Table>,
    bv: Arc<Table>,
    but: Arc<Table>,
    bvt: Arc<Table>,
}

impl Pattern {
    /// None when the pattern vanishes at this degree.
    fn new(grid: &Grid, (n, m): (usize, usize), (r, s): (usize, usize)) -> Option<Self> {
        (r <= n && s <= m).then(|| Self {
            r,
            s,
            bu: grid.u.bernstein(n - r, false),
            bv: grid.v.bernstein(m - s, false),
            but: grid.u.bernstein(n - r, true),
            bvt: grid.v.bernstein(m - s, true),
        })
    }

    /// ∂ᵘʳ∂ᵛˢ of the net at every node (rows: u-nodes).
    fn eval(&self, net: &Table) -> Table {
        let d = net
            .diff_rows(self.r)
            .transpose()
            .diff_rows(self.s)
            .transpose();
        self.bu.mul(&d).mul(&self.bvt)
    }

    /// The adjoint of [`Pattern::eval`]: ∂/∂P of Σ_ab G_ab · (∂ᵘʳ∂ᵛˢR)_ab.
    fn adjoint(&self, g: &Table, (n, m): (usize, usize)) -> Table {
        let t = self.but.mul(g).mul(&self.bv);
        t.diff_rows_adjoint(self.r, n + 1)
            .transpose()
            .diff_rows_adjoint(self.s, m + 1)
            .transpose()
    }
}

/// Adds `t` into `acc` entry by entry.
fn accumulate(acc: &mut Table, t: &Table) {
    for (a, b) in acc.v.iter_mut().zip(&t.v) {
        *a += *b;
    }
}

/// E and ∂E/∂P of the problem's terms and operators at `patch`. `None`
/// when a term does not describe its integrand.
pub(crate) fn energy_at(
    integrands: &[Option<Integrand<'_>>],
    operators: &[(&TensorOperator, &[Residual])],
    patch: &TensorPatch,
) -> Option<EnergyAt> {
    let degree = patch.degree();
    let (n, m) = degree;
    let nets: [Table; 3] = std::array::from_fn(|c| coordinate(patch.points(), degree, c));
    let mut gradient: [Table; 3] = std::array::from_fn(|_| Table::zeros(n + 1, m + 1));
    let mut shared = Shared::new(integrands, &nets, degree);
    let mut total = Dd::new(0.0);
    let mut terms = Vec::with_capacity(integrands.len());
    for integrand in integrands {
        let e = match integrand.as_ref()? {
            Integrand::Fairness {
                weight,
                measure: Measure::Exact,
                patterns,
            } => shared.fairness(*weight, patterns),
            Integrand::Fairness {
                weight,
                measure,
                patterns,
            } => fairness(*weight, measure, patterns, &nets, degree, &mut gradient),
            Integrand::NormalField {
                weight,
                guide: NormalGuide::Field(f),
            } => shared.normal_field(*weight, f),
            Integrand::NormalField { weight, guide } => {
                normal_field(*weight, guide, &nets, degree, &mut gradient)?
            }
            Integrand::GuideSurface {
                weight,
                surface,
                measure: Measure::Exact,
                ..
            } => shared.guide(*weight, surface),
            Integrand::GuideSurface {
                weight,
                surface,
                measure,
                sample_weights,
            } => guide(
                *weight,
                surface,
                measure,
                *sample_weights,
                &nets,
                degree,
                &mut gradient,
            ),
            // A B-spline guide is refused by a Bézier patch's problem.
            Integrand::GuideSpline { .. } => return None,
        };
        total += e;
        terms.push(e);
    }
    shared.add_gradient(&mut gradient);
    let x: Vec<Dd> = patch
        .points()
        .iter()
        .flatten()
        .map(|&v| Dd::new(v))
        .collect();
    for (op, residuals) in operators {
        total += super::operator_energy(op.strength, op.repel, residuals, &x, |i, g| {
            gradient[i % 3].v[i / 3] += g;
        });
    }
    Some(EnergyAt {
        total,
        terms,
        gradient,
    })
}

/// The exactly integrated terms' derivative patterns, each evaluated once
/// on one Gauss grid that is exact for every term using it (stretch and the
/// normal field both integrate R_u and R_v), with the node weights the terms
/// put on it: the gradient's adjoint is taken once per pattern and
/// coordinate, not once per term. Sample sums keep their own grids.
struct Shared {
    degree: (usize, usize),
    /// Grids by the degrees (du, dv) they are exact for.
    grids: Vec<((usize, usize), Grid)>,
    groups: Vec<Group>,
}

/// One pattern on its grid: the net's values and the terms' weights.
struct Group {
    pattern: (usize, usize),
    grid: usize,
    p: Pattern,
    values: [Table; 3],
    weights: [Table; 3],
}

impl Shared {
    fn new(
        integrands: &[Option<Integrand<'_>>],
        nets: &[Table; 3],
        degree: (usize, usize),
    ) -> Self {
        let (n, m) = degree;
        // The integrand degree each exact term needs per pattern.
        let mut needs: Vec<((usize, usize), (usize, usize))> = Vec::new();
        for integrand in integrands.iter().flatten() {
            match integrand {
                Integrand::Fairness {
                    measure: Measure::Exact,
                    patterns,
                    ..
                } => {
                    for &((r, s), _) in patterns.iter() {
                        let d = (2 * n.saturating_sub(r), 2 * m.saturating_sub(s));
                        needs.push(((r, s), d));
                    }
                }
                Integrand::NormalField {
                    guide: NormalGuide::Field(f),
                    ..
                } => {
                    let (n1, m1) = f.degree();
                    for pattern in [(1, 0), (0, 1)] {
                        needs.push((pattern, (2 * n + 2 * n1, 2 * m + 2 * m1)));
                    }
                }
                Integrand::GuideSurface {
                    measure: Measure::Exact,
                    surface,
                    ..
                } => {
                    let sd = surface.degree();
                    needs.push(((0, 0), (2 * n.max(sd.0), 2 * m.max(sd.1))));
                }
                _ => {}
            }
        }
        let mut shared = Self {
            degree,
            grids: Vec::new(),
            groups: Vec::new(),
        };
        let mut patterns: Vec<(usize, usize)> = needs.iter().map(|&(p, _)| p).collect();
        patterns.sort_unstable();
        patterns.dedup();
        for pattern in patterns {
            let d = needs
                .iter()
                .filter(|(p, _)| *p == pattern)
                .fold((0, 0), |(a, b), &(_, (c, d))| (a.max(c), b.max(d)));
            let grid = shared.grid(d);
            let Some(p) = Pattern::new(&shared.grids[grid].1, degree, pattern) else {
                continue;
            };
            let values = std::array::from_fn(|c| p.eval(&nets[c]));
            let weights = zero_weights(&values);
            shared.groups.push(Group {
                pattern,
                grid,
                p,
                values,
                weights,
            });
        }
        shared
    }

    /// The index of the grid exact for degrees d, made on first use.
    fn grid(&mut self, d: (usize, usize)) -> usize {
        if let Some(k) = self.grids.iter().position(|(e, _)| *e == d) {
            return k;
        }
        self.grids.push((d, Grid::exact(d.0, d.1)));
        self.grids.len() - 1
    }

    fn group(&mut self, pattern: (usize, usize)) -> Option<(&mut Group, &Grid)> {
        let g = self.groups.iter_mut().find(|g| g.pattern == pattern)?;
        let grid = &self.grids[g.grid].1;
        Some((g, grid))
    }

    /// w · ½ Σ_patterns c ∫ |∂ᵘʳ∂ᵛˢR|².
    fn fairness(&mut self, weight: f64, patterns: &[((usize, usize), f64)]) -> Dd {
        let mut e = Dd::new(0.0);
        for &(pattern, c) in patterns {
            let Some((g, grid)) = self.group(pattern) else {
                continue;
            };
            e += squares(&g.values, &grid.omega, weight * c, &mut g.weights);
        }
        e
    }

    /// ½ λ ∫ (R_u·N)² + (R_v·N)² with a Bézier field N.
    fn normal_field(&mut self, weight: f64, field: &TensorPatch) -> Dd {
        let fd = field.degree();
        let mut e = Dd::new(0.0);
        // The field at the nodes of the last grid it was evaluated on.
        let mut normals: Option<(usize, [Table; 3])> = None;
        for pattern in [(1, 0), (0, 1)] {
            let Some(k) = self.groups.iter().position(|g| g.pattern == pattern) else {
                continue;
            };
            let grid_index = self.groups[k].grid;
            let grid = &self.grids[grid_index].1;
            if normals.as_ref().is_none_or(|(i, _)| *i != grid_index) {
                let Some(p) = Pattern::new(grid, fd, (0, 0)) else {
                    continue;
                };
                let tables = std::array::from_fn(|c| p.eval(&coordinate(field.points(), fd, c)));
                normals = Some((grid_index, tables));
            }
            let Some((_, nt)) = normals.as_ref() else {
                continue;
            };
            let g = &mut self.groups[k];
            e += normal_squares(&g.values, nt, &grid.omega, weight, &mut g.weights);
        }
        e
    }

    /// ½ γ ∫ |R − S|² with S at its own degree.
    fn guide(&mut self, weight: f64, surface: &TensorPatch) -> Dd {
        let sd = surface.degree();
        let Some((g, grid)) = self.group((0, 0)) else {
            return Dd::new(0.0);
        };
        let Some(ps) = Pattern::new(grid, sd, (0, 0)) else {
            return Dd::new(0.0);
        };
        let s = std::array::from_fn(|c| ps.eval(&coordinate(surface.points(), sd, c)));
        distance_squares(&g.values, &s, &grid.omega, weight, &mut g.weights)
    }

    /// Each pattern's adjoint of the summed node weights, into `gradient`.
    fn add_gradient(&self, gradient: &mut [Table; 3]) {
        for g in &self.groups {
            add_adjoints(&g.p, &g.weights, self.degree, gradient);
        }
    }
}

/// The adjoint of `p` on each coordinate's node weights, into `gradient`.
fn add_adjoints(
    p: &Pattern,
    weights: &[Table; 3],
    degree: (usize, usize),
    gradient: &mut [Table; 3],
) {
    for (acc, w) in gradient.iter_mut().zip(weights) {
        accumulate(acc, &p.adjoint(w, degree));
    }
}

/// Zero node weights shaped as `values`.
fn zero_weights(values: &[Table; 3]) -> [Table; 3] {
    std::array::from_fn(|c| Table::zeros(values[c].rows, values[c].cols))
}

/// w · ½ Σ_k ω_k f_k² over each coordinate's node values `f` (a fairness
/// pattern), with w ω_k f_k added to the node weights (the gradient's
/// adjoint input).
fn squares(f: &[Table; 3], omega: &[Dd], w: f64, weights: &mut [Table; 3]) -> Dd {
    let mut e = Dd::new(0.0);
    for (fc, wc) in f.iter().zip(weights.iter_mut()) {
        let mut sum = Dd::new(0.0);
        for ((&x, &o), wk) in fc.v.iter().zip(omega).zip(wc.v.iter_mut()) {
            sum += o * x * x;
            *wk += o * x * w;
        }
        e += sum * (0.5 * w);
    }
    e
}

/// ½ λ Σ_k ω_k φ_k² with φ_k = f_k · N_k (a normal-field pattern), with
/// λ ω_k φ_k N_k added to the node weights.
fn normal_squares(
    f: &[Table; 3],
    normals: &[Table; 3],
    omega: &[Dd],
    weight: f64,
    weights: &mut [Table; 3],
) -> Dd {
    let mut e = Dd::new(0.0);
    for (k, &o) in omega.iter().enumerate() {
        let phi = (0..3).fold(Dd::new(0.0), |s, c| s + f[c].v[k] * normals[c].v[k]);
        e += o * phi * phi * (0.5 * weight);
        for c in 0..3 {
            weights[c].v[k] += o * phi * normals[c].v[k] * weight;
        }
    }
    e
}

/// ½ γ Σ_k ω_k |f_k − s_k|² (the guide surface's term), with γ ω_k (f_k − s_k)
/// added to the node weights.
fn distance_squares(
    f: &[Table; 3],
    s: &[Table; 3],
    omega: &[Dd],
    weight: f64,
    weights: &mut [Table; 3],
) -> Dd {
    let mut e = Dd::new(0.0);
    for c in 0..3 {
        for (k, &o) in omega.iter().enumerate() {
            let diff = f[c].v[k] - s[c].v[k];
            e += o * diff * diff * (0.5 * weight);
            weights[c].v[k] += o * diff * weight;
        }
    }
    e
}

/// w · ½ Σ_patterns c ∫ |∂ᵘʳ∂ᵛˢR|².
fn fairness(
    weight: f64,
    measure: &Measure,
    patterns: &[((usize, usize), f64)],
    nets: &[Table; 3],
    degree: (usize, usize),
    gradient: &mut [Table; 3],
) -> Dd {
    let (n, m) = degree;
    let mut e = Dd::new(0.0);
    for &((r, s), c) in patterns {
        let grid = Grid::for_measure(
            measure,
            2 * n.saturating_sub(r),
            2 * m.saturating_sub(s),
            None,
        );
        let Some(p) = Pattern::new(&grid, degree, (r, s)) else {
            continue;
        };
        let values: [Table; 3] = std::array::from_fn(|k| p.eval(&nets[k]));
        let mut weights = zero_weights(&values);
        e += squares(&values, &grid.omega, weight * c, &mut weights);
        add_adjoints(&p, &weights, degree, gradient);
    }
    e
}

/// ½ λ Σ ω [(R_u·N)² + (R_v·N)²] at samples; None when a sampled normal is
/// zero or the field is a B-spline (the solve refuses both before).
fn normal_field(
    weight: f64,
    guide: &NormalGuide,
    nets: &[Table; 3],
    degree: (usize, usize),
    gradient: &mut [Table; 3],
) -> Option<Dd> {
    let (grid, normals) = match guide {
        // A Bézier field is integrated on the shared grids
        // ([`Shared::normal_field`]).
        NormalGuide::Field(_) | NormalGuide::Spline(_) => return None,
        NormalGuide::Samples {
            grid: g,
            normals,
            weights,
        } => {
            let (np, mp) = g.size();
            let grid = Grid::samples(np, mp, weights.as_deref());
            let mut tables: [Table; 3] = std::array::from_fn(|_| Table::zeros(np + 1, mp + 1));
            for (k, nk) in normals.iter().enumerate() {
                let d: [Dd; 3] = nk.map(Dd::new);
                let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                if len.hi == 0.0 {
                    return None;
                }
                for c in 0..3 {
                    tables[c].v[k] = d[c] / len;
                }
            }
            (grid, tables)
        }
    };
    let mut e = Dd::new(0.0);
    for pattern in [(1, 0), (0, 1)] {
        let Some(p) = Pattern::new(&grid, degree, pattern) else {
            continue;
        };
        let values: [Table; 3] = std::array::from_fn(|c| p.eval(&nets[c]));
        let mut weights = zero_weights(&values);
        e += normal_squares(&values, &normals, &grid.omega, weight, &mut weights);
        add_adjoints(&p, &weights, degree, gradient);
    }
    Some(e)
}

/// ½ γ Σ ω |R − S|² with S at its own degree.
fn guide(
    weight: f64,
    surface: &TensorPatch,
    measure: &Measure,
    sample_weights: Option<&[f64]>,
    nets: &[Table; 3],
    degree: (usize, usize),
    gradient: &mut [Table; 3],
) -> Dd {
    let (n, m) = degree;
    let sd = surface.degree();
    let grid = Grid::for_measure(measure, 2 * n.max(sd.0), 2 * m.max(sd.1), sample_weights);
    let (Some(pr), Some(ps)) = (
        Pattern::new(&grid, degree, (0, 0)),
        Pattern::new(&grid, sd, (0, 0)),
    ) else {
        return Dd::new(0.0);
    };
    let values: [Table; 3] = std::array::from_fn(|c| pr.eval(&nets[c]));
    let target = std::array::from_fn(|c| ps.eval(&coordinate(surface.points(), sd, c)));
    let mut weights = zero_weights(&values);
    let e = distance_squares(&values, &target, &grid.omega, weight, &mut weights);
    add_adjoints(&pr, &weights, degree, gradient);
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::{EnergyTerm, Hessian, SampleGrid};
    use crate::{Bend, GuideSurface, NormalField, Stretch};

    fn wavy(n: usize, m: usize, s: f64) -> TensorPatch {
        TensorPatch::from_fn(n, m, |i, j| {
            let (a, b) = (i as f64, j as f64);
            [
                a + 0.3 * (s * b).sin(),
                b - 0.2 * (a * s).cos(),
                (a * b * s).sin(),
            ]
        })
    }

    /// Terms that share a pattern share its grid and its adjoint: the
    /// energy and gradient of stretch + normal field + guide + bend together
    /// are the sums of each term's alone (on its own smaller grid), to
    /// double-double rounding.
    #[test]
    fn shared_grids_give_the_single_terms_sums() {
        let (n, m) = (7, 6);
        let patch = wavy(n, m, 0.6);
        let terms: Vec<Box<dyn EnergyTerm>> = vec![
            Box::new(Stretch::new(1.3)),
            Box::new(NormalField::new(2.0, wavy(3, 2, 0.3))),
            Box::new(GuideSurface::new(1.5, wavy(8, 4, 1.1))),
            Box::new(Bend::new(0.7)),
            Box::new(NormalField::new(0.5, wavy(1, 3, 0.9))),
        ];
        let all: Vec<_> = terms.iter().map(|t| t.integrand()).collect();
        let together = energy_at(&all, &[], &patch).unwrap();
        let mut total = Dd::new(0.0);
        let mut gradient: [Table; 3] = std::array::from_fn(|_| Table::zeros(n + 1, m + 1));
        for (k, t) in terms.iter().enumerate() {
            let alone = energy_at(&[t.integrand()], &[], &patch).unwrap();
            let (a, b) = (together.terms[k], alone.total);
            assert!(
                (a - b).to_f64().abs() <= 1e-28 * b.to_f64().abs(),
                "{}: {:e} vs {:e}",
                t.name(),
                a.to_f64(),
                b.to_f64()
            );
            total += alone.total;
            for c in 0..3 {
                accumulate(&mut gradient[c], &alone.gradient[c]);
            }
        }
        let size = total.to_f64().abs();
        assert!((together.total - total).to_f64().abs() <= 1e-28 * size);
        let g_size = gradient
            .iter()
            .flat_map(|g| &g.v)
            .map(|x| x.to_f64().abs())
            .fold(0.0, f64::max);
        for c in 0..3 {
            for (x, y) in together.gradient[c].v.iter().zip(&gradient[c].v) {
                assert!(
                    (*x - *y).to_f64().abs() <= 1e-28 * g_size,
                    "{:e} vs {:e}",
                    x.to_f64(),
                    y.to_f64()
                );
            }
        }
    }

    /// The quadrature energy and its gradient equal the closed-form term's
    /// value and H(x − s) from its assembled Hessian, for every built-in
    /// term and measure.
    #[test]
    fn energy_and_gradient_equal_the_closed_forms() {
        let (n, m) = (5, 4);
        let patch = wavy(n, m, 0.7);
        let grid = SampleGrid::new(6, 5);
        let weights: Vec<f64> = (0..grid.len()).map(|k| 0.5 + (k % 3) as f64).collect();
        let normals: Vec<_> = (0..grid.len())
            .map(|k| [0.1 * (k % 4) as f64, -0.2, 1.0 + 0.05 * k as f64])
            .collect();
        let terms: Vec<Box<dyn EnergyTerm>> = vec![
            Box::new(Stretch::new(1.3)),
            Box::new(Bend::new(0.7).with_measure(Measure::Grid(grid))),
            Box::new(NormalField::new(2.0, wavy(2, 1, 0.3))),
            Box::new(NormalField::sampled(
                3.0,
                grid,
                normals,
                Some(weights.clone()),
            )),
            Box::new(GuideSurface::new(1.5, wavy(3, 4, 1.1))),
            Box::new(
                GuideSurface::new(0.5, wavy(5, 2, 0.4))
                    .with_measure(Measure::Grid(grid), Some(weights.clone())),
            ),
        ];
        for t in &terms {
            let at = energy_at(&[t.integrand()], &[], &patch).unwrap();
            let value = t.value(&patch).unwrap();
            assert!(
                (at.total.to_f64() - value).abs() <= 1e-13 * value,
                "{}: {} vs {value}",
                t.name(),
                at.total.to_f64()
            );
            let form = t.form((n, m)).unwrap();
            let d: Vec<crate::Vec3> = match &form.center {
                None => patch.points().to_vec(),
                Some(s) => patch
                    .points()
                    .iter()
                    .zip(s)
                    .map(|(a, b)| crate::vec3::sub(*a, *b))
                    .collect(),
            };
            let np = d.len();
            let (mut max_err, mut max_g) = (0.0f64, 0.0f64);
            for p in 0..np {
                for c in 0..3 {
                    let expected: f64 = match &form.hessian {
                        Hessian::PerCoordinate(h) => (0..np).map(|q| h[(p, q)] * d[q][c]).sum(),
                        Hessian::Coupled(h) => (0..3 * np)
                            .map(|q| h[(3 * p + c, q)] * d[q / 3][q % 3])
                            .sum(),
                    };
                    max_err = max_err.max((at.gradient[c].v[p].to_f64() - expected).abs());
                    max_g = max_g.max(expected.abs());
                }
            }
            assert!(
                max_err <= 1e-12 * max_g,
                "{}: gradient off by {max_err:.2e} of {max_g:.2e}",
                t.name()
            );
        }
    }
}
