//! The map between the multi-index (i, j, k), i + j + k = n, of a triangular
//! Bézier net and the position of P_ijk in its linear storage.
//!
//! # Storage order
//!
//! Rows of constant k (the exponent of w), from k = 0 up to k = n; within a
//! row, increasing j (so decreasing i):
//!
//! ```text
//! index(i, j, k) = k(2n + 3 − k)/2 + j
//!
//! n = 2:   0: P₂₀₀  1: P₁₁₀  2: P₀₂₀     (row k = 0, the edge w = 0)
//!          3: P₁₀₁  4: P₀₁₁               (row k = 1)
//!          5: P₀₀₂                        (row k = 2, the corner w = 1)
//! ```
//!
//! Row k starts at `k(2n + 3 − k)/2` = (n+1) + n + … + (n−k+2) and holds the
//! n − k + 1 points P_{n−k−j, j, k}, j = 0 … n − k. The first n + 1 points are
//! the boundary edge w = 0 from the corner P_n00 to the corner P_0n0, and the
//! last point is the corner P_00n.

/// Number of control points of a degree-n triangular net, (n+1)(n+2)/2.
///
/// # Panics
/// If the count overflows `usize`.
///
/// ```
/// use fairsurf::triangle::point_count;
/// assert_eq!(point_count(3), 10);
/// ```
pub fn point_count(n: usize) -> usize {
    checked_point_count(n).expect("triangular net size overflows usize")
}

/// (n+1)(n+2)/2, or `None` when it overflows `usize`.
pub(crate) fn checked_point_count(n: usize) -> Option<usize> {
    let a = n.checked_add(1)?;
    let b = n.checked_add(2)?;
    // One of two consecutive integers is even: halve it before multiplying.
    if a % 2 == 0 {
        (a / 2).checked_mul(b)
    } else {
        a.checked_mul(b / 2)
    }
}

/// Where row k (the points with w-exponent k) starts: k(2n + 3 − k)/2.
#[inline]
fn row_start(n: usize, k: usize) -> usize {
    k * (2 * n + 3 - k) / 2
}

/// Position of P_ijk in the linear storage of a degree-n net:
/// `k(2n + 3 − k)/2 + j`.
///
/// # Panics
/// If i + j + k ≠ n.
///
/// ```
/// use fairsurf::triangle::linear_index;
/// assert_eq!(linear_index(2, 2, 0, 0), 0);
/// assert_eq!(linear_index(2, 0, 1, 1), 4);
/// assert_eq!(linear_index(2, 0, 0, 2), 5);
/// ```
#[inline]
pub fn linear_index(n: usize, i: usize, j: usize, k: usize) -> usize {
    assert!(
        i.checked_add(j).and_then(|s| s.checked_add(k)) == Some(n),
        "multi-index ({i}, {j}, {k}) does not sum to the degree {n}"
    );
    row_start(n, k) + j
}

/// The multi-index [i, j, k] stored at position `index` of a degree-n net;
/// the inverse of [`linear_index`].
///
/// # Panics
/// If `index` ≥ (n+1)(n+2)/2.
///
/// ```
/// use fairsurf::triangle::{linear_index, multi_index};
/// assert_eq!(multi_index(3, 7), [1, 0, 2]);
/// assert_eq!(linear_index(3, 1, 0, 2), 7);
/// ```
pub fn multi_index(n: usize, index: usize) -> [usize; 3] {
    assert!(
        index < point_count(n),
        "index {index} out of range for a degree-{n} triangular net"
    );
    // Row k holds n − k + 1 points; walk down the rows.
    let mut k = 0;
    let mut rest = index;
    while rest > n - k {
        rest -= n - k + 1;
        k += 1;
    }
    let j = rest;
    [n - k - j, j, k]
}

/// All multi-indices [i, j, k] of a degree-n net, in storage order.
///
/// ```
/// use fairsurf::triangle::multi_indices;
/// let all: Vec<[usize; 3]> = multi_indices(1).collect();
/// assert_eq!(all, vec![[1, 0, 0], [0, 1, 0], [0, 0, 1]]);
/// ```
pub fn multi_indices(n: usize) -> impl Iterator<Item = [usize; 3]> + Clone {
    (0..=n).flat_map(move |k| (0..=n - k).map(move |j| [n - k - j, j, k]))
}

/// Position of the multi-index `m` (summing to n) in a degree-n net.
#[inline]
pub(crate) fn index_of(n: usize, m: [usize; 3]) -> usize {
    linear_index(n, m[0], m[1], m[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn count_is_the_triangular_number() {
        for n in 0..20 {
            assert_eq!(point_count(n), (0..=n).map(|k| n - k + 1).sum::<usize>());
            assert_eq!(multi_indices(n).count(), point_count(n));
        }
        assert_eq!(checked_point_count(usize::MAX), None);
        assert_eq!(checked_point_count(usize::MAX - 1), None);
    }

    #[test]
    fn storage_order_is_rows_of_constant_k_by_increasing_j() {
        let order: Vec<[usize; 3]> = multi_indices(2).collect();
        assert_eq!(
            order,
            vec![
                [2, 0, 0],
                [1, 1, 0],
                [0, 2, 0],
                [1, 0, 1],
                [0, 1, 1],
                [0, 0, 2]
            ]
        );
    }

    #[test]
    fn linear_and_multi_index_are_inverse() {
        for n in 0..15 {
            for (l, m) in multi_indices(n).enumerate() {
                assert_eq!(m.iter().sum::<usize>(), n);
                assert_eq!(linear_index(n, m[0], m[1], m[2]), l);
                assert_eq!(multi_index(n, l), m);
            }
        }
    }

    #[test]
    fn first_row_is_the_edge_w_zero_and_last_point_the_apex() {
        let n = 5;
        for j in 0..=n {
            assert_eq!(linear_index(n, n - j, j, 0), j);
        }
        assert_eq!(linear_index(n, 0, 0, n), point_count(n) - 1);
    }

    #[test]
    #[should_panic(expected = "does not sum")]
    fn a_multi_index_of_the_wrong_degree_panics() {
        linear_index(3, 1, 1, 0);
    }

    #[test]
    #[should_panic(expected = "out of range")]
    fn an_index_past_the_end_panics() {
        multi_index(2, 6);
    }
}
