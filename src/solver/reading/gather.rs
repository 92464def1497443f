//! The final gather: a probe's irradiance at a point of a surface or in
//! space, from every element in front of it with Lambert's exact form
//! factor and its visible share, partly hidden elements refined until the
//! estimate's standard error is small ([`PENUMBRA_RAY_BUDGET`]), plus the
//! photometric luminaires' direct light.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::{DVec2, DVec3};

use crate::lighting::{DaylightReceiver, SampleStream};
use crate::mesh::Cell;
use crate::radiometry::{polygon_form_factor, polygon_form_factor_gradient};
use crate::rgb::Rgb;
use crate::scene::{SurfaceId, distance_to_boundary, polygon_contains};
use crate::solver::reading::penumbra::{AdaptiveVisibility, GatherPoint, SourceElement};
use crate::solver::reading::solution::{Probe, Solution};

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

/// The shadow rays from a gather's point to the mesh's vertices, each
/// cast once for all the elements around it.
struct VertexWitnesses<'s, 'a> {
    solution: &'s Solution<'a>,
    at: GatherPoint,
    offset: f64,
    /// Per vertex: 0 not yet cast, 1 none possible, 2 blocked, 3 unblocked.
    slots: Vec<u8>,
}

impl<'s, 'a> VertexWitnesses<'s, 'a> {
    /// None cast yet, from `at`.
    fn new(solution: &'s Solution<'a>, at: GatherPoint) -> Self {
        VertexWitnesses {
            solution,
            at,
            offset: solution.visibility.surface_offset(),
            slots: vec![0u8; solution.mesh.vertices.len()],
        }
    }

    /// Whether the shadow ray to vertex `v` is unblocked, cast on first
    /// use; none where no ray could be cast (either side facing away).
    fn of(&mut self, v: u32) -> Option<bool> {
        let GatherPoint {
            position: x,
            normal,
            surface,
        } = self.at;
        let (solution, offset) = (self.solution, self.offset);
        let slot = &mut self.slots[v as usize];
        if *slot == 0 {
            let vertex = &solution.mesh.vertices[v as usize];
            // The corner itself, a hair inside its surface: not where a
            // thin surface's vertex gathers, at its Gauss point.
            let y = vertex.position
                + (vertex.receiver_position() - vertex.position)
                    .clamp_length_max(solution.receiver_inset(vertex.surface));
            let source_normal = solution.scene.surface(vertex.surface).normal();
            let d = y - x;
            *slot = if normal.dot(d) > 0.0 && source_normal.dot(d) < 0.0 {
                let unblocked = solution.visibility.is_unblocked(
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
    }
}

impl Solution<'_> {
    /// The final gather at a point of a surface: every element's mean
    /// radiosity times its exact form factor and its visible share, with
    /// partly hidden elements refined until the irradiance's standard error
    /// is under [`PENUMBRA_RELATIVE_ERROR`] of its value or the probe has cast
    /// [`PENUMBRA_RAY_BUDGET`] extra rays.
    pub(super) fn gather(&self, position: DVec3, surface: SurfaceId) -> Probe {
        let s = self.scene.surface(surface);
        let material = self.scene.material_of(s);
        let x = self.gather_point(position, surface);
        let zone = self.gathered_zone(x, surface);
        let (irradiance, standard_error, gradient) =
            self.gather_irradiance(x, zone, s.normal(), surface, material.reflectance);
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
            self.gather_irradiance(x, zone, normal, SurfaceId::NONE, Rgb::ZERO);
        (irradiance, standard_error)
    }

    /// The gather's irradiance at `x` (unit `normal`) on `surface`
    /// ([`SurfaceId::NONE`] in free space), in closed zone `zone` if any
    /// ([`Solution::gathered_zone`]), its standard error, and the
    /// in-plane gradient of ρ H per channel for reflectance `reflectance`.
    fn gather_irradiance(
        &self,
        x: DVec3,
        zone: Option<usize>,
        normal: DVec3,
        surface: SurfaceId,
        reflectance: Rgb,
    ) -> (Rgb, Rgb, [DVec3; 3]) {
        let mut sources = self.gather_sources(x, zone, normal, surface);
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
        irradiance += direct + self.daylight_light(x, normal, surface);
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

    /// The direct daylight at `x` on `surface` (unit `normal`), when the
    /// solution holds the daylight's light; its gradient is left out of
    /// the gather's (the sky changes slowly; the sun's penumbra is the
    /// mesh's to follow).
    fn daylight_light(&self, x: DVec3, normal: DVec3, surface: SurfaceId) -> Rgb {
        let Some(source) = self.daylight else {
            return Rgb::ZERO;
        };
        let receiver = DaylightReceiver {
            position: x,
            normal,
            surface,
            key: x.x.to_bits() ^ x.y.to_bits().rotate_left(21) ^ x.z.to_bits().rotate_left(42),
        };
        let mut rays = 0;
        Rgb::splat(source.irradiance_at(self.scene, self.visibility, &receiver, &mut rays))
    }

    /// The elements a gather at `x` facing `normal` on `surface`
    /// ([`SurfaceId::NONE`] in free space) sees in front of it, each with
    /// its unoccluded factor and its shadow rays' base strata; only closed
    /// zone `zone`'s where it lies in one ([`Solution::gathered_zone`]).
    fn gather_sources(
        &self,
        x: DVec3,
        zone: Option<usize>,
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
        let at = GatherPoint {
            position: x,
            normal,
            surface,
        };
        let mut vertex_witnesses = VertexWitnesses::new(self, at);
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
            let source = SourceElement {
                cell,
                normal: source_normal,
                surface: element.surface,
            };
            let visibility = AdaptiveVisibility::new(
                source,
                at,
                base,
                {
                    let mut witnesses = [None; 4];
                    for (witness, &v) in witnesses.iter_mut().zip(ids) {
                        *witness = vertex_witnesses.of(v);
                    }
                    witnesses
                },
                self.visibility,
                SampleStream::new(key, index as u64),
            );
            // An emitting body's emission comes from its luminaire.
            let mut radiosity = element.corner_mean(|v| self.radiosity_at(v as usize));
            if self.in_emitting_body[element.surface.index()] {
                let material = self.scene.material_of(self.scene.surface(element.surface));
                radiosity = radiosity - material.emitted_radiosity();
            }
            sources.push(GatherSource {
                radiosity,
                factor,
                visibility,
            });
        }
        sources
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
    use crate::phase::silent;
    use crate::scene::ProbePoint;
    use crate::solver::Ambient;
    use crate::solver::reading::request::solution_from;
    use crate::solver::test_scenes::two_closed_rooms;
    use crate::solver::{ProbeMode, Settings, Solver};

    /// A gather inside a closed room, on its floor or in its air, tries
    /// that room's elements alone, and reads what a gather over every
    /// element of the building reads: the other room's are all hidden.
    #[test]
    fn a_gather_in_a_closed_room_reads_what_one_over_every_element_reads() {
        let mut settings = Settings::default();
        settings.mesh.max_edge = crate::Length::Absolute(0.5);
        let mut solver = Solver::new(two_closed_rooms(), settings).expect("a valid scene");
        solver.run();
        let zoned = solver.solution(Ambient::Everywhere, &silent);
        assert!(zoned.zones.is_some());
        let mut everywhere = solution_from(&solver.ambient_term(), zoned.ambient.clone());
        everywhere.zones = None;
        for x in [0.0, 5.0] {
            let floor = ProbePoint {
                position: DVec3::new(x + 3.1, 0.0, 0.6),
                normal: Some(DVec3::Y),
                line: 1,
            };
            // Each gather finds its room, the floor's and the air's alike.
            let air = DVec3::new(x + 0.6, 1.5, 3.2);
            let room = zoned.gathered_zone(air, SurfaceId::NONE);
            assert!(room.is_some());
            let on_floor = zoned.probe(&floor, ProbeMode::Mesh);
            let surface = on_floor.expect("a point on the floor").surface;
            assert_eq!(zoned.gathered_zone(floor.position, surface), room);
            let [a, b] = [&zoned, &everywhere].map(|solution| {
                let probe = solution.probe(&floor, ProbeMode::Gather);
                probe.expect("a point on the floor").irradiance
            });
            assert!(
                a.g > 0.0 && (a.g - b.g).abs() <= 1e-9 * b.g,
                "{a:?} against {b:?}"
            );
            let [a, b] = [&zoned, &everywhere].map(|s| s.irradiance_in_space(air, DVec3::X).0);
            assert!(
                a.g > 0.0 && (a.g - b.g).abs() <= 1e-9 * b.g,
                "{a:?} against {b:?}"
            );
        }
    }
}
