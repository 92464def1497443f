//! Edge refinement: pixels whose samples disagree are drawn again with more
//! samples.
//!
//! A pixel is the mean of its s × s samples, an estimate of the mean
//! radiance over its square (the box filter of a path tracer's reference).
//! Inside a surface the Gouraud radiance varies slowly and s = 3 is exact to
//! a fraction of a percent; where an object's outline crosses the pixel the
//! estimate counts the samples on each side, so its coverage is read in
//! steps of 1/s along each axis, and along an edge near a grid line every
//! pixel errs the same way. A bright book against a dark gap is then off by
//! up to half the contrast over s: in the cluttered office of
//! `bench/generate_building.py` 3 × 3 samples render 3.60 % off per pixel
//! against Mitsuba, 16 × 16 everywhere 3.00 %, for the same solution.
//!
//! After the first pass, a pixel is refined when its own samples, or its
//! mean with its eight neighbours' means, span more than [`EDGE_CONTRAST`]
//! of their greatest value, in any channel: its own samples catch an
//! outline through it, the neighbours' means one that passes between its
//! samples and its border or clips its corner. Those pixels alone are drawn again
//! with e × e samples, in a sparse buffer that holds only their samples:
//! each sample row of a triangle visits the refined pixels of its pixel row
//! that its span reaches (found by bisection), so the cost follows the
//! refined pixels, not the image. The same edge functions and tie rule
//! decide coverage (see the `setup` module), so a mesh still covers each
//! sample exactly once.

use glam::DVec2;
use rayon::prelude::*;

use super::sampling::{binned_setups, row_span, shade_sample};
use super::setup::{Setup, View};
use super::shaded_triangle::ShadedTriangle;
use crate::scene::Camera;

/// A pixel is refined when its own samples, or its mean with its
/// neighbours' means, span more than this fraction of their greatest value
/// (in some channel): on the shipped office at 1920 × 1080, a tenth of the
/// pixels. Lower thresholds refine up to four times the pixels for the
/// same golden-test metric; a higher one makes it worse.
pub(super) const EDGE_CONTRAST: f32 = 0.1;

/// Pixel rows per band of the refinement pass: two keep a band's samples
/// under 40 MB (20 bytes each) even when every pixel of a 3840-pixel row is
/// refined.
const BAND_PIXEL_ROWS: u32 = 2;

/// The least and greatest value of each channel over a set of samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SampleRange {
    lo: [f32; 3],
    hi: [f32; 3],
}

impl SampleRange {
    /// The range of no samples.
    pub(super) const EMPTY: SampleRange = SampleRange {
        lo: [f32::INFINITY; 3],
        hi: [f32::NEG_INFINITY; 3],
    };

    /// Widens the range to hold `value`.
    #[inline]
    pub(super) fn include(&mut self, value: [f32; 3]) {
        for ((lo, hi), v) in self.lo.iter_mut().zip(&mut self.hi).zip(value) {
            *lo = lo.min(v);
            *hi = hi.max(v);
        }
    }

    /// Whether some channel spans more than `fraction` of the greatest
    /// value of any channel.
    pub(super) fn spans_more_than(&self, fraction: f32) -> bool {
        let top = self.hi[0].max(self.hi[1]).max(self.hi[2]);
        (0..3).any(|c| self.hi[c] - self.lo[c] > fraction * top)
    }
}

/// Which pixels to refine, row-major: those whose own samples `disagree`,
/// and those whose mean and their eight neighbours' `means` span more than
/// [`EDGE_CONTRAST`].
pub(super) fn edge_pixels(width: u32, means: &[[f32; 3]], disagree: &[bool]) -> Vec<bool> {
    let width = width as usize;
    let height = means.len() / width;
    (0..means.len())
        .into_par_iter()
        .map(|index| {
            if disagree[index] {
                return true;
            }
            let (i, j) = (index % width, index / width);
            let mut range = SampleRange::EMPTY;
            for row in j.saturating_sub(1)..=(j + 1).min(height - 1) {
                for column in i.saturating_sub(1)..=(i + 1).min(width - 1) {
                    range.include(means[row * width + column]);
                }
            }
            range.spans_more_than(EDGE_CONTRAST)
        })
        .collect()
}

/// Draws the pixels marked in `edges` again with `samples` × `samples`
/// samples each and writes their means into `pixels`; the other pixels are
/// left as they are.
pub(super) fn refine_edges(
    pixels: &mut [[f32; 3]],
    edges: &[bool],
    triangles: &[ShadedTriangle],
    camera: &Camera,
    samples: u32,
    background: [f32; 3],
) {
    let width = camera.width as usize;
    if !edges.contains(&true) {
        return;
    }
    let Some(view) = View::new(camera, samples) else {
        return;
    };
    let (setups, bins) = binned_setups(triangles, &view, BAND_PIXEL_ROWS, camera.height);
    let band_pixels = BAND_PIXEL_ROWS as usize * width;
    pixels
        .par_chunks_mut(band_pixels)
        .zip(edges.par_chunks(band_pixels))
        .zip(bins.par_iter())
        .enumerate()
        .for_each(|(band, ((out, marked), bin))| {
            if !marked.contains(&true) {
                return;
            }
            let mut buffer = EdgeSamples::new(
                band as u32 * BAND_PIXEL_ROWS,
                marked,
                width,
                samples,
                background,
            );
            for &index in bin {
                buffer.draw(&setups[index as usize], &view);
            }
            buffer.resolve(out, width);
        });
}

/// The samples of the refined pixels of one band of pixel rows.
struct EdgeSamples {
    /// First pixel row of the band.
    first_row: u32,
    /// Samples per pixel along each axis.
    samples: u32,
    /// For each pixel row of the band, where its refined pixels start in
    /// `columns` (one more entry than rows).
    starts: Vec<usize>,
    /// The refined pixels' columns, row by row, ascending within a row.
    columns: Vec<u32>,
    /// Depth of the nearest surface seen by each sample, pixel by pixel
    /// (in the order of `columns`), each pixel's samples row-major.
    depth: Vec<f64>,
    /// Radiance seen by each sample, in the same order.
    radiance: Vec<[f32; 3]>,
}

impl EdgeSamples {
    /// The refined pixels of a band starting at pixel row `first_row`,
    /// marked row-major in `marked` (rows of `width` pixels).
    fn new(
        first_row: u32,
        marked: &[bool],
        width: usize,
        samples: u32,
        background: [f32; 3],
    ) -> Self {
        let mut starts = vec![0];
        let mut columns = Vec::new();
        for row in marked.chunks(width) {
            columns.extend(
                row.iter()
                    .enumerate()
                    .filter(|(_, refine)| **refine)
                    .map(|(column, _)| column as u32),
            );
            starts.push(columns.len());
        }
        let count = columns.len() * (samples * samples) as usize;
        EdgeSamples {
            first_row,
            samples,
            starts,
            columns,
            depth: vec![f64::INFINITY; count],
            radiance: vec![background; count],
        }
    }

    /// Depth-tests and shades every sample of the band's refined pixels that
    /// `setup` covers.
    fn draw(&mut self, setup: &Setup, view: &View) {
        let s = self.samples;
        let first_sample_row = self.first_row * s;
        let sample_rows = (self.starts.len() as u32 - 1) * s;
        let first = setup.rows.0.max(first_sample_row);
        let last = setup.rows.1.min(first_sample_row + sample_rows - 1);
        for row in first..=last {
            let local = row - first_sample_row;
            let (pixel_row, sample_row) = ((local / s) as usize, local % s);
            let (start, end) = (self.starts[pixel_row], self.starts[pixel_row + 1]);
            if start == end {
                continue;
            }
            let y = view.y_of_row[row as usize];
            let partial = setup.row_parts(y);
            let Some((lo, hi)) = row_span(setup, partial, view) else {
                continue;
            };
            // The refined pixels of this row that the span reaches.
            let first_pixel = start + self.columns[start..end].partition_point(|&c| c < lo / s);
            for slot in first_pixel..end {
                let column = self.columns[slot];
                if column > hi / s {
                    break;
                }
                let left = column * s;
                let base = slot * (s * s) as usize + (sample_row * s) as usize;
                for sample_column in left.max(lo)..=(left + s - 1).min(hi) {
                    let x = view.x_of_column[sample_column as usize];
                    let index = base + (sample_column - left) as usize;
                    shade_sample(
                        setup,
                        view,
                        DVec2::new(x, y),
                        partial,
                        &mut self.depth[index],
                        &mut self.radiance[index],
                    );
                }
            }
        }
    }

    /// Box-filters each refined pixel's samples into its place in `out`, the
    /// band's pixels (rows of `width`).
    fn resolve(&self, out: &mut [[f32; 3]], width: usize) {
        let per_pixel = (self.samples * self.samples) as usize;
        let weight = 1.0 / per_pixel as f64;
        for (row, bounds) in self.starts.windows(2).enumerate() {
            for slot in bounds[0]..bounds[1] {
                let mut sum = [0.0_f64; 3];
                for sample in &self.radiance[slot * per_pixel..(slot + 1) * per_pixel] {
                    for (total, &value) in sum.iter_mut().zip(sample) {
                        *total += f64::from(value);
                    }
                }
                out[row * width + self.columns[slot] as usize] =
                    sum.map(|total| (total * weight) as f32);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_shading_is_not_refined() {
        // 8 × 4 pixels rising 1 % per pixel.
        let means: Vec<[f32; 3]> = (0..32).map(|k| [1.0 + 0.01 * (k % 8) as f32; 3]).collect();
        let edges = edge_pixels(8, &means, &[false; 32]);
        assert!(edges.iter().all(|&e| !e));
    }

    #[test]
    fn a_step_refines_the_pixels_on_either_side() {
        // 6 × 3 pixels, columns 0..=2 dark, 3..=5 bright: the step lies
        // between columns 2 and 3, which are refined with no other.
        let means: Vec<[f32; 3]> = (0..18)
            .map(|k| if k % 6 < 3 { [0.5; 3] } else { [1.0; 3] })
            .collect();
        let edges = edge_pixels(6, &means, &[false; 18]);
        for (k, &e) in edges.iter().enumerate() {
            assert_eq!(e, matches!(k % 6, 2 | 3), "pixel {k}");
        }
    }

    #[test]
    fn a_pixel_whose_own_samples_disagree_is_refined() {
        // Uniform means, but the middle pixel's samples disagree (an outline
        // through it that happens to average out).
        let means = vec![[1.0_f32; 3]; 9];
        let mut disagree = [false; 9];
        disagree[4] = true;
        let edges = edge_pixels(3, &means, &disagree);
        for (k, &e) in edges.iter().enumerate() {
            assert_eq!(e, k == 4, "pixel {k}");
        }
    }

    #[test]
    fn sample_ranges_measure_against_the_brightest_channel() {
        let mut range = SampleRange::EMPTY;
        range.include([1.0, 0.5, 0.001]);
        range.include([1.0, 0.5, 0.002]);
        assert!(!range.spans_more_than(0.1));
        range.include([0.85, 0.5, 0.002]);
        assert!(range.spans_more_than(0.1));
        assert!(!range.spans_more_than(0.2));
    }

    #[test]
    fn a_dim_channel_counts_against_the_brightest() {
        // Blue doubles from 0.001 to 0.002 beside a red of 1: 0.1 % of the
        // pixel's light, not an edge.
        let means: Vec<[f32; 3]> = (0..4)
            .map(|k| [1.0, 0.5, if k < 2 { 0.001 } else { 0.002 }])
            .collect();
        let edges = edge_pixels(4, &means, &[false; 4]);
        assert!(edges.iter().all(|&e| !e));
    }
}
