//! Log–log line plots, as SVG or PNG: error against vertex count for the
//! square and contour meshers.
//!
//! [`write_loglog_plot`] takes plain [`Series`] of (x, y) points and draws,
//! on a white 900 × 600 canvas, both axes logarithmic with ranges fitted to
//! the data (padded by a factor [`PADDING`] on each side), major and minor
//! gridlines, one colour and one marker shape per series, the points of each
//! series joined in order of x, and a legend in the upper right, or in the
//! corner holding the fewest points when data run there. Points that
//! a log axis cannot show (non-finite, zero or negative coordinates) are left
//! out; a plot with nothing left still writes a valid file that says so.
//!
//! ```no_run
//! use isorad::study::{Series, write_loglog_plot};
//! use std::path::Path;
//!
//! let square = Series { name: "square".into(), points: vec![(121.0, 0.08), (961.0, 0.02)] };
//! let contour = Series { name: "contour".into(), points: vec![(101.0, 0.03), (401.0, 0.006)] };
//! write_loglog_plot(Path::new("error.svg"), "Cornell box", "vertices", "RMS error", &[square, contour])?;
//! # Ok::<(), isorad::Error>(())
//! ```

use std::io::Write;
use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::combinators::WithKeyPoints;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use ::image::RgbImage;

use crate::error::Result;
use crate::font::{FONT_FAMILY, ensure_font_registered};
use crate::fs::{io_error, output_error, write_atomically};

/// One named curve of a plot: points (x, y) in any order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    /// The name shown in the legend.
    pub name: String,
    /// The points, (x, y); joined by lines in order of increasing x.
    pub points: Vec<(f64, f64)>,
}

/// Width and height of a plot, pixels (SVG user units).
const PLOT_SIZE: (u32, u32) = (900, 600);

/// Factor by which the data's range is widened at each end of both axes.
const PADDING: f64 = 1.3;

/// Series colours, in order (the Tableau 10 palette); repeated past ten.
const COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Marker shapes, in order, as polygons of pixel offsets from the point.
const MARKERS: [&[(i32, i32)]; 5] = [
    // Octagon (a round dot).
    &[
        (2, -5),
        (5, -2),
        (5, 2),
        (2, 5),
        (-2, 5),
        (-5, 2),
        (-5, -2),
        (-2, -5),
    ],
    // Square.
    &[(-4, -4), (4, -4), (4, 4), (-4, 4)],
    // Triangle pointing up.
    &[(0, -6), (5, 4), (-5, 4)],
    // Diamond.
    &[(0, -6), (6, 0), (0, 6), (-6, 0)],
    // Triangle pointing down.
    &[(0, 6), (5, -4), (-5, -4)],
];

/// A log axis with our own ticks.
type LogAxis = WithKeyPoints<LogCoord<f64>>;

/// The chart both axes of which are [`LogAxis`].
type LogLogChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<LogAxis, LogAxis>>;

/// What the axes and title say.
struct Labels<'a> {
    title: &'a str,
    x: &'a str,
    y: &'a str,
}

/// Writes a log–log plot of `series` to `path`: SVG when the extension is
/// `.svg`, PNG when it is `.png` (case-insensitive), 900 × 600 pixels.
///
/// Points with a non-finite or non-positive coordinate are skipped; series
/// left without points keep their legend entry. When no series has a point
/// the axes span 1 to 10 and the plot says "no positive, finite data".
/// The file is written atomically (temporary file, then rename).
///
/// # Errors
///
/// [`Error::Output`](crate::Error::Output) when the extension is neither
/// `svg` nor `png` or drawing fails, [`Error::Io`](crate::Error::Io) when
/// the file cannot be written (missing directory, permission); the target is
/// then untouched.
pub fn write_loglog_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<()> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if !ensure_font_registered() {
        return Err(output_error(path, "the bundled font cannot be loaded"));
    }
    let labels = Labels {
        title,
        x: x_label,
        y: y_label,
    };
    let series: Vec<Series> = series.iter().map(plottable).collect();
    let draw_error = |e: String| output_error(path, format!("cannot draw the plot: {e}"));
    match extension.as_deref() {
        Some("svg") => {
            let svg = render_svg(&labels, &series).map_err(draw_error)?;
            write_atomically(path, |writer| {
                writer
                    .write_all(svg.as_bytes())
                    .map_err(|e| io_error(path, e))
            })
        }
        Some("png") => {
            let image = render_png(&labels, &series).map_err(draw_error)?;
            write_atomically(path, |writer| {
                image
                    .write_with_encoder(::image::codecs::png::PngEncoder::new(writer))
                    .map_err(|e| output_error(path, e))
            })
        }
        _ => Err(output_error(
            path,
            "a plot is written as .svg or .png; give the file one of these extensions",
        )),
    }
}

/// The plot as an SVG document.
fn render_svg(labels: &Labels, series: &[Series]) -> std::result::Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, PLOT_SIZE).into_drawing_area();
        draw_plot(&root, labels, series)?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// The plot as an 8-bit RGB picture.
fn render_png(labels: &Labels, series: &[Series]) -> std::result::Result<RgbImage, String> {
    let (width, height) = PLOT_SIZE;
    let mut rgb = vec![0_u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, PLOT_SIZE).into_drawing_area();
        draw_plot(&root, labels, series)?;
        root.present().map_err(|e| e.to_string())?;
    }
    RgbImage::from_raw(width, height, rgb)
        .ok_or_else(|| "pixel buffer does not match the plot size".to_string())
}

/// `series` without the points a log–log plot cannot show, sorted by x.
fn plottable(series: &Series) -> Series {
    let mut points: Vec<(f64, f64)> = series
        .points
        .iter()
        .copied()
        .filter(|&(x, y)| x.is_finite() && y.is_finite() && x > 0.0 && y > 0.0)
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    Series {
        name: series.name.clone(),
        points,
    }
}

/// The range of `values` (all finite and positive) widened by [`PADDING`]
/// at both ends, or 1..10 when there are none. A single value v gives
/// v/2..2v.
fn padded_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (low, high) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), v| {
        (low.min(v), high.max(v))
    });
    if low > high {
        return 1.0..10.0;
    }
    let factor = if high / low < 1.0 + 1e-9 {
        2.0
    } else {
        PADDING
    };
    low / factor..high * factor
}

/// A log axis over `range` with ticks from [`log_ticks`].
fn log_axis(range: std::ops::Range<f64>) -> LogAxis {
    let (labelled, light) = log_ticks(range.clone());
    range
        .log_scale()
        .with_key_points(labelled)
        .with_light_points(light)
}

/// Tick positions on a log axis over `range` (positive, finite): labelled
/// ticks at 1, 2, 3, … 9 × 10^k when the range spans at most one decade and
/// a bit, at 1, 2, 5 × 10^k up to 2.5 decades, at powers of ten beyond
/// (every second, third… past 8 decades); and gridlines at every integer
/// multiple of a power of ten (powers of ten only past 8 decades). A range
/// too narrow to hold two such ticks gets three ticks spaced evenly on the
/// log scale, rounded to two significant digits.
fn log_ticks(range: std::ops::Range<f64>) -> (Vec<f64>, Vec<f64>) {
    let (low, high) = (range.start, range.end);
    let decades = (high / low).log10();
    let inside = |v: &f64| (low..=high).contains(v);
    let multiples_of_decades = |multiples: &[f64], every: i32| -> Vec<f64> {
        let first = low.log10().floor() as i32;
        let last = high.log10().ceil() as i32;
        (first..=last)
            .filter(|k| k.rem_euclid(every) == 0)
            .flat_map(|k| multiples.iter().map(move |m| m * 10_f64.powi(k)))
            .filter(inside)
            .collect()
    };
    let one_to_nine: Vec<f64> = (1..=9).map(f64::from).collect();
    let labelled = if decades <= 1.2 {
        multiples_of_decades(&one_to_nine, 1)
    } else if decades <= 2.5 {
        multiples_of_decades(&[1.0, 2.0, 5.0], 1)
    } else {
        multiples_of_decades(&[1.0], (decades / 8.0).ceil() as i32)
    };
    let light = if decades <= 8.0 {
        multiples_of_decades(&one_to_nine, 1)
    } else {
        multiples_of_decades(&[1.0], 1)
    };
    if labelled.len() >= 2 {
        return (labelled, light);
    }
    let evenly = (1..=3)
        .map(|i| low * (high / low).powf(f64::from(i) / 4.0))
        .map(|v| {
            let unit = 10_f64.powi(v.log10().floor() as i32 - 1);
            (v / unit).round() * unit
        })
        .collect();
    (evenly, light)
}

/// A tick label for a log axis: plain decimals from 0.001 to 99 999 with at
/// most three significant digits, scientific notation beyond.
fn tick_label(value: f64) -> String {
    let magnitude = value.abs();
    if (1e-3..1e5).contains(&magnitude) {
        let decimals = (2 - magnitude.log10().floor() as i32).max(0) as usize;
        let text = format!("{value:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    } else {
        format!("{value:.0e}")
    }
}

/// Where the legend goes: the upper right unless points lie there, else
/// the corner (lower right, upper left, lower left) with the fewest points,
/// so that rising curves are not hidden under it. A corner is the outer
/// 40 % of the width and 25 % of the height, on the log scales.
fn legend_corner(
    series: &[Series],
    x_range: &std::ops::Range<f64>,
    y_range: &std::ops::Range<f64>,
) -> SeriesLabelPosition {
    let fraction = |v: f64, r: &std::ops::Range<f64>| (v / r.start).ln() / (r.end / r.start).ln();
    let in_corner = |right: bool, upper: bool| {
        series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|&&(x, y)| {
                let (fx, fy) = (fraction(x, x_range), fraction(y, y_range));
                (if right { fx > 0.6 } else { fx < 0.4 })
                    && (if upper { fy > 0.75 } else { fy < 0.25 })
            })
            .count()
    };
    [
        (SeriesLabelPosition::UpperRight, in_corner(true, true)),
        (SeriesLabelPosition::LowerRight, in_corner(true, false)),
        (SeriesLabelPosition::UpperLeft, in_corner(false, true)),
        (SeriesLabelPosition::LowerLeft, in_corner(false, false)),
    ]
    .into_iter()
    .min_by_key(|&(_, count)| count)
    .map_or(SeriesLabelPosition::UpperRight, |(corner, _)| corner)
}

/// Draws the whole plot on `root`; plotters' errors as text.
fn draw_plot<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    labels: &Labels,
    series: &[Series],
) -> std::result::Result<(), String> {
    let text = |size: u32| (FONT_FAMILY, size).into_font();
    root.fill(&WHITE).map_err(|e| e.to_string())?;

    // Axes fitted to every remaining point.
    let all_points = || series.iter().flat_map(|s| s.points.iter());
    let x_range = padded_range(all_points().map(|p| p.0));
    let y_range = padded_range(all_points().map(|p| p.1));
    let legend = legend_corner(series, &x_range, &y_range);
    let mut chart = ChartBuilder::on(root)
        .caption(labels.title, text(24))
        .margin(20)
        .x_label_area_size(55)
        .y_label_area_size(80)
        .build_cartesian_2d(log_axis(x_range), log_axis(y_range))
        .map_err(|e| e.to_string())?;

    // Gridlines, ticks and axis names.
    chart
        .configure_mesh()
        .x_desc(labels.x)
        .y_desc(labels.y)
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v))
        .label_style(text(15))
        .axis_desc_style(text(18))
        .max_light_lines(9)
        .bold_line_style(BLACK.mix(0.2))
        .light_line_style(BLACK.mix(0.07))
        .draw()
        .map_err(|e| e.to_string())?;

    // Each series: a line through its points, a marker on each, a legend entry.
    draw_curves(&mut chart, series, legend)?;

    // Say so when there was nothing to draw.
    if all_points().next().is_none() {
        draw_note(root, "no positive, finite data")?;
    }
    Ok(())
}

/// Each series as a line through its points with a marker on each point,
/// and the legend.
fn draw_curves<'a, DB: DrawingBackend + 'a>(
    chart: &mut LogLogChart<'a, DB>,
    series: &[Series],
    legend: SeriesLabelPosition,
) -> std::result::Result<(), String> {
    for (index, one) in series.iter().enumerate() {
        let colour = COLOURS[index % COLOURS.len()];
        let marker = MARKERS[index % MARKERS.len()];
        chart
            .draw_series(LineSeries::new(
                one.points.iter().copied(),
                colour.stroke_width(2),
            ))
            .map_err(|e| e.to_string())?
            .label(one.name.as_str())
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(-12, 0), (12, 0)], colour.stroke_width(2))
                    + Polygon::new(marker.to_vec(), colour.filled())
            });
        chart
            .draw_series(one.points.iter().map(|&point| {
                EmptyElement::at(point) + Polygon::new(marker.to_vec(), colour.filled())
            }))
            .map_err(|e| e.to_string())?;
    }
    if !series.is_empty() {
        chart
            .configure_series_labels()
            .position(legend)
            .label_font((FONT_FAMILY, 16).into_font())
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK.mix(0.5))
            .draw()
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// `message` in grey at the centre of `root`.
fn draw_note<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    message: &str,
) -> std::result::Result<(), String> {
    let (width, height) = root.dim_in_pixel();
    let centred = Pos::new(HPos::Center, VPos::Center);
    let style = (FONT_FAMILY, 20)
        .into_font()
        .color(&BLACK.mix(0.6))
        .pos(centred);
    root.draw_text(message, &style, (width as i32 / 2, height as i32 / 2))
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn legend_leaves_rising_curves_visible() {
        let series = |points: Vec<(f64, f64)>| {
            let one = [Series {
                name: "s".into(),
                points,
            }];
            let all = || one.iter().flat_map(|s| s.points.iter());
            let x_range = padded_range(all().map(|p| p.0));
            let y_range = padded_range(all().map(|p| p.1));
            legend_corner(&one, &x_range, &y_range)
        };
        let falling = series(vec![(10.0, 1.0), (100.0, 0.1), (1000.0, 0.01)]);
        assert!(matches!(falling, SeriesLabelPosition::UpperRight));
        let rising = series(vec![(10.0, 0.01), (100.0, 0.1), (1000.0, 1.0)]);
        assert!(matches!(rising, SeriesLabelPosition::LowerRight));
        assert!(matches!(
            legend_corner(&[], &(1.0..10.0), &(1.0..10.0)),
            SeriesLabelPosition::UpperRight
        ));
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick_label(100.0), "100");
        assert_eq!(tick_label(2000.0), "2000");
        assert_eq!(tick_label(0.05), "0.05");
        assert_eq!(tick_label(0.0123), "0.0123");
        assert_eq!(tick_label(1.5), "1.5");
        assert_eq!(tick_label(1e6), "1e6");
        assert_eq!(tick_label(2e-5), "2e-5");
    }

    #[test]
    fn log_ticks_suit_the_span() {
        let close = |got: Vec<f64>, want: &[f64]| {
            got.len() == want.len()
                && got
                    .iter()
                    .zip(want)
                    .all(|(g, w)| (g / w - 1.0).abs() < 1e-12)
        };
        let (labelled, light) = log_ticks(80.0..200_000.0);
        assert!(close(labelled, &[100.0, 1000.0, 10_000.0, 100_000.0]));
        assert_eq!(light.len(), 2 + 9 + 9 + 9 + 2);
        let (labelled, _) = log_ticks(0.0011..0.12);
        assert!(close(labelled, &[0.002, 0.005, 0.01, 0.02, 0.05, 0.1]));
        let (labelled, _) = log_ticks(15.0..90.0);
        let tens = [20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0];
        assert!(close(labelled, &tens));
        let (labelled, _) = log_ticks(0.021..0.029);
        assert_eq!(labelled.len(), 3);
        assert!(labelled.iter().all(|v| (0.021..0.029).contains(v)));
        let (labelled, _) = log_ticks(1e-10..1e10);
        assert_eq!(labelled.len(), 7);
    }

    #[test]
    fn ranges_are_padded_by_a_factor() {
        let range = padded_range([10.0, 1000.0].into_iter());
        assert!((range.start - 10.0 / PADDING).abs() < 1e-12);
        assert!((range.end - 1000.0 * PADDING).abs() < 1e-9);
        assert_eq!(padded_range([4.0].into_iter()), 2.0..8.0);
        assert_eq!(padded_range(std::iter::empty()), 1.0..10.0);
    }

    #[test]
    fn unplottable_points_are_dropped_and_the_rest_sorted() {
        let series = Series {
            name: "s".into(),
            points: vec![
                (3.0, 1.0),
                (f64::NAN, 1.0),
                (-1.0, 2.0),
                (1.0, 0.0),
                (2.0, 5.0),
            ],
        };
        assert_eq!(plottable(&series).points, vec![(2.0, 5.0), (3.0, 1.0)]);
    }
}
