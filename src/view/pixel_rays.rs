//! The rays through a camera's pixel centres, as the rasterizer looks at
//! them with one sample a pixel: the rays the daylight passes of a render
//! cast.

use glam::DVec3;

use crate::scene::{Camera, CameraFrame, Scene, Visibility};

/// A camera's pixel-centre rays, row-major.
pub(super) struct PixelRays {
    frame: CameraFrame,
    width: u32,
    height: u32,
    half_width: f64,
    half_height: f64,
    /// A reach no ray from the camera through the scene exceeds.
    pub(super) reach: f64,
}

impl PixelRays {
    /// The rays of `camera` looking into `scene`.
    pub(super) fn new(camera: &Camera, scene: &Scene, visibility: &Visibility) -> PixelRays {
        let half_height = (0.5 * camera.vfov_deg.to_radians()).tan();
        PixelRays {
            frame: camera.frame(),
            width: camera.width,
            height: camera.height,
            half_width: half_height * f64::from(camera.width) / f64::from(camera.height),
            half_height,
            reach: 4.0 * visibility.diagonal() + (camera.position - scene.bounds().min).length(),
        }
    }

    /// The number of pixels.
    pub(super) fn count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The unit direction through pixel `index` (row-major): pixel (i, j)
    /// looks at x = (2 (i + ½)/W − 1) tan(fov/2) W/H, y = (1 − 2 (j + ½)/H)
    /// tan(fov/2) on the image plane at unit depth.
    pub(super) fn direction(&self, index: usize) -> DVec3 {
        let width = self.width as usize;
        let (i, j) = ((index % width) as f64, (index / width) as f64);
        let x = (2.0 * (i + 0.5) / f64::from(self.width) - 1.0) * self.half_width;
        let y = (1.0 - 2.0 * (j + 0.5) / f64::from(self.height)) * self.half_height;
        (self.frame.right * x + self.frame.up * y + self.frame.forward).normalize()
    }
}
