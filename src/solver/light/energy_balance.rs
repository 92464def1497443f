//! The energy ledger of a solve: where the emitted power has gone.

use crate::rgb::Rgb;

/// Where the emitted power has gone so far, per RGB channel, in watts (or
/// the scene's length unit squared times W/m²).
///
/// `absorbed + unshot + escaped = emitted` holds at every step. After
/// patch shots ([`crate::Solver::shoot_patches`]) each term counts them
/// too: what the receiving patches absorbed, what they left unshot, and
/// what landed nowhere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyBalance {
    /// Power emitted by all emitters: Σ E·A.
    pub emitted: Rgb,
    /// Power absorbed by surfaces: Σ (1 − ρ_e) P_e over the power P_e each
    /// shot gave element e (A_e times its corners' mean irradiance, scaled
    /// for a reflected shot in a zone that keeps all its light so that the
    /// zone receives the whole shot, see `solver/shot/landing_scale.rs`; or, from
    /// an emitter, that with the curvature of its field: see
    /// `solver/shot/element_power.rs`).
    pub absorbed: Rgb,
    /// Power waiting to be shot: Σ_p ΔB_p A_p, or what the patch shots
    /// left of it.
    pub unshot: Rgb,
    /// Power shot that no surface received: it left an open scene or fell
    /// on the black back of a one-sided surface (or is the discretisation
    /// error of the emitters' shots, and of reflected shots where zones do
    /// not keep all their light).
    pub escaped: Rgb,
}
