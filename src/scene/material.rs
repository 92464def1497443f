//! Diffuse materials: reflectance and emitted radiance per RGB channel.

use crate::rgb::Rgb;

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
    /// Visible transmittance τ_n at normal incidence: the luminance of the
    /// MTL `Tf`. Above zero, the material is glazing: a clear pane that
    /// lets daylight through, τ falling with the angle of incidence as in
    /// Radiance's `glass` ([`crate::daylight::pane_transmittance`]), and
    /// that reflects as such a pane does; its `Kd` is not used. Zero for an
    /// opaque material.
    pub transmittance: f64,
}

impl Material {
    /// A diffuse material that emits nothing.
    #[must_use]
    pub fn diffuse(name: impl Into<String>, reflectance: Rgb) -> Material {
        Material {
            name: name.into(),
            reflectance,
            emitted_radiance: Rgb::ZERO,
            transmittance: 0.0,
        }
    }

    /// An emitter of radiance L_e (W/(m²·sr) per channel) that reflects
    /// nothing; see [`Material::with_reflectance`].
    #[must_use]
    pub fn emitter(name: impl Into<String>, emitted_radiance: Rgb) -> Material {
        Material {
            name: name.into(),
            reflectance: Rgb::ZERO,
            emitted_radiance,
            transmittance: 0.0,
        }
    }

    /// The same material with diffuse reflectance ρ.
    #[must_use]
    pub fn with_reflectance(self, reflectance: Rgb) -> Material {
        Material {
            reflectance,
            ..self
        }
    }

    /// What is wrong with the material, as the MTL loader words it (`Kd`
    /// finite and in [0, 1), `Ke` finite and ≥ 0), or `None`.
    #[must_use]
    pub fn problem(&self) -> Option<String> {
        let shown = |keyword: &str, c: Rgb| format!("{keyword} = ({} {} {})", c.r, c.g, c.b);
        if let Some(problem) = reflectance_problem(self.reflectance) {
            return Some(format!("{}: {problem}", shown("Kd", self.reflectance)));
        }
        if let Some(problem) = emitted_radiance_problem(self.emitted_radiance) {
            return Some(format!("{}: {problem}", shown("Ke", self.emitted_radiance)));
        }
        let tf = self.transmittance;
        (!tf.is_finite() || !(0.0..1.0).contains(&tf))
            .then(|| format!("Tf = {tf}: the transmittance must be at least 0 and below 1"))
    }

    /// Emitted exitance (radiosity) E = π L_e, W/m².
    #[must_use]
    pub fn emitted_radiosity(&self) -> Rgb {
        self.emitted_radiance * std::f64::consts::PI
    }

    /// A clear glazing pane of visible transmittance `transmittance` at
    /// normal incidence (0 < τ_n < 1).
    #[must_use]
    pub fn glazing(name: impl Into<String>, transmittance: f64) -> Material {
        Material {
            name: name.into(),
            reflectance: Rgb::ZERO,
            emitted_radiance: Rgb::ZERO,
            transmittance,
        }
    }

    /// True when the material is glazing (transmits daylight).
    #[must_use]
    pub fn is_glazing(&self) -> bool {
        self.transmittance > 0.0
    }

    /// True when the material emits light in any channel.
    #[must_use]
    pub fn is_emitter(&self) -> bool {
        self.emitted_radiance.max_element() > 0.0
    }
}

/// A colour that is not finite in every channel.
pub(crate) const NOT_FINITE: &str = "not a finite colour";

/// Why a diffuse reflectance is out of range (each channel finite, ≥ 0 and
/// < 1), or `None`.
pub(crate) fn reflectance_problem(rgb: Rgb) -> Option<&'static str> {
    if !rgb.is_finite() {
        Some(NOT_FINITE)
    } else if rgb.min_element() < 0.0 || rgb.max_element() >= 1.0 {
        Some("diffuse reflectance must be at least 0 and below 1 in every channel")
    } else {
        None
    }
}

/// Why an emitted radiance is out of range (each channel finite and ≥ 0),
/// or `None`.
pub(crate) fn emitted_radiance_problem(rgb: Rgb) -> Option<&'static str> {
    if !rgb.is_finite() {
        Some(NOT_FINITE)
    } else if rgb.min_element() < 0.0 {
        Some("emitted radiance must not be negative")
    } else {
        None
    }
}
