//! A linear-radiance image: what the rasterizer produces and the writers store.

use crate::photometry::LUMENS_PER_WATT;
use crate::rgb::Rgb;

/// A rectangular image of linear radiance, W/(m²·sr), one RGB triple per pixel.
///
/// Pixels are stored row-major with row 0 at the top of the picture, so the
/// pixel in column `x` and row `y` is `pixels()[y * width + x]`. Values are
/// linear (no transfer curve): tone mapping happens only when writing 8-bit
/// output (see [`ToneMap`](crate::ToneMap)).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    width: u32,
    height: u32,
    pixels: Vec<[f32; 3]>,
}

impl Image {
    /// A black image of `width` × `height` pixels.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Image {
        Image::filled(width, height, [0.0; 3])
    }

    /// An image of `width` × `height` pixels, each set to `value`.
    #[must_use]
    pub fn filled(width: u32, height: u32, value: [f32; 3]) -> Image {
        let count = width as usize * height as usize;
        Image {
            width,
            height,
            pixels: vec![value; count],
        }
    }

    /// An image from row-major pixels (row 0 at the top), or `None` when
    /// `pixels.len() != width × height`.
    #[must_use]
    pub fn from_pixels(width: u32, height: u32, pixels: Vec<[f32; 3]>) -> Option<Image> {
        (pixels.len() == width as usize * height as usize).then_some(Image {
            width,
            height,
            pixels,
        })
    }

    /// Width, pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height, pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The radiance of the pixel in column `x`, row `y` (row 0 at the top).
    ///
    /// # Panics
    ///
    /// When `x >= width()` or `y >= height()`.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[self.index(x, y)]
    }

    /// Sets the radiance of the pixel in column `x`, row `y`.
    ///
    /// # Panics
    ///
    /// When `x >= width()` or `y >= height()`.
    pub fn set_pixel(&mut self, x: u32, y: u32, value: [f32; 3]) {
        let index = self.index(x, y);
        self.pixels[index] = value;
    }

    /// All pixels, row-major, row 0 at the top.
    #[must_use]
    pub fn pixels(&self) -> &[[f32; 3]] {
        &self.pixels
    }

    /// Each pixel's photometric value, 179 lm/W × its Rec. 709 luminance
    /// Y: cd/m² in an image of radiance, lx in one of irradiance. What a
    /// false-colour scale is fitted to.
    #[must_use]
    pub fn photometric_values(&self) -> Vec<f64> {
        self.pixels
            .iter()
            .map(|&[r, g, b]| {
                let rgb = Rgb::new(f64::from(r), f64::from(g), f64::from(b));
                rgb.luminance() * LUMENS_PER_WATT
            })
            .collect()
    }

    /// Mean radiance per channel over all pixels, (1/N) Σ L_p; zero for an
    /// empty image. Accumulated in f64.
    #[must_use]
    pub fn mean(&self) -> Rgb {
        if self.pixels.is_empty() {
            return Rgb::ZERO;
        }
        let sum = self.pixels.iter().fold(Rgb::ZERO, |sum, p| {
            sum + Rgb::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
        });
        sum / self.pixels.len() as f64
    }

    fn index(&self, x: u32, y: u32) -> usize {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside a {}×{} image",
            self.width,
            self.height
        );
        y as usize * self.width as usize + x as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_is_row_major_from_the_top() {
        let mut image = Image::new(3, 2);
        image.set_pixel(2, 1, [1.0, 2.0, 3.0]);
        assert_eq!(image.pixels()[5], [1.0, 2.0, 3.0]);
        assert_eq!(image.pixel(2, 1), [1.0, 2.0, 3.0]);
        assert_eq!(image.mean(), Rgb::new(1.0, 2.0, 3.0) / 6.0);
    }

    #[test]
    fn from_pixels_checks_the_length() {
        assert!(Image::from_pixels(2, 2, vec![[0.0; 3]; 3]).is_none());
        assert!(Image::from_pixels(2, 2, vec![[0.0; 3]; 4]).is_some());
        assert_eq!(Image::new(0, 0).mean(), Rgb::ZERO);
    }
}
