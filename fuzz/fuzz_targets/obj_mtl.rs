//! OBJ + MTL loading: the input, split at its first NUL byte, is an OBJ file
//! and the MTL file it names (`fuzz.mtl`, also named by a `mtllib` line put
//! first). Loading must answer with a scene that keeps its promises or an
//! error, never a panic; a loaded scene must also build its BVH.
#![no_main]

use libfuzzer_sys::fuzz_target;

use isorad_fuzz::{check_scene, split_at_nul, write_scratch};

fuzz_target!(|data: &[u8]| {
    let (obj, mtl) = split_at_nul(data);
    let mut text = b"mtllib fuzz.mtl\n".to_vec();
    text.extend_from_slice(obj);
    write_scratch("fuzz.mtl", mtl);
    let path = write_scratch("fuzz.obj", &text);
    if let Ok(scene) = isorad::scene::load_obj(&path) {
        check_scene(&scene);
        let _ = isorad::scene::Visibility::new(&scene);
        let settings = isorad::MeshSettings::default();
        assert!(settings.estimate_elements(&scene).is_finite());
    }
});
