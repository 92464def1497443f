//! Where a calculation grid's points lie: [`CalculationGrid::on_surface`]
//! lays a regular grid over the named surfaces, or over the work plane a
//! height above them, in the frame a plan shows.
//!
//! The grid follows EN 12464-1:2021, §4.4 and Annex: the largest cell size
//! is p = 0.2 · 5^log₁₀(d) m, with d the longer side of the area in metres;
//! each side is cut into ⌈side / p⌉ equal cells and the points sit at the
//! cells' centres, so none lies on the boundary. Points outside the
//! surface's outline are left out.

use crate::scene::Box3;
use glam::{DVec2, DVec3};

use super::grid::CalculationGrid;
use crate::error::{Error, Result};
use crate::scene::{PlaneFrame, Scene, SurfaceId, polygon_contains};

/// The most points a grid may have: a million (a metre-wide grid at
/// one-millimetre spacing), far beyond what a standard asks for.
pub const MAX_GRID_POINTS: usize = 1_000_000;

/// The largest grid spacing EN 12464-1 allows on an area whose longer side
/// is `longer_side` metres: p = 0.2 · 5^log₁₀(d), and at most 10 m. For a
/// 10 m room that is 1 m; for a 1 m desk, 0.2 m.
#[must_use]
pub fn en12464_spacing(longer_side: f64) -> f64 {
    (0.2 * 5f64.powf(longer_side.max(f64::MIN_POSITIVE).log10())).min(10.0)
}

impl CalculationGrid {
    /// The grid on the surfaces named `name`, or on the plane `height` above
    /// them, with points at most `spacing` apart (EN 12464-1's spacing for
    /// the area when `None`).
    ///
    /// A name may cover several polygons (an OBJ object split into faces);
    /// the grid takes those in the plane of the largest, facing its way.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] when no surface has the name, when
    /// `height` is negative or not finite or puts the plane beyond the
    /// scene's bounding box, when `spacing` is not positive, or when the
    /// grid would pass [`MAX_GRID_POINTS`].
    pub fn on_surface(
        scene: &Scene,
        name: &str,
        height: f64,
        spacing: Option<f64>,
    ) -> Result<CalculationGrid> {
        check_height_and_spacing(height, spacing)?;
        // The named surfaces in the plane of the largest.
        let tolerance = 1e-4 * scene.diagonal();
        let surfaces = NamedSurfaces::find(scene, name, tolerance)?;
        let base = scene.surface(surfaces.largest);
        let normal = base.normal();
        let frame = plan_frame(base.frame().origin + normal * height, normal);
        check_within_scene(scene, base.frame(), name, height, tolerance)?;
        // Their outlines in the grid's plane, and the cells over them.
        let outlines: Vec<Vec<DVec2>> = surfaces
            .covered
            .iter()
            .map(|&id| {
                let s = scene.surface(id);
                s.vertices().iter().map(|&p| frame.to_plane(p)).collect()
            })
            .collect();
        let cells = Cells::over(&outlines, spacing, name)?;
        // A point at each cell's centre inside an outline.
        let points = (0..cells.rows * cells.columns)
            .map(|k| {
                let p = cells.origin
                    + DVec2::new((k % cells.columns) as f64, (k / cells.columns) as f64)
                        * cells.spacing;
                let (inside, _) = surfaces
                    .covered
                    .iter()
                    .zip(&outlines)
                    .find(|(_, outline)| polygon_contains(outline, p))?;
                Some((frame.to_world(p), *inside))
            })
            .collect();
        let axes = [axis_name(frame.u), axis_name(frame.v)];
        Ok(CalculationGrid {
            axes,
            name: name.to_owned(),
            height,
            frame,
            origin: cells.origin,
            spacing: cells.spacing,
            columns: cells.columns,
            rows: cells.rows,
            outlines,
            points,
        })
    }
}

/// An [`Error::InvalidSetting`] for `field`.
fn invalid(field: &str, message: String) -> Error {
    Error::InvalidSetting {
        name: field.into(),
        message,
    }
}

/// Refuses a height that is negative or not finite, and a spacing that is
/// given but not positive.
fn check_height_and_spacing(height: f64, spacing: Option<f64>) -> Result<()> {
    if !(height.is_finite() && height >= 0.0) {
        return Err(invalid("height", format!("{height} must be ≥ 0")));
    }
    if let Some(spacing) = spacing
        && !(spacing.is_finite() && spacing > 0.0)
    {
        return Err(invalid("spacing", format!("{spacing} must be > 0")));
    }
    Ok(())
}

/// The surfaces a grid covers: the largest of those with its name, and
/// those of them in its plane (within a tolerance) facing its way.
struct NamedSurfaces {
    /// The largest surface with the name: its plane is the grid's.
    largest: SurfaceId,
    /// The named surfaces in that plane, the largest among them.
    covered: Vec<SurfaceId>,
}

impl NamedSurfaces {
    /// The surfaces named `name`; [`Error::InvalidSetting`] when there is
    /// none.
    fn find(scene: &Scene, name: &str, tolerance: f64) -> Result<NamedSurfaces> {
        let named: Vec<SurfaceId> = scene
            .surfaces_with_ids()
            .filter(|(_, s)| s.name == name)
            .map(|(id, _)| id)
            .collect();
        let Some(&largest) = named.iter().max_by(|a, b| {
            scene
                .surface(**a)
                .area()
                .total_cmp(&scene.surface(**b).area())
        }) else {
            return Err(invalid("surface", unknown_surface_message(scene, name)));
        };
        let base = scene.surface(largest);
        let normal = base.normal();
        let covered: Vec<SurfaceId> = named
            .into_iter()
            .filter(|&id| {
                let s = scene.surface(id);
                s.normal().dot(normal) > 0.9999
                    && base.frame().height(s.frame().origin).abs() <= tolerance
            })
            .collect();
        Ok(NamedSurfaces { largest, covered })
    }
}

/// Refuses a work plane `height` above the surface in plane `base` that
/// lies above the scene's highest point over it (its bounding box's
/// corners): such a plane lies outside the scene.
fn check_within_scene(
    scene: &Scene,
    base: &PlaneFrame,
    name: &str,
    height: f64,
    tolerance: f64,
) -> Result<()> {
    let Box3 {
        min: low,
        max: high,
    } = scene.bounds();
    let reach = (0..8)
        .map(|k| {
            let corner = DVec3::new(
                if k & 1 == 0 { low.x } else { high.x },
                if k & 2 == 0 { low.y } else { high.y },
                if k & 4 == 0 { low.z } else { high.z },
            );
            base.height(corner)
        })
        .fold(f64::NEG_INFINITY, f64::max);
    if height > reach + tolerance {
        return Err(invalid(
            "height",
            format!(
                "{} puts the work plane above `{name}` outside the scene, \
                 which reaches {} above it",
                short_number(height),
                short_number(reach)
            ),
        ));
    }
    Ok(())
}

/// The grid's cells over the outlines' bounding rectangle: `columns` ×
/// `rows` equal cells, their centres from `origin` on, `spacing` apart.
struct Cells {
    origin: DVec2,
    spacing: DVec2,
    columns: usize,
    rows: usize,
}

impl Cells {
    /// Cells at most `spacing` wide (EN 12464-1's spacing for the area when
    /// `None`) over `outlines`; [`Error::InvalidSetting`] when they would
    /// be more than [`MAX_GRID_POINTS`] (`name` names the surface).
    fn over(outlines: &[Vec<DVec2>], spacing: Option<f64>, name: &str) -> Result<Cells> {
        let (low, high) = outlines
            .iter()
            .flatten()
            .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(low, high), &p| {
                (low.min(p), high.max(p))
            });
        let size = high - low;
        let largest_spacing = spacing.unwrap_or_else(|| en12464_spacing(size.max_element()));
        let cells = |side: f64| ((side / largest_spacing).ceil() as usize).max(1);
        let (columns, rows) = (cells(size.x), cells(size.y));
        if columns.saturating_mul(rows) > MAX_GRID_POINTS {
            return Err(invalid(
                "spacing",
                format!(
                    "{largest_spacing} gives {columns} × {rows} points on `{name}`, \
                     more than {MAX_GRID_POINTS}"
                ),
            ));
        }
        let spacing = DVec2::new(size.x / columns as f64, size.y / rows as f64);
        let origin = low + spacing / 2.0;
        Ok(Cells {
            origin,
            spacing,
            columns,
            rows,
        })
    }
}

/// The name of a unit axis as a world axis with its unit: `x (m)`,
/// `−z (m)`, …, or `in-plane (m)` where it is oblique.
fn axis_name(axis: DVec3) -> String {
    for (name, world) in [("x", DVec3::X), ("y", DVec3::Y), ("z", DVec3::Z)] {
        if axis.dot(world) > 0.9999 {
            return format!("{name} (m)");
        }
        if axis.dot(world) < -0.9999 {
            return format!("−{name} (m)");
        }
    }
    "in-plane (m)".to_owned()
}

/// The frame a plan shows: for a horizontal surface (|n_y| > 0.9), u along
/// +x and v = n × u (−z on a floor seen from above); otherwise v up (+y
/// projected onto the plane) and u = v × n, a wall seen from its front.
/// The origin is the plane's point nearest the world's origin, so that
/// plane coordinates along world axes are world coordinates.
fn plan_frame(point: DVec3, normal: DVec3) -> PlaneFrame {
    let origin = normal * normal.dot(point);
    let (u, v) = if normal.y.abs() > 0.9 {
        let u = (DVec3::X - normal * normal.x).normalize();
        (u, normal.cross(u))
    } else {
        let v = (DVec3::Y - normal * normal.y).normalize();
        (v.cross(normal), v)
    };
    PlaneFrame {
        origin,
        u,
        v,
        normal,
    }
}

/// A number as a message shows it: plain when of everyday size, else in
/// scientific notation (1e300, not three hundred digits).
fn short_number(value: f64) -> String {
    if value == 0.0 || (1e-3..1e6).contains(&value.abs()) {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

/// "no surface is named `x`", with the names there are (the first 20).
fn unknown_surface_message(scene: &Scene, name: &str) -> String {
    let mut names: Vec<&str> = scene.surfaces.iter().map(|s| s.name.as_str()).collect();
    names.sort_unstable();
    names.dedup();
    let more = names.len().saturating_sub(20);
    names.truncate(20);
    let mut message = format!(
        "no surface is named `{name}`; the scene has {}",
        names.join(", ")
    );
    if more > 0 {
        message.push_str(&format!(" and {more} more"));
    }
    message
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn en12464_spacing_follows_the_formula() {
        assert!((en12464_spacing(10.0) - 1.0).abs() < 1e-12);
        assert!((en12464_spacing(1.0) - 0.2).abs() < 1e-12);
        assert!((en12464_spacing(100.0) - 5.0).abs() < 1e-12);
        assert!((en12464_spacing(1e6) - 10.0).abs() < 1e-12);
        assert!(en12464_spacing(0.0) > 0.0);
    }

    #[test]
    fn a_floor_plan_is_seen_from_above() {
        let frame = plan_frame(DVec3::ZERO, DVec3::Y);
        assert_eq!(frame.u, DVec3::X);
        assert!((frame.v + DVec3::Z).length() < 1e-12);
        assert!((frame.u.cross(frame.v) - frame.normal).length() < 1e-12);
        let wall = plan_frame(DVec3::ZERO, DVec3::Z);
        assert!((wall.v - DVec3::Y).length() < 1e-12);
        assert!((wall.u.cross(wall.v) - wall.normal).length() < 1e-12);
    }
}
