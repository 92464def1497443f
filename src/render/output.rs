//! Image files: linear EXR (written and read back) and tone-mapped PNG.
//!
//! Every writer is atomic (`fs.rs`, `write_atomically`): an existing file
//! is either left as it was or replaced whole, and errors name the target
//! path.

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use exr::prelude::{ReadChannels, ReadLayers, SpecificChannels, Vec2, WritableImage, read};

use super::image::Image;
use super::tone_map::ToneMap;
use crate::error::{Error, Result};
use crate::fs::{io_error, output_error, write_atomically};

/// Writes `image` to `path` as an OpenEXR file of 32-bit float linear RGB
/// (lossless compression), values exactly as stored.
///
/// # Errors
///
/// [`Error::Io`] when the file cannot be created or renamed (missing
/// directory, permission), [`Error::Output`] when the image is empty, holds
/// NaN or an infinity, or cannot be encoded; in every case the target is left untouched.
pub fn write_exr(image: &Image, path: &Path) -> Result<()> {
    ensure_not_empty(image, path)?;
    ensure_finite(image, path)?;
    let width = image.width() as usize;
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let [r, g, b] = image.pixels()[y * width + x];
        (r, g, b)
    });
    let exr_image = exr::prelude::Image::from_channels((width, image.height() as usize), channels);
    write_atomically(path, |writer| {
        exr_image
            .write()
            .to_buffered(writer)
            .map_err(|e| output_error(path, e))
    })
}

/// Reads the RGB channels of the first layer of an OpenEXR file, at full
/// resolution, as linear radiance (f16 and u32 samples are converted to f32).
///
/// # Errors
///
/// [`Error::Io`] when the file cannot be opened, [`Error::InvalidImage`]
/// when it is not an EXR file with R, G and B channels.
pub fn read_exr(path: &Path) -> Result<Image> {
    let file = File::open(path).map_err(|source| io_error(path, source))?;
    let exr_image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |resolution: Vec2<usize>, _| {
                (resolution.width(), vec![[0.0_f32; 3]; resolution.area()])
            },
            |(width, pixels): &mut (usize, Vec<[f32; 3]>),
             at: Vec2<usize>,
             (r, g, b): (f32, f32, f32)| {
                pixels[at.y() * *width + at.x()] = [r, g, b];
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(BufReader::new(file))
        .map_err(|e| invalid_image(path, e))?;
    let layer = exr_image.layer_data;
    let (width, height) = (layer.size.width(), layer.size.height());
    let (_, pixels) = layer.channel_data.pixels;
    let size = u32::try_from(width).ok().zip(u32::try_from(height).ok());
    size.and_then(|(w, h)| Image::from_pixels(w, h, pixels))
        .ok_or_else(|| invalid_image(path, format!("unsupported size {width}×{height}")))
}

/// Writes `image` to `path` as an 8-bit sRGB PNG, each channel mapped by
/// `tone_map` (exposure, sRGB curve, clamp, rounding).
///
/// # Errors
///
/// [`Error::Io`] when the file cannot be created or renamed, [`Error::Output`]
/// when the image is empty, holds NaN or an infinity, the exposure is not
/// finite, or encoding fails; the target is then untouched.
pub fn write_png(image: &Image, tone_map: &ToneMap, path: &Path) -> Result<()> {
    ensure_not_empty(image, path)?;
    ensure_finite(image, path)?;
    if !tone_map.exposure.is_finite() {
        return Err(output_error(
            path,
            format!(
                "the exposure {} is not a finite number of stops",
                tone_map.exposure
            ),
        ));
    }
    let bytes: Vec<u8> = image
        .pixels()
        .iter()
        .flat_map(|&p| tone_map.map_pixel(p))
        .collect();
    let rgb = ::image::RgbImage::from_raw(image.width(), image.height(), bytes)
        .ok_or_else(|| output_error(path, "pixel buffer does not match the image size"))?;
    write_atomically(path, |writer| {
        rgb.write_with_encoder(::image::codecs::png::PngEncoder::new(writer))
            .map_err(|e| output_error(path, e))
    })
}

/// Refuses images without pixels, which neither format can hold.
fn ensure_not_empty(image: &Image, path: &Path) -> Result<()> {
    if image.width() == 0 || image.height() == 0 {
        return Err(output_error(
            path,
            format!("the image is empty ({}×{})", image.width(), image.height()),
        ));
    }
    Ok(())
}

/// Refuses images holding NaN or an infinity: a bug upstream, which must
/// not reach a file as if it were a picture.
fn ensure_finite(image: &Image, path: &Path) -> Result<()> {
    let width = image.width() as usize;
    match image
        .pixels()
        .iter()
        .position(|p| p.iter().any(|c| !c.is_finite()))
    {
        None => Ok(()),
        Some(index) => Err(output_error(
            path,
            format!(
                "pixel ({}, {}) is {:?}: the image holds a non-finite value, nothing was written",
                index % width,
                index / width,
                image.pixels()[index]
            ),
        )),
    }
}

fn invalid_image(path: &Path, message: impl ToString) -> Error {
    Error::InvalidImage {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}
