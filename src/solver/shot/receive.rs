//! What a shot's receivers take: the irradiance at its vertices, the power
//! at its elements (and so the ledger's received and absorbed power), and
//! what the elements reflect into their corners' and patches' unshot light.

use rayon::prelude::*;

use crate::meshing::ShotPlaces;
use crate::rgb::Rgb;
use crate::scene::SurfaceId;
use crate::solver::layout::CulledZones;
use crate::solver::light::indexed_update;
use crate::solver::light::state::LightState;
use crate::solver::shot::context::ShotContext;
use crate::solver::shot::element_power::{self, Emitter};
use crate::solver::shot::landing_scale::landing_scale;
use crate::solver::shot::receivers::ShotReceivers;

impl ShotContext<'_> {
    /// Adds a shot's irradiance to vertices of `light`, and what elements
    /// reflect to their corners' and their patches' unshot radiosity: over
    /// the elements of closed zone `zone` only when given (no other
    /// receives). For the shot of an emitting patch (`emitter`), the
    /// elements' received power takes the curvature of its unoccluded field
    /// (see `solver/shot/element_power.rs`); otherwise it is the corners'
    /// mean times the area, scaled to land whole when `lands_whole` gives
    /// the shot's power (see [`landing_scale`]). The vertices, the
    /// elements' powers (into `powers`) and their corners are updated in
    /// parallel, the sums in order, so that a solve is the same on any
    /// number of threads.
    pub(crate) fn receive(
        &self,
        light: &mut LightState,
        incident: &[Rgb],
        zone: Option<usize>,
        emitter: Option<Emitter>,
        lands_whole: Option<Rgb>,
        powers: &mut Vec<Rgb>,
    ) {
        let mesh = self.mesh;
        let (all_vertices, all_elements): (Vec<u32>, Vec<u32>);
        let (vertices, elements): (&[u32], &[u32]) = match zone.zip(self.layout.zones.as_ref()) {
            Some((zone, CulledZones { members, .. })) => {
                (&members.vertices[zone], &members.elements[zone])
            }
            None => {
                all_vertices = (0..mesh.vertices.len() as u32).collect();
                all_elements = (0..mesh.elements.len() as u32).collect();
                (&all_vertices, &all_elements)
            }
        };
        // The k-th of `vertices` keeps its light at place k.
        let receivers = ShotReceivers {
            vertices,
            elements,
            places: ShotPlaces::new(zone, self.members()),
        };
        let places = receivers.places;
        let at = |v: u32| incident[places.of(v)];
        let reflectances = &self.layout.surface_reflectance;
        let reflectance_of = |surface: SurfaceId| reflectances[surface.index()];
        light.irradiance.add_at(vertices, incident);
        match emitter {
            Some(emitter) => {
                *powers = element_power::emitter_shot_powers(
                    self.scene, mesh, &emitter, incident, &receivers,
                );
            }
            None => {
                let power = |&e: &u32| {
                    let element = &mesh.elements[e as usize];
                    element.corner_mean(at) * element.area
                };
                if elements.len() > indexed_update::SERIAL_PART {
                    elements.par_iter().map(power).collect_into_vec(powers);
                } else {
                    powers.clear();
                    powers.extend(elements.iter().map(power));
                }
            }
        }
        let scale = lands_whole.map_or(Rgb::ONE, |shot_power| {
            landing_scale(shot_power, powers.iter().copied().sum())
        });
        for (&e, &power) in elements.iter().zip(powers.iter()) {
            let incident_power = power * scale;
            if incident_power == Rgb::ZERO {
                continue;
            }
            let element = &mesh.elements[e as usize];
            light.received_power += incident_power;
            let patch = element.patch as usize;
            let reflectance = reflectance_of(element.surface);
            light.unshot[patch] += reflectance * incident_power / self.layout.patch_areas[patch];
            light.absorbed_power += (Rgb::ONE - reflectance) * incident_power;
        }
        light.unshot_corners.add_shot(mesh, elements, |element, v| {
            reflectance_of(element.surface) * scale * at(v)
        });
    }
}
