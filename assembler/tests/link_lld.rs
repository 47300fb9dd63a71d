//! Links clang-14 and llc objects with our linker and with ld.lld-14 (same layout through
//! `lld_script`), and compares disassembly, DWARF line tables, section contents and symbols.

mod link_common;

use std::path::{Path, PathBuf};
use std::process::Command;

use link_common::*;
use object::{Object, ObjectSection};
use trax_assembler::link::{self, lld_script, startup::startup_object, LinkOptions};
use trax_runtime::abi;
use trax_runtime::exe::Executable;
use trax_runtime::image::Perms;

/// Links `objs` with our linker and with ld.lld-14; returns (ours, lld's) executable paths.
fn link_both(dir: &Path, objs: &[PathBuf]) -> (PathBuf, PathBuf, link::Linked) {
    let linked = link::link(&inputs(objs), &LinkOptions::default()).expect("our link");
    let ours = dir.join("ours.elf");
    std::fs::write(&ours, &linked.elf).unwrap();

    let startup = dir.join("startup.o");
    std::fs::write(&startup, startup_object().unwrap()).unwrap();
    let script = lld_script(abi::TEXT_BASE);
    let script_path = dir.join("trax.ld");
    std::fs::write(&script_path, script).unwrap();
    let lld = dir.join("lld.elf");
    run(Command::new("ld.lld-14")
        .args(["-O0", "-static", "--no-gc-sections", "-T"])
        .arg(&script_path)
        .arg("-o")
        .arg(&lld)
        .arg(&startup)
        .args(objs));
    (ours, lld, linked)
}

/// `llvm-objdump -d` output from the first section heading on (the file name differs).
fn disassembly(path: &Path) -> String {
    let out = run(Command::new("llvm-objdump")
        .args(["-d", "--mattr=+msa"])
        .arg(path));
    let start = out.find("Disassembly of section").expect("no disassembly");
    // Drop the symbolic ` <sym+off>` comments on instruction lines: ld.lld adds `_gp` and
    // other linker symbols the comments may pick. Raw bytes and operands stay compared.
    out[start..]
        .lines()
        .map(|l| match (l.starts_with(' '), l.rfind(" <")) {
            (true, Some(i)) if l.ends_with('>') => &l[..i],
            _ => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The line-table rows of `llvm-dwarfdump --debug-line` (address, line, column, file,
/// flags), one per line, with sequence boundaries.
fn line_rows(path: &Path) -> Vec<String> {
    let out = run(Command::new("llvm-dwarfdump").arg("--debug-line").arg(path));
    out.lines()
        .filter(|l| l.starts_with("0x") && l.split_whitespace().count() >= 7)
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect()
}

/// File names listed in the line table headers.
fn line_files(path: &Path) -> Vec<String> {
    let out = run(Command::new("llvm-dwarfdump").arg("--debug-line").arg(path));
    out.lines()
        .filter(|l| l.trim_start().starts_with("name:"))
        .map(|l| l.trim().to_string())
        .collect()
}

/// (address, contents) of a section by name.
fn section(elf: &[u8], name: &str) -> Option<(u64, Vec<u8>)> {
    let file = object::File::parse(elf).unwrap();
    let s = file.section_by_name(name)?;
    Some((s.address(), s.data().unwrap().to_vec()))
}

fn compare(dir: &Path, objs: &[PathBuf]) -> link::Linked {
    let (ours, lld, linked) = link_both(dir, objs);
    let (dis_ours, dis_lld) = (disassembly(&ours), disassembly(&lld));
    assert!(dis_ours.contains("<__trax_start>:"), "{dis_ours}");
    assert!(dis_ours.contains("<trax_main>:"));
    assert_eq!(
        dis_ours,
        dis_lld,
        "disassembly differs from ld.lld (see {})",
        dir.display()
    );

    let (rows_ours, rows_lld) = (line_rows(&ours), line_rows(&lld));
    assert!(rows_ours.len() > 10, "too few line rows: {rows_ours:?}");
    assert_eq!(rows_ours, rows_lld, "line table rows differ");
    assert_eq!(
        line_files(&ours),
        line_files(&lld),
        "line table file names differ"
    );

    let (b_ours, b_lld) = (std::fs::read(&ours).unwrap(), std::fs::read(&lld).unwrap());
    for name in [".text", ".rodata", ".init_array", ".data"] {
        // ld.lld keeps an empty .init_array (it holds the bound symbols); we omit it.
        let a = section(&b_ours, name).filter(|s| !s.1.is_empty());
        let b = section(&b_lld, name).filter(|s| !s.1.is_empty());
        assert_eq!(a, b, "section {name} differs");
    }
    // .bss: same address and size.
    let bss = |bytes: &[u8]| {
        let f = object::File::parse(bytes).unwrap();
        f.section_by_name(".bss").map(|s| (s.address(), s.size()))
    };
    assert_eq!(bss(&b_ours), bss(&b_lld));

    // Every global symbol lld defines has the same address in ours.
    let exe_ours = Executable::parse("ours", &b_ours).unwrap();
    let exe_lld = Executable::parse("lld", &b_lld).unwrap();
    assert_eq!(exe_ours.entry, exe_lld.entry);
    assert_eq!(exe_ours.entry, abi::TEXT_BASE);
    for s in exe_lld.symbols.iter().filter(|s| s.is_global) {
        if ["_gp", "_gp_disp", "__gnu_local_gp"].contains(&s.name.as_str()) {
            continue; // ld.lld's MIPS GOT symbols; TRaX code has no $gp
        }
        if s.name.starts_with(link::SCENE_SYMBOL_PREFIX) && !s.is_absolute {
            continue;
        }
        if s.name.starts_with(link::SCENE_SYMBOL_PREFIX) && exe_ours.symbol(&s.name).is_none() {
            continue; // lld keeps PROVIDEd symbols only when referenced; so do we
        }
        let mine = exe_ours
            .symbol(&s.name)
            .unwrap_or_else(|| panic!("symbol {} missing from our output", s.name));
        assert_eq!(mine.addr, s.addr, "address of {}", s.name);
    }
    linked
}

fn has_tools() {
    for tool in [
        "clang-14",
        "ld.lld-14",
        "llc",
        "llvm-objdump",
        "llvm-dwarfdump",
    ] {
        assert!(
            Command::new(tool).arg("--version").output().is_ok(),
            "{tool} is required (see .ci/run)"
        );
    }
}

#[test]
fn clang_objects_match_lld() {
    has_tools();
    let dir = scratch("clang");
    let mut flags = CLANG_FLAGS.to_vec();
    flags.push("-fcommon");
    let main = clang(&dir, "link_main.c", &flags);
    let util = clang(&dir, "link_util.c", &flags);
    let linked = compare(&dir, &[main, util]);
    assert_eq!(linked.scene_components(), vec!["triangles", "bvh_nodes"]);

    let exe = Executable::parse("ours", &linked.elf).unwrap();
    // Common symbol allocated once, in .bss.
    let common = exe.symbol("shared_counter").unwrap();
    let bss = linked.sections.iter().find(|s| s.name == ".bss").unwrap();
    assert!(common.addr >= bss.addr && common.addr < bss.addr + bss.size);
    // Two constructors survive clang -O2 (main_init is evaluated at compile time); the
    // prioritised one (.init_array.101) comes first.
    let init = linked
        .sections
        .iter()
        .find(|s| s.name == ".init_array")
        .unwrap();
    assert_eq!(init.size, 8);
    let (_, words) = section(&linked.elf, ".init_array").unwrap();
    let first = u32::from_le_bytes(words[0..4].try_into().unwrap());
    let early = exe
        .symbols
        .iter()
        .find(|s| s.name == "util_init_early")
        .unwrap();
    assert_eq!(first, early.addr);
    // Scene symbols are absolute and point into the header.
    let tri = exe.symbol("__trax_scene_triangles").unwrap();
    assert!(tri.is_absolute);
    let off = abi::scene_header_fields()
        .iter()
        .find(|f| f.0 == "triangles")
        .unwrap()
        .1;
    assert_eq!(tri.addr, abi::SCENE_HEADER_ADDR + off as u32);
    assert_eq!(exe.referenced, vec!["bvh_nodes", "triangles"]);
    // Segments: text R+X at TEXT_BASE, data R+W with bss beyond the file size.
    assert_eq!(exe.segments.len(), 2);
    let (text, data) = (&exe.segments[0], &exe.segments[1]);
    assert!(text.perms == Perms::RX && text.addr == abi::TEXT_BASE);
    assert!(data.perms == Perms::RW);
    assert!(
        data.size as usize >= data.data.len() + 4000,
        "bss holds util_big_buffer"
    );
    let end = exe.symbol("_end").unwrap();
    assert_eq!(end.addr, data.addr + data.size);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn llc_objects_match_lld() {
    has_tools();
    let dir = scratch("llc");
    let kernel = llc(&dir, "link_kernel.ll");
    let lib = llc(&dir, "link_lib.ll");
    let linked = compare(&dir, &[kernel, lib]);
    assert_eq!(linked.scene_components(), vec!["framebuffer"]);
    let dis = disassembly(&dir.join("ours.elf"));
    for insn in ["auipc", "lwpc", "beqzc", "bc\t", "fmul.w", "jal\t"] {
        assert!(dis.contains(insn), "expected {insn} in the disassembly");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn mixed_clang_and_llc_objects_match_lld() {
    has_tools();
    let dir = scratch("mixed");
    let helper = clang_text(
        &dir,
        "helper",
        "extern int pick(int);\nint lib_counter_probe;\n\
         int clang_helper(int x) { return pick(x) + 1; }\n",
        CLANG_FLAGS,
    );
    let kernel = llc(&dir, "link_kernel.ll");
    let lib = llc(&dir, "link_lib.ll");
    let linked = compare(&dir, &[kernel, helper, lib]);
    assert!(linked.sections.iter().any(|s| s.name == ".debug_line"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn comdat_groups_and_function_sections_match_lld() {
    has_tools();
    let dir = scratch("comdat");
    // C++ inline functions land in COMDAT groups; the second copy must be dropped.
    let mut flags = vec!["-x", "c++", "-ffunction-sections", "-fdata-sections"];
    flags.extend_from_slice(CLANG_FLAGS);
    let a = clang_text(
        &dir,
        "a",
        "__attribute__((noinline)) inline int shared_inline(int x) { return x * 7 + 1; }\n\
         int use_b(int x);\nint table_a[3] = {1, 2, 3};\n\
         extern \"C\" int trax_main() { return use_b(3) + shared_inline(table_a[1]); }\n",
        &flags,
    );
    let b = clang_text(
        &dir,
        "b",
        "__attribute__((noinline)) inline int shared_inline(int x) { return x * 7 + 1; }\n\
         static int zeroes_b[8];\nconst char *name_b = \"b\";\n\
         int use_b(int x) { return shared_inline(x) + zeroes_b[x & 7] + name_b[0]; }\n",
        &flags,
    );
    let linked = compare(&dir, &[a, b]);
    let exe = Executable::parse("ours", &linked.elf).unwrap();
    let copies = exe
        .symbols
        .iter()
        .filter(|s| s.name == "_Z13shared_inlinei")
        .count();
    assert_eq!(copies, 1, "one definition of the inline function survives");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gdb_reads_lines_and_symbols() {
    has_tools();
    let dir = scratch("gdb");
    let mut flags = CLANG_FLAGS.to_vec();
    flags.push("-fcommon");
    let objs = [
        clang(&dir, "link_main.c", &flags),
        clang(&dir, "link_util.c", &flags),
    ];
    let linked = link::link(&inputs(&objs), &LinkOptions::default()).unwrap();
    let exe = dir.join("prog.elf");
    std::fs::write(&exe, &linked.elf).unwrap();
    let out = Command::new("gdb-multiarch")
        .args([
            "-nx",
            "-batch",
            "-ex",
            "info line classify",
            "-ex",
            "info symbol 0x100000",
        ])
        .arg(&exe)
        .output()
        .expect("gdb-multiarch is required (see .ci/run)");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("link_main.c"), "gdb output: {text}");
    assert!(text.contains("__trax_start"), "gdb output: {text}");
    let _ = std::fs::remove_dir_all(&dir);
}
