//! What the ambient term keeps between images: the rays it gathers along,
//! and the patch shots of the unshot power the last run left.

use std::sync::Mutex;

use crate::solver::ambient::patch_shots::PatchShots;
use crate::solver::ambient::rooms::AmbientCache;

/// The ambient term's memory.
#[derive(Default)]
pub(crate) struct AmbientState {
    /// The rays the ambient term gathers the unshot light along, cast on
    /// first use and kept while the mesh is not too large
    /// (`solver/ambient/rooms.rs`).
    pub(crate) rays: Mutex<AmbientCache>,
    /// The patch shots of the unshot power the last run left
    /// (`solver/ambient/patch_shots.rs`), until the next shot changes it.
    pub(crate) patch_shots: Option<PatchShots>,
}
