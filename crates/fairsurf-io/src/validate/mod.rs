//! From a parsed [`TensorScene`] to a [`Problem`]: every check that serde cannot
//! do, each failing with the JSON path of the offending value.

use crate::tensor_scene::{EnergySpec, Net, NumberOrGrid, TensorScene};
use crate::{Error, Result};
use fairsurf::{
    Bend, GuideSurface, Measure, NormalField, Problem, SampleGrid, Stretch, TensorPatch, Vec3,
};

mod field;
mod parse;
pub(crate) use field::*;
pub(crate) use parse::*;

/// Largest accepted coordinate magnitude: energies square coordinates and
/// multiply them by powers of the degree, which must stay finite in double
/// precision (at 1e154 they overflowed to NaN).
pub const MAX_COORDINATE: f64 = 1e100;

/// Largest accepted degree: the dense system of a degree-40 patch with a
/// normal field has 3·39² ≈ 4,600 unknowns (a 170 MB matrix).
pub const MAX_DEGREE: usize = 40;
/// Largest accepted sample grid size per direction.
pub const MAX_GRID: usize = 2000;

/// What solving a scene means.
#[derive(Debug)]
pub enum Plan {
    /// Minimize the energy of this problem.
    Minimize(Problem),
    /// Build the surface from the boundary of this net (points the
    /// construction does not read are zero).
    Construct(fairsurf::harmonic::Method, TensorPatch),
}

/// A validated scene, ready to solve.
#[derive(Debug)]
pub struct Built {
    /// The problem or the construction.
    pub plan: Plan,
    /// The given net when it has no null: the initial surface.
    pub initial: Option<TensorPatch>,
    /// Whether each control point is free, row-major.
    pub free: Vec<bool>,
    /// The normal-field term, for measuring the result against it.
    pub normal_field: Option<NormalField>,
    /// Grid on which to measure the normal deviation.
    pub deviation_grid: (usize, usize),
    /// The guide surface S, as used.
    pub guide: Option<TensorPatch>,
    /// What was assumed where the scene was silent.
    pub notes: Vec<String>,
}

impl Built {
    fn new(plan: Plan, initial: Option<TensorPatch>, free: Vec<bool>) -> Self {
        Built {
            plan,
            initial,
            free,
            normal_field: None,
            deviation_grid: (32, 32),
            guide: None,
            notes: Vec::new(),
        }
    }
}

/// The given net as a patch when it has no null.
fn initial_patch(given: &[Option<Vec3>], (n, m): (usize, usize)) -> Option<TensorPatch> {
    given
        .iter()
        .all(Option::is_some)
        .then(|| TensorPatch::new(n, m, given.iter().map(|p| p.expect("all given")).collect()))
}

impl TensorScene {
    /// Checks the scene and builds its problem.
    pub fn build(&self) -> Result<Built> {
        let t = self.tensor();
        let [n, m] = self.checked_degree()?;
        let given = parse_net(&t.control_points, "surface.control_points", (n, m), true)?;
        if let Some(method) = self.method.construction() {
            return self.build_construction(method, &given, (n, m));
        }
        if self.least_squares {
            return Err(Error::scene(
                "least_squares",
                "only applies to method \"harmonic\" or \"biharmonic\"",
            ));
        }
        let free = self.free_mask(&given, (n, m))?;
        let initial = initial_patch(&given, (n, m));
        let known: Vec<Option<Vec3>> = given
            .iter()
            .zip(&free)
            .map(|(p, &f)| if f { None } else { *p })
            .collect();
        let mut problem = Problem::new((n, m)).with_known(known)?;
        // The plan is replaced by the finished problem below.
        let mut built = Built::new(Plan::Minimize(Problem::new((n, m))), initial, free);
        self.add_terms(&mut problem, &mut built, &given)?;
        for (i, o) in self.operators.iter().enumerate() {
            problem = problem.with_operator(crate::operators::tensor_operator(o, i)?);
        }
        for (i, c) in self.constraints.iter().enumerate() {
            let (name, constraint) = c.build(i)?;
            problem = problem.with_constraint(name, constraint);
        }
        built.plan = Plan::Minimize(problem);
        Ok(built)
    }

    /// A construction from the boundary: checks that the scene says nothing
    /// the construction would ignore and gives every point it reads.
    fn build_construction(
        &self,
        method: fairsurf::harmonic::Method,
        given: &[Option<Vec3>],
        (n, m): (usize, usize),
    ) -> Result<Built> {
        use fairsurf::harmonic::Method as M;
        let name = method.name();
        let unused = |path: &str| {
            Err(Error::scene(
                path,
                format!("is not used by method \"{name}\" (it fixes its own points and has no energy); remove it"),
            ))
        };
        if self.fixed_rings.is_some() {
            return unused("fixed_rings");
        }
        if self.free_points.is_some() {
            return unused("free_points");
        }
        if !self.energy.is_empty() {
            return unused("energy");
        }
        if !self.operators.is_empty() {
            return unused("operators");
        }
        if !self.constraints.is_empty() {
            return unused("constraints");
        }
        if self.least_squares && !matches!(method, M::Harmonic | M::Biharmonic) {
            return Err(Error::scene(
                "least_squares",
                format!("only applies to method \"harmonic\" or \"biharmonic\" (a {name} always exists)"),
            ));
        }
        let min = if method == M::BiharmonicMask { 4 } else { 2 };
        for (k, d) in [n, m].into_iter().enumerate() {
            if d < min {
                return Err(Error::scene(
                    format!("surface.degree[{k}]"),
                    format!("method \"{name}\" needs degrees ≥ {min}, got {d}"),
                ));
            }
        }
        // Which points the construction reads, and which it determines.
        let ring = |i: usize, j: usize| i.min(j).min(n - i).min(m - j);
        let read = |i: usize, j: usize| match method {
            M::Harmonic => i == 0 || i == n,
            M::Biharmonic | M::HarmonicMask => ring(i, j) == 0,
            M::BiharmonicMask => ring(i, j) <= 1,
        };
        let what = match method {
            M::Harmonic => "the first and last rows",
            M::Biharmonic | M::HarmonicMask => "the boundary ring",
            M::BiharmonicMask => "the two outer rings",
        };
        let mut points = Vec::with_capacity(given.len());
        let mut free = Vec::with_capacity(given.len());
        for (k, p) in given.iter().enumerate() {
            let (i, j) = (k / (m + 1), k % (m + 1));
            if read(i, j) && p.is_none() {
                return Err(Error::scene(
                    format!("surface.control_points[{i}][{j}]"),
                    format!("is null, but method \"{name}\" is built from {what}: give its value"),
                ));
            }
            free.push(!read(i, j));
            points.push(if read(i, j) {
                p.expect("checked")
            } else {
                [0.0; 3]
            });
        }
        Ok(Built::new(
            Plan::Construct(method, TensorPatch::new(n, m, points)),
            initial_patch(given, (n, m)),
            free,
        ))
    }

    /// The surface as a patch when every control point is given (a result
    /// file, or a scene with no null), else an error naming the first null.
    pub fn surface_patch(&self) -> Result<TensorPatch> {
        let t = self.tensor();
        let [n, m] = self.checked_degree()?;
        let pts = parse_net(&t.control_points, "surface.control_points", (n, m), true)?;
        if let Some(k) = pts.iter().position(Option::is_none) {
            return Err(Error::scene(
                format!("surface.control_points[{}][{}]", k / (m + 1), k % (m + 1)),
                "is null: solve the scene first and use the result file",
            ));
        }
        Ok(TensorPatch::new(
            n,
            m,
            pts.into_iter().map(|p| p.expect("checked")).collect(),
        ))
    }

    /// The surface's degree, each 1 to [`MAX_DEGREE`]: what every command
    /// (solve, analyse, eval, export, render) accepts, so that no entry
    /// point allocates for a degree the solver refuses.
    fn checked_degree(&self) -> Result<[usize; 2]> {
        let [n, m] = self.tensor().degree;
        for (k, d) in [n, m].into_iter().enumerate() {
            if d == 0 || d > MAX_DEGREE {
                return Err(Error::scene(
                    format!("surface.degree[{k}]"),
                    format!("expected 1 to {MAX_DEGREE}, got {d}"),
                ));
            }
        }
        Ok([n, m])
    }

    fn free_mask(&self, given: &[Option<Vec3>], (n, m): (usize, usize)) -> Result<Vec<bool>> {
        free_mask(
            self.fixed_rings,
            self.free_points.as_deref(),
            given,
            (n + 1, m + 1),
            &format!("degree [{n}, {m}]: both degrees must be at least"),
        )
    }

    fn add_terms(&self, pb: &mut Problem, built: &mut Built, given: &[Option<Vec3>]) -> Result<()> {
        let e: &EnergySpec = &self.energy;
        let [n, m] = self.tensor().degree;
        let grid = sample_grid(e.sampling.as_ref())?;
        let measure = grid.map_or(Measure::Exact, Measure::Grid);
        let (stretch, bend, note) = default_weights(e.stretch, e.bend, self.fixed_rings);
        built.notes.extend(note.map(String::from));
        if let Some(w) = stretch {
            check_weight("energy.stretch", w)?;
            pb.push_term(Box::new(Stretch::new(w).with_measure(measure.clone())));
        }
        if let Some(w) = bend {
            check_weight("energy.bend", w)?;
            pb.push_term(Box::new(Bend::new(w).with_measure(measure.clone())));
        }
        if let Some(nf) = self.normal_term(grid, built)? {
            built.normal_field = Some(nf.clone());
            pb.push_term(Box::new(nf));
        }
        if let Some(g) = self.guide_term(grid, given, (n, m))? {
            built.guide = g.bezier().ok().cloned();
            pb.push_term(Box::new(g));
        }
        Ok(())
    }

    fn normal_term(
        &self,
        grid: Option<SampleGrid>,
        built: &mut Built,
    ) -> Result<Option<NormalField>> {
        if let Some(g) = grid {
            built.deviation_grid = g.size();
        }
        normal_field_term(
            self.energy.normal_field.as_ref(),
            None,
            self.energy.sampling.as_ref(),
            grid,
        )
    }

    fn guide_term(
        &self,
        grid: Option<SampleGrid>,
        given: &[Option<Vec3>],
        (n, m): (usize, usize),
    ) -> Result<Option<GuideSurface>> {
        let e = &self.energy;
        let Some(gs) = &e.guide_surface else {
            if e.sampling
                .as_ref()
                .is_some_and(|s| s.guide_weights.is_some())
            {
                return Err(Error::scene(
                    "energy.sampling.guide_weights",
                    "needs energy.guide_surface",
                ));
            }
            return Ok(None);
        };
        check_weight("energy.guide_surface.weight", gs.weight)?;
        let surface = match &gs.control_points {
            Some(cp) => {
                let p = parse_patch(cp, gs.degree, "energy.guide_surface")?;
                let (a, b) = p.degree();
                if a > n || b > m {
                    return Err(Error::scene(
                        "energy.guide_surface.degree",
                        format!("expected at most the surface's degree [{n}, {m}], got [{a}, {b}]"),
                    ));
                }
                p
            }
            None => {
                if let Some(k) = given.iter().position(Option::is_none) {
                    return Err(Error::scene(
                        "energy.guide_surface.control_points",
                        format!(
                            "required because surface.control_points[{}][{}] is null (the default guide surface is the initial net)",
                            k / (m + 1),
                            k % (m + 1)
                        ),
                    ));
                }
                TensorPatch::new(n, m, given.iter().map(|p| p.expect("checked")).collect())
            }
        };
        let mut term = GuideSurface::new(gs.weight, surface);
        if let Some(g) = grid {
            let s = e.sampling.as_ref().expect("grid from sampling");
            let w = parse_weights(
                s.guide_weights.as_ref(),
                "energy.sampling.guide_weights",
                g.size(),
            )?;
            term = term.with_measure(Measure::Grid(g), w);
        }
        Ok(Some(term))
    }
}

/// The internal energy's weights as a scene gives them, and the note when
/// a default was taken: with neither stretch nor bend given, bend 1 when
/// two or more rings are fixed (G1 data: the thin plate), else stretch 1
/// (the membrane). The one rule for tensor and B-spline scenes and the
/// editor's sliders.
pub fn default_weights(
    stretch: Option<f64>,
    bend: Option<f64>,
    fixed_rings: Option<usize>,
) -> (Option<f64>, Option<f64>, Option<&'static str>) {
    match (stretch, bend) {
        (None, None) if fixed_rings.unwrap_or(0) >= 2 => (
            None,
            Some(1.0),
            Some("energy.bend defaulted to 1 (no stretch or bend given, fixed_rings ≥ 2)"),
        ),
        (None, None) => (
            Some(1.0),
            None,
            Some("energy.stretch defaulted to 1 (no stretch or bend given)"),
        ),
        given => (given.0, given.1, None),
    }
}
