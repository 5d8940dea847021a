//! The few complex-number operations the cross field needs (a field value is one complex
//! number per vertex, Knöppel et al. 2013).

use std::ops::{Add, Mul, Sub};

/// A complex number `re + i im`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Complex {
    pub re: f64,
    pub im: f64,
}

impl Complex {
    pub const ZERO: Complex = Complex { re: 0.0, im: 0.0 };

    /// `r e^{iθ}`.
    pub fn polar(r: f64, theta: f64) -> Complex {
        Complex { re: r * theta.cos(), im: r * theta.sin() }
    }
    pub fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
    pub fn arg(self) -> f64 {
        self.im.atan2(self.re)
    }
    pub fn conj(self) -> Complex {
        Complex { re: self.re, im: -self.im }
    }
    /// `self / |self|`, or zero for zero.
    pub fn unit(self) -> Complex {
        let m = self.abs();
        if m > 1e-300 {
            self * (1.0 / m)
        } else {
            Complex::ZERO
        }
    }
}

impl Add for Complex {
    type Output = Complex;
    fn add(self, o: Complex) -> Complex {
        Complex { re: self.re + o.re, im: self.im + o.im }
    }
}

impl Sub for Complex {
    type Output = Complex;
    fn sub(self, o: Complex) -> Complex {
        Complex { re: self.re - o.re, im: self.im - o.im }
    }
}

impl Mul for Complex {
    type Output = Complex;
    fn mul(self, o: Complex) -> Complex {
        Complex { re: self.re * o.re - self.im * o.im, im: self.re * o.im + self.im * o.re }
    }
}

impl Mul<f64> for Complex {
    type Output = Complex;
    fn mul(self, s: f64) -> Complex {
        Complex { re: self.re * s, im: self.im * s }
    }
}
