//! Calculation grids: illuminance at the points of a regular grid on a named
//! surface, or on the work plane a height above it, with the statistics a
//! lighting standard asks for.
//!
//! The points are laid out as EN 12464-1 spaces them
//! ([`CalculationGrid::on_surface`], in the `grid_layout` module). A point
//! on the surface is read by the solution's gather probe; a point of a
//! raised work plane lies in free space, where the gather is evaluated on a
//! small horizontal receiver ([`Solution::irradiance_in_space`]), not
//! interpolated on a mesh. Points inside an object or closer than a
//! clearance to another surface are left out of the statistics unless
//! kept (the `grid_obstruction` module's rule).

use std::io::Write;
use std::path::Path;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::grid_obstruction::{GridSelection, ObstructionRule, obstruction_at};
use super::grid_picture::GridPicture;
use super::grid_quantity::{GridQuantity, IlluminanceStatistics};
use crate::error::Result;
use crate::fs::{io_error, write_atomically};
use crate::lighting::area_lights;
use crate::photometry::LUMENS_PER_WATT;
use crate::rgb::Rgb;
use crate::scene::{PlaneFrame, ProbePoint, Scene, SurfaceId, Visibility};
use crate::solver::{ProbeMode, ReadingPlace, Solution};

/// A calculation grid: points on a plane over a surface's outline.
#[derive(Clone, Debug, PartialEq)]
pub struct CalculationGrid {
    /// The surface name the grid was asked for.
    pub name: String,
    /// Height of the grid's plane above the surface, along its normal.
    pub height: f64,
    /// The grid's plane: the surface's plane raised by `height`, with `u`
    /// and `v` as a plan shows them (for a floor, x to the right and −z up,
    /// seen from above; for a wall, up is +y).
    pub frame: PlaneFrame,
    /// Plane coordinates of point (0, 0); point (column, row) is at
    /// `origin + (column · spacing.x, row · spacing.y)`.
    pub origin: DVec2,
    /// Distance between neighbouring points along u and v.
    pub spacing: DVec2,
    /// Points along u and along v.
    pub columns: usize,
    /// Points along v.
    pub rows: usize,
    /// The outlines of the surfaces the grid covers, in plane coordinates.
    pub outlines: Vec<Vec<DVec2>>,
    /// The names of the plane's axes u and v as world axes, with units
    /// (`x (m)`, `−z (m)`, …; `in-plane (m)` where an axis is oblique).
    pub axes: [String; 2],
    /// Row-major (`row * columns + column`): the world position of each point
    /// and the surface under it, `None` outside every outline.
    pub points: Vec<Option<(DVec3, SurfaceId)>>,
}

/// Illuminance, lx, of an irradiance: its luminance (Rec. 709 weights of
/// isorad's linear RGB primaries) at 179 lm/W.
#[must_use]
pub fn illuminance_lux(irradiance: Rgb) -> f64 {
    irradiance.luminance() * LUMENS_PER_WATT
}

impl CalculationGrid {
    /// The grid's points sorted by `rule` (see [`ObstructionRule`]): which
    /// are inside an object or near a surface, and whether those count.
    /// Points are tested in parallel.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`](crate::Error::InvalidSetting) naming
    /// `clearance` when the rule's clearance is negative or not finite.
    pub fn select(
        &self,
        scene: &Scene,
        visibility: &Visibility,
        rule: &ObstructionRule,
    ) -> Result<GridSelection> {
        rule.validate()?;
        let on_surface = self.height <= 0.0;
        let obstructions = self
            .points
            .par_iter()
            .map(|point| {
                let (position, _) = (*point)?;
                obstruction_at(
                    scene,
                    visibility,
                    position,
                    &self.frame,
                    on_surface,
                    rule.clearance,
                )
            })
            .collect();
        Ok(GridSelection {
            obstructions,
            rule: *rule,
        })
    }

    /// The illuminance at every point, lx, row-major, under the default
    /// [`ObstructionRule`]: NaN outside the outline, and at points inside
    /// an object or within 1 cm of another surface.
    /// [`CalculationGrid::illuminance_of`] with
    /// [`CalculationGrid::select`]'s default selection.
    #[must_use]
    pub fn illuminance(&self, solution: &Solution<'_>) -> Vec<f64> {
        let rule = ObstructionRule::default();
        match self.select(solution.scene, solution.visibility, &rule) {
            Ok(selection) => self.illuminance_of(solution, &selection),
            // The default rule is valid.
            Err(_) => vec![f64::NAN; self.points.len()],
        }
    }

    /// The illuminance at the points `selection` counts, lx, row-major;
    /// NaN outside the outline and at the points it leaves out. On the
    /// surface (height 0) each point is a gather probe of the surface
    /// under it; above it, a gather in free space facing the surface's
    /// normal. A point outside the rooms whose ambient term `solution` was
    /// made for is NaN too (give it the grid's
    /// [`CalculationGrid::reading_places`], or the whole term). Points are
    /// evaluated in parallel.
    #[must_use]
    pub fn illuminance_of(&self, solution: &Solution<'_>, selection: &GridSelection) -> Vec<f64> {
        let normal = self.frame.normal;
        self.points
            .par_iter()
            .enumerate()
            .map(|(index, point)| {
                let Some((position, _)) = *point else {
                    return f64::NAN;
                };
                if !selection.counts(index) {
                    return f64::NAN;
                }
                let irradiance = if self.height > 0.0 {
                    solution.irradiance_in_space(position, normal).0
                } else {
                    match solution.probe(&self.probe_point(position), ProbeMode::Gather) {
                        Ok(probe) => probe.irradiance,
                        // The point lies on the surface by construction; a
                        // gather that cannot place it, or a solution whose
                        // ambient term was made for other rooms, reads
                        // nothing there.
                        Err(_) => return f64::NAN,
                    }
                };
                illuminance_lux(irradiance)
            })
            .collect()
    }

    /// Writes the grid's points inside the outline as CSV, columns
    /// `x,y,z,illuminance_lux,status`, after `#` lines that say what the
    /// grid is, which points were left out and why, and give Emin, Eavg,
    /// Emax, U₀ = Emin/Eavg and Emin/Emax, one per line as
    /// `# name = value` ([`CalculationGrid::header_lines`]). `lux` comes
    /// from [`CalculationGrid::illuminance_of`] with the same `selection`;
    /// a point left out has an empty illuminance and its reason as status
    /// ([`GridSelection::status`]). The file is written atomically.
    ///
    /// # Errors
    /// [`Error::Io`](crate::Error::Io) when the file cannot be written.
    pub fn write_csv(&self, path: &Path, lux: &[f64], selection: &GridSelection) -> Result<()> {
        let quantity = GridQuantity::Illuminance { daylight: false };
        self.write_csv_as(path, lux, selection, quantity)
    }

    /// [`CalculationGrid::write_csv`] for values of `quantity`: its column
    /// (`illuminance_lux` or `daylight_factor_percent`) and statistics
    /// ([`GridQuantity::statistics_lines`]).
    ///
    /// # Errors
    /// [`Error::Io`](crate::Error::Io) when the file cannot be written.
    pub fn write_csv_as(
        &self,
        path: &Path,
        lux: &[f64],
        selection: &GridSelection,
        quantity: GridQuantity,
    ) -> Result<()> {
        write_atomically(path, |out| {
            let io = |error| io_error(path, error);
            for line in self.header_lines_as(lux, selection, quantity) {
                writeln!(out, "# {line}").map_err(io)?;
            }
            writeln!(out, "x,y,z,{},status", quantity.column()).map_err(io)?;
            for (index, (point, &e)) in self.points.iter().zip(lux).enumerate() {
                let Some((p, _)) = point else { continue };
                let status = selection.status(index, e.is_finite());
                let value = if e.is_finite() {
                    e.to_string()
                } else {
                    String::new()
                };
                writeln!(out, "{},{},{},{value},{status}", p.x, p.y, p.z).map_err(io)?;
            }
            Ok(())
        })
    }

    /// What the grid is and its statistics, as `name = value` lines.
    /// Besides the grid, the clearance and the points left out (or kept)
    /// for each reason ([`GridSelection::summary_lines`]), and `unread` when
    /// counted points could not be read.
    #[must_use]
    pub fn header_lines(&self, lux: &[f64], selection: &GridSelection) -> Vec<String> {
        self.header_lines_as(
            lux,
            selection,
            GridQuantity::Illuminance { daylight: false },
        )
    }

    /// [`CalculationGrid::header_lines`] for values of `quantity`.
    #[must_use]
    pub fn header_lines_as(
        &self,
        lux: &[f64],
        selection: &GridSelection,
        quantity: GridQuantity,
    ) -> Vec<String> {
        let n = self.frame.normal;
        let mut lines = vec![
            format!("surface = {}", self.name),
            format!("height = {}", self.height),
            format!("normal = {} {} {}", n.x, n.y, n.z),
            format!(
                "grid = {} x {} at {:.4} x {:.4}",
                self.columns, self.rows, self.spacing.x, self.spacing.y
            ),
        ];
        lines.extend(selection.summary_lines());
        let unread = (self.points.iter().zip(lux).enumerate())
            .filter(|(k, (p, e))| p.is_some() && e.is_nan() && selection.counts(*k))
            .count();
        if unread > 0 {
            lines.push(format!("unread = {unread}"));
        }
        lines.extend(quantity.statistics_lines(lux));
        lines
    }

    /// The grid ready to be drawn ([`write_isolux_plot`],
    /// [`write_falsecolor_grid`]) with its illuminance `lux`, the
    /// luminaires' marks (see [`CalculationGrid::luminaire_marks`]) and a
    /// title.
    ///
    /// [`write_isolux_plot`]: super::write_isolux_plot
    /// [`write_falsecolor_grid`]: super::write_falsecolor_grid
    #[must_use]
    pub fn picture<'a>(
        &'a self,
        lux: &'a [f64],
        luminaires: &'a [(DVec2, String)],
        title: &'a str,
    ) -> GridPicture<'a> {
        GridPicture {
            origin: self.origin,
            spacing: self.spacing,
            columns: self.columns,
            rows: self.rows,
            values: lux,
            outlines: &self.outlines,
            luminaires,
            title,
            unit: "lx",
            axes: [self.axes[0].as_str(), self.axes[1].as_str()],
        }
    }

    /// Where the scene's lamps stand over the grid's plane, with labels:
    /// each area luminaire's centre (labelled by its first surface's name)
    /// and each photometric luminaire's centre (`p0`, `p1`, … as `isorad
    /// info` numbers them), projected onto the plane, for those in front of
    /// it.
    #[must_use]
    pub fn luminaire_marks(&self, scene: &Scene) -> Vec<(DVec2, String)> {
        let in_front = |p: DVec3| self.frame.height(p) > 0.0;
        let mut marks: Vec<(DVec2, String)> = area_lights(scene)
            .iter()
            .filter(|lamp| in_front(lamp.centre))
            .map(|lamp| {
                let name = scene.surface(lamp.surfaces[0]).name.clone();
                (self.frame.to_plane(lamp.centre), name)
            })
            .collect();
        marks.extend(
            scene
                .luminaires
                .iter()
                .enumerate()
                .filter(|(_, l)| in_front(l.position))
                .map(|(k, l)| (self.frame.to_plane(l.position), format!("p{k}"))),
        );
        marks
    }

    /// A title for the grid's pictures: the surface, the height and the
    /// statistics.
    #[must_use]
    pub fn title(&self, lux: &[f64]) -> String {
        self.titled(lux, |s| {
            format!(
                "Eavg {:.0} lx, Emin {:.0} lx, U0 {:.2}",
                s.average,
                s.minimum,
                s.uniformity()
            )
        })
    }

    /// The grid's place (the surface, and the height when raised), then
    /// `statistics` of `values`' statistics when there are any.
    fn titled(
        &self,
        values: &[f64],
        statistics: impl Fn(&IlluminanceStatistics) -> String,
    ) -> String {
        let place = if self.height > 0.0 {
            format!("{} + {} m", self.name, self.height)
        } else {
            self.name.clone()
        };
        match IlluminanceStatistics::of(values) {
            Some(stats) => format!("{place}: {}", statistics(&stats)),
            None => place,
        }
    }

    /// A title for a daylight-factor grid's pictures: the place, the mean
    /// and minimum DF and the uniformity.
    #[must_use]
    pub fn daylight_factor_title(&self, df: &[f64]) -> String {
        self.titled(df, |s| {
            format!(
                "DF avg {:.2} %, min {:.2} %, U0 {:.2}",
                s.average,
                s.minimum,
                s.uniformity()
            )
        })
    }

    /// Where the grid's points read the solution, for
    /// [`crate::Ambient::For`]: on the surface (height
    /// 0), the front of the surface each point's probe lies on
    /// ([`ReadingPlace::of_probe`], as [`Solution::probe`] finds it);
    /// above it, each point in space. Points `selection` leaves out, which
    /// read nothing ([`CalculationGrid::illuminance_of`]), are left out.
    #[must_use]
    pub fn reading_places(&self, scene: &Scene, selection: &GridSelection) -> Vec<ReadingPlace> {
        self.points
            .par_iter()
            .enumerate()
            .filter_map(|(index, point)| {
                let (position, _) = (*point)?;
                if !selection.counts(index) {
                    return None;
                }
                if self.height > 0.0 {
                    Some(ReadingPlace::InSpace(position))
                } else {
                    ReadingPlace::of_probe(scene, &self.probe_point(position))
                }
            })
            .collect()
    }

    /// The probe a point of the grid on its surface (height 0) reads.
    fn probe_point(&self, position: DVec3) -> ProbePoint {
        ProbePoint {
            position,
            normal: Some(self.frame.normal),
            line: 0,
        }
    }

    /// Plane coordinates of point `index` (row-major).
    #[must_use]
    pub fn plane_point(&self, index: usize) -> DVec2 {
        let (column, row) = (index % self.columns, index / self.columns);
        self.origin + DVec2::new(column as f64, row as f64) * self.spacing
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_skip_points_outside() {
        let stats = IlluminanceStatistics::of(&[100.0, f64::NAN, 300.0, 200.0]).unwrap();
        assert_eq!(stats.points, 3);
        assert_eq!(
            (stats.minimum, stats.average, stats.maximum),
            (100.0, 200.0, 300.0)
        );
        assert!((stats.uniformity() - 0.5).abs() < 1e-12);
        assert!((stats.diversity() - 1.0 / 3.0).abs() < 1e-12);
        assert!(IlluminanceStatistics::of(&[f64::NAN]).is_none());
    }
}
