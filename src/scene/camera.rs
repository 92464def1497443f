//! The pinhole look-at camera shared with other renderers.

use glam::DVec3;

/// A pinhole camera, in the convention that pbrt and Mitsuba scenes use.
///
/// `right = normalize(forward × up)`; pixel (i, j) has its centre at
/// ((i + 0.5)/W, (j + 0.5)/H) of the image, row 0 at the top; `vfov_deg` is
/// the full vertical field of view.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub position: DVec3,
    /// A point the camera looks at.
    pub look_at: DVec3,
    /// The world's up direction (need not be orthogonal to the view).
    pub up: DVec3,
    /// Full vertical field of view, degrees.
    pub vfov_deg: f64,
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
}

/// The camera's orthonormal frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraFrame {
    /// Unit vector to the image's right.
    pub right: DVec3,
    /// Unit vector to the image's top.
    pub up: DVec3,
    /// Unit viewing direction.
    pub forward: DVec3,
}

impl Camera {
    /// The camera's frame: forward = normalize(look_at − position),
    /// right = normalize(forward × up), up' = right × forward.
    #[must_use]
    pub fn frame(&self) -> CameraFrame {
        let forward = (self.look_at - self.position).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        CameraFrame { right, up, forward }
    }

    /// A camera at `position` looking at `look_at`, with the world's `up`
    /// and a full vertical field of view of `vfov_deg` degrees, at
    /// 512 × 512 pixels (set `width` and `height` to change).
    #[must_use]
    pub fn look_at(position: DVec3, look_at: DVec3, up: DVec3, vfov_deg: f64) -> Camera {
        Camera {
            position,
            look_at,
            up,
            vfov_deg,
            width: 512,
            height: 512,
        }
    }

    /// A camera that frames an axis-aligned box from its −z side, y up,
    /// at 512 × 512 with a 40° field of view.
    #[must_use]
    pub fn framing(min: DVec3, max: DVec3) -> Camera {
        let centre = 0.5 * (min + max);
        let radius = 0.5 * (max - min).length().max(f64::MIN_POSITIVE);
        let vfov_deg: f64 = 40.0;
        let distance = radius / (0.5 * vfov_deg.to_radians()).tan() + 0.5 * (max.z - min.z);
        Camera {
            position: centre - DVec3::Z * distance,
            look_at: centre,
            up: DVec3::Y,
            vfov_deg,
            width: 512,
            height: 512,
        }
    }

    /// Checks the camera can form an image; returns what is wrong otherwise.
    pub fn validate(&self) -> Result<(), String> {
        let finite = [self.position, self.look_at, self.up]
            .iter()
            .all(|v| v.is_finite());
        if !finite || !self.vfov_deg.is_finite() {
            return Err("camera has a non-finite value".into());
        }
        let forward = self.look_at - self.position;
        if forward.length_squared() == 0.0 {
            return Err("camera position equals look_at".into());
        }
        if forward.cross(self.up).length_squared() <= 1e-12 * forward.length_squared() {
            return Err("camera up is parallel to the viewing direction".into());
        }
        if !(self.vfov_deg > 0.0 && self.vfov_deg < 180.0) {
            return Err(format!("vfov_deg = {} is not in (0, 180)", self.vfov_deg));
        }
        if self.width == 0 || self.height == 0 || self.width > 16384 || self.height > 16384 {
            return Err(format!(
                "image size {}×{} is not in 1..=16384",
                self.width, self.height
            ));
        }
        Ok(())
    }
}
