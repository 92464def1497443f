//! The light state of a solve: the irradiance each vertex has received, the
//! unshot radiosity of each patch and of its elements' corners, the unshot
//! power zone by zone, and the energy ledger; with the element index and the
//! indexed updates that change them in parallel.

pub(super) mod after_split;
pub(super) mod cell_coordinates;
pub(super) mod element_index;
pub(super) mod energy_balance;
pub(super) mod indexed_update;
pub(super) mod patch_field;
pub(super) mod shooting_order;
pub(super) mod state;
pub(super) mod unshot;
pub(super) mod unshot_by_zone;
pub(super) mod vertex_irradiance;
