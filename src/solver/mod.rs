//! The progressive shooting solver. [`Solver`] (`progressive.rs`) is the
//! driver: it chooses each shot, refines an adaptive mesh, runs until an
//! [`Until`] criterion (`stop.rs`) is met, and holds its state in named
//! parts, whose code lives in four folders:
//! - `light/`: the light shot and not yet shot (irradiance per vertex,
//!   unshot light per element corner, per-zone totals) and the ledger;
//! - `shot/`: one shot (the shooter and its strata, shaft culling, the
//!   visibility memory, coarse reception, what each element receives);
//! - `ambient/`: the ambient term for the light not yet shot, and the
//!   patch shots with their clusters;
//! - `reading/`: the [`Solution`] ([`Solver::solution`] with an
//!   [`Ambient`] request), probes, final gathers, reading places.
//!
//! Beside them: `layout.rs` (where things are: zones, reflectances,
//! insets), `stats.rs` ([`SolveStats`]), the settings of a whole solve and
//! their scene-file tables. The meshes it solves on are planned in
//! [`crate::meshing`].

mod ambient;
mod layout;
mod light;
mod progressive;
mod reading;
mod refinement;
mod settings;
mod settings_tables;
mod shot;
mod stats;
mod stop;
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
pub use settings::{FormFactorKernel, Settings, ShootFrom, SolverSettings};
pub use stats::SolveStats;
pub use stop::{Progress, StopReason, Until};
