//! Constrained variational design of a triangular surface (Veltkamp &
//! Wesselink §6, eq. 32–33):
//!
//! ```text
//! minimize   E(P) = α·E_stretch + β·E_bend = ½ Σ_c P_cᵀ K P_c     (eq. 6–7, 25–27)
//! subject to F P = G                                             (eq. 31)
//! ```
//!
//! In order: curve constraints refine the mesh so that chains of patch
//! edges interpolate the curves (§4.2) and fix those edges' control points;
//! fixed control points (the user's and the curves') are eliminated; the
//! remaining rows — the user's interpolation constraints first, then the
//! default continuity conditions (§4.3) — are classified by sparse
//! elimination, so dependent rows are reduced and a continuity condition
//! that contradicts an interpolation constraint gives way (reported as
//! dropped); the independent rows and the energy form a KKT system solved
//! by regularized sparse LDLᵀ with iterative refinement.
//!
//! The report says how good the result is: energies, the stationarity
//! residual (the gradient of the Lagrangian), every constraint's violation,
//! what was reduced, dropped or found inconsistent, the largest normal
//! angle across interior edges, and timings.

use super::constraint::{Constraint, NamedConstraint};
use super::continuity::{max_edge_normal_angle, Continuity};
use super::energy::InternalEnergy;
use super::reduce::{classify, SparseRow, Verdict};
use super::refine::{check_point, embed_curve, DomainPoint, Refinement};
use super::surface::TriSurface;
use crate::analysis::largest_tri_normal_turn;
use crate::check::triangle::{TriEnergy, Verify};
use crate::check::Check;
use crate::constraint::{ConstraintOutcome, Row};
use crate::energy::{EnergyTerm, Integrand, Measure, BEND_PATTERNS, STRETCH_PATTERNS};
use crate::operator::newton::{add_quadratic, newton, FreeResiduals, NewtonReport};
use crate::operator::triangle::Located;
use crate::operator::{OperatorOutcome, Residual};
use crate::solve::kkt::{same_terms, shared_rows, try_kkt, KktFactor, KktInfo, KktOutcome};
use crate::solve::{SolveReport, SurfaceKind, TermEnergy, Timings, TriFigures};
use crate::vec3::{norm, sub, Vec3};
use crate::{BezierCurve, Error, Result};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use std::time::Instant;

/// The relative pivot tolerances tried, in order, when classifying the
/// continuity rows (see step 5 of [`TriProblem::solve`]).
const ROW_TOLERANCES: [f64; 3] = [1e-9, 1e-6, 1e-3];

mod pipeline;

/// A curve the surface must pass through (§4.2): patch edges are made to
/// interpolate it ([`super::embed_curve`]).
#[derive(Clone, Debug, PartialEq)]
pub struct CurveConstraint {
    /// How reports call it.
    pub name: String,
    /// The curve, of degree at most the surface's.
    pub curve: BezierCurve,
    /// Where in the (original) domain it starts.
    pub from: DomainPoint,
    /// Where it ends.
    pub to: DomainPoint,
    /// The triangles it runs through, first to last (None: a shortest
    /// path). Indices of the surface as refined by the curves before it; a
    /// split triangle's index stays with its first child.
    pub through: Option<Vec<usize>>,
}

/// A triangular surface, its energy terms, constraints, curves, continuity
/// and operators: the core's [`crate::Problem`] over a [`TriSurface`].
pub type TriProblem = crate::Problem<TriSurface>;

/// What only a triangular surface's problem holds.
#[derive(Clone, Debug, Default)]
pub struct TriExtra {
    /// Curves the surface interpolates (§4.2).
    pub(crate) curves: Vec<CurveConstraint>,
    /// The continuity conditions between the patches.
    pub(crate) continuity: Continuity,
}

impl SurfaceKind for TriSurface {
    type At = DomainPoint;
    type Place = crate::operator::Place;
    type Extra = TriExtra;
}

/// The factored KKT matrix of a solve, kept to solve problems that differ
/// only in the right-hand side: the values of fixed points, point targets,
/// plane offsets, operator targets (see [`crate::FactorCache`]).
pub struct TriFactored {
    kkt: KktFactor,
    /// The continuity rows' pivot tolerance that classified them.
    tolerance: f64,
    /// Every constraint row's coefficients over the free coordinates (the
    /// kept rows' and the others'), user rows first.
    rows: Vec<Vec<(usize, f64)>>,
    /// How many of them are the user's.
    user_rows: usize,
    /// The free coordinates (3g + c for point g, coordinate c) in the
    /// factor's order.
    free: Vec<usize>,
    /// Whether a fresh solve of another right-hand side would come to it
    /// (its rows classified at the first tolerance, or the looser ones
    /// needed for want of a factorization, not for this right-hand side's
    /// sake): only then is it kept for later solves ([`crate::FactorCache`]).
    /// Either way it is the matrix of this solve's kept rows, which the
    /// fill's descent on W steps along.
    pub(crate) reusable: bool,
}

impl TriFactored {
    /// About how many bytes it holds.
    pub fn bytes(&self) -> usize {
        self.kkt.bytes() + 16 * self.rows.iter().map(Vec::len).sum::<usize>() + 8 * self.free.len()
    }

    /// The free coordinates (3g + c for point g, coordinate c) in the
    /// order of [`Self::projected`]'s vectors.
    pub(crate) fn free(&self) -> &[usize] {
        &self.free
    }

    /// sᵀHs over the free coordinates (H the thin plate's, stored whole).
    pub(crate) fn h_norm2(&self, s: &[f64]) -> f64 {
        let h = &self.kkt.h;
        (0..h.ncols())
            .map(|j| {
                let col: f64 = h
                    .row_idx_of_col(j)
                    .zip(h.val_of_col(j))
                    .map(|(i, v)| v * s[i])
                    .sum();
                col * s[j]
            })
            .sum()
    }

    /// r = Z(ZᵀHZ)⁻¹Zᵀq over the free coordinates (Z a basis of the kept
    /// rows' null space), from [H Fᵀ; F 0][r; μ] = [q; 0]: the step that
    /// minimizes ½rᵀHr − qᵀr along the rows. None when the solve fails.
    pub(crate) fn projected(&self, q: &[f64]) -> Option<Vec<f64>> {
        let b: Vec<f64> = q.iter().map(|v| -v).collect();
        let g = vec![0.0; self.kkt.row_count()];
        self.kkt.solve(&b, &g).ok().map(|s| s.x)
    }

    /// Whether both are of the same KKT matrix: the same H and rows (the
    /// kept rows follow from the rows at the same tolerance).
    pub(crate) fn same_as(&self, other: &TriFactored) -> bool {
        self.tolerance == other.tolerance
            && self.made_for(
                &other.kkt.h,
                other.rows.iter().map(Vec::as_slice),
                other.user_rows,
            )
    }

    /// Whether H and every row's coefficients are those it was made for,
    /// value for value (H first: the cheap refusal).
    fn made_for<'r>(
        &self,
        h: &SparseColMat<usize, f64>,
        rows: impl ExactSizeIterator<Item = &'r [(usize, f64)]>,
        user_rows: usize,
    ) -> bool {
        self.kkt.h_is(h) && self.rows_match(rows, user_rows)
    }

    /// Whether every row's coefficients are those it was made for.
    fn rows_match<'r>(
        &self,
        rows: impl ExactSizeIterator<Item = &'r [(usize, f64)]>,
        user_rows: usize,
    ) -> bool {
        user_rows == self.user_rows
            && rows.len() == self.rows.len()
            && rows.zip(&self.rows).all(|(a, b)| same_terms(a, b))
    }
}

impl std::fmt::Debug for TriFactored {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TriFactored")
            .field("bytes", &self.bytes())
            .field("tolerance", &self.tolerance)
            .finish_non_exhaustive()
    }
}

/// Which factorization solved a problem.
pub(crate) enum Factor {
    /// None (nothing was free).
    None,
    /// The kept one at this index.
    Reused(usize),
    /// A new one.
    New(Box<TriFactored>),
}

/// A constraint row left out of the solve.
#[derive(Clone, Debug, PartialEq)]
pub struct DroppedRow {
    /// The row's name (constraint, equation, coordinate).
    pub name: String,
    /// How far the constraints kept force it off (its reduced right-hand
    /// side over its largest coefficient).
    pub residual: f64,
}

/// Wall-clock seconds per phase of a solve, and how many classifications
/// and factorizations it made, gathered into the report's
/// [`crate::Timings`] and [`crate::TriFigures`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Phases {
    /// Mesh refinement for curve constraints.
    pub refine: f64,
    /// Energy matrix and constraint rows.
    pub assemble: f64,
    /// Row classification (dependent / inconsistent).
    pub classify: f64,
    /// KKT factorization and refinement.
    pub solve: f64,
    /// How many times the rows were classified.
    pub classifications: usize,
    /// How many KKT systems were factored (numerically).
    pub factorizations: usize,
}

/// The solved triangular surface (refined by curve constraints, if any)
/// and its report: the core's [`crate::Solution`] over a [`TriSurface`];
/// where the result's triangles lie in the problem's mesh and which points
/// were held are in its figures ([`TriFigures::origin`],
/// [`TriFigures::fixed`]).
pub type TriSolution = crate::Solution<TriSurface>;

impl crate::Solution<TriSurface> {
    /// The triangular figures of the report (mesh, rows, continuity
    /// residuals, edge angles): [`SolveReport::triangular`], which the
    /// triangular solve always fills.
    pub fn figures(&self) -> &TriFigures {
        self.report
            .triangular
            .as_ref()
            .expect("the triangular solve fills its figures")
    }

    /// The result's point at (`triangle`, `bary`) of the problem's own
    /// mesh: found in the result patch that came from that triangle (curve
    /// constraints split patches) and contains the point, evaluated there.
    /// None when no result patch came from it or contains the point.
    pub fn point_at(&self, triangle: usize, bary: [f64; 3]) -> Option<Vec3> {
        self.figures()
            .origin
            .iter()
            .enumerate()
            .filter(|(_, (from, _))| *from == triangle)
            .find_map(|(k, (_, [a, b, c]))| {
                // bary = c₀a + c₁b + c₂c with c₀ + c₁ + c₂ = 1, in the first
                // two coordinates of the original triangle.
                let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
                if det.abs() < 1e-14 {
                    return None;
                }
                let (px, py) = (bary[0] - a[0], bary[1] - a[1]);
                let c1 = (px * (c[1] - a[1]) - (c[0] - a[0]) * py) / det;
                let c2 = ((b[0] - a[0]) * py - px * (b[1] - a[1])) / det;
                let child = [1.0 - c1 - c2, c1, c2];
                (child.iter().all(|&x| x >= -1e-12) && k < self.surface.patch_count())
                    .then(|| self.surface.patch(k).eval(child))
            })
    }
}

/// A term as the triangular assembly takes it: the membrane or the thin
/// plate with its weight (Veltkamp & Wesselink eq. 6–7), or a term it
/// cannot integrate, refused by the solve.
#[derive(Clone, Debug, PartialEq)]
enum TriTerm {
    /// α and β added by the term.
    Weights { stretch: f64, bend: f64 },
    /// The term's name and what the triangular assembly takes instead.
    Refused {
        name: &'static str,
        expected: &'static str,
    },
}

impl TriTerm {
    /// What `term` adds, from its [`crate::EnergyTerm::integrand`].
    fn of(term: &dyn EnergyTerm) -> Self {
        let name = term.name();
        let refused = |expected| TriTerm::Refused { name, expected };
        match term.integrand() {
            Some(Integrand::Fairness {
                weight,
                measure,
                patterns,
            }) => {
                if *measure != Measure::Exact {
                    refused("the exact integral (sampled terms are for tensor surfaces)")
                } else if patterns == STRETCH_PATTERNS {
                    TriTerm::Weights {
                        stretch: weight,
                        bend: 0.0,
                    }
                } else if patterns == BEND_PATTERNS {
                    TriTerm::Weights {
                        stretch: 0.0,
                        bend: weight,
                    }
                } else {
                    refused("the membrane's or the thin plate's derivative patterns")
                }
            }
            None => refused("a term with an integrand (the triangular assembly reads it)"),
            Some(_) => refused(
                "stretch or bend (Veltkamp & Wesselink's internal energy; normal fields and \
                 guide surfaces are for tensor surfaces)",
            ),
        }
    }
}

impl TriProblem {
    /// The surface (its points are the initial net), no energy yet, no
    /// constraints and the default continuity ([`Continuity::default`]).
    /// Add [`crate::Stretch`] (α) and [`crate::Bend`] (β) terms: the same
    /// terms a tensor surface's problem takes (their weights add up: α·
    /// stretch + β·bend, eq. 6–7); the solve refuses any other, naming it.
    /// Points are held by `Fixed` constraints ([`Self::with_fixed_boundary`]).
    /// (Not `new`: `Problem::new(degree)` is a Bézier patch's.)
    pub fn from_mesh(surface: TriSurface) -> Self {
        let n = surface.point_count();
        Self::over(surface, vec![true; n])
    }

    /// α·stretch + β·bend from the terms; an error naming a term the
    /// triangular assembly cannot take, a bad weight, or no term at all.
    pub(crate) fn energy(&self) -> Result<InternalEnergy> {
        if self.terms.is_empty() {
            return Err(Error::NoEnergy);
        }
        let mut e = InternalEnergy::new(0.0, 0.0);
        for t in &self.terms {
            match TriTerm::of(t.as_ref()) {
                TriTerm::Weights { stretch, bend } => {
                    crate::energy::check_weight("stretch weight α", stretch)?;
                    crate::energy::check_weight("bend weight β", bend)?;
                    e.stretch += stretch;
                    e.bend += bend;
                }
                TriTerm::Refused { name, expected } => {
                    return Err(Error::Mismatch {
                        what: format!("energy term {name} on a triangular surface"),
                        expected: expected.into(),
                        got: "another".into(),
                    })
                }
            }
        }
        Ok(e)
    }

    /// Adds a constraint at a point of the mesh (Veltkamp & Wesselink
    /// §4.1). Unlike a tensor surface's, a `Fixed` one stays a constraint:
    /// it holds the global control point's coordinates in the solve, is
    /// reported with its violation among `report.constraints`, and two
    /// that disagree on a point are reported inconsistent (a tensor
    /// surface's problem holds the point itself, the last value winning).
    pub fn with_constraint(mut self, name: impl Into<String>, constraint: Constraint) -> Self {
        self.constraints.push(NamedConstraint {
            name: name.into(),
            constraint,
        });
        self
    }

    /// Fixes every boundary control point at its current value.
    pub fn with_fixed_boundary(mut self) -> Self {
        for g in self.surface.boundary_points() {
            let value = self.surface.points()[g];
            self.constraints.push(NamedConstraint {
                name: format!("boundary point {g}"),
                constraint: Constraint::Fixed { point: g, value },
            });
        }
        self
    }

    /// Adds a curve constraint.
    pub fn with_curve(mut self, curve: CurveConstraint) -> Self {
        self.extra.curves.push(curve);
        self
    }

    /// Sets the continuity conditions.
    pub fn with_continuity(mut self, continuity: Continuity) -> Self {
        self.extra.continuity = continuity;
        self
    }

    /// Solves; errors name the bad constraint or say why the system has no
    /// unique solution.
    pub fn solve(&self) -> Result<TriSolution> {
        Ok(self.solve_kept(&[])?.0)
    }

    /// Solves, and returns the KKT factorization of the rows it kept too
    /// (reusable or not, [`TriFactored::reusable`]): the fill's descent on
    /// W steps along the rows with it.
    pub(crate) fn solve_factored(&self) -> Result<(TriSolution, Option<Box<TriFactored>>)> {
        let (solution, factor) = self.solve_kept(&[])?;
        Ok((
            solution,
            match factor {
                Factor::New(f) => Some(f),
                Factor::None | Factor::Reused(_) => None,
            },
        ))
    }

    /// Embeds the curves one after another; returns the composed
    /// refinement and each curve's chain of vertices.
    fn embed_curves(&self) -> Result<(Refinement, Vec<Chain>)> {
        let mut r = Refinement::identity(&self.surface);
        let mut chains = Vec::new();
        for c in &self.extra.curves {
            let locate = |p: DomainPoint, which: &str| {
                check_point(&self.surface, p, &format!("{}: `{which}` point", c.name))?;
                Ok::<_, Error>(r.locate(p).expect("checked"))
            };
            let (from, to) = (locate(c.from, "from")?, locate(c.to, "to")?);
            let path = embed_curve(&r.surface, &c.curve, from, to, c.through.as_deref())
                .map_err(|e| named(e, &c.name))?;
            r = compose(&r, path.refinement);
            chains.push((c.name.clone(), path.vertices));
        }
        Ok((r, chains))
    }

    /// H over the free coordinates (both triangles) and b = H_fk x_k.
    /// H is written column by column: the free coordinates 3i + c are
    /// numbered in increasing order and K's row indices are sorted, so each
    /// column's rows come sorted without a triplet sort.
    fn hessian(
        &self,
        surface: &TriSurface,
        known: &[Option<f64>],
        free_index: &[usize],
        free: usize,
    ) -> Result<(SparseColMat<usize, f64>, Vec<f64>)> {
        let k = self.energy()?.surface_matrix(surface)?;
        let mut b = vec![0.0; free];
        for j in 0..k.ncols() {
            for (i, v) in k.row_idx_of_col(j).zip(k.val_of_col(j)) {
                for c in 0..3 {
                    let (ci, cj) = (3 * i + c, 3 * j + c);
                    if let (None, Some(xj)) = (known[ci], known[cj]) {
                        b[free_index[ci]] += v * xj;
                    }
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(free + 1);
        let mut rows = Vec::with_capacity(3 * k.compute_nnz());
        let mut values = Vec::with_capacity(3 * k.compute_nnz());
        col_ptr.push(0);
        for cj in (0..known.len()).filter(|&cj| known[cj].is_none()) {
            let (j, c) = (cj / 3, cj % 3);
            for (i, v) in k.row_idx_of_col(j).zip(k.val_of_col(j)) {
                let ci = 3 * i + c;
                if known[ci].is_none() {
                    rows.push(free_index[ci]);
                    values.push(*v);
                }
            }
            col_ptr.push(rows.len());
        }
        let symbolic = SymbolicSparseColMat::new_checked(free, free, col_ptr, None, rows);
        Ok((SparseColMat::new(symbolic, values), b))
    }
}

/// ‖H x + b + Fᵀλ‖∞ over the free coordinates (the gradient of the
/// Lagrangian) and the same over ‖H‖∞‖x‖∞ + ‖b‖∞, the size of the terms
/// that cancel.
fn lagrangian_gradient(
    h: &SparseColMat<usize, f64>,
    b: &[f64],
    f: &[&[(usize, f64)]],
    x: &[f64],
    lambda: &[f64],
) -> (f64, f64) {
    let mut grad = b.to_vec();
    let mut row_sums = vec![0.0f64; x.len()];
    for (j, xj) in x.iter().enumerate() {
        for (i, v) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
            grad[i] += v * xj;
            row_sums[i] += v.abs();
        }
    }
    for (row, lam) in f.iter().zip(lambda) {
        for &(i, a) in row.iter() {
            grad[i] += a * lam;
        }
    }
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = inf(&row_sums) * inf(x) + inf(b);
    let norm = inf(&grad);
    (norm, if scale > 0.0 { norm / scale } else { norm })
}

/// A curve's name and its chain of mesh vertices.
type Chain = (String, Vec<usize>);

/// Prefixes an error's description with the constraint's name.
fn named(e: Error, name: &str) -> Error {
    match e {
        Error::Mismatch {
            what,
            expected,
            got,
        } if !what.starts_with(name) => Error::Mismatch {
            what: format!("{name}: {what}"),
            expected,
            got,
        },
        other => other,
    }
}

/// outer: original → A; inner: A → B; result: original → B.
fn compose(outer: &Refinement, inner: Refinement) -> Refinement {
    let origin = inner
        .origin
        .iter()
        .map(|&(a, corners)| {
            let (o, oc) = outer.origin[a];
            let mapped = corners.map(|b| {
                let mut p = [0.0; 3];
                for m in 0..3 {
                    for q in 0..3 {
                        p[q] += b[m] * oc[m][q];
                    }
                }
                p
            });
            (o, mapped)
        })
        .collect();
    Refinement {
        surface: inner.surface,
        origin,
    }
}

/// The global point of the refined surface that is original point g, if
/// it survived: a vertex keeps its index, an edge point stays if its edge
/// was not split, an interior point if its triangle was not split.
fn map_global(original: &TriSurface, r: &Refinement, g: usize) -> Option<usize> {
    if g < original.vertex_count() {
        return Some(g);
    }
    let refined = &r.surface;
    let n = original.degree();
    let edge_points = original.edges().len() * (n - 1);
    let local = g - original.vertex_count();
    if local < edge_points {
        let (e, pos) = (local / (n - 1), local % (n - 1) + 1);
        let [a, b] = original.edges()[e].vertices;
        let e2 = refined.edge_between(a, b)?;
        return Some(refined.edge_points(e2)[pos]);
    }
    let per = (n - 1) * (n - 2) / 2;
    let t = (local - edge_points) / per;
    let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let t2 = (0..refined.patch_count()).find(|&x| r.origin[x] == (t, identity))?;
    let at = original.patch_indices(t).iter().position(|&x| x == g)?;
    Some(refined.patch_indices(t2)[at])
}

/// The globals (with values) along a chain of vertices.
fn chain_points(surface: &TriSurface, chain: &[usize], name: &str) -> Result<Vec<(usize, Vec3)>> {
    let mut out = Vec::new();
    for w in chain.windows(2) {
        let e = surface
            .edge_between(w[0], w[1])
            .ok_or_else(|| Error::Mismatch {
                what: format!("{name}: chain edge {}–{}", w[0], w[1]),
                expected: "an edge of the refined mesh".into(),
                got: "an edge split by a later curve (curves that cross are not supported)".into(),
            })?;
        for g in surface.edge_points(e) {
            out.push((g, surface.points()[g]));
        }
    }
    Ok(out)
}

/// The largest distance between the chain edges of the surface and the
/// curve at matching parameters (the chain's edge i covers t ∈ [i/m, (i+1)/m]).
fn curve_distance(surface: &TriSurface, chain: &[usize], curve: &BezierCurve) -> f64 {
    let m = chain.len().saturating_sub(1).max(1);
    let mut worst = 0.0f64;
    for (i, w) in chain.windows(2).enumerate() {
        let Some(e) = surface.edge_between(w[0], w[1]) else {
            return f64::INFINITY;
        };
        let pts: Vec<Vec3> = surface
            .edge_points(e)
            .iter()
            .map(|&g| surface.points()[g])
            .collect();
        let edge = BezierCurve::new(if surface.edges()[e].vertices[0] == w[0] {
            pts
        } else {
            pts.into_iter().rev().collect()
        });
        for s in 0..=16 {
            let u = s as f64 / 16.0;
            let t = (i as f64 + u) / m as f64;
            worst = worst.max(norm(sub(edge.eval(u), curve.eval(t))));
        }
    }
    worst
}

fn bounding_size(points: &[Vec3]) -> f64 {
    crate::vec3::bounding_diagonal(points).max(1.0)
}

/// A direction in which every free control point can move together without
/// changing the internal energy (translation invariant) or any constraint
/// row or attractor residual: `None` when known coordinates, rows and
/// residuals pin all three. A known coordinate pins its axis (the mesh
/// couples it to every free point); a row or residual Σ a_i x_i pins the
/// direction (Σ_{i: x} a_i, Σ_{i: y} a_i, Σ_{i: z} a_i) over its free
/// coordinates i = 3g + c.
fn free_translation<'a>(
    known: &[Option<f64>],
    pinning: impl Iterator<Item = &'a [(usize, f64)]>,
) -> Option<Vec3> {
    let axes = (0..3)
        .filter(|&c| (0..known.len() / 3).any(|g| known[3 * g + c].is_some()))
        .map(|c| std::array::from_fn(|k| if k == c { 1.0 } else { 0.0 }));
    let directions = pinning.map(|terms| {
        let mut v = [0.0; 3];
        let mut scale: f64 = 0.0;
        for &(i, a) in terms {
            if known[i].is_none() {
                v[i % 3] += a;
                scale = scale.max(a.abs());
            }
        }
        // Coefficients that cancel to rounding pin nothing.
        v.map(|x| if x.abs() > 1e-9 * scale { x } else { 0.0 })
    });
    // Gram–Schmidt: an orthonormal basis of the pinned directions.
    let mut basis: Vec<Vec3> = Vec::new();
    for mut v in axes.chain(directions) {
        if basis.len() == 3 {
            return None;
        }
        for q in &basis {
            let d = crate::vec3::dot(v, *q);
            v = crate::vec3::sub(v, crate::vec3::scale(*q, d));
        }
        if let Some(u) = crate::vec3::normalize(v).filter(|_| crate::vec3::norm(v) > 1e-9) {
            basis.push(u);
        }
    }
    if basis.len() == 3 {
        return None;
    }
    // A unit vector orthogonal to the basis.
    let mut free =
        (0..3).map(|c| -> Vec3 { std::array::from_fn(|k| if k == c { 1.0 } else { 0.0 }) });
    free.find_map(|mut v| {
        for q in &basis {
            v = crate::vec3::sub(v, crate::vec3::scale(*q, crate::vec3::dot(v, *q)));
        }
        crate::vec3::normalize(v).filter(|_| crate::vec3::norm(v) > 0.5)
    })
}

/// Estimated peak bytes of a triangular solve: x, y and z of every patch's
/// (d+1)(d+2)/2 points coupled in one sparse KKT system, k² entries a patch
/// and coordinate pair block, 16 bytes an entry (value and indices), four
/// times for the matrix, its ordering and the factor's fill. Measured: 200
/// degree-20 patches took 2.0–2.3 GB (estimate 2.0 GB); 10,000 cubic
/// patches with C0 0.3 GB (estimate 0.2 GB).
pub(crate) fn memory_estimate(surface: &TriSurface) -> f64 {
    let d = surface.degree() as f64;
    let k = (d + 1.0) * (d + 2.0) / 2.0;
    64.0 * 3.0 * surface.patch_count() as f64 * k * k
}
