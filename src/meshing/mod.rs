//! Meshing: the plan of which mesher each receiver gets, between the
//! lighting and the mesh below and the solver above.
//!
//! The mesh settings ([`MeshSettings`], [`Length`], [`MeshKind`]) are
//! written before a scene exists, with lengths relative to its size; they
//! are resolved once against the scene ([`ResolvedMeshSettings`]), and the
//! resolved form travels down to everything that meshes. The closed zones
//! (`zones/`: the rooms of a building whose doors are shut) pair each
//! receiver with its own room's lights and occluders. Each receiver's mesh
//! follows the shadow boundaries its lights cast (`boundaries.rs`, from
//! `lighting::shadow_boundaries`), and a receiver lit by a dominant small
//! emitter gets a contour layout of its direct light (`layouts.rs`, from
//! `lighting`'s direct fields and `mesh`'s contour meshers). [`mesh_scene`]
//! puts them together into one [`SceneMesh`].
//!
//! Layers: this module uses `scene`, `lighting` and `mesh`, and the solver
//! uses it (it meshes through [`mesh_scene`] and keeps its shots to the
//! zones); study and the CLI plan meshes here without the solver.

mod analyses;
mod boundaries;
mod layouts;
mod length;
mod mesh_table;
mod receiver_survey;
mod refinement_settings;
mod resolved;
mod scene_mesh;
mod settings;
mod zones;

pub use analyses::scene_receiver_analyses;
pub use boundaries::{receiver_shadow_boundaries, scene_shadow_boundaries};
pub use layouts::{field_layout, receiver_layout, total_field_layout};
pub use length::Length;
pub use receiver_survey::{ReceiverSurvey, survey_receivers};
pub use refinement_settings::RefinementSettings;
pub use resolved::ResolvedMeshSettings;
pub(crate) use scene_mesh::mesh_scene_in_zones;
pub use scene_mesh::{MeshAnalysis, SceneMesh, mesh_scene};
pub use settings::{MeshKind, MeshSettings};
pub(crate) use zones::{ShotPlaces, ZoneLabels, ZoneMembers, Zones};
