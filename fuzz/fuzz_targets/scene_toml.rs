//! Scene files: the input is a scene TOML beside a small valid OBJ scene
//! (`scene.obj`, which it may name). Loading must answer with a scene and
//! settings that keep their promises or an error, never a panic or a hang.
#![no_main]

use libfuzzer_sys::fuzz_target;

use isorad_fuzz::{FLOOR_AND_LAMP_MTL, check_scene, floor_and_lamp_obj, write_scratch};

fuzz_target!(|data: &[u8]| {
    static SCENE: std::sync::Once = std::sync::Once::new();
    SCENE.call_once(|| {
        let floor = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(x, y)| glam::DVec2::new(x, y));
        write_scratch("fuzz.mtl", FLOOR_AND_LAMP_MTL.as_bytes());
        write_scratch("scene.obj", floor_and_lamp_obj(&floor).as_bytes());
    });
    let path = write_scratch("fuzz.toml", data);
    if let Ok(loaded) = isorad::scene::load_scene_file(&path) {
        check_scene(&loaded.scene);
        if let Some(camera) = &loaded.scene.camera {
            camera.validate().expect("a loaded camera is valid");
            let frame = camera.frame();
            assert!(frame.right.is_finite() && frame.up.is_finite() && frame.forward.is_finite());
        }
        // The file's [mesh] and [solver] tables: valid settings or an error.
        if let Ok(settings) = isorad::Settings::from_scene_options(&loaded.options) {
            settings.validate().expect("settings read from a file are valid");
        }
    }
});
