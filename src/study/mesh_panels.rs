//! Pictures of meshes side by side: a field shaded over each mesh with its
//! wireframe on top, to compare square and contour meshes at a glance (as in
//! Arquès, Biri and Derpierre's Figure 5: square 10×10 | contour 20×5 |
//! square 30×30).
//!
//! [`write_mesh_panels`] draws each [`MeshPanel`] in a `panel_size` square:
//!
//! - **Fit.** The bounding box of the panel's `outline` (of its points when
//!   it has no outline) is centred in the square and scaled so that it fits
//!   inside a margin of `panel_size / 16` pixels (at least 2). The scale is
//!   the same for every panel — the largest box decides — so panels of the
//!   same polygon line up and compare. The y axis points up.
//! - **Field.** `values` (one per point) are interpolated linearly over each
//!   triangle (Gouraud), divided by the largest finite value over all panels,
//!   clamped to [0, 1], and shown as grey through the sRGB curve
//!   ([`srgb_encode`]). Missing, NaN and infinite values count as 0.
//! - **Wireframe.** Triangle edges in orange `[255, 140, 0]`, one pixel wide
//!   (Bresenham), then the outline in light blue `[90, 180, 255]`.
//! - **Header.** Above each square, a band of 48 pixels holds the title and
//!   the vertex count ("N vertices").
//!
//! Pixels outside every triangle keep the dark grey background
//! `[40, 40, 40]`. Panels are laid left to right, 4 pixels apart, so the
//! picture is `n · panel_size + 4 · (n − 1)` by `48 + panel_size` pixels.
//! Triangles with an index out of range, a non-finite corner or no area are
//! skipped.

use std::path::Path;

use glam::DVec2;
use plotters::prelude::*;

use super::font::{FONT_FAMILY, ensure_font_registered};
use crate::error::Result;
use crate::fs::{output_error, write_atomically};
use crate::render::srgb_encode;

/// One mesh to draw: its vertices, a scalar per vertex, its triangles and
/// the polygon it covers, in any 2D units (the same for all panels).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshPanel {
    /// Shown above the panel, e.g. "square 10×10".
    pub title: String,
    /// Vertex positions; their number is shown as "N vertices".
    pub points: Vec<DVec2>,
    /// The field at each point (e.g. radiosity, W/m²); shaded in grey.
    pub values: Vec<f64>,
    /// Triangles as indices into `points`.
    pub triangles: Vec<[usize; 3]>,
    /// The polygon the mesh covers, drawn as a closed line; it also decides
    /// how the panel is framed.
    pub outline: Vec<DVec2>,
}

/// Pixels between neighbouring panels.
const GAP: u32 = 4;
/// Height of the band above each panel holding its title and vertex count.
const HEADER: u32 = 48;
/// Pixels outside every triangle, and the header band.
const BACKGROUND: [u8; 3] = [40, 40, 40];
/// Triangle edges.
const WIREFRAME: [u8; 3] = [255, 140, 0];
/// The outline polygon.
const OUTLINE: [u8; 3] = [90, 180, 255];
/// Header text.
const TEXT: RGBColor = RGBColor(230, 230, 230);

/// Writes `panels` side by side to `path` as one PNG, each in a square of
/// `panel_size` pixels under a 48-pixel header (see the module notes for
/// the layout and colours). The file is written atomically.
///
/// # Errors
///
/// [`Error::Output`](crate::Error::Output) when there is no panel, when
/// `panel_size` is 0 or the picture would be wider than 65 535 pixels, or
/// encoding fails; [`Error::Io`](crate::Error::Io) when the file cannot be
/// written (missing directory, permission). The target is then untouched.
pub fn write_mesh_panels(path: &Path, panels: &[MeshPanel], panel_size: u32) -> Result<()> {
    // Check there is a picture to make.
    let count = u32::try_from(panels.len()).unwrap_or(u32::MAX);
    let width = count
        .checked_mul(panel_size)
        .and_then(|w| w.checked_add(GAP * count.saturating_sub(1)))
        .filter(|&w| w <= u32::from(u16::MAX));
    let (Some(width), true, true) = (width, count > 0, panel_size > 0) else {
        return Err(output_error(
            path,
            format!(
                "cannot lay out {} mesh panels of {panel_size} pixels",
                panels.len()
            ),
        ));
    };
    if !ensure_font_registered() {
        return Err(output_error(path, "the bundled font cannot be loaded"));
    }
    let mut canvas = Canvas::new(width, HEADER + panel_size);

    // One scale for all panels, one brightness scale for all values.
    let scale = shared_scale(panels, panel_size);
    let value_scale = brightest_value(panels);

    // Shade and outline each panel in its square.
    for (index, panel) in panels.iter().enumerate() {
        let square = Square {
            left: index as u32 * (panel_size + GAP),
            top: HEADER,
            size: panel_size,
        };
        let centre = framing_box(panel).map_or(DVec2::ZERO, |(low, high)| 0.5 * (low + high));
        let frame = Frame {
            square,
            centre,
            scale,
        };
        draw_panel(&mut canvas, panel, &frame, value_scale);
    }

    // Titles and vertex counts, with the bundled font.
    draw_headers(&mut canvas, panels, panel_size).map_err(|e| output_error(path, e))?;

    // Save.
    let image = ::image::RgbImage::from_raw(canvas.width, canvas.height, canvas.rgb)
        .ok_or_else(|| output_error(path, "pixel buffer does not match the picture size"))?;
    write_atomically(path, |writer| {
        image
            .write_with_encoder(::image::codecs::png::PngEncoder::new(writer))
            .map_err(|e| output_error(path, e))
    })
}

/// Pixels per unit that fit the largest framing box of all panels inside
/// a `panel_size` square less a margin of `panel_size / 16` (at least 2)
/// pixels; 1 when no panel has a box with extent.
fn shared_scale(panels: &[MeshPanel], panel_size: u32) -> f64 {
    let margin = (panel_size / 16).max(2);
    let extent = panels
        .iter()
        .filter_map(framing_box)
        .map(|(low, high)| (high - low).max_element())
        .fold(0.0, f64::max);
    if extent > 0.0 {
        f64::from(panel_size.saturating_sub(2 * margin).max(1)) / extent
    } else {
        1.0
    }
}

/// The largest finite value over all panels, shown as white; 1 when none is
/// positive.
fn brightest_value(panels: &[MeshPanel]) -> f64 {
    let brightest = panels
        .iter()
        .flat_map(|panel| panel.values.iter().copied())
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    if brightest > 0.0 { brightest } else { 1.0 }
}

/// An 8-bit RGB picture, row-major from the top.
struct Canvas {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Canvas {
    fn new(width: u32, height: u32) -> Canvas {
        let rgb = BACKGROUND.repeat(width as usize * height as usize);
        Canvas { width, height, rgb }
    }

    /// Sets pixel (`x`, `y`); ignores pixels outside the canvas.
    fn set(&mut self, x: i64, y: i64, colour: [u8; 3]) {
        if (0..i64::from(self.width)).contains(&x) && (0..i64::from(self.height)).contains(&y) {
            let index = 3 * (y as usize * self.width as usize + x as usize);
            self.rgb[index..index + 3].copy_from_slice(&colour);
        }
    }
}

/// A panel's square on the canvas, pixels.
#[derive(Clone, Copy, Debug)]
struct Square {
    left: u32,
    top: u32,
    size: u32,
}

/// Where a panel's 2D units land on the canvas.
struct Frame {
    square: Square,
    /// The point drawn at the centre of the square.
    centre: DVec2,
    /// Pixels per unit.
    scale: f64,
}

impl Frame {
    /// Canvas position (pixels, continuous, y down) of a point.
    fn pixel_from_point(&self, point: DVec2) -> DVec2 {
        let half = 0.5 * f64::from(self.square.size);
        let offset = (point - self.centre) * self.scale;
        DVec2::new(
            f64::from(self.square.left) + half + offset.x,
            f64::from(self.square.top) + half - offset.y,
        )
    }
}

/// The box the panel is framed by: its outline's, or its points' when it
/// has no outline; finite coordinates only. `None` when nothing is finite.
fn framing_box(panel: &MeshPanel) -> Option<(DVec2, DVec2)> {
    let source = if panel.outline.is_empty() {
        &panel.points
    } else {
        &panel.outline
    };
    source
        .iter()
        .filter(|p| p.is_finite())
        .fold(None, |bounds, &p| match bounds {
            None => Some((p, p)),
            Some((low, high)) => Some((low.min(p), high.max(p))),
        })
}

/// Shades the panel's triangles, then draws their edges and the outline.
fn draw_panel(canvas: &mut Canvas, panel: &MeshPanel, frame: &Frame, value_scale: f64) {
    let corner = |index: usize| {
        let point = *panel.points.get(index)?;
        let value = panel.values.get(index).copied().unwrap_or(0.0);
        let value = if value.is_finite() { value } else { 0.0 };
        Some((frame.pixel_from_point(point), value / value_scale))
    };
    let triangles: Vec<[(DVec2, f64); 3]> = panel
        .triangles
        .iter()
        .filter_map(|t| Some([corner(t[0])?, corner(t[1])?, corner(t[2])?]))
        .filter(|t| t.iter().all(|(p, _)| p.is_finite()))
        .collect();
    for triangle in &triangles {
        fill_triangle(canvas, frame.square, triangle);
    }
    for triangle in &triangles {
        for k in 0..3 {
            let (a, b) = (triangle[k].0, triangle[(k + 1) % 3].0);
            draw_segment(canvas, frame.square, a, b, WIREFRAME);
        }
    }
    let outline: Vec<DVec2> = panel
        .outline
        .iter()
        .map(|&p| frame.pixel_from_point(p))
        .collect();
    for k in 0..outline.len() {
        let (a, b) = (outline[k], outline[(k + 1) % outline.len()]);
        if a.is_finite() && b.is_finite() {
            draw_segment(canvas, frame.square, a, b, OUTLINE);
        }
    }
}

/// Fills the pixels of `square` whose centres lie in the triangle (corners
/// in canvas pixels, values already divided by the brightness scale), each
/// with the value interpolated linearly at its centre, as sRGB grey.
fn fill_triangle(canvas: &mut Canvas, square: Square, triangle: &[(DVec2, f64); 3]) {
    let [(p0, v0), (p1, v1), (p2, v2)] = *triangle;
    let double_area = (p1 - p0).perp_dot(p2 - p0);
    if !double_area.is_finite() || double_area.abs() < 1e-12 {
        return;
    }
    // Pixel range covered by the triangle, within the square.
    let low = p0.min(p1).min(p2).floor();
    let high = p0.max(p1).max(p2).ceil();
    let x_range = clamp_span(low.x, high.x, square.left, square.size);
    let y_range = clamp_span(low.y, high.y, square.top, square.size);
    for y in y_range {
        for x in x_range.clone() {
            // Barycentric weights of the pixel centre.
            let centre = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
            let w0 = (p2 - p1).perp_dot(centre - p1) / double_area;
            let w1 = (p0 - p2).perp_dot(centre - p2) / double_area;
            let w2 = 1.0 - w0 - w1;
            // Written so that NaN weights count as outside.
            if !(w0 >= -1e-9 && w1 >= -1e-9 && w2 >= -1e-9) {
                continue;
            }
            let value = (w0 * v0 + w1 * v1 + w2 * v2).clamp(0.0, 1.0);
            let grey = (255.0 * srgb_encode(value).clamp(0.0, 1.0)).round() as u8;
            canvas.set(x, y, [grey; 3]);
        }
    }
}

/// The integer pixels from `low` to `high` (exclusive) that lie in
/// `start..start + size`.
fn clamp_span(low: f64, high: f64, start: u32, size: u32) -> std::ops::Range<i64> {
    let (start, end) = (i64::from(start), i64::from(start) + i64::from(size));
    // `as` saturates, so far-away corners cannot overflow.
    (low as i64).clamp(start, end)..(high as i64).clamp(start, end)
}

/// Draws the part of segment `a`–`b` (canvas pixels) inside `square`, one
/// pixel wide (Bresenham), in `colour`.
fn draw_segment(canvas: &mut Canvas, square: Square, a: DVec2, b: DVec2, colour: [u8; 3]) {
    let low = DVec2::new(f64::from(square.left), f64::from(square.top));
    let high = low + DVec2::splat(f64::from(square.size) - 1e-6);
    let Some((a, b)) = clip_segment(a, b, low, high) else {
        return;
    };
    let (mut x, mut y) = (a.x.floor() as i64, a.y.floor() as i64);
    let (x_end, y_end) = (b.x.floor() as i64, b.y.floor() as i64);
    let (dx, dy) = ((x_end - x).abs(), -(y_end - y).abs());
    let (step_x, step_y) = ((x_end - x).signum(), (y_end - y).signum());
    let mut error = dx + dy;
    loop {
        canvas.set(x, y, colour);
        if x == x_end && y == y_end {
            break;
        }
        let doubled = 2 * error;
        if doubled >= dy {
            error += dy;
            x += step_x;
        }
        if doubled <= dx {
            error += dx;
            y += step_y;
        }
    }
}

/// The part of segment `a`–`b` inside the box `low`–`high` (Liang–Barsky),
/// or `None` when it misses the box.
fn clip_segment(a: DVec2, b: DVec2, low: DVec2, high: DVec2) -> Option<(DVec2, DVec2)> {
    let delta = b - a;
    let (mut t_in, mut t_out) = (0.0_f64, 1.0_f64);
    for (p, q) in [
        (-delta.x, a.x - low.x),
        (delta.x, high.x - a.x),
        (-delta.y, a.y - low.y),
        (delta.y, high.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t_in = t_in.max(t);
            } else {
                t_out = t_out.min(t);
            }
        }
    }
    // Rounding may leave an end a hair outside: clamp it back in.
    let at = |t: f64| (a + t * delta).clamp(low, high);
    (t_in <= t_out).then(|| (at(t_in), at(t_out)))
}

/// Draws each panel's title and vertex count in the header band, shrinking
/// the text to fit the panel's width.
fn draw_headers(
    canvas: &mut Canvas,
    panels: &[MeshPanel],
    panel_size: u32,
) -> std::result::Result<(), String> {
    let size = (canvas.width, canvas.height);
    let root = BitMapBackend::with_buffer(&mut canvas.rgb, size).into_drawing_area();
    let room = f64::from(panel_size.saturating_sub(12).max(1));
    for (index, panel) in panels.iter().enumerate() {
        let left = (index as u32 * (panel_size + GAP) + 6) as i32;
        let count = match panel.points.len() {
            1 => "1 vertex".to_string(),
            n => format!("{n} vertices"),
        };
        for (text, font_size, top) in [(panel.title.as_str(), 18.0, 11), (count.as_str(), 15.0, 32)]
        {
            // Shrink the text until it fits the panel's width.
            let style = TextStyle::from((FONT_FAMILY, font_size).into_font());
            let (width, _) = root
                .estimate_text_size(text, &style)
                .map_err(|e| e.to_string())?;
            let fitted = font_size * (room / f64::from(width.max(1))).min(1.0);
            let style = (FONT_FAMILY, fitted).into_font().color(&TEXT);
            root.draw_text(text, &style, (left, top))
                .map_err(|e| e.to_string())?;
        }
    }
    root.present().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_are_clipped_to_the_box() {
        let (low, high) = (DVec2::ZERO, DVec2::splat(10.0));
        let clipped = clip_segment(DVec2::new(-5.0, 5.0), DVec2::new(15.0, 5.0), low, high);
        assert_eq!(clipped, Some((DVec2::new(0.0, 5.0), DVec2::new(10.0, 5.0))));
        assert!(clip_segment(DVec2::new(-5.0, -1.0), DVec2::new(15.0, -1.0), low, high).is_none());
        let inside = clip_segment(DVec2::splat(2.0), DVec2::splat(3.0), low, high);
        assert_eq!(inside, Some((DVec2::splat(2.0), DVec2::splat(3.0))));
    }

    #[test]
    fn long_segments_are_cut_to_the_square() {
        let mut canvas = Canvas::new(20, 20);
        let square = Square {
            left: 0,
            top: 0,
            size: 10,
        };
        let lit = |canvas: &Canvas| -> Vec<usize> {
            (0..400)
                .filter(|&i| canvas.rgb[3 * i..3 * i + 3] == WIREFRAME)
                .collect()
        };
        let (a, b) = (DVec2::new(-1e6, 5.5), DVec2::new(1e6, 5.5));
        draw_segment(&mut canvas, square, a, b, WIREFRAME);
        assert_eq!(lit(&canvas), (100..110).collect::<Vec<_>>());

        // Absurd coordinates lose the line's place, but stay in the square.
        let mut canvas = Canvas::new(20, 20);
        let (a, b) = (DVec2::new(-1e300, 5.5), DVec2::new(1e300, 7.5));
        draw_segment(&mut canvas, square, a, b, WIREFRAME);
        assert!(lit(&canvas).iter().all(|i| i % 20 < 10 && i / 20 < 10));
        draw_segment(
            &mut canvas,
            square,
            DVec2::splat(-5.0),
            DVec2::splat(-1.0),
            OUTLINE,
        );
        assert!(!canvas.rgb.chunks(3).any(|p| p == OUTLINE));
    }
}
