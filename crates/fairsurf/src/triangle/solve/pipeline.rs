//! [`TriProblem::solve_kept`] step by step (the steps of the module
//! documentation): [`TriProblem::assemble`] (1–4: curves refine the mesh,
//! known coordinates, rows, the reduced system), [`TriProblem::factored`]
//! (5–6: rows classified, the KKT system factored or a kept factorization
//! reused), [`TriProblem::verified`] (the solution checked on the net as
//! written, repellors by Newton) and [`TriProblem::measured`] (7: the
//! report).

use super::*;
use crate::check::triangle::Verified as Checked;
use crate::solve::kkt::KktSolution;

mod report;

/// A row over the free coordinates (coefficients by free index) and its
/// right-hand side.
type ReducedRow = (Vec<(usize, f64)>, f64);

/// The kept rows' coefficients and right-hand sides: F and G of F x = G.
type System<'a> = (Vec<&'a [(usize, f64)]>, Vec<f64>);

/// What steps 1–4 leave: the refined surface with its known coordinates,
/// the rows and the system over the free coordinates.
struct Assembled {
    refinement: Refinement,
    chains: Vec<Chain>,
    placed: Vec<Located>,
    surface: TriSurface,
    known: Vec<Option<f64>>,
    located: Vec<(NamedConstraint, Constraint)>,
    inconsistent: Vec<DroppedRow>,
    rows: Vec<Row>,
    user_rows: usize,
    free: Vec<usize>,
    x0: Vec<f64>,
    /// Each row over the free coordinates, its right-hand side less the
    /// known coordinates' part.
    reduced: Vec<ReducedRow>,
    size: f64,
    h: SparseColMat<usize, f64>,
    b: Vec<f64>,
    residuals: Vec<Vec<Residual>>,
    repellors: Vec<FreeResiduals>,
}

impl Assembled {
    /// The kept rows' coefficients and right-hand sides.
    fn system(&self, kept: &[usize]) -> System<'_> {
        let f = kept.iter().map(|&r| self.reduced[r].0.as_slice()).collect();
        let g = kept.iter().map(|&r| self.reduced[r].1).collect();
        (f, g)
    }

    /// Every row's coefficients over the free coordinates.
    fn row_terms(&self) -> impl ExactSizeIterator<Item = &[(usize, f64)]> {
        self.reduced.iter().map(|(t, _)| t.as_slice())
    }
}

/// The rows classified at a tolerance: each row's verdict and the
/// independent ones.
type Classification = (Vec<Verdict>, Vec<usize>);

/// The rows classified at the tolerances asked: each classification made
/// once, and one serves every tolerance it would come to the same at.
struct Classifier<'a> {
    a: &'a Assembled,
    /// F₁ when the rows are F₁ ⊗ I₃ over interleaved unknowns and the
    /// user's rows come in whole triples: x, y and z classified at once.
    shared: Option<Vec<Vec<(usize, f64)>>>,
    /// Each classification made: its tolerance, its result and every
    /// row's reduced figure ([`classify`]).
    done: Vec<(f64, Classification, Vec<f64>)>,
}

impl<'a> Classifier<'a> {
    fn new(a: &'a Assembled) -> Self {
        let shared = (a.user_rows % 3 == 0)
            .then(|| shared_rows(&a.row_terms().collect::<Vec<_>>()))
            .flatten();
        Self {
            a,
            shared,
            done: Vec::new(),
        }
    }

    /// The classification with the continuity rows at `tol` (the user's
    /// rows keep the strict one). An earlier classification serves when no
    /// continuity row's reduced figure lies between its tolerance and
    /// `tol`: the elimination would take every step as it did.
    fn at(&mut self, tol: f64, seconds: &mut Phases) -> Classification {
        let a = self.a;
        let same =
            |t: f64, reduced: &[f64]| reduced[a.user_rows..].iter().all(|&r| (r > t) == (r > tol));
        if let Some((_, c, _)) = self.done.iter().find(|(t, _, r)| same(*t, r)) {
            return c.clone();
        }
        let t = Instant::now();
        let tol_of = |r: usize| {
            if r < a.user_rows {
                ROW_TOLERANCES[0]
            } else {
                tol
            }
        };
        let (verdicts, reduced) = match &self.shared {
            // F = F₁ ⊗ I₃: F₁ eliminated once for x, y and z.
            Some(f1) => {
                let sparse: Vec<SparseRow<'_, 3>> = f1
                    .iter()
                    .enumerate()
                    .map(|(s, terms)| SparseRow {
                        terms,
                        rhs: [0, 1, 2].map(|c| a.reduced[3 * s + c].1),
                        tol: tol_of(3 * s),
                    })
                    .collect();
                let (v, r) = classify(&sparse, a.free.len().div_ceil(3), 1e-9 * a.size);
                (
                    v.into_iter().flatten().collect(),
                    r.into_iter().flat_map(|x| [x; 3]).collect(),
                )
            }
            None => {
                let sparse: Vec<SparseRow<'_>> = a
                    .reduced
                    .iter()
                    .enumerate()
                    .map(|(r, (terms, rhs))| SparseRow {
                        terms,
                        rhs: [*rhs],
                        tol: tol_of(r),
                    })
                    .collect();
                let (v, r) = classify(&sparse, a.free.len(), 1e-9 * a.size);
                (v.into_iter().map(|[v]| v).collect::<Vec<_>>(), r)
            }
        };
        seconds.classify += t.elapsed().as_secs_f64();
        seconds.classifications += 1;
        let kept: Vec<usize> = (0..a.rows.len())
            .filter(|&r| verdicts[r] == Verdict::Independent)
            .collect();
        self.done
            .push((tol, (verdicts.clone(), kept.clone()), reduced));
        (verdicts, kept)
    }
}

/// What steps 5–6 leave.
struct Solved {
    verdicts: Vec<Verdict>,
    row_tolerance: f64,
    /// The kept rows and the KKT system's solution (None: nothing free).
    sol: Option<(Vec<usize>, KktSolution)>,
    factor: Factor,
    /// A new factorization, and whether to keep it for later solves.
    fresh: Option<(Box<KktFactor>, bool)>,
    reused: bool,
}

/// The solution on the net, checked.
struct Solution {
    x: Vec<f64>,
    kept: Vec<usize>,
    kkt: Option<KktInfo>,
    newton: Option<NewtonReport>,
    gradient_norm: f64,
    relative_gradient: f64,
    /// The check and when it started.
    verified: Option<(Checked, Instant)>,
}

impl TriProblem {
    /// Solves with the first of the factorizations `kept` (of earlier
    /// solves) that is of this problem's KKT matrix (see
    /// [`crate::FactorCache`]); returns the solution and which was used, or
    /// the new factorization.
    pub(crate) fn solve_kept(
        &self,
        kept_factors: &[&TriFactored],
    ) -> Result<(TriSolution, Factor)> {
        let start = Instant::now();
        let mut seconds = Phases::default();
        let a = self.assemble(&mut seconds, start)?;
        crate::budget::checkpoint()?;
        let mut solved = self.factored(&a, kept_factors, &mut seconds)?;
        let t = Instant::now();
        let factor = match (&solved.factor, &solved.fresh) {
            (Factor::Reused(which), _) => Some(&kept_factors[*which].kkt),
            (_, Some((f, _))) => Some(&**f),
            _ => None,
        };
        let sol = self.verified(&a, solved.sol.take(), factor, &mut seconds, t)?;
        self.measured(a, solved, sol, seconds, start)
    }

    /// Steps 1–4. Errors: a bad constraint or operator, a curve that
    /// cannot be embedded, a system too large, a surface nothing holds in
    /// place.
    fn assemble(&self, seconds: &mut Phases, start: Instant) -> Result<Assembled> {
        self.energy()?;
        for c in &self.constraints {
            c.constraint.validate(&self.surface, &c.name)?;
        }
        for op in &self.operators {
            op.validate(&self.surface)?;
        }
        // 1. Curves refine the mesh.
        let (refinement, chains) = self.embed_curves()?;
        let mut surface = refinement.surface.clone();
        crate::budget::reserve(
            &format!(
                "the system of {} degree-{} patches",
                surface.patch_count(),
                surface.degree()
            ),
            memory_estimate(&surface),
        )?;
        crate::budget::checkpoint()?;
        let placed: Vec<Located> = self
            .operators
            .iter()
            .map(|op| op.locate(&self.surface, &refinement))
            .collect::<Result<_>>()?;
        seconds.refine = start.elapsed().as_secs_f64();

        // 2. Known coordinates: curve edges, then the user's fixed points.
        let t = Instant::now();
        let (known, located, inconsistent) =
            self.known_coordinates(&surface, &refinement, &chains)?;
        let mut points = surface.points().to_vec();
        for (g, p) in points.iter_mut().enumerate() {
            for c in 0..3 {
                if let Some(v) = known[3 * g + c] {
                    p[c] = v;
                }
            }
        }
        surface.set_points(points)?;

        crate::budget::checkpoint()?;
        // 3. Rows: the user's, then continuity.
        let mut rows: Vec<Row> = Vec::new();
        for (nc, c) in &located {
            rows.extend(c.rows(&surface, &nc.name));
        }
        let user_rows = rows.len();
        rows.extend(self.extra.continuity.rows(&surface)?);

        crate::budget::checkpoint()?;
        // 4. Eliminate known coordinates.
        let (free_index, free, reduced) = eliminate(&known, &rows);
        let x0: Vec<f64> = surface.points().iter().flat_map(|p| *p).collect();
        let size = bounding_size(surface.points());
        let (h, mut b) = self.hessian(&surface, &known, &free_index, free.len())?;
        // Operators: attractors and directors join the quadratic energy,
        // repellors wait for the Newton iterations.
        let residuals: Vec<Vec<Residual>> = self
            .operators
            .iter()
            .zip(&placed)
            .map(|(op, at)| op.residuals(at, &surface))
            .collect();
        let mut quadratic = Vec::new();
        let mut repellors = Vec::new();
        for (op, res) in self.operators.iter().zip(&residuals) {
            let f = FreeResiduals::new(op.strength, res, &known, &free_index);
            if op.repel {
                repellors.push(f);
            } else {
                quadratic.push(f);
            }
        }
        let h = add_quadratic(h, &mut b, &quadratic)?;
        seconds.assemble = t.elapsed().as_secs_f64();
        self.held_in_place(&known, &rows, &residuals, free.len())?;
        Ok(Assembled {
            refinement,
            chains,
            placed,
            surface,
            known,
            located,
            inconsistent,
            rows,
            user_rows,
            free,
            x0,
            reduced,
            size,
            h,
            b,
            residuals,
            repellors,
        })
    }

    /// Refuses a surface that every free point can leave together in one
    /// direction without changing the energy: no fixed coordinate, row or
    /// attractor holds it.
    fn held_in_place(
        &self,
        known: &[Option<f64>],
        rows: &[Row],
        residuals: &[Vec<Residual>],
        unknowns: usize,
    ) -> Result<()> {
        let pinning = rows.iter().map(|r| &r.terms[..]).chain(
            self.operators
                .iter()
                .zip(residuals)
                .filter(|(op, _)| !op.repel)
                .flat_map(|(_, res)| res.iter().map(|r| &r.terms[..])),
        );
        match free_translation(known, pinning) {
            Some(d) => Err(Error::Singular {
                unknowns,
                condition: f64::INFINITY,
                hint: format!(
                    "nothing holds the surface in place along ({:.3}, {:.3}, {:.3}): the internal \
                     energy does not change when every point moves that way; fix the boundary \
                     (\"fix_boundary\": true), fix or constrain a point, or add an attractor",
                    d[0], d[1], d[2]
                ),
            }),
            None => Ok(()),
        }
    }

    /// Step 2: the coordinates the curves' edges and the user's fixed
    /// points give (a fixed point that disagrees with a curve is reported
    /// inconsistent), and the constraints located on the refined surface.
    #[allow(clippy::type_complexity)]
    fn known_coordinates(
        &self,
        surface: &TriSurface,
        refinement: &Refinement,
        chains: &[Chain],
    ) -> Result<(
        Vec<Option<f64>>,
        Vec<(NamedConstraint, Constraint)>,
        Vec<DroppedRow>,
    )> {
        let mut known: Vec<Option<f64>> = vec![None; 3 * surface.point_count()];
        let mut inconsistent = Vec::new();
        for (name, chain) in chains {
            for (g, p) in chain_points(surface, chain, name)? {
                for c in 0..3 {
                    known[3 * g + c] = Some(p[c]);
                }
            }
        }
        let mut located: Vec<(NamedConstraint, Constraint)> = Vec::new();
        for nc in &self.constraints {
            let c = match nc.constraint {
                Constraint::Fixed { point, value } => {
                    let g = map_global(&self.surface, refinement, point).ok_or_else(|| {
                        Error::Mismatch {
                            what: format!("{}: control point {point}", nc.name),
                            expected:
                                "a control point that survives the curve constraints' refinement"
                                    .into(),
                            got: "a point of a patch split by a curve constraint".into(),
                        }
                    })?;
                    for c in 0..3 {
                        match known[3 * g + c] {
                            Some(v) if (v - value[c]).abs() > 1e-12 * (1.0 + v.abs()) => {
                                inconsistent.push(DroppedRow {
                                    name: format!("{}, {}", nc.name, ["x", "y", "z"][c]),
                                    residual: (v - value[c]).abs(),
                                })
                            }
                            Some(_) => {}
                            None => known[3 * g + c] = Some(value[c]),
                        }
                    }
                    Constraint::Fixed { point: g, value }
                }
                ref other => {
                    let at = other.at().expect("not fixed");
                    let moved = refinement.locate(at).expect("validated domain point");
                    other.moved_to(moved)
                }
            };
            located.push((nc.clone(), c));
        }
        Ok((known, located, inconsistent))
    }

    /// Steps 5–6. Continuity conditions near dependence (F nearly
    /// rank-deficient) make the KKT system singular to working precision
    /// although every kept pivot is far from 0: on a failed or inaccurate
    /// solve the continuity rows are classified again with a looser
    /// tolerance, so nearly dependent ones are reduced or dropped instead
    /// (measured: exact cubic G1 on 1,000 patches needs 1e-3). The user's
    /// rows keep the strict one.
    fn factored(
        &self,
        a: &Assembled,
        kept_factors: &[&TriFactored],
        seconds: &mut Phases,
    ) -> Result<Solved> {
        let mut rows = Classifier::new(a);
        if let Some(s) = reuse_kept(a, kept_factors, &mut rows, seconds) {
            return Ok(s);
        }
        if let Some(s) = refactor_kept(a, kept_factors, &mut rows, seconds) {
            return Ok(s);
        }
        let mut attempt = 0;
        // Whether every looser attempt so far failed for want of a
        // factorization (not for this right-hand side's sake).
        let mut matrix_bound = true;
        // The last attempt's rows and outcome: the same rows give the same
        // system, and it is not factored again.
        let mut previous: Option<(Vec<usize>, KktOutcome)> = None;
        loop {
            let tol = ROW_TOLERANCES[attempt];
            let (verdicts, kept) = rows.at(tol, seconds);
            if a.free.is_empty() {
                return Ok(Solved {
                    verdicts,
                    row_tolerance: tol,
                    sol: None,
                    factor: Factor::None,
                    fresh: None,
                    reused: false,
                });
            }
            // (An earlier outcome of other rows is dropped before this
            // system is factored: its factor may be large.)
            let result = match previous.take().filter(|(rows, _)| *rows == kept) {
                Some((_, outcome)) => outcome,
                None => {
                    let t = Instant::now();
                    let (f, g) = a.system(&kept);
                    let outcome = try_kkt(&a.h, &f, &a.b, &g);
                    seconds.solve += t.elapsed().as_secs_f64();
                    seconds.factorizations += 1;
                    outcome
                }
            };
            let last = attempt + 1 == ROW_TOLERANCES.len() || kept.len() <= a.user_rows;
            match result {
                KktOutcome::Solved {
                    factor: kkt,
                    solution,
                    first_choice,
                } if last || solution.info.relative_residual <= 1e-12 => {
                    // Kept only when a fresh solve of another right-hand
                    // side would come to it too.
                    let keep =
                        first_choice && matrix_bound && solution.info.relative_residual <= 1e-12;
                    return Ok(Solved {
                        verdicts,
                        row_tolerance: tol,
                        sol: Some((kept, solution)),
                        factor: Factor::None,
                        fresh: Some((kkt, keep)),
                        reused: false,
                    });
                }
                KktOutcome::Unfactorable(e) | KktOutcome::Failed(e) if last => return Err(e),
                outcome => {
                    if !matches!(outcome, KktOutcome::Unfactorable(_)) {
                        matrix_bound = false;
                    }
                    previous = Some((kept, outcome));
                    attempt += 1;
                }
            }
        }
    }
}

/// A kept factorization that serves: H and every row's coefficients (the
/// kept rows' and the others') are, value for value, those it was made
/// for, so the rows classify as they did at every tolerance (independence
/// depends on the coefficients only) and a fresh solve would come to the
/// same tolerance and factorization. The right-hand side is new, and with
/// it which rows are dependent or inconsistent.
fn reuse_kept(
    a: &Assembled,
    kept_factors: &[&TriFactored],
    rows: &mut Classifier,
    seconds: &mut Phases,
) -> Option<Solved> {
    for (which, k) in kept_factors.iter().enumerate() {
        if a.free.is_empty() || !k.made_for(&a.h, a.row_terms(), a.user_rows) {
            continue;
        }
        let (verdicts, kept_rows) = rows.at(k.tolerance, seconds);
        let (f, g) = a.system(&kept_rows);
        if !k.kkt.is_for(&a.h, &f) {
            continue;
        }
        let t = Instant::now();
        let sol = k.kkt.solve(&a.b, &g).ok();
        seconds.solve += t.elapsed().as_secs_f64();
        if let Some(sol) = sol.filter(|s| s.info.relative_residual <= 1e-12) {
            return Some(Solved {
                verdicts,
                row_tolerance: k.tolerance,
                sol: Some((kept_rows, sol)),
                factor: Factor::Reused(which),
                fresh: None,
                reused: true,
            });
        }
    }
    None
}

/// A kept factorization of the same pattern and rows (a weight changed):
/// its symbolic analysis serves, only the numbers are factored again.
fn refactor_kept(
    a: &Assembled,
    kept_factors: &[&TriFactored],
    rows: &mut Classifier,
    seconds: &mut Phases,
) -> Option<Solved> {
    for k in kept_factors {
        if a.free.is_empty()
            || !k.rows_match(a.row_terms(), a.user_rows)
            || !k.kkt.same_pattern(&a.h)
        {
            continue;
        }
        let (verdicts, kept_rows) = rows.at(k.tolerance, seconds);
        let (f, g) = a.system(&kept_rows);
        if !k.kkt.rows_are(&f) {
            continue;
        }
        let t = Instant::now();
        let solved = k
            .kkt
            .refactored(&a.h)
            .and_then(|kkt| Some((kkt.solve(&a.b, &g).ok()?, kkt)));
        seconds.solve += t.elapsed().as_secs_f64();
        seconds.factorizations += 1;
        if let Some((sol, kkt)) = solved.filter(|(s, _)| s.info.relative_residual <= 1e-12) {
            return Some(Solved {
                verdicts,
                row_tolerance: k.tolerance,
                sol: Some((kept_rows, sol)),
                factor: Factor::None,
                fresh: Some((Box::new(kkt), true)),
                reused: false,
            });
        }
    }
    None
}

/// The free coordinates (each coordinate's index among them, or
/// `usize::MAX` for a known one; the free ones in order) and each row over
/// them, its right-hand side less the known coordinates' part.
fn eliminate(known: &[Option<f64>], rows: &[Row]) -> (Vec<usize>, Vec<usize>, Vec<ReducedRow>) {
    let mut free_index = vec![usize::MAX; known.len()];
    let mut free = Vec::new();
    for (i, k) in known.iter().enumerate() {
        if k.is_none() {
            free_index[i] = free.len();
            free.push(i);
        }
    }
    let reduced = rows
        .iter()
        .map(|r| {
            let mut rhs = r.rhs;
            let mut terms = Vec::with_capacity(r.terms.len());
            for &(i, a) in &r.terms {
                match known[i] {
                    Some(v) => rhs -= a * v,
                    None => terms.push((free_index[i], a)),
                }
            }
            (terms, rhs)
        })
        .collect();
    (free_index, free, reduced)
}
