//! isorad embedded in a program: a scene built in code, solved, read at a
//! point and rendered to an image in memory, with no files.
//!
//! ```sh
//! cargo run --release --example embed
//! ```

use glam::DVec3;
use isorad::{
    Ambient, Camera, Material, ProbeMode, RenderSettings, Rgb, Scene, Settings, Solver,
    phase::silent, scene::ProbePoint,
};

fn main() -> isorad::Result<()> {
    // A 4 × 4 m floor under a 1 × 1 m light, 2 m up, facing down.
    let mut scene = Scene::new();
    let floor = scene.add_material(Material::diffuse("floor", Rgb::splat(0.5)))?;
    let lamp = scene.add_material(Material::emitter("lamp", Rgb::splat(10.0)))?;
    let quad = |y: f64, half: f64| {
        [(-1.0, -1.0), (-1.0, 1.0), (1.0, 1.0), (1.0, -1.0)]
            .map(|(x, z)| DVec3::new(x * half, y, z * half))
    };
    scene.add_polygon("floor", floor, &quad(0.0, 2.0))?; // faces up (+y)
    let mut light = quad(2.0, 0.5);
    light.reverse(); // faces down (−y)
    scene.add_polygon("light", lamp, &light)?;
    let mut camera = Camera::look_at(DVec3::new(0.0, 3.0, -5.0), DVec3::ZERO, DVec3::Y, 40.0);
    (camera.width, camera.height) = (256, 192);
    scene.set_camera(camera.clone());

    // Mesh, build the BVH and shoot to the preset's tolerance.
    let mut solver = Solver::new(scene, Settings::preview())?;
    let stop = solver.run();
    println!(
        "{stop:?} after {} shots, {} shadow rays; unshot {:.2} %",
        solver.stats().shots,
        solver.stats().rays,
        100.0 * solver.unshot_fraction()
    );

    // Irradiance under the light's centre, by a final gather, against the
    // exact unoccluded value: E_light × F for a square seen from its axis.
    let solution = solver.solution(Ambient::Everywhere, &silent);
    let centre = ProbePoint {
        position: DVec3::ZERO,
        normal: None,
        line: 1,
    };
    let probe = solution.probe(&centre, ProbeMode::Gather)?;
    let exact = std::f64::consts::PI
        * 10.0
        * isorad::radiometry::polygon_form_factor(DVec3::ZERO, DVec3::Y, &light);
    println!(
        "irradiance under the light: {:.3} W/m² (exact {exact:.3}), radiosity {:.3} W/m²",
        probe.irradiance.r, probe.radiosity.r
    );
    assert!((probe.irradiance.r / exact - 1.0).abs() < 0.01);

    // Per-surface totals, and the image in memory.
    for (surface, totals) in solver
        .scene()
        .surfaces
        .iter()
        .zip(solution.surface_totals())
    {
        println!(
            "{:>6}: area {:.2} m², mean radiosity {:.3} W/m², received {:.3} W",
            surface.name, totals.area, totals.mean_radiosity.r, totals.received_power.r
        );
    }
    let image = solution.render(&camera, &RenderSettings::default());
    let mean = image.mean();
    println!(
        "rendered {}×{} pixels in memory, mean radiance {:.4} W/(m²·sr); write it with isorad::write_exr or write_png",
        image.width(),
        image.height(),
        mean.r
    );
    Ok(())
}
