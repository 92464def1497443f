//! Pure functions of geometry: form-factor kernels, their gradients, and the
//! seed paper's small-disc emitter model.
//!
//! Nothing here knows of meshes, solvers or images.

mod form_factor;
mod polygon_gradient;
mod small_disc;

pub use form_factor::{disc_form_factor, polygon_form_factor};
pub use polygon_gradient::{polygon_form_factor_gradient, polygon_form_factor_with_gradient};
pub use small_disc::{DiscModel, ReceiverPlane, SmallDisc, TiltFrame, tilt_line_maximum};
