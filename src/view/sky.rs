//! The sky in a render: seen where no surface is, and through glazing.
//!
//! The rasterizer knows only triangles. Drawn twice, over a black and over
//! a white background, a pixel's difference is the share of it no triangle
//! covers (its samples average linearly); that share shows the sky or the
//! ground toward the pixel. A pixel whose centre ray meets a glazing pane
//! first shows, besides the pane's own reflection, the sky behind it times
//! the pane's transmittance at that incidence and whatever else the ray
//! crosses beyond ([`sky_transmittance`]).

use rayon::prelude::*;

use crate::daylight::{Daylight, pane_transmittance};
use crate::lighting::sky_transmittance;
use crate::render::{Image, RenderSettings, ShadedTriangle, rasterize};
use crate::rgb::Rgb;
use crate::scene::{Camera, SurfaceId};
use crate::solver::Solution;

use super::pixel_rays::PixelRays;

impl Solution<'_> {
    /// `triangles` rendered through `camera` under `daylight`: the sky
    /// where no triangle is, and behind glazing.
    pub(crate) fn render_daylit(
        &self,
        triangles: &[ShadedTriangle],
        camera: &Camera,
        settings: &RenderSettings,
        daylight: &Daylight,
    ) -> Image {
        let black = rasterize(
            triangles,
            camera,
            &settings.clone().with_background(Rgb::ZERO),
        );
        let white = rasterize(
            triangles,
            camera,
            &settings.clone().with_background(Rgb::ONE),
        );
        let (width, height) = (camera.width, camera.height);
        let sky_radiance = daylight.radiance();
        let rays = PixelRays::new(camera, self.scene, self.visibility);
        let pixels: Vec<[f32; 3]> = (0..rays.count())
            .into_par_iter()
            .map(|index| {
                let direction = rays.direction(index);
                let (b, w) = (black.pixels()[index], white.pixels()[index]);
                let open = ((w[0] - b[0] + w[1] - b[1] + w[2] - b[2]) / 3.0).clamp(0.0, 1.0);
                let mut sky = f64::from(open) * sky_radiance.toward(direction);
                let hit = self.visibility.closest_hit(
                    camera.position,
                    direction,
                    rays.reach,
                    SurfaceId::NONE,
                );
                if let Some((surface, distance)) = hit {
                    let pane = self.scene.surface(surface);
                    let material = self.scene.material_of(pane);
                    if material.is_glazing() {
                        let cos_theta = pane.normal().dot(direction).abs();
                        let from = camera.position + direction * distance;
                        let beyond = sky_transmittance(
                            self.scene,
                            self.visibility,
                            from,
                            direction,
                            surface,
                        );
                        let tau = pane_transmittance(material.transmittance, cos_theta);
                        sky += tau * beyond * sky_radiance.toward(direction);
                    }
                }
                [b[0] + sky as f32, b[1] + sky as f32, b[2] + sky as f32]
            })
            .collect();
        Image::from_pixels(width, height, pixels).unwrap_or(black)
    }
}
