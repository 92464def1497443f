//! The progressive shooting solver: shooters and their source sampling,
//! run/stop criteria, adaptive refinement, the solution and its probes, and
//! the settings of a whole solve (the meshes it solves on are planned in
//! `crate::meshing`).

mod ambient;
mod layout;
mod light;
mod progressive;
mod reading;
mod refinement;
mod run;
mod settings;
mod settings_file;
mod shot;
mod stats;
#[cfg(test)]
mod test_scenes;

#[cfg(test)]
pub(crate) use ambient::irradiance::AmbientIrradiance;
pub use ambient::patch_shots::PatchShotSummary;
pub use light::energy_balance::EnergyBalance;
pub use progressive::Solver;
pub use reading::gather::PENUMBRA_RAY_BUDGET;
pub use reading::places::ReadingPlace;
pub use reading::request::Ambient;
pub use reading::solution::{Probe, ProbeMode, Solution, SurfaceTotals};
pub use run::{Progress, StopReason, Until};
pub use settings::{FormFactorKernel, Settings, ShootFrom, SolverSettings};
pub use stats::SolveStats;
