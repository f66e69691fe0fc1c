//! Steps after the factorization: the solution checked on the net as
//! written ([`TriProblem::verified`]) and the report
//! ([`TriProblem::measured`]).

use super::*;

impl TriProblem {
    /// The solution put on the net and checked there (energy and gradient
    /// of the net as written, corrections while they help; repellors by
    /// Newton iterations first); the Lagrangian's gradient.
    pub(super) fn verified(
        &self,
        a: &Assembled,
        sol: Option<(Vec<usize>, KktSolution)>,
        factor: Option<&KktFactor>,
        seconds: &mut Phases,
        t: Instant,
    ) -> Result<Solution> {
        let mut out = Solution {
            x: a.x0.clone(),
            kept: Vec::new(),
            kkt: None,
            newton: None,
            gradient_norm: 0.0,
            relative_gradient: 0.0,
            verified: None,
        };
        let Some((kept_rows, sol)) = sol else {
            seconds.solve += t.elapsed().as_secs_f64();
            return Ok(out);
        };
        let factor = factor.expect("a solution comes with its factorization");
        out.kept = kept_rows;
        let (f, rhs) = a.system(&out.kept);
        let (mut xf, lambda) = (sol.x, sol.lambda);
        out.kkt = Some(sol.info);
        if !a.repellors.is_empty() {
            let (x_newton, report) = newton(&a.h, &a.b, &f, &a.repellors, xf)?;
            xf = x_newton;
            out.newton = Some(report);
        }
        seconds.solve += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let data = a
            .known
            .iter()
            .flatten()
            .chain(a.rows.iter().map(|r| &r.rhs))
            .chain(a.residuals.iter().flatten().map(|r| &r.target))
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let h = &a.h;
        let max_diagonal = (0..a.free.len())
            .map(|j| {
                h.row_idx_of_col(j)
                    .zip(h.val_of_col(j))
                    .find(|(i, _)| *i == j)
                    .map_or(0.0, |(_, v)| *v)
            })
            .fold(0.0, f64::max);
        let v = Verify {
            energy: TriEnergy::new(
                &self.energy()?,
                a.surface.degree(),
                self.operators
                    .iter()
                    .zip(&a.residuals)
                    .map(|(op, r)| (op.strength, op.repel, &r[..]))
                    .collect(),
            ),
            free: &a.free,
            factor,
            rows: &f,
            rhs: &rhs,
            rounding: max_diagonal * a.free.len() as f64 * data * data,
            correct: a.repellors.is_empty(),
        };
        let checked = v.run(&a.surface, xf, lambda)?;
        for (k, &i) in a.free.iter().enumerate() {
            out.x[i] = checked.xf[k];
        }
        (out.gradient_norm, out.relative_gradient) = match &out.newton {
            Some(r) if checked.corrections == 0 => (r.gradient_norm, r.relative_gradient),
            _ => lagrangian_gradient(&a.h, &a.b, &f, &checked.xf, &checked.lambda),
        };
        out.verified = Some((checked, t));
        Ok(out)
    }

    /// Step 7: the surface and its report. Errors: the written net misses
    /// a user's row or fails its check.
    pub(super) fn measured(
        &self,
        a: Assembled,
        solved: Solved,
        sol: Solution,
        seconds: Phases,
        start: Instant,
    ) -> Result<(TriSolution, Factor)> {
        let Assembled {
            refinement,
            chains,
            placed,
            mut surface,
            known,
            located,
            inconsistent: mut inconsistent_rows,
            rows,
            user_rows,
            free,
            reduced,
            residuals,
            ..
        } = a;
        let x = &sol.x;
        let pts: Vec<Vec3> = x.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        surface.set_points(pts)?;
        let verdicts = &solved.verdicts;
        let (dropped, dependent) = sorted_out(verdicts, &rows, user_rows, &mut inconsistent_rows);
        let continuity_residual = sol
            .kept
            .iter()
            .filter(|&&r| r >= user_rows)
            .map(|&r| rows[r].residual(x).abs())
            .fold(0.0f64, f64::max);
        let unenforced_residual = (user_rows..rows.len())
            .filter(|&r| verdicts[r] != Verdict::Independent)
            .map(|r| rows[r].residual(x).abs())
            .fold(0.0f64, f64::max);
        self.rows_met(x, &free, &rows, user_rows, verdicts, &surface)?;
        let (outcomes, max_violation) = self.outcomes(&located, &chains, &surface);
        let operators: Vec<OperatorOutcome> = self
            .operators
            .iter()
            .zip(placed.iter().zip(&residuals))
            .map(|(op, (at, res))| op.outcome(at, res, &surface, x))
            .collect();
        let external = operators.iter().map(|o| o.energy).sum::<f64>();
        let ([stretch, bend, external, total_energy], check) =
            self.energies(&surface, external, sol.verified)?;
        let mut factor = solved.factor;
        if let Some((kkt, reusable)) = solved.fresh {
            factor = Factor::New(Box::new(TriFactored {
                kkt: *kkt,
                tolerance: solved.row_tolerance,
                rows: reduced.into_iter().map(|(terms, _)| terms).collect(),
                user_rows,
                free: free.clone(),
                reusable,
            }));
        }
        let coords = known.len();
        let kkt = sol.kkt;
        let fixed: Vec<usize> = (0..surface.point_count())
            .filter(|g| (0..3).all(|c| known[3 * g + c].is_some()))
            .collect();
        let free_points = surface.point_count() - fixed.len();
        let triangular = TriFigures {
            patches: surface.patch_count(),
            vertices: surface.vertex_count(),
            points: surface.point_count(),
            fixed_coordinates: coords - free.len(),
            rows: rows.len(),
            independent_rows: sol.kept.len(),
            dependent_rows: dependent,
            dropped,
            inconsistent: inconsistent_rows,
            continuity_residual,
            unenforced_residual,
            row_tolerance: solved.row_tolerance,
            max_edge_normal_angle: max_edge_normal_angle(&surface, 65),
            normal_turn: largest_tri_normal_turn(&surface, 2 * surface.degree() + 2),
            refine_seconds: seconds.refine,
            classify_seconds: seconds.classify,
            classifications: seconds.classifications,
            factorizations: seconds.factorizations,
            origin: refinement.origin,
            fixed,
        };
        let before = seconds.refine + seconds.assemble + seconds.classify + seconds.solve;
        let total = start.elapsed().as_secs_f64();
        let report = SolveReport {
            terms: vec![
                TermEnergy {
                    name: "stretch".into(),
                    value: stretch,
                },
                TermEnergy {
                    name: "bend".into(),
                    value: bend,
                },
            ],
            energy: total_energy,
            check,
            external,
            operators,
            constraints: outcomes,
            max_violation,
            newton: sol.newton,
            gradient_norm: sol.gradient_norm,
            relative_gradient: sol.relative_gradient,
            // Nothing solved (every coordinate fixed): no residual to tell.
            residual: kkt.map_or(f64::NAN, |k| k.relative_residual),
            condition_estimate: kkt.map_or(f64::NAN, |k| k.condition),
            basis: "triangular".into(),
            refinement_steps: kkt.map_or(0, |k| k.refinement_steps),
            unknowns: free.len(),
            free_points,
            coupled: kkt.is_some_and(|k| !k.per_coordinate),
            reused: solved.reused,
            reused_symbolic: kkt.is_some_and(|k| k.reused_symbolic),
            measures: None,
            factor_nonzeros: kkt.and_then(|k| k.factor_nonzeros),
            kkt,
            timings: Timings {
                assemble: seconds.assemble,
                factor: 0.0,
                solve: seconds.solve,
                // The check on the written net (its corrections too), the
                // outcomes, energies and edge angles measured on the result.
                analyse: (total - before).max(0.0),
                total,
            },
            triangular: Some(Box::new(triangular)),
        };
        let solution = TriSolution { surface, report };
        Ok((solution, factor))
    }

    /// Each constraint's and curve's violation on the surface, and the
    /// largest (infinite for one that cannot be measured).
    fn outcomes(
        &self,
        located: &[(NamedConstraint, Constraint)],
        chains: &[Chain],
        surface: &TriSurface,
    ) -> (Vec<ConstraintOutcome>, f64) {
        let mut outcomes: Vec<ConstraintOutcome> = located
            .iter()
            .map(|(nc, c)| ConstraintOutcome {
                name: nc.name.clone(),
                kind: c.kind(),
                violation: c.violation(surface),
            })
            .collect();
        for (curve, (name, chain)) in self.extra.curves.iter().zip(chains) {
            outcomes.push(ConstraintOutcome {
                name: name.clone(),
                kind: "curve",
                violation: curve_distance(surface, chain, &curve.curve),
            });
        }
        let max_violation = outcomes
            .iter()
            .map(|o| {
                if o.violation.is_nan() {
                    f64::INFINITY
                } else {
                    o.violation
                }
            })
            .fold(0.0f64, f64::max);
        (outcomes, max_violation)
    }

    /// The written net must meet the user's rows (but those found
    /// inconsistent) as well as it is a minimum: a miss above the check's
    /// tolerance of the data's size (fixed coordinates, the rows'
    /// right-hand sides) is refused, not reported as met.
    fn rows_met(
        &self,
        x: &[f64],
        free: &[usize],
        rows: &[Row],
        user_rows: usize,
        verdicts: &[Verdict],
        surface: &TriSurface,
    ) -> Result<()> {
        let mut is_free = vec![false; x.len()];
        for &i in free {
            is_free[i] = true;
        }
        let data = (0..x.len())
            .filter(|&i| !is_free[i])
            .map(|i| x[i])
            .chain(rows[..user_rows].iter().map(|r| r.rhs))
            .chain(self.operators.iter().map(|o| o.target.size()))
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        let unmet = (0..user_rows)
            .filter(|&r| !matches!(verdicts[r], Verdict::Inconsistent { .. }))
            .map(|r| (r, rows[r].residual(x).abs() / data))
            .filter(|&(_, miss)| miss.is_nan() || miss > crate::check::TOLERANCE)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match unmet {
            Some((r, miss)) => Err(Error::Unmet {
                degree: surface.degree().to_string(),
                row: rows[r].name.clone(),
                miss,
                tolerance: crate::check::TOLERANCE,
            }),
            None => Ok(()),
        }
    }

    /// Stretch, bend, external and total energy: the closed forms, or
    /// when the solve was checked the check's recomputed values, with the
    /// check (refused when it failed).
    fn energies(
        &self,
        surface: &TriSurface,
        external: f64,
        verified: Option<(Checked, Instant)>,
    ) -> Result<([f64; 4], Option<Check>)> {
        let energy = self.energy()?;
        let stretch = InternalEnergy::new(energy.stretch, 0.0).surface_value(surface)?;
        let bend = InternalEnergy::new(0.0, energy.bend).surface_value(surface)?;
        let closed_form = stretch + bend + external;
        let Some((v, t)) = verified else {
            return Ok(([stretch, bend, external, closed_form], None));
        };
        // The closed forms in double precision give way to the recomputed
        // values.
        let total = v.at.total.to_f64();
        let check = Check {
            energy: total,
            energy_error: (closed_form - total).abs() / v.scale,
            excess: v.excess / v.scale,
            scale: v.scale,
            corrections: v.corrections,
            tolerance: crate::check::TOLERANCE,
            seconds: t.elapsed().as_secs_f64(),
        };
        if !check.passed() {
            return Err(Error::Unverified {
                degree: surface.degree().to_string(),
                checked: total,
                excess: check.excess,
                tolerance: check.tolerance,
                hint: "A triangular net of this degree cannot hold this minimizer to that \
                       accuracy: use a lower degree, with more triangles for more freedom."
                    .into(),
            });
        }
        let energies = [
            v.at.stretch.to_f64(),
            v.at.bend.to_f64(),
            v.at.external.to_f64(),
            total,
        ];
        Ok((energies, Some(check)))
    }
}

/// The rows left out: continuity rows found inconsistent (dropped; the
/// user's go to `inconsistent`), and how many were dependent.
fn sorted_out(
    verdicts: &[Verdict],
    rows: &[Row],
    user_rows: usize,
    inconsistent: &mut Vec<DroppedRow>,
) -> (Vec<DroppedRow>, usize) {
    let mut dropped = Vec::new();
    let mut dependent = 0;
    for (r, v) in verdicts.iter().enumerate() {
        match *v {
            Verdict::Independent => {}
            Verdict::Dependent => dependent += 1,
            Verdict::Inconsistent { residual } => {
                let d = DroppedRow {
                    name: rows[r].name.clone(),
                    residual,
                };
                if r < user_rows {
                    inconsistent.push(d);
                } else {
                    dropped.push(d);
                }
            }
        }
    }
    (dropped, dependent)
}
