//! `isorad compare`: contour meshes (radial, and level lines) and greedy
//! insertion against square meshes on the receivers the contour meshers take.

use std::path::{Path, PathBuf};

use clap::Args;
use isorad::{
    MeshSettings, Scene, SurfaceId,
    lighting::{ContourMesher, ReceiverAnalysis, analyse_receivers, area_lights, dominant_field},
    load_scene,
    scene::Visibility,
    study::{
        CompareSettings, MeshRecord, MeshSpec, ReceiverComparison, compare_receiver,
        panels_for_figure, write_json, write_loglog_plot, write_mesh_panels,
    },
};

use crate::args::ensure_directory_exists;

#[derive(Args)]
pub struct CompareArgs {
    /// A scene file (.toml), an OBJ file, or a built-in scene name.
    scene: String,
    /// Only this receiver (its OBJ object name), even if it does not qualify.
    #[arg(long)]
    receiver: Option<String>,
    /// Write one JSON record per mesh.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write the meshes side by side: square 10×10 | contour 20×5 |
    /// shadow-aware contour 20×5 | contour ε 1 % | level lines ε 1 % |
    /// greedy ≤ 300 vertices | square 30×30 (those measured).
    #[arg(long)]
    image: Option<PathBuf>,
    /// Write log–log plots of error against vertices (.png or .svg): the
    /// RMS error to this file, the mean relative error to FILE_mean.
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Error grid: N × N points over the receiver (at least 200).
    #[arg(long, default_value_t = 400)]
    grid: usize,
}

pub fn compare(args: &CompareArgs) -> anyhow::Result<()> {
    for path in [&args.json, &args.image, &args.plot].into_iter().flatten() {
        ensure_directory_exists(path)?;
    }
    let loaded = load_scene(&args.scene)?;
    // The scene file's [mesh.dominance] decides which receivers qualify, as
    // for `isorad info` and `render --mesh contour`.
    let mesh = MeshSettings::from_scene_options(&loaded.options)?;
    let dominance = mesh.dominance.clone();
    let scene = &loaded.scene;
    let visibility = Visibility::new(scene);
    let lamps = area_lights(scene);
    let analyses = analyse_receivers(scene, &visibility, &lamps, &dominance);
    let chosen = receivers_to_compare(scene, &analyses, args.receiver.as_deref());
    if chosen.is_empty() {
        anyhow::bail!(
            "{}: no receiver {}",
            loaded.source,
            match &args.receiver {
                Some(name) => format!("named `{name}` is lit by a luminaire"),
                None => "is lit directly (see `isorad info`)".into(),
            }
        );
    }
    let mut settings = CompareSettings::default();
    settings.grid = args.grid.max(200);
    settings.mesh = mesh;
    let mut comparisons = Vec::new();
    for (receiver, lights) in chosen {
        // Area lights, then photometric luminaires after them.
        let fields: Vec<_> = lights
            .iter()
            .filter_map(|&k| dominant_field(scene, receiver, &lamps, k))
            .collect();
        if !fields.is_empty() {
            let comparison = compare_receiver(scene, &visibility, receiver, &fields, &settings);
            print_comparison(&comparison);
            comparisons.push(comparison);
        }
    }
    if let Some(path) = &args.json {
        write_json(&comparisons, path)?;
    }
    write_pictures(args, &comparisons)
}

/// The receivers to compare, each with the lights to mesh for: the
/// dominant small luminaire of a receiver the radial mesher takes, or every
/// light of one meshed along level lines; only the one named `only` (if
/// any light reaches it), or every receiver the contour meshers take.
fn receivers_to_compare(
    scene: &Scene,
    analyses: &[ReceiverAnalysis],
    only: Option<&str>,
) -> Vec<(SurfaceId, Vec<usize>)> {
    analyses
        .iter()
        .filter(|analysis| match only {
            Some(name) => scene.surface(analysis.receiver).name == name,
            None => analysis.contour_mesher() != ContourMesher::Square,
        })
        .map(|analysis| (analysis.receiver, analysis.contour_lights()))
        .filter(|(_, lights)| !lights.is_empty())
        .collect()
}

/// The `--image` and `--plot` pictures of every comparison, one file per
/// receiver when there are several.
fn write_pictures(args: &CompareArgs, comparisons: &[ReceiverComparison]) -> anyhow::Result<()> {
    for comparison in comparisons {
        let several = comparisons.len() > 1;
        if let Some(path) = &args.image {
            write_mesh_panels(
                &per_receiver(path, &comparison.receiver, several),
                &panels_for_figure(comparison),
                480,
            )?;
        }
        if let Some(path) = &args.plot {
            let path = per_receiver(path, &comparison.receiver, several);
            let plots: [(PathBuf, &str, ErrorMeasure); 2] = [
                (path.clone(), "RMS relative error", |r| r.rms_rel_error),
                (
                    with_suffix(&path, "_mean"),
                    "mean relative error (B > 1 % of max)",
                    |r| r.mean_rel_error,
                ),
            ];
            for (file, measure_name, measure) in plots {
                let title = format!(
                    "{}: {measure_name} of Gouraud interpolation",
                    comparison.receiver
                );
                let series = comparison.plot_series(measure);
                write_loglog_plot(&file, &title, "vertices", measure_name, &series)?;
            }
        }
    }
    Ok(())
}

/// `out.png` → `out_floor.png` when several receivers are written.
fn per_receiver(path: &Path, receiver: &str, several: bool) -> PathBuf {
    if !several {
        return path.to_path_buf();
    }
    let safe: String = receiver
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    with_suffix(path, &format!("_{safe}"))
}

/// `out.png` → `out{suffix}.png`.
fn with_suffix(path: &Path, suffix: &str) -> PathBuf {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let extension = path
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    path.with_file_name(format!("{stem}{suffix}{extension}"))
}

/// One error figure of a measured mesh.
type ErrorMeasure = fn(&MeshRecord) -> f64;

/// A table of the records, and the vertex ratios at equal error: RMS, and
/// the mean relative error a tone-mapped picture shows.
fn print_comparison(comparison: &ReceiverComparison) {
    println!("receiver {}:", comparison.receiver);
    print_records(comparison);
    let measures: [(&str, ErrorMeasure); 2] = [
        ("RMS error", |r| r.rms_rel_error),
        ("mean relative error (B > 1 % of max)", |r| r.mean_rel_error),
    ];
    for (name, measure) in measures {
        print_square_ratios(comparison, name, measure);
        // Square 30 × 30, the seed paper's reference mesh: the vertices the
        // contour meshes need for its error, along their lower envelope.
        let reference = MeshSpec::Square { n: 30 };
        if let Some(square) = comparison.record(reference) {
            print_against_reference(comparison, square, name, measure);
            print_each_mesher(comparison, square, measure);
        }
    }
}

/// One line per measured mesh.
fn print_records(comparison: &ReceiverComparison) {
    println!(
        "  {:<14} {:>7} {:>9} {:>10} {:>12} {:>12} {:>13} {:>9}",
        "mesher",
        "params",
        "vertices",
        "triangles",
        "rms_rel_err",
        "max_rel_err",
        "mean_rel_err",
        "seconds"
    );
    for record in &comparison.records {
        println!(
            "  {:<14} {:>7} {:>9} {:>10} {:>12.5} {:>12.5} {:>13.5} {:>9.4}",
            record.spec.mesher(),
            record.spec.size(),
            record.vertex_count(),
            record.triangle_count(),
            record.rms_rel_error,
            record.max_rel_error,
            record.mean_rel_error,
            record.seconds
        );
    }
}

/// For each contour mesh, the square mesh vertices the same error needs
/// (by `measure`, called `name`): the median ratio and its range. The
/// seed's layouts are counted once (not again with the shadow boundaries,
/// which on a receiver they barely touch would repeat them).
fn print_square_ratios(comparison: &ReceiverComparison, name: &str, measure: ErrorMeasure) {
    let mut ratios: Vec<f64> = comparison
        .records
        .iter()
        .filter(|r| r.spec.is_contour() && !matches!(r.spec, MeshSpec::ShadowContour { .. }))
        .filter_map(|r| {
            comparison
                .vertices_for_measure(MeshSpec::is_square, measure, measure(r))
                .map(|v| v / r.vertex_count() as f64)
        })
        .collect();
    if ratios.is_empty() {
        println!("  (no contour or greedy mesh falls within the square meshes' range of {name})");
    } else {
        ratios.sort_by(f64::total_cmp);
        println!(
            "  square meshes need {:.1}× (median; {:.1}× to {:.1}×) the contour and greedy meshes' vertices for the same {name}",
            ratios[ratios.len() / 2],
            ratios[0],
            ratios[ratios.len() - 1]
        );
    }
}

/// The vertices the contour and greedy meshes together need for the
/// error of `square` (the reference mesh), or where that error lies
/// beyond theirs.
fn print_against_reference(
    comparison: &ReceiverComparison,
    square: &MeshRecord,
    name: &str,
    measure: ErrorMeasure,
) {
    let reference = square.spec;
    let error = measure(square);
    match comparison.vertices_for_measure(MeshSpec::is_contour, measure, error) {
        Some(vertices) => println!(
            "  {reference}'s {name}, {error:.4}, takes the contour and greedy meshes {vertices:.0} vertices: {:.1}× fewer than its {}",
            square.vertex_count() as f64 / vertices,
            square.vertex_count()
        ),
        None => {
            let smallest = comparison
                .records
                .iter()
                .filter(|r| r.spec.is_contour())
                .min_by_key(|r| r.vertex_count());
            match smallest.filter(|r| measure(r) <= error) {
                Some(r) => println!(
                    "  {reference}'s {name}, {error:.4}, is above every contour and greedy mesh's: the smallest, {} with {} vertices, errs {:.4}",
                    r.spec,
                    r.vertex_count(),
                    measure(r)
                ),
                None => println!(
                    "  {reference}'s {name}, {error:.4}, is below every contour and greedy mesh's"
                ),
            }
        }
    }
}

/// [`print_against_reference`] for each mesher on its own.
fn print_each_mesher(comparison: &ReceiverComparison, square: &MeshRecord, measure: ErrorMeasure) {
    let error = measure(square);
    let mut meshers: Vec<&str> = Vec::new();
    for record in comparison.records.iter().filter(|r| r.spec.is_contour()) {
        if !meshers.contains(&record.spec.mesher()) {
            meshers.push(record.spec.mesher());
        }
    }
    for mesher in meshers {
        let of = |spec: &MeshSpec| spec.mesher() == mesher;
        let smallest = comparison
            .records
            .iter()
            .filter(|r| of(&r.spec))
            .min_by_key(|r| r.vertex_count());
        match (
            comparison.vertices_for_measure(of, measure, error),
            smallest,
        ) {
            (Some(vertices), _) => println!(
                "    {mesher}: {vertices:.0} vertices, {:.1}× fewer",
                square.vertex_count() as f64 / vertices
            ),
            (None, Some(r)) if measure(r) <= error => println!(
                "    {mesher}: its smallest, {} with {} vertices, errs {:.4}",
                r.spec,
                r.vertex_count(),
                measure(r)
            ),
            (None, _) => println!("    {mesher}: every mesh errs more"),
        }
    }
}
