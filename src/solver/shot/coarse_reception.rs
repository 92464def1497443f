//! Coarse reception of a dim reflected shot: which vertices gather it and
//! which take it interpolated from their patch's samples
//! (`patch_reception.rs`), and that interpolation, bent by the shooter's
//! point kernel so that it keeps the curvature of the shot's light.

use glam::DVec3;
use rayon::prelude::*;

use crate::rgb::Rgb;
use crate::solver::layout::CulledZones;
use crate::solver::light::indexed_update;
use crate::solver::light::vertex_irradiance::VertexIrradiance;
use crate::solver::shot::context::ShotContext;
use crate::solver::shot::incident::Shot;
use crate::solver::shot::patch_reception::{PatchReception, ReceptionPlan};
use crate::solver::shot::scratch::ShotScratch;
use crate::solver::stats::SolveStats;

/// Interpolated vertices per parallel task.
const INTERPOLATION_CHUNK: usize = 2048;

impl ShotContext<'_> {
    /// Which vertices of the receiving zone (`zone`, or the whole scene)
    /// gather a reflected shot of `shot_power` from patch j, and which are
    /// interpolated from their patch's samples: those whose `irradiance`
    /// so far is at least the shot's bound on their patches over
    /// [`SolverSettings::coarse_reception`], and whose samples agree with
    /// them (see `solver/shot/patch_reception.rs`). The plan is made in
    /// the `scratch` buffers, from the patches' samples in `reception`.
    ///
    /// [`SolverSettings::coarse_reception`]: crate::SolverSettings::coarse_reception
    pub(crate) fn reception_plan(
        &self,
        j: usize,
        shot_power: Rgb,
        zone: Option<usize>,
        irradiance: &VertexIrradiance,
        scratch: &mut ShotScratch,
        reception: &mut PatchReception,
    ) -> ReceptionPlan {
        reception.refresh(self.mesh);
        let mut plan = std::mem::take(&mut scratch.reception_plan);
        // Without zones, every patch and vertex, listed once per mesh size.
        if scratch.every_patch.len() != self.mesh.patches.len() {
            scratch.every_patch = (0..self.mesh.patches.len() as u32).collect();
        }
        if scratch.every_vertex.len() != self.mesh.vertices.len() {
            scratch.every_vertex = (0..self.mesh.vertices.len() as u32).collect();
        }
        let (patches, vertices): (&[u32], &[u32]) = match zone.zip(self.layout.zones.as_ref()) {
            Some((zone, CulledZones { members, .. })) => {
                (&members.patches[zone], &members.vertices[zone])
            }
            None => (&scratch.every_patch, &scratch.every_vertex),
        };
        let fraction = self.settings.coarse_reception;
        let never = Rgb::splat(f64::INFINITY);
        scratch.thresholds.resize(self.mesh.patches.len(), never);
        let reception = &*reception;
        let threshold =
            |&p: &u32| reception.interpolation_threshold(p as usize, j, shot_power, fraction);
        // A patch's bound costs about as much as a hundred vertices' updates.
        if patches.len() > indexed_update::SERIAL_PART / 64 {
            patches
                .par_iter()
                .map(threshold)
                .collect_into_vec(&mut scratch.patch_thresholds);
        } else {
            scratch.patch_thresholds.clear();
            scratch
                .patch_thresholds
                .extend(patches.iter().map(threshold));
        }
        for (&p, &t) in patches.iter().zip(&scratch.patch_thresholds) {
            scratch.thresholds[p as usize] = t;
        }
        reception.plan(vertices, &scratch.thresholds, irradiance, &mut plan);
        for &p in patches {
            scratch.thresholds[p as usize] = never;
        }
        plan
    }
}

impl Shot<'_> {
    /// Gives the `plan`'s interpolated vertices the shot's irradiance
    /// interpolated from their patch's samples (`reception`'s weights),
    /// already in `incident`, each times its [`curvature_factor`]; in
    /// parallel. A vertex without weights keeps what it has.
    pub(super) fn interpolate(
        &self,
        plan: &ReceptionPlan,
        reception: &PatchReception,
        incident: &mut [Rgb],
        stats: &mut SolveStats,
    ) {
        let ShotContext { scene, mesh, .. } = self.context;
        let places = self.places;
        let shooter = &mesh.patches[self.patch];
        let kernel = PointKernel {
            centre: shooter.cell.point(0.5, 0.5),
            normal: scene.surface(shooter.surface).normal(),
        };
        let at = |v: u32| {
            let vertex = &mesh.vertices[v as usize];
            kernel.at(
                vertex.receiver_position(),
                scene.surface(vertex.surface).normal(),
            )
        };
        let interpolate = |&v: &u32| {
            reception.weights_of(v).map(|weights| {
                let (mut light, mut kernel_there) = (Rgb::ZERO, 0.0);
                for &(s, w) in &weights {
                    light += incident[places.of(s)] * f64::from(w);
                    kernel_there += at(s) * f64::from(w);
                }
                light * curvature_factor(at(v), kernel_there)
            })
        };
        let values: Vec<Option<Rgb>> = plan
            .interpolated
            .par_iter()
            .with_min_len(INTERPOLATION_CHUNK)
            .map(interpolate)
            .collect();
        for (&v, value) in plan.interpolated.iter().zip(values) {
            if let Some(value) = value {
                incident[places.of(v)] = value;
            }
        }
        let count = (plan.interpolated.len() + plan.gathered.len()) as u64;
        stats.interpolated_receptions += plan.interpolated.len() as u64;
        stats.receptions += count;
    }
}

/// A shooting patch seen as a point at its centre: the kernel
/// cos θ_x cos θ_s / r² of a receiving point x with normal n_x, which
/// carries how a shot's irradiance bends across a receiving patch (falling
/// off as the inverse square of the distance and with both cosines).
struct PointKernel {
    centre: DVec3,
    normal: DVec3,
}

impl PointKernel {
    /// cos θ_x cos θ_s / r² at x facing `normal` (0 behind either plane).
    fn at(&self, x: DVec3, normal: DVec3) -> f64 {
        let d = self.centre - x;
        let r2 = d.length_squared();
        if r2 <= 0.0 {
            return 0.0;
        }
        normal.dot(d).max(0.0) * self.normal.dot(-d).max(0.0) / (r2 * r2)
    }
}

/// How much a shot's irradiance interpolated from a patch's samples is
/// scaled at a vertex: the shooter's point kernel there over the same
/// interpolation of the kernel at the samples, within [1/2, 2]; 1 where
/// either is 0. Linear interpolation of a field that bends (a shot falls
/// off as 1/r² and with the cosines) misses its curvature: a receiving
/// patch under a shooter, where the field peaks, took too little.
fn curvature_factor(here: f64, interpolated: f64) -> f64 {
    if here > 0.0 && interpolated > 0.0 {
        (here / interpolated).clamp(0.5, 2.0)
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Under a small shooter the shot's irradiance is its point kernel
    /// times a constant: interpolated linearly between two samples either
    /// side of the peak it falls short, and the curvature factor restores
    /// it; a vertex behind either plane keeps the interpolation.
    #[test]
    fn the_curvature_factor_restores_a_point_shooters_peak() {
        let kernel = PointKernel {
            centre: DVec3::new(0.0, 2.0, 0.0),
            normal: DVec3::NEG_Y,
        };
        let up = DVec3::Y;
        let field = |x: f64| 7.0 * kernel.at(DVec3::new(x, 0.0, 0.0), up);
        let (left, right) = (field(-0.5), field(0.5));
        let linear = 0.5 * (left + right);
        assert!(linear < 0.9 * field(0.0), "{linear} against {}", field(0.0));
        let interpolated_kernel = 0.5
            * (kernel.at(DVec3::new(-0.5, 0.0, 0.0), up)
                + kernel.at(DVec3::new(0.5, 0.0, 0.0), up));
        let here = kernel.at(DVec3::ZERO, up);
        let restored = linear * curvature_factor(here, interpolated_kernel);
        assert!((restored / field(0.0) - 1.0).abs() < 1e-12, "{restored}");
        // Facing away from the shooter: no kernel, no change.
        let behind = kernel.at(DVec3::ZERO, DVec3::NEG_Y);
        assert_eq!(behind, 0.0);
        assert_eq!(curvature_factor(behind, interpolated_kernel), 1.0);
        // Far off the peak the factor is held within [1/2, 2].
        assert_eq!(curvature_factor(1.0, 0.01), 2.0);
    }
}
