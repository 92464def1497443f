//! isorad's integration tests, one module per subject, compiled as one
//! crate so that the suite links once. Shared scene builders and references
//! are in `support`.

mod support;

mod adaptive_mesh;
mod adaptive_solve;
mod api;
mod bad_inputs;
mod cie171;
mod cli;
mod compare;
mod contacts;
mod contour;
mod coplanar_merge;
mod daylight;
mod direct_field;
mod dominance;
mod emitting_bodies;
mod export;
mod fuzz_regressions;
mod golden;
mod grid_points;
mod level_lines;
mod long_runs;
mod luminaire_files;
mod luminaires;
mod office;
mod patch_shots;
mod plots;
mod probe;
mod properties;
mod radiometry;
mod render;
mod scene_loading;
mod solver;
mod source_refinement;
mod square_mesh;
mod strata;
mod thin_faces;
mod two_sided;
#[cfg(feature = "view")]
mod view_browser;
#[cfg(feature = "view")]
mod view_server;
