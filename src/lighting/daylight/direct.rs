//! Direct daylight at a point: the sky and the ground through the portals,
//! the rest of the sky by hemisphere rays, and the sun.
//!
//! The irradiance of a point x of unit normal n from the sky is
//!
//! ```text
//! E = ∫ L(ω) T(x, ω) cos θ dω
//! ```
//!
//! with L the sky's (or, below the horizon, the ground's) radiance and T
//! the transmittance to it (1 through air, τ(θ) per pane, 0 when blocked).
//! The directions split three ways ([`super::portals`]):
//! - through a portal: each portal triangle is cut into k² triangles, k
//!   growing as its size over its distance; each contributes
//!   π F L(ω_c) T(x, ω_c), with F its exact (Lambert) form factor and ω_c
//!   toward its centroid. Unobstructed, that is exact to the variation of L
//!   over one small triangle.
//! - through no portal: 64 stratified cosine-weighted rays estimate
//!   E_rest = ∫ L c cos dω, c = T when no portal is crossed, else 0; where
//!   most rays reach the sky, as the complement
//!   E_unobstructed(n) − ∫ L (1 − c) cos dω, exact in the open.
//! - the sun: E_n cos θ T averaged over 16 points of its 0.53° disc.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::RwLock;

use glam::DVec3;

use crate::daylight::{Daylight, SUN_DIAMETER_DEG, SkyRadiance};
use crate::lighting::SampleStream;
use crate::lighting::cosine_direction_at;
use crate::radiometry::polygon_form_factor;
use crate::scene::{Scene, SurfaceId, Visibility};

use super::portals::Portals;
use super::transmission::sky_transmittance;

/// Hemisphere rays for the sky no portal shows: an 8 × 8 stratification.
const REST_STRATA: usize = 8;
/// Points on the sun's disc: a 4 × 4 stratification.
const SUN_STRATA: usize = 4;
/// The streams' second seeds: the rest-of-sky rays', the sun's.
const REST_SEED: u64 = 0x736b_7921;
const SUN_SEED: u64 = 0x7375_6e21;
/// The most subdivisions of a portal triangle's side.
const MAX_SPLITS: usize = 32;

/// What a point on a surface, or in free space, gathers daylight as.
#[derive(Clone, Copy, Debug)]
pub struct DaylightReceiver {
    /// The point.
    pub position: DVec3,
    /// Its unit normal.
    pub normal: DVec3,
    /// Its surface ([`SurfaceId::NONE`] in free space), which rays ignore.
    pub surface: SurfaceId,
    /// A key for its jitter (the vertex index).
    pub key: u64,
}

/// A scene's daylight, ready to light points.
#[derive(Debug)]
pub struct DaylightSource {
    daylight: Daylight,
    radiance: SkyRadiance,
    portals: Portals,
    /// E_unobstructed per normal, W/m²: the complement's start.
    unobstructed: RwLock<HashMap<[u64; 3], f64>>,
}

impl DaylightSource {
    /// The daylight of `scene` with its portals, if it has any daylight.
    #[must_use]
    pub fn of_scene(scene: &Scene) -> Option<DaylightSource> {
        let daylight = scene.daylight.clone()?;
        Some(DaylightSource::new(daylight, Portals::of_scene(scene)))
    }

    /// `daylight` through `portals`.
    #[must_use]
    pub fn new(daylight: Daylight, portals: Portals) -> DaylightSource {
        DaylightSource {
            radiance: daylight.radiance(),
            daylight,
            portals,
            unobstructed: RwLock::new(HashMap::new()),
        }
    }

    /// The daylight.
    #[must_use]
    pub fn daylight(&self) -> &Daylight {
        &self.daylight
    }

    /// The portals.
    #[must_use]
    pub fn portals(&self) -> &Portals {
        &self.portals
    }

    /// The direct irradiance (W/m², grey) at `at` from the sky, the ground
    /// and the sun; the shadow rays it cast are added to `rays`.
    #[must_use]
    pub fn irradiance_at(
        &self,
        scene: &Scene,
        visibility: &Visibility,
        at: &DaylightReceiver,
        rays: &mut u64,
    ) -> f64 {
        self.through_portals(scene, visibility, at, rays)
            + self.rest_of_sky(scene, visibility, at, rays)
            + self.sun_irradiance(scene, visibility, at, rays)
    }

    /// The sky and ground through the portals.
    fn through_portals(
        &self,
        scene: &Scene,
        visibility: &Visibility,
        at: &DaylightReceiver,
        rays: &mut u64,
    ) -> f64 {
        let (x, n) = (at.position, at.normal);
        let mut irradiance = 0.0;
        for (index, portal) in self.portals.portals.iter().enumerate() {
            for triangle in &portal.triangles {
                if triangle.iter().all(|&c| (c - x).dot(n) <= 0.0) {
                    continue;
                }
                let centroid = (triangle[0] + triangle[1] + triangle[2]) / 3.0;
                let size = (triangle[1] - triangle[0])
                    .cross(triangle[2] - triangle[0])
                    .length()
                    .sqrt();
                let distance = (centroid - x).length().max(1e-12);
                let splits = ((16.0 * size / distance).ceil() as usize).clamp(4, MAX_SPLITS);
                for piece in split_triangle(triangle, splits) {
                    let factor = polygon_form_factor(x, n, &piece);
                    if factor <= 0.0 {
                        continue;
                    }
                    let middle = (piece[0] + piece[1] + piece[2]) / 3.0;
                    let Some(direction) = (middle - x).try_normalize() else {
                        continue;
                    };
                    if direction.dot(n) <= 0.0 {
                        continue;
                    }
                    // Counted by the first portal the ray crosses.
                    if self
                        .portals
                        .first_crossed(x, direction)
                        .is_some_and(|(first, _)| first != index)
                    {
                        continue;
                    }
                    *rays += 1;
                    let t = sky_transmittance(scene, visibility, x, direction, at.surface);
                    if t > 0.0 {
                        irradiance += PI * factor * self.radiance.toward(direction) * t;
                    }
                }
            }
        }
        irradiance
    }

    /// The sky no portal shows, by stratified cosine-weighted rays.
    fn rest_of_sky(
        &self,
        scene: &Scene,
        visibility: &Visibility,
        at: &DaylightReceiver,
        rays: &mut u64,
    ) -> f64 {
        let (x, n) = (at.position, at.normal);
        let mut random = SampleStream::new(at.key, REST_SEED);
        let count = REST_STRATA * REST_STRATA;
        let (mut seen, mut unseen, mut reached) = (0.0, 0.0, 0usize);
        for i in 0..REST_STRATA {
            for j in 0..REST_STRATA {
                let u1 = (i as f64 + random.next_f64()) / REST_STRATA as f64;
                let u2 = (j as f64 + random.next_f64()) / REST_STRATA as f64;
                let direction = cosine_direction_at(n, u1, u2);
                let radiance = self.radiance.toward(direction);
                let c = if self.portals.first_crossed(x, direction).is_some() {
                    0.0
                } else {
                    *rays += 1;
                    sky_transmittance(scene, visibility, x, direction, at.surface)
                };
                if c > 0.0 {
                    reached += 1;
                }
                seen += radiance * c;
                unseen += radiance * (1.0 - c);
            }
        }
        // ∫ L cos dω ≈ (π / N) Σ L for cosine-weighted directions.
        let scale = PI / count as f64;
        if 2 * reached > count {
            (self.unobstructed(n) - scale * unseen).max(0.0)
        } else {
            scale * seen
        }
    }

    /// The sun's direct irradiance (W/m²) at `at`: E_n cos θ times the
    /// transmittance toward 16 stratified points of its disc; 0 without a
    /// shining sun.
    #[must_use]
    pub fn sun_irradiance(
        &self,
        scene: &Scene,
        visibility: &Visibility,
        at: &DaylightReceiver,
        rays: &mut u64,
    ) -> f64 {
        let Some(centre) = self.daylight.sun_direction() else {
            return 0.0;
        };
        let cos_theta = centre.dot(at.normal);
        if cos_theta <= 0.0 {
            return 0.0;
        }
        let radius = (SUN_DIAMETER_DEG / 2.0).to_radians();
        let tangent = centre.any_orthonormal_vector();
        let bitangent = centre.cross(tangent);
        let mut random = SampleStream::new(at.key, SUN_SEED);
        let mut sum = 0.0;
        for i in 0..SUN_STRATA {
            for j in 0..SUN_STRATA {
                // A uniform point of the disc, stratified in (r², angle).
                let r = radius * ((i as f64 + random.next_f64()) / SUN_STRATA as f64).sqrt();
                let angle =
                    std::f64::consts::TAU * (j as f64 + random.next_f64()) / SUN_STRATA as f64;
                let direction =
                    (centre + (tangent * angle.cos() + bitangent * angle.sin()) * r).normalize();
                sum += sky_transmittance(scene, visibility, at.position, direction, at.surface);
            }
        }
        let count = SUN_STRATA * SUN_STRATA;
        *rays += count as u64;
        self.daylight.sun_normal_irradiance() * cos_theta * sum / count as f64
    }

    /// E_unobstructed(n), W/m², computed once per normal.
    fn unobstructed(&self, normal: DVec3) -> f64 {
        let key = normal.to_array().map(f64::to_bits);
        if let Some(value) = self
            .unobstructed
            .read()
            .ok()
            .and_then(|m| m.get(&key).copied())
        {
            return value;
        }
        let value = self.daylight.unobstructed_irradiance(normal);
        if let Ok(mut map) = self.unobstructed.write() {
            map.insert(key, value);
        }
        value
    }
}

/// Triangle `t` cut into `k²` congruent triangles (k per side).
fn split_triangle(t: &[DVec3; 3], k: usize) -> Vec<[DVec3; 3]> {
    let (a, e1, e2) = (t[0], (t[1] - t[0]) / k as f64, (t[2] - t[0]) / k as f64);
    let at = |i: usize, j: usize| a + e1 * i as f64 + e2 * j as f64;
    let mut pieces = Vec::with_capacity(k * k);
    for i in 0..k {
        for j in 0..k - i {
            pieces.push([at(i, j), at(i + 1, j), at(i, j + 1)]);
            if i + j + 1 < k {
                pieces.push([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_triangles_tile_the_triangle() {
        let t = [DVec3::ZERO, DVec3::X * 2.0, DVec3::new(0.5, 1.5, 0.0)];
        let area = |t: &[DVec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]).length() / 2.0;
        for k in 1..6 {
            let pieces = split_triangle(&t, k);
            assert_eq!(pieces.len(), k * k);
            let sum: f64 = pieces.iter().map(area).sum();
            assert!((sum - area(&t)).abs() < 1e-12);
        }
    }
}
