//! Which constraint rows are independent: sparse Gaussian elimination row
//! by row, in priority order.
//!
//! Each new row is reduced against the rows accepted before it (each
//! accepted row keeps a pivot column and is zero in the pivot columns of
//! the rows accepted earlier, so one pass in acceptance order clears them
//! all). What is left decides:
//!
//! ```text
//! max |reduced coefficient| > tol·max |coefficient|   independent: accepted, pivot = its largest entry
//!                                                     (tol is the row's own)
//! otherwise, |reduced rhs| ≤ tol_rhs                  dependent: implied by earlier rows, dropped silently
//! otherwise                                           inconsistent with earlier rows: dropped, with the residual
//! ```
//!
//! Because rows are taken in order, earlier rows win: the user's
//! interpolation constraints come first and the default continuity
//! conditions give way to them (§4.3).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// What the elimination found for one row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Verdict {
    /// Independent of the earlier rows: kept.
    Independent,
    /// A combination of earlier rows, right-hand side included.
    Dependent,
    /// Its coefficients are a combination of earlier rows but its
    /// right-hand side is not: the earlier rows force it off by `residual`
    /// (the reduced right-hand side over the row's largest coefficient).
    Inconsistent {
        /// The reduced right-hand side, relative to the row's scale.
        residual: f64,
    },
}

/// A sparse row over the unknowns 0 … n−1.
pub(crate) struct SparseRow<'a> {
    pub terms: &'a [(usize, f64)],
    pub rhs: f64,
    /// Reduced coefficients at most this fraction of the row's largest
    /// make the row (numerically) a combination of the earlier ones.
    pub tol: f64,
}

struct Accepted {
    terms: Vec<(usize, f64)>,
    rhs: f64,
    pivot: usize,
    pivot_value: f64,
}

/// Classifies rows in order. Each row's `tol` is relative to its largest
/// coefficient; `rhs_tol` is the absolute right-hand-side tolerance after
/// that scaling (a length: the problem's size times a small factor).
pub(crate) fn classify(rows: &[SparseRow<'_>], unknowns: usize, rhs_tol: f64) -> Vec<Verdict> {
    let mut count = vec![0u32; unknowns];
    for r in rows {
        for &(i, _) in r.terms {
            count[i] += 1;
        }
    }
    let mut accepted: Vec<Accepted> = Vec::new();
    let mut pivot_of: Vec<Option<usize>> = vec![None; unknowns];
    let mut work = vec![0.0f64; unknowns];
    let mut touched_mark = vec![false; unknowns];
    let mut queued = Vec::<bool>::new();
    let mut out = Vec::with_capacity(rows.len());
    for row in rows {
        let scale = row.terms.iter().fold(0.0f64, |m, &(_, a)| m.max(a.abs()));
        if scale == 0.0 {
            out.push(rhs_verdict(row.rhs, 1.0, rhs_tol));
            continue;
        }
        let mut touched: Vec<usize> = Vec::with_capacity(row.terms.len() * 4);
        let mut heap = BinaryHeap::new();
        let mut queued_list: Vec<usize> = Vec::new();
        queued.resize(accepted.len(), false);
        let mut rhs = row.rhs / scale;
        for &(i, a) in row.terms {
            work[i] += a / scale;
            if !touched_mark[i] {
                touched_mark[i] = true;
                touched.push(i);
            }
            if let Some(k) = pivot_of[i] {
                if !queued[k] {
                    queued[k] = true;
                    queued_list.push(k);
                    heap.push(Reverse(k));
                }
            }
        }
        while let Some(Reverse(k)) = heap.pop() {
            let acc = &accepted[k];
            let v = work[acc.pivot];
            if v == 0.0 {
                continue;
            }
            let factor = v / acc.pivot_value;
            for &(i, a) in &acc.terms {
                work[i] -= factor * a;
                if !touched_mark[i] {
                    touched_mark[i] = true;
                    touched.push(i);
                    if let Some(j) = pivot_of[i] {
                        if !queued[j] {
                            queued[j] = true;
                            queued_list.push(j);
                            heap.push(Reverse(j));
                        }
                    }
                }
            }
            work[acc.pivot] = 0.0;
            rhs -= factor * acc.rhs;
        }
        // Pick the pivot: the largest entry, preferring rarely used columns
        // among those within a factor 10 of it (less fill).
        let largest = touched.iter().fold(0.0f64, |m, &i| m.max(work[i].abs()));
        let verdict = if largest > row.tol {
            let pivot = touched
                .iter()
                .copied()
                .filter(|&i| work[i].abs() >= 0.1 * largest && pivot_of[i].is_none())
                .min_by_key(|&i| (count[i], i))
                .expect("the largest entry is not a pivot column");
            let terms: Vec<(usize, f64)> = touched
                .iter()
                .map(|&i| (i, work[i]))
                .filter(|&(_, a)| a.abs() > 1e-14 * largest)
                .collect();
            pivot_of[pivot] = Some(accepted.len());
            accepted.push(Accepted {
                pivot_value: work[pivot],
                terms,
                rhs,
                pivot,
            });
            Verdict::Independent
        } else {
            rhs_verdict(rhs, 1.0, rhs_tol)
        };
        for &i in &touched {
            work[i] = 0.0;
            touched_mark[i] = false;
        }
        for k in queued_list {
            queued[k] = false;
        }
        out.push(verdict);
    }
    out
}

fn rhs_verdict(rhs: f64, scale: f64, rhs_tol: f64) -> Verdict {
    if rhs.abs() <= rhs_tol {
        Verdict::Dependent
    } else {
        Verdict::Inconsistent {
            residual: rhs.abs() / scale,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(data: &[(Vec<(usize, f64)>, f64)]) -> Vec<SparseRow<'_>> {
        data.iter()
            .map(|(t, r)| SparseRow {
                terms: t,
                rhs: *r,
                tol: 1e-10,
            })
            .collect()
    }

    #[test]
    fn dependent_inconsistent_and_independent_rows() {
        let data = vec![
            (vec![(0, 1.0), (1, 1.0)], 2.0),           // x0 + x1 = 2
            (vec![(1, 1.0), (2, -1.0)], 0.0),          // x1 = x2
            (vec![(0, 2.0), (1, 1.0), (2, 1.0)], 4.0), // sum of 2·row0 and row1: dependent
            (vec![(0, 1.0), (2, 1.0)], 3.0),           // row0 − row1 says 2: off by 1
            (vec![(2, 5.0)], 5.0),                     // new
            (vec![], 0.0),                             // empty and satisfied
            (vec![], 1e-3),                            // empty and not
        ];
        let v = classify(&rows(&data), 3, 1e-12);
        assert_eq!(v[0], Verdict::Independent);
        assert_eq!(v[1], Verdict::Independent);
        assert_eq!(v[2], Verdict::Dependent);
        match v[3] {
            Verdict::Inconsistent { residual } => assert!((residual - 1.0).abs() < 1e-14),
            other => panic!("{other:?}"),
        }
        assert_eq!(v[4], Verdict::Independent);
        assert_eq!(v[5], Verdict::Dependent);
        assert!(matches!(v[6], Verdict::Inconsistent { .. }));
    }

    #[test]
    fn a_nearly_dependent_row_is_independent_only_under_a_strict_tolerance() {
        // x0 + x1 = 0, then x0 + (1 + 1e-6)·x1 = 1e-7: reduced to 1e-6·x1 = 1e-7.
        let data = [
            (vec![(0, 1.0), (1, 1.0)], 0.0),
            (vec![(0, 1.0), (1, 1.0 + 1e-6)], 1e-7),
        ];
        let with = |tol: f64| {
            let rows: Vec<SparseRow<'_>> = data
                .iter()
                .map(|(t, r)| SparseRow {
                    terms: t,
                    rhs: *r,
                    tol,
                })
                .collect();
            classify(&rows, 2, 1e-12)
        };
        assert_eq!(with(1e-9)[1], Verdict::Independent);
        match with(1e-3)[1] {
            Verdict::Inconsistent { residual } => {
                assert!((residual - 1e-7 / (1.0 + 1e-6)).abs() < 1e-15)
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_long_chain_of_fill_is_resolved() {
        // x_i − x_{i+1} = 0 for i < 50, then x_0 − x_50 = 0 (dependent) and
        // x_0 − x_50 = 1 (inconsistent by 1).
        let mut data: Vec<(Vec<(usize, f64)>, f64)> = (0..50)
            .map(|i| (vec![(i, 1.0), (i + 1, -1.0)], 0.0))
            .collect();
        data.push((vec![(0, 1.0), (50, -1.0)], 0.0));
        data.push((vec![(0, 1.0), (50, -1.0)], 1.0));
        let v = classify(&rows(&data), 51, 1e-12);
        assert!(v[..50].iter().all(|x| *x == Verdict::Independent));
        assert_eq!(v[50], Verdict::Dependent);
        assert!(
            matches!(v[51], Verdict::Inconsistent { residual } if (residual - 1.0).abs() < 1e-12)
        );
    }
}
