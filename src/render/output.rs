//! Image files: linear EXR (written and read back) and tone-mapped PNG.
//!
//! Every writer is atomic: it writes a temporary file `.<name>.tmp-<pid>-<n>`
//! next to the target, then renames it over the target, so an existing file is
//! either left as it was or replaced whole. On failure the temporary file is
//! removed and the error names the target path.

use std::fs::{self, File};
use std::io::{BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use exr::prelude::{ReadChannels, ReadLayers, SpecificChannels, Vec2, WritableImage, read};

use super::image::Image;
use super::tone_map::ToneMap;
use crate::error::{Error, Result};

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

/// Distinguishes temporary files written concurrently by one process.
static TEMPORARY_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Runs `encode` on a temporary file beside `path`, syncs it, and renames it
/// over `path`; removes the temporary file on any failure.
pub(crate) fn write_atomically(
    path: &Path,
    encode: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let temporary = temporary_path(path)?;
    let result = write_then_rename(path, &temporary, encode);
    if result.is_err() {
        // Nothing to report if it was never created.
        let _ = fs::remove_file(&temporary);
    }
    result
}

/// The steps of [`write_atomically`], any of which may fail.
fn write_then_rename(
    path: &Path,
    temporary: &Path,
    encode: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let io = |source| io_error(path, source);
    let mut writer = BufWriter::new(File::create(temporary).map_err(io)?);
    encode(&mut writer)?;
    writer.flush().map_err(io)?;
    let file = writer.into_inner().map_err(|e| io(e.into_error()))?;
    file.sync_all().map_err(io)?;
    fs::rename(temporary, path).map_err(io)
}

/// `.<name>.tmp-<pid>-<n>` in the directory of `path`.
fn temporary_path(path: &Path) -> Result<PathBuf> {
    let name = path
        .file_name()
        .ok_or_else(|| output_error(path, "the path does not name a file"))?;
    let count = TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed);
    let temporary = format!(
        ".{}.tmp-{}-{count}",
        name.to_string_lossy(),
        std::process::id()
    );
    Ok(path.with_file_name(temporary))
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

/// [`Error::Io`] naming `path`.
pub(super) fn io_error(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// [`Error::Output`] naming `path`.
pub(super) fn output_error(path: &Path, message: impl ToString) -> Error {
    Error::Output {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}

fn invalid_image(path: &Path, message: impl ToString) -> Error {
    Error::InvalidImage {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}
