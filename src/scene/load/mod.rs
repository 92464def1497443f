//! Loaders: scenes built in code (`Scene::new`, `add_polygon`), scene files
//! (TOML), OBJ + MTL, built-in scenes and probe-point files, all reading
//! through one [`source::SourceFiles`] so that built-in scenes and files on
//! disk go through the same checks; and a scene file's settings tables,
//! read for the layers that own them (`SceneOptions::read_settings`).

mod build;
mod builtin;
mod coplanar_merge;
mod emitting_bodies;
mod glazing_table;
mod loaded;
mod luminaire_tables;
mod material_names;
mod mtl;
mod obj;
mod obj_scan;
mod probe_points;
mod repair_report;
mod scene_file;
mod settings_tables;
mod sky_tables;
mod source;
mod spec;
mod statement;
mod two_sided;

pub use builtin::builtin_names;
pub use coplanar_merge::{MergeReport, merge_coplanar_faces};
pub use loaded::{LoadSettings, LoadedScene};
pub use obj::load_obj;
pub use probe_points::{ProbePoint, load_probe_points, parse_probe_points};
pub use scene_file::load_scene_file;
pub use spec::{load_scene, load_scene_with};
