//! Isolux plots of a calculation grid, as PNG or SVG: the lines of equal
//! illuminance over a surface, as lighting designers draw them.
//!
//! A [`GridPicture`] is the plain data of one grid on a plane: its points,
//! their illuminance, the surface's outline and the luminaires above it, all
//! in the plane's coordinates (metres). [`write_isolux_plot`] draws, on a
//! white canvas 1000 pixels wide:
//!
//! - **Axes.** x and y in metres with ticks and light gridlines, on equal
//!   scales (a metre is as long across as up), fitted to the outline, the
//!   grid and the luminaires with a margin of 6 % of their extent.
//! - **Outline.** The surface's polygon, closed, in black.
//! - **Iso-lux lines.** One per level, from
//!   [`contour_polylines`](super::contour_polylines) over the grid (points
//!   outside the outline carry NaN, so lines stop at the grid's edge of
//!   data), coloured from blue (lowest level) to red (highest). Each
//!   polyline at least three labels long is labelled with its level
//!   ([`format_lux`](super::format_lux), "lx" after it) halfway along, on a
//!   white backdrop. They are drawn by the `isolux_lines` module.
//! - **Luminaires.** A circle with a cross (the symbol of a luminaire on a
//!   lighting plan) at each position, its label beside it.
//! - **Title** at the top.
//!
//! Points, outline corners and luminaires with a non-finite coordinate are
//! left out; a grid without a finite value is drawn with its outline and
//! luminaires and says "no illuminance to show".
//!
//! ```no_run
//! use glam::DVec2;
//! use isorad::calculation::{GridPicture, write_isolux_plot};
//! use std::path::Path;
//!
//! let values: Vec<f64> = (0..20 * 15).map(|i| 300.0 + (i % 20) as f64 * 10.0).collect();
//! let outline = [DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(4.0, 3.0), DVec2::new(0.0, 3.0)];
//! let picture = GridPicture {
//!     origin: DVec2::splat(0.1),
//!     spacing: DVec2::splat(0.2),
//!     columns: 20,
//!     rows: 15,
//!     values: &values,
//!     outlines: &[outline.to_vec()],
//!     luminaires: &[(DVec2::new(2.0, 1.5), "L1".to_string())],
//!     title: "floor at 0.80 m",
//!     unit: "lx",
//!     axes: ["x (m)", "y (m)"],
//! };
//! write_isolux_plot(Path::new("floor.svg"), &picture, &[])?;
//! # Ok::<(), isorad::Error>(())
//! ```

use std::io::Write;
use std::path::Path;

use ::image::RgbImage;
use glam::DVec2;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::grid_picture::{GridPicture, Rect2};
use super::isolux_lines::{PlaneChart, draw_contours, draw_label};
use super::levels::nice_levels;
use crate::error::Result;
use crate::font::{FONT_FAMILY, ensure_font_registered};
use crate::fs::{io_error, output_error, write_atomically};

/// Width of an isolux plot, pixels (SVG user units).
const PLOT_WIDTH: u32 = 1000;
/// Least and greatest height of the plotting area, pixels.
const PLOT_AREA_HEIGHTS: (f64, f64) = (300.0, 900.0);
/// Pixels around the chart.
const MARGIN: u32 = 20;
/// Room for the x axis's ticks and name, and the y axis's.
const LABEL_AREAS: (u32, u32) = (55, 75);
/// Room for the title.
const TITLE_HEIGHT: u32 = 50;
/// The margin around the data, as a share of its extent.
const DATA_MARGIN: f64 = 0.06;
/// The largest extent of the data drawn, metres.
const MAX_EXTENT: f64 = 1e300;

/// Writes an isolux plot of `picture` to `path` (see the module notes):
/// SVG when the extension is `.svg`, PNG when it is `.png`
/// (case-insensitive), 1000 pixels wide and as high as the surface's shape
/// asks (the plotting area 300 to 900 pixels high). `levels` are the
/// illuminances (lux) to draw lines at; when none is finite, the levels are
/// [`nice_levels`] of the finite values, about 8 of them. The file is
/// written atomically.
///
/// # Errors
///
/// [`Error::Output`](crate::Error::Output) when the extension is neither
/// `svg` nor `png`, when the grid is inconsistent (a non-finite origin, a
/// spacing that is not finite and non-zero, a number of values other than
/// columns · rows) or drawing fails; [`Error::Io`](crate::Error::Io) when
/// the file cannot be written. The target is then untouched.
pub fn write_isolux_plot(path: &Path, picture: &GridPicture, levels: &[f64]) -> Result<()> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if !matches!(extension.as_deref(), Some("svg" | "png")) {
        return Err(output_error(
            path,
            "an isolux plot is written as .svg or .png; give the file one of these extensions",
        ));
    }
    picture.check().map_err(|e| output_error(path, e))?;
    if !ensure_font_registered() {
        return Err(output_error(path, "the bundled font cannot be loaded"));
    }
    let levels = chosen_levels(picture, levels);
    let bounds = framed_bounds(picture).ok_or_else(|| {
        output_error(
            path,
            "the grid, outline and luminaires lie too far apart to draw (over 1e300 m)",
        )
    })?;
    let size = canvas_size(bounds);
    let draw_error = |e: String| output_error(path, format!("cannot draw the isolux plot: {e}"));
    if extension.as_deref() == Some("svg") {
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
            draw_isolux(&root, picture, bounds, &levels).map_err(draw_error)?;
            root.present().map_err(|e| draw_error(e.to_string()))?;
        }
        write_atomically(path, |writer| {
            writer
                .write_all(svg.as_bytes())
                .map_err(|e| io_error(path, e))
        })
    } else {
        let mut rgb = vec![0_u8; size.0 as usize * size.1 as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
            draw_isolux(&root, picture, bounds, &levels).map_err(draw_error)?;
            root.present().map_err(|e| draw_error(e.to_string()))?;
        }
        let image = RgbImage::from_raw(size.0, size.1, rgb)
            .ok_or_else(|| draw_error("pixel buffer does not match the plot size".into()))?;
        write_atomically(path, |writer| {
            image
                .write_with_encoder(::image::codecs::png::PngEncoder::new(writer))
                .map_err(|e| output_error(path, e))
        })
    }
}

/// The finite `levels`, sorted and without repeats, or [`nice_levels`] of
/// the grid's finite values when there are none.
fn chosen_levels(picture: &GridPicture, levels: &[f64]) -> Vec<f64> {
    let mut chosen: Vec<f64> = levels.iter().copied().filter(|v| v.is_finite()).collect();
    chosen.sort_by(f64::total_cmp);
    chosen.dedup();
    if chosen.is_empty()
        && let Some((low, high)) = picture.value_range()
    {
        chosen = nice_levels(low, high, 8);
    }
    chosen
}

/// The data's box widened by [`DATA_MARGIN`] of its extent (at least 10⁻⁹
/// of its coordinates, 0.5 m at the origin), or −1..1 m without data; None when
/// it is too large to draw (its extent beyond 10³⁰⁰ m, where plotters'
/// ticks overflow).
fn framed_bounds(picture: &GridPicture) -> Option<Rect2> {
    let Some(Rect2 { low, high }) = picture.bounds() else {
        return Some(Rect2 {
            low: DVec2::splat(-1.0),
            high: DVec2::ONE,
        });
    };
    let extent = (high - low).max_element();
    if !extent.is_finite() || extent > MAX_EXTENT {
        return None;
    }
    // At least a billionth of the coordinates, so that the ends differ.
    let magnitude = low.abs().max(high.abs()).max_element();
    let margin = (DATA_MARGIN * extent).max(1e-9 * magnitude);
    let margin = if margin > 0.0 { margin } else { 0.5 };
    Some(Rect2 {
        low: low - DVec2::splat(margin),
        high: high + DVec2::splat(margin),
    })
}

/// The canvas: [`PLOT_WIDTH`] wide, and as high as a plotting area of the
/// data's aspect needs, that area held between [`PLOT_AREA_HEIGHTS`].
fn canvas_size(bounds: Rect2) -> (u32, u32) {
    let extent = bounds.high - bounds.low;
    let area_width = f64::from(PLOT_WIDTH - 2 * MARGIN - LABEL_AREAS.1);
    let aspect = extent.y / extent.x;
    let area_height = if aspect.is_finite() {
        (area_width * aspect).clamp(PLOT_AREA_HEIGHTS.0, PLOT_AREA_HEIGHTS.1)
    } else {
        PLOT_AREA_HEIGHTS.0
    };
    let height = area_height as u32 + 2 * MARGIN + LABEL_AREAS.0 + TITLE_HEIGHT;
    (PLOT_WIDTH, height)
}

/// The chart on `area`: axes in metres with the same pixels per metre on
/// both, the data's box centred. The plotting area is measured from a first
/// chart with the same layout, then the ranges widened to fill it.
fn equal_aspect_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    bounds: Rect2,
) -> std::result::Result<PlaneChart<'a, DB>, String> {
    let Rect2 { low, high } = bounds;
    let build = |x: std::ops::Range<f64>, y: std::ops::Range<f64>| {
        ChartBuilder::on(area)
            .margin(MARGIN)
            .x_label_area_size(LABEL_AREAS.0)
            .y_label_area_size(LABEL_AREAS.1)
            .build_cartesian_2d(x, y)
            .map_err(|e| e.to_string())
    };
    let trial = build(low.x..high.x, low.y..high.y)?;
    let (width, height) = trial.plotting_area().dim_in_pixel();
    let pixels = DVec2::new(f64::from(width.max(1)), f64::from(height.max(1)));
    let metres_per_pixel = ((high - low) / pixels).max_element();
    let centre = 0.5 * (low + high);
    let half = 0.5 * pixels * metres_per_pixel;
    build(
        centre.x - half.x..centre.x + half.x,
        centre.y - half.y..centre.y + half.y,
    )
}

/// Draws the whole plot on `root`; plotters' errors as text.
fn draw_isolux<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    picture: &GridPicture,
    bounds: Rect2,
    levels: &[f64],
) -> std::result::Result<(), String> {
    let text = |size: u32| (FONT_FAMILY, size).into_font();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (width, _) = root.dim_in_pixel();
    let title_style = text(22)
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Center));
    root.draw_text(
        picture.title,
        &title_style,
        (width as i32 / 2, TITLE_HEIGHT as i32 / 2 + 4),
    )
    .map_err(|e| e.to_string())?;
    let (_, body) = root.split_vertically(TITLE_HEIGHT);

    // Axes in metres, equal scales.
    let mut chart = equal_aspect_chart(&body, bounds)?;
    chart
        .configure_mesh()
        .x_desc(picture.axes[0])
        .y_desc(picture.axes[1])
        .label_style(text(15))
        .axis_desc_style(text(17))
        .bold_line_style(BLACK.mix(0.12))
        .light_line_style(BLACK.mix(0.04))
        .draw()
        .map_err(|e| e.to_string())?;

    // The outlines, closed.
    for polygon in picture.outlines {
        let mut outline: Vec<(f64, f64)> = polygon
            .iter()
            .filter(|p| p.is_finite())
            .map(|p| (p.x, p.y))
            .collect();
        if let Some(&first) = outline.first() {
            outline.push(first);
        }
        chart
            .draw_series(std::iter::once(PathElement::new(
                outline,
                BLACK.stroke_width(2),
            )))
            .map_err(|e| e.to_string())?;
    }

    // Iso-lux lines, then their labels over every line.
    let labels = draw_contours(&mut chart, picture, levels)?;
    for label in &labels {
        draw_label(root, label)?;
    }

    // Luminaires, and a note when there is nothing to show.
    draw_luminaires(&mut chart, picture)?;
    if picture.value_range().is_none() {
        let centred = Pos::new(HPos::Center, VPos::Center);
        let (_, height) = root.dim_in_pixel();
        root.draw_text(
            "no illuminance to show",
            &text(20).color(&BLACK.mix(0.6)).pos(centred),
            (width as i32 / 2, height as i32 / 2),
        )
        .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Each luminaire with a finite position: a circle with a cross, its label
/// to the upper right.
fn draw_luminaires<DB: DrawingBackend>(
    chart: &mut PlaneChart<'_, DB>,
    picture: &GridPicture,
) -> std::result::Result<(), String> {
    let stroke = BLACK.stroke_width(2);
    let symbols = picture
        .luminaires
        .iter()
        .filter(|(position, _)| position.is_finite())
        .map(|(position, label)| {
            EmptyElement::at((position.x, position.y))
                + Circle::new((0, 0), 8, stroke)
                + PathElement::new(vec![(-6, -6), (6, 6)], stroke)
                + PathElement::new(vec![(-6, 6), (6, -6)], stroke)
                + Text::new(label.clone(), (10, -22), (FONT_FAMILY, 14).into_font())
        });
    chart.draw_series(symbols).map_err(|e| e.to_string())?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calculation::isolux_lines::level_colour;

    /// A 4 m × 3 m floor with a 20 × 15 grid, lit by one luminaire over
    /// (1.5, 1.5): E = 1000 / (1 + d²) lux.
    fn floor_values() -> Vec<f64> {
        let mut values = Vec::new();
        for row in 0..15 {
            for column in 0..20 {
                let p = DVec2::new(0.1 + 0.2 * column as f64, 0.1 + 0.2 * row as f64);
                values.push(1000.0 / (1.0 + p.distance_squared(DVec2::new(1.5, 1.5))));
            }
        }
        values
    }

    const OUTLINE: [DVec2; 4] = [
        DVec2::ZERO,
        DVec2::new(4.0, 0.0),
        DVec2::new(4.0, 3.0),
        DVec2::new(0.0, 3.0),
    ];

    static FLOOR_OUTLINES: std::sync::LazyLock<Vec<Vec<DVec2>>> =
        std::sync::LazyLock::new(|| vec![OUTLINE.to_vec()]);

    fn floor<'a>(values: &'a [f64], luminaires: &'a [(DVec2, String)]) -> GridPicture<'a> {
        GridPicture {
            origin: DVec2::splat(0.1),
            spacing: DVec2::splat(0.2),
            columns: 20,
            rows: 15,
            values,
            outlines: &FLOOR_OUTLINES,
            luminaires,
            title: "floor at 0.80 m",
            unit: "lx",
            axes: ["x (m)", "y (m)"],
        }
    }

    #[test]
    fn svg_plots_carry_levels_and_luminaires() {
        let values = floor_values();
        let luminaires = [(DVec2::new(1.5, 1.5), "L1".to_string())];
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("floor.svg");
        write_isolux_plot(&path, &floor(&values, &luminaires), &[200.0, 500.0]).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        assert!(svg.contains("<svg"));
        assert!(svg.contains("500 lx"), "the 500 lx line is labelled");
        assert!(svg.contains("200 lx"));
        assert!(svg.contains("L1"));
        assert!(svg.contains("floor at 0.80 m"));
        // Both levels' colours are drawn.
        for colour in [level_colour(0, 2), level_colour(1, 2)] {
            let hex = format!("#{:02X}{:02X}{:02X}", colour.0, colour.1, colour.2);
            assert!(svg.to_uppercase().contains(&hex), "{hex}");
        }
    }

    #[test]
    fn png_plots_decode_and_draw_lines() {
        let values = floor_values();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("floor.PNG");
        write_isolux_plot(&path, &floor(&values, &[]), &[]).unwrap();
        let image = ::image::open(&path).unwrap().to_rgb8();
        assert_eq!(image.width(), PLOT_WIDTH);
        // The default levels are drawn: some pixels are of the lowest
        // level's colour.
        let levels = chosen_levels(&floor(&values, &[]), &[]);
        assert!(levels.len() >= 4, "{levels:?}");
        let lowest = level_colour(0, levels.len());
        assert!(
            image
                .pixels()
                .any(|p| p.0 == [lowest.0, lowest.1, lowest.2])
        );
    }

    #[test]
    fn the_axes_have_equal_scales() {
        let values = floor_values();
        let picture = floor(&values, &[]);
        let bounds = framed_bounds(&picture).unwrap();
        let (width, height) = canvas_size(bounds);
        let mut svg = String::new();
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        assert!(ensure_font_registered());
        let (_, body) = root.split_vertically(TITLE_HEIGHT);
        let chart = equal_aspect_chart(&body, bounds).unwrap();
        let a = chart.backend_coord(&(0.0, 0.0));
        let b = chart.backend_coord(&(4.0, 3.0));
        let (across, up) = (f64::from(b.0 - a.0), f64::from(a.1 - b.1));
        assert!(
            (across / 4.0 - up / 3.0).abs() < 1.0,
            "{across} px for 4 m, {up} px for 3 m"
        );
    }

    #[test]
    fn empty_and_broken_grids_do_not_panic() {
        let dir = tempfile::tempdir().unwrap();
        let nan = [f64::NAN; 300];
        let path = dir.path().join("nothing.png");
        write_isolux_plot(&path, &floor(&nan, &[]), &[]).unwrap();
        assert!(::image::open(&path).is_ok());
        let svg = dir.path().join("nothing.svg");
        write_isolux_plot(&svg, &floor(&nan, &[]), &[100.0]).unwrap();
        assert!(
            std::fs::read_to_string(&svg)
                .unwrap()
                .contains("no illuminance to show")
        );

        let empty = GridPicture {
            columns: 0,
            rows: 0,
            values: &[],
            outlines: &[],
            ..floor(&nan, &[])
        };
        write_isolux_plot(&svg, &empty, &[]).unwrap();

        let values = floor_values();
        let refused = [
            GridPicture {
                spacing: DVec2::new(f64::NAN, 0.2),
                ..floor(&values, &[])
            },
            GridPicture {
                spacing: DVec2::new(0.2, 0.0),
                ..floor(&values, &[])
            },
            GridPicture {
                columns: 19,
                ..floor(&values, &[])
            },
            GridPicture {
                columns: usize::MAX,
                rows: 2,
                ..floor(&values, &[])
            },
        ];
        for picture in refused {
            let error = write_isolux_plot(&svg, &picture, &[]).unwrap_err();
            assert!(matches!(error, crate::Error::Output { .. }), "{error}");
        }
        let odd = [DVec2::new(f64::INFINITY, 1.0), DVec2::ONE];
        let luminaires = [(DVec2::NAN, "lost".to_string())];
        let picture = GridPicture {
            outlines: &[odd.to_vec()],
            ..floor(&values, &luminaires)
        };
        write_isolux_plot(&path, &picture, &[f64::NAN, 300.0, 300.0]).unwrap();
    }

    #[test]
    fn extreme_coordinates_do_not_panic() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("extreme.png");
        let values = [1.0, 2.0, 3.0, 4.0];
        let far = 1e300;
        let extremes: [(DVec2, DVec2, [DVec2; 3]); 5] = [
            (
                DVec2::splat(far),
                DVec2::splat(1e280),
                [
                    DVec2::splat(far),
                    DVec2::new(far * 1.5, far),
                    DVec2::splat(far * 1.5),
                ],
            ),
            (DVec2::splat(far), DVec2::splat(1.0), [DVec2::splat(far); 3]),
            (
                DVec2::ZERO,
                DVec2::splat(1e-300),
                [DVec2::ZERO, DVec2::new(1e-300, 0.0), DVec2::splat(1e-300)],
            ),
            (
                DVec2::splat(-1e308),
                DVec2::splat(1e308),
                [
                    DVec2::splat(-f64::MAX),
                    DVec2::new(f64::MAX, 0.0),
                    DVec2::splat(f64::MAX),
                ],
            ),
            (
                DVec2::splat(1e15),
                DVec2::splat(1e-3),
                [
                    DVec2::splat(1e15),
                    DVec2::new(1e15 + 1.0, 1e15),
                    DVec2::splat(1e15 + 1.0),
                ],
            ),
        ];
        for (origin, spacing, outline) in extremes {
            let picture = GridPicture {
                origin,
                spacing,
                columns: 2,
                rows: 2,
                values: &values,
                outlines: &[outline.to_vec()],
                luminaires: &[],
                title: "extreme",
                unit: "lx",
                axes: ["x (m)", "y (m)"],
            };
            // A valid picture or a clear error, never a panic nor a hang.
            match write_isolux_plot(&path, &picture, &[]) {
                Ok(()) => assert!(::image::open(&path).is_ok()),
                Err(error) => assert!(error.to_string().contains("too far apart"), "{error}"),
            }
        }
    }

    #[test]
    fn other_extensions_are_refused() {
        let values = floor_values();
        let dir = tempfile::tempdir().unwrap();
        for name in ["floor.jpg", "floor"] {
            let path = dir.path().join(name);
            let error = write_isolux_plot(&path, &floor(&values, &[]), &[]).unwrap_err();
            assert!(error.to_string().contains(".svg or .png"), "{error}");
            assert!(!path.exists());
        }
    }
}
