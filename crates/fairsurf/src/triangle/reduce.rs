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

/// A sparse row over the unknowns 0 … n−1 with K right-hand sides (K
/// systems of the same coefficients, such as the x, y and z rows of
/// conditions that treat the coordinates alike).
pub(crate) struct SparseRow<'a, const K: usize = 1> {
    pub terms: &'a [(usize, f64)],
    pub rhs: [f64; K],
    /// Reduced coefficients at most this fraction of the row's largest
    /// make the row (numerically) a combination of the earlier ones.
    pub tol: f64,
}

struct Accepted<const K: usize> {
    terms: Vec<(usize, f64)>,
    rhs: [f64; K],
    pivot: usize,
    pivot_value: f64,
}

/// Classifies rows in order. Each row's `tol` is relative to its largest
/// coefficient; `rhs_tol` is the absolute right-hand-side tolerance after
/// that scaling (a length: the problem's size times a small factor).
///
/// With K right-hand sides the rows are K systems of the same
/// coefficients, eliminated once: a row is independent in all of them or
/// in none, and dependent or inconsistent system by system.
///
/// Also returns each row's largest reduced coefficient relative to its
/// largest coefficient (0 for an empty row): the figure compared with
/// `tol`. The elimination does not depend on the tolerances otherwise, so
/// rows classified again at other tolerances get the same verdicts as long
/// as no row's figure lies between its old and new tolerance.
pub(crate) fn classify<const K: usize>(
    rows: &[SparseRow<'_, K>],
    unknowns: usize,
    rhs_tol: f64,
) -> (Vec<[Verdict; K]>, Vec<f64>) {
    let mut count = vec![0u32; unknowns];
    for r in rows {
        for &(i, _) in r.terms {
            count[i] += 1;
        }
    }
    let mut accepted: Vec<Accepted<K>> = Vec::new();
    let mut pivot_of: Vec<Option<usize>> = vec![None; unknowns];
    let mut work = vec![0.0f64; unknowns];
    let mut touched_mark = vec![false; unknowns];
    let mut queued = Vec::<bool>::new();
    let mut out = Vec::with_capacity(rows.len());
    let mut reduced = Vec::with_capacity(rows.len());
    for row in rows {
        let scale = row.terms.iter().fold(0.0f64, |m, &(_, a)| m.max(a.abs()));
        if scale == 0.0 {
            out.push(row.rhs.map(|r| rhs_verdict(r, 1.0, rhs_tol)));
            reduced.push(0.0);
            continue;
        }
        let mut touched: Vec<usize> = Vec::with_capacity(row.terms.len() * 4);
        let mut heap = BinaryHeap::new();
        let mut queued_list: Vec<usize> = Vec::new();
        queued.resize(accepted.len(), false);
        let mut rhs = row.rhs.map(|r| r / scale);
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
            for (r, a) in rhs.iter_mut().zip(acc.rhs) {
                *r -= factor * a;
            }
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
            [Verdict::Independent; K]
        } else {
            rhs.map(|r| rhs_verdict(r, 1.0, rhs_tol))
        };
        for &i in &touched {
            work[i] = 0.0;
            touched_mark[i] = false;
        }
        for k in queued_list {
            queued[k] = false;
        }
        out.push(verdict);
        reduced.push(largest);
    }
    (out, reduced)
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
                rhs: [*r],
                tol: 1e-10,
            })
            .collect()
    }

    /// The verdicts of one system.
    fn one(classified: (Vec<[Verdict; 1]>, Vec<f64>)) -> Vec<Verdict> {
        classified.0.into_iter().map(|[v]| v).collect()
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
        let v = one(classify(&rows(&data), 3, 1e-12));
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
                    rhs: [*r],
                    tol,
                })
                .collect();
            classify(&rows, 2, 1e-12)
        };
        let (strict, loose) = (with(1e-9), with(1e-3));
        // The figure compared with the tolerance, the same at both.
        let figure = 1e-6 / (1.0 + 1e-6);
        for (_, reduced) in [&strict, &loose] {
            assert_eq!(reduced[0], 1.0);
            assert!((reduced[1] - figure).abs() < 1e-9 * figure);
        }
        assert_eq!(strict.0[1], [Verdict::Independent]);
        match loose.0[1][0] {
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
        let v = one(classify(&rows(&data), 51, 1e-12));
        assert!(v[..50].iter().all(|x| *x == Verdict::Independent));
        assert_eq!(v[50], Verdict::Dependent);
        assert!(
            matches!(v[51], Verdict::Inconsistent { residual } if (residual - 1.0).abs() < 1e-12)
        );
    }

    /// Three right-hand sides at once are three classifications of the
    /// same coefficients.
    #[test]
    fn systems_sharing_coefficients_classify_as_each_alone() {
        let terms = [
            vec![(0, 1.0), (1, 1.0)],
            vec![(1, 1.0), (2, -1.0)],
            vec![(0, 2.0), (1, 1.0), (2, 1.0)],
            vec![(0, 1.0), (2, 1.0)],
            vec![(2, 5.0)],
            vec![],
        ];
        let rhs = [
            [2.0, 1.0, -3.0],
            [0.0, 0.5, 1.0],
            [4.0, 1.5, -5.0], // 2·row 0 − row 1: dependent, dependent, inconsistent
            [3.0, 0.5, 0.0],  // row 0 − row 1: inconsistent, dependent, inconsistent
            [5.0, -1.0, 2.0],
            [0.0, 1e-3, 0.0],
        ];
        let shared: Vec<SparseRow<'_, 3>> = terms
            .iter()
            .zip(rhs)
            .map(|(t, r)| SparseRow {
                terms: t,
                rhs: r,
                tol: 1e-10,
            })
            .collect();
        let (together, figures) = classify(&shared, 3, 1e-12);
        assert_eq!(together[2][..2], [Verdict::Dependent; 2]);
        assert!(matches!(together[2][2], Verdict::Inconsistent { .. }));
        assert_eq!(together[3][1], Verdict::Dependent);
        assert!(matches!(together[3][0], Verdict::Inconsistent { .. }));
        assert!(matches!(together[5][1], Verdict::Inconsistent { .. }));
        for c in 0..3 {
            let alone: Vec<SparseRow<'_>> = terms
                .iter()
                .zip(rhs)
                .map(|(t, r)| SparseRow {
                    terms: t,
                    rhs: [r[c]],
                    tol: 1e-10,
                })
                .collect();
            let (verdicts, alone_figures) = classify(&alone, 3, 1e-12);
            assert_eq!(alone_figures, figures);
            for (a, t) in verdicts.iter().zip(&together) {
                assert_eq!(a[0], t[c]);
            }
        }
    }

    /// Rows F₁ ⊗ I₃ over interleaved unknowns 3p + c (rows 3s + c)
    /// classified one by one come to the verdicts of F₁ with three
    /// right-hand sides: the pivots, the fill and the figures are the same.
    #[test]
    fn interleaved_coordinates_classify_as_one_system() {
        // A chain of 40 unknowns: rows i, i+1, i+3 (chained like continuity
        // conditions), then combinations of earlier rows, one nudged by
        // 1e-7 (nearly dependent).
        let mut f1: Vec<Vec<(usize, f64)>> = (0..36)
            .map(|i| {
                let t = i as f64;
                vec![
                    (i, 1.0 + 0.1 * t.sin()),
                    (i + 1, -2.0),
                    (i + 3, 0.5 + 0.01 * t),
                ]
            })
            .collect();
        for k in [3usize, 10, 20] {
            let mut sum: Vec<(usize, f64)> = f1[k].clone();
            for &(i, a) in &f1[k + 1] {
                match sum.iter_mut().find(|(j, _)| *j == i) {
                    Some(e) => e.1 += 0.7 * a,
                    None => sum.push((i, 0.7 * a)),
                }
            }
            f1.push(sum);
        }
        f1.last_mut().unwrap()[0].1 += 1e-7;
        let rhs = |s: usize, c: usize| ((s * 3 + c) as f64 * 0.37).cos();
        let interleaved: Vec<Vec<(usize, f64)>> = (0..f1.len())
            .flat_map(|s| (0..3).map(move |c| (s, c)))
            .map(|(s, c)| f1[s].iter().map(|&(i, a)| (3 * i + c, a)).collect())
            .collect();
        for tol in [1e-9, 1e-3] {
            let one: Vec<SparseRow<'_>> = interleaved
                .iter()
                .enumerate()
                .map(|(r, t)| SparseRow {
                    terms: t,
                    rhs: [rhs(r / 3, r % 3)],
                    tol,
                })
                .collect();
            let three: Vec<SparseRow<'_, 3>> = f1
                .iter()
                .enumerate()
                .map(|(s, t)| SparseRow {
                    terms: t,
                    rhs: [0, 1, 2].map(|c| rhs(s, c)),
                    tol,
                })
                .collect();
            let (v1, r1) = classify(&one, 3 * 40, 1e-12);
            let (v3, r3) = classify(&three, 40, 1e-12);
            let flat: Vec<Verdict> = v3.into_iter().flatten().collect();
            assert_eq!(v1.into_iter().map(|[v]| v).collect::<Vec<_>>(), flat);
            let spread: Vec<f64> = r3.iter().flat_map(|&x| [x; 3]).collect();
            assert_eq!(r1, spread);
            // Two of the combinations are dependent-or-inconsistent; the
            // nudged one is independent only at the strict tolerance.
            let last = flat[flat.len() - 1];
            assert_eq!(last == Verdict::Independent, tol == 1e-9, "{tol}");
        }
    }
}
