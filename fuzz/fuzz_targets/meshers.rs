//! The meshers on random polygons: the bytes decode to a floor polygon
//! (concave, nearly degenerate, tiny or huge as they come), which goes
//! through the OBJ loader's clean-up as a user's face would (skipped,
//! projected or split), under a lamp; every mesher in `MESHERS` then meshes
//! the scene, and every mesh must keep `check_mesh`'s invariants.
#![no_main]

use libfuzzer_sys::fuzz_target;

use isorad_fuzz::{
    Bytes, FLOOR_AND_LAMP_MTL, MESHERS, check_mesh, check_scene, decode_polygon,
    floor_and_lamp_obj, small_enough, write_scratch,
};

fuzz_target!(|data: &[u8]| {
    let floor = decode_polygon(&mut Bytes(data), 256);
    if floor.len() < 3 {
        return;
    }
    write_scratch("fuzz.mtl", FLOOR_AND_LAMP_MTL.as_bytes());
    let path = write_scratch("floor.obj", floor_and_lamp_obj(&floor).as_bytes());
    let Ok(scene) = isorad::load_obj(&path) else {
        return;
    };
    check_scene(&scene);
    if !small_enough(&scene) {
        return;
    }
    for (name, mesher) in MESHERS {
        check_mesh(name, &scene, &mesher(&scene));
    }
});
