//! Bounded work: a memory budget and a cancellation flag for the solves run
//! on a thread. Front ends set them ([`with_budget`]: the command line from
//! its flags, the server per request, cancelling on timeout or when the
//! client goes away); solves estimate their memory before the work and
//! refuse what exceeds the budget ([`crate::Error::TooLarge`]), and stop at
//! their checkpoints once cancelled ([`crate::Error::Cancelled`]).
//!
//! The dense Cholesky checks between its panels. The sparse factorizations
//! (faer's LLT, LDLᵀ, LU) are not interrupted: cancellation takes effect at
//! the next checkpoint after them (the server runs large sparse problems in
//! a worker process it can kill).

use crate::{Error, Result};
use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The limits of the work done on one thread.
#[derive(Clone, Debug)]
pub struct Budget {
    /// Largest estimated memory of one solve, in bytes.
    pub max_bytes: usize,
    /// Set to true to stop the work at its next checkpoint.
    pub cancel: Option<Arc<AtomicBool>>,
}

/// 8 GB: a 24 GB machine with room for two solves at once and the rest.
pub const DEFAULT_MAX_BYTES: usize = 8 << 30;

impl Default for Budget {
    fn default() -> Self {
        Self {
            max_bytes: DEFAULT_MAX_BYTES,
            cancel: None,
        }
    }
}

thread_local! {
    static BUDGET: RefCell<Budget> = RefCell::new(Budget::default());
}

/// Runs `f` with `budget` as this thread's budget (the previous one again
/// afterwards, also when `f` panics).
pub fn with_budget<T>(budget: Budget, f: impl FnOnce() -> T) -> T {
    struct Restore(Option<Budget>);
    impl Drop for Restore {
        fn drop(&mut self) {
            if let Some(b) = self.0.take() {
                BUDGET.with(|c| *c.borrow_mut() = b);
            }
        }
    }
    let previous = BUDGET.with(|c| c.replace(budget));
    let _restore = Restore(Some(previous));
    f()
}

/// Runs `a` and `b` on rayon's pool (the one faer's parallel kernels use),
/// both under this thread's budget, and returns both results: on two of its
/// threads when one is free to take `b`, else one after the other. The
/// pool's threads live on, so what a thread keeps (the 1-D integral tables)
/// serves the next solve, and no thread is started per call (a scoped
/// thread per solve cost ~0.3 ms at degree 10, half of it rebuilding that
/// thread's tables). The pool is shared: in the server, concurrent solves
/// take turns on its two threads, and a thread waiting for its half may run
/// another request's half meanwhile (a cancelled request's answer can wait
/// for it; each half still stops at its own budget's checkpoints).
pub(crate) fn join<A: Send, B: Send>(
    a: impl FnOnce() -> A + Send,
    b: impl FnOnce() -> B + Send,
) -> (A, B) {
    let budget = BUDGET.with(|c| c.borrow().clone());
    let other = budget.clone();
    rayon::join(|| with_budget(budget, a), || with_budget(other, b))
}

/// Refuses work whose estimated memory exceeds the budget.
pub(crate) fn reserve(what: &str, bytes: f64) -> Result<()> {
    let limit = BUDGET.with(|c| c.borrow().max_bytes);
    if bytes > limit as f64 {
        return Err(Error::TooLarge {
            what: what.to_string(),
            estimate: bytes,
            limit: limit as f64,
        });
    }
    Ok(())
}

/// Whether the work was cancelled (for loops that stop early and leave the
/// error to the next [`checkpoint`]).
pub(crate) fn cancelled() -> bool {
    BUDGET.with(|c| {
        c.borrow()
            .cancel
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
    })
}

/// An error once the work was cancelled.
pub(crate) fn checkpoint() -> Result<()> {
    if cancelled() {
        return Err(Error::Cancelled);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joined_work_runs_under_the_callers_budget() {
        let flag = Arc::new(AtomicBool::new(true));
        let b = Budget {
            max_bytes: 10,
            cancel: Some(flag),
        };
        let (x, y) = with_budget(b, || join(cancelled, || (cancelled(), reserve("x", 11.0))));
        assert!(x && y.0);
        assert!(matches!(y.1, Err(Error::TooLarge { .. })));
        assert!(!join(cancelled, cancelled).1);
    }

    #[test]
    fn budgets_are_per_call_and_restored() {
        assert!(reserve("x", 1e9).is_ok());
        let flag = Arc::new(AtomicBool::new(false));
        let b = Budget {
            max_bytes: 1000,
            cancel: Some(flag.clone()),
        };
        with_budget(b, || {
            assert!(matches!(reserve("x", 2000.0), Err(Error::TooLarge { .. })));
            assert!(checkpoint().is_ok());
            flag.store(true, Ordering::Relaxed);
            assert!(matches!(checkpoint(), Err(Error::Cancelled)));
        });
        assert!(reserve("x", 2000.0).is_ok());
        assert!(checkpoint().is_ok());
    }
}
