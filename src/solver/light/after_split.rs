//! What an adaptive split changes in the light: the new vertices'
//! irradiance, the new elements' unshot corners, and the difference in
//! incident power the finer elements find, booked in the ledger.

use std::collections::HashMap;

use crate::mesh::{Element, ElementHierarchy, Mesh};
use crate::rgb::Rgb;
use crate::scene::Scene;
use crate::solver::light::state::LightState;

impl LightState {
    /// Σ over each patch's elements of the mean irradiance of the element's
    /// corners times its area: the incident power the ledger counts.
    pub(crate) fn incident_power_per_patch(&self, mesh: &Mesh) -> Vec<Rgb> {
        let mut power = vec![Rgb::ZERO; mesh.patches.len()];
        for element in &mesh.elements {
            let mean = element.corner_mean(|v| self.irradiance.at(v as usize));
            power[element.patch as usize] += mean * element.area;
        }
        power
    }

    /// Gives the new vertices `added` (the next indices, in order) the
    /// irradiance they `gathered`.
    pub(crate) fn add_vertices(&mut self, added: &[u32], gathered: Vec<Rgb>) {
        for (&v, irradiance) in added.iter().zip(gathered) {
            debug_assert_eq!(v as usize, self.irradiance.len());
            self.irradiance.push(irradiance);
        }
    }

    /// The unshot corners of the mesh's new elements after a split (see
    /// [`UnshotCorners::after_split`]), from `before`, the corners of the
    /// elements before it by their vertex arrays.
    ///
    /// [`UnshotCorners::after_split`]: crate::solver::light::unshot::UnshotCorners::after_split
    pub(crate) fn carry_unshot_corners(
        &mut self,
        scene: &Scene,
        mesh: &Mesh,
        hierarchy: &ElementHierarchy,
        before: &HashMap<[u32; 4], [Rgb; 4]>,
    ) {
        let parent_of = |e: usize| {
            let parent = hierarchy.leaf(e).parent?;
            hierarchy.node(parent).map(|node| node.element)
        };
        let reflectance = |element: &Element| {
            scene
                .material_of(scene.surface(element.surface))
                .reflectance
        };
        self.unshot_corners
            .after_split(mesh, parent_of, before, &self.irradiance, reflectance);
    }

    /// Books the change in each patch's incident power a split found,
    /// from `before` to `after` ([`LightState::incident_power_per_patch`]):
    /// ΔP moves from the escaped power to the received power, and ρ ΔP to
    /// the patch's unshot power.
    pub(crate) fn book_split(
        &mut self,
        scene: &Scene,
        mesh: &Mesh,
        before: Vec<Rgb>,
        after: Vec<Rgb>,
    ) {
        for (p, (old, new)) in before.into_iter().zip(after).enumerate() {
            let change = new - old;
            let patch = &mesh.patches[p];
            if patch.area > 0.0 {
                let reflectance = scene.material_of(scene.surface(patch.surface)).reflectance;
                self.unshot[p] += reflectance * change / patch.area;
                self.received_power += change;
                self.absorbed_power += (Rgb::ONE - reflectance) * change;
            }
        }
    }
}
