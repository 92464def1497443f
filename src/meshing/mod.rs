//! Meshing: the plan of which mesher each receiver gets, between the
//! lighting and the mesh below and the solver above.
//!
//! The mesh settings ([`MeshSettings`], [`Length`], [`MeshKind`]) are
//! written before a scene exists, with lengths relative to its size; they
//! are resolved once against the scene ([`ResolvedMeshSettings`]), and the
//! resolved form travels down to everything that meshes. The closed zones
//! ([`Zones`]: the rooms of a building whose doors are shut) pair each
//! receiver with its own room's lights and occluders. The shadow boundaries
//! each receiver follows come from `lighting`, the contour layouts of the
//! receivers lit by a dominant small emitter from `lighting`'s direct
//! fields and the meshers of `mesh`; [`mesh_scene`] puts them together
//! into one [`SceneMesh`]. The solver meshes through [`mesh_scene`] and
//! uses the zones for its shots; study and the CLI plan meshes here
//! without the solver.

mod refinement_settings;
mod scene_mesh;
mod settings;
mod zones;

pub use refinement_settings::RefinementSettings;
pub(crate) use scene_mesh::mesh_scene_in_zones;
pub use scene_mesh::{
    MeshAnalysis, SceneMesh, field_layout, mesh_scene, receiver_layout, receiver_shadow_boundaries,
    scene_receiver_analyses, scene_shadow_boundaries, total_field_layout,
};
pub use settings::{Length, MeshKind, MeshSettings};
pub(crate) use zones::{
    ShotPlaces, ZoneLabels, ZoneMembers, Zones, cosine_direction, cosine_direction_at,
};
