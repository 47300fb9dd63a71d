//! Entry points of the fuzz targets in `fuzz/` (run with `cargo fuzz`, see `.ci/fuzz`) and
//! of the regression test that replays their kept inputs on stable Rust. Each takes any
//! bytes and must return (errors are fine) without panicking, hanging or allocating
//! without bound.

use std::path::Path;

use crate::bvh::BvhOptions;
use crate::image::{self, RenderOptions};
use crate::link::{self, Input, LinkOptions};
use crate::scene::{self, Scene};

/// Separates the OBJ text from the MTL text in an `obj` input.
pub const MTL_SEPARATOR: &str = "\n#--mtl--\n";

/// Small render options for images built from fuzzed input.
fn small_render() -> RenderOptions {
    RenderOptions {
        width: 4,
        height: 3,
        bvh: BvhOptions::default(),
        ..RenderOptions::default()
    }
}

/// Lays out `scene` with every optional component (so the BVH is built) for an empty program.
fn lay_out(scene: &Scene) {
    let _ = image::build_image_from_symbols(
        Vec::new(),
        0,
        &image::on_demand_components(),
        scene,
        &small_render(),
    );
}

/// Loads `data` as an OBJ file (up to [`MTL_SEPARATOR`]) whose every `mtllib` is the rest
/// of `data`, then builds its BVH and memory image.
pub fn obj(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let (obj, mtl) = text.split_once(MTL_SEPARATOR).unwrap_or((&text, ""));
    let read = |p: &Path| -> std::io::Result<String> {
        match p.extension().and_then(|e| e.to_str()) {
            Some("obj") => Ok(obj.to_string()),
            Some("mtl") => Ok(mtl.to_string()),
            _ => Err(std::io::ErrorKind::NotFound.into()),
        }
    };
    match scene::load_obj_with(Path::new("fuzz.obj"), &read) {
        Ok(s) => lay_out(&s),
        Err(e) => {
            let _ = e.to_string();
        }
    }
}

/// Parses `data` as a `.view` file and as a `.light` file; a view that parses frames the
/// Cornell box, which is then laid out.
pub fn view(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let _ = scene::parse_light_str(Path::new("fuzz.light"), &text);
    if let Ok(v) = scene::parse_view_str(Path::new("fuzz.view"), &text) {
        let mut s = scene::cornell_box();
        s.view = v;
        lay_out(&s);
    }
}

/// Links `data` as a relocatable object (after the start-up object) and lays out the
/// result with the Cornell box; also reads `data` itself as an executable.
pub fn link(data: &[u8]) {
    let input = Input {
        name: "fuzz.o".into(),
        bytes: data.to_vec(),
    };
    if let Ok(l) = link::link(&[input], &LinkOptions::default()) {
        let _ = image::build_image(&l.elf, &scene::cornell_box(), &small_render());
    }
    let _ = image::build_image(data, &scene::cornell_box(), &small_render());
}
