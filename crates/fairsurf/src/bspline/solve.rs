//! Minimizing a B-spline surface's energy over its free control points:
//! the Hessian Σ c · M_r^u ⊗ M_s^v (+ γ M_0^u ⊗ M_0^v for a guide surface)
//! restricted to the free points — one sparse matrix for x, y and z, or,
//! with a normal field (which couples them), the interleaved 3n system with
//! the field's 3 × 3 blocks added — the fixed points moved to the
//! right-hand side, Cholesky (dense up to 160 unknowns, else sparse with AMD
//! ordering) and iterative
//! refinement (`system.rs`; with constraints the core's KKT solve,
//! `constraint.rs`), and the energy on the written net by two roads:
//! closed forms (Bernstein products on the Bézier pieces, Gram matrices)
//! or Gauss quadrature from de Boor derivatives, against Gauss quadrature
//! on the pieces with more nodes.

use super::energy::{energy_by_pieces, energy_by_quadrature, Gram1d};
use super::guidance::{guide_value, guide_value_by_pieces, pair, NormalTerm};
use super::problem::{BSplineProblem, Energies, Part};
use super::project::guide_value_by_quadrature;
use super::system::{unconstrained, BSplineFactor, Reuse, Solved, System};
use super::BSplineSurface;
use crate::check::{self, Check};
use crate::operator::bspline::Nodes;
use crate::operator::newton::{newton, repellors};
use crate::operator::{NewtonReport, Residual};
use crate::solve::{SolveReport, TermEnergy, Timings};
use crate::{Error, Result, Vec3};
use faer::sparse::Triplet;
use faer::Mat;
use std::sync::Arc;
use std::time::Instant;

/// Relative agreement required between the two roads to the energy of the
/// written net.
pub const ENERGY_TOLERANCE: f64 = 1e-10;

/// The factor a solve used and how much of it was kept from before (`None`
/// with constraints).
pub(crate) type UsedFactor = Option<(Arc<BSplineFactor>, Reuse)>;

/// A B-spline surface with its free points solved, and its report.
pub type BSplineSolution = crate::Solution<BSplineSurface>;

impl BSplineProblem {
    /// Minimizes; refuses no free point, no energy, a negative weight, a
    /// singular system, and an answer whose energy the second road does
    /// not confirm.
    ///
    /// The report is every tensor kind's [`crate::SolveReport`]. Here
    /// `energy` is the closed forms' (Bernstein products on the Bézier
    /// pieces), which the check's Gauss quadrature span by span confirms to
    /// [`ENERGY_TOLERANCE`] of its scale; `basis` is "b-spline";
    /// `condition_estimate` is Hager's ‖H‖₁‖H⁻¹‖₁ of the matrix factored;
    /// `timings.analyse` is the energy's two roads (also `check.seconds`),
    /// `timings.factor` the Cholesky factorization with its
    /// condition estimate (Hager's, several solves), `timings.solve` the
    /// solves, refinement and the excess (with constraints the KKT
    /// factorization too, `factor` then 0); `measures` is `None` (the
    /// scene layer adds them, [`BSplineSurface::measures`]).
    pub fn solve(&self) -> Result<BSplineSolution> {
        self.solve_kept(&[]).map(|(solution, _)| solution)
    }

    /// [`Self::solve`] with kept factorizations (the editor's drags,
    /// [`crate::FactorCache::solve_bspline`]): without constraints, the one
    /// of this very matrix is used as it is (only the right-hand side is
    /// new: `report.reused`), else the ordering of one with this pattern
    /// (`report.reused_symbolic`). Returns the factor used, to keep (`None`
    /// with constraints, which the core's KKT solve factors).
    pub(crate) fn solve_kept(
        &self,
        kept: &[Arc<BSplineFactor>],
    ) -> Result<(BSplineSolution, UsedFactor)> {
        // The terms read (a guide on other knots projected) count in the
        // assembly.
        let t0 = Instant::now();
        let en = self.energies()?;
        let lambda = en.normal.as_ref().map_or(0.0, |n| n.weight);
        let gamma = en.guide.as_ref().map_or(0.0, |g| g.0);
        let pats = &en.pats();
        if pats.is_empty() && lambda == 0.0 && gamma == 0.0 {
            return Err(Error::NoEnergy);
        }
        let free = self.free_list();
        if free.is_empty() {
            let (cu, cv) = self.surface.counts();
            return Err(Error::NoFreePoints {
                why: format!("every control point of the {cu} × {cv} net is fixed"),
            });
        }
        let (ku, kv) = self.surface.knots();
        let (gu, gv) = (Gram1d::new(ku), Gram1d::new(kv));
        let normal = en.normal.as_ref().filter(|n| n.weight > 0.0);
        let placed = self.place_operators()?;
        // Attractors and directors: s Σ w (a·x − t)² adds 2sw a aᵀ to H and
        // 2sw t a to b.
        let quadratic: Vec<(f64, &Residual)> = self
            .operators
            .iter()
            .zip(&placed)
            .filter(|(op, _)| !op.repel)
            .flat_map(|(op, (_, res))| res.iter().map(move |r| (2.0 * op.strength * r.weight, r)))
            .collect();
        let coupled = normal.is_some() || !self.operators.is_empty();
        let sys = self.assemble(&free, (&gu, &gv), &en, (normal, coupled), &quadratic);
        let assemble = t0.elapsed().as_secs_f64();

        let mut factor = None;
        let mut solved = if self.constraints.is_empty() {
            let (solved, f, reuse) = unconstrained(&sys, coupled, free.len(), kept)?;
            factor = Some((f, reuse));
            solved
        } else {
            let rows = self.constraint_rows()?;
            let mut slot = vec![usize::MAX; self.free.len()];
            for (s, &k) in free.iter().enumerate() {
                slot[k] = s;
            }
            let t1 = Instant::now();
            let c = super::constraint::solve(&sys, coupled, &rows, &slot, self.surface.points())?;
            let x: Vec<Vec3> = c.x.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
            let x_inf = c.x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let denom = sys.h_inf * x_inf + c.b_inf;
            Solved {
                xx: c.x.iter().map(|v| v * v).sum(),
                x,
                gradient_norm: c.gradient_norm,
                relative_gradient: if denom > 0.0 {
                    c.gradient_norm / denom
                } else {
                    c.gradient_norm
                },
                residual: c.kkt.relative_residual,
                excess: c.excess,
                corrections: c.corrections,
                condition_estimate: c.kkt.condition,
                factor_nonzeros: c.kkt.factor_nonzeros.unwrap_or(0),
                kkt: Some(c.kkt),
                factor: 0.0,
                solve: t1.elapsed().as_secs_f64(),
            }
        };
        let newton = self.repel(&sys, coupled, &free, &placed, &mut solved)?;
        let mut points: Vec<Vec3> = self.surface.points().to_vec();
        for (row, &k) in free.iter().enumerate() {
            points[k] = solved.x[row];
        }
        let surface = self.surface.with_points(points);
        let t3 = Instant::now();
        let (pieces, degree) = (surface.bezier_pieces(), surface.degree());
        let normal_field = normal.map_or(0.0, |n| n.value(&surface));
        let guide_surface = en
            .guide
            .as_ref()
            .map_or(0.0, |(g, s)| guide_value(&gu, &gv, *g, surface.points(), s))
            + en.guide_rest();
        // The terms in the problem's order, each with its value.
        let terms: Vec<TermEnergy> = en
            .parts
            .iter()
            .map(|(name, part)| TermEnergy {
                name: (*name).into(),
                value: match part {
                    Part::Fairness(p) => energy_by_pieces(&pieces, degree, p),
                    Part::Normal => normal_field,
                    Part::Guide => guide_surface,
                },
            })
            .collect();
        let x_flat: Vec<f64> = surface.points().iter().flatten().copied().collect();
        let (external, external_check) = self.external(&placed, &x_flat);
        let total = terms.iter().map(|t| t.value).sum::<f64>() + external;
        let mut check_energy = energy_by_quadrature(&pieces, degree, pats) + external_check;
        if let Some(n) = normal {
            check_energy += n.value_by_pieces(&surface, &pieces);
        }
        match (&en.guide, &en.guide_source) {
            (Some((g, _)), Some((source, _))) => {
                check_energy += guide_value_by_quadrature(&surface, source, *g);
            }
            (Some((g, s)), None) => {
                let guide = self.surface.with_points(s.clone()).bezier_pieces();
                check_energy += guide_value_by_pieces(&pieces, &guide, degree, *g);
            }
            _ => {}
        }
        let analyse = t3.elapsed().as_secs_f64();
        // Rounding the free points to doubles can change the energy by about
        // ε² · max H_ii · Σ x_i²: below that, neither the energy's two roads
        // nor the excess tell anything (the scale of both, as the tensor
        // check's).
        let rounding = sys.h_diag * solved.xx;
        let scale = check::scale(total, rounding);
        let (energy_error, agree) = roads_agree(total, check_energy, rounding);
        if !agree {
            return Err(Error::Unverified {
                degree: format!("{:?} (B-spline)", surface.degree()),
                checked: check_energy,
                excess: energy_error,
                tolerance: ENERGY_TOLERANCE,
                hint: "the closed forms and the quadrature of its energy disagree".into(),
            });
        }
        // With repellors the energy is not quadratic: Newton's stationarity
        // (its relative gradient, ≤ 1e-10 or an error) stands for the excess.
        let excess = if newton.is_some() {
            0.0
        } else {
            solved.excess.max(0.0) / scale
        };
        if excess > check::TOLERANCE {
            return Err(Error::Unverified {
                degree: format!("{:?} (B-spline)", surface.degree()),
                checked: total,
                excess,
                tolerance: check::TOLERANCE,
                hint: "the written net is not the minimizer of the assembled system to the \
                       tolerance even after Newton corrections"
                    .into(),
            });
        }
        let (constraints, max_violation) = self.outcomes(&surface, &en)?;
        let operators = self
            .operators
            .iter()
            .zip(&placed)
            .map(|(op, (nodes, res))| op.outcome_on(nodes, res, &surface, &x_flat))
            .collect();
        let reuse = factor.as_ref().map_or(Reuse::New, |f| f.1);
        let solution = BSplineSolution {
            surface,
            report: SolveReport {
                terms,
                energy: total,
                check: Some(Check {
                    energy: check_energy,
                    energy_error,
                    excess,
                    scale,
                    corrections: solved.corrections,
                    tolerance: check::TOLERANCE,
                    seconds: analyse,
                }),
                external,
                operators,
                constraints,
                max_violation,
                newton,
                gradient_norm: solved.gradient_norm,
                relative_gradient: solved.relative_gradient,
                residual: solved.residual,
                condition_estimate: solved.condition_estimate,
                basis: "b-spline".into(),
                refinement_steps: solved.kkt.map_or(1, |k| k.refinement_steps),
                unknowns: 3 * free.len(),
                free_points: free.len(),
                coupled,
                reused: reuse == Reuse::Numeric,
                reused_symbolic: reuse == Reuse::Symbolic,
                measures: None,
                factor_nonzeros: solved.kkt.is_none().then_some(solved.factor_nonzeros),
                kkt: solved.kkt,
                timings: Timings {
                    assemble,
                    factor: solved.factor,
                    solve: solved.solve,
                    analyse,
                    total: t0.elapsed().as_secs_f64(),
                },
                triangular: None,
            },
        };
        Ok((solution, factor))
    }

    /// With repellors (Veltkamp & Wesselink eq. 23, s/E_attr): Newton's
    /// method on the total energy from the quadratic solution, the rows
    /// kept (the core's `operator::newton`, as the tensor and triangular
    /// solves use it); the free points and gradient figures replaced.
    fn repel(
        &self,
        sys: &System,
        coupled: bool,
        free: &[usize],
        placed: &[(Nodes, Vec<Residual>)],
        solved: &mut Solved,
    ) -> Result<Option<NewtonReport>> {
        if !self.operators.iter().any(|op| op.repel) {
            return Ok(None);
        }
        let x0 = self.surface.points();
        let mut slot = vec![usize::MAX; self.free.len()];
        for (s, &k) in free.iter().enumerate() {
            slot[k] = s;
        }
        let known: Vec<Option<Vec3>> = x0
            .iter()
            .zip(&slot)
            .map(|(p, &s)| (s == usize::MAX).then_some(*p))
            .collect();
        let repellors = repellors(&self.operators, placed, &known, free);
        let system = super::constraint::interleaved(sys, coupled);
        let rows = if self.constraints.is_empty() {
            Vec::new()
        } else {
            super::constraint::reduced_rows(&self.constraint_rows()?, &slot, x0)?.0
        };
        let f: Vec<&[(usize, f64)]> = rows.iter().map(Vec::as_slice).collect();
        let minus_b: Vec<f64> = system.b.iter().map(|v| -v).collect();
        let start: Vec<f64> = solved.x.iter().flatten().copied().collect();
        let t = Instant::now();
        let (x, report) = newton(&system.h, &minus_b, &f, &repellors, start)?;
        solved.x = x.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
        solved.xx = x.iter().map(|v| v * v).sum();
        solved.gradient_norm = report.gradient_norm;
        solved.relative_gradient = report.relative_gradient;
        solved.solve += t.elapsed().as_secs_f64();
        Ok(Some(report))
    }

    /// The problem's energy at the net of `surface` (same knots): the sum
    /// of its terms as the report computes them; the terms' and operators'
    /// errors as a solve gives them.
    pub fn energy_at(&self, surface: &BSplineSurface) -> Result<f64> {
        let en = self.energies()?;
        let (ku, kv) = surface.knots();
        let (pieces, degree) = (surface.bezier_pieces(), surface.degree());
        let mut e = energy_by_pieces(&pieces, degree, &en.pats());
        if let Some(n) = &en.normal {
            e += n.value(surface);
        }
        if let Some((g, s)) = &en.guide {
            e += guide_value(&Gram1d::new(ku), &Gram1d::new(kv), *g, surface.points(), s);
            e += en.guide_rest();
        }
        let placed = self.place_operators()?;
        let x: Vec<f64> = surface.points().iter().flatten().copied().collect();
        Ok(e + self.external(&placed, &x).0)
    }

    /// The free block's lower triangle and right-hand side: one matrix for
    /// x, y and z (three columns) unless `coupled` (a normal field or
    /// operators), else the interleaved system (unknown 3·slot + c, one
    /// column).
    fn assemble(
        &self,
        free: &[usize],
        (gu, gv): (&Gram1d, &Gram1d),
        en: &Energies,
        (normal, coupled): (Option<&NormalTerm>, bool),
        operators: &[(f64, &Residual)],
    ) -> System {
        let cv = gv.count();
        let mut slot = vec![usize::MAX; self.free.len()];
        for (s, &k) in free.iter().enumerate() {
            slot[k] = s;
        }
        let x0 = self.surface.points();
        let (pats, gamma) = (&en.pats(), en.guide.as_ref().map_or(0.0, |g| g.0));
        let nf = free.len();
        let (dim, cols) = if coupled { (3 * nf, 1) } else { (nf, 3) };
        // Room for the triplets at once (growing the vector by doubling
        // copied it and faulted in fresh pages: a fifth of a 21 × 27
        // coupled fill's time went to the kernel zeroing pages): per free
        // point its band of neighbours, one value or (coupled) a 3 × 3
        // block each, half of them on or below the diagonal.
        let (p, q) = self.surface.degree();
        let per_point = (2 * p + 1) * (2 * q + 1) * if coupled { 9 } else { 1 };
        let mut sys = System {
            dim,
            lower: Vec::with_capacity(nf * per_point / 2 + dim),
            b: Mat::zeros(dim, cols),
            h_inf: 0.0,
            h_diag: 0.0,
        };
        // ‖H‖∞ of the free block (the matrix factored), row by row.
        let mut row_sums = vec![0.0f64; dim];
        // (global row, coordinate) → the system's row and column.
        let at = |s: usize, c: usize| if coupled { (3 * s + c, 0) } else { (s, c) };
        let mut add = |sys: &mut System, k: usize, c: usize, l: usize, d: usize, h: f64| {
            let (row, rc) = at(slot[k], c);
            match slot[l] {
                usize::MAX => sys.b[(row, rc)] -= h * x0[l][d],
                sl => {
                    row_sums[row] += h.abs();
                    let (col, _) = at(sl, d);
                    if col <= row {
                        sys.lower.push(Triplet::new(row, col, h));
                    }
                }
            }
        };
        // Coupled: the 3 × 3 blocks between free points, summed into a
        // store (per free point and free neighbour when the block is small
        // enough to factor dense, else per free point and neighbour offset)
        // and then emitted once — the thin plate's diagonal blocks, the
        // field's and the operators' alike: adding every span's blocks as
        // triplets made 5 M of them at 50 × 50 (and an operator's every
        // node's). The fixed neighbours' columns go to the right-hand side
        // directly.
        let (wu, wv) = (2 * p + 1, 2 * q + 1);
        let dense = dim <= super::system::DENSE_UNKNOWNS;
        let width = if dense { nf } else { wu * wv };
        let cell = |sk: usize, k: usize, l: usize| -> usize {
            let off = if dense {
                slot[l]
            } else {
                (l / cv + p - k / cv) * wv + (l % cv + q - k % cv)
            };
            (sk * width + off) * 9
        };
        let mut store = vec![0.0f64; if coupled { nf * width * 9 } else { 0 }];
        for &k in free {
            let (i, j) = (k / cv, k % cv);
            for i2 in gu.band(i) {
                for j2 in gv.band(j) {
                    let (mu, mv) = (gu.at(0, i, i2), gv.at(0, j, j2));
                    let h: f64 = pats
                        .iter()
                        .map(|&(c, r, s)| c * gu.at(r, i, i2) * gv.at(s, j, j2))
                        .sum::<f64>()
                        + gamma * mu * mv;
                    let l = i2 * cv + j2;
                    if h != 0.0 && coupled && slot[l] != usize::MAX {
                        let blk = &mut store[cell(slot[k], k, l)..][..9];
                        for c in 0..3 {
                            blk[4 * c] += h;
                        }
                    } else if h != 0.0 {
                        for c in 0..3 {
                            if coupled || c == 0 {
                                add(&mut sys, k, c, l, c, h);
                            }
                        }
                        if !coupled && slot[l] == usize::MAX {
                            // Columns y and z of a fixed neighbour (x went above).
                            let (row, _) = at(slot[k], 0);
                            for c in 1..3 {
                                sys.b[(row, c)] -= h * x0[l][c];
                            }
                        }
                    }
                    // The guide's linear term: + γ M s.
                    if let Some((g, s)) = &en.guide {
                        for c in 0..3 {
                            let (row, rc) = at(slot[k], c);
                            sys.b[(row, rc)] += g * mu * mv * s[l][c];
                        }
                    }
                }
            }
        }
        if coupled {
            for grid in normal.iter().flat_map(|n| n.spans(&self.surface)) {
                let (su, sv) = grid.span;
                let (i0, j0) = (su - p, sv - q);
                let global = |i: usize, j: usize| (i0 + i) * cv + j0 + j;
                let is_free = |i: usize, j: usize| slot[global(i, j)] != usize::MAX;
                // The rows and columns of the span's free points: the
                // local u and v indices that have one.
                let fu: Vec<usize> = (0..=p)
                    .filter(|&i| (0..=q).any(|j| is_free(i, j)))
                    .collect();
                let fv: Vec<usize> = (0..=q)
                    .filter(|&j| (0..=p).any(|i| is_free(i, j)))
                    .collect();
                if fu.is_empty() {
                    continue;
                }
                // Local Σ_nodes w (Y Yᵀ + Z Zᵀ), Y = ∂_u B ⊗ N, Z = ∂_v B ⊗ N.
                let local = grid.local_on(&fu, &fv);
                let (n, size) = (fv.len(), fu.len() * fv.len());
                for a in 0..size {
                    let ka = global(fu[a / n], fv[a % n]);
                    let sk = slot[ka];
                    if sk == usize::MAX {
                        continue;
                    }
                    for b in 0..size {
                        let l = global(fu[b / n], fv[b % n]);
                        if slot[l] == usize::MAX {
                            continue;
                        }
                        let blk = &mut store[cell(sk, ka, l)..][..9];
                        for c in 0..3 {
                            for d in 0..3 {
                                blk[3 * c + d] += local[pair(c, d)][a * size + b];
                            }
                        }
                    }
                }
                // The fixed points' part: b −= H_free,fixed x_fixed, as the
                // span's gradient at its net with the free points at 0.
                let all = (0..=p).flat_map(|i| (0..=q).map(move |j| (i, j)));
                if all.clone().all(|(i, j)| is_free(i, j)) {
                    continue;
                }
                let net: Vec<Vec3> = all
                    .clone()
                    .map(|(i, j)| match is_free(i, j) {
                        true => [0.0; 3],
                        false => x0[global(i, j)],
                    })
                    .collect();
                for ((i, j), g) in all.zip(grid.apply(&net)) {
                    let sk = slot[global(i, j)];
                    if sk != usize::MAX {
                        for (c, g) in g.iter().enumerate() {
                            sys.b[(3 * sk + c, 0)] -= g;
                        }
                    }
                }
            }
            // The operators' residuals w (a·x − t)²: w a aᵀ and w t a, over
            // coordinates 3g + c of one span's points.
            for &(w, r) in operators {
                for &(i, a) in &r.terms {
                    let (k, c) = (i / 3, i % 3);
                    let sk = slot[k];
                    if sk == usize::MAX {
                        continue;
                    }
                    let (row, rc) = at(sk, c);
                    sys.b[(row, rc)] += w * r.target * a;
                    for &(j, b) in &r.terms {
                        let (l, d) = (j / 3, j % 3);
                        match slot[l] {
                            usize::MAX => sys.b[(row, rc)] -= w * a * b * x0[l][d],
                            _ => store[cell(sk, k, l) + 3 * c + d] += w * a * b,
                        }
                    }
                }
            }
            for (sk, &k) in free.iter().enumerate() {
                let (i, j) = (k / cv, k % cv);
                for di in 0..wu {
                    for dj in 0..wv {
                        let (Some(i2), Some(j2)) =
                            ((i + di).checked_sub(p), (j + dj).checked_sub(q))
                        else {
                            continue;
                        };
                        let l = i2 * cv + j2;
                        if j2 >= cv || l >= slot.len() || slot[l] == usize::MAX {
                            continue;
                        }
                        let blk = &store[cell(sk, k, l)..][..9];
                        for c in 0..3 {
                            for d in 0..3 {
                                let h = blk[3 * c + d];
                                if h != 0.0 {
                                    add(&mut sys, k, c, l, d, h);
                                }
                            }
                        }
                    }
                }
            }
        }
        sys.h_inf = row_sums.iter().fold(0.0, |m, &v| m.max(v));
        // The diagonal arrives in several triplets (summed by the matrix).
        let mut diag = vec![0.0; sys.dim];
        for t in sys.lower.iter().filter(|t| t.row == t.col) {
            diag[t.row] += t.val;
        }
        sys.h_diag = diag.iter().fold(0.0, |m, &v| m.max(v));
        sys
    }
}

/// The energy's two roads — the closed forms' `total` and the quadrature's
/// `checked` — compared: their difference over the check's scale
/// ([`check::scale`] of the energy and `rounding`, max H_ii · Σ x_i²) or,
/// when larger, over what cancelled derivatives leave. Both roads sum the
/// net's derivatives in doubles: a small energy of a large net (a nearly
/// flat sliver 1e-3 wide: E 1.4e-11 of points about 1) comes from
/// derivatives that cancelled, each off by about ε·√(max H_ii · Σ x_i²), so
/// the roads may differ by about ε·√(E · max H_ii · Σ x_i²) — 2e-9 of E
/// there. Returns that relative difference and whether it is within
/// [`ENERGY_TOLERANCE`]; a zero energy (a reproduced linear surface) is
/// confirmed when the second road finds it at rounding level of the data,
/// and a NaN on either road fails.
pub(crate) fn roads_agree(total: f64, checked: f64, rounding: f64) -> (f64, bool) {
    let scale = check::scale(total, rounding);
    let roads = scale.max(f64::EPSILON * (total.abs() * rounding).sqrt() / ENERGY_TOLERANCE);
    let error = (total - checked).abs() / roads;
    (
        error,
        error <= ENERGY_TOLERANCE || (total - checked).abs() <= 1e-24,
    )
}
