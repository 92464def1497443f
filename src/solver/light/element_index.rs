//! Which elements of a patch lie where: a grid in the patch's plane, so
//! that the element under a point is found among a few rather than by a
//! scan of the patch. The same grid over a surface's patches finds the
//! patch an ambient ray lands on (`solver/ambient/rays.rs`, `PatchLocator`).

use glam::DVec3;

/// A grid over a patch's elements, projected on the two coordinate axes
/// its plane spreads most along: each cell lists the elements whose boxes
/// meet it, so the element under a point is found among a few.
#[derive(Clone, Debug)]
pub(crate) struct ElementIndex {
    /// The two axes kept (indices into x, y, z).
    axes: [usize; 2],
    origin: [f64; 2],
    /// Cells per unit length along each axis.
    scale: [f64; 2],
    side: usize,
    /// Each cell's elements: `members[starts[c]..starts[c + 1]]`.
    starts: Vec<u32>,
    members: Vec<u32>,
}

/// The bounding box of a cell's corners, padded by 10⁻⁹ of its size: a
/// point on the cell's plane that rounding sets a hair off still falls in.
pub(crate) fn padded_box(corners: &[DVec3]) -> (DVec3, DVec3) {
    let min = corners.iter().copied().fold(DVec3::INFINITY, DVec3::min);
    let max = corners
        .iter()
        .copied()
        .fold(DVec3::NEG_INFINITY, DVec3::max);
    let pad = (max - min).max_element() * 1e-9;
    (min - pad, max + pad)
}

impl ElementIndex {
    /// The index of elements with bounding boxes `boxes` (min, max), on a
    /// plane facing `normal`.
    pub(crate) fn new(boxes: &[(DVec3, DVec3)], normal: DVec3) -> ElementIndex {
        let (min, max) = boxes.iter().fold(
            (DVec3::INFINITY, DVec3::NEG_INFINITY),
            |(lo, hi), (a, b)| (lo.min(*a), hi.max(*b)),
        );
        // Drop the axis the plane's normal leans most along.
        let n = normal.abs().to_array();
        let thin = (0..3).max_by(|&a, &b| n[a].total_cmp(&n[b])).unwrap_or(2);
        let axes = match thin {
            0 => [1, 2],
            1 => [0, 2],
            _ => [0, 1],
        };
        let side = ((boxes.len() as f64).sqrt().ceil() as usize).clamp(1, 32);
        let (lo, hi) = (min.to_array(), max.to_array());
        let origin = [lo[axes[0]], lo[axes[1]]];
        let scale = [0, 1].map(|k| {
            let length = hi[axes[k]] - lo[axes[k]];
            if length > 0.0 && length.is_finite() {
                side as f64 / length
            } else {
                0.0
            }
        });
        let mut index = ElementIndex {
            axes,
            origin,
            scale,
            side,
            starts: Vec::new(),
            members: Vec::new(),
        };
        let ranges: Vec<[(usize, usize); 2]> = boxes
            .iter()
            .map(|(a, b)| {
                let (a, b) = (a.to_array(), b.to_array());
                [0, 1].map(|k| (index.cell_of(k, a[axes[k]]), index.cell_of(k, b[axes[k]])))
            })
            .collect();
        let mut counts = vec![0u32; side * side + 1];
        for [(u0, u1), (v0, v1)] in &ranges {
            for v in *v0..=*v1 {
                for u in *u0..=*u1 {
                    counts[v * side + u + 1] += 1;
                }
            }
        }
        for c in 1..counts.len() {
            counts[c] += counts[c - 1];
        }
        let mut next = counts.clone();
        let mut members = vec![0; counts[side * side] as usize];
        for (k, [(u0, u1), (v0, v1)]) in ranges.iter().enumerate() {
            for v in *v0..=*v1 {
                for u in *u0..=*u1 {
                    let slot = &mut next[v * side + u];
                    members[*slot as usize] = k as u32;
                    *slot += 1;
                }
            }
        }
        index.starts = counts;
        index.members = members;
        index
    }

    /// The cell along kept axis k of coordinate w (clamped to the grid).
    fn cell_of(&self, k: usize, w: f64) -> usize {
        let c = ((w - self.origin[k]) * self.scale[k]).floor();
        if c.is_finite() && c > 0.0 {
            (c as usize).min(self.side - 1)
        } else {
            0
        }
    }

    /// The elements whose boxes meet the cell of point y.
    pub(crate) fn near(&self, y: DVec3) -> &[u32] {
        let p = y.to_array();
        let (u, v) = (
            self.cell_of(0, p[self.axes[0]]),
            self.cell_of(1, p[self.axes[1]]),
        );
        let c = v * self.side + u;
        &self.members[self.starts[c] as usize..self.starts[c + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_box_is_listed_where_its_points_are() {
        // Boxes of a 5 × 3 grid of unit squares in the plane y = 2, and one
        // long box across the top row.
        let mut boxes = Vec::new();
        for j in 0..3 {
            for i in 0..5 {
                let min = DVec3::new(f64::from(i), 2.0, f64::from(j));
                boxes.push((min, min + DVec3::new(1.0, 0.0, 1.0)));
            }
        }
        boxes.push((DVec3::new(0.0, 2.0, 2.5), DVec3::new(5.0, 2.0, 3.0)));
        let index = ElementIndex::new(&boxes, DVec3::Y);
        for k in 0..=50 {
            for m in 0..=30 {
                let p = DVec3::new(f64::from(k) * 0.1, 2.0, f64::from(m) * 0.1);
                for (e, (lo, hi)) in boxes.iter().enumerate() {
                    let inside = p.cmpge(*lo).all() && p.cmple(*hi).all();
                    if inside {
                        assert!(index.near(p).contains(&(e as u32)), "{p} in box {e}");
                    }
                }
            }
        }
        // A point off the grid finds the nearest cell's boxes, not a panic.
        assert!(!index.near(DVec3::new(-7.0, 2.0, 99.0)).is_empty());
    }
}
