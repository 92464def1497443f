//! Flags shared by commands: what to solve and the settings overrides, the
//! enums they name, and how a flag's invalid value is reported.

use std::path::Path;
use std::time::Instant;

use clap::{Args, ValueEnum};
use isorad::{
    Length, MeshKind, ProbeMode, Settings, Solver,
    scene::{LoadSettings, SceneOptions, load_scene_with},
    solver::FormFactorKernel,
};

use crate::progress::PhaseBars;

/// What to solve, and how: shared by `render` and `probe`.
#[derive(Args)]
pub struct SolveArgs {
    /// A scene file (.toml), an OBJ file, or a built-in scene name.
    #[arg(default_value = "cornell")]
    pub scene: String,
    #[command(flatten)]
    pub overrides: Overrides,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    /// Keep adjacent coplanar faces apart (by default they are merged into
    /// polygons when loading).
    #[arg(long)]
    pub no_merge: bool,
    /// Stop the solve once the command has run this long (loading and
    /// meshing count); the ambient term stands in for the light not yet
    /// shot, as after Ctrl-C, and the outputs are written.
    #[arg(long, value_name = "SECONDS", value_parser = crate::stop::parse_time_limit, allow_hyphen_values = true)]
    pub time_limit: Option<f64>,
}

/// Flags that override the scene file's settings, each onto one field of
/// [`Settings`].
#[derive(Args)]
pub struct Overrides {
    /// Stop when unshot power < TOLERANCE × emitted power [default: 0.05];
    /// a closed room's unshot power counts at --closed-zone-weight.
    #[arg(long)]
    tolerance: Option<f64>,
    /// How much a closed room's unshot power counts toward --tolerance
    /// [default: 0.1; a closed room stops at ten times --tolerance, half
    /// unshot at 0.05]; 1 holds
    /// every room to the tolerance.
    #[arg(long, value_name = "WEIGHT")]
    closed_zone_weight: Option<f64>,
    /// Then shoot what is left patch to patch until unshot power <
    /// FRACTION × emitted power, every room counted in full [default:
    /// 0.0001]; 1 shoots none.
    #[arg(long, value_name = "FRACTION")]
    patch_tolerance: Option<f64>,
    /// At most this many sweeps over the vertices resolve the ambient
    /// term's further bounces where its rays land [default: 16; they stop
    /// once it changes by under 0.5 %]; 0 keeps each patch's mean.
    #[arg(long, value_name = "COUNT")]
    ambient_sweeps: Option<usize>,
    /// Form-factor kernel: mixed (default), wallace or exact.
    #[arg(long, value_enum, value_name = "KERNEL")]
    form_factor: Option<KernelArg>,
    /// Receive a dim reflected shot at a few vertices of each patch and
    /// interpolate it to the others where its bound is at most this
    /// fraction of the light a vertex already has [default: 0.01]; 0
    /// gathers every shot at every vertex.
    #[arg(long, value_name = "FRACTION")]
    coarse_reception: Option<f64>,
    /// Mesher: square, contour (the radial contour-level mesher on
    /// receivers lit by a dominant small emitter, square elsewhere), or
    /// adaptive (a coarser grid whose elements split while solving where the
    /// light changes).
    #[arg(long, value_enum)]
    mesh: Option<MeshArg>,
    /// Adaptive mesher: split an element when the jump of the radiosity
    /// gradient across it times its size exceeds this fraction of its mean.
    #[arg(long, value_name = "FRACTION")]
    refine_threshold: Option<f64>,
    /// Adaptive mesher: how many times an element may be halved.
    #[arg(long, value_name = "N")]
    refine_levels: Option<u32>,
    /// Contour mesher: D, rays from the light's maximum.
    #[arg(long)]
    directions: Option<usize>,
    /// Contour mesher: K, contour levels (the fewest, unless
    /// --contour-error is 0).
    #[arg(long)]
    levels: Option<usize>,
    /// Contour mesher: the relative interpolation error to mesh the light
    /// to, adding levels and rays where it needs them [default: 0.01]; 0
    /// lays out exactly --directions × --levels.
    #[arg(long, value_name = "FRACTION")]
    contour_error: Option<f64>,
    /// Longest element edge, in scene units.
    #[arg(long)]
    max_edge: Option<f64>,
    /// N × N elements on every quad instead of --max-edge.
    #[arg(long)]
    elements_per_side: Option<usize>,
    /// Refuse to mesh when the mesh would have more elements than this
    /// (counted before meshing, so absurd settings fail at once) [default:
    /// 5000000, or the scene file's `[mesh] max_elements`].
    #[arg(long)]
    max_elements: Option<usize>,
    /// Mesh without element edges along the shadow boundaries the lights
    /// cast (discontinuity meshing, on by default).
    #[arg(long)]
    no_shadow_boundaries: bool,
    /// The most shadow boundaries one receiver gets, longest first
    /// [default: 256, or the scene file's `[mesh] max_shadow_boundaries`].
    #[arg(long, value_name = "N")]
    max_shadow_boundaries: Option<usize>,
}

impl Overrides {
    /// Sets every field whose flag was given, then validates; an invalid
    /// value from a flag is named by the flag.
    pub fn apply(&self, settings: &mut Settings) -> anyhow::Result<()> {
        let (mesh, solver) = (&mut settings.mesh, &mut settings.solver);
        if let Some(tolerance) = self.tolerance {
            solver.tolerance = tolerance;
        }
        if let Some(weight) = self.closed_zone_weight {
            solver.closed_zone_weight = weight;
        }
        if let Some(fraction) = self.patch_tolerance {
            solver.patch_tolerance = fraction;
        }
        if let Some(sweeps) = self.ambient_sweeps {
            solver.ambient_sweeps = sweeps;
        }
        if let Some(kernel) = self.form_factor {
            solver.kernel = kernel.into();
        }
        if let Some(fraction) = self.coarse_reception {
            solver.coarse_reception = fraction;
        }
        if let Some(kind) = self.mesh {
            mesh.kind = kind.into();
        }
        if let Some(threshold) = self.refine_threshold {
            mesh.refinement.threshold = threshold;
        }
        if let Some(levels) = self.refine_levels {
            mesh.refinement.max_levels = levels;
        }
        if let Some(directions) = self.directions {
            mesh.contour.directions = directions;
        }
        if let Some(levels) = self.levels {
            mesh.contour.levels = levels;
        }
        if let Some(error) = self.contour_error {
            mesh.contour.max_relative_error = error;
        }
        if let Some(max_edge) = self.max_edge {
            mesh.max_edge = Length::Absolute(max_edge);
        }
        if self.elements_per_side.is_some() {
            mesh.elements_per_side = self.elements_per_side;
        }
        if let Some(max_elements) = self.max_elements {
            mesh.max_elements = max_elements;
        }
        if self.no_shadow_boundaries {
            mesh.shadow_boundaries = false;
        }
        if let Some(count) = self.max_shadow_boundaries {
            mesh.max_shadow_boundaries = count;
        }
        settings
            .validate()
            .map_err(|error| with_flag_names(error, &self.given()))
    }

    /// The flags given, each with the field path of the setting it sets.
    fn given(&self) -> Vec<(&'static str, &'static str)> {
        [
            ("--tolerance", "solver.tolerance", self.tolerance.is_some()),
            (
                "--closed-zone-weight",
                "solver.closed_zone_weight",
                self.closed_zone_weight.is_some(),
            ),
            (
                "--patch-tolerance",
                "solver.patch_tolerance",
                self.patch_tolerance.is_some(),
            ),
            (
                "--ambient-sweeps",
                "solver.ambient_sweeps",
                self.ambient_sweeps.is_some(),
            ),
            (
                "--coarse-reception",
                "solver.coarse_reception",
                self.coarse_reception.is_some(),
            ),
            (
                "--refine-threshold",
                "mesh.refinement.threshold",
                self.refine_threshold.is_some(),
            ),
            (
                "--refine-levels",
                "mesh.refinement.max_levels",
                self.refine_levels.is_some(),
            ),
            (
                "--directions",
                "mesh.contour.directions",
                self.directions.is_some(),
            ),
            ("--levels", "mesh.contour.levels", self.levels.is_some()),
            (
                "--contour-error",
                "mesh.contour.max_relative_error",
                self.contour_error.is_some(),
            ),
            ("--max-edge", "mesh.max_edge", self.max_edge.is_some()),
            (
                "--elements-per-side",
                "mesh.elements_per_side",
                self.elements_per_side.is_some(),
            ),
            (
                "--max-elements",
                "mesh.max_elements",
                self.max_elements.is_some(),
            ),
            (
                "--max-shadow-boundaries",
                "mesh.max_shadow_boundaries",
                self.max_shadow_boundaries.is_some(),
            ),
        ]
        .into_iter()
        .filter(|&(_, _, given)| given)
        .map(|(flag, field, _)| (flag, field))
        .collect()
    }
}

/// A library error in the command line's words: an invalid setting that one
/// of `flags` (flag, field path) set is named by the flag, and a mesh over
/// the element budget names the flags that change it.
pub fn with_flag_names(error: isorad::Error, flags: &[(&str, &str)]) -> anyhow::Error {
    match error {
        isorad::Error::InvalidSetting { name, message } => {
            match flags.iter().find(|&&(_, field)| field == name) {
                Some((flag, _)) => anyhow::anyhow!("invalid value for {flag}: {message}"),
                None => isorad::Error::InvalidSetting { name, message }.into(),
            }
        }
        isorad::Error::MeshTooLarge {
            estimate,
            limit,
            max_edge,
            diagonal,
        } => anyhow::anyhow!(
            "the mesh would have about {estimate:.0} elements, more than --max-elements {limit} \
             (elements of edge {max_edge:.3e} on a scene {diagonal:.3e} across); use a larger \
             --max-edge (`[mesh] max_edge`) or fewer --elements-per-side, or raise \
             --max-elements (`[mesh] max_elements`) if this machine can hold and solve that many"
        ),
        other => other.into(),
    }
}

/// A clap value enum mirroring a library enum variant for variant, and its
/// conversion into that enum.
macro_rules! value_enum {
    ($(#[$meta:meta])* $name:ident => $target:ident { $($variant:ident),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, ValueEnum)]
        pub enum $name {
            $(#[allow(missing_docs)] $variant),+
        }

        impl From<$name> for $target {
            fn from(value: $name) -> $target {
                match value {
                    $($name::$variant => $target::$variant),+
                }
            }
        }
    };
}

value_enum!(
    /// `--mesh`, as [`MeshKind`].
    MeshArg => MeshKind { Square, Contour, Adaptive }
);
value_enum!(
    /// `--form-factor`, as [`FormFactorKernel`].
    KernelArg => FormFactorKernel { Mixed, Wallace, Exact }
);
value_enum!(
    /// `probe --mode`, as [`ProbeMode`].
    ProbeModeArg => ProbeMode { Gather, Mesh }
);

/// A loaded and meshed scene, ready to solve.
pub struct Prepared {
    pub solver: Solver,
    /// When the command began preparing: `--time-limit` counts from here.
    pub started: Instant,
    /// The progress bars of the phases outside the shots, and their times.
    pub phases: PhaseBars,
    /// Where the scene came from, for messages.
    pub source: String,
}

/// Loads and meshes a scene: the scene file's settings, then the flags.
pub fn prepare(args: &SolveArgs) -> anyhow::Result<Prepared> {
    prepare_adjusted(args, |_| Ok(()))
}

/// [`prepare`], with the scene changed by `adjust` before it is meshed.
pub fn prepare_adjusted(
    args: &SolveArgs,
    adjust: impl FnOnce(&mut isorad::Scene) -> anyhow::Result<()>,
) -> anyhow::Result<Prepared> {
    let started = Instant::now();
    let mut load_settings = LoadSettings::default();
    load_settings.merge_coplanar = !args.no_merge;
    let mut loaded = load_scene_with(&args.scene, &load_settings)?;
    adjust(&mut loaded.scene)?;
    for warning in &loaded.scene.warnings {
        eprintln!("warning: {}", warning.message);
    }
    let settings = settings_from(&args.overrides, &loaded.options)?;
    let contour = settings.mesh.kind == MeshKind::Contour;
    let phases = PhaseBars::new(args.quiet);
    let report = |progress| phases.report(progress);
    let solver = Solver::new_with_progress(loaded.scene, settings, &report)
        .map_err(|error| with_flag_names(error, &args.overrides.given()));
    phases.finish();
    let solver = solver?;
    let analysis = solver.mesh_analysis();
    if contour {
        eprintln!(
            "contour mesher on {} of {} receivers: {} radial, {} along level lines ({} vertices placed in {} Newton iterations)",
            analysis.contour_surfaces.len() + analysis.level_line_surfaces.len(),
            analysis.receivers.len(),
            analysis.contour_surfaces.len(),
            analysis.level_line_surfaces.len(),
            analysis.newton_solves,
            analysis.newton_iterations
        );
    }
    if analysis.shadow_boundaries > 0 {
        eprintln!(
            "shadow boundaries: {} on {} receivers",
            analysis.shadow_boundaries, analysis.shadow_receivers
        );
    }
    if solver.closed_zones() > 1 {
        eprintln!(
            "closed zones: {} (shots skip the receivers of the others)",
            solver.closed_zones()
        );
    }
    Ok(Prepared {
        solver,
        started,
        phases,
        source: loaded.source,
    })
}

/// The library's settings: its defaults, then the scene file's, then the
/// flags given.
fn settings_from(overrides: &Overrides, options: &SceneOptions) -> anyhow::Result<Settings> {
    let mut settings = Settings::from_scene_options(options)?;
    overrides.apply(&mut settings)?;
    Ok(settings)
}

/// Fails unless the directory that would hold `path` exists.
pub fn ensure_directory_exists(path: &Path) -> anyhow::Result<()> {
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    anyhow::ensure!(
        parent.is_dir(),
        "{}: cannot write: directory {} does not exist",
        path.display(),
        parent.display()
    );
    Ok(())
}
