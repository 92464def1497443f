//! `isorad info`: a scene's area lights and, per receiver, its dominant
//! light and the mesher it would get.

use std::io::Write;

use clap::Args;
use glam::DVec2;
use isorad::lighting::Portals;
use isorad::{
    MeshSettings, Scene, SurfaceId,
    lighting::{AreaLight, ContourMesher, ReceiverAnalysis, area_lights},
    load_scene,
    meshing::{ReceiverSurvey, survey_receivers},
    photometry::LUMENS_PER_WATT,
    scene::Visibility,
};

use crate::args::with_flag_names;
use crate::daylight_report::daylight_lines;
use crate::progress::PhaseBars;
use crate::table::{significant, write_table};

#[derive(Args)]
pub struct InfoArgs {
    /// A scene file (.toml), an OBJ file, or a built-in scene name.
    #[arg(default_value = "cornell")]
    scene: String,
    /// A luminaire dominates a receiver from this share of its direct light
    /// [default: 0.6, or the scene file's `[mesh.dominance] min_share`].
    #[arg(long)]
    min_share: Option<f64>,
    /// A dominant luminaire is small under this radius / distance [default:
    /// 0.25, or the scene file's `[mesh.dominance] max_size_ratio`].
    #[arg(long)]
    max_size_ratio: Option<f64>,
    /// No progress bars.
    #[arg(long, short)]
    quiet: bool,
}

/// Prints the scene's area lights and the dominant-emitter analysis of each
/// receiver, as aligned text tables on stdout. The analysis takes the scene
/// file's `[mesh.dominance]`, then the flags.
pub fn info(args: &InfoArgs) -> anyhow::Result<()> {
    let loaded = load_scene(&args.scene)?;
    let mesh_settings = MeshSettings::from_scene_options(&loaded.options)?;
    let mut settings = mesh_settings.dominance.clone();
    let mut flags = Vec::new();
    if let Some(min_share) = args.min_share {
        settings.min_share = min_share;
        flags.push(("--min-share", "min_share"));
    }
    if let Some(max_size_ratio) = args.max_size_ratio {
        settings.max_size_ratio = max_size_ratio;
        flags.push(("--max-size-ratio", "max_size_ratio"));
    }
    settings
        .validate()
        .map_err(|error| with_flag_names(error, &flags))?;
    let scene = &loaded.scene;
    for warning in &scene.warnings {
        eprintln!("warning: {}", warning.message);
    }
    let visibility = Visibility::new(scene);
    let lights = area_lights(scene);
    let phases = PhaseBars::new(args.quiet);
    let report = |progress| phases.report(progress);
    let mesh_settings = mesh_settings.resolve(scene);
    let ReceiverSurvey {
        analyses,
        boundaries,
    } = survey_receivers(
        scene,
        &visibility,
        &lights,
        &settings,
        &mesh_settings,
        &report,
    );
    phases.finish();
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    writeln!(
        out,
        "{}: {} surfaces, {} luminaire(s), {} photometric luminaire(s), {} receivers\n",
        loaded.source,
        scene.surfaces.len(),
        lights.len(),
        scene.luminaires.len(),
        analyses.len()
    )?;
    for line in daylight_lines(scene, &Portals::of_scene(scene)) {
        writeln!(out, "{line}")?;
    }
    let header = ["luminaire", "surfaces", "area", "radius", "exitance (W/m²)"];
    write_table(&mut out, &header, &area_light_rows(&lights))?;
    writeln!(out)?;
    if !scene.luminaires.is_empty() {
        // Luminous flux: the radiant power's luminance at 179 lm/W.
        let rows: Vec<Vec<String>> = scene
            .luminaires
            .iter()
            .enumerate()
            .map(|(k, l)| {
                let p = l.position;
                vec![
                    format!("p{k}"),
                    l.name.clone(),
                    format!(
                        "{} {} {}",
                        significant(p.x),
                        significant(p.y),
                        significant(p.z)
                    ),
                    significant(l.power().luminance() * LUMENS_PER_WATT),
                ]
            })
            .collect();
        let header = ["photometric luminaire", "file", "position", "flux (lm)"];
        write_table(&mut out, &header, &rows)?;
        writeln!(out)?;
    }
    let header = [
        "receiver",
        "name",
        "area",
        "dominant",
        "share %",
        "size ratio",
        "mesher",
        "shadow boundaries",
    ];
    write_table(
        &mut out,
        &header,
        &receiver_rows(scene, lights.len(), &analyses, &boundaries),
    )?;
    out.flush()?;
    Ok(())
}

/// One row per area light: index, surfaces, area, radius, exitance.
fn area_light_rows(lights: &[AreaLight]) -> Vec<Vec<String>> {
    lights
        .iter()
        .enumerate()
        .map(|(index, light)| {
            let surfaces: Vec<String> = light.surfaces.iter().map(SurfaceId::to_string).collect();
            let e = light.exitance;
            vec![
                index.to_string(),
                surfaces.join(","),
                significant(light.area),
                significant(light.radius),
                format!("{:.3} {:.3} {:.3}", e.r, e.g, e.b),
            ]
        })
        .collect()
}

/// One row per receiver: index, name, area, dominant light (an area
/// light's index among the `lights`, or `p` and a photometric luminaire's), share,
/// size ratio, mesher, shadow boundaries.
fn receiver_rows(
    scene: &Scene,
    lights: usize,
    analyses: &[ReceiverAnalysis],
    boundaries: &[Vec<[DVec2; 2]>],
) -> Vec<Vec<String>> {
    analyses
        .iter()
        .map(|analysis| {
            let surface = scene.surface(analysis.receiver);
            let ratio = if analysis.size_ratio.is_finite() {
                format!("{:.3}", analysis.size_ratio)
            } else {
                "-".to_owned()
            };
            let mesher = match analysis.contour_mesher() {
                ContourMesher::Radial => "radial",
                ContourMesher::LevelLines => "level-lines",
                ContourMesher::Square => "square",
            };
            vec![
                analysis.receiver.to_string(),
                surface.name.clone(),
                significant(surface.area()),
                analysis.dominant.map_or("-".to_owned(), |d| {
                    // Photometric luminaires follow the area ones, as `p0`, `p1`, ….
                    if d < lights {
                        d.to_string()
                    } else {
                        format!("p{}", d - lights)
                    }
                }),
                format!("{:.1}", 100.0 * analysis.share),
                ratio,
                mesher.to_owned(),
                boundaries[analysis.receiver.index()].len().to_string(),
            ]
        })
        .collect()
}
