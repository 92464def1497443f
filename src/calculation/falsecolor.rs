//! False-colour pictures, as Radiance's `falsecolor` makes them: each value
//! painted with the colour of its band on a scale from 0 to a maximum, and
//! a legend beside the picture with one swatch per band and the values
//! between them.
//!
//! The scale and its palette ([`FalseColorScale`], viridis) are in the
//! `falsecolor_scale` module; this one composes the pictures.
//!
//! **The pictures.** [`write_falsecolor_image`] paints a raster one pixel
//! per value (a camera view of luminance); [`write_falsecolor_grid`] paints
//! a calculation grid's points as cells scaled up to 720 pixels across,
//! with the surface's outline and the luminaires over them, in lux. Both
//! put a 36-pixel title band above the picture and the legend to its right
//! (160 pixels wide: the unit, then the swatches, highest at the top, 24
//! pixels each, labelled at their boundaries), and write PNG.
//!
//! # References
//! - G. Ward, `falsecolor`(1), Radiance (the picture and its legend).

use std::path::Path;

use ::image::{Rgb as Rgb8, RgbImage};
use glam::DVec2;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::falsecolor_scale::{FalseColorScale, NO_DATA};
use super::grid_picture::{GridPicture, Rect2};
use super::levels::format_lux;
use crate::error::Result;
use crate::font::{FONT_FAMILY, ensure_font_registered};
use crate::fs::{output_error, write_atomically};

/// Text on the background.
const TEXT: RGBColor = RGBColor(230, 230, 230);
/// Height of the title band, pixels.
const TITLE_HEIGHT: u32 = 36;
/// Width of the legend, pixels.
const LEGEND_WIDTH: u32 = 160;
/// Height of one swatch, pixels.
const SWATCH_HEIGHT: u32 = 24;
/// Width of a swatch, pixels.
const SWATCH_WIDTH: u32 = 28;
/// Room above the swatches for the unit, pixels.
const LEGEND_HEADER: u32 = 36;
/// The larger side of a grid's picture, pixels (before its margin).
const GRID_SIZE: f64 = 720.0;
/// Pixels around a grid's picture.
const GRID_MARGIN: u32 = 24;
/// Largest raster side [`write_falsecolor_image`] takes, pixels.
const MAX_RASTER: u32 = 16_384;

/// Writes a false-colour picture of a raster of `values` (`width` ×
/// `height`, row-major, top row first; NaN = no data, painted dark grey) to
/// `path` as PNG: one pixel per value, a title band above, and the legend
/// to the right, its labels followed by `unit` ("cd/m²", "lx"). The picture
/// is `width + 160` pixels wide and `36 + max(height, legend)` high, the
/// legend 36 + 24 · steps + 12 pixels. Written atomically.
///
/// # Errors
///
/// [`Error::Output`](crate::Error::Output) when the extension is not
/// `.png`, when `width` or `height` is 0 or above 16 384, when `values`
/// does not hold `width · height` values, when the scale's maximum is not
/// finite and positive, or drawing fails; [`Error::Io`](crate::Error::Io)
/// when the file cannot be written. The target is then untouched.
pub fn write_falsecolor_image(
    path: &Path,
    values: &[f64],
    width: u32,
    height: u32,
    scale: &FalseColorScale,
    unit: &str,
    title: &str,
) -> Result<()> {
    check_png(path)?;
    let sides = 1..=MAX_RASTER;
    if !sides.contains(&width) || !sides.contains(&height) {
        return Err(output_error(
            path,
            format!("a false-colour raster of {width} × {height} pixels cannot be drawn"),
        ));
    }
    if values.len() != width as usize * height as usize {
        return Err(output_error(
            path,
            format!(
                "a raster of {width} × {height} pixels has {} values",
                values.len()
            ),
        ));
    }
    scale.check().map_err(|e| output_error(path, e))?;
    let mut picture = canvas(width, height, scale);
    for (index, &value) in values.iter().enumerate() {
        let (x, y) = (index as u32 % width, index as u32 / width);
        picture.put_pixel(x, TITLE_HEIGHT + y, Rgb8(scale.colour(value)));
    }
    let legend_left = width;
    draw_legend(&mut picture, legend_left, scale, unit).map_err(|e| output_error(path, e))?;
    draw_title(&mut picture, title).map_err(|e| output_error(path, e))?;
    save_png(path, &picture)
}

/// Writes a false-colour picture of a calculation grid to `path` as PNG:
/// each point painted as the cell around it (one spacing across, centred on
/// the point), the picture's larger side 720 pixels plus a margin of 24,
/// the y axis up; the outline in white over the cells, each luminaire as a
/// white disc with a black ring and cross, its label beside it; the grid's
/// title above and the legend, in lux, to the right. Pixels outside every
/// cell, and cells without a value, are dark grey. Written atomically.
///
/// # Errors
///
/// [`Error::Output`](crate::Error::Output) when the extension is not
/// `.png`, when the grid is inconsistent (as for
/// [`write_isolux_plot`](super::write_isolux_plot)), when the scale's
/// maximum is not finite and positive, or drawing fails;
/// [`Error::Io`](crate::Error::Io) when the file cannot be written.
pub fn write_falsecolor_grid(
    path: &Path,
    picture: &GridPicture,
    scale: &FalseColorScale,
) -> Result<()> {
    check_png(path)?;
    picture.check().map_err(|e| output_error(path, e))?;
    scale.check().map_err(|e| output_error(path, e))?;
    let frame = GridFrame::new(picture);
    let mut image = canvas(frame.size.0, frame.size.1, scale);

    // Each pixel takes the value of the grid point nearest its centre.
    for y in 0..frame.size.1 {
        for x in 0..frame.size.0 {
            let plane = frame.plane_from_pixel(DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5));
            let grid = (plane - picture.origin) / picture.spacing;
            let (column, row) = (grid.x.round(), grid.y.round());
            let inside = (0.0..picture.columns as f64).contains(&column)
                && (0.0..picture.rows as f64).contains(&row);
            if inside {
                let value = picture.values[row as usize * picture.columns + column as usize];
                image.put_pixel(x, TITLE_HEIGHT + y, Rgb8(scale.colour(value)));
            }
        }
    }

    draw_plan(&mut image, picture, &frame).map_err(|e| output_error(path, e))?;
    draw_legend(&mut image, frame.size.0, scale, picture.unit)
        .map_err(|e| output_error(path, e))?;
    draw_title(&mut image, picture.title).map_err(|e| output_error(path, e))?;
    save_png(path, &image)
}

/// [`Error::Output`](crate::Error::Output) unless `path` ends in `.png`
/// (case-insensitive); also checks that the font loads.
fn check_png(path: &Path) -> Result<()> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if extension.as_deref() != Some("png") {
        return Err(output_error(
            path,
            "a false-colour picture is written as .png; give the file that extension",
        ));
    }
    if !ensure_font_registered() {
        return Err(output_error(path, "the bundled font cannot be loaded"));
    }
    Ok(())
}

/// A dark grey canvas for a picture of `width` × `height` pixels under the
/// title band, with the legend of `scale` to its right.
fn canvas(width: u32, height: u32, scale: &FalseColorScale) -> RgbImage {
    let legend_height = LEGEND_HEADER + SWATCH_HEIGHT * scale.bands() as u32 + 12;
    RgbImage::from_pixel(
        width + LEGEND_WIDTH,
        TITLE_HEIGHT + height.max(legend_height),
        Rgb8(NO_DATA),
    )
}

/// Where a grid's plane lies in its picture: `pixels_per_metre`, the
/// plane point at the picture's lower-left corner, the picture's size
/// (pixels, below the title band).
struct GridFrame {
    pixels_per_metre: f64,
    lower_left: DVec2,
    size: (u32, u32),
}

impl GridFrame {
    /// The frame holding every cell, the outline and the luminaires, its
    /// larger side [`GRID_SIZE`] pixels, within [`GRID_MARGIN`].
    fn new(picture: &GridPicture) -> GridFrame {
        let half_cell = 0.5 * picture.spacing.abs();
        let Rect2 { low, high } = picture.bounds().map_or(
            Rect2 {
                low: -DVec2::ONE,
                high: DVec2::ONE,
            },
            |Rect2 { low, high }| Rect2 {
                low: low - half_cell,
                high: high + half_cell,
            },
        );
        let extent = (high - low).max_element();
        let pixels_per_metre = if extent > 0.0 && extent.is_finite() {
            GRID_SIZE / extent
        } else {
            1.0
        };
        let margin = f64::from(GRID_MARGIN) / pixels_per_metre;
        let size =
            ((high - low) * pixels_per_metre).ceil() + DVec2::splat(2.0 * f64::from(GRID_MARGIN));
        let side = |s: f64| s.clamp(1.0, GRID_SIZE + 2.0 * f64::from(GRID_MARGIN)) as u32;
        GridFrame {
            pixels_per_metre,
            lower_left: low - DVec2::splat(margin),
            size: (side(size.x), side(size.y)),
        }
    }

    /// The plane point at a pixel position (x right, y down from the top
    /// of the picture, below the title band).
    fn plane_from_pixel(&self, pixel: DVec2) -> DVec2 {
        let up = DVec2::new(pixel.x, f64::from(self.size.1) - pixel.y);
        self.lower_left + up / self.pixels_per_metre
    }

    /// The canvas pixel (title band included) of a plane point, held within
    /// a few pictures of the canvas so that lines stay short.
    fn canvas_pixel(&self, plane: DVec2) -> (i32, i32) {
        let up = (plane - self.lower_left) * self.pixels_per_metre;
        let pixel = DVec2::new(
            up.x,
            f64::from(self.size.1) - up.y + f64::from(TITLE_HEIGHT),
        );
        let reach = 4.0 * GRID_SIZE;
        let pixel = pixel.clamp(DVec2::splat(-reach), DVec2::splat(2.0 * reach));
        (pixel.x.round() as i32, pixel.y.round() as i32)
    }
}

/// The outline and the luminaires over a grid's cells.
fn draw_plan(
    image: &mut RgbImage,
    picture: &GridPicture,
    frame: &GridFrame,
) -> std::result::Result<(), String> {
    let size = image.dimensions();
    let root = BitMapBackend::with_buffer(image, size).into_drawing_area();
    for polygon in picture.outlines {
        let mut outline: Vec<(i32, i32)> = polygon
            .iter()
            .filter(|p| p.is_finite())
            .map(|&p| frame.canvas_pixel(p))
            .collect();
        if let Some(&first) = outline.first() {
            outline.push(first);
        }
        root.draw(&PathElement::new(outline, WHITE.stroke_width(2)))
            .map_err(|e| e.to_string())?;
    }
    let ring = BLACK.stroke_width(2);
    for (position, label) in picture.luminaires.iter().filter(|(p, _)| p.is_finite()) {
        let (x, y) = frame.canvas_pixel(*position);
        root.draw(&Circle::new((x, y), 8, WHITE.filled()))
            .map_err(|e| e.to_string())?;
        root.draw(&Circle::new((x, y), 8, ring))
            .map_err(|e| e.to_string())?;
        root.draw(&PathElement::new(
            vec![(x - 5, y - 5), (x + 5, y + 5)],
            ring,
        ))
        .map_err(|e| e.to_string())?;
        root.draw(&PathElement::new(
            vec![(x - 5, y + 5), (x + 5, y - 5)],
            ring,
        ))
        .map_err(|e| e.to_string())?;
        let style = (FONT_FAMILY, 14).into_font();
        let (width, height) = root
            .estimate_text_size(label, &TextStyle::from(style.clone()))
            .map_err(|e| e.to_string())?;
        let corner = (x + 11, y - 24);
        let far = (corner.0 + width as i32 + 6, corner.1 + height as i32 + 4);
        root.draw(&Rectangle::new([corner, far], BLACK.mix(0.7).filled()))
            .map_err(|e| e.to_string())?;
        root.draw_text(label, &style.color(&WHITE), (corner.0 + 3, corner.1 + 2))
            .map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}

/// The legend at `left`: the unit, then one swatch per band (highest at the
/// top), each boundary labelled with its value.
fn draw_legend(
    image: &mut RgbImage,
    left: u32,
    scale: &FalseColorScale,
    unit: &str,
) -> std::result::Result<(), String> {
    // Swatches in their exact colours.
    let bands = scale.bands() as u32;
    let swatch_left = left + 16;
    let top = TITLE_HEIGHT + LEGEND_HEADER;
    for band in 0..bands {
        let colour = Rgb8(scale.band_colour(band as usize));
        let swatch_top = top + (bands - 1 - band) * SWATCH_HEIGHT;
        for y in swatch_top..swatch_top + SWATCH_HEIGHT {
            for x in swatch_left..swatch_left + SWATCH_WIDTH {
                image.put_pixel(x, y, colour);
            }
        }
    }

    // The unit above, the values beside.
    let size = image.dimensions();
    let root = BitMapBackend::with_buffer(image, size).into_drawing_area();
    let style = (FONT_FAMILY, 15).into_font().color(&TEXT);
    root.draw_text(
        unit,
        &style,
        (swatch_left as i32, (TITLE_HEIGHT + 10) as i32),
    )
    .map_err(|e| e.to_string())?;
    let beside = style.pos(Pos::new(HPos::Left, VPos::Center));
    for (i, value) in scale.boundaries().into_iter().enumerate() {
        let y = top + (bands - i as u32) * SWATCH_HEIGHT;
        let x = swatch_left + SWATCH_WIDTH + 8;
        root.draw_text(&format_lux(value), &beside, (x as i32, y as i32))
            .map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}

/// The title in the band at the top, shrunk to fit the picture's width.
fn draw_title(image: &mut RgbImage, title: &str) -> std::result::Result<(), String> {
    let size = image.dimensions();
    let root = BitMapBackend::with_buffer(image, size).into_drawing_area();
    let room = f64::from(size.0.saturating_sub(16).max(1));
    let (width, _) = root
        .estimate_text_size(title, &TextStyle::from((FONT_FAMILY, 18.0).into_font()))
        .map_err(|e| e.to_string())?;
    let fitted = (18.0 * (room / f64::from(width.max(1))).min(1.0)).max(6.0);
    let style = (FONT_FAMILY, fitted)
        .into_font()
        .color(&TEXT)
        .pos(Pos::new(HPos::Left, VPos::Center));
    root.draw_text(title, &style, (8, TITLE_HEIGHT as i32 / 2))
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())
}

/// Writes `picture` to `path` as PNG, atomically.
fn save_png(path: &Path, picture: &RgbImage) -> Result<()> {
    write_atomically(path, |writer| {
        picture
            .write_with_encoder(::image::codecs::png::PngEncoder::new(writer))
            .map_err(|e| output_error(path, e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calculation::falsecolor_scale::{TEST_SCALE as SCALE, VIRIDIS};

    #[test]
    fn images_have_a_legend_and_grey_holes() {
        let (width, height) = (64, 48);
        let mut values: Vec<f64> = (0..width * height)
            .map(|i| f64::from(i % width) * 10.0)
            .collect();
        values[0] = f64::NAN;
        values[1] = 1000.0;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("view.png");
        write_falsecolor_image(&path, &values, width, height, &SCALE, "cd/m²", "office").unwrap();
        let image = ::image::open(&path).unwrap().to_rgb8();
        let legend_height = LEGEND_HEADER + SWATCH_HEIGHT * 8 + 12;
        assert_eq!(
            image.dimensions(),
            (width + LEGEND_WIDTH, TITLE_HEIGHT + legend_height)
        );
        assert_eq!(image.get_pixel(0, TITLE_HEIGHT).0, NO_DATA);
        assert_eq!(image.get_pixel(1, TITLE_HEIGHT).0, VIRIDIS[8]);
        assert_eq!(image.get_pixel(2, TITLE_HEIGHT).0, SCALE.colour(20.0));
        // The legend's top swatch is the maximum's colour, its bottom the
        // lowest.
        let (x, top) = (width + 16 + SWATCH_WIDTH / 2, TITLE_HEIGHT + LEGEND_HEADER);
        assert_eq!(image.get_pixel(x, top + SWATCH_HEIGHT / 2).0, VIRIDIS[8]);
        assert_eq!(
            image.get_pixel(x, top + 15 * SWATCH_HEIGHT / 2).0,
            VIRIDIS[0]
        );
        // The labels are drawn: light pixels right of the swatches.
        let labelled = (top..top + 8 * SWATCH_HEIGHT)
            .flat_map(|y| (width + 52..width + LEGEND_WIDTH).map(move |x| (x, y)))
            .any(|(x, y)| image.get_pixel(x, y).0[0] > 150);
        assert!(labelled);
    }

    #[test]
    fn bad_rasters_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let png = dir.path().join("view.png");
        let cases: [(&Path, &[f64], u32, u32, FalseColorScale); 5] = [
            (&dir.path().join("view.jpg"), &[1.0; 4], 2, 2, SCALE),
            (&png, &[1.0; 3], 2, 2, SCALE),
            (&png, &[], 0, 0, SCALE),
            (
                &png,
                &[1.0; 4],
                2,
                2,
                FalseColorScale {
                    maximum: 0.0,
                    ..SCALE
                },
            ),
            (
                &png,
                &[1.0; 4],
                2,
                2,
                FalseColorScale {
                    maximum: f64::NAN,
                    ..SCALE
                },
            ),
        ];
        for (path, values, width, height, scale) in cases {
            let error =
                write_falsecolor_image(path, values, width, height, &scale, "lx", "").unwrap_err();
            assert!(matches!(error, crate::Error::Output { .. }), "{error}");
            assert!(!path.exists());
        }
        let error =
            write_falsecolor_image(&dir.path().join("v.exr"), &[1.0], 1, 1, &SCALE, "lx", "")
                .unwrap_err();
        assert!(error.to_string().contains(".png"), "{error}");
    }

    #[test]
    fn grids_are_scaled_up_with_their_cells() {
        // 20 × 15 points 0.2 m apart on a 4 m × 3 m floor; the last column
        // has no data.
        let values: Vec<f64> = (0..300)
            .map(|i| {
                if i % 20 == 19 {
                    f64::NAN
                } else {
                    f64::from(i % 20) * 50.0
                }
            })
            .collect();
        let outline = [
            DVec2::ZERO,
            DVec2::new(4.0, 0.0),
            DVec2::new(4.0, 3.0),
            DVec2::new(0.0, 3.0),
        ];
        let luminaires = [(DVec2::new(2.0, 1.5), "L1".to_string())];
        let picture = GridPicture {
            origin: DVec2::splat(0.1),
            spacing: DVec2::splat(0.2),
            columns: 20,
            rows: 15,
            values: &values,
            outlines: &[outline.to_vec()],
            luminaires: &luminaires,
            title: "floor at 0.80 m",
            unit: "lx",
            axes: ["x (m)", "y (m)"],
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("floor.png");
        let scale = FalseColorScale::fitted(&values);
        assert_eq!(scale.maximum, 1000.0);
        write_falsecolor_grid(&path, &picture, &scale).unwrap();
        let image = ::image::open(&path).unwrap().to_rgb8();
        assert!(image.width() >= 600 + LEGEND_WIDTH, "{} px", image.width());

        // The centre of the cell of point (column, row), on the canvas.
        let frame = GridFrame::new(&picture);
        let cell = |column: f64, row: f64| {
            let (x, y) = frame.canvas_pixel(picture.plane_point(DVec2::new(column, row)));
            image.get_pixel(x as u32, y as u32).0
        };
        assert_eq!(cell(2.0, 3.0), scale.colour(100.0));
        assert_eq!(cell(18.0, 14.0), scale.colour(900.0));
        assert_eq!(cell(19.0, 7.0), NO_DATA);
        // Cells are square and about 720 / 4.2 m · 0.2 m = 34 pixels wide:
        // 10 pixels from a centre is still the same cell.
        let (x, y) = frame.canvas_pixel(picture.plane_point(DVec2::new(5.0, 5.0)));
        assert_eq!(
            image.get_pixel(x as u32 + 10, y as u32 + 10).0,
            scale.colour(250.0)
        );
        // Row 0 is at the bottom: the grid's y axis points up.
        let (_, bottom) = frame.canvas_pixel(picture.plane_point(DVec2::new(0.0, 0.0)));
        let (_, top) = frame.canvas_pixel(picture.plane_point(DVec2::new(0.0, 14.0)));
        assert!(bottom > top);
        // The luminaire's disc is white between its cross and its ring.
        let (lx, ly) = frame.canvas_pixel(DVec2::new(2.0, 1.5));
        assert_eq!(image.get_pixel(lx as u32 + 4, ly as u32).0, [255, 255, 255]);
    }

    #[test]
    fn broken_grids_are_refused_or_drawn_empty() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("grid.png");
        let empty = GridPicture {
            origin: DVec2::ZERO,
            spacing: DVec2::ONE,
            columns: 0,
            rows: 0,
            values: &[],
            outlines: &[],
            luminaires: &[],
            title: "",
            unit: "lx",
            axes: ["x (m)", "y (m)"],
        };
        write_falsecolor_grid(&path, &empty, &SCALE).unwrap();
        assert!(::image::open(&path).is_ok());
        let bad = GridPicture {
            spacing: DVec2::new(1.0, f64::NAN),
            ..empty
        };
        assert!(write_falsecolor_grid(&path, &bad, &SCALE).is_err());
        let huge = GridPicture {
            spacing: DVec2::splat(1e-300),
            columns: 1,
            rows: 1,
            values: &[5.0],
            outlines: &[vec![
                DVec2::ZERO,
                DVec2::splat(1e300),
                DVec2::new(0.0, 1e300),
            ]],
            ..empty
        };
        write_falsecolor_grid(&path, &huge, &SCALE).unwrap();
        let widest = GridPicture {
            outlines: &[vec![
                DVec2::splat(-f64::MAX),
                DVec2::new(f64::MAX, 0.0),
                DVec2::splat(f64::MAX),
            ]],
            ..huge
        };
        write_falsecolor_grid(&path, &widest, &SCALE).unwrap();
        assert!(::image::open(&path).is_ok());
    }
}
