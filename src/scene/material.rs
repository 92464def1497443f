//! Diffuse materials: reflectance and emitted radiance per RGB channel.

use glam::DVec3;

/// A linear RGB triple. Its unit depends on the quantity it holds
/// (reflectance: none; radiance: W/(m²·sr); radiosity: W/m²).
pub type Rgb = DVec3;

/// A Lambertian material.
///
/// `reflectance` is the MTL `Kd` (diffuse albedo ρ, each channel in [0, 1)).
/// `emitted_radiance` is the MTL `Ke`, read as emitted **radiance** L_e, as
/// pbrt and Mitsuba area lights do; the emitter's exitance is E = π L_e.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The material's name in its MTL file.
    pub name: String,
    /// Diffuse reflectance ρ per channel.
    pub reflectance: Rgb,
    /// Emitted radiance L_e per channel, W/(m²·sr).
    pub emitted_radiance: Rgb,
}

impl Material {
    /// Emitted exitance (radiosity) E = π L_e, W/m².
    #[must_use]
    pub fn emitted_radiosity(&self) -> Rgb {
        self.emitted_radiance * std::f64::consts::PI
    }

    /// True when the material emits light in any channel.
    #[must_use]
    pub fn is_emitter(&self) -> bool {
        self.emitted_radiance.max_element() > 0.0
    }
}
