//! Compensated arithmetic: products and dot products carried to about
//! twice the working precision (Ogita, Rump & Oishi 2005, "Accurate sum and
//! dot product"; Dekker's and Veltkamp's exact product and split), for the
//! residuals of iterative refinement and the checks' sums, with a run-time
//! dispatch to fused multiply-add where the CPU has it.

use faer::Mat;

/// Runs `fast` compiled for and on a CPU with fused multiply-add (x86-64-v3
/// and up, detected at run time), else `portable`: the two are the same
/// computation with [`two_product_err`]'s two exact forms. What `fast`
/// calls must be inlined into it (`#[inline(always)]`, no closures handed
/// to other crates' generic code), or it runs without the target feature
/// and `mul_add` becomes a library call.
#[inline(always)]
pub(crate) fn with_fma<R>(fast: impl FnOnce() -> R, portable: impl FnOnce() -> R) -> R {
    match pulp::Arch::new() {
        pulp::Arch::Scalar => portable(),
        #[allow(unreachable_patterns)]
        arch => arch.dispatch(fast),
    }
}

/// B − H X with every entry computed by a compensated dot product (about
/// twice the working precision before the final rounding).
pub(crate) fn residual(h: &Mat<f64>, x: &Mat<f64>, b: &Mat<f64>) -> Mat<f64> {
    with_fma(
        #[inline(always)]
        || residual_with::<true>(h, x, b),
        || residual_with::<false>(h, x, b),
    )
}

#[inline(always)]
fn residual_with<const FMA: bool>(h: &Mat<f64>, x: &Mat<f64>, b: &Mat<f64>) -> Mat<f64> {
    let n = h.nrows();
    let mut r = Mat::<f64>::zeros(n, x.ncols());
    for c in 0..x.ncols() {
        let (xc, bc) = (x.col_as_slice(c), b.col_as_slice(c));
        for (i, ri) in r.col_as_slice_mut(c).iter_mut().enumerate() {
            // Row i of symmetric H is its column i, contiguous in memory.
            *ri = dot2_residual_with::<FMA>(bc[i], h.col_as_slice(i), xc);
        }
    }
    r
}

/// b − Σ a_j x_j by Ogita, Rump & Oishi's Dot2 (2005): error-free products
/// (TwoProduct) and sums (Knuth's TwoSum), errors accumulated apart.
///
/// [`DOT2_LANES`] independent Dot2 accumulators over interleaved terms,
/// joined by error-free sums at the end: one chain of TwoSums is bound by
/// its latency, many run side by side in vector registers (the error bound
/// is Dot2's with n/L + L terms). Compiled for and run with fused
/// multiply-add where the CPU has it ([`with_fma`]: the product's error is
/// one FMA, the lanes fill AVX2 registers), else with Dekker's split; both
/// give the product's error exactly, so the same bits, while |a_j|, |x_j| <
/// 2^995 or so (the split by 2^27 + 1 must not overflow) and the products
/// stay above the underflow threshold (2^−969 or so: below it neither error
/// is exact, and the two may differ in the last bits of a term that small).
/// Inside another [`with_fma`] context call [`dot2_residual_with`] instead:
/// the dispatch is per call here.
pub(crate) fn dot2_residual(b: f64, a: &[f64], x: &[f64]) -> f64 {
    with_fma(
        #[inline(always)]
        || dot2_residual_with::<true>(b, a, x),
        || dot2_residual_with::<false>(b, a, x),
    )
}

/// Lanes of [`dot2_residual`]: four AVX2 registers of accumulators.
const DOT2_LANES: usize = 16;

/// [`dot2_residual`] with the product's error by FMA (`FMA = true`: only
/// inside [`with_fma`]'s fast branch) or by Dekker's split.
#[inline(always)]
pub(crate) fn dot2_residual_with<const FMA: bool>(b: f64, a: &[f64], x: &[f64]) -> f64 {
    const L: usize = DOT2_LANES;
    let mut s = [0.0; L];
    let mut c = [0.0; L];
    s[0] = b;
    let n = a.len().min(x.len());
    let body = n - n % L;
    for (ac, xc) in a[..body].chunks_exact(L).zip(x[..body].chunks_exact(L)) {
        for k in 0..L {
            let p = -ac[k] * xc[k];
            let ep = two_product_err::<FMA>(-ac[k], xc[k], p);
            let (t, es) = two_sum(s[k], p);
            s[k] = t;
            c[k] += ep + es;
        }
    }
    for j in body..n {
        let p = -a[j] * x[j];
        let ep = two_product_err::<FMA>(-a[j], x[j], p);
        let (t, es) = two_sum(s[0], p);
        s[0] = t;
        c[0] += ep + es;
    }
    let mut total = s[0];
    let mut err = c.iter().sum::<f64>();
    for &sk in &s[1..] {
        let (t, e) = two_sum(total, sk);
        total = t;
        err += e;
    }
    total + err
}

/// (fl(a + b), a + b − fl(a + b)), exactly (Knuth's TwoSum).
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let t = a + b;
    let z = t - a;
    (t, (a - (t - z)) + (b - z))
}

/// The rounding error a·b − p of p = fl(a·b), exactly: one fused
/// multiply-add, or Dekker's split ([`two_product_error`]). Call with
/// `FMA = true` only inside [`with_fma`]'s fast branch: elsewhere `mul_add`
/// is a library call.
#[inline(always)]
pub(crate) fn two_product_err<const FMA: bool>(a: f64, b: f64, p: f64) -> f64 {
    if FMA {
        a.mul_add(b, -p)
    } else {
        two_product_error(a, b, p)
    }
}

/// The rounding error a·b − p of p = fl(a·b), exactly (Dekker 1971):
/// a and b split into 26-bit halves whose products are exact.
#[inline(always)]
pub(crate) fn two_product_error(a: f64, b: f64, p: f64) -> f64 {
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    ((ah * bh - p) + ah * bl + al * bh) + al * bl
}

/// Veltkamp's split a = hi + lo, each with at most 26 significant bits.
#[inline(always)]
fn split(a: f64) -> (f64, f64) {
    const FACTOR: f64 = 134_217_729.0; // 2^27 + 1
    let c = FACTOR * a;
    let hi = c - (c - a);
    (hi, a - hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dekker's product error equals the fused multiply-add's (exact) on
    /// awkward operands.
    #[test]
    fn two_product_error_is_exact() {
        let mut r = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..10_000 {
            r ^= r << 13;
            r ^= r >> 7;
            r ^= r << 17;
            let a = f64::from_bits((r & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000)
                * 2f64.powi((r >> 52) as i32 % 200 - 100);
            let b = f64::from_bits(((r >> 7) & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000)
                * if r & 1 == 0 { -1.0 } else { 1.0 };
            let p = a * b;
            assert_eq!(two_product_error(a, b, p), a.mul_add(b, -p), "{a} {b}");
        }
    }

    /// Long sums that cancel to a small integer, across lanes and the
    /// remainder: Dot2 gets them exactly where plain summation loses them.
    #[test]
    fn dot2_is_exact_on_cancelling_sums() {
        for n in [1, 2, 5, 13, 81] {
            let (mut a, mut exact) = (Vec::new(), 0.0);
            for k in 0..n {
                // A 2^53-scale term, a small odd integer, the big term back.
                let big = (1u64 << 53) as f64 * (1 + k % 7) as f64;
                let small = (2 * (k % 5) + 1) as f64;
                a.extend([big, small, -big]);
                exact += small;
            }
            let x = vec![1.0; a.len()];
            assert_eq!(-dot2_residual(0.0, &a, &x), exact, "n = {n}");
            if n == 1 || n == 81 {
                let plain: f64 = a.iter().sum();
                assert_ne!(plain, exact, "the plain sum loses the odd parts, n = {n}");
            }
        }
    }

    /// The two forms of the product's error (a fused multiply-add, Dekker's
    /// split) give the same bits, and so do the residual's two builds: on
    /// long rows of mixed magnitudes, with and without a remainder past
    /// the lanes.
    #[test]
    fn dot2_with_and_without_fma_agree_bit_for_bit() {
        for n in [3, 16, 17, 243, 250] {
            let a: Vec<f64> = (0..n)
                .map(|k| ((k * 7919 % 1013) as f64 - 506.5) * 10f64.powi(k % 9 - 4))
                .collect();
            let x: Vec<f64> = (0..n).map(|k| 1.0 / (1.0 + k as f64) - 0.37).collect();
            let b = 0.1 * n as f64;
            let fma = dot2_residual_with::<true>(b, &a, &x);
            assert_eq!(
                fma.to_bits(),
                dot2_residual_with::<false>(b, &a, &x).to_bits(),
                "{n}"
            );
            assert_eq!(fma.to_bits(), dot2_residual(b, &a, &x).to_bits(), "{n}");
        }
        let h = Mat::from_fn(20, 20, |i, j| 1.0 / (1.0 + i as f64 + j as f64));
        let x = Mat::from_fn(20, 3, |i, c| (i * 3 + c) as f64 - 7.5);
        let b = Mat::from_fn(20, 3, |i, c| (i + c) as f64 * 0.25);
        let r = residual(&h, &x, &b);
        for c in 0..3 {
            for i in 0..20 {
                let want =
                    dot2_residual_with::<false>(b[(i, c)], h.col_as_slice(i), x.col_as_slice(c));
                assert_eq!(r[(i, c)].to_bits(), want.to_bits());
            }
        }
    }

    #[test]
    fn dot2_recovers_cancelled_digits() {
        // 1e16 + 1 − 1e16 in plain arithmetic is 0 or 2; Dot2 gives 1.
        let a = [1e16, 1.0, -1e16];
        let x = [1.0, 1.0, 1.0];
        assert_eq!(dot2_residual(0.0, &a, &x), -1.0);
    }
}
