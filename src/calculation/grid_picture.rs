//! The plain data of a calculation grid on a plane, ready to be drawn
//! ([`GridPicture`]): its points and their illuminance, the surface's
//! outline and the luminaires, in the plane's coordinates (metres); and the
//! axis-aligned rectangle ([`Rect2`]) its pictures are framed by.

use glam::DVec2;

/// An axis-aligned rectangle in a plane's coordinates, metres: its low and
/// high corners (low ≤ high on each axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Rect2 {
    /// The corner with the least x and y.
    pub low: DVec2,
    /// The corner with the greatest x and y.
    pub high: DVec2,
}

/// A calculation grid on a plane, ready to be drawn: regularly spaced
/// points with their illuminance, the surface's outline and the luminaires,
/// all in the plane's coordinates (metres, y up).
#[derive(Clone, Copy, Debug)]
pub struct GridPicture<'a> {
    /// Plane coordinates (metres) of point (0, 0); point (column, row) is at origin + (column·spacing.x, row·spacing.y).
    pub origin: DVec2,
    /// Distance between neighbouring points along x (columns) and y (rows),
    /// metres; finite and non-zero.
    pub spacing: DVec2,
    /// Points per row.
    pub columns: usize,
    /// Rows of points.
    pub rows: usize,
    /// Illuminance in lux (or the quantity `unit` names), row-major (row * columns + column); NaN where the point lies outside the outline.
    pub values: &'a [f64],
    /// The outlines of the surface's polygons in the same plane coordinates
    /// (closed polygons, first point not repeated).
    pub outlines: &'a [Vec<DVec2>],
    /// Luminaires projected onto the plane, with their labels.
    pub luminaires: &'a [(DVec2, String)],
    /// Title, e.g. "floor at 0.80 m: Eavg 512 lx, U0 0.61".
    pub title: &'a str,
    /// The values' unit, after each label: "lx", or "%" for daylight
    /// factors.
    pub unit: &'a str,
    /// The names of the plane's axes, with units, e.g. `["x (m)", "−z (m)"]`.
    pub axes: [&'a str; 2],
}

impl GridPicture<'_> {
    /// The plane coordinates of a point in grid coordinates (fractional
    /// column, row): origin + (column · spacing.x, row · spacing.y).
    #[must_use]
    pub fn plane_point(&self, grid: DVec2) -> DVec2 {
        self.origin + grid * self.spacing
    }

    /// The least and greatest finite value, or None when there is none.
    #[must_use]
    pub fn value_range(&self) -> Option<(f64, f64)> {
        self.values
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(None, |range, v| match range {
                None => Some((v, v)),
                Some((low, high)) => Some((v.min(low), v.max(high))),
            })
    }

    /// What is inconsistent about the grid, if anything: a non-finite
    /// origin, a spacing that is not finite and non-zero, or a number of
    /// values other than columns · rows.
    pub(super) fn check(&self) -> std::result::Result<(), String> {
        if !self.origin.is_finite() {
            return Err(format!("the grid's origin {} is not finite", self.origin));
        }
        if !self.spacing.is_finite() || self.spacing.x == 0.0 || self.spacing.y == 0.0 {
            return Err(format!(
                "the grid's spacing {} is not finite and non-zero",
                self.spacing
            ));
        }
        match self.columns.checked_mul(self.rows) {
            Some(count) if count == self.values.len() => Ok(()),
            _ => Err(format!(
                "a grid of {} × {} points has {} values",
                self.columns,
                self.rows,
                self.values.len()
            )),
        }
    }

    /// The rectangle holding the grid's points, the outline and the
    /// luminaires, finite ones only; None when there is none.
    pub(super) fn bounds(&self) -> Option<Rect2> {
        let corners = (self.columns > 0 && self.rows > 0).then(|| {
            let last = DVec2::new(
                self.columns.saturating_sub(1) as f64,
                self.rows.saturating_sub(1) as f64,
            );
            [self.plane_point(DVec2::ZERO), self.plane_point(last)]
        });
        corners
            .into_iter()
            .flatten()
            .chain(self.outlines.iter().flatten().copied())
            .chain(self.luminaires.iter().map(|(position, _)| *position))
            .filter(|p| p.is_finite())
            .fold(None, |bounds, p| match bounds {
                None => Some(Rect2 { low: p, high: p }),
                Some(Rect2 { low, high }) => Some(Rect2 {
                    low: low.min(p),
                    high: high.max(p),
                }),
            })
    }
}
