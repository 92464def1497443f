//! The lines of an isolux plot: one polyline per level through the grid's
//! values ([`contour_polylines`]), coloured from blue (the lowest level) to
//! red (the highest), and each line long enough to carry it labelled with
//! its level halfway along, on a white backdrop.

use glam::DVec2;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::grid_picture::GridPicture;
use super::levels::format_lux;
use crate::font::FONT_FAMILY;
use crate::mesh::contour_polylines;

/// Level colours from the lowest level to the highest, interpolated:
/// blue, teal, orange, red (dark enough to read on white).
const LEVEL_COLOURS: [[u8; 3]; 4] = [[33, 102, 172], [0, 140, 130], [225, 130, 0], [200, 30, 30]];

/// The plane coordinates of the plotting area.
pub(super) type PlaneChart<'a, DB> =
    ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A level's value placed on its line, in pixels.
pub(super) struct Label {
    text: String,
    centre: (i32, i32),
    colour: RGBColor,
}

/// The colour of level `index` of `count`, from blue (0) to red (the last).
pub(super) fn level_colour(index: usize, count: usize) -> RGBColor {
    let t = if count > 1 {
        index as f64 / (count - 1) as f64
    } else {
        0.0
    };
    let scaled = t.clamp(0.0, 1.0) * (LEVEL_COLOURS.len() - 1) as f64;
    let below = (scaled.floor() as usize).min(LEVEL_COLOURS.len() - 2);
    let f = scaled - below as f64;
    let mix = |channel: usize| {
        let (a, b) = (
            f64::from(LEVEL_COLOURS[below][channel]),
            f64::from(LEVEL_COLOURS[below + 1][channel]),
        );
        (a + f * (b - a)).round() as u8
    };
    RGBColor(mix(0), mix(1), mix(2))
}

/// Draws every level's polylines and returns a label for each polyline
/// long enough to carry one: at least three times the label's width in
/// pixels, labelled halfway along its length.
pub(super) fn draw_contours<DB: DrawingBackend>(
    chart: &mut PlaneChart<'_, DB>,
    picture: &GridPicture,
    levels: &[f64],
) -> std::result::Result<Vec<Label>, String> {
    let mut labels = Vec::new();
    for (index, &level) in levels.iter().enumerate() {
        let colour = level_colour(index, levels.len());
        let text = format!("{} {}", format_lux(level), picture.unit);
        let text_width = 9 * text.chars().count() as i32;
        for line in contour_polylines(picture.values, picture.columns, picture.rows, level) {
            let plane: Vec<(f64, f64)> = line
                .iter()
                .map(|&p| picture.plane_point(p))
                .map(|p| (p.x, p.y))
                .collect();
            let pixels: Vec<(i32, i32)> = plane.iter().map(|p| chart.backend_coord(p)).collect();
            chart
                .draw_series(std::iter::once(PathElement::new(
                    plane,
                    colour.stroke_width(2),
                )))
                .map_err(|e| e.to_string())?;
            if let Some(centre) = halfway(&pixels, f64::from(3 * text_width)) {
                labels.push(Label {
                    text: text.clone(),
                    centre,
                    colour,
                });
            }
        }
    }
    Ok(labels)
}

/// The point halfway along a pixel polyline, when it is at least
/// `min_length` pixels long.
fn halfway(pixels: &[(i32, i32)], min_length: f64) -> Option<(i32, i32)> {
    let point = |&(x, y): &(i32, i32)| DVec2::new(f64::from(x), f64::from(y));
    let lengths: Vec<f64> = pixels
        .windows(2)
        .map(|w| point(&w[0]).distance(point(&w[1])))
        .collect();
    let total: f64 = lengths.iter().sum();
    if total < min_length {
        return None;
    }
    let mut left = total / 2.0;
    for (segment, length) in pixels.windows(2).zip(lengths) {
        if left <= length && length > 0.0 {
            let p = point(&segment[0]).lerp(point(&segment[1]), left / length);
            return Some((p.x.round() as i32, p.y.round() as i32));
        }
        left -= length;
    }
    pixels.last().copied()
}

/// A label's text in its level's colour on a white box, centred on its
/// point.
pub(super) fn draw_label<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    label: &Label,
) -> std::result::Result<(), String> {
    let style = (FONT_FAMILY, 14).into_font();
    let (width, height) = root
        .estimate_text_size(&label.text, &TextStyle::from(style.clone()))
        .map_err(|e| e.to_string())?;
    let (half_width, half_height) = (width as i32 / 2 + 3, height as i32 / 2 + 2);
    let (x, y) = label.centre;
    root.draw(&Rectangle::new(
        [
            (x - half_width, y - half_height),
            (x + half_width, y + half_height),
        ],
        WHITE.filled(),
    ))
    .map_err(|e| e.to_string())?;
    let centred = Pos::new(HPos::Center, VPos::Center);
    root.draw_text(
        &label.text,
        &style.color(&label.colour).pos(centred),
        (x, y),
    )
    .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_go_halfway_along_long_lines() {
        let line = [(0, 0), (100, 0), (100, 100)];
        assert_eq!(halfway(&line, 150.0), Some((100, 0)));
        assert_eq!(halfway(&line, 250.0), None);
        assert_eq!(halfway(&[(5, 5), (5, 5)], 0.0), Some((5, 5)));
    }
}
