//! The Gouraud rasterizer: triangles with per-vertex radiance → an [`Image`].
//!
//! A pinhole camera looks at one-sided triangles. Every pixel holds an s × s
//! grid of samples; each sample is depth-tested on its own against a z-buffer
//! and takes the radiance of the nearest triangle it falls in, interpolated
//! perspective-correctly from the three vertices; a pixel is the mean of its
//! samples (box filter). The rasterizer knows nothing of how the radiance was
//! computed.
//!
//! Coverage uses homogeneous edge functions (see the `setup` module): a
//! triangle crossing the eye's plane is clipped at a small near distance and
//! never projected through the eye, and two triangles sharing an edge have
//! exactly opposite edge functions, so with the top-left tie rule every
//! sample on the shared edge belongs to exactly one of them (no cracks, no
//! double coverage).
//!
//! The image is cut into bands of rows rendered in parallel (rayon); each
//! triangle is binned into the bands its screen bounds overlap. The pixels
//! whose samples disagree (an outline through them) are then drawn again
//! with e × e samples (see the `edge_refinement` module).

use glam::DVec2;
use rayon::prelude::*;

use super::edge_refinement::{EDGE_CONTRAST, SampleRange, edge_pixels, refine_edges};
use super::image::Image;
use super::sampling::{binned_setups, row_span, shade_sample};
use super::setup::{Setup, View};
use super::shaded_triangle::ShadedTriangle;
use crate::rgb::Rgb;
use crate::scene::Camera;

/// How to rasterize: anti-aliasing and background.
///
/// Build it from [`RenderSettings::default`] or a preset and set fields:
///
/// ```
/// let mut settings = isorad::RenderSettings::preview();
/// settings.background = isorad::Rgb::splat(0.1);
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct RenderSettings {
    /// Samples per pixel along each axis: s × s samples, box-filtered.
    /// Clamped to 1..=[`RenderSettings::MAX_SUPERSAMPLING`]. With 1 the one
    /// sample sits exactly at the pixel centre. Default 3.
    pub supersampling: u32,
    /// Samples per pixel along each axis where a pixel's samples disagree
    /// (an object's outline, a sharp shadow): such pixels are drawn again
    /// with e × e samples (see the `edge_refinement` module). Clamped to
    /// 1..=[`RenderSettings::MAX_SUPERSAMPLING`]; at most `supersampling`
    /// turns the refinement off. Default 16.
    pub edge_supersampling: u32,
    /// Radiance where no triangle is seen, W/(m²·sr). Default black.
    /// Non-finite channels are drawn as 0.
    pub background: Rgb,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            supersampling: 3,
            edge_supersampling: 16,
            background: Rgb::ZERO,
        }
    }
}

impl RenderSettings {
    /// The largest supersampling honoured (256 samples per pixel).
    pub const MAX_SUPERSAMPLING: u32 = 16;

    /// One sample per pixel, at its centre: fast, aliased edges.
    #[must_use]
    pub fn preview() -> Self {
        RenderSettings {
            supersampling: 1,
            edge_supersampling: 1,
            ..Self::default()
        }
    }

    /// 4 × 4 samples per pixel, 16 × 16 on edges.
    #[must_use]
    pub fn final_quality() -> Self {
        RenderSettings {
            supersampling: 4,
            ..Self::default()
        }
    }

    /// These settings with `supersampling` samples per pixel per axis.
    #[must_use]
    pub fn with_supersampling(mut self, supersampling: u32) -> Self {
        self.supersampling = supersampling;
        self
    }

    /// These settings with `edge_supersampling` samples per axis on the
    /// pixels whose samples disagree (1 turns the refinement off).
    #[must_use]
    pub fn with_edge_supersampling(mut self, edge_supersampling: u32) -> Self {
        self.edge_supersampling = edge_supersampling;
        self
    }

    /// These settings with the given background radiance.
    #[must_use]
    pub fn with_background(mut self, background: Rgb) -> Self {
        self.background = background;
        self
    }

    /// Samples per axis actually used: `supersampling` clamped to 1..=16.
    fn samples_per_axis(&self) -> u32 {
        self.supersampling.clamp(1, Self::MAX_SUPERSAMPLING)
    }

    /// Samples per axis on edges: `edge_supersampling` clamped to 1..=16.
    fn edge_samples_per_axis(&self) -> u32 {
        self.edge_supersampling.clamp(1, Self::MAX_SUPERSAMPLING)
    }
}

/// Target height of a band, in sample rows.
const BAND_SAMPLE_ROWS: u32 = 24;

/// Renders `triangles` seen by `camera` into a `camera.width × camera.height`
/// image of linear radiance.
///
/// Pixel (i, j) (row 0 at the top) covers the image-plane square around
/// ((i + 0.5)/W, (j + 0.5)/H); a sample at (u, v) looks along
/// forward + (2u − 1)·tan(vfov/2)·(W/H)·right + (1 − 2v)·tan(vfov/2)·up.
/// The radiance of a covered sample is Σ b_k L_k, with b_k the barycentric
/// coordinates of the point where its ray meets the triangle (perspective
/// correct). The nearest triangle wins; on an exact depth tie the first one
/// submitted. A pixel is the mean of its s × s samples on a regular grid, or
/// of e × e where its samples disagree (`settings.edge_supersampling`).
///
/// Triangles with non-finite positions or radiance, zero area, or seen
/// exactly edge-on are skipped. A camera that cannot form an image (see
/// [`Camera::validate`]: position at `look_at`, `up` along the view,
/// field of view outside (0°, 180°)) yields an image filled with the
/// background. The output never holds NaN when the inputs are finite.
#[must_use]
pub fn rasterize(
    triangles: &[ShadedTriangle],
    camera: &Camera,
    settings: &RenderSettings,
) -> Image {
    let (width, height) = (camera.width, camera.height);
    let background = settings
        .background
        .to_array()
        .map(|l| if l.is_finite() { l as f32 } else { 0.0 });
    let samples = settings.samples_per_axis();
    // A camera that cannot see draws the background only.
    let Some(view) = View::new(camera, samples) else {
        return Image::filled(width, height, background);
    };
    let mut pixels = vec![[0.0_f32; 3]; width as usize * height as usize];
    let mut disagree = vec![false; pixels.len()];
    {
        let band_rows = (BAND_SAMPLE_ROWS / samples).max(1);
        let (setups, bins) = binned_setups(triangles, &view, band_rows, height);
        // Render the bands in parallel, each into its own rows of the image.
        let band_pixels = band_rows as usize * width as usize;
        pixels
            .par_chunks_mut(band_pixels)
            .zip(disagree.par_chunks_mut(band_pixels))
            .zip(bins.par_iter())
            .enumerate()
            .for_each(|(band, ((out, out_disagree), bin))| {
                let first_row = band as u32 * band_rows * samples;
                let mut buffer = SampleBuffer::new(
                    first_row,
                    out.len() as u32 / width * samples,
                    &view,
                    background,
                );
                for &index in bin {
                    buffer.draw(&setups[index as usize], &view);
                }
                buffer.resolve(out, out_disagree, samples);
            });
    }
    // Draw the pixels whose samples disagree again, more finely.
    let edge_samples = settings.edge_samples_per_axis();
    if edge_samples > samples {
        let edges = edge_pixels(width, &pixels, &disagree);
        drop(disagree);
        refine_edges(
            &mut pixels,
            &edges,
            triangles,
            camera,
            edge_samples,
            background,
        );
    }
    Image::from_pixels(width, height, pixels)
        .unwrap_or_else(|| Image::filled(width, height, background))
}

/// The samples of one band: depth and radiance, row-major.
struct SampleBuffer {
    /// First sample row of the band.
    first_row: u32,
    /// Number of sample rows.
    rows: u32,
    /// Sample columns (image width × samples per axis).
    columns: u32,
    /// Depth of the nearest surface seen by each sample (+∞: none yet).
    depth: Vec<f64>,
    /// Radiance seen by each sample.
    radiance: Vec<[f32; 3]>,
}

impl SampleBuffer {
    /// An empty band of `rows` sample rows starting at `first_row`.
    fn new(first_row: u32, rows: u32, view: &View, background: [f32; 3]) -> Self {
        let count = rows as usize * view.columns as usize;
        SampleBuffer {
            first_row,
            rows,
            columns: view.columns,
            depth: vec![f64::INFINITY; count],
            radiance: vec![background; count],
        }
    }

    /// Depth-tests and shades every sample of this band that `setup` covers.
    fn draw(&mut self, setup: &Setup, view: &View) {
        // Rows of the triangle's bounds inside this band.
        let first = setup.rows.0.max(self.first_row);
        let last = setup.rows.1.min(self.first_row + self.rows - 1);
        for row in first..=last {
            // Row part of each edge function: b·y + c.
            let y = view.y_of_row[row as usize];
            let partial = setup.row_parts(y);
            let Some((column_lo, column_hi)) = row_span(setup, partial, view) else {
                continue;
            };
            let base = (row - self.first_row) as usize * self.columns as usize;
            for column in column_lo..=column_hi {
                let x = view.x_of_column[column as usize];
                self.shade(
                    setup,
                    view,
                    DVec2::new(x, y),
                    partial,
                    base + column as usize,
                );
            }
        }
    }

    /// Tests one sample (tangent-plane point `sample`, row part `partial`) against
    /// `setup` and the z-buffer, and shades it when it is the nearest so far.
    #[inline]
    fn shade(
        &mut self,
        setup: &Setup,
        view: &View,
        sample: DVec2,
        partial: [f64; 3],
        index: usize,
    ) {
        shade_sample(
            setup,
            view,
            sample,
            partial,
            &mut self.depth[index],
            &mut self.radiance[index],
        );
    }

    /// Box-filters the samples into `out`, the band's pixels (row-major),
    /// and marks in `disagree` the pixels whose samples span more than
    /// [`EDGE_CONTRAST`] of their greatest value.
    fn resolve(&self, out: &mut [[f32; 3]], disagree: &mut [bool], samples: u32) {
        let width = (self.columns / samples) as usize;
        let s = samples as usize;
        let weight = 1.0 / (s * s) as f64;
        for (index, (pixel, disagrees)) in out.iter_mut().zip(disagree).enumerate() {
            let (i, j) = (index % width, index / width);
            let mut sum = [0.0_f64; 3];
            let mut range = SampleRange::EMPTY;
            for row in j * s..(j + 1) * s {
                let start = row * self.columns as usize + i * s;
                for sample in &self.radiance[start..start + s] {
                    range.include(*sample);
                    for (total, &value) in sum.iter_mut().zip(sample) {
                        *total += f64::from(value);
                    }
                }
            }
            *pixel = sum.map(|total| (total * weight) as f32);
            *disagrees = range.spans_more_than(EDGE_CONTRAST);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// How many triangles cover each sample (near plane and z-buffer aside).
    fn coverage_counts(triangles: &[ShadedTriangle], view: &View) -> Vec<u32> {
        let mut counts = vec![0; view.columns as usize * view.rows as usize];
        for setup in triangles.iter().filter_map(|t| Setup::new(t, view)) {
            for (row, &y) in view.y_of_row.iter().enumerate() {
                let partial = setup.row_parts(y);
                for (column, &x) in view.x_of_column.iter().enumerate() {
                    if setup.covers(x, y, partial, view).is_some() {
                        counts[row * view.columns as usize + column] += 1;
                    }
                }
            }
        }
        counts
    }

    /// A non-planar height-field mesh over tangent-plane grid coordinates
    /// `xs` × `ys`, each vertex moved by `jitter(k)` and placed at depth
    /// 2 + 0.5x + 0.3y along its ray; cells split by alternating diagonals.
    fn grid_mesh(
        camera: &Camera,
        xs: &[f64],
        ys: &[f64],
        jitter: impl Fn(usize) -> (f64, f64),
    ) -> Vec<ShadedTriangle> {
        let frame = camera.frame();
        let vertex = |i: usize, j: usize| {
            let (dx, dy) = jitter(j * xs.len() + i);
            let (x, y) = (xs[i] + dx, ys[j] + dy);
            let depth = 2.0 + 0.5 * x + 0.3 * y;
            camera.position + depth * (x * frame.right + y * frame.up + frame.forward)
        };
        let mut triangles = Vec::new();
        for j in 0..ys.len() - 1 {
            for i in 0..xs.len() - 1 {
                let [a, b, c, d] = [
                    vertex(i, j),
                    vertex(i + 1, j),
                    vertex(i + 1, j + 1),
                    vertex(i, j + 1),
                ];
                let cells = if (i + j) % 2 == 0 {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, b, d], [b, c, d]]
                };
                triangles.extend(cells.map(|positions| ShadedTriangle {
                    positions,
                    radiance: [Rgb::ONE; 3],
                }));
            }
        }
        triangles
    }

    fn camera() -> Camera {
        Camera {
            position: DVec3::new(0.5, -0.25, 1.0),
            look_at: DVec3::new(0.0, 0.0, 5.0),
            up: DVec3::Y,
            vfov_deg: 50.0,
            width: 24,
            height: 18,
        }
    }

    #[test]
    fn mesh_through_sample_centres_covers_each_sample_once() {
        // Interior vertices sit on sample rays, so edges pass through samples.
        let camera = camera();
        for samples in [1, 3] {
            let view = View::new(&camera, samples).expect("valid camera");
            let pick = |values: &[f64]| {
                let mut picked: Vec<f64> = values.iter().step_by(5).copied().collect();
                picked.extend([-1.5, 1.5]);
                picked.sort_by(f64::total_cmp);
                picked
            };
            let (xs, ys) = (pick(&view.x_of_column), pick(&view.y_of_row));
            let mesh = grid_mesh(&camera, &xs, &ys, |_| (0.0, 0.0));
            let counts = coverage_counts(&mesh, &view);
            assert!(
                counts.iter().all(|&c| c == 1),
                "samples {samples}: {counts:?}"
            );
        }
    }

    #[test]
    fn jittered_mesh_covers_each_sample_once() {
        let camera = camera();
        let view = View::new(&camera, 2).expect("valid camera");
        let xs: Vec<f64> = (0..=12).map(|k| -2.0 + k as f64 / 3.0).collect();
        let ys: Vec<f64> = (0..=12).map(|k| -1.5 + k as f64 / 4.0).collect();
        // A deterministic jitter of up to ±0.1 (a third of a cell).
        let jitter = |k: usize| {
            let h = (k as f64 * 12.9898).sin() * 43758.5453;
            let g = (k as f64 * 78.233).sin() * 12345.678;
            (
                0.1 * (2.0 * h.fract().abs() - 1.0),
                0.06 * (2.0 * g.fract().abs() - 1.0),
            )
        };
        let mesh = grid_mesh(&camera, &xs, &ys, jitter);
        let counts = coverage_counts(&mesh, &view);
        assert!(counts.iter().all(|&c| c == 1), "{counts:?}");
    }
}
