//! A sparse matrix built column by column into a dense accumulator
//! (Gustavson 1978, "Two fast algorithms for sparse matrices"): each
//! column's entries are summed where they fall and its rows sorted once —
//! no global sort of triplets, and every entry summed in the order the
//! caller adds them (so the result does not depend on a sort's order).

use faer::sparse::{SparseColMat, SymbolicSparseColMat};

/// An n × n sparse matrix under construction, one column at a time.
pub(crate) struct Columns {
    n: usize,
    col_ptr: Vec<usize>,
    rows: Vec<usize>,
    values: Vec<f64>,
    sum: Vec<f64>,
    /// The column a row's accumulator was last opened in.
    mark: Vec<usize>,
    touched: Vec<usize>,
}

impl Columns {
    /// An empty n × n matrix, its first column open.
    pub(crate) fn new(n: usize) -> Self {
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        Self {
            n,
            col_ptr,
            rows: Vec::new(),
            values: Vec::new(),
            sum: vec![0.0; n],
            mark: vec![usize::MAX; n],
            touched: Vec::new(),
        }
    }

    /// Adds v to entry (row, the open column).
    #[inline]
    pub(crate) fn add(&mut self, row: usize, v: f64) {
        let col = self.col_ptr.len() - 1;
        if self.mark[row] != col {
            self.mark[row] = col;
            self.sum[row] = 0.0;
            self.touched.push(row);
        }
        self.sum[row] += v;
    }

    /// Closes the open column (its rows sorted) and opens the next.
    pub(crate) fn next_column(&mut self) {
        self.touched.sort_unstable();
        self.rows.extend_from_slice(&self.touched);
        self.values
            .extend(self.touched.iter().map(|&r| self.sum[r]));
        self.touched.clear();
        self.col_ptr.push(self.rows.len());
    }

    /// The matrix, once all n columns are closed.
    pub(crate) fn finish(self) -> SparseColMat<usize, f64> {
        assert_eq!(self.col_ptr.len(), self.n + 1, "every column closed");
        let symbolic =
            SymbolicSparseColMat::new_checked(self.n, self.n, self.col_ptr, None, self.rows);
        SparseColMat::new(symbolic, self.values)
    }
}
