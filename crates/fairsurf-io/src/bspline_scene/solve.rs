//! A B-spline scene read into the library's problem (knots, net, free
//! points, refinement, energy, guide, constraints, operators), solved, and
//! measured as it is (`analyse`).

use super::*;

impl BSplineScene {
    /// Parses a scene; errors name the JSON path.
    pub fn from_json(text: &str) -> Result<BSplineScene> {
        crate::scene::parse_with_path(text)
    }

    /// The JSON Schema of B-spline scene files.
    pub fn json_schema() -> Value {
        serde_json::to_value(schemars::schema_for!(BSplineScene)).expect("a schema serializes")
    }

    /// The knot vectors; errors name `surface.degree[k]` or `surface.knots[k]`.
    pub(super) fn knot_vectors(&self) -> Result<(KnotVector, KnotVector)> {
        let s = &self.surface;
        let one = |k: usize| -> Result<KnotVector> {
            let p = s.degree[k];
            if !(1..=MAX_DEGREE).contains(&p) {
                return Err(Error::scene(
                    format!("surface.degree[{k}]"),
                    format!("must be 1 to {MAX_DEGREE}, got {p} (for more freedom, add knots)"),
                ));
            }
            KnotVector::new(p, s.knots[k].clone())
                .map_err(|e| Error::scene(format!("surface.knots[{k}]"), e.to_string()))
        };
        Ok((one(0)?, one(1)?))
    }

    /// The net as given (`None` for null), checked against the knots.
    pub(super) fn given(&self) -> Result<(KnotVector, KnotVector, Vec<Option<Vec3>>)> {
        let (u, v) = self.knot_vectors()?;
        let (cu, cv) = (u.count(), v.count());
        let given = parse_net(
            &self.surface.control_points,
            "surface.control_points",
            (cu - 1, cv - 1),
            true,
        )
        .map_err(|e| match e {
            Error::Scene { path, message } => Error::Scene {
                path,
                message: format!("{message} (the knots give {cu} × {cv} control points)"),
            },
            e => e,
        })?;
        Ok((u, v, given))
    }

    /// The surface as given (a result file's), every point required.
    pub fn surface(&self) -> Result<BSplineSurface> {
        let (u, v, given) = self.given()?;
        let cv = v.count();
        let points = every_point(
            &given,
            cv,
            "is null: there is no surface to measure until it is solved",
        )?;
        Ok(BSplineSurface::new(u, v, points)?)
    }

    /// The problem the scene describes; errors name the field.
    pub fn problem(&self) -> Result<BSplineProblem> {
        let (u, v, given) = self.given()?;
        // Free points without a value start anywhere: the energy is quadratic.
        let points = given.iter().map(|p| p.unwrap_or([0.0; 3])).collect();
        let mut surface = BSplineSurface::new(u, v, points)?;
        let mut given = given;
        if let Some(r) = self.refine.as_ref().filter(|r| !r.is_noop()) {
            // Knot insertion mixes neighbouring points of a row; the outer
            // rings of the refined net come from the given rings alone, so
            // `fixed_rings` says which refined points are free.
            if self.fixed_rings.is_none() {
                return Err(Error::scene(
                    "refine",
                    "needs fixed_rings: the refined net's free points follow from the rings",
                ));
            }
            surface = refined(&surface, r)?;
            given = surface.points().iter().map(|&p| Some(p)).collect();
        }
        let (cu, cv) = surface.counts();
        let surface_domain = (surface.knots().0.domain(), surface.knots().1.domain());
        let free = free_mask(
            self.fixed_rings,
            self.free_points.as_deref(),
            &given,
            (cu, cv),
            &format!("{cu} × {cv} control points: both counts must be above"),
        )?;
        let e = &self.energy;
        let (stretch, bend, _) =
            crate::validate::default_weights(e.stretch, e.bend, self.fixed_rings);
        let mut problem = BSplineProblem::from_surface(surface).with_free(free)?;
        if let Some(w) = stretch {
            check_weight("energy.stretch", w)?;
            problem = problem.with_term(Stretch::new(w));
        }
        if let Some(w) = bend {
            check_weight("energy.bend", w)?;
            problem = problem.with_term(Bend::new(w));
        }
        if e.sampling
            .as_ref()
            .is_some_and(|s| s.guide_weights.is_some())
        {
            return Err(Error::scene(
                "energy.sampling.guide_weights",
                "B-spline scenes integrate the guide surface exactly; per-sample guide weights \
                 are for tensor scenes",
            ));
        }
        let grid = crate::validate::sample_grid(e.sampling.as_ref())?;
        let domain = [surface_domain.0, surface_domain.1];
        let spline = match &e.normal_field {
            Some(f) => f.spline(problem.surface())?,
            None => None,
        };
        if let Some(field) = crate::validate::normal_field_term(
            e.normal_field
                .as_deref()
                .map(BSplineNormalFieldSpec::bezier)
                .as_ref(),
            spline,
            e.sampling.as_ref(),
            grid,
        )? {
            if let NormalGuide::Spline(f) = &field.guide {
                problem
                    .surface()
                    .check_domain(f, "normal field")
                    .map_err(|err| Error::scene("energy.normal_field", err.to_string()))?;
            }
            problem = problem.with_term(field);
        }
        if let Some(g) = &e.guide_surface {
            check_weight("energy.guide_surface.weight", g.weight)?;
            let guide = match g.own_surface(domain)? {
                Some(own) => {
                    problem
                        .surface()
                        .check_domain(&own, "guide surface")
                        .map_err(|err| Error::scene("energy.guide_surface", err.to_string()))?;
                    own
                }
                None => {
                    let points = match &g.control_points {
                        Some(net) => {
                            let (u, v, _) = self.given()?;
                            let (gu, gv) = (u.count(), v.count());
                            let pts: Vec<Vec3> = parse_net(
                                net,
                                "energy.guide_surface.control_points",
                                (gu - 1, gv - 1),
                                false,
                            )?
                            .into_iter()
                            .map(|p| p.expect("no null"))
                            .collect();
                            match &self.refine {
                                Some(r) => refined(&BSplineSurface::new(u, v, pts)?, r)?
                                    .points()
                                    .to_vec(),
                                None => pts,
                            }
                        }
                        None => every_point(
                            &given,
                            cv,
                            "is null, but energy.guide_surface has no control_points and \
                             defaults to the initial net: give this point or the guide's net",
                        )?,
                    };
                    let (ku, kv) = problem.surface().knots();
                    BSplineSurface::new(ku.clone(), kv.clone(), points)?
                }
            };
            problem = problem.with_term(GuideSurface::spline(g.weight, guide));
        }
        let (ku, kv) = problem.surface().knots();
        let domain = [ku.domain(), kv.domain()];
        let [(u0, u1), (v0, v1)] = domain;
        let described = format!("the knot domain [{u0}, {u1}] × [{v0}, {v1}]");
        for (i, c) in self.constraints.iter().enumerate() {
            let (name, constraint) = c.build_in(i, domain, &described)?;
            problem = problem.with_constraint(name, constraint);
        }
        for (i, o) in self.operators.iter().enumerate() {
            let op = crate::operators::unchecked_operator(o, i)?;
            op.validate_on(problem.surface())
                .map_err(|e| Error::scene(format!("operators[{i}]"), e.to_string()))?;
            problem = problem.with_operator(op);
        }
        Ok(problem)
    }

    /// Validates and solves with default options.
    pub fn solve(&self) -> Result<SolvedBSplineScene> {
        self.solve_with(&SolveOptions::default())
    }

    /// Validates and solves; with `opts.analyse` the report carries the
    /// result's measures (area, functionals, |H|: [`BSplineSurface::measures`]),
    /// their time in `timings.analyse` and `timings.total`. `analyse` is
    /// the only option a B-spline solve reads (the others tune the Bézier
    /// patch's dense solve).
    pub fn solve_with(&self, opts: &SolveOptions) -> Result<SolvedBSplineScene> {
        self.solve_using(opts, None)
    }

    /// [`Self::solve_with`], reusing a factorization from `cache` when one
    /// fits (and keeping this one there): for a designer dragging points
    /// ([`fairsurf::FactorCache::solve_bspline`]).
    pub fn solve_cached(
        &self,
        opts: &SolveOptions,
        cache: &fairsurf::FactorCache,
    ) -> Result<SolvedBSplineScene> {
        self.solve_using(opts, Some(cache))
    }

    fn solve_using(
        &self,
        opts: &SolveOptions,
        cache: Option<&fairsurf::FactorCache>,
    ) -> Result<SolvedBSplineScene> {
        let problem = self.problem()?;
        let mut solution = match cache {
            Some(c) => c.solve_bspline(&problem)?,
            None => problem.solve()?,
        };
        let t = std::time::Instant::now();
        let normal_turn = if opts.analyse {
            let measures = solution.surface.measures();
            let turn = measures.normal_turn;
            let r = &mut solution.report;
            r.measures = Some(measures);
            let seconds = t.elapsed().as_secs_f64();
            r.timings.analyse += seconds;
            r.timings.total += seconds;
            turn
        } else {
            solution.surface.largest_normal_turn()
        };
        Ok(SolvedBSplineScene {
            scene: self.clone(),
            guide_points: problem
                .terms()
                .iter()
                .find_map(|t| match t.integrand() {
                    // A guide on the solved knots (not one on its own).
                    Some(Integrand::GuideSpline { surface, .. })
                        if surface.knots() == problem.surface().knots() =>
                    {
                        Some(surface.points().to_vec())
                    }
                    _ => None,
                })
                .unwrap_or_default(),
            normal_field: problem.normal_field().map(Box::new),
            free: problem.free().to_vec(),
            solution,
            normal_turn,
        })
    }

    /// Area (the Bézier pieces' adaptive Gauss–Legendre), the Dirichlet and
    /// biharmonic functionals (exact), spans and control points of the
    /// surface as given.
    pub fn analyse(&self) -> Result<crate::Measures> {
        let s = self.surface()?;
        let (cu, cv) = s.counts();
        let (su, sv) = (s.knots().0.spans().len(), s.knots().1.spans().len());
        Ok(vec![
            ("area".into(), json!(s.area())),
            ("Dirichlet".into(), json!(s.dirichlet())),
            ("biharmonic".into(), json!(s.biharmonic())),
            (
                "degree".into(),
                json!(format!("{} × {}", s.degree().0, s.degree().1)),
            ),
            ("spans".into(), json!(format!("{su} × {sv}"))),
            ("control points".into(), json!(format!("{cu} × {cv}"))),
        ])
    }
}

/// Every point of the net, or an error naming the first null one and `why`.
pub(super) fn every_point(given: &[Option<Vec3>], cv: usize, why: &str) -> Result<Vec<Vec3>> {
    given
        .iter()
        .enumerate()
        .map(|(k, p)| {
            p.ok_or_else(|| {
                Error::scene(
                    format!("surface.control_points[{}][{}]", k / cv, k % cv),
                    why,
                )
            })
        })
        .collect()
}
