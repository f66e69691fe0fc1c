//! A few factorizations kept for interactive use (the editor's drags).

use super::builder::Problem;
use super::factored::Factored;
use super::problem::{Prepared, Solution, SolveOptions};
use crate::bspline::{BSplineFactor, BSplineProblem, BSplineSolution, Reuse};
use crate::triangle::solve::Factor;
use crate::triangle::{TriFactored, TriProblem, TriSolution};
use crate::Result;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Instant;

/// The most recently used factorizations, shared between threads: a solve
/// reuses one that [fits](Factored::fits) the problem, or factors the
/// problem and keeps it, dropping the least recently used ones beyond the
/// limits on count and bytes. Bézier ([`Self::solve`]), B-spline
/// ([`Self::solve_bspline`]) and triangular ([`Self::solve_triangular`])
/// solves share the limits.
///
/// ```
/// use fairsurf::{FactorCache, Problem, SolveOptions, Stretch, TensorPatch};
/// let cache = FactorCache::new(4, 64 << 20);
/// let net = |h: f64| TensorPatch::from_fn(4, 4, |i, j| [i as f64, j as f64, h * (i * j) as f64]);
/// let problem = |h| Problem::new((4, 4)).with_fixed_rings(&net(h), 1).with_term(Stretch::new(1.0));
/// let opts = SolveOptions::default();
/// assert!(!cache.solve(&problem(0.1), &opts).unwrap().report.reused);
/// assert!(cache.solve(&problem(0.2), &opts).unwrap().report.reused);
/// ```
#[derive(Debug)]
pub struct FactorCache {
    max_entries: usize,
    max_bytes: usize,
    entries: Mutex<VecDeque<Kept>>,
}

/// A kept factorization of any kind.
#[derive(Clone, Debug)]
enum Kept {
    Tensor(Arc<Factored>),
    Triangular(Arc<TriFactored>),
    BSpline(Arc<BSplineFactor>),
}

impl Kept {
    fn bytes(&self) -> usize {
        match self {
            Kept::Tensor(f) => f.bytes(),
            Kept::Triangular(f) => f.bytes(),
            Kept::BSpline(f) => f.bytes(),
        }
    }
}

impl FactorCache {
    /// Keeps at most `max_entries` factorizations of at most `max_bytes`
    /// together (a larger one is used once and not kept).
    pub fn new(max_entries: usize, max_bytes: usize) -> Self {
        Self {
            max_entries,
            max_bytes,
            entries: Mutex::new(VecDeque::new()),
        }
    }

    /// Solves `problem`, reusing a kept factorization when one fits.
    pub fn solve(&self, problem: &Problem, opts: &SolveOptions) -> Result<Solution> {
        let t_total = Instant::now();
        let prep = problem.prepare()?;
        if let Some(f) = self.find(problem, &prep) {
            return f.solve_prepared(problem, &prep, opts, t_total);
        }
        let (f, solution) = problem.factor_and_solve_prepared(&prep, opts, t_total)?;
        self.keep(Kept::Tensor(Arc::new(f)), |e| match e {
            Kept::Tensor(e) => e.mismatch(problem, &prep).is_none(),
            Kept::Triangular(_) | Kept::BSpline(_) => false,
        });
        Ok(solution)
    }

    /// Solves the triangular `problem`, reusing a kept KKT factorization
    /// when its matrix is this problem's, value for value (only fixed
    /// values, targets, plane offsets or operator targets moved). The
    /// report says whether it was ([`crate::SolveReport::reused`]).
    pub fn solve_triangular(&self, problem: &TriProblem) -> Result<TriSolution> {
        let kept: Vec<Arc<TriFactored>> = self
            .lock()
            .iter()
            .filter_map(|e| match e {
                Kept::Triangular(f) => Some(f.clone()),
                Kept::Tensor(_) | Kept::BSpline(_) => None,
            })
            .collect();
        let refs: Vec<&TriFactored> = kept.iter().map(|f| &**f).collect();
        let (solution, factor) = problem.solve_kept(&refs)?;
        match factor {
            Factor::Reused(k) => {
                self.touch(|e| matches!(e, Kept::Triangular(f) if Arc::ptr_eq(f, &kept[k])));
            }
            // One a fresh solve of another right-hand side would not come
            // to is not kept (its rows needed a looser tolerance for this
            // right-hand side's sake).
            Factor::New(f) if !f.reusable => {}
            Factor::New(f) => {
                let f: Arc<TriFactored> = Arc::from(f);
                self.keep(
                    Kept::Triangular(f.clone()),
                    |e| matches!(e, Kept::Triangular(k) if k.same_as(&f)),
                );
            }
            Factor::None => {}
        }
        Ok(solution)
    }

    /// Solves the B-spline `problem`, reusing a kept Cholesky factor: as it
    /// is when its matrix is this problem's, value for value (only fixed
    /// points or guide targets moved: `report.reused`), or a sparse one's
    /// ordering when only the numbers differ (a weight changed:
    /// `report.reused_symbolic`; the new factor then replaces the kept
    /// one). With constraints nothing is kept (the core's KKT solve factors
    /// them each time).
    pub fn solve_bspline(&self, problem: &BSplineProblem) -> Result<BSplineSolution> {
        let kept: Vec<Arc<BSplineFactor>> = self
            .lock()
            .iter()
            .filter_map(|e| match e {
                Kept::BSpline(f) => Some(f.clone()),
                Kept::Tensor(_) | Kept::Triangular(_) => None,
            })
            .collect();
        let (solution, factor) = problem.solve_kept(&kept)?;
        match factor {
            Some((f, Reuse::Numeric)) => {
                self.touch(|e| matches!(e, Kept::BSpline(k) if Arc::ptr_eq(k, &f)));
            }
            Some((f, _)) => {
                // A factor of the same pattern is replaced (a weight
                // slider's steps would otherwise crowd out the others).
                self.keep(
                    Kept::BSpline(f.clone()),
                    |e| matches!(e, Kept::BSpline(k) if k.same_pattern_as(&f)),
                );
            }
            None => {}
        }
        Ok(solution)
    }

    /// How many factorizations are kept.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// Whether none is kept.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, VecDeque<Kept>> {
        // A panic elsewhere cannot leave the list half-changed.
        self.entries.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// A fitting tensor factorization, moved to the front.
    fn find(&self, problem: &Problem, prep: &Prepared) -> Option<Arc<Factored>> {
        let f =
            self.touch(|e| matches!(e, Kept::Tensor(f) if f.mismatch(problem, prep).is_none()))?;
        match f {
            Kept::Tensor(f) => Some(f),
            Kept::Triangular(_) | Kept::BSpline(_) => None,
        }
    }

    /// The first entry that `is` says is the one, moved to the front.
    fn touch(&self, is: impl Fn(&Kept) -> bool) -> Option<Kept> {
        let mut entries = self.lock();
        let k = entries.iter().position(is)?;
        let e = entries.remove(k)?;
        entries.push_front(e.clone());
        Some(e)
    }

    /// Keeps `f` in front, in place of any entry `same` says is of the same
    /// matrix (another thread may have factored it meanwhile).
    fn keep(&self, f: Kept, same: impl Fn(&Kept) -> bool) {
        if f.bytes() > self.max_bytes || self.max_entries == 0 {
            return;
        }
        let mut entries = self.lock();
        entries.retain(|e| !same(e));
        entries.push_front(f);
        let mut total = 0;
        let mut keep = 0;
        for e in entries.iter() {
            if keep == self.max_entries || total + e.bytes() > self.max_bytes {
                break;
            }
            total += e.bytes();
            keep += 1;
        }
        entries.truncate(keep);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Bend, Stretch, TensorPatch};

    fn problem(n: usize, h: f64, bend: bool) -> Problem {
        let net = TensorPatch::from_fn(n, n, |i, j| [i as f64, j as f64, h * (i + j) as f64]);
        let p = Problem::new((n, n)).with_fixed_rings(&net, 1);
        if bend {
            p.with_term(Bend::new(1.0))
        } else {
            p.with_term(Stretch::new(1.0))
        }
    }

    #[test]
    fn keeps_the_most_recent_within_the_limits() {
        let opts = SolveOptions::default();
        let cache = FactorCache::new(2, usize::MAX);
        let solve = |n, h, bend| {
            cache
                .solve(&problem(n, h, bend), &opts)
                .unwrap()
                .report
                .reused
        };
        assert!(!solve(4, 0.0, false));
        assert!(!solve(4, 0.0, true));
        assert_eq!(cache.len(), 2);
        // Both kept; using the first makes the second the oldest.
        assert!(solve(4, 0.5, false));
        assert!(!solve(5, 0.0, false));
        assert_eq!(cache.len(), 2);
        assert!(!solve(4, 0.5, true), "the least recently used was dropped");
        assert!(solve(5, 0.3, false));
        // A byte limit below one factorization keeps none.
        let tiny = FactorCache::new(8, 100);
        assert!(
            !tiny
                .solve(&problem(4, 0.0, false), &opts)
                .unwrap()
                .report
                .reused
        );
        assert!(tiny.is_empty());
    }

    /// Threads share one cache; each gets its own answer.
    #[test]
    fn shared_between_threads() {
        let opts = SolveOptions::default();
        let cache = FactorCache::new(4, usize::MAX);
        std::thread::scope(|s| {
            for k in 0..4 {
                let cache = &cache;
                s.spawn(move || {
                    for step in 0..5 {
                        let h = 0.1 * (k * 5 + step) as f64;
                        let p = problem(5, h, false);
                        let got = cache.solve(&p, &opts).unwrap();
                        let fresh = p.solve_with(&opts).unwrap();
                        let d = got
                            .surface
                            .points()
                            .iter()
                            .zip(fresh.surface.points())
                            .map(|(a, b)| (a[2] - b[2]).abs())
                            .fold(0.0, f64::max);
                        assert!(d < 1e-13, "{d}");
                    }
                });
            }
        });
        assert_eq!(cache.len(), 1);
    }
}
