//! Pure functions of geometry: form-factor kernels.
//!
//! Nothing here knows of meshes, solvers or images.

mod form_factor;

pub use form_factor::{disc_form_factor, polygon_form_factor};
