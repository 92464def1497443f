//! The daylight's shot: the irradiance the sky, the ground and the sun give
//! each vertex through the portals.

use rayon::prelude::*;

use crate::lighting::DaylightReceiver;
use crate::rgb::Rgb;
use crate::solver::shot::context::ShotContext;

impl ShotContext<'_> {
    /// The direct daylight at each of `vertices` (grey, W/m²), in parallel,
    /// with the shadow rays cast; nothing without daylight.
    pub(crate) fn daylight_light(&self, vertices: &[u32]) -> (Vec<Rgb>, u64) {
        let Some(source) = &self.layout.daylight else {
            return (vec![Rgb::ZERO; vertices.len()], 0);
        };
        let (scene, mesh, visibility) = (self.scene, self.mesh, self.visibility);
        let lit: Vec<(f64, u64)> = vertices
            .par_iter()
            .map(|&v| {
                let vertex = &mesh.vertices[v as usize];
                let receiver = DaylightReceiver {
                    position: vertex.receiver_position(),
                    normal: scene.surface(vertex.surface).normal(),
                    surface: vertex.surface,
                    key: u64::from(v),
                };
                let mut rays = 0;
                let irradiance = source.irradiance_at(scene, visibility, &receiver, &mut rays);
                (irradiance, rays)
            })
            .collect();
        let rays = lit.iter().map(|l| l.1).sum();
        (lit.into_iter().map(|l| Rgb::splat(l.0)).collect(), rays)
    }
}
