//! A photometric luminaire's shot: the irradiance it gives each vertex, with
//! one shadow ray from its photometric centre.

use rayon::prelude::*;

use crate::rgb::Rgb;
use crate::solver::layout::CulledZones;
use crate::solver::shot::context::ShotContext;

impl ShotContext<'_> {
    /// The irradiance photometric luminaire `k` gives each of `vertices`,
    /// E = I(ω) cos θ / r², in parallel: none, without rays, outside its
    /// closed zone, whose BVH the rays traverse.
    pub(crate) fn luminaire_light(&self, k: usize, vertices: &[u32]) -> Vec<Rgb> {
        let (scene, mesh) = (self.scene, self.mesh);
        let zone = self.layout.luminaire_zones[k].zip(
            self.layout
                .zones
                .as_ref()
                .map(|CulledZones { zones, .. }| zones),
        );
        let visibility = zone
            .and_then(|(zone, zones)| zones.visibility(zone))
            .unwrap_or(self.visibility);
        let luminaire = &scene.luminaires[k];
        vertices
            .par_iter()
            .map(|&v| {
                let vertex = &mesh.vertices[v as usize];
                if zone.is_some_and(|(zone, zones)| zones.of(vertex.surface) != zone) {
                    return Rgb::ZERO;
                }
                let normal = scene.surface(vertex.surface).normal();
                luminaire.irradiance_at(
                    vertex.receiver_position(),
                    normal,
                    vertex.surface,
                    visibility,
                )
            })
            .collect()
    }
}
