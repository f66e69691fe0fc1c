//! A few factorizations kept for interactive use (the editor's drags).

use super::problem::{Factored, Prepared, Problem, Solution, SolveOptions};
use crate::Result;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Instant;

/// The most recently used factorizations, shared between threads: a solve
/// reuses one that [fits](Factored::fits) the problem, or factors the
/// problem and keeps it, dropping the least recently used ones beyond the
/// limits on count and bytes.
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
    entries: Mutex<VecDeque<Arc<Factored>>>,
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
        self.keep(Arc::new(f), problem, &prep);
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

    fn lock(&self) -> std::sync::MutexGuard<'_, VecDeque<Arc<Factored>>> {
        // A panic elsewhere cannot leave the list half-changed.
        self.entries.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// A fitting factorization, moved to the front.
    fn find(&self, problem: &Problem, prep: &Prepared) -> Option<Arc<Factored>> {
        let mut entries = self.lock();
        let k = entries
            .iter()
            .position(|f| f.mismatch(problem, prep).is_none())?;
        let f = entries.remove(k)?;
        entries.push_front(f.clone());
        Some(f)
    }

    /// Keeps `f`, the factorization of `problem`, in place of any other of
    /// the same matrix (another thread may have factored it meanwhile).
    fn keep(&self, f: Arc<Factored>, problem: &Problem, prep: &Prepared) {
        if f.bytes() > self.max_bytes || self.max_entries == 0 {
            return;
        }
        let mut entries = self.lock();
        entries.retain(|e| e.mismatch(problem, prep).is_some());
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
                            .patch
                            .points()
                            .iter()
                            .zip(fresh.patch.points())
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
