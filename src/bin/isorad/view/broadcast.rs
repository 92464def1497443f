//! What the viewer publishes to its pages, each part the latest of its
//! kind: the scene's `hello`, the mesh, the light on it and the solve's
//! status. The solve thread writes it; every page's socket thread waits on
//! it and sends the parts that changed since it last looked, so a page that
//! connects late, or reconnects, gets the whole current state, and a slow
//! page skips states rather than queueing them.
//!
//! The binary messages (little-endian, every field 4 bytes, so that the page
//! reads them as typed arrays without copying):
//!
//! - `mesh`: u32 kind = 1, u32 version, u32 V, u32 T, then the f32
//!   positions (3V, world space), then the u32 indices (3T, counter-clockwise
//!   seen from the front);
//! - `light`: u32 kind = 2, u32 mesh version, u32 V, u32 0, then the f32
//!   radiance L = B/π (3V, linear RGB, W/(m²·sr)), then the f32 illuminance
//!   E = 179 lm/W · Y(H) (V, lx).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex, MutexGuard, PoisonError};
use std::time::Duration;

use glam::DVec3;
use isorad::{Rgb, calculation::illuminance_lux};
use tungstenite::Bytes;

/// Kind of the `mesh` message.
const MESH_KIND: u32 = 1;
/// Kind of the `light` message.
const LIGHT_KIND: u32 = 2;

/// One published part: its message and a serial number that grows
/// whenever it changes.
#[derive(Clone, Default)]
pub struct Part<T> {
    pub serial: u64,
    pub message: T,
}

/// The latest state of each part.
#[derive(Clone, Default)]
pub struct Published {
    /// The `hello` JSON (scene name, camera, bounds), once the scene is
    /// loaded.
    pub hello: Option<String>,
    /// The `mesh` message; its serial is the version its lights name.
    pub mesh: Option<Part<Bytes>>,
    /// The `light` message.
    pub light: Option<Part<Bytes>>,
    /// The `status` JSON.
    pub status: Part<String>,
}

/// The published state, and who waits on it.
#[derive(Default)]
pub struct Broadcast {
    state: Mutex<Published>,
    changed: Condvar,
    /// Pages connected over a WebSocket.
    pub clients: AtomicUsize,
    /// Set when a page connects: the solve thread publishes a mesh and a
    /// light at its next chance, even when no page had wanted them.
    pub wanted: AtomicBool,
}

impl Broadcast {
    fn lock(&self) -> MutexGuard<'_, Published> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Changes the published state and wakes every page.
    pub fn publish(&self, change: impl FnOnce(&mut Published)) {
        change(&mut self.lock());
        self.changed.notify_all();
    }

    /// Publishes a new status JSON.
    pub fn set_status(&self, json: String) {
        self.publish(|state| {
            state.status = Part {
                serial: state.status.serial + 1,
                message: json,
            };
        });
    }

    /// Publishes a new mesh message under `version`.
    pub fn set_mesh(&self, version: u32, message: Bytes) {
        let serial = u64::from(version);
        self.publish(|state| state.mesh = Some(Part { serial, message }));
    }

    /// Publishes a new light message.
    pub fn set_light(&self, message: Bytes) {
        self.publish(|state| {
            let serial = state.light.as_ref().map_or(1, |part| part.serial + 1);
            state.light = Some(Part { serial, message });
        });
    }

    /// The latest status JSON.
    pub fn status(&self) -> String {
        self.lock().status.message.clone()
    }

    /// The published state once it differs from `seen` (as [`Seen`]
    /// compares), or after `timeout` whatever it is.
    pub fn wait_for_change(&self, seen: &Seen, timeout: Duration) -> Published {
        let state = self.lock();
        let (state, _) = self
            .changed
            .wait_timeout_while(state, timeout, |state| !seen.differs(state))
            .unwrap_or_else(PoisonError::into_inner);
        state.clone()
    }

    /// Counts a page in, and asks for the frames it needs.
    pub fn connect(&self) {
        self.clients.fetch_add(1, Ordering::SeqCst);
        self.wanted.store(true, Ordering::SeqCst);
    }

    /// Counts a page out.
    pub fn disconnect(&self) {
        self.clients.fetch_sub(1, Ordering::SeqCst);
    }
}

/// What one page has been sent of each part.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Seen {
    pub hello: bool,
    pub mesh: Option<u64>,
    pub light: Option<u64>,
    pub status: u64,
}

impl Seen {
    /// Whether `state` holds a part this page has not been sent.
    pub fn differs(&self, state: &Published) -> bool {
        (state.hello.is_some() && !self.hello)
            || state.mesh.as_ref().map(|part| part.serial) != self.mesh
            || state.light.as_ref().map(|part| part.serial) != self.light
            || state.status.serial != self.status
    }
}

/// The `mesh` message: `positions` and the triangles' vertex indices.
pub fn mesh_message(version: u32, positions: &[DVec3], triangles: &[[u32; 3]]) -> Bytes {
    let mut bytes = Vec::with_capacity(16 + 12 * positions.len() + 12 * triangles.len());
    for word in [
        MESH_KIND,
        version,
        count(positions.len()),
        count(triangles.len()),
    ] {
        bytes.extend_from_slice(&word.to_le_bytes());
    }
    for p in positions {
        for c in [p.x, p.y, p.z] {
            bytes.extend_from_slice(&(c as f32).to_le_bytes());
        }
    }
    for index in triangles.iter().flatten() {
        bytes.extend_from_slice(&index.to_le_bytes());
    }
    Bytes::from(bytes)
}

/// The `light` message for the mesh of `version`: radiance L = B/π from
/// each vertex's radiosity B, and illuminance from its irradiance H.
pub fn light_message(version: u32, radiosity: &[Rgb], irradiance: &[Rgb]) -> Bytes {
    let mut bytes = Vec::with_capacity(16 + 16 * radiosity.len());
    for word in [LIGHT_KIND, version, count(radiosity.len()), 0] {
        bytes.extend_from_slice(&word.to_le_bytes());
    }
    for b in radiosity {
        let radiance = *b / std::f64::consts::PI;
        for c in [radiance.r, radiance.g, radiance.b] {
            bytes.extend_from_slice(&finite_f32(c).to_le_bytes());
        }
    }
    for h in irradiance {
        bytes.extend_from_slice(&finite_f32(illuminance_lux(*h)).to_le_bytes());
    }
    Bytes::from(bytes)
}

/// A length as the messages' u32 (a mesh past 4 billion vertices cannot be
/// built on a machine that serves it).
fn count(length: usize) -> u32 {
    u32::try_from(length).unwrap_or(u32::MAX)
}

/// `value` as f32, with NaN and infinities as 0: a page's typed array
/// should hold only numbers it can draw.
fn finite_f32(value: f64) -> f32 {
    let single = value as f32;
    if single.is_finite() { single } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(bytes: &[u8]) -> Vec<u32> {
        bytes
            .chunks_exact(4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
            .collect()
    }

    #[test]
    fn mesh_message_lays_out_header_positions_and_indices() {
        let positions = [DVec3::new(1.0, 2.0, 3.0), DVec3::new(-1.5, 0.0, 4.25)];
        let message = mesh_message(7, &positions, &[[0, 1, 1]]);
        let w = words(&message);
        assert_eq!(&w[..4], &[1, 7, 2, 1]);
        let floats: Vec<f32> = w[4..10].iter().map(|&b| f32::from_bits(b)).collect();
        assert_eq!(floats, [1.0, 2.0, 3.0, -1.5, 0.0, 4.25]);
        assert_eq!(&w[10..], &[0, 1, 1]);
    }

    #[test]
    fn light_message_carries_radiance_and_lux() {
        let pi = std::f64::consts::PI;
        let radiosity = [Rgb::new(pi, 2.0 * pi, f64::NAN)];
        let irradiance = [Rgb::splat(1.0)];
        let message = light_message(3, &radiosity, &irradiance);
        let w = words(&message);
        assert_eq!(&w[..4], &[2, 3, 1, 0]);
        let floats: Vec<f32> = w[4..].iter().map(|&b| f32::from_bits(b)).collect();
        assert_eq!(&floats[..3], &[1.0, 2.0, 0.0]);
        // 179 lm/W × Y(1, 1, 1) = 179 lx.
        assert!((floats[3] - 179.0).abs() < 1e-3, "{}", floats[3]);
    }

    #[test]
    fn a_page_sees_what_it_was_not_sent() {
        let broadcast = Broadcast::default();
        let mut seen = Seen::default();
        assert!(!seen.differs(&broadcast.lock()));
        broadcast.set_status("{}".into());
        let state = broadcast.wait_for_change(&seen, Duration::from_secs(1));
        assert!(seen.differs(&state));
        seen.status = state.status.serial;
        assert!(!seen.differs(&broadcast.lock()));
        broadcast.set_light(Bytes::from_static(b"x"));
        broadcast.set_light(Bytes::from_static(b"y"));
        let state = broadcast.wait_for_change(&seen, Duration::from_secs(1));
        assert_eq!(state.light.map(|part| part.serial), Some(2));
    }
}
