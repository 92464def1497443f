//! The progressive shooting solver: shooters and their source sampling,
//! run/stop criteria, adaptive refinement, the solution and its probes, the
//! settings of a whole solve, and the plan of which mesher each receiver
//! gets (`scene_mesh.rs`, where lighting's fields meet the meshers).

mod ambient;
mod ambient_irradiance;
mod ambient_rooms;
mod ambient_smoothing;
mod ambient_sweeps;
mod element_index;
mod element_power;
mod energy_balance;
mod indexed_update;
mod mesh_settings;
mod patch_clusters;
mod patch_reception;
mod patch_shots;
mod penumbra;
mod progressive;
mod refinement;
mod run;
mod scene_mesh;
mod settings;
mod settings_file;
mod shaft_culling;
mod shooter;
mod solution;
mod unshot;
mod unshot_by_zone;
mod vertex_irradiance;
mod visibility_memory;
mod zones;

#[cfg(test)]
pub(crate) use ambient_irradiance::AmbientIrradiance;
pub use ambient_rooms::ReadingPlace;
pub use energy_balance::EnergyBalance;
pub use mesh_settings::{Length, MeshKind, MeshSettings};
pub use patch_shots::PatchShotSummary;
pub use progressive::Solver;
pub use refinement::RefinementSettings;
pub use run::{Progress, StopReason, Until};
pub use scene_mesh::{
    MeshAnalysis, SceneMesh, field_layout, mesh_scene, receiver_layout, receiver_shadow_boundaries,
    scene_receiver_analyses, scene_shadow_boundaries, total_field_layout,
};
pub use settings::{FormFactorKernel, Settings, ShootFrom, SolverSettings};
pub use solution::{PENUMBRA_RAY_BUDGET, Probe, ProbeMode, Solution, SurfaceTotals};
