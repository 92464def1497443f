//! The records of a comparison, and their JSON form.

use glam::DVec2;
use std::fmt;
use std::path::Path;

use super::plot::Series;
use crate::error::{Error, Result};
use crate::mesh::{ErrorGrid, PlaneTriangulation};
use crate::scene::SurfaceId;

/// Which mesh of a receiver: the mesher and its size.
///
/// Shown as "square 10×10", "contour 20×5", "shadow-aware contour 20×5",
/// "contour ε 1.0 %", "level lines ε 1.0 %" or "greedy ≤ 300 vertices"; in
/// the records' JSON ([`MeshRecord`]) as `"mesher": "square"` with
/// `"params": {"n": 10}`, `"contour"` with `{"directions": 20, "levels": 5,
/// …}` or `{"max_relative_error": 0.01, …}`, `"shadow_contour"` with
/// `{"directions": 20, "levels": 5, …}`, `"level_lines"` with
/// `{"max_relative_error": 0.01, …}`, and `"greedy"` with
/// `{"max_vertices": 300}`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(tag = "mesher", content = "params", rename_all = "lowercase")]
pub enum MeshSpec {
    /// The square N × N mesh.
    Square {
        /// Divisions along each side.
        n: usize,
    },
    /// The radial contour-level mesh of D directions and K levels.
    Contour {
        /// D, the rays from the light's maximum.
        directions: usize,
        /// K, the iso-radiosity levels.
        levels: usize,
    },
    /// The radial contour-level mesh of D directions and K levels with the
    /// receiver's shadow boundaries as edges, each with vertices at its ends
    /// and where it crosses the layout's contour pieces: along a boundary
    /// the unoccluded field then changes by about one level step between
    /// vertices, as it does between the layout's rings.
    #[serde(rename = "shadow_contour")]
    ShadowContour {
        /// D, the rays from the light's maximum.
        directions: usize,
        /// K, the iso-radiosity levels.
        levels: usize,
    },
    /// The radial contour-level mesh refined to a relative interpolation
    /// error (`ContourSettings::max_relative_error`, from 16 × 8 up).
    #[serde(rename = "contour_to_error")]
    ContourToError {
        /// The error aimed for, in thousandths.
        per_mille: u32,
    },
    /// The level lines of the total direct field, to a relative error
    /// (`level_line_layout`).
    #[serde(rename = "level_lines")]
    LevelLines {
        /// The error aimed for, in thousandths.
        per_mille: u32,
    },
    /// Greedy insertion on the direct field sampled with visibility
    /// (`greedy_insertion`), to a vertex budget.
    #[serde(rename = "greedy")]
    Greedy {
        /// The most vertices the mesh may have.
        vertices: usize,
    },
}

impl MeshSpec {
    /// The mesher's name: "square", "contour", "shadow_contour",
    /// "level_lines" or "greedy".
    #[must_use]
    pub fn mesher(&self) -> &'static str {
        match self {
            MeshSpec::Square { .. } => "square",
            MeshSpec::Contour { .. } => "contour",
            MeshSpec::ContourToError { .. } => "contour",
            MeshSpec::ShadowContour { .. } => "shadow_contour",
            MeshSpec::LevelLines { .. } => "level_lines",
            MeshSpec::Greedy { .. } => "greedy",
        }
    }

    /// The size as a table shows it: "NxN", "DxK", "e1.0%" or "v300".
    #[must_use]
    pub fn size(&self) -> String {
        match *self {
            MeshSpec::Square { n } => format!("{n}x{n}"),
            MeshSpec::Contour { directions, levels }
            | MeshSpec::ShadowContour { directions, levels } => format!("{directions}x{levels}"),
            MeshSpec::ContourToError { per_mille } | MeshSpec::LevelLines { per_mille } => {
                format!("e{:.1}%", f64::from(per_mille) / 10.0)
            }
            MeshSpec::Greedy { vertices } => format!("v{vertices}"),
        }
    }

    /// True for a square mesh.
    #[must_use]
    pub fn is_square(&self) -> bool {
        matches!(self, MeshSpec::Square { .. })
    }

    /// True for every mesh that is compared with the square ones: the
    /// contour meshes (radial, of fixed size or refined to an error, or
    /// along level lines) and greedy insertion.
    #[must_use]
    pub fn is_contour(&self) -> bool {
        !self.is_square()
    }
}

impl fmt::Display for MeshSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            MeshSpec::Square { n } => write!(f, "square {n}×{n}"),
            MeshSpec::Contour { directions, levels } => {
                write!(f, "contour {directions}×{levels}")
            }
            MeshSpec::ShadowContour { directions, levels } => {
                write!(f, "shadow-aware contour {directions}×{levels}")
            }
            MeshSpec::ContourToError { per_mille } => {
                write!(f, "contour ε {:.1} %", f64::from(per_mille) / 10.0)
            }
            MeshSpec::LevelLines { per_mille } => {
                write!(f, "level lines ε {:.1} %", f64::from(per_mille) / 10.0)
            }
            MeshSpec::Greedy { vertices } => write!(f, "greedy ≤ {vertices} vertices"),
        }
    }
}

/// One mesh of one receiver, measured: the mesh itself, its exact vertex
/// values and its errors.
///
/// Serialized as one record of [`write_json`]: `receiver`, `mesher`,
/// `params` (`{"n"}`, `{"directions", "levels", "newton_iterations",
/// "shadow_points"}`, `{"max_relative_error", "newton_iterations",
/// "shadow_points"}` or `{"max_vertices"}`), `vertices`, `triangles`, `rms_rel_error`,
/// `max_rel_error`, `mean_rel_error`, `seconds`.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshRecord {
    /// The receiver's name (its OBJ object).
    pub receiver: String,
    /// Which mesh.
    pub spec: MeshSpec,
    /// Newton iterations spent placing a contour mesh's vertices (0 for a
    /// square mesh).
    pub newton_iterations: usize,
    /// A contour mesh's vertices added on and beside shadow boundaries (0
    /// for a square mesh).
    pub shadow_points: usize,
    /// The mesh, in the receiver's plane coordinates.
    pub triangulation: PlaneTriangulation,
    /// The exact field at its points.
    pub values: Vec<f64>,
    /// √mean((B_h − B)²) / √mean(B²) over the receiver.
    pub rms_rel_error: f64,
    /// max |B_h − B| / max B over the receiver.
    pub max_rel_error: f64,
    /// mean |B_h − B| / B where B is above 1 % of its maximum.
    pub mean_rel_error: f64,
    /// Seconds to build the mesh (layout and triangulation).
    pub seconds: f64,
}

impl MeshRecord {
    /// Vertices of the mesh.
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.triangulation.points.len()
    }

    /// Triangles of the mesh.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.triangulation.triangles.len()
    }
}

impl serde::Serialize for MeshRecord {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        /// The mesher's parameters as the JSON has them.
        #[derive(serde::Serialize)]
        #[serde(untagged)]
        enum Params {
            Square {
                n: usize,
            },
            Contour {
                directions: usize,
                levels: usize,
                newton_iterations: usize,
                shadow_points: usize,
            },
            ContourToError {
                max_relative_error: f64,
                newton_iterations: usize,
                shadow_points: usize,
            },
            Greedy {
                max_vertices: usize,
            },
        }
        /// The record as the JSON has it.
        #[derive(serde::Serialize)]
        struct Json<'a> {
            receiver: &'a str,
            mesher: &'static str,
            params: Params,
            vertices: usize,
            triangles: usize,
            rms_rel_error: f64,
            max_rel_error: f64,
            mean_rel_error: f64,
            seconds: f64,
        }
        let params = match self.spec {
            MeshSpec::Square { n } => Params::Square { n },
            MeshSpec::Contour { directions, levels }
            | MeshSpec::ShadowContour { directions, levels } => Params::Contour {
                directions,
                levels,
                newton_iterations: self.newton_iterations,
                shadow_points: self.shadow_points,
            },
            MeshSpec::ContourToError { per_mille } | MeshSpec::LevelLines { per_mille } => {
                Params::ContourToError {
                    max_relative_error: f64::from(per_mille) / 1000.0,
                    newton_iterations: self.newton_iterations,
                    shadow_points: self.shadow_points,
                }
            }
            MeshSpec::Greedy { vertices } => Params::Greedy {
                max_vertices: vertices,
            },
        };
        Json {
            receiver: &self.receiver,
            mesher: self.spec.mesher(),
            params,
            vertices: self.vertex_count(),
            triangles: self.triangle_count(),
            rms_rel_error: self.rms_rel_error,
            max_rel_error: self.max_rel_error,
            mean_rel_error: self.mean_rel_error,
            seconds: self.seconds,
        }
        .serialize(serializer)
    }
}

/// Every mesh of one receiver, measured.
#[derive(Clone, Debug, PartialEq)]
pub struct ReceiverComparison {
    /// The receiver's name.
    pub receiver: String,
    /// Its id in the scene.
    pub surface: SurfaceId,
    /// Its polygon, in plane coordinates.
    pub outline: Vec<DVec2>,
    /// One record per mesh, in the order measured.
    pub records: Vec<MeshRecord>,
}

/// How a mesh was built, besides its triangulation.
pub(super) struct Built {
    /// Which mesh.
    pub spec: MeshSpec,
    /// Newton iterations of a contour layout (0 for a square mesh).
    pub newton_iterations: usize,
    /// Shadow-boundary vertices of a contour layout (0 for a square mesh).
    pub shadow_points: usize,
    /// Seconds to build it.
    pub seconds: f64,
}

impl ReceiverComparison {
    /// Gives the mesh the exact values at its points, measures it and
    /// records it.
    pub(super) fn add(
        &mut self,
        built: Built,
        triangulation: PlaneTriangulation,
        exact: &dyn Fn(DVec2) -> f64,
        grid: &ErrorGrid,
    ) {
        let values: Vec<f64> = triangulation.points.iter().map(|&p| exact(p)).collect();
        let error = grid.measure(&triangulation, &values);
        self.records.push(MeshRecord {
            receiver: self.receiver.clone(),
            spec: built.spec,
            newton_iterations: built.newton_iterations,
            shadow_points: built.shadow_points,
            triangulation,
            values,
            rms_rel_error: error.rms_rel_error,
            max_rel_error: error.max_rel_error,
            mean_rel_error: error.mean_rel_error,
            seconds: built.seconds,
        });
    }

    /// The record of the mesh `spec`, if it was measured.
    #[must_use]
    pub fn record(&self, spec: MeshSpec) -> Option<&MeshRecord> {
        self.records.iter().find(|r| r.spec == spec)
    }

    /// The series of a log–log plot of an error `measure` (such as the RMS
    /// error) against vertices, those measured on this receiver: square
    /// meshes, the seed paper's contour
    /// sizes, the balanced D = 2K contour sizes, the contour sizes with the
    /// receiver's shadow boundaries, contour meshes refined to a relative
    /// error, and level lines.
    #[must_use]
    pub fn plot_series(&self, measure: impl Fn(&MeshRecord) -> f64) -> Vec<Series> {
        const FAMILIES: [&str; 7] = [
            "square N × N",
            "contour D × K, seed sizes",
            "contour D × K, D = 2K",
            "contour D × K with shadow boundaries",
            "contour to a relative error ε",
            "level lines to a relative error ε",
            "greedy insertion",
        ];
        let family = |spec: MeshSpec| match spec {
            MeshSpec::Square { .. } => FAMILIES[0],
            MeshSpec::Contour { directions, levels } if directions == 2 * levels => FAMILIES[2],
            MeshSpec::Contour { .. } => FAMILIES[1],
            MeshSpec::ShadowContour { .. } => FAMILIES[3],
            MeshSpec::ContourToError { .. } => FAMILIES[4],
            MeshSpec::LevelLines { .. } => FAMILIES[5],
            MeshSpec::Greedy { .. } => FAMILIES[6],
        };
        FAMILIES
            .into_iter()
            .map(|name| {
                let mut points: Vec<(f64, f64)> = self
                    .records
                    .iter()
                    .filter(|r| family(r.spec) == name)
                    .map(|r| (r.vertex_count() as f64, measure(r)))
                    .collect();
                // In order of vertices: a family may mix two sweeps.
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                Series {
                    name: name.into(),
                    points,
                }
            })
            // A family not measured on this receiver has no legend entry.
            .filter(|series| !series.points.is_empty())
            .collect()
    }

    /// The vertices the meshes `of` selects (e.g. [`MeshSpec::is_square`])
    /// need to reach `rms` RMS error, interpolated log-linearly between
    /// their measurements (None outside their range).
    #[must_use]
    pub fn vertices_for_error(&self, of: impl Fn(&MeshSpec) -> bool, rms: f64) -> Option<f64> {
        self.vertices_for_measure(of, |r| r.rms_rel_error, rms)
    }

    /// [`ReceiverComparison::vertices_for_error`] for any error `measure`
    /// of a record (such as the mean relative error) reaching `target`.
    #[must_use]
    pub fn vertices_for_measure(
        &self,
        of: impl Fn(&MeshSpec) -> bool,
        measure: impl Fn(&MeshRecord) -> f64,
        target: f64,
    ) -> Option<f64> {
        let mut points: Vec<(f64, f64)> = self
            .records
            .iter()
            .filter(|r| of(&r.spec) && measure(r) > 0.0)
            .map(|r| (r.vertex_count() as f64, measure(r)))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        // The lower envelope: error must fall as vertices grow.
        let mut frontier: Vec<(f64, f64)> = Vec::new();
        for p in points {
            if frontier.last().is_none_or(|last| p.1 < last.1) {
                frontier.push(p);
            }
        }
        frontier.windows(2).find_map(|w| {
            let ((v0, e0), (v1, e1)) = (w[0], w[1]);
            (target <= e0 && target >= e1).then(|| {
                let s = (target.ln() - e0.ln()) / (e1.ln() - e0.ln());
                (v0.ln() + s * (v1.ln() - v0.ln())).exp()
            })
        })
    }
}

/// Writes every record of every comparison as a JSON array (atomically).
pub fn write_json(comparisons: &[ReceiverComparison], path: &Path) -> Result<()> {
    let records: Vec<&MeshRecord> = comparisons.iter().flat_map(|c| &c.records).collect();
    // JSON has no NaN: serde_json would write `null` where a number belongs.
    if let Some(bad) = records.iter().find(|r| {
        !(r.rms_rel_error.is_finite()
            && r.max_rel_error.is_finite()
            && r.mean_rel_error.is_finite()
            && r.seconds.is_finite())
    }) {
        return Err(Error::Output {
            path: path.to_path_buf(),
            message: format!(
                "the record of {} on `{}` holds a non-finite error; nothing was written",
                bad.spec, bad.receiver
            ),
        });
    }
    let text = serde_json::to_string_pretty(&records).map_err(|e| Error::Output {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    crate::fs::write_atomically(path, |file| {
        use std::io::Write;
        file.write_all(text.as_bytes()).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::{Value, json};

    /// A record of `spec` on a unit square split into two triangles.
    fn record(spec: MeshSpec, newton_iterations: usize, shadow_points: usize) -> MeshRecord {
        MeshRecord {
            receiver: "floor".into(),
            spec,
            newton_iterations,
            shadow_points,
            triangulation: PlaneTriangulation {
                points: vec![DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y],
                triangles: vec![[0, 1, 2], [0, 2, 3]],
            },
            values: vec![1.0; 4],
            rms_rel_error: 0.125,
            max_rel_error: 0.5,
            mean_rel_error: 0.0625,
            seconds: 0.25,
        }
    }

    #[test]
    fn specs_read_as_the_tables_and_the_json_name_them() {
        let square = MeshSpec::Square { n: 10 };
        let contour = MeshSpec::Contour {
            directions: 20,
            levels: 5,
        };
        assert_eq!(square.to_string(), "square 10×10");
        assert_eq!(contour.to_string(), "contour 20×5");
        assert_eq!((square.mesher(), square.size()), ("square", "10x10".into()));
        assert_eq!(
            (contour.mesher(), contour.size()),
            ("contour", "20x5".into())
        );
        assert!(square.is_square() && !square.is_contour() && contour.is_contour());
        let shadow_aware = MeshSpec::ShadowContour {
            directions: 20,
            levels: 5,
        };
        assert_eq!(shadow_aware.to_string(), "shadow-aware contour 20×5");
        assert_eq!(
            (shadow_aware.mesher(), shadow_aware.size()),
            ("shadow_contour", "20x5".into())
        );
        assert!(shadow_aware.is_contour());
        assert_eq!(
            serde_json::to_value(shadow_aware).unwrap(),
            json!({ "mesher": "shadow_contour", "params": { "directions": 20, "levels": 5 } })
        );
        assert_eq!(
            serde_json::to_value(square).unwrap(),
            json!({ "mesher": "square", "params": { "n": 10 } })
        );
        assert_eq!(
            serde_json::to_value(contour).unwrap(),
            json!({ "mesher": "contour", "params": { "directions": 20, "levels": 5 } })
        );
        let greedy = MeshSpec::Greedy { vertices: 300 };
        assert_eq!(greedy.to_string(), "greedy ≤ 300 vertices");
        assert_eq!((greedy.mesher(), greedy.size()), ("greedy", "v300".into()));
        assert!(greedy.is_contour() && !greedy.is_square());
    }

    #[test]
    fn the_json_has_the_documented_fields_and_no_others() {
        let contour = MeshSpec::Contour {
            directions: 20,
            levels: 5,
        };
        let comparison = ReceiverComparison {
            receiver: "floor".into(),
            surface: SurfaceId::new(3),
            outline: Vec::new(),
            records: vec![
                record(MeshSpec::Square { n: 1 }, 0, 0),
                record(contour, 41, 7),
                record(MeshSpec::Greedy { vertices: 300 }, 0, 0),
            ],
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("records.json");
        write_json(&[comparison], &path).unwrap();
        let written: Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let measured = json!({
            "receiver": "floor",
            "vertices": 4,
            "triangles": 2,
            "rms_rel_error": 0.125,
            "max_rel_error": 0.5,
            "mean_rel_error": 0.0625,
            "seconds": 0.25,
        });
        let with = |mesher: &str, params: Value| {
            let mut record = measured.clone();
            record["mesher"] = mesher.into();
            record["params"] = params;
            record
        };
        let expected = json!([
            with("square", json!({ "n": 1 })),
            with(
                "contour",
                json!({ "directions": 20, "levels": 5, "newton_iterations": 41, "shadow_points": 7 })
            ),
            with("greedy", json!({ "max_vertices": 300 })),
        ]);
        assert_eq!(written, expected);
    }

    #[test]
    fn non_finite_errors_are_refused_before_writing() {
        let mut bad = record(MeshSpec::Square { n: 1 }, 0, 0);
        bad.rms_rel_error = f64::NAN;
        let comparison = ReceiverComparison {
            receiver: "floor".into(),
            surface: SurfaceId::new(0),
            outline: Vec::new(),
            records: vec![bad],
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("records.json");
        let result = write_json(&[comparison], &path);
        assert!(
            matches!(&result, Err(Error::Output { message, .. }) if message.contains("square 1×1 on `floor`")),
            "{result:?}"
        );
        assert!(!path.exists());
    }
}
