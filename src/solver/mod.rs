//! The progressive shooting solver: shooters and their source sampling,
//! run/stop criteria, adaptive refinement, the solution and its probes, the
//! settings of a whole solve, and the plan of which mesher each receiver
//! gets (`scene_mesh.rs`, where lighting's fields meet the meshers).

mod ambient;
mod layout;
mod light;
mod mesh_settings;
mod progressive;
mod reading;
mod refinement;
mod run;
mod scene_mesh;
mod settings;
mod settings_file;
mod shot;
mod stats;
#[cfg(test)]
mod test_scenes;
mod zones;

#[cfg(test)]
pub(crate) use ambient::irradiance::AmbientIrradiance;
pub use ambient::patch_shots::PatchShotSummary;
pub use light::energy_balance::EnergyBalance;
pub use mesh_settings::{Length, MeshKind, MeshSettings};
pub use progressive::Solver;
pub use reading::gather::PENUMBRA_RAY_BUDGET;
pub use reading::places::ReadingPlace;
pub use reading::request::Ambient;
pub use reading::solution::{Probe, ProbeMode, Solution, SurfaceTotals};
pub use refinement::RefinementSettings;
pub use run::{Progress, StopReason, Until};
pub use scene_mesh::{
    MeshAnalysis, SceneMesh, field_layout, mesh_scene, receiver_layout, receiver_shadow_boundaries,
    scene_receiver_analyses, scene_shadow_boundaries, total_field_layout,
};
pub use settings::{FormFactorKernel, Settings, ShootFrom, SolverSettings};
pub use stats::SolveStats;
