//! Linear RGB triples: reflectance, radiance, radiosity and power per channel.
//!
//! Each operation computes channel by channel exactly what glam's `DVec3`
//! computes for x, y and z (the type `Rgb` once was), so that replacing one
//! by the other changes no result by a bit.

use std::fmt;
use std::iter::Sum;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, Sub};

/// A linear RGB triple. Its unit depends on the quantity it holds
/// (reflectance: none; radiance: W/(m²·sr); radiosity: W/m²; power: W).
/// The default is black, [`Rgb::ZERO`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rgb {
    /// Red.
    pub r: f64,
    /// Green.
    pub g: f64,
    /// Blue.
    pub b: f64,
}

impl Rgb {
    /// Zero in every channel.
    pub const ZERO: Rgb = Rgb::splat(0.0);
    /// One in every channel.
    pub const ONE: Rgb = Rgb::splat(1.0);

    /// The triple (r, g, b).
    #[must_use]
    pub const fn new(r: f64, g: f64, b: f64) -> Rgb {
        Rgb { r, g, b }
    }

    /// The same value in every channel.
    #[must_use]
    pub const fn splat(value: f64) -> Rgb {
        Rgb::new(value, value, value)
    }

    /// `[r, g, b]`.
    #[must_use]
    pub const fn to_array(self) -> [f64; 3] {
        [self.r, self.g, self.b]
    }

    /// `[r, g, b]`, each channel rounded to `f32` (for image buffers).
    #[must_use]
    pub fn to_f32_array(self) -> [f32; 3] {
        self.to_array().map(|c| c as f32)
    }

    /// r + g + b, summed in that order.
    #[must_use]
    pub fn element_sum(self) -> f64 {
        self.r + self.g + self.b
    }

    /// The largest channel, `larger(larger(r, g), b)` as glam computes it.
    #[must_use]
    pub fn max_element(self) -> f64 {
        larger(larger(self.r, self.g), self.b)
    }

    /// The smallest channel, `smaller(smaller(r, g), b)` as glam computes it.
    #[must_use]
    pub fn min_element(self) -> f64 {
        smaller(smaller(self.r, self.g), self.b)
    }

    /// The larger of `self` and `other` in each channel, as glam computes it.
    #[must_use]
    pub fn max(self, other: Rgb) -> Rgb {
        self.zip(other, larger)
    }

    /// The smaller of `self` and `other` in each channel.
    fn min(self, other: Rgb) -> Rgb {
        self.zip(other, smaller)
    }

    /// Each channel clamped to `[min, max]`: `self.max(min).min(max)`.
    #[must_use]
    pub fn clamp(self, min: Rgb, max: Rgb) -> Rgb {
        self.max(min).min(max)
    }

    /// 1 / c in each channel.
    #[must_use]
    pub fn recip(self) -> Rgb {
        self.map(|c| 1.0 / c)
    }

    /// |c| in each channel.
    #[must_use]
    pub fn abs(self) -> Rgb {
        self.map(f64::abs)
    }

    /// True when every channel is finite.
    #[must_use]
    pub fn is_finite(self) -> bool {
        self.r.is_finite() && self.g.is_finite() && self.b.is_finite()
    }

    /// Rec. 709 luminance Y = 0.2126 r + 0.7152 g + 0.0722 b.
    #[must_use]
    pub fn luminance(self) -> f64 {
        0.2126 * self.r + 0.7152 * self.g + 0.0722 * self.b
    }

    /// `f` applied to each channel.
    fn map(self, f: impl Fn(f64) -> f64) -> Rgb {
        Rgb::new(f(self.r), f(self.g), f(self.b))
    }

    /// `f` applied to each channel of `self` and `other`.
    fn zip(self, other: Rgb, f: impl Fn(f64, f64) -> f64) -> Rgb {
        Rgb::new(f(self.r, other.r), f(self.g, other.g), f(self.b, other.b))
    }
}

/// glam's maximum: `a` when `a > b`, otherwise `b` (so a NaN `b` is
/// returned, a NaN `a` is not).
fn larger(a: f64, b: f64) -> f64 {
    if a > b { a } else { b }
}

/// glam's minimum: `a` when `a < b`, otherwise `b`.
fn smaller(a: f64, b: f64) -> f64 {
    if a < b { a } else { b }
}

/// `[r, g, b]`, as glam prints a vector.
impl fmt::Display for Rgb {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(precision) = f.precision() {
            write!(
                f,
                "[{:.*}, {:.*}, {:.*}]",
                precision, self.r, precision, self.g, precision, self.b
            )
        } else {
            write!(f, "[{}, {}, {}]", self.r, self.g, self.b)
        }
    }
}

/// Channel-wise sum.
impl Add for Rgb {
    type Output = Rgb;
    fn add(self, other: Rgb) -> Rgb {
        self.zip(other, |a, b| a + b)
    }
}

/// Channel-wise difference.
impl Sub for Rgb {
    type Output = Rgb;
    fn sub(self, other: Rgb) -> Rgb {
        self.zip(other, |a, b| a - b)
    }
}

/// Channel-wise product: a reflectance filtering a radiosity.
impl Mul for Rgb {
    type Output = Rgb;
    fn mul(self, other: Rgb) -> Rgb {
        self.zip(other, |a, b| a * b)
    }
}

/// Each channel scaled by `s`.
impl Mul<f64> for Rgb {
    type Output = Rgb;
    fn mul(self, s: f64) -> Rgb {
        self.map(|c| c * s)
    }
}

/// Channel-wise quotient.
impl Div for Rgb {
    type Output = Rgb;
    fn div(self, other: Rgb) -> Rgb {
        self.zip(other, |a, b| a / b)
    }
}

/// Each channel divided by `s`.
impl Div<f64> for Rgb {
    type Output = Rgb;
    fn div(self, s: f64) -> Rgb {
        self.map(|c| c / s)
    }
}

/// `self = self + other`.
impl AddAssign for Rgb {
    fn add_assign(&mut self, other: Rgb) {
        *self = *self + other;
    }
}

/// `self = self / s`.
impl DivAssign<f64> for Rgb {
    fn div_assign(&mut self, s: f64) {
        *self = *self / s;
    }
}

/// Σ from [`Rgb::ZERO`], added in iteration order.
impl Sum for Rgb {
    fn sum<I: Iterator<Item = Rgb>>(iter: I) -> Rgb {
        iter.fold(Rgb::ZERO, Rgb::add)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn vec(rgb: Rgb) -> DVec3 {
        DVec3::from_array(rgb.to_array())
    }

    /// Every operation matches glam's `DVec3` bit for bit, NaN and infinity
    /// included.
    #[test]
    fn matches_glam_bit_for_bit() {
        let values = [
            0.1,
            -0.0,
            0.7,
            1.0 / 3.0,
            f64::NAN,
            2.5e-300,
            f64::INFINITY,
            -4.0,
        ];
        let bits = |v: DVec3| v.to_array().map(f64::to_bits);
        let same = |a: Rgb, b: DVec3| assert_eq!(a.to_array().map(f64::to_bits), bits(b));
        for (k, &x) in values.iter().enumerate() {
            let a = Rgb::new(x, values[(k + 3) % 8], values[(k + 5) % 8]);
            let b = Rgb::new(values[(k + 1) % 8], values[(k + 6) % 8], x);
            let (va, vb) = (vec(a), vec(b));
            same(a + b, va + vb);
            same(a - b, va - vb);
            same(a * b, va * vb);
            same(a / b, va / vb);
            same(a * 0.3, va * 0.3);
            same(a / 0.3, va / 0.3);
            same(a.max(b), va.max(vb));
            same(a.min(b), va.min(vb));
            same(a.recip(), va.recip());
            same(a.abs(), va.abs());
            same([a, b, a].into_iter().sum(), [va, vb, va].into_iter().sum());
            same(
                a.clamp(Rgb::ZERO, Rgb::ONE),
                va.clamp(DVec3::ZERO, DVec3::ONE),
            );
            assert_eq!(
                a.to_f32_array().map(f32::to_bits),
                va.as_vec3().to_array().map(f32::to_bits)
            );
            assert_eq!(a.element_sum().to_bits(), va.element_sum().to_bits());
            assert_eq!(a.max_element().to_bits(), va.max_element().to_bits());
            assert_eq!(a.min_element().to_bits(), va.min_element().to_bits());
            assert_eq!(a.is_finite(), va.is_finite());
            assert_eq!(
                a.luminance().to_bits(),
                (0.2126 * va.x + 0.7152 * va.y + 0.0722 * va.z).to_bits()
            );
            assert_eq!(a.to_string(), va.to_string());
        }
    }
}
