//! The one error type of the library.

use std::path::PathBuf;

/// Everything that can go wrong when loading, solving or writing.
///
/// Each variant names the file, line, object or setting at fault, so that the
/// message alone tells a user what to fix.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// An OBJ file could not be parsed.
    #[error("{path}{}: {message}", line_suffix(*.line))]
    ObjParse {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line number, where known.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// An OBJ file names a material library that does not exist or cannot be read.
    #[error("{path}: material library `{mtl}` cannot be read: {message}")]
    MissingMtl {
        /// The OBJ file that names the library.
        path: PathBuf,
        /// The library as named in the OBJ file.
        mtl: String,
        /// Why it cannot be read.
        message: String,
    },
    /// A face uses a material that no material library defines, or no material at all.
    #[error(
        "{path}{}: object `{object}` {}",
        line_suffix(*.line),
        missing_material_phrase(material)
    )]
    MissingMaterial {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line of the `usemtl` (or of the first face without a material), where known.
        line: Option<usize>,
        /// The object or group whose faces use it.
        object: String,
        /// The missing material's name (empty when the faces have none).
        material: String,
    },
    /// A coordinate is NaN or infinite.
    #[error("{path}{}: object `{object}` has a non-finite coordinate", line_suffix(*.line))]
    NonFiniteCoordinate {
        /// The file.
        path: PathBuf,
        /// 1-based line number, where known.
        line: Option<usize>,
        /// The object holding the vertex.
        object: String,
    },
    /// A photometric file (IES LM-63, EULUMDAT) could not be read as a
    /// luminaire's intensity distribution.
    #[error("{path}{}: {message}", line_suffix(*.line))]
    Photometry {
        /// The photometric file.
        path: PathBuf,
        /// 1-based line number, where known.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// A material library (MTL file) could not be parsed.
    #[error("{path}{}: {message}", line_suffix(*.line))]
    MtlParse {
        /// The MTL file.
        path: PathBuf,
        /// 1-based line number, where known.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// A material's reflectance or emission is out of range.
    #[error("{path}{}: material `{material}`: {message}", line_suffix(*.line))]
    InvalidMaterial {
        /// The MTL (or OBJ) file.
        path: PathBuf,
        /// 1-based line of the offending statement, where known.
        line: Option<usize>,
        /// The material's name.
        material: String,
        /// What is wrong, with the offending value.
        message: String,
    },
    /// A scene file (TOML) is malformed or inconsistent.
    #[error("{path}: {message}")]
    SceneFile {
        /// The scene file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A scene file's `[[luminaire]]` table holds a value isorad cannot
    /// use, or names a photometric file that cannot be read or parsed
    /// (whose own error, with its file and line, is then the message).
    #[error("{path}:{line}: [[luminaire]] {index}: {key} = {value}: {message}")]
    SceneLuminaire {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the value in the scene file.
        line: usize,
        /// 1-based index of the table among the file's `[[luminaire]]`s.
        index: usize,
        /// The key at fault: `ies`, `position`, `aim`, `c0`, `multiplier`
        /// or `color`.
        key: String,
        /// Its value as the file gives it.
        value: String,
        /// What is wrong.
        message: String,
    },
    /// A scene file's `[sky]` or `[sun]` table holds a value isorad cannot
    /// use, or misses one it needs.
    #[error("{path}:{line}: [{table}] {key} = {value}: {message}")]
    SceneDaylight {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the value (of the table's header when the key
        /// is missing).
        line: usize,
        /// `sky` or `sun`.
        table: &'static str,
        /// The key at fault.
        key: String,
        /// Its value as the file gives it (`(missing)` when absent).
        value: String,
        /// What is wrong.
        message: String,
    },
    /// A scene name is neither a file nor a built-in scene.
    #[error("`{name}` is neither a readable file nor a built-in scene (built-in: {builtins})")]
    UnknownScene {
        /// The name given.
        name: String,
        /// The built-in scene names.
        builtins: String,
    },
    /// A scene has no usable surface, or no emitter.
    #[error("{path}: {message}")]
    EmptyScene {
        /// The file (or built-in name).
        path: PathBuf,
        /// What is missing.
        message: String,
    },
    /// A probe-points file is malformed, or one of its points lies on no surface.
    #[error("{path}:{line}: {message}")]
    ProbePoint {
        /// The points file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A setting is out of range.
    #[error("invalid setting `{name}`: {message}")]
    InvalidSetting {
        /// The setting's field path in [`crate::Settings`] (and in a scene
        /// file), such as `mesh.max_edge` or `solver.tolerance`; from a part
        /// validated on its own, such as [`crate::lighting::DominanceSettings`],
        /// the field's name in that part (`min_share`).
        name: String,
        /// What is wrong.
        message: String,
    },
    /// A scene file's `[mesh]` or `[solver]` table holds a value of the
    /// wrong type, an unknown key or a value out of range.
    #[error("{path}{}: invalid setting `{name}`: {message}", line_phrase(*.line))]
    SceneSetting {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the value (or key), where known.
        line: Option<usize>,
        /// The setting's field path, such as `mesh.refinement.threshold`.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// An image file could be opened but not decoded (malformed, or not the
    /// expected kind of image).
    #[error("{path}: cannot read image: {message}")]
    InvalidImage {
        /// The image file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A mesh would have more elements than [`crate::MeshSettings::max_elements`]
    /// allows: refused before any memory is spent on it.
    #[error(
        "the mesh would have about {estimate:.0} elements, more than the {limit} that \
         `mesh.max_elements` allows (elements of edge {max_edge:.3e} on a scene {diagonal:.3e} \
         across); use a larger `mesh.max_edge` or fewer `mesh.elements_per_side`, or raise \
         `mesh.max_elements` if this machine can hold and solve that many"
    )]
    MeshTooLarge {
        /// Elements the settings would make.
        estimate: f64,
        /// The limit in force.
        limit: usize,
        /// The requested element edge, scene units.
        max_edge: f64,
        /// The scene's bounding diagonal, scene units.
        diagonal: f64,
    },
    /// An output image or file could not be encoded.
    #[error("{path}: cannot write: {message}")]
    Output {
        /// The output file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

fn line_suffix(line: Option<usize>) -> String {
    line.map(|l| format!(":{l}")).unwrap_or_default()
}

/// ": line N", as scene-file messages say it.
fn line_phrase(line: Option<usize>) -> String {
    line.map(|l| format!(": line {l}")).unwrap_or_default()
}

impl Error {
    /// An [`Error::InvalidSetting`] with its name put under `table` (so
    /// `min_share` becomes `mesh.dominance.min_share`); other errors as
    /// they are.
    #[must_use]
    pub(crate) fn within(self, table: &str) -> Error {
        match self {
            Error::InvalidSetting { name, message } => Error::InvalidSetting {
                name: format!("{table}.{name}"),
                message,
            },
            other => other,
        }
    }
}

fn missing_material_phrase(material: &str) -> String {
    if material.is_empty() {
        "has faces without a material (no `usemtl` before them)".to_owned()
    } else {
        format!("uses material `{material}`, which no MTL file defines")
    }
}

/// The library's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
