//! The field greedy insertion meshes, sampled once on a lattice over the
//! polygon and along its edges, with the samples binned by lattice cell.

use glam::DVec2;
use rayon::prelude::*;

use crate::scene::polygon_contains;

/// A field sampled at the centres of a lattice of square cells over a
/// polygon's bounding box, for the centres inside the polygon, and along
/// the polygon's edges at the same spacing: the boundary's samples let the
/// mesh put vertices on its edges, where a step that the field takes
/// across an edge would otherwise be interpolated from the corners alone.
/// Points where the field is NaN (inside an object standing on a
/// receiver) are left out.
#[derive(Clone, Debug, PartialEq)]
pub struct SampledField {
    min: DVec2,
    step: f64,
    columns: usize,
    rows: usize,
    /// The samples' positions and values.
    pub(super) points: Vec<DVec2>,
    pub(super) values: Vec<f64>,
    /// The samples of lattice cell c are `binned[start[c]..start[c + 1]]`.
    start: Vec<usize>,
    binned: Vec<usize>,
}

impl SampledField {
    /// Samples `field` (in parallel) at the centres of square cells,
    /// `cells` of them along the longer side of `outline`'s bounding box,
    /// and along `outline`'s edges at the cells' spacing.
    #[must_use]
    pub fn sample(
        outline: &[DVec2],
        cells: usize,
        field: &(dyn Fn(DVec2) -> f64 + Sync),
    ) -> SampledField {
        let (min, max) = outline.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let extent = max - min;
        let longest = extent.max_element();
        let mut sampled = SampledField {
            min,
            step: 1.0,
            columns: 0,
            rows: 0,
            points: Vec::new(),
            values: Vec::new(),
            start: vec![0],
            binned: Vec::new(),
        };
        if !(longest.is_finite() && longest > 0.0) {
            return sampled;
        }
        let step = longest / cells.max(2) as f64;
        let count = |length: f64| ((length / step).ceil() as usize).max(1);
        let (columns, rows) = (count(extent.x), count(extent.y));
        sampled.step = step;
        sampled.columns = columns;
        sampled.rows = rows;
        let mut candidates: Vec<DVec2> = (0..columns * rows)
            .map(|k| {
                let (i, j) = (k % columns, k / columns);
                min + step * DVec2::new(i as f64 + 0.5, j as f64 + 0.5)
            })
            .filter(|&p| polygon_contains(outline, p))
            .collect();
        for (k, &a) in outline.iter().enumerate() {
            let b = outline[(k + 1) % outline.len()];
            let pieces = (a.distance(b) / step).ceil().clamp(1.0, 1e6) as usize;
            candidates.extend((0..pieces).map(|t| a.lerp(b, t as f64 / pieces as f64)));
        }
        let values: Vec<f64> = candidates.par_iter().map(|&p| field(p)).collect();
        for (p, value) in candidates.into_iter().zip(values) {
            if value.is_finite() {
                sampled.points.push(p);
                sampled.values.push(value);
            }
        }
        // The samples by cell (a counting sort).
        let cells: Vec<usize> = sampled.points.iter().map(|&p| sampled.cell_of(p)).collect();
        let mut start = vec![0; columns * rows + 1];
        for &c in &cells {
            start[c + 1] += 1;
        }
        for c in 0..columns * rows {
            start[c + 1] += start[c];
        }
        let mut filled = start.clone();
        let mut binned = vec![0; cells.len()];
        for (k, &c) in cells.iter().enumerate() {
            binned[filled[c]] = k;
            filled[c] += 1;
        }
        sampled.start = start;
        sampled.binned = binned;
        sampled
    }

    /// The lattice cell holding p (clamped to the lattice).
    fn cell_of(&self, p: DVec2) -> usize {
        let (i, j) = self.column_row(p);
        j * self.columns + i
    }

    /// The lattice column and row of p (clamped to the lattice).
    fn column_row(&self, p: DVec2) -> (usize, usize) {
        let q = ((p - self.min) / self.step).floor();
        let clamp = |v: f64, count: usize| (v.max(0.0) as usize).min(count.saturating_sub(1));
        (clamp(q.x, self.columns), clamp(q.y, self.rows))
    }

    /// The samples in the lattice cells that the box [lo, hi] touches.
    pub(super) fn samples_in(&self, lo: DVec2, hi: DVec2) -> impl Iterator<Item = usize> + '_ {
        let ((i0, j0), (i1, j1)) = if self.columns == 0 {
            ((1, 1), (0, 0))
        } else {
            (self.column_row(lo), self.column_row(hi))
        };
        (j0..=j1).flat_map(move |j| {
            let (first, last) = (j * self.columns + i0, j * self.columns + i1);
            self.binned[self.start[first]..self.start[last + 1]]
                .iter()
                .copied()
        })
    }
}
