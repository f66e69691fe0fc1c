//! From a parsed [`TensorScene`] to a [`Problem`]: every check that serde cannot
//! do, each failing with the JSON path of the offending value.

use crate::tensor_scene::{EnergySpec, Net, NumberOrGrid, TensorScene};
use crate::{Error, Result};
use fairsurf::{
    Bend, GuideSurface, Measure, NormalField, Problem, SampleGrid, Stretch, TensorPatch, Vec3,
};

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
            built.guide = Some(g.surface.clone());
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

pub(crate) fn check_weight(path: &str, w: f64) -> Result<()> {
    if !w.is_finite() {
        return Err(Error::scene(
            path,
            format!("expected a finite number, got {w}"),
        ));
    }
    if w < 0.0 {
        return Err(Error::scene(
            path,
            format!("expected a weight ≥ 0, got {w}"),
        ));
    }
    Ok(())
}

/// Rows × columns of points `[x, y, z]` (or null where allowed), row-major.
pub(crate) fn parse_net(
    net: &Net,
    path: &str,
    (n, m): (usize, usize),
    allow_null: bool,
) -> Result<Vec<Option<Vec3>>> {
    if net.len() != n + 1 {
        return Err(Error::scene(
            path,
            format!("expected {} rows, got {}", n + 1, net.len()),
        ));
    }
    let mut out = Vec::with_capacity((n + 1) * (m + 1));
    for (i, row) in net.iter().enumerate() {
        if row.len() != m + 1 {
            return Err(Error::scene(
                format!("{path}[{i}]"),
                format!("expected {} points, got {}", m + 1, row.len()),
            ));
        }
        for (j, p) in row.iter().enumerate() {
            let here = || format!("{path}[{i}][{j}]");
            match p {
                None if allow_null => out.push(None),
                None => return Err(Error::scene(here(), "expected 3 numbers, got null")),
                Some(c) if c.len() != 3 => {
                    return Err(Error::scene(
                        here(),
                        format!("expected 3 numbers, got {}", c.len()),
                    ))
                }
                Some(c) => {
                    if let Some(k) = c.iter().position(|x| !x.is_finite()) {
                        return Err(Error::scene(
                            format!("{}[{k}]", here()),
                            "expected a finite number",
                        ));
                    }
                    if let Some(k) = c.iter().position(|x| x.abs() > MAX_COORDINATE) {
                        return Err(Error::scene(
                            format!("{}[{k}]", here()),
                            format!(
                                "{:e} is too large: coordinates must be at most {MAX_COORDINATE:e} \
                                 in magnitude (energies square them; scale the scene)",
                                c[k]
                            ),
                        ));
                    }
                    out.push(Some([c[0], c[1], c[2]]));
                }
            }
        }
    }
    Ok(out)
}

/// A complete net whose degree is given or read off its shape.
/// The Bézier field N of `energy.normal_field`; a field that is zero
/// everywhere is an error (it gives no direction).
pub(crate) fn normal_field_patch(net: &Net, degree: Option<[usize; 2]>) -> Result<TensorPatch> {
    let patch = parse_patch(net, degree, "energy.normal_field")?;
    if patch.points().iter().flatten().all(|&x| x == 0.0) {
        return Err(Error::scene(
            "energy.normal_field.control_points",
            "the field is zero everywhere and gives no direction: give the normals N to follow",
        ));
    }
    Ok(patch)
}

fn parse_patch(net: &Net, degree: Option<[usize; 2]>, path: &str) -> Result<TensorPatch> {
    let cp = format!("{path}.control_points");
    let [n, m] = match degree {
        Some(d) => d,
        None => {
            let rows = net.len();
            let cols = net.first().map_or(0, Vec::len);
            if rows == 0 || cols == 0 {
                return Err(Error::scene(
                    cp,
                    "expected at least one row of at least one point",
                ));
            }
            [rows - 1, cols - 1]
        }
    };
    if n > MAX_DEGREE || m > MAX_DEGREE {
        return Err(Error::scene(
            format!("{path}.degree"),
            format!("expected degrees ≤ {MAX_DEGREE}, got [{n}, {m}]"),
        ));
    }
    let pts = parse_net(net, &cp, (n, m), false)?;
    Ok(TensorPatch::new(
        n,
        m,
        pts.into_iter().map(|p| p.expect("no null")).collect(),
    ))
}

/// Per-sample weights: one number or a (np+1)×(mp+1) grid, each finite ≥ 0.
fn parse_weights(
    w: Option<&NumberOrGrid>,
    path: &str,
    (np, mp): (usize, usize),
) -> Result<Option<Vec<f64>>> {
    match w {
        None => Ok(None),
        Some(NumberOrGrid::Number(x)) => {
            check_weight(path, *x)?;
            Ok(Some(vec![*x; (np + 1) * (mp + 1)]))
        }
        Some(NumberOrGrid::Grid(rows)) => {
            if rows.len() != np + 1 {
                return Err(Error::scene(
                    path,
                    format!("expected {} rows (grid[0] + 1), got {}", np + 1, rows.len()),
                ));
            }
            let mut out = Vec::with_capacity((np + 1) * (mp + 1));
            for (i, row) in rows.iter().enumerate() {
                if row.len() != mp + 1 {
                    return Err(Error::scene(
                        format!("{path}[{i}]"),
                        format!(
                            "expected {} numbers (grid[1] + 1), got {}",
                            mp + 1,
                            row.len()
                        ),
                    ));
                }
                for (j, &x) in row.iter().enumerate() {
                    check_weight(&format!("{path}[{i}][{j}]"), x)?;
                    out.push(x);
                }
            }
            Ok(Some(out))
        }
    }
}

/// Which points of a `rows × cols` net are free: the outer `fixed_rings`
/// fixed and the rest free, or the null ones and `free_points`. Errors
/// name the path; `shape` ends the message for too many rings ("degree
/// [n, m]: both degrees must be at least" and 2k follows).
pub(crate) fn free_mask(
    fixed_rings: Option<usize>,
    free_points: Option<&[[usize; 2]]>,
    given: &[Option<Vec3>],
    (rows, cols): (usize, usize),
    shape: &str,
) -> Result<Vec<bool>> {
    let at = |k: usize| (k / cols, k % cols);
    let mut free: Vec<bool> = given.iter().map(Option::is_none).collect();
    if let Some(k) = fixed_rings {
        if k == 0 {
            return Err(Error::scene(
                "fixed_rings",
                "expected k ≥ 1 (omit fixed_rings to fix exactly the given points)",
            ));
        }
        if free_points.is_some() {
            return Err(Error::scene(
                "free_points",
                "cannot be combined with fixed_rings",
            ));
        }
        if rows <= 2 * k || cols <= 2 * k {
            return Err(Error::scene(
                "fixed_rings",
                format!(
                    "{k} fixed ring(s) leave no free control point at {shape} {}",
                    2 * k
                ),
            ));
        }
        for (q, f) in free.iter_mut().enumerate() {
            let (i, j) = at(q);
            let ring = i.min(j).min(rows - 1 - i).min(cols - 1 - j);
            *f = ring >= k;
            if !*f && given[q].is_none() {
                return Err(Error::scene(
                    format!("surface.control_points[{i}][{j}]"),
                    format!("is null but lies in the {k} fixed ring(s); give its value"),
                ));
            }
        }
    }
    for (q, &[i, j]) in free_points.into_iter().flatten().enumerate() {
        if i >= rows || j >= cols {
            return Err(Error::scene(
                format!("free_points[{q}]"),
                format!("[{i}, {j}] is outside the {rows} × {cols} net"),
            ));
        }
        free[i * cols + j] = true;
    }
    if !free.contains(&true) {
        return Err(Error::scene(
            "surface.control_points",
            "no free control point: mark free points with null, list them in free_points, or set fixed_rings",
        ));
    }
    Ok(free)
}

/// The sample grid of `energy.sampling`, each count 1 to [`MAX_GRID`].
pub(crate) fn sample_grid(sampling: Option<&crate::SamplingSpec>) -> Result<Option<SampleGrid>> {
    let Some(s) = sampling else {
        return Ok(None);
    };
    for (k, d) in s.grid.into_iter().enumerate() {
        if d == 0 || d > MAX_GRID {
            return Err(Error::scene(
                format!("energy.sampling.grid[{k}]"),
                format!("expected 1 to {MAX_GRID}, got {d}"),
            ));
        }
    }
    Ok(Some(SampleGrid::new(s.grid[0], s.grid[1])))
}

/// A normal field as a scene gives it: a Bézier patch, or a B-spline on
/// its own knots (B-spline scenes).
enum Field {
    Bezier(TensorPatch),
    Spline(fairsurf::bspline::BSplineSurface),
}

impl Field {
    /// N at (u, v) of [0, 1]² (a B-spline's domain mapped onto it).
    fn eval01(&self, u: f64, v: f64) -> Vec3 {
        match self {
            Field::Bezier(p) => p.eval(u, v),
            Field::Spline(s) => fairsurf::ParamSurface::eval_unit(s, u, v),
        }
    }
}

/// The normal-field term of `energy.normal_field` and `energy.sampling`
/// (the same rules for every surface kind): a Bézier field — or `spline`,
/// a B-spline scene's field on its own knots (its net already read from
/// the spec) — integrated exactly without sampling; with sampling, its
/// normals at the samples or `normal_samples`, and `normal_weights`.
/// Errors name the JSON path.
pub(crate) fn normal_field_term(
    normal_field: Option<&crate::NormalFieldSpec>,
    spline: Option<fairsurf::bspline::BSplineSurface>,
    sampling: Option<&crate::SamplingSpec>,
    grid: Option<SampleGrid>,
) -> Result<Option<NormalField>> {
    let field = match normal_field {
        Some(f) => {
            check_weight("energy.normal_field.weight", f.weight)?;
            match (&f.control_points, spline) {
                (_, Some(s)) => Some((f.weight, Some(Field::Spline(s)))),
                (Some(cp), None) => Some((f.weight, Some(Field::Bezier(normal_field_patch(cp, f.degree)?)))),
                (None, None) if sampling.is_some_and(|s| s.normal_samples.is_some()) => {
                    Some((f.weight, None))
                }
                (None, None) => {
                    return Err(Error::scene(
                        "energy.normal_field.control_points",
                        "required (the Bézier field N), unless energy.sampling.normal_samples gives the normals",
                    ))
                }
            }
        }
        None if sampling.is_some_and(|s| s.normal_samples.is_some()) => Some((1.0, None)),
        None => None,
    };
    if let (None, Some(s)) = (&field, sampling) {
        if s.normal_weights.is_some() {
            return Err(Error::scene(
                "energy.sampling.normal_weights",
                "needs energy.normal_field or energy.sampling.normal_samples",
            ));
        }
    }
    let Some((weight, patch)) = field else {
        return Ok(None);
    };
    let Some(g) = grid else {
        return Ok(Some(
            match patch.expect("without sampling the field has control points") {
                Field::Bezier(p) => NormalField::new(weight, p),
                Field::Spline(s) => NormalField::spline(weight, s),
            },
        ));
    };
    let s = sampling.expect("grid comes from sampling");
    let (np, mp) = g.size();
    let normals: Vec<Vec3> = match &s.normal_samples {
        Some(ns) => {
            let pts = parse_net(ns, "energy.sampling.normal_samples", (np, mp), false)?;
            pts.into_iter()
                .enumerate()
                .map(|(k, p)| {
                    let p = p.expect("no null");
                    if fairsurf::vector::norm(p) == 0.0 {
                        return Err(Error::scene(
                            format!(
                                "energy.sampling.normal_samples[{}][{}]",
                                k / (mp + 1),
                                k % (mp + 1)
                            ),
                            "is the zero vector and has no direction",
                        ));
                    }
                    Ok(p)
                })
                .collect::<Result<_>>()?
        }
        None => {
            let f = patch.expect("field given when samples are not");
            (0..g.len())
                .map(|k| {
                    let (u, v) = g.param(k);
                    let p = f.eval01(u, v);
                    if fairsurf::vector::normalize(p).is_none() {
                        return Err(Error::scene(
                            "energy.normal_field.control_points",
                            format!("N vanishes at sample (u, v) = ({u}, {v}), so it has no direction there"),
                        ));
                    }
                    Ok(p)
                })
                .collect::<Result<_>>()?
        }
    };
    let weights = parse_weights(
        s.normal_weights.as_ref(),
        "energy.sampling.normal_weights",
        (np, mp),
    )?;
    Ok(Some(NormalField::sampled(weight, g, normals, weights)))
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
