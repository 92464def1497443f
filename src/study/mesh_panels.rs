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
//!   ([`srgb_encode`](crate::render::srgb_encode)). Missing, NaN and infinite
//!   values count as 0. A pixel is shaded when its centre lies in a triangle:
//!   isorad's own rasterizer ([`rasterize`], one sample per pixel) draws the
//!   triangles seen straight down from above their plane, where perspective
//!   interpolation is exactly linear.
//! - **Wireframe.** Triangle edges in orange `[255, 140, 0]`, then the
//!   outline in light blue `[90, 180, 255]`, one pixel wide, drawn by
//!   plotters: exact colours on horizontal, vertical and 45° lines,
//!   antialiased (blended over two pixels) on the others. Lines stop at the
//!   panel's square; an end farther than 4 squares outside it is pulled in
//!   to that distance, so only absurd coordinates bend a line.
//! - **Header.** Above each square, a band of 48 pixels holds the title and
//!   the vertex count ("N vertices").
//!
//! Pixels outside every triangle keep the dark grey background
//! `[40, 40, 40]`. Panels are laid left to right, 4 pixels apart, so the
//! picture is `n · panel_size + 4 · (n − 1)` by `48 + panel_size` pixels.
//! Triangles with an index out of range, a non-finite corner or no area are
//! skipped; clockwise triangles are drawn like counter-clockwise ones.

use std::path::Path;

use ::image::{Rgb as Rgb8, RgbImage, imageops};
use glam::{DVec2, DVec3};
use plotters::prelude::*;

use crate::error::Result;
use crate::font::{FONT_FAMILY, ensure_font_registered};
use crate::fs::{output_error, write_atomically};
use crate::render::{RenderSettings, ShadedTriangle, ToneMap, rasterize};
use crate::rgb::Rgb;
use crate::scene::Camera;

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
const WIREFRAME: RGBColor = RGBColor(255, 140, 0);
/// The outline polygon.
const OUTLINE: RGBColor = RGBColor(90, 180, 255);
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
    let mut picture = RgbImage::from_pixel(width, HEADER + panel_size, Rgb8(BACKGROUND));

    // One scale for all panels, one brightness scale for all values.
    let scale = shared_scale(panels, panel_size);
    let value_scale = brightest_value(panels);

    // Shade and outline each panel in its own square, then place it.
    for (index, panel) in panels.iter().enumerate() {
        let centre = framing_box(panel).map_or(DVec2::ZERO, |(low, high)| 0.5 * (low + high));
        let frame = Frame {
            size: panel_size,
            centre,
            scale,
        };
        let square = draw_panel(panel, &frame, value_scale).map_err(|e| output_error(path, e))?;
        let left = index as u32 * (panel_size + GAP);
        imageops::replace(&mut picture, &square, left.into(), HEADER.into());
    }

    // Titles and vertex counts, with the bundled font.
    draw_headers(&mut picture, panels, panel_size).map_err(|e| output_error(path, e))?;

    // Save.
    write_atomically(path, |writer| {
        picture
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

/// Where a panel's 2D units land in its square of pixels.
struct Frame {
    /// Side of the square, pixels.
    size: u32,
    /// The point drawn at the centre of the square.
    centre: DVec2,
    /// Pixels per unit.
    scale: f64,
}

impl Frame {
    /// Position in the square (pixels, continuous, y down) of a point.
    fn pixel_from_point(&self, point: DVec2) -> DVec2 {
        let half = 0.5 * f64::from(self.size);
        let offset = (point - self.centre) * self.scale;
        DVec2::new(half + offset.x, half - offset.y)
    }

    /// A camera straight above the plane z = 0, looking down with +y up,
    /// whose `size` × `size` image shows the square: at height h, a 90°
    /// field of view spans 2h, which is `size / scale` units.
    fn camera(&self) -> Camera {
        let height = 0.5 * f64::from(self.size) / self.scale;
        Camera {
            position: self.centre.extend(height),
            look_at: self.centre.extend(0.0),
            up: DVec3::Y,
            vfov_deg: 90.0,
            width: self.size,
            height: self.size,
        }
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

/// The panel's square: its triangles shaded, then their edges and the
/// outline drawn on top.
fn draw_panel(
    panel: &MeshPanel,
    frame: &Frame,
    value_scale: f64,
) -> std::result::Result<RgbImage, String> {
    // The drawable triangles, corners with their scaled values.
    let corner = |index: usize| {
        let point = *panel.points.get(index)?;
        let value = panel.values.get(index).copied().unwrap_or(0.0);
        let value = if value.is_finite() { value } else { 0.0 };
        point.is_finite().then_some((point, value / value_scale))
    };
    let triangles: Vec<[(DVec2, f64); 3]> = panel
        .triangles
        .iter()
        .filter_map(|t| Some([corner(t[0])?, corner(t[1])?, corner(t[2])?]))
        .collect();
    let mut square = shade(&triangles, frame);

    // Edges, then the outline, clipped to the square by the bitmap.
    let size = (frame.size, frame.size);
    let root = BitMapBackend::with_buffer(&mut square, size).into_drawing_area();
    let draw = |a: DVec2, b: DVec2, colour: &RGBColor| {
        let ends = [a, b].map(|p| pixel_coordinate(frame, p));
        root.draw(&PathElement::new(ends, colour))
            .map_err(|e| e.to_string())
    };
    for triangle in &triangles {
        for k in 0..3 {
            draw(triangle[k].0, triangle[(k + 1) % 3].0, &WIREFRAME)?;
        }
    }
    let outline = &panel.outline;
    for (k, &a) in outline.iter().enumerate() {
        let b = outline[(k + 1) % outline.len()];
        if a.is_finite() && b.is_finite() {
            draw(a, b, &OUTLINE)?;
        }
    }
    root.present().map_err(|e| e.to_string())?;
    drop(root);
    Ok(square)
}

/// The square's pixels: the sRGB grey of the field where a pixel's centre
/// lies in a triangle, the background elsewhere.
fn shade(triangles: &[[(DVec2, f64); 3]], frame: &Frame) -> RgbImage {
    // Red carries the field, blue 1 marks the pixels a triangle covers.
    let shaded: Vec<ShadedTriangle> = triangles
        .iter()
        .map(|triangle| {
            let [a, mut b, mut c] = *triangle;
            // Counter-clockwise seen from above: the front faces the camera.
            if (b.0 - a.0).perp_dot(c.0 - a.0) < 0.0 {
                std::mem::swap(&mut b, &mut c);
            }
            ShadedTriangle {
                positions: [a, b, c].map(|(p, _)| p.extend(0.0)),
                radiance: [a, b, c].map(|(_, v)| Rgb::new(v, 0.0, 1.0)),
            }
        })
        .collect();
    let image = rasterize(&shaded, &frame.camera(), &RenderSettings::preview());
    let grey = ToneMap::default();
    RgbImage::from_fn(frame.size, frame.size, |x, y| {
        let [value, _, covered] = image.pixel(x, y);
        if covered > 0.5 {
            Rgb8([grey.map_channel(f64::from(value)); 3])
        } else {
            Rgb8(BACKGROUND)
        }
    })
}

/// The pixel a point falls in, for plotters; coordinates are held within
/// 4 squares of the square, so that a line's pixels stay few.
fn pixel_coordinate(frame: &Frame, point: DVec2) -> (i32, i32) {
    let reach = 4.0 * f64::from(frame.size);
    let pixel = frame.pixel_from_point(point).floor().clamp(
        DVec2::splat(-reach),
        DVec2::splat(f64::from(frame.size) + reach),
    );
    (pixel.x as i32, pixel.y as i32)
}

/// Draws each panel's title and vertex count in the header band, shrinking
/// the text to fit the panel's width.
fn draw_headers(
    picture: &mut RgbImage,
    panels: &[MeshPanel],
    panel_size: u32,
) -> std::result::Result<(), String> {
    let size = picture.dimensions();
    let root = BitMapBackend::with_buffer(picture, size).into_drawing_area();
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
