//! One triangle's samples: the set-ups binned into bands of rows, the
//! sample columns a row of a triangle spans, and the depth test and
//! Gouraud shading of one sample. The first pass (the `rasterizer` module)
//! and the edge refinement (`edge_refinement`) both draw with them.

use glam::DVec2;
use rayon::prelude::*;

use super::setup::{Setup, View, clamp_range};
use super::shaded_triangle::ShadedTriangle;

/// Every triangle set up for `view`, in submission order, and for each band
/// of `band_rows` pixel rows of an image `height` pixels high, the indices
/// of the set-ups whose row range overlaps it.
pub(super) fn binned_setups(
    triangles: &[ShadedTriangle],
    view: &View,
    band_rows: u32,
    height: u32,
) -> (Vec<Setup>, Vec<Vec<u32>>) {
    let setups: Vec<Setup> = triangles
        .par_iter()
        .filter_map(|triangle| Setup::new(triangle, view))
        .collect();
    let samples = view.rows / height.max(1);
    let bins = bin_by_band(&setups, band_rows * samples, height.div_ceil(band_rows));
    (setups, bins)
}

/// For each band of `band_sample_rows` sample rows, the indices of the
/// triangles whose row range overlaps it, in submission order.
fn bin_by_band(setups: &[Setup], band_sample_rows: u32, band_count: u32) -> Vec<Vec<u32>> {
    let mut bins = vec![Vec::new(); band_count as usize];
    for (index, setup) in setups.iter().enumerate() {
        let first = setup.rows.0 / band_sample_rows;
        let last = (setup.rows.1 / band_sample_rows).min(band_count.saturating_sub(1));
        for bin in &mut bins[first as usize..=last as usize] {
            bin.push(index as u32);
        }
    }
    bins
}

/// Tests one sample (tangent-plane point `sample`, row part `partial`) against
/// `setup` and the depth `nearest` seen there so far, and when the triangle
/// covers it nearer, stores its depth and radiance in `nearest` and
/// `radiance`.
#[inline]
pub(super) fn shade_sample(
    setup: &Setup,
    view: &View,
    sample: DVec2,
    partial: [f64; 3],
    nearest: &mut f64,
    radiance: &mut [f32; 3],
) {
    // Inside when all edge functions are ≥ 0, a tie (e = 0) going to the
    // edge's owner by the top-left rule.
    let Some(e) = setup.covers(sample.x, sample.y, partial, view) else {
        return;
    };
    // Depth t = |D| / Σ e_k; clip near, then the z-test.
    let sum = e[0] + e[1] + e[2];
    let depth = setup.volume / sum;
    let visible = sum > 0.0 && depth >= setup.z_near && depth * setup.depth_scale < *nearest;
    if !visible {
        return;
    }
    // Perspective-correct Gouraud: L = Σ e_k L_k / Σ e_k.
    let [l0, l1, l2] = setup.radiance;
    *nearest = depth * setup.depth_scale;
    *radiance = ((l0 * e[0] + l1 * e[1] + l2 * e[2]) / sum).to_f32_array();
}

/// The inclusive range of sample columns in which row-part edge values
/// `partial` can all be ≥ 0, within the triangle's column bounds, with one
/// sample of margin for rounding; `None` when the row misses the triangle.
pub(super) fn row_span(setup: &Setup, partial: [f64; 3], view: &View) -> Option<(u32, u32)> {
    // Each edge a·x + partial ≥ 0 bounds x on one side (or the whole row).
    let (mut x_lo, mut x_hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for (edge, &p) in setup.edges.iter().zip(&partial) {
        if edge.a > 0.0 {
            x_lo = x_lo.max(-p / edge.a);
        } else if edge.a < 0.0 {
            x_hi = x_hi.min(-p / edge.a);
        } else if p < 0.0 {
            return None;
        }
    }
    // In sample columns, intersected with the triangle's bounds.
    let (lo, hi) = clamp_range(view.column_of(x_lo), view.column_of(x_hi), view.columns)?;
    let (lo, hi) = (lo.max(setup.columns.0), hi.min(setup.columns.1));
    (lo <= hi).then_some((lo, hi))
}
