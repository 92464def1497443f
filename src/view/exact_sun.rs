//! The sun exact in a render. A sun patch's edge falls across elements,
//! and Gouraud shading spreads it over one: where the interpolated
//! sunlight is neither none nor all of what the surface would get in full
//! sun, the pixel's own point is lit by the sun instead, E_n cos θ times
//! the transmittance toward 16 points of its disc, so the patch's edge and
//! penumbra are where its geometry puts them on any mesh.

use rayon::prelude::*;

use crate::lighting::{DaylightReceiver, DaylightSource};
use crate::render::{Image, RenderSettings, ShadedTriangle, rasterize};
use crate::rgb::Rgb;
use crate::scene::{Camera, SurfaceId};
use crate::solver::Solution;

use super::pixel_rays::PixelRays;

/// The share of full sun under which, or over 1 − it above which, the
/// interpolated sunlight is taken as exact.
const SETTLED: f64 = 1e-3;

impl Solution<'_> {
    /// `image` (of the triangles `indices`, as [`Solution::render`] drew
    /// them) with the sun's light computed at each pixel where the mesh
    /// interpolates across its edge.
    pub(crate) fn with_exact_sun(
        &self,
        image: Image,
        indices: &[[u32; 3]],
        camera: &Camera,
        settings: &RenderSettings,
        source: &DaylightSource,
    ) -> Image {
        let daylight = source.daylight();
        let Some(sun) = daylight.sun_direction() else {
            return image;
        };
        // The sunlight each vertex reflects, L = ρ E_sun / π, drawn as the
        // image's triangles are.
        let vertex_sun = |v: u32| {
            let vertex = &self.mesh.vertices[v as usize];
            let surface = self.scene.surface(vertex.surface);
            let at = DaylightReceiver {
                position: vertex.receiver_position(),
                normal: surface.normal(),
                surface: vertex.surface,
                key: u64::from(v),
            };
            let e = source.sun_irradiance(self.scene, self.visibility, &at, &mut 0);
            self.scene.material_of(surface).reflectance * (e / std::f64::consts::PI)
        };
        let triangles: Vec<ShadedTriangle> = indices
            .par_iter()
            .map(|&[a, b, c]| ShadedTriangle {
                positions: [a, b, c].map(|v| self.mesh.vertices[v as usize].position),
                radiance: [vertex_sun(a), vertex_sun(b), vertex_sun(c)],
            })
            .collect();
        let interpolated = rasterize(
            &triangles,
            camera,
            &settings.clone().with_background(Rgb::ZERO),
        );
        let (width, height) = (camera.width, camera.height);
        let rays = PixelRays::new(camera, self.scene, self.visibility);
        let full_sun = daylight.sun_normal_irradiance() / std::f64::consts::PI;
        let pixels: Vec<[f32; 3]> = (0..rays.count())
            .into_par_iter()
            .map(|index| {
                let pixel = image.pixels()[index];
                let direction = rays.direction(index);
                let Some((id, distance)) = self.visibility.closest_hit(
                    camera.position,
                    direction,
                    rays.reach,
                    SurfaceId::NONE,
                ) else {
                    return pixel;
                };
                let surface = self.scene.surface(id);
                let material = self.scene.material_of(surface);
                let cos_theta = surface.normal().dot(sun);
                let seen_front = surface.normal().dot(direction) < 0.0;
                if material.is_glazing() || !seen_front || cos_theta <= 0.0 {
                    return pixel;
                }
                let full = material.reflectance * (full_sun * cos_theta);
                let drawn = interpolated.pixels()[index];
                let drawn_sun = Rgb::new(
                    f64::from(drawn[0]),
                    f64::from(drawn[1]),
                    f64::from(drawn[2]),
                );
                let share = drawn_sun.luminance() / full.luminance().max(f64::MIN_POSITIVE);
                if !(SETTLED..1.0 - SETTLED).contains(&share) {
                    return pixel;
                }
                let at = DaylightReceiver {
                    position: camera.position + direction * distance,
                    normal: surface.normal(),
                    surface: id,
                    key: index as u64,
                };
                let e = source.sun_irradiance(self.scene, self.visibility, &at, &mut 0);
                let exact = material.reflectance * (e / std::f64::consts::PI);
                let exact = exact.to_array();
                std::array::from_fn(|c| (pixel[c] - drawn[c] + exact[c] as f32).max(0.0))
            })
            .collect();
        Image::from_pixels(width, height, pixels).unwrap_or(image)
    }
}
