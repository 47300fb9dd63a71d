//! The kernel prelude (crate `trax`) sources, embedded for the compiler and for
//! `trax native`.
//!
//! Paths are relative to the prelude directory [`DIR`]. Three entries lie outside it
//! (`../src/rng.rs`, `../src/fops.rs`, `../src/pipes.rs`): the host implementation
//! shares the emulator's RNG, f32 operation and pipeline semantics verbatim. Writers of these files to disk must keep
//! the relative layout (write `p` to `<root>/prelude/<p>`).

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
    ("../src/rng.rs", include_str!("rng.rs")),
    ("../src/fops.rs", include_str!("fops.rs")),
    ("../src/pipes.rs", include_str!("pipes.rs")),
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

#[cfg(test)]
mod tests {
    use super::*;

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
    fn fnv1a_known_value() {
        let mut h = Fnv1a::new();
        h.write(b"a");
        assert_eq!(h.finish(), 0xaf63dc4c8601ec8c);
        assert_ne!(content_hash(), Fnv1a::new().finish());
    }
}
