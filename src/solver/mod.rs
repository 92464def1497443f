//! The progressive shooting solver and its source sampling; luminaires, the
//! direct field of one on a receiver's plane, and which receivers a dominant
//! small luminaire lights (the contour mesher's candidates).

mod direct_field;
mod dominance;
mod emitters;
mod mesh_budget;
mod progressive;
mod refinement;
mod run;
mod sampling;
mod scene_mesh;
mod settings;
mod solution;
mod source_sampling;
mod stratified;

pub use direct_field::DirectField;
pub use dominance::{DominanceSettings, ReceiverAnalysis, analyse_receivers};
pub use emitters::{Luminaire, luminaires};
pub use progressive::{EnergyBalance, Solver};
pub use refinement::{RefinementSettings, elements_to_split};
pub use run::{Progress, StopReason, Until};
pub use scene_mesh::{
    Length, MeshAnalysis, MeshKind, MeshSettings, SceneMesh, mesh_scene, receiver_layout,
};
pub use settings::{FormFactorKernel, Settings, SolverSettings};
pub use solution::{Probe, ProbeMode, Solution, SurfaceTotals};
