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
//! A closed cube whose faces all emit E = π and reflect half: the radiosity
//! everywhere is E/(1 − ρ) = 2π.
//!
//! ```
//! use glam::DVec3;
//! use isorad::{Material, Rgb, Scene, Solver, SolverSettings, SquareMeshSettings, Surface, Visibility, mesh_square};
//!
//! let mut scene = Scene::default();
//! scene.materials.push(Material {
//!     name: "glowing wall".into(),
//!     reflectance: Rgb::splat(0.5),
//!     emitted_radiance: Rgb::splat(1.0),
//! });
//! // Six faces of the unit cube, counter-clockwise seen from inside.
//! let corner = |axis: usize, side: f64, s: f64, t: f64| {
//!     let mut p = [0.0; 3];
//!     p[axis] = side;
//!     p[(axis + 1) % 3] = s;
//!     p[(axis + 2) % 3] = t;
//!     DVec3::from_array(p)
//! };
//! for axis in 0..3 {
//!     let low = vec![corner(axis, 0.0, 0.0, 0.0), corner(axis, 0.0, 1.0, 0.0), corner(axis, 0.0, 1.0, 1.0), corner(axis, 0.0, 0.0, 1.0)];
//!     let high: Vec<DVec3> = low.iter().rev().map(|p| *p + DVec3::from_array({ let mut d = [0.0; 3]; d[axis] = 1.0; d })).collect();
//!     scene.surfaces.push(Surface::new("face", 0, low).unwrap());
//!     scene.surfaces.push(Surface::new("face", 0, high).unwrap());
//! }
//!
//! let mut mesh_settings = SquareMeshSettings::for_scene(&scene);
//! mesh_settings.max_edge = 0.125;
//! let mesh = mesh_square(&scene, &mesh_settings);
//! let visibility = Visibility::new(&scene);
//! let mut settings = SolverSettings::default();
//! settings.tolerance = 1e-3;
//! let mut solver = Solver::new(&scene, &mesh, &visibility, settings)?;
//! solver.run(|_| {});
//! for radiosity in solver.radiosity() {
//!     assert!((radiosity.x / (2.0 * std::f64::consts::PI) - 1.0).abs() < 0.01);
//! }
//! # Ok::<(), isorad::Error>(())
//! ```
//!
//! To load files instead, use [`load_scene`] with a scene TOML, an OBJ path or
//! the built-in name `"cornell"`; to look at the result, [`mesh_triangles`],
//! [`rasterize`], [`write_exr`] and [`write_png`]; to compare meshers,
//! [`write_loglog_plot`] (error against vertex count) and
//! [`write_mesh_panels`] (meshes side by side with their wireframes).
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

mod compare;
mod error;
mod mesh;
mod radiometry;
mod render;
mod scene;
mod solver;

pub use compare::{
    CompareSettings, ComparedMesh, MeshRecord, ReceiverComparison, compare_receiver,
    panels_for_figure, write_json,
};
pub use error::{Error, Result};
pub use mesh::{
    Cell, ContourLayout, ContourSettings, Element, ErrorGrid, InterpolationError, Mesh, MeshVertex,
    Patch, PlaneTriangulation, ScalarField, SquareMeshSettings, contour_layout,
    estimate_square_elements, interpolation_error, mesh_square, mesh_surfaces,
};
pub use radiometry::{
    DiscModel, ReceiverPlane, SmallDisc, TiltFrame, disc_form_factor, polygon_form_factor,
    polygon_form_factor_gradient, polygon_form_factor_with_gradient, tilt_line_maximum,
};
pub use render::{
    Image, MeshPanel, RenderSettings, Series, ShadedTriangle, ToneMap, auto_exposure,
    mesh_triangles, rasterize, read_exr, srgb_encode, write_exr, write_loglog_plot,
    write_mesh_panels, write_png,
};
pub use scene::{
    Camera, CameraFrame, LoadedScene, Material, PlaneFrame, PolygonPlane, ProbePoint, Rgb, Scene,
    SceneOptions, Surface, Visibility, Warning, best_fit_plane, builtin_names,
    distance_to_boundary, load_obj, load_probe_points, load_scene, load_scene_file, newell_normal,
    parse_probe_points, polygon_contains, triangulate_polygon,
};
pub use solver::{
    DirectField, DominanceSettings, EnergyBalance, FormFactorKernel, Luminaire, MeshKind,
    MeshSettings, Probe, ProbeMode, ReceiverAnalysis, SceneMesh, Solution, Solver, SolverSettings,
    analyse_receivers, luminaires, mesh_scene, receiver_layout,
};
