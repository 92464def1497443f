//! The light new vertices of an adaptive mesh gather: every shot so far,
//! the patches', the photometric luminaires' and the daylight's, shot again
//! at them alone.

use crate::rgb::Rgb;
use crate::solver::layout::CulledZones;
use crate::solver::light::state::LightState;
use crate::solver::shot::cache_runs::in_shadow_cache_runs;
use crate::solver::shot::context::ShotContext;
use crate::solver::shot::shooter::{Receiver, Shooter, ShotRadiosity};
use crate::solver::stats::SolveStats;

impl ShotContext<'_> {
    /// The irradiance of new `vertices` from every shot so far: for each
    /// patch p that has shot radiosity S_p in all, H_v = Σ_p S_p F_{v→p},
    /// with the form factors of the solver's kernel and sampling, plus the
    /// photometric luminaires that have shot. Parallel over vertices; the
    /// rays are counted in `stats`.
    pub(crate) fn gather_shot_light(
        &self,
        light: &LightState,
        stats: &mut SolveStats,
        vertices: &[u32],
    ) -> Vec<Rgb> {
        let shooters: Vec<Shooter> = light
            .shot
            .iter()
            .enumerate()
            .filter(|(_, s)| s.element_sum() > 0.0)
            .map(|(p, &s)| {
                let power = s.element_sum() * self.mesh.patches[p].area;
                self.shooter(p, power, light.reference_power, ShotRadiosity::Uniform(s))
            })
            .collect();
        let (scene, mesh, visibility) = (self.scene, self.mesh, self.visibility);
        let zones = self
            .layout
            .zones
            .as_ref()
            .map(|CulledZones { zones, .. }| zones);
        let (density, kernel, shot) = (
            self.settings.sample_density,
            self.settings.kernel,
            stats.shots as u64,
        );
        let gathered: Vec<(Rgb, u64)> = in_shadow_cache_runs(vertices, |&v, cache| {
            let vertex = &mesh.vertices[v as usize];
            // Only the vertex's own closed zone's shooters reach it.
            let elsewhere = |shooter: &Shooter| {
                zones.is_some_and(|zones| zones.of(shooter.surface) != zones.of(vertex.surface))
            };
            let receiver = Receiver {
                position: vertex.receiver_position(),
                normal: scene.surface(vertex.surface).normal(),
                surface: vertex.surface,
                key: u64::from(v),
                clear: false,
                occluders: None,
            };
            let mut irradiance = Rgb::ZERO;
            let mut rays = 0;
            for shooter in &shooters {
                if shooter.surface == vertex.surface || elsewhere(shooter) {
                    continue;
                }
                let g = shooter.gather(&receiver, density, shot, kernel, visibility, &mut *cache);
                irradiance += g.irradiance;
                rays += u64::from(g.rays);
            }
            (irradiance, rays)
        });
        stats.rays += gathered.iter().map(|g| g.1).sum::<u64>();
        let mut gathered_light: Vec<Rgb> = gathered.into_iter().map(|g| g.0).collect();
        for k in 0..self.scene.luminaires.len() {
            if light.luminaire_shot[k] {
                let direct = self.luminaire_light(k, vertices);
                stats.rays += vertices.len() as u64;
                for (h, d) in gathered_light.iter_mut().zip(direct) {
                    *h += d;
                }
            }
        }
        if light.daylight_shot {
            let (direct, rays) = self.daylight_light(vertices);
            stats.rays += rays;
            for (h, d) in gathered_light.iter_mut().zip(direct) {
                *h += d;
            }
        }
        gathered_light
    }
}
