//! The surfaces' bounding boxes in a uniform grid: which surfaces may touch
//! a region, without looking at every surface of the scene.
//!
//! Meshing asks, for every surface, which others stand on it (contact
//! lines). Asked of every pair, that is quadratic: a building floor of 16
//! furnished offices (26,000 faces) spent two minutes on it. A grid of
//! cubes about twice the mean surface's extent, each listing the surfaces
//! whose box overlaps it, answers the same question from the few cells
//! around a surface.

use crate::scene::Box3;
use std::collections::HashMap;

use glam::DVec3;

use crate::scene::{Scene, SurfaceId};

/// Cells a surface may be listed in; a larger one (a floor under a grid of
/// small books) goes on a list every query scans.
const MAX_CELLS_PER_SURFACE: usize = 512;

/// Every surface's bounding box, in a uniform grid of cells.
pub struct SurfaceBoxes {
    boxes: Vec<(DVec3, DVec3)>,
    origin: DVec3,
    cell: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
    /// Surfaces too large to list cell by cell.
    large: Vec<u32>,
}

impl SurfaceBoxes {
    /// Lists the surfaces of `scene` by the cells their boxes overlap.
    #[must_use]
    pub fn new(scene: &Scene) -> SurfaceBoxes {
        let boxes: Vec<(DVec3, DVec3)> = (scene.surfaces.iter())
            .map(|surface| {
                let Box3 { min, max } = surface.bounds();
                (min, max)
            })
            .collect();
        let Box3 {
            min: origin,
            max: top,
        } = scene.bounds();
        let extent = boxes
            .iter()
            .map(|(min, max)| (*max - *min).max_element())
            .sum::<f64>()
            / boxes.len().max(1) as f64;
        // Twice the mean extent, and no finer than a 10⁻⁶ of the scene.
        let cell = (2.0 * extent)
            .max(1e-6 * (top - origin).length())
            .max(f64::MIN_POSITIVE);
        let mut grid = SurfaceBoxes {
            boxes,
            origin,
            cell,
            cells: HashMap::new(),
            large: Vec::new(),
        };
        for k in 0..grid.boxes.len() {
            let (min, max) = grid.boxes[k];
            let (lo, hi) = (grid.index(min), grid.index(max));
            let count = (0..3)
                .map(|a| (hi[a] - lo[a] + 1).max(1) as usize)
                .try_fold(1usize, usize::checked_mul);
            if count.is_none_or(|count| count > MAX_CELLS_PER_SURFACE) {
                grid.large.push(k as u32);
                continue;
            }
            for cell in cells_between(lo, hi) {
                grid.cells.entry(cell).or_default().push(k as u32);
            }
        }
        grid
    }

    /// The bounding box (min, max) of surface `id`.
    #[must_use]
    pub fn bounds(&self, id: SurfaceId) -> (DVec3, DVec3) {
        self.boxes[id.index()]
    }

    /// The cell holding `p`, clamped far from overflow.
    fn index(&self, p: DVec3) -> [i64; 3] {
        let q = (p - self.origin) / self.cell;
        let clamp = |x: f64| x.floor().clamp(-1e9, 1e9) as i64;
        [clamp(q.x), clamp(q.y), clamp(q.z)]
    }

    /// Every surface whose bounding box comes within `margin` of the box
    /// (`min`, `max`), each once, in increasing order.
    #[must_use]
    pub fn near(&self, min: DVec3, max: DVec3, margin: f64) -> Vec<SurfaceId> {
        let (min, max) = (min - DVec3::splat(margin), max + DVec3::splat(margin));
        let overlaps = |k: u32| {
            let (a, b) = self.boxes[k as usize];
            a.cmple(max).all() && b.cmpge(min).all()
        };
        let (lo, hi) = (self.index(min), self.index(max));
        let span = (0..3)
            .map(|a| (hi[a] - lo[a] + 1).max(1) as usize)
            .try_fold(1usize, usize::checked_mul);
        let mut found: Vec<u32> = if span.is_none_or(|span| span > self.cells.len()) {
            // A box over most of the grid: every surface is a candidate.
            (0..self.boxes.len() as u32).collect()
        } else {
            cells_between(lo, hi)
                .filter_map(|cell| self.cells.get(&cell))
                .flatten()
                .copied()
                .chain(self.large.iter().copied())
                .collect()
        };
        found.sort_unstable();
        found.dedup();
        found.retain(|&k| overlaps(k));
        found
            .into_iter()
            .map(|k| SurfaceId::new(k as usize))
            .collect()
    }
}

/// The cells from `lo` to `hi`, both included.
fn cells_between(lo: [i64; 3], hi: [i64; 3]) -> impl Iterator<Item = [i64; 3]> {
    (lo[0]..=hi[0]).flat_map(move |x| {
        (lo[1]..=hi[1]).flat_map(move |y| (lo[2]..=hi[2]).map(move |z| [x, y, z]))
    })
}
