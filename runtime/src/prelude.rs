//! The kernel prelude (crate `trax`) sources, embedded for the compiler and for
//! `trax native`.
//!
//! Paths are relative to the prelude directory [`DIR`]. Seven entries lie outside it
//! (`../src/rng.rs`, `../src/fops.rs`, `../src/pipes.rs`, `../src/streams.rs` with its
//! `../src/stream_spill.rs`, `../src/image.rs`, `../src/counters.rs`): the host implementation shares the emulator's RNG, f32 operation,
//! pipeline and ray-stream semantics, the memory-image format and the counters' report verbatim. Writers of these files to disk must keep
//! the relative layout (write `p` to `<root>/prelude/<p>`).

use crate::abi;

/// Root file of crate `trax`.
pub const ROOT: &str = "lib.rs";

/// The prelude directory in the source tree.
pub const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/prelude");

/// `(path relative to the prelude directory, source)` for every prelude file.
pub static FILES: &[(&str, &str)] = &[
    ("lib.rs", include_str!("../prelude/lib.rs")),
    ("hw_trax.rs", include_str!("../prelude/hw_trax.rs")),
    ("hw_host.rs", include_str!("../prelude/hw_host.rs")),
    ("simd.rs", include_str!("../prelude/simd.rs")),
    ("lang.rs", include_str!("../prelude/lang.rs")),
    ("layout.rs", include_str!("../prelude/layout.rs")),
    ("math.rs", include_str!("../prelude/math.rs")),
    ("libm.rs", include_str!("../prelude/libm.rs")),
    ("libm_host.rs", include_str!("../prelude/libm_host.rs")),
    ("ray.rs", include_str!("../prelude/ray.rs")),
    ("camera.rs", include_str!("../prelude/camera.rs")),
    ("scene.rs", include_str!("../prelude/scene.rs")),
    ("bvh.rs", include_str!("../prelude/bvh.rs")),
    ("sampling.rs", include_str!("../prelude/sampling.rs")),
    ("pipe.rs", include_str!("../prelude/pipe.rs")),
    ("stream.rs", include_str!("../prelude/stream.rs")),
    ("../src/rng.rs", include_str!("rng.rs")),
    ("../src/fops.rs", include_str!("fops.rs")),
    ("../src/pipes.rs", include_str!("pipes.rs")),
    ("../src/streams.rs", include_str!("streams.rs")),
    ("../src/stream_spill.rs", include_str!("stream_spill.rs")),
    ("../src/image.rs", include_str!("image.rs")),
    ("../src/counters.rs", include_str!("counters.rs")),
];

/// The source of prelude file `path` (as listed in [`FILES`]).
pub fn file(path: &str) -> Option<&'static str> {
    FILES.iter().find(|(p, _)| *p == path).map(|(_, s)| *s)
}

/// A stable 64-bit FNV-1a hash of every prelude file (paths and contents), for build
/// caches keyed by the prelude version.
pub fn content_hash() -> u64 {
    let mut h = Fnv1a::new();
    for (p, s) in FILES {
        h.write(p.as_bytes());
        h.write(&[0]);
        h.write(s.as_bytes());
        h.write(&[0]);
    }
    h.finish()
}

/// 64-bit FNV-1a, a small stable hash (std's hashers are not stable across releases).
#[derive(Clone, Copy, Debug)]
pub struct Fnv1a(u64);

impl Fnv1a {
    /// The empty hash.
    pub fn new() -> Fnv1a {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }

    /// Feeds bytes.
    pub fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 ^= *b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// The hash so far.
    pub fn finish(&self) -> u64 {
        self.0
    }
}

impl Default for Fnv1a {
    fn default() -> Self {
        Fnv1a::new()
    }
}

/// The prelude's `layout.rs`, rendered from the scene contract ([`crate::abi`]): the
/// header address, magic and version; for every contract struct (header, component,
/// elements) the byte offset of each field as `PREFIX_FIELD` and its size as
/// `PREFIX_SIZE`; for every component its element stride as `NAME_STRIDE`. The prelude
/// keeps the rendered text in `prelude/layout.rs` (TRaX-Rust cannot use the Rust structs);
/// a test fails when the file and the contract differ (`TRAX_BLESS=1` rewrites it).
pub fn render_layout() -> String {
    use crate::abi::{Kind, Struct, StructLayout};
    use std::fmt::Write as _;
    let mut out = String::from(
        "//! Byte layouts of the scene data in simulated memory, generated from the scene\n\
         //! contract (`trax_runtime::abi`) by `trax_runtime::prelude::render_layout`: do not\n\
         //! edit; after changing the contract run\n\
         //! `TRAX_BLESS=1 cargo test -p trax-runtime --lib prelude` to rewrite this file.\n\
         //!\n\
         //! Header offsets are used by the host implementation only (on TRaX the linker\n\
         //! resolves `__trax_scene_<field>` symbols).\n\n",
    );
    // The first line of a doc comment, without rustdoc links (the prelude has no `abi`).
    let first_line = |doc: &str| {
        let line = doc.lines().next().unwrap_or("").trim();
        line.replace("[`", "`").replace("`]", "`")
    };
    let _ = writeln!(out, "/// Address of the scene header.");
    let _ = writeln!(
        out,
        "pub const SCENE_HEADER_ADDR: u32 = {:#x};",
        abi::SCENE_HEADER_ADDR
    );
    let _ = writeln!(out, "/// Value of the header's `magic` field (\"TRAX\").");
    let _ = writeln!(out, "pub const SCENE_MAGIC: u32 = {:#x};", abi::SCENE_MAGIC);
    let _ = writeln!(out, "/// Value of the header's `version` field.");
    let _ = writeln!(
        out,
        "pub const SCENE_VERSION: u32 = {};",
        abi::SCENE_VERSION
    );
    let _ = writeln!(
        out,
        "/// The global register `pixel_share` hands pixels out from (sampled simulation\n\
         /// follows a frame's progress along it)."
    );
    let _ = writeln!(
        out,
        "pub const PIXEL_COUNTER_REG: u32 = {};",
        abi::PIXEL_COUNTER_REG
    );
    let _ = writeln!(
        out,
        "/// The global registers `declare_work` records a kernel's work counter in (its\n\
         /// register plus one; 0: none declared) and the items it hands out."
    );
    let _ = writeln!(
        out,
        "pub const WORK_COUNTER_REG: u32 = {};\npub const WORK_ITEMS_REG: u32 = {};",
        abi::WORK_COUNTER_REG,
        abi::WORK_ITEMS_REG
    );
    let _ = writeln!(
        out,
        "/// Words of the ray record `trax::stream` writes and reads (thesis §3.2.1)."
    );
    let _ = writeln!(
        out,
        "pub const STREAM_RECORD_WORDS: usize = {};",
        abi::STREAM_RECORD_BYTES / 4
    );
    let mut structs: Vec<StructLayout> = vec![abi::SceneHeader::layout(), abi::Component::layout()];
    for c in abi::SCENE_COMPONENTS {
        if let Kind::Struct(l) = c.element {
            let l = l();
            if !structs.iter().any(|s| s.name == l.name) {
                structs.push(l);
            }
        }
    }
    for l in &structs {
        let _ = writeln!(out, "\n// `abi::{}` (C: `{}`).", l.name, l.c_name);
        for f in &l.fields {
            let _ = writeln!(out, "/// {}", first_line(f.doc));
            let _ = writeln!(
                out,
                "pub const {}_{}: u32 = {};",
                l.prefix,
                f.name.to_uppercase(),
                f.offset
            );
        }
        let _ = writeln!(out, "/// Size of `{}` in bytes.", l.name);
        let _ = writeln!(out, "pub const {}_SIZE: u32 = {};", l.prefix, l.size);
    }
    let _ = writeln!(out, "\n// Bytes per element of each component.");
    for c in abi::SCENE_COMPONENTS {
        let _ = writeln!(out, "/// `{}`: {}.", c.name, c.element.rust_type());
        let _ = writeln!(
            out,
            "pub const {}_STRIDE: u32 = {};",
            c.name.to_uppercase(),
            c.element_bytes
        );
    }
    out
}

/// The prelude backends whose scene header accessors [`render_header_fields`] writes.
pub const HEADER_FIELD_BACKENDS: [&str; 2] = ["hw_trax.rs", "hw_host.rs"];

/// First line of the generated header-field accessors in a backend file.
const HEADER_FIELDS_BEGIN: &str =
    "// ---- Scene header fields, generated from abi::SceneHeader (prelude::render_header_fields) ----";
/// Line after them.
const HEADER_FIELDS_END: &str = "// ---- end of the scene header fields ----";

/// The accessors `hdr_<field>() -> u32` (the field's address) of every scene header
/// field, as backend `backend` of [`HEADER_FIELD_BACKENDS`] defines them: on the machine each
/// references only its own linker symbol (so a kernel's image holds only the components
/// it reads), on the host it is the header's address plus the field's offset. Begin and
/// end lines included.
pub fn render_header_fields(backend: &str) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let _ = writeln!(out, "{HEADER_FIELDS_BEGIN}");
    for (name, _) in abi::scene_header_fields() {
        if name == "reserved" {
            continue;
        }
        let body = if backend == "hw_trax.rs" {
            format!(
                "__trax_symbol_addr!(\"{}{name}\")",
                abi::SCENE_SYMBOL_PREFIX
            )
        } else {
            format!(
                "layout::SCENE_HEADER_ADDR + layout::HDR_{}",
                name.to_uppercase()
            )
        };
        let _ = writeln!(out, "\npub fn hdr_{name}() -> u32 {{\n    {body}\n}}");
    }
    let _ = writeln!(out, "\n{HEADER_FIELDS_END}");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The generated header-field accessors in a backend file's text (begin to end line).
    fn header_fields_in(text: &str) -> Option<std::ops::Range<usize>> {
        let a = text.find(HEADER_FIELDS_BEGIN)?;
        let b = text[a..].find(HEADER_FIELDS_END)? + a + HEADER_FIELDS_END.len() + 1;
        Some(a..b.min(text.len()))
    }

    #[test]
    fn header_field_accessors_are_rendered_from_the_contract() {
        for backend in HEADER_FIELD_BACKENDS {
            let path = format!("{DIR}/{backend}");
            let mut have = std::fs::read_to_string(&path).unwrap();
            let at = header_fields_in(&have).unwrap_or_else(|| {
                panic!("{path}: no generated header fields ({HEADER_FIELDS_BEGIN})")
            });
            let want = render_header_fields(backend);
            if std::env::var_os("TRAX_BLESS").is_some() {
                have.replace_range(at.clone(), &want);
                std::fs::write(&path, &have).unwrap();
                continue;
            }
            assert!(
                have[at] == want,
                "{path}'s header field accessors differ from the scene contract: run \
                 `TRAX_BLESS=1 cargo test -p trax-runtime --lib prelude` to rewrite them\n\
                 --- rendered:\n{want}"
            );
        }
    }

    #[test]
    fn files_match_the_prelude_directory() {
        let mut on_disk: Vec<String> = std::fs::read_dir(DIR)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .filter(|n| n.ends_with(".rs"))
            .collect();
        on_disk.sort();
        let mut listed: Vec<&str> = FILES
            .iter()
            .map(|(p, _)| *p)
            .filter(|p| !p.starts_with("../"))
            .collect();
        listed.sort();
        assert_eq!(
            on_disk, listed,
            "every prelude file must be listed in FILES"
        );
        for (p, src) in FILES {
            let disk = std::fs::read_to_string(format!("{DIR}/{p}")).unwrap();
            assert_eq!(&disk, src, "{p}");
        }
        assert!(file(ROOT).unwrap().contains("pub fn global_id() -> u32"));
    }

    #[test]
    fn layout_rs_is_rendered_from_the_contract() {
        let want = render_layout();
        let path = format!("{DIR}/layout.rs");
        if std::env::var_os("TRAX_BLESS").is_some() {
            std::fs::write(&path, &want).unwrap();
        }
        let have = std::fs::read_to_string(&path).unwrap();
        assert!(
            have == want,
            "{path} differs from the scene contract: run `TRAX_BLESS=1 cargo test -p \
             trax-runtime --lib prelude` to rewrite it\n--- rendered:\n{want}"
        );
    }

    #[test]
    fn fnv1a_known_value() {
        let mut h = Fnv1a::new();
        h.write(b"a");
        assert_eq!(h.finish(), 0xaf63dc4c8601ec8c);
        assert_ne!(content_hash(), Fnv1a::new().finish());
    }
}
