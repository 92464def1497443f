//! isorad computes global illumination of diffuse polygonal scenes by
//! **progressive radiosity**, and renders the view-independent solution with
//! a Gouraud rasterizer to linear-radiance EXR and tone-mapped PNG.
//!
//! Units follow pbrt and Mitsuba, so that renders are comparable with a path
//! tracer's: MTL `Kd` is diffuse reflectance, `Ke` emitted radiance L_e
//! (exitance E = π L_e); radiosity B is in W/m²; images hold radiance B/π.
//!
//! # Example
//!
//! A closed cube whose faces all emit E = π and reflect half, built in code:
//! the radiosity everywhere is E/(1 − ρ) = 2π.
//!
//! ```
//! use glam::DVec3;
//! use isorad::{Length, Material, Rgb, Scene, Settings, Solver, StopReason, Until};
//!
//! let mut scene = Scene::new();
//! let glow = scene.add_material(Material::emitter("glowing wall", Rgb::splat(1.0)).with_reflectance(Rgb::splat(0.5)))?;
//! // Six faces of the unit cube, counter-clockwise seen from inside.
//! let corner = |axis: usize, side: f64, s: f64, t: f64| {
//!     let mut p = [0.0; 3];
//!     p[axis] = side;
//!     p[(axis + 1) % 3] = s;
//!     p[(axis + 2) % 3] = t;
//!     DVec3::from_array(p)
//! };
//! for axis in 0..3 {
//!     let low = [corner(axis, 0.0, 0.0, 0.0), corner(axis, 0.0, 1.0, 0.0), corner(axis, 0.0, 1.0, 1.0), corner(axis, 0.0, 0.0, 1.0)];
//!     let high: Vec<DVec3> = low.iter().rev().map(|p| *p + DVec3::from_array({ let mut d = [0.0; 3]; d[axis] = 1.0; d })).collect();
//!     scene.add_polygon("face", glow, &low)?;
//!     scene.add_polygon("face", glow, &high)?;
//! }
//!
//! let mut settings = Settings::default();
//! settings.mesh.max_edge = Length::Absolute(0.125);
//! let mut solver = Solver::new(scene, settings)?;
//! let stop = solver.run_until(&Until::default().tolerance(1e-3), |_progress| {});
//! assert_eq!(stop, StopReason::Converged);
//! for radiosity in solver.radiosity() {
//!     assert!((radiosity.r / (2.0 * std::f64::consts::PI) - 1.0).abs() < 0.01);
//! }
//! # Ok::<(), isorad::Error>(())
//! ```
//!
//! # The API in five steps
//!
//! The crate root holds what these steps need; the rest lives in public
//! modules named after the pipeline ([`scene`], [`radiometry`],
//! [`photometry`], [`lighting`], [`mesh`], [`meshing`], [`solver`],
//! [`render`], [`view`], [`export`], [`study`], [`calculation`]), and the
//! pure sky and sun models in [`daylight`].
//!
//! 1. **A scene.** Build it in code with [`Scene::new`],
//!    [`Scene::add_material`] ([`Material::diffuse`], [`Material::emitter`]),
//!    [`Scene::add_polygon`] and [`Scene::set_camera`], or load a scene TOML,
//!    an OBJ + MTL or the built-in `"cornell"` with [`load_scene`]
//!    ([`scene::load_scene_with`] and [`scene::LoadSettings`] to keep the
//!    adjacent coplanar faces of a triangulated OBJ apart instead of merging
//!    them). Both paths check the same things and fail with the same
//!    [`Error`] variants; what was repaired or skipped (a non-planar face
//!    split, a degenerate one dropped) is listed in [`Scene::warnings`]. The
//!    library prints nothing.
//! 2. **Settings.** [`Settings`] holds [`MeshSettings`] and
//!    [`SolverSettings`]: plain data with defaults and the presets
//!    [`Settings::preview`] and [`Settings::final_quality`]; lengths may be
//!    fractions of the scene's size ([`Length::OfDiagonal`]), resolved once
//!    against the scene ([`meshing::ResolvedMeshSettings`]).
//!    [`Settings::from_scene_options`] reads a scene file's tables.
//! 3. **Solve.** [`Solver::new`] takes the scene and settings, meshes the
//!    scene and builds its BVH ([`Solver::with_mesh`] takes a mesh of your
//!    own). [`Solver::step`] makes one shot; [`Solver::run_until`] shoots
//!    until an [`Until`] criterion is met — tolerance, shot count, time budget
//!    or an `AtomicBool` set from another thread — calling back with
//!    [`Progress`] after each shot, and says why it stopped ([`StopReason`]).
//!    It stops only between shots, so the solution is always consistent;
//!    [`Solver::stats`] counts its shots and shadow rays.
//! 4. **Query.** [`Solver::solution`] gives a [`Solution`] with the
//!    [`Ambient`] term you ask for, the light not yet shot gathered where
//!    it will land: [`Ambient::Everywhere`], or [`Ambient::Omitted`] for
//!    the light shot alone (pass `&isorad::phase::silent`, or a reporter
//!    of your own, for the term's progress). It reads values at any point
//!    of a surface ([`Solution::probe`], by final gather or mesh
//!    interpolation), per-surface totals ([`Solution::surface_totals`]),
//!    and the shaded triangles for a viewer of your own
//!    ([`Solution::triangles`]). In a building, [`Ambient::For`] makes the
//!    ambient term only in the closed rooms of the
//!    [`solver::ReadingPlace`]s you will read (probes' surfaces, a
//!    calculation grid's points).
//! 5. **Look.** [`Solution::render`] rasterizes into an [`Image`] of linear
//!    radiance that you own (for one view of a building,
//!    [`Ambient::SeenFrom`] makes the ambient term only in the closed room
//!    the camera stands in); [`write_exr`] and [`write_png`] write it (to
//!    a temporary file, then renamed). Beside them, [`export_solution`]
//!    (or [`export::export_glb`] and [`export::export_ply`]) writes the
//!    solved mesh with its light baked into the vertices, for a viewer or
//!    another tool, with the PNG's exposure ([`ToneMap`]).
//!
//! `examples/embed.rs` and `examples/progress.rs` show all of it. To compare
//! meshers: [`study::compare_receiver`], [`study::write_loglog_plot`] (error
//! against vertex count) and [`study::write_mesh_panels`] (meshes side by
//! side with their wireframes).
//!
//! # References
//! - M. F. Cohen, S. E. Chen, J. R. Wallace, D. P. Greenberg, "A Progressive
//!   Refinement Approach to Fast Radiosity Image Generation", SIGGRAPH 1988.
//! - J. R. Wallace, K. A. Elmquist, E. A. Haines, "A Ray Tracing Algorithm for
//!   Progressive Radiosity", SIGGRAPH 1989.
//! - J. H. Lambert, *Photometria*, 1760 (the exact polygon form factor).
//! - J. Arvo, "The Irradiance Jacobian for Partially Occluded Polyhedral
//!   Sources", SIGGRAPH 1994 (the form factor's gradient).
//! - P. Arquès, V. Biri, S. Derpierre, "A new formulation of differential
//!   radiosity and a rendering application", WSCG 2005 (the small-disc emitter
//!   model and its maximum; the contour mesher to come).
//! - Y. Ylitie, T. Karras, S. Laine, "Efficient Incoherent Ray Traversal on
//!   GPUs Through Compressed Wide BVHs", HPG 2017 (obvhs's CWBVH).
//! - P. Hanrahan, D. Salzman, L. Aupperle, "A Rapid Hierarchical Radiosity
//!   Algorithm", SIGGRAPH 1991; L. Neumann, M. Feda, M. Kopp, W. Purgathofer,
//!   "A New Stochastic Radiosity Method for Highly Complex Scenes", EGWR
//!   1994; P. Bekaert, "Hierarchical and Stochastic Algorithms for
//!   Radiosity", KU Leuven 1999 (the patch shots along fixed lines).
//! - A. Willmott, P. Heckbert, M. Garland, "Face Cluster Radiosity", EGWR
//!   1999 (the clutter's small patches shot as clusters).

#![warn(missing_docs)]

mod error;
mod fixed_hash;
mod font;
mod freed_memory;
mod fs;
mod rgb;
mod union_find;

pub mod calculation;
pub mod daylight;
pub mod export;
pub mod lighting;
pub mod mesh;
pub mod meshing;
pub mod phase;
pub mod photometry;
pub mod radiometry;
pub mod render;
pub mod scene;
pub mod solver;
pub mod study;
pub mod view;

// The five steps: load, settings, solve, query, render and export.
pub use error::{Error, Result};
pub use export::export_solution;
pub use meshing::{Length, MeshKind, MeshSettings};
pub use phase::{Phase, PhaseProgress};
pub use render::{Image, RenderSettings, ToneMap, write_exr, write_png};
pub use rgb::Rgb;
pub use scene::{Camera, LoadedScene, Material, Scene, SurfaceId, load_scene};
pub use solver::{
    Ambient, Probe, ProbeMode, Progress, Settings, Solution, Solver, SolverSettings, StopReason,
    Until,
};

/// Helpers that exist for isorad's tests, fuzz targets and benchmarks:
/// polygon predicates and element counts. Not part of the supported API;
/// they may change without notice.
#[doc(hidden)]
pub mod internals {
    pub use crate::mesh::meshers::budget::estimate_square_elements;
    pub use crate::scene::geometry::plane_polygon::{distance_to_boundary, polygon_contains};
    pub use crate::scene::geometry::polygon::{PolygonPlane, best_fit_plane};
    pub use crate::scene::geometry::triangulate::triangulate_polygon;
    pub use crate::scene::surface::newell_normal;
}
