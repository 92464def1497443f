//! A solved scene ([`Solution`]): radiosity and irradiance at its mesh
//! vertices, per-surface totals, and probes read at any point of a
//! surface, by final gather (`reading/gather.rs`) or on the mesh
//! (`reading/interpolation.rs`).

use glam::DVec3;

use crate::error::{Error, Result};
use crate::lighting::DaylightSource;
use crate::mesh::{Mesh, receiver_inset};
use crate::rgb::Rgb;
use crate::scene::{ProbePoint, Scene, SurfaceId, Visibility};
use crate::solver::ambient::irradiance::AmbientIrradiance;
use crate::solver::light::vertex_irradiance::VertexIrradiance;
use crate::solver::reading::places::{ReadingPlace, locate_probe};

/// How a probe reads the solution.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ProbeMode {
    /// A final gather at the exact point: the light of every element, with
    /// Lambert's exact form factor and stratified shadow rays.
    #[default]
    Gather,
    /// The value interpolated on the rendered mesh: what a viewer sees.
    Mesh,
}

/// What a probe read at a point, per RGB channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probe {
    /// The point.
    pub position: DVec3,
    /// The surface it lies on.
    pub surface: SurfaceId,
    /// Irradiance H, W/m²: light arriving on the surface's front.
    pub irradiance: Rgb,
    /// Standard error of `irradiance` per channel, W/m²: the sampling error
    /// of the gather's shadow rays (partly hidden sources), not the
    /// solution's own error. Zero in [`ProbeMode::Mesh`], which samples
    /// nothing, and where every source is wholly visible or hidden.
    pub standard_error: Rgb,
    /// Radiosity B = E + ρ H, W/m².
    pub radiosity: Rgb,
    /// In-plane gradient of the radiosity of each channel (r, g, b), as
    /// world-space vectors, W/m³ (per scene unit).
    pub gradient: [DVec3; 3],
}

/// Totals over one surface's mesh elements: area-weighted means of the
/// elements' vertex values, and the power they carry.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SurfaceTotals {
    /// Meshed area (a part hidden under an object standing on the surface
    /// is not meshed), square scene units.
    pub area: f64,
    /// Mean radiosity B, W/m².
    pub mean_radiosity: Rgb,
    /// Mean irradiance H, W/m².
    pub mean_irradiance: Rgb,
    /// Power received, ∫ H dA, W (with lengths in metres).
    pub received_power: Rgb,
}

/// A solution: radiosity and irradiance at every mesh vertex
/// ([`Solution::radiosity_at`], [`Solution::irradiance_at`]), with the
/// scene, mesh and visibility needed to read it anywhere. It borrows the
/// light shot from its solver and holds the ambient term it adds, where
/// that was gathered (every vertex, or the rooms an image is taken in).
pub struct Solution<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// Its mesh.
    pub mesh: &'a Mesh,
    /// Its shadow-ray structure.
    pub visibility: &'a Visibility,
    /// Which of the scene's photometric luminaires the solution holds the
    /// light of (gather probes add their direct light).
    pub luminaires_shot: Vec<bool>,
    /// The daylight, when the solution holds its light (gather probes add
    /// its direct light).
    pub(crate) daylight: Option<&'a DaylightSource>,
    /// Irradiance per mesh vertex from the light shot, W/m²: the solver's.
    pub(crate) shot_irradiance: &'a VertexIrradiance,
    /// The ambient term G_v added to it (`solver/ambient/rays.rs`).
    pub(crate) ambient: AmbientIrradiance,
    /// The closed zone of every surface, when the solver found more than
    /// one: an image taken from inside a closed room draws that room alone.
    pub(crate) zones: Option<&'a crate::meshing::ZoneLabels>,
    /// How far each surface's boundary vertices gather inside it, by
    /// surface index (the scene's inset past its end).
    pub(crate) receiver_insets: &'a [f64],
    /// Whether each surface is a face of an emitting body, by surface
    /// index: a gather takes its emission from the body's luminaire, and
    /// from the faces only the light they reflect.
    pub(crate) in_emitting_body: &'a [bool],
    /// The closed zones, ascending, whose ambient term this solution
    /// holds when it was made for some alone
    /// ([`crate::solver::Ambient::For`]); a probe elsewhere
    /// would read light that lacks the term, and is refused.
    pub(crate) ambient_zones: Option<Vec<usize>>,
}

impl Solution<'_> {
    /// Irradiance H at mesh vertex `vertex`, W/m²: the light shot there
    /// plus the ambient term.
    ///
    /// # Panics
    /// When `vertex` is not an index into the mesh's vertices.
    #[must_use]
    pub fn irradiance_at(&self, vertex: usize) -> Rgb {
        self.shot_irradiance.at(vertex) + self.ambient.at(vertex)
    }

    /// Radiosity B = E + ρ H at mesh vertex `vertex`, W/m², with the
    /// emission E and reflectance ρ of its surface's material.
    ///
    /// # Panics
    /// When `vertex` is not an index into the mesh's vertices.
    #[must_use]
    pub fn radiosity_at(&self, vertex: usize) -> Rgb {
        let surface = self.scene.surface(self.mesh.vertices[vertex].surface);
        let material = self.scene.material_of(surface);
        material.emitted_radiosity() + material.reflectance * self.irradiance_at(vertex)
    }

    /// Every mesh vertex's irradiance ([`Solution::irradiance_at`]), in
    /// the mesh's order: a new list, 24 bytes a vertex.
    #[must_use]
    pub fn irradiance(&self) -> Vec<Rgb> {
        (0..self.mesh.vertices.len())
            .map(|v| self.irradiance_at(v))
            .collect()
    }

    /// Every mesh vertex's radiosity ([`Solution::radiosity_at`]), in the
    /// mesh's order: a new list, 24 bytes a vertex.
    #[must_use]
    pub fn radiosity(&self) -> Vec<Rgb> {
        (0..self.mesh.vertices.len())
            .map(|v| self.radiosity_at(v))
            .collect()
    }

    /// Totals per surface, indexed as [`Scene::surfaces`]; each element
    /// contributes its area times the mean of its corners' values: the
    /// integrals of the shaded mesh. (The solver's energy ledger counts an
    /// emitter's light on each element with the curvature of its field,
    /// which the corners' mean misses; see [`crate::solver::EnergyBalance`].)
    #[must_use]
    pub fn surface_totals(&self) -> Vec<SurfaceTotals> {
        let mut totals = vec![
            SurfaceTotals {
                area: 0.0,
                mean_radiosity: Rgb::ZERO,
                mean_irradiance: Rgb::ZERO,
                received_power: Rgb::ZERO,
            };
            self.scene.surfaces.len()
        ];
        for element in &self.mesh.elements {
            let total = &mut totals[element.surface.index()];
            total.area += element.area;
            let radiosity = element.corner_mean(|v| self.radiosity_at(v as usize));
            let irradiance = element.corner_mean(|v| self.irradiance_at(v as usize));
            total.mean_radiosity += radiosity * element.area;
            total.received_power += irradiance * element.area;
        }
        for total in &mut totals {
            if total.area > 0.0 {
                total.mean_radiosity /= total.area;
                total.mean_irradiance = total.received_power / total.area;
            }
        }
        totals
    }

    /// Reads the solution at a point on a surface.
    ///
    /// Fails with [`Error::ProbePoint`] (naming the point's line) when the
    /// point lies on no surface, or on none facing along its normal, or
    /// outside the rooms whose ambient term the solution was made for
    /// ([`Solution::holds_term_at`]).
    pub fn probe(&self, point: &ProbePoint, mode: ProbeMode) -> Result<Probe> {
        let surface = self.locate(point).ok_or_else(|| Error::ProbePoint {
            path: "points".into(),
            line: point.line,
            message: format!(
                "({}, {}, {}) lies on no surface{}",
                point.position.x,
                point.position.y,
                point.position.z,
                if point.normal.is_some() {
                    " facing along its normal"
                } else {
                    ""
                }
            ),
        })?;
        if !self.holds_term_at(&ReadingPlace::OnSurface(surface)) {
            return Err(Error::ProbePoint {
                path: "points".into(),
                line: point.line,
                message: format!(
                    "({}, {}, {}) lies outside the rooms this solution's ambient term was made for",
                    point.position.x, point.position.y, point.position.z
                ),
            });
        }
        Ok(match mode {
            ProbeMode::Gather => self.gather(point.position, surface),
            ProbeMode::Mesh => self.interpolate(point.position, surface),
        })
    }

    /// The surface a point lies on ([`locate_probe`]).
    fn locate(&self, point: &ProbePoint) -> Option<SurfaceId> {
        locate_probe(self.scene, point)
    }

    /// Whether the solution holds the ambient term at `place`: always,
    /// unless it was made for some rooms' readings alone
    /// ([`crate::solver::Ambient::For`]) and `place` lies in
    /// none of them. Probes and gathers in space are read only where it
    /// does; images, exports and totals read every vertex as it is.
    #[must_use]
    pub fn holds_term_at(&self, place: &ReadingPlace) -> bool {
        let Some(zones) = self.zones.filter(|_| self.ambient_zones.is_some()) else {
            return true;
        };
        self.holds_term_in(place.zone(zones, self.scene, self.visibility))
    }

    /// [`Solution::holds_term_at`] a place in closed zone `zone` (`None`:
    /// in none).
    pub(super) fn holds_term_in(&self, zone: Option<usize>) -> bool {
        match (self.zones, &self.ambient_zones) {
            (Some(_), Some(made)) => zone.is_some_and(|z| made.binary_search(&z).is_ok()),
            _ => true,
        }
    }

    /// The closed zone a gather at `x` on `surface` ([`SurfaceId::NONE`]
    /// in free space) sees alone, if any ([`ReadingPlace::zone`]). A
    /// closed zone keeps its light, so no other zone's element can send
    /// any there, and a gather in one office of a building need not try
    /// the others'.
    pub(crate) fn gathered_zone(&self, x: DVec3, surface: SurfaceId) -> Option<usize> {
        let place = if surface == SurfaceId::NONE {
            ReadingPlace::InSpace(x)
        } else {
            ReadingPlace::OnSurface(surface)
        };
        place.zone(self.zones?, self.scene, self.visibility)
    }

    /// How far `surface`'s boundary vertices gather inside it: its room's
    /// inset, or the scene's for a mesh the caller brought.
    pub(super) fn receiver_inset(&self, surface: SurfaceId) -> f64 {
        let own = self.receiver_insets.get(surface.index()).copied();
        own.unwrap_or_else(|| receiver_inset(self.scene))
    }
}
