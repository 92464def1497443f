//! Draws the Cornell box's floor as three meshes solve it — square at 1/40
//! of the diagonal, adaptive from that grid, square at 1/60 — shaded with
//! each mesh's radiosity and wireframed, into `docs/adaptive_floor.png`
//! (or the path given as the first argument).
//!
//! ```sh
//! cargo run --release --example adaptive_floor
//! ```

use std::path::PathBuf;

use glam::DVec2;
use isorad::{
    Length, MeshKind, Settings, Solver, load_scene,
    study::{MeshPanel, write_mesh_panels},
};

/// The floor of a solved Cornell box as a panel: vertices in the floor's
/// plane, their radiosity (sum of channels), and the rendered triangles
/// (through the hanging vertices of refined neighbours).
fn floor_panel(title: &str, kind: MeshKind, fraction: f64) -> MeshPanel {
    let scene = load_scene("cornell").expect("built-in scene").scene;
    let mut settings = Settings::default();
    settings.mesh.kind = kind;
    settings.mesh.max_edge = Length::OfDiagonal(fraction);
    let mut solver = Solver::new(scene, settings).expect("valid settings");
    solver.run();
    let (scene, mesh) = (solver.scene(), solver.mesh());
    let radiosity = solver.radiosity();
    let floor = scene.surface_named("floor").expect("a floor");
    let frame = scene.surface(floor).frame();
    let mut index = vec![usize::MAX; mesh.vertices.len()];
    let (mut points, mut values, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    let mut split = Vec::new();
    for element in mesh.elements.iter().filter(|e| e.surface == floor) {
        mesh.element_triangles(element, |_, _| 0.0, &mut split);
        for triangle in &split {
            triangles.push(triangle.map(|v| {
                let v = v as usize;
                if index[v] == usize::MAX {
                    index[v] = points.len();
                    points.push(frame.to_plane(mesh.vertices[v].position));
                    values.push(radiosity[v].element_sum());
                }
                index[v]
            }));
        }
    }
    let outline: Vec<DVec2> = scene.surface(floor).plane_vertices();
    MeshPanel {
        title: title.into(),
        points,
        values,
        triangles,
        outline,
    }
}

fn main() -> isorad::Result<()> {
    let path = std::env::args_os()
        .nth(1)
        .map_or_else(|| PathBuf::from("docs/adaptive_floor.png"), PathBuf::from);
    let panels = [
        floor_panel("square 1/40", MeshKind::Square, 1.0 / 40.0),
        floor_panel("adaptive from 1/40", MeshKind::Adaptive, 1.0 / 40.0),
        floor_panel("square 1/60", MeshKind::Square, 1.0 / 60.0),
    ];
    write_mesh_panels(&path, &panels, 480)?;
    println!("wrote {}", path.display());
    Ok(())
}
