//! A solved scene, and reading it at any point (the probes).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::{DVec2, DVec3};

use crate::error::{Error, Result};
use crate::lighting::SampleStream;
use crate::mesh::{Cell, Mesh, receiver_inset};
use crate::radiometry::{polygon_form_factor, polygon_form_factor_gradient};
use crate::scene::{
    ProbePoint, Rgb, Scene, SurfaceId, Visibility, distance_to_boundary, distance_to_segment,
    polygon_contains,
};
use crate::solver::ambient::irradiance::AmbientIrradiance;
use crate::solver::light::vertex_irradiance::VertexIrradiance;
use crate::solver::reading::penumbra::AdaptiveVisibility;
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

/// Extra shadow rays one gather probe may cast refining partly hidden
/// sources, beyond one ray per base stratum: 16 384 (a few milliseconds).
pub const PENUMBRA_RAY_BUDGET: usize = 16_384;

/// The standard error, relative to the probe's irradiance (summed over
/// channels), under which a gather stops refining penumbrae.
const PENUMBRA_RELATIVE_ERROR: f64 = 0.005;

/// One element a gather sees: its mean radiosity, its unoccluded form
/// factor and its shadow rays.
struct GatherSource<'a> {
    radiosity: Rgb,
    factor: f64,
    visibility: AdaptiveVisibility<'a>,
}

/// Refines the sources' visibility, the largest contributor to the
/// variance first, until the irradiance's standard error is under
/// [`PENUMBRA_RELATIVE_ERROR`] of its value, every source is settled, or the
/// next step would pass [`PENUMBRA_RAY_BUDGET`]. Returns each source's
/// visible share and its variance.
fn refine_penumbrae(sources: &mut [GatherSource<'_>]) -> Vec<(f64, f64)> {
    let weight = |source: &GatherSource<'_>| source.factor * source.radiosity.element_sum();
    let mut estimates: Vec<(f64, f64)> = sources.iter().map(|s| s.visibility.estimate()).collect();
    // The irradiance (all channels) and its variance, kept up to date as
    // sources are refined, and the unsettled sources by their variance.
    let (mut value, mut variance) = (0.0, 0.0);
    let mut unsettled = BinaryHeap::new();
    for (k, (source, &(visible, visible_variance))) in sources.iter().zip(&estimates).enumerate() {
        let w = weight(source);
        value += w * visible;
        variance += w * w * visible_variance;
        if !source.visibility.is_settled() {
            unsettled.push(VarianceShare(w * w * visible_variance, k));
        }
    }
    let mut rays = 0;
    while variance.max(0.0).sqrt() > PENUMBRA_RELATIVE_ERROR * value {
        // The unsettled source contributing most variance.
        let Some(VarianceShare(_, k)) = unsettled.pop() else {
            break;
        };
        let next = sources[k].visibility.next_rays();
        if rays + next > PENUMBRA_RAY_BUDGET {
            break;
        }
        let before = sources[k].visibility.rays;
        sources[k].visibility.refine();
        rays += sources[k].visibility.rays - before;
        let (old_visible, old_variance) = estimates[k];
        estimates[k] = sources[k].visibility.estimate();
        let w = weight(&sources[k]);
        value += w * (estimates[k].0 - old_visible);
        variance += w * w * (estimates[k].1 - old_variance);
        if !sources[k].visibility.is_settled() {
            unsettled.push(VarianceShare(w * w * estimates[k].1, k));
        }
    }
    estimates
}

/// A source's share of a gather's variance, ordered by that share (the
/// source's index breaks ties), for the refinement's priority queue.
#[derive(Clone, Copy, Debug)]
struct VarianceShare(f64, usize);

impl PartialEq for VarianceShare {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for VarianceShare {}

impl PartialOrd for VarianceShare {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for VarianceShare {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0).then(self.1.cmp(&other.1))
    }
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
    /// Irradiance per mesh vertex from the light shot, W/m²: the solver's.
    pub(crate) shot_irradiance: &'a VertexIrradiance,
    /// The ambient term G_v added to it (`solver/ambient/rays.rs`).
    pub(crate) ambient: AmbientIrradiance,
    /// The closed zone of every surface, when the solver found more than
    /// one: an image taken from inside a closed room draws that room alone.
    pub(crate) zones: Option<&'a crate::solver::zones::ZoneLabels>,
    /// How far each surface's boundary vertices gather inside it, by
    /// surface index (the scene's inset past its end).
    pub(crate) receiver_insets: &'a [f64],
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

    /// The final gather at a point of a surface: every element's mean
    /// radiosity times its exact form factor and its visible share, with
    /// partly hidden elements refined until the irradiance's standard error
    /// is under [`PENUMBRA_RELATIVE_ERROR`] of its value or the probe has cast
    /// [`PENUMBRA_RAY_BUDGET`] extra rays.
    fn gather(&self, position: DVec3, surface: SurfaceId) -> Probe {
        let s = self.scene.surface(surface);
        let material = self.scene.material_of(s);
        let x = self.gather_point(position, surface);
        let zone = self.gathered_zone(x, surface);
        let (irradiance, standard_error, gradient) =
            self.gather_irradiance((x, zone), s.normal(), surface, material.reflectance);
        Probe {
            position,
            surface,
            irradiance,
            standard_error,
            radiosity: material.emitted_radiosity() + material.reflectance * irradiance,
            gradient,
        }
    }

    /// The irradiance a gather finds at a point `x` in free space (a point
    /// of a work plane above a floor, say) on a small receiver facing the
    /// unit `normal`, W/m², with its standard error per channel: the light of
    /// every element in front of it, as [`Solution::probe`] gathers it on a
    /// surface, and of every photometric luminaire. NaN where the
    /// solution's ambient term was made for other rooms
    /// ([`Solution::holds_term_at`]).
    #[must_use]
    pub fn irradiance_in_space(&self, x: DVec3, normal: DVec3) -> (Rgb, Rgb) {
        // The room around the point, found once for the check and the
        // sources (64 rays).
        let zone = self.gathered_zone(x, SurfaceId::NONE);
        if !self.holds_term_in(zone) {
            return (Rgb::splat(f64::NAN), Rgb::splat(f64::NAN));
        }
        let (irradiance, standard_error, _) =
            self.gather_irradiance((x, zone), normal, SurfaceId::NONE, Rgb::ZERO);
        (irradiance, standard_error)
    }

    /// The gather's irradiance at `x` (unit `normal`) on `surface`
    /// ([`SurfaceId::NONE`] in free space), in closed zone `zone` if any
    /// ([`Solution::gathered_zone`]), its standard error, and the
    /// in-plane gradient of ρ H per channel for reflectance `reflectance`.
    fn gather_irradiance(
        &self,
        (x, zone): (DVec3, Option<usize>),
        normal: DVec3,
        surface: SurfaceId,
        reflectance: Rgb,
    ) -> (Rgb, Rgb, [DVec3; 3]) {
        let mut sources = self.gather_sources((x, zone), normal, surface);
        let visible = refine_penumbrae(&mut sources);
        let mut irradiance = Rgb::ZERO;
        let mut variance = Rgb::ZERO;
        let mut gradient = [DVec3::ZERO; 3];
        let reflectance = reflectance.to_array();
        for (source, (visible, visible_variance)) in sources.iter().zip(visible) {
            let light = source.radiosity * source.factor;
            irradiance += light * visible;
            variance += light * light * visible_variance;
            if visible <= 0.0 || reflectance == [0.0; 3] {
                continue;
            }
            let factor_gradient =
                polygon_form_factor_gradient(x, normal, source.visibility.cell().polygon());
            let in_plane = factor_gradient - normal * factor_gradient.dot(normal);
            let radiosity = source.radiosity.to_array();
            for (channel, g) in gradient.iter_mut().enumerate() {
                *g += in_plane * (radiosity[channel] * visible * reflectance[channel]);
            }
        }
        let (direct, direct_gradient) =
            self.luminaire_light(x, normal, surface, reflectance != [0.0; 3]);
        irradiance += direct;
        for (channel, g) in gradient.iter_mut().enumerate() {
            *g += direct_gradient[channel] * reflectance[channel];
        }
        let standard_error = Rgb::new(variance.r.sqrt(), variance.g.sqrt(), variance.b.sqrt());
        (irradiance, standard_error, gradient)
    }

    /// The direct irradiance the photometric luminaires that have shot give
    /// `x` on `surface` (unit `normal`), and (`with_gradient`) its in-plane
    /// gradient per channel by central differences over a ten-thousandth of the scene's
    /// diagonal (within that of a point light's sharp shadow edge the
    /// difference spans the jump: there the gradient is not defined).
    fn luminaire_light(
        &self,
        x: DVec3,
        normal: DVec3,
        surface: SurfaceId,
        with_gradient: bool,
    ) -> (Rgb, [DVec3; 3]) {
        let mut total = Rgb::ZERO;
        let mut gradient = [DVec3::ZERO; 3];
        let h = 1e-4 * self.visibility.diagonal();
        let u = normal.any_orthonormal_vector();
        let v = normal.cross(u);
        for (luminaire, _) in self
            .scene
            .luminaires
            .iter()
            .zip(&self.luminaires_shot)
            .filter(|(_, shot)| **shot)
        {
            let at = |p: DVec3| luminaire.irradiance_at(p, normal, surface, self.visibility);
            total += at(x);
            if !with_gradient {
                continue;
            }
            for axis in [u, v] {
                let slope = (at(x + axis * h) - at(x - axis * h)) / (2.0 * h);
                for (channel, g) in gradient.iter_mut().enumerate() {
                    *g += axis * slope.to_array()[channel];
                }
            }
        }
        (total, gradient)
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
    fn holds_term_in(&self, zone: Option<usize>) -> bool {
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

    /// The elements a gather at `x` facing `normal` on `surface`
    /// ([`SurfaceId::NONE`] in free space) sees in front of it, each with
    /// its unoccluded factor and its shadow rays' base strata; only closed
    /// zone `zone`'s where it lies in one ([`Solution::gathered_zone`]).
    fn gather_sources(
        &self,
        (x, zone): (DVec3, Option<usize>),
        normal: DVec3,
        surface: SurfaceId,
    ) -> Vec<GatherSource<'_>> {
        let in_zone = |source: SurfaceId| match (zone, self.zones) {
            (Some(zone), Some(zones)) => zones.of(source) == zone,
            _ => true,
        };
        // Jitter keyed by the point: deterministic and independent of the order of probes.
        let key = x.x.to_bits() ^ x.y.to_bits().rotate_left(21) ^ x.z.to_bits().rotate_left(42);
        let mut sources = Vec::new();
        // The shadow ray to each mesh vertex, cast once for all the elements
        // around it: 0 not yet cast, 1 none possible, 2 blocked, 3 unblocked.
        let mut vertex_witnesses = vec![0u8; self.mesh.vertices.len()];
        let offset = self.visibility.surface_offset();
        let mut vertex_witness = |v: u32| {
            let slot = &mut vertex_witnesses[v as usize];
            if *slot == 0 {
                let vertex = &self.mesh.vertices[v as usize];
                // The corner itself, a hair inside its surface: not where a
                // thin surface's vertex gathers, at its Gauss point.
                let y = vertex.position
                    + (vertex.receiver_position() - vertex.position)
                        .clamp_length_max(self.receiver_inset(vertex.surface));
                let source_normal = self.scene.surface(vertex.surface).normal();
                let d = y - x;
                *slot = if normal.dot(d) > 0.0 && source_normal.dot(d) < 0.0 {
                    let unblocked = self.visibility.is_unblocked(
                        x + normal * offset,
                        y + source_normal * offset,
                        [surface, vertex.surface],
                    );
                    2 + u8::from(unblocked)
                } else {
                    1
                };
            }
            match *slot {
                2 => Some(false),
                3 => Some(true),
                _ => None,
            }
        };
        for (index, element) in self.mesh.elements.iter().enumerate() {
            if element.surface == surface || !in_zone(element.surface) {
                continue;
            }
            let ids = element.corners();
            let mut corners = [DVec3::ZERO; 4];
            for (corner, &v) in corners.iter_mut().zip(ids) {
                *corner = self.mesh.vertices[v as usize].position;
            }
            let corners = &corners[..ids.len()];
            let source_normal = self.scene.surface(element.surface).normal();
            // One-sided: the element must face the point.
            if source_normal.dot(x - corners[0]) <= 0.0 {
                continue;
            }
            let factor = polygon_form_factor(x, normal, corners);
            if factor <= 0.0 {
                continue;
            }
            let cell = if corners.len() == 3 {
                Cell::triangle(corners[0], corners[1], corners[2])
            } else {
                Cell::quad(corners[0], corners[1], corners[2], corners[3])
            };
            // m × m base strata, m growing with the element's apparent size.
            let distance = (cell.centre() - x).length().max(f64::MIN_POSITIVE);
            let base = ((3.0 * cell.area.sqrt() / distance).ceil() as usize).clamp(2, 8);
            let visibility = AdaptiveVisibility::new(
                cell,
                (x, normal, surface),
                (source_normal, element.surface),
                base,
                {
                    let mut witnesses = [None; 4];
                    for (witness, &v) in witnesses.iter_mut().zip(ids) {
                        *witness = vertex_witness(v);
                    }
                    witnesses
                },
                self.visibility,
                SampleStream::new(key, index as u64),
            );
            sources.push(GatherSource {
                radiosity: element.corner_mean(|v| self.radiosity_at(v as usize)),
                factor,
                visibility,
            });
        }
        sources
    }

    /// How far `surface`'s boundary vertices gather inside it: its room's
    /// inset, or the scene's for a mesh the caller brought.
    fn receiver_inset(&self, surface: SurfaceId) -> f64 {
        let own = self.receiver_insets.get(surface.index()).copied();
        own.unwrap_or_else(|| receiver_inset(self.scene))
    }

    /// Where a probe on a surface gathers: the point itself, moved inside its
    /// polygon when it is on (or within the inset of) the polygon's edge, as
    /// mesh vertices are.
    fn gather_point(&self, position: DVec3, surface: SurfaceId) -> DVec3 {
        let s = self.scene.surface(surface);
        let inset = self.receiver_inset(surface);
        let plane_vertices = s.plane_vertices();
        let p = s.frame().to_plane(position);
        let on_plane = s.frame().to_world(p);
        if distance_inside_polygon(p, &plane_vertices) >= inset {
            return on_plane;
        }
        let centroid = plane_vertices.iter().copied().sum::<DVec2>() / plane_vertices.len() as f64;
        let towards = (centroid - p).normalize_or_zero();
        s.frame().to_world(p + towards * inset)
    }

    /// The mesh's piecewise-linear value at a point of a surface, split into
    /// triangles as the renderer splits it. A point that no element covers
    /// lies where meshing dropped the surface as hidden (under a block
    /// standing on it, behind a book a millimetre away,
    /// `mesh/contacts.rs`): no light reaches it, and the renderer shows
    /// none of it, so it gets no irradiance and only its own emission.
    fn interpolate(&self, position: DVec3, surface: SurfaceId) -> Probe {
        let normal = self.scene.surface(surface).normal();
        let frame = self.scene.surface(surface).frame();
        let at = frame.to_plane(position);
        let hidden = Probe {
            position,
            surface,
            irradiance: Rgb::ZERO,
            standard_error: Rgb::ZERO,
            radiosity: self
                .scene
                .material_of(self.scene.surface(surface))
                .emitted_radiosity(),
            gradient: [DVec3::ZERO; 3],
        };
        let radiosity = |v: u32| self.radiosity_at(v as usize);
        let gap = |p: u32, q: u32| (radiosity(p) - radiosity(q)).abs().element_sum();
        let mut best: Option<(f64, [u32; 3], [f64; 3])> = None;
        let mut split = Vec::new();
        for element in self.mesh.elements.iter().filter(|e| e.surface == surface) {
            self.mesh.element_triangles(element, gap, &mut split);
            for &triangle in &split {
                let [a, b, c] = triangle.map(|v| self.mesh.vertices[v as usize].position);
                let weights = barycentric(position, a, b, c, normal);
                // How far outside the triangle (0 inside).
                let corners = [a, b, c].map(|q| frame.to_plane(q));
                let outside = distance_outside_triangle(at, corners, weights);
                if best.is_none_or(|(o, _, _)| outside < o) {
                    best = Some((outside, triangle, weights));
                }
            }
        }
        // Farther from every element than a point may be from its surface
        // (`Solution::locate`'s tolerance): in a dropped part.
        let covered = 1e-4 * self.scene.diagonal();
        let Some((_, triangle, weights)) = best.filter(|&(outside, _, _)| outside <= covered)
        else {
            return hidden;
        };
        let weights = weights.map(|w| w.max(0.0));
        let total: f64 = weights.iter().sum();
        let value = |at: &dyn Fn(u32) -> Rgb| {
            (0..3)
                .map(|k| at(triangle[k]) * (weights[k] / total))
                .sum::<Rgb>()
        };
        let [a, b, c] = triangle.map(|v| self.mesh.vertices[v as usize].position);
        let gradients = barycentric_gradients(a, b, c, normal);
        let gradient = [0, 1, 2].map(|channel| {
            (0..3)
                .map(|k| gradients[k] * radiosity(triangle[k]).to_array()[channel])
                .sum()
        });
        Probe {
            position,
            surface,
            irradiance: value(&|v| self.irradiance_at(v as usize)),
            standard_error: Rgb::ZERO,
            radiosity: value(&radiosity),
            gradient,
        }
    }
}

/// The distance from `p` to the triangle `corners` (plane coordinates), 0
/// inside it, given `p`'s barycentric `weights` there: the distance to the
/// nearest of its sides when a weight is negative. Infinite for weights a
/// degenerate triangle leaves undefined: it covers nothing.
fn distance_outside_triangle(p: DVec2, corners: [DVec2; 3], weights: [f64; 3]) -> f64 {
    if !weights.iter().all(|w| w.is_finite()) {
        return f64::INFINITY;
    }
    if weights.iter().all(|&w| w >= 0.0) {
        return 0.0;
    }
    (0..3)
        .map(|k| distance_to_segment(p, corners[k], corners[(k + 1) % 3]))
        .fold(f64::INFINITY, f64::min)
}

/// Barycentric weights of `p` (projected onto the triangle's plane) in the
/// triangle (a, b, c) whose front normal is `normal`.
fn barycentric(p: DVec3, a: DVec3, b: DVec3, c: DVec3, normal: DVec3) -> [f64; 3] {
    let twice_area = (b - a).cross(c - a).dot(normal);
    if twice_area.abs() <= f64::MIN_POSITIVE {
        return [-f64::INFINITY; 3];
    }
    let wa = (c - b).cross(p - b).dot(normal) / twice_area;
    let wb = (a - c).cross(p - c).dot(normal) / twice_area;
    [wa, wb, 1.0 - wa - wb]
}

/// Gradients of the barycentric coordinates of a counter-clockwise triangle:
/// ∇λ_a = n × (c − b) / (2A), and cyclically.
fn barycentric_gradients(a: DVec3, b: DVec3, c: DVec3, normal: DVec3) -> [DVec3; 3] {
    let twice_area = (b - a).cross(c - a).dot(normal);
    if twice_area.abs() <= f64::MIN_POSITIVE {
        return [DVec3::ZERO; 3];
    }
    [
        normal.cross(c - b) / twice_area,
        normal.cross(a - c) / twice_area,
        normal.cross(b - a) / twice_area,
    ]
}

/// Distance from a point inside a polygon to its boundary (0 when outside).
fn distance_inside_polygon(p: DVec2, polygon: &[DVec2]) -> f64 {
    if polygon_contains(polygon, p) {
        distance_to_boundary(polygon, p)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SLIVER: [DVec2; 3] = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(1.0, 0.01),
    ];

    /// The weights of `p` in the sliver, through the 3-D barycentric.
    fn weights(p: DVec2) -> [f64; 3] {
        let lift = |q: DVec2| DVec3::new(q.x, q.y, 0.0);
        let [a, b, c] = SLIVER.map(lift);
        barycentric(lift(p), a, b, c, DVec3::Z)
    }

    #[test]
    fn the_distance_outside_a_triangle_is_to_its_nearest_side() {
        let inside = DVec2::new(0.9, 0.005);
        assert_eq!(
            distance_outside_triangle(inside, SLIVER, weights(inside)),
            0.0
        );
        // Beyond the sharp corner at the origin: a unit from it, where the
        // sides' lines are a hundredth away.
        let beyond = DVec2::new(-1.0, 0.005);
        let d = distance_outside_triangle(beyond, SLIVER, weights(beyond));
        assert!((d - 1.0).abs() < 1e-4, "{d}");
        let below = DVec2::new(0.5, -0.25);
        let d = distance_outside_triangle(below, SLIVER, weights(below));
        assert!((d - 0.25).abs() < 1e-12, "{d}");
    }

    #[test]
    fn a_degenerate_triangle_covers_nothing() {
        let flat = [DVec2::ZERO, DVec2::X, 2.0 * DVec2::X];
        let lift = |q: DVec2| DVec3::new(q.x, q.y, 0.0);
        let [a, b, c] = flat.map(lift);
        let p = DVec2::new(0.5, 0.0);
        let w = barycentric(lift(p), a, b, c, DVec3::Z);
        assert_eq!(distance_outside_triangle(p, flat, w), f64::INFINITY);
    }
}
