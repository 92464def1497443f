//! Scenes built in code: materials and polygons added one by one, checked
//! as the OBJ/MTL loader checks a file's, with the same errors.

use std::ops::Range;
use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::error::{Error, Result};

use crate::scene::camera::Camera;
use crate::scene::geometry::polygon::clean_polygon;
use crate::scene::material::Material;
use crate::scene::surface::Surface;
use crate::scene::{Scene, Warning};

/// What errors and warnings about a scene built in code name as its file.
pub(crate) const BUILT_IN_CODE: &str = "<scene built in code>";

impl Scene {
    /// An empty scene, to fill with [`Scene::add_material`] and
    /// [`Scene::add_polygon`].
    #[must_use]
    pub fn new() -> Scene {
        Scene::default()
    }

    /// Adds a material; returns its index, for [`Scene::add_polygon`].
    ///
    /// Fails with [`Error::InvalidMaterial`], as the MTL loader does, when
    /// the reflectance is not in [0, 1) or the emitted radiance is negative
    /// (or either is not finite).
    pub fn add_material(&mut self, material: Material) -> Result<usize> {
        check_material(&material)?;
        self.materials.push(material);
        Ok(self.materials.len() - 1)
    }

    /// Adds a polygon named `name` (counter-clockwise seen from its front)
    /// with material `material`, cleaned as the OBJ loader cleans a face: a
    /// nearly planar polygon is projected onto its plane, a clearly
    /// non-planar one split into triangles, a degenerate one skipped, the
    /// last two with a warning in [`Scene::warnings`]. Returns the indices
    /// of the surfaces added (empty when skipped).
    ///
    /// Fails with [`Error::NonFiniteCoordinate`] for a NaN or infinite
    /// coordinate and [`Error::MissingMaterial`] for a material index that
    /// [`Scene::add_material`] did not return.
    pub fn add_polygon(
        &mut self,
        name: &str,
        material: usize,
        vertices: &[DVec3],
    ) -> Result<Range<usize>> {
        check_material_index(self, name, material)?;
        if vertices.iter().any(|v| !v.is_finite()) {
            return Err(Error::NonFiniteCoordinate {
                path: PathBuf::from(BUILT_IN_CODE),
                line: None,
                object: name.to_owned(),
            });
        }
        let cleaned = clean_polygon(name, material, vertices);
        if let Some(message) = cleaned.warning {
            self.warnings.push(Warning {
                message: format!("{BUILT_IN_CODE}: {message}"),
            });
        }
        let start = self.surfaces.len();
        self.surfaces.extend(cleaned.surfaces);
        Ok(start..self.surfaces.len())
    }

    /// Sets the camera that renders the scene.
    pub fn set_camera(&mut self, camera: Camera) {
        self.camera = Some(camera);
    }

    /// Checks the scene can be solved, with the loaders' errors: every
    /// material in range, every surface's material defined, at least one
    /// surface and one emitting surface.
    pub fn validate(&self) -> Result<()> {
        for material in &self.materials {
            check_material(material)?;
        }
        for surface in &self.surfaces {
            check_material_index(self, &surface.name, surface.material)?;
        }
        check_not_empty(Path::new(BUILT_IN_CODE), self)
    }
}

/// A material's reflectance and emission must be in range.
fn check_material(material: &Material) -> Result<()> {
    match material.problem() {
        Some(message) => Err(Error::InvalidMaterial {
            path: PathBuf::from(BUILT_IN_CODE),
            line: None,
            material: material.name.clone(),
            message,
        }),
        None => Ok(()),
    }
}

/// A material index must name one of the scene's materials.
fn check_material_index(scene: &Scene, object: &str, material: usize) -> Result<()> {
    if material < scene.materials.len() {
        return Ok(());
    }
    Err(Error::MissingMaterial {
        path: PathBuf::from(BUILT_IN_CODE),
        line: None,
        object: object.to_owned(),
        material: format!("#{material}"),
    })
}

/// A scene needs a surface and an emitting surface.
pub(crate) fn check_not_empty(path: &Path, scene: &Scene) -> Result<()> {
    let empty = |message: &str| Error::EmptyScene {
        path: PathBuf::from(path),
        message: message.to_owned(),
    };
    if scene.surfaces.is_empty() {
        return Err(empty("the scene has no usable faces"));
    }
    let emits = |s: &Surface| scene.material_of(s).is_emitter();
    if !scene.surfaces.iter().any(emits) && scene.luminaires.is_empty() && scene.daylight.is_none()
    {
        return Err(empty(
            "the scene has no emitter: no face uses a material with a positive `Ke`, and it has no [[luminaire]] and no [sky]",
        ));
    }
    Ok(())
}
