//! Every linker error kind, from real (or deliberately damaged) objects; and no panics on
//! corrupt input.

mod link_common;

use link_common::*;
use trax_assembler::link::{link, Input, LinkError, LinkOptions, RelocationOverflow};
use trax_runtime::exe::Executable;

fn link_err(paths: &[std::path::PathBuf]) -> LinkError {
    link(&inputs(paths), &LinkOptions::default()).expect_err("link must fail")
}

const MAIN_CALLS_MISSING: &str = "extern int missing_fn(int);\n\
                                  int trax_main(void) { return missing_fn(2); }\n";

#[test]
fn undefined_symbol_names_object_and_section() {
    let dir = scratch("undef");
    let obj = clang_text(&dir, "main", MAIN_CALLS_MISSING, CLANG_FLAGS);
    match link_err(&[obj]) {
        LinkError::UndefinedSymbol {
            symbol,
            file,
            section,
        } => {
            assert_eq!(symbol, "missing_fn");
            assert!(file.ends_with("main.o"), "{file}");
            assert_eq!(section, ".text");
        }
        e => panic!("wrong error: {e}"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn missing_trax_main_is_reported_against_the_startup_code() {
    let dir = scratch("nomain");
    let obj = clang_text(&dir, "lib", "int f(int x) { return x; }\n", CLANG_FLAGS);
    match link_err(&[obj]) {
        LinkError::UndefinedSymbol { symbol, file, .. } => {
            assert_eq!(symbol, "trax_main");
            assert!(file.contains("startup"), "{file}");
        }
        e => panic!("wrong error: {e}"),
    }
    // Without start-up code the entry symbol must come from the inputs.
    let obj = clang_text(&dir, "lib2", "int g(int x) { return x; }\n", CLANG_FLAGS);
    let opts = LinkOptions {
        startup: false,
        ..LinkOptions::default()
    };
    let err = link(&inputs(&[obj]), &opts).unwrap_err();
    assert!(
        matches!(err, LinkError::UndefinedSymbol { ref symbol, .. } if symbol == "__trax_start")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unknown_scene_field_is_undefined() {
    let dir = scratch("scene");
    let obj = clang_text(
        &dir,
        "main",
        "extern int __trax_scene_no_such_field;\n\
         int trax_main(void) { return __trax_scene_no_such_field; }\n",
        CLANG_FLAGS,
    );
    let err = link_err(&[obj]);
    assert!(
        matches!(err, LinkError::UndefinedSymbol { ref symbol, .. } if symbol == "__trax_scene_no_such_field"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn duplicate_symbol_names_both_objects() {
    let dir = scratch("dup");
    let a = clang_text(
        &dir,
        "a",
        "int trax_main(void) { return 1; }\n",
        CLANG_FLAGS,
    );
    let b = clang_text(
        &dir,
        "b",
        "int trax_main(void) { return 2; }\n",
        CLANG_FLAGS,
    );
    match link_err(&[a, b]) {
        LinkError::DuplicateSymbol {
            symbol,
            first,
            second,
        } => {
            assert_eq!(symbol, "trax_main");
            assert!(
                first.ends_with("a.o") && second.ends_with("b.o"),
                "{first} {second}"
            );
        }
        e => panic!("wrong error: {e}"),
    }
    // A weak definition yields to a strong one, in either order.
    let w = clang_text(
        &dir,
        "w",
        "__attribute__((weak)) int trax_main(void) { return 3; }\n",
        CLANG_FLAGS,
    );
    let s = clang_text(
        &dir,
        "s",
        "int trax_main(void) { return 4; }\n",
        CLANG_FLAGS,
    );
    link(&inputs(&[w.clone(), s.clone()]), &LinkOptions::default()).unwrap();
    link(&inputs(&[s, w]), &LinkOptions::default()).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn branch_out_of_range_is_an_overflow() {
    let dir = scratch("overflow");
    // A 16-bit branch (±128 KiB) to a function placed 256 KiB away.
    let near = llc_text(
        &dir,
        "near",
        &format!(
            "{IR_HEADER}module asm \".text\"\nmodule asm \".globl trax_main\"\n\
             module asm \"trax_main:\"\nmodule asm \"  beq $4, $5, far_away\"\n\
             module asm \"  nop\"\nmodule asm \"  jrc $ra\"\n"
        ),
    );
    let far = llc_text(
        &dir,
        "far",
        &format!(
            "{IR_HEADER}module asm \".text\"\nmodule asm \".space 0x40000\"\n\
             module asm \".globl far_away\"\nmodule asm \"far_away:\"\n\
             module asm \"  jrc $ra\"\n"
        ),
    );
    match link_err(&[near, far]) {
        LinkError::RelocationOverflow(o) => {
            let RelocationOverflow {
                kind,
                file,
                section,
                symbol,
                value,
                ..
            } = *o;
            assert_eq!(kind, "R_MIPS_PC16");
            assert!(file.ends_with("near.o"));
            assert_eq!(section, ".text");
            assert_eq!(symbol, "far_away");
            assert!(value > 0x20000, "{value:#x}");
        }
        e => panic!("wrong error: {e}"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn pic_code_is_an_unsupported_relocation_with_a_hint() {
    let dir = scratch("pic");
    let obj = clang_text(
        &dir,
        "pic",
        "extern int other(void);\nint trax_main(void) { return other(); }\n\
         int other(void) { return 1; }\n",
        &[
            "--target=mipsel-unknown-elf",
            "-mcpu=mips32r6",
            "-G0",
            "-fpic",
            "-O0",
            "-c",
        ],
    );
    match link_err(&[obj]) {
        LinkError::UnsupportedRelocation { kind, hint, .. } => {
            assert!(
                kind.starts_with("R_MIPS_") && (kind.contains("GOT") || kind.contains("CALL")),
                "{kind}"
            );
            assert!(hint.contains("-fno-pic"), "{hint}");
        }
        e => panic!("wrong error: {e}"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn small_data_is_gp_relative_with_rebuild_advice() {
    let dir = scratch("gprel");
    let obj = clang_text(
        &dir,
        "small",
        "int small_var = 3;\nint trax_main(void) { return small_var; }\n",
        &[
            "--target=mipsel-unknown-elf",
            "-mcpu=mips32r6",
            "-G8",
            "-fno-pic",
            "-mno-abicalls",
            "-mgpopt",
            "-O2",
            "-c",
        ],
    );
    let err = link_err(&[obj]);
    match &err {
        LinkError::GpRelative { file, what } => {
            assert!(file.ends_with("small.o"));
            assert!(what.contains("GPREL") || what.contains("SCOMMON"), "{what}");
        }
        e => panic!("wrong error: {e}"),
    }
    assert!(err.to_string().contains("-G0"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn hi16_without_lo16_is_reported() {
    let dir = scratch("unpaired");
    let obj = llc_text(
        &dir,
        "hi",
        &format!(
            "{IR_HEADER}@v = global i32 0\nmodule asm \".text\"\nmodule asm \".globl trax_main\"\n\
             module asm \"trax_main:\"\nmodule asm \"  lui $2, %hi(v)\"\nmodule asm \"  jrc $ra\"\n"
        ),
    );
    match link_err(&[obj]) {
        LinkError::UnpairedHi16 {
            kind, pair, symbol, ..
        } => {
            assert_eq!(kind, "R_MIPS_HI16");
            assert_eq!(pair, "R_MIPS_LO16");
            assert_eq!(symbol, "v");
        }
        e => panic!("wrong error: {e}"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn other_isa_is_incompatible() {
    let dir = scratch("isa");
    let obj = clang_text(
        &dir,
        "r2",
        "int trax_main(void) { return 1; }\n",
        &[
            "--target=mipsel-unknown-elf",
            "-mcpu=mips32r2",
            "-G0",
            "-fno-pic",
            "-mno-abicalls",
            "-c",
        ],
    );
    match link_err(&[obj]) {
        LinkError::Incompatible { file, detail } => {
            assert!(file.ends_with("r2.o"));
            assert!(detail.contains("mips32r6"), "{detail}");
        }
        e => panic!("wrong error: {e}"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn malformed_inputs_name_the_file() {
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("empty.o", vec![]),
        (
            "text.o",
            b"this is not an ELF file at all, just text".to_vec(),
        ),
        ("elf64.o", {
            let mut v = vec![0x7f, b'E', b'L', b'F', 2, 1, 1];
            v.resize(64, 0);
            v
        }),
    ];
    for (name, bytes) in cases {
        let err = link(
            &[Input {
                name: name.into(),
                bytes,
            }],
            &LinkOptions::default(),
        )
        .unwrap_err();
        match err {
            LinkError::Malformed { file, .. } => assert_eq!(file, name),
            e => panic!("{name}: wrong error: {e}"),
        }
    }
    // An executable is not an input.
    let dir = scratch("exec-input");
    let obj = clang_text(
        &dir,
        "m",
        "int trax_main(void) { return 0; }\n",
        CLANG_FLAGS,
    );
    let exe = link(&inputs(&[obj]), &LinkOptions::default()).unwrap().elf;
    let err = link(
        &[Input {
            name: "prog.elf".into(),
            bytes: exe.clone(),
        }],
        &LinkOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(err, LinkError::Malformed { ref detail, .. } if detail.contains("ET_REL")),
        "{err}"
    );
    // ... and an object is not an executable.
    let obj_bytes = std::fs::read(dir.join("m.o")).unwrap();
    assert!(Executable::parse("m.o", &obj_bytes).is_err());
    assert!(Executable::parse("prog.elf", &exe).is_ok());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Damaged objects: every outcome is a value, never a panic.
#[test]
fn corrupt_objects_never_panic() {
    let dir = scratch("corrupt");
    let mut flags = CLANG_FLAGS.to_vec();
    flags.push("-fcommon");
    let obj = clang(&dir, "link_util.c", &flags);
    let good = std::fs::read(&obj).unwrap();
    let main = clang_text(
        &dir,
        "m",
        "int trax_main(void) { return 0; }\n",
        CLANG_FLAGS,
    );
    let main = Input {
        name: "m.o".into(),
        bytes: std::fs::read(main).unwrap(),
    };
    let mut outcomes = (0, 0);
    // Truncations.
    for len in (0..good.len()).step_by(97) {
        let input = Input {
            name: "cut.o".into(),
            bytes: good[..len].to_vec(),
        };
        match link(&[main.clone(), input], &LinkOptions::default()) {
            Ok(_) => outcomes.0 += 1,
            Err(_) => outcomes.1 += 1,
        }
    }
    // Byte corruption at many offsets, with several values.
    for (i, at) in (0..good.len()).step_by(13).enumerate() {
        let mut bytes = good.clone();
        bytes[at] = [0xFF, 0x00, 0x80, 0x7F][i % 4] ^ bytes[at].rotate_left(3);
        let input = Input {
            name: "bad.o".into(),
            bytes,
        };
        match link(&[main.clone(), input], &LinkOptions::default()) {
            Ok(l) => {
                outcomes.0 += 1;
                // Whatever we produced must read back.
                Executable::parse("out", &l.elf).unwrap();
            }
            Err(e) => {
                outcomes.1 += 1;
                assert!(!e.to_string().is_empty());
            }
        }
    }
    assert!(outcomes.1 > 0, "some corruptions must be detected");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_text_base_is_an_invalid_option() {
    for base in [0u32, 0x100, 0x10_0002] {
        let opts = LinkOptions {
            text_base: base,
            ..LinkOptions::default()
        };
        let err = link(&[], &opts).unwrap_err();
        assert!(
            matches!(err, LinkError::InvalidOption(_)),
            "{base:#x}: {err}"
        );
    }
}

/// Offset of the section header named `want` in an ELF32 LE object.
fn section_header(elf: &[u8], want: &str) -> usize {
    let u32_at = |o: usize| u32::from_le_bytes(elf[o..o + 4].try_into().unwrap()) as usize;
    let u16_at = |o: usize| u16::from_le_bytes(elf[o..o + 2].try_into().unwrap()) as usize;
    let (shoff, size, n, strndx) = (u32_at(0x20), u16_at(0x2e), u16_at(0x30), u16_at(0x32));
    let strtab = u32_at(shoff + strndx * size + 16);
    (0..n)
        .map(|i| shoff + i * size)
        .find(|&h| {
            let name = &elf[strtab + u32_at(h)..];
            name.starts_with(want.as_bytes()) && name[want.len()] == 0
        })
        .unwrap_or_else(|| panic!("no section {want}"))
}

/// Section headers that would make the linker materialise gigabytes are rejected: a
/// contents-less (SHT_NOBITS) section going into `.text` (found by fuzzing: a 704 MB
/// `.bss` with the exec flag was filled with trap words), and a huge alignment.
#[test]
fn sections_that_would_size_the_output_at_gigabytes_are_rejected() {
    let dir = scratch("huge");
    let main = clang_text(
        &dir,
        "m",
        "int trax_main(void) { return 0; }\n",
        CLANG_FLAGS,
    );
    let good = std::fs::read(&main).unwrap();
    let h = section_header(&good, ".text");
    let link_bytes = |bytes: Vec<u8>| {
        link(
            &[Input {
                name: "m.o".into(),
                bytes,
            }],
            &LinkOptions::default(),
        )
        .expect_err("must be rejected")
        .to_string()
    };
    let mut nobits = good.clone();
    nobits[h + 4..h + 8].copy_from_slice(&8u32.to_le_bytes()); // SHT_NOBITS
    nobits[h + 20..h + 24].copy_from_slice(&0x2a00_0000u32.to_le_bytes());
    let e = link_bytes(nobits);
    assert!(
        e.contains("m.o") && e.contains("SHT_NOBITS") && e.contains(".text"),
        "{e}"
    );
    let mut aligned = good.clone();
    aligned[h + 32..h + 36].copy_from_slice(&0x4000_0000u32.to_le_bytes());
    let e = link_bytes(aligned);
    assert!(
        e.contains("m.o") && e.contains("alignment 1073741824"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
