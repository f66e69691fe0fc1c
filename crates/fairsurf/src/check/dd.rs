//! Double-double arithmetic: a number is an unevaluated sum hi + lo of two
//! doubles with |lo| ≤ ulp(hi)/2, about 106 significant bits (ε ≈ 1.1e-32).
//! Dekker (1971), "A floating-point technique for extending the available
//! precision"; the algorithms are those of Hida, Li & Bailey's QD library
//! (sloppy addition is not used: every sum is the accurate one).
//!
//! Only what the independent check of a solve needs: +, −, ×, ÷, √.

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

/// hi + lo, about 32 significant digits.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Dd {
    pub hi: f64,
    pub lo: f64,
}

/// (fl(a + b), a + b − fl(a + b)), exactly (Knuth's TwoSum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// (fl(a + b), error) when |a| ≥ |b| (Dekker's FastTwoSum).
fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// (fl(a·b), a·b − fl(a·b)), exactly while no split overflows.
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, crate::solve::compensated::two_product_error(a, b, p))
}

impl Dd {
    /// The double x, exactly.
    pub const fn new(x: f64) -> Self {
        Self { hi: x, lo: 0.0 }
    }

    /// The nearest double.
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// √x for x ≥ 0 (one Newton step from the double square root).
    pub fn sqrt(self) -> Self {
        if self.hi <= 0.0 {
            return Self::new(0.0);
        }
        let x = self.hi.sqrt();
        let (p, e) = two_prod(x, x);
        let r = (self - Dd { hi: p, lo: e }).hi / (2.0 * x);
        let (hi, lo) = fast_two_sum(x, r);
        Dd { hi, lo }
    }
}

impl From<f64> for Dd {
    fn from(x: f64) -> Self {
        Self::new(x)
    }
}

impl Add for Dd {
    type Output = Dd;
    fn add(self, b: Dd) -> Dd {
        let (s, e) = two_sum(self.hi, b.hi);
        let (t, f) = two_sum(self.lo, b.lo);
        let (s, e) = fast_two_sum(s, e + t);
        let (hi, lo) = fast_two_sum(s, e + f);
        Dd { hi, lo }
    }
}

impl Add<f64> for Dd {
    type Output = Dd;
    fn add(self, b: f64) -> Dd {
        let (s, e) = two_sum(self.hi, b);
        let (hi, lo) = fast_two_sum(s, e + self.lo);
        Dd { hi, lo }
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, b: Dd) -> Dd {
        self + (-b)
    }
}

impl Mul for Dd {
    type Output = Dd;
    fn mul(self, b: Dd) -> Dd {
        let (p, e) = two_prod(self.hi, b.hi);
        let (hi, lo) = fast_two_sum(p, e + (self.hi * b.lo + self.lo * b.hi));
        Dd { hi, lo }
    }
}

impl Mul<f64> for Dd {
    type Output = Dd;
    fn mul(self, b: f64) -> Dd {
        let (p, e) = two_prod(self.hi, b);
        let (hi, lo) = fast_two_sum(p, e + self.lo * b);
        Dd { hi, lo }
    }
}

impl Div for Dd {
    type Output = Dd;
    /// Long division: three double quotients, each from the remainder of the
    /// one before.
    fn div(self, b: Dd) -> Dd {
        let q1 = self.hi / b.hi;
        let r = self - b * q1;
        let q2 = r.hi / b.hi;
        let r = r - b * q2;
        let q3 = r.hi / b.hi;
        let (hi, lo) = fast_two_sum(q1, q2);
        Dd { hi, lo } + q3
    }
}

impl AddAssign for Dd {
    fn add_assign(&mut self, b: Dd) {
        *self = *self + b;
    }
}

impl SubAssign for Dd {
    fn sub_assign(&mut self, b: Dd) {
        *self = *self - b;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 1/3 · 3 = 1 and (1/3)·(1/3)·9 = 1 to about 1e-32; 0.1 + 0.2 − 0.3
    /// gives the exact error of the doubles' sum (5.55e-17 = 2⁻⁵⁴), which a
    /// double computes as 5.55e-17 too only by luck: check the digits.
    /// 1/3 · 3 = 1 and (1/3)·(1/3)·9 = 1 to about 1e-32; 0.1 + 0.2 − 0.3
    /// of the doubles is 2⁻⁵⁵ exactly (computed here in integers), which
    /// double arithmetic rounds to 2⁻⁵⁴.
    #[test]
    fn arithmetic_keeps_thirty_digits() {
        let third = Dd::new(1.0) / Dd::new(3.0);
        let one = third * Dd::new(3.0) - Dd::new(1.0);
        assert!(one.to_f64().abs() < 1e-31, "{one:?}");
        let nine = third * third * 9.0 - Dd::new(1.0);
        assert!(nine.to_f64().abs() < 1e-31, "{nine:?}");
        // 0.1 = a/2⁵⁵, 0.2 = a/2⁵⁴, 0.3 = b/2⁵⁴ as doubles.
        let (a, b): (i64, i64) = (3602879701896397, 5404319552844595);
        assert_eq!(
            (0.1f64 * 2f64.powi(55), 0.3f64 * 2f64.powi(54)),
            (a as f64, b as f64)
        );
        let exact = (3 * a - 2 * b) as f64 / 2f64.powi(55);
        let r = Dd::new(0.1) + Dd::new(0.2) - Dd::new(0.3);
        assert_eq!(r.to_f64(), exact);
        assert_ne!(0.1 + 0.2 - 0.3, exact);
    }

    #[test]
    fn square_root_of_two_squares_back() {
        let s = Dd::new(2.0).sqrt();
        assert!((s * s - Dd::new(2.0)).to_f64().abs() < 1e-31);
        assert_eq!(Dd::new(0.0).sqrt(), Dd::new(0.0));
    }
}
