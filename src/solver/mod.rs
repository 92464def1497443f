//! The progressive shooting solver: shooters and their source sampling,
//! run/stop criteria, adaptive refinement, the solution and its probes, and
//! the settings of a whole solve (the meshes it solves on are planned in
//! `crate::meshing`).

mod ambient;
mod ambient_irradiance;
mod ambient_rooms;
mod ambient_smoothing;
mod ambient_sweeps;
mod element_index;
mod element_power;
mod energy_balance;
mod indexed_update;
mod patch_clusters;
mod patch_reception;
mod patch_shots;
mod penumbra;
mod progressive;
mod refinement;
mod run;
mod settings;
mod settings_file;
mod shaft_culling;
mod shooter;
mod solution;
mod unshot;
mod unshot_by_zone;
mod vertex_irradiance;
mod visibility_memory;

#[cfg(test)]
pub(crate) use ambient_irradiance::AmbientIrradiance;
pub use ambient_rooms::ReadingPlace;
pub use energy_balance::EnergyBalance;
pub use patch_shots::PatchShotSummary;
pub use progressive::Solver;
pub use run::{Progress, StopReason, Until};
pub use settings::{FormFactorKernel, Settings, ShootFrom, SolverSettings};
pub use solution::{PENUMBRA_RAY_BUDGET, Probe, ProbeMode, Solution, SurfaceTotals};
