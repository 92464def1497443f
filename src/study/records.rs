//! The records of a comparison, and their JSON form.

use glam::DVec2;
use std::path::Path;

use super::plot::Series;
use crate::error::{Error, Result};
use crate::mesh::{ErrorGrid, PlaneTriangulation};
use crate::scene::SurfaceId;

/// One mesh of one receiver, measured.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MeshRecord {
    /// The receiver's name (its OBJ object).
    pub receiver: String,
    /// "square" or "contour".
    pub mesher: String,
    /// The mesher's parameters: `{"n"}` or `{"directions", "levels", …}`.
    pub params: serde_json::Value,
    /// Vertices of the mesh.
    pub vertices: usize,
    /// Triangles of the mesh.
    pub triangles: usize,
    /// √mean((B_h − B)²) / √mean(B²) over the receiver.
    pub rms_rel_error: f64,
    /// max |B_h − B| / max B over the receiver.
    pub max_rel_error: f64,
    /// Seconds to build the mesh (layout and triangulation).
    pub seconds: f64,
}

/// A mesh kept for pictures: its triangles and exact vertex values.
#[derive(Clone, Debug, PartialEq)]
pub struct ComparedMesh {
    /// "square" or "contour".
    pub mesher: String,
    /// "NxN" or "DxK".
    pub params: String,
    /// The mesh, in the receiver's plane coordinates.
    pub triangulation: PlaneTriangulation,
    /// The exact field at its points.
    pub values: Vec<f64>,
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
    /// One record per mesh.
    pub records: Vec<MeshRecord>,
    /// The meshes, for pictures.
    pub meshes: Vec<ComparedMesh>,
}

impl ReceiverComparison {
    /// Measures a mesh and records it.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn add(
        &mut self,
        mesher: &str,
        label: String,
        params: serde_json::Value,
        triangulation: PlaneTriangulation,
        exact: &dyn Fn(DVec2) -> f64,
        grid: &ErrorGrid,
        seconds: f64,
    ) {
        let values: Vec<f64> = triangulation.points.iter().map(|&p| exact(p)).collect();
        let error = grid.measure(&triangulation, &values);
        self.records.push(MeshRecord {
            receiver: self.receiver.clone(),
            mesher: mesher.into(),
            params,
            vertices: triangulation.points.len(),
            triangles: triangulation.triangles.len(),
            rms_rel_error: error.rms_rel_error,
            max_rel_error: error.max_rel_error,
            seconds,
        });
        self.meshes.push(ComparedMesh {
            mesher: mesher.into(),
            params: label,
            triangulation,
            values,
        });
    }

    /// The series of a log–log plot of RMS error against vertices: square
    /// meshes, the seed paper's contour sizes, and the balanced D = 2K
    /// contour sizes.
    #[must_use]
    pub fn plot_series(&self) -> Vec<Series> {
        const FAMILIES: [&str; 3] = [
            "square N × N",
            "contour D × K, seed sizes",
            "contour D × K, D = 2K",
        ];
        let family = |record: &MeshRecord| {
            if record.mesher == "square" {
                FAMILIES[0]
            } else if record.params["directions"]
                == 2 * record.params["levels"].as_u64().unwrap_or(0)
            {
                FAMILIES[2]
            } else {
                FAMILIES[1]
            }
        };
        FAMILIES
            .into_iter()
            .map(|name| Series {
                name: name.into(),
                points: self
                    .records
                    .iter()
                    .filter(|r| family(r) == name)
                    .map(|r| (r.vertices as f64, r.rms_rel_error))
                    .collect(),
            })
            .collect()
    }

    /// The vertices each mesher needs to reach `rms` RMS error, interpolated
    /// log-linearly between its measured meshes (None outside their range).
    #[must_use]
    pub fn vertices_for_error(&self, mesher: &str, rms: f64) -> Option<f64> {
        let mut points: Vec<(f64, f64)> = self
            .records
            .iter()
            .filter(|r| r.mesher == mesher && r.rms_rel_error > 0.0)
            .map(|r| (r.vertices as f64, r.rms_rel_error))
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
            (rms <= e0 && rms >= e1).then(|| {
                let s = (rms.ln() - e0.ln()) / (e1.ln() - e0.ln());
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
        !(r.rms_rel_error.is_finite() && r.max_rel_error.is_finite() && r.seconds.is_finite())
    }) {
        return Err(Error::Output {
            path: path.to_path_buf(),
            message: format!(
                "the record of {} {} on `{}` holds a non-finite error; nothing was written",
                bad.mesher, bad.params, bad.receiver
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
