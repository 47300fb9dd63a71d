//! One crash per kind: each report must name the fault and the right source line.

mod common;
use common::*;
use trax_emulator::Fault;
use trax_emulator::Outcome;

/// Builds and runs `src`; returns the fault and the report. `marker` is a comment on the
/// line that must be reported; its line number is found in the source.
fn crash(name: &str, src: &str, opt: &str) -> (Fault, String, u32) {
    let line = src
        .lines()
        .position(|l| l.contains("// CRASH"))
        .expect("marker") as u32
        + 1;
    let elf = build_c(name, src, opt);
    let (r, _) = run_elf(&elf, 1, 1);
    let report = r.failure.clone().unwrap_or_default();
    match r.outcome {
        Outcome::Crashed(c) => (c.fault, report, line),
        o => panic!("{name}: expected a crash, got {o:?}"),
    }
}

fn assert_line(name: &str, report: &str, line: u32) {
    let needle = format!("{name}.c:{line}");
    assert!(
        report.contains(&needle),
        "report should name {needle}:\n{report}"
    );
}

#[test]
fn null_dereference() {
    let src = "#include \"trax.h\"\nint *volatile p = 0;\nint get(void) {\n  return *p; // CRASH\n}\nvoid trax_main(void) { trax_printi(get()); }\n";
    let (f, report, line) = crash("null", src, "-O1");
    assert!(
        matches!(f, Fault::Memory { fault, .. } if fault.kind == trax_emulator::MemFaultKind::Null),
        "{f:?}"
    );
    assert!(report.contains("null pointer dereference"), "{report}");
    assert_line("null", &report, line);
    assert!(
        report.contains("backtrace:") && report.contains("trax_main"),
        "{report}"
    );
}

/// MIPS32r6 performs misaligned loads and stores (LLVM's r6 backend relies on it for byte
/// arrays and packed fields); the values must be the bytes at those addresses.
#[test]
fn misaligned_loads_and_stores_are_performed() {
    let src = "#include \"trax.h\"\nunsigned char buf[16];\nvoid trax_main(void) {\n  for (int i = 0; i < 16; i++) buf[i] = (unsigned char)(i * 17);\n  volatile unsigned *w = (volatile unsigned *)(buf + 1);\n  trax_printu(*w);\n  volatile unsigned short *h = (volatile unsigned short *)(buf + 7);\n  trax_printu(*h);\n  *(volatile unsigned *)(buf + 10) = 0xA1B2C3D4u;\n  for (int i = 9; i < 15; i++) trax_printu(buf[i]);\n}\n";
    for opt in ["-O0", "-O2"] {
        let elf = build_c("misaligned_ok", src, opt);
        let (r, out) = run_elf(&elf, 1, 1);
        assert!(r.failure.is_none(), "{opt}: {:?}", r.failure);
        // Little-endian words of the bytes i*17 (computed here, on the host).
        let b = |i: u32| i * 17;
        let mut want = format!("{}", b(1) | b(2) << 8 | b(3) << 16 | b(4) << 24);
        want += &format!("{}", b(7) | b(8) << 8);
        for v in [b(9), 0xD4, 0xC3, 0xB2, 0xA1, b(14)] {
            want += &v.to_string();
        }
        assert_eq!(out, want, "{opt}");
    }
}

/// `ll`/`sc` still need alignment: an Address Error, reported with its line.
#[test]
fn misaligned_ll() {
    let src = "#include \"trax.h\"\nchar buf[16];\nint bump(char *q) {\n  return __atomic_fetch_add((int *)(q + 1), 1, __ATOMIC_SEQ_CST); // CRASH\n}\nvoid trax_main(void) { trax_printi(bump(buf)); }\n";
    let (f, report, line) = crash("misaligned", src, "-O0");
    assert!(
        matches!(f, Fault::Memory { fault, .. } if fault.kind == trax_emulator::MemFaultKind::Misaligned),
        "{f:?}"
    );
    assert!(report.contains("misaligned access"), "{report}");
    assert_line("misaligned", &report, line);
}

#[test]
fn bad_address_store() {
    let src = "#include \"trax.h\"\n__attribute__((noinline)) void put(int *q) {\n  *q = 5; // CRASH\n}\nvoid trax_main(void) { put((int *)0x40000000); }\n";
    let (_, report, line) = crash("badaddr", src, "-O0");
    assert!(
        report.contains("bad address: 4-byte store at address 0x40000000"),
        "{report}"
    );
    assert_line("badaddr", &report, line);
}

#[test]
fn stack_overflow() {
    let src = "#include \"trax.h\"\nint deep(volatile int n) {\n  volatile int pad[64];\n  pad[0] = n; // CRASH\n  return deep(n + 1) + pad[0];\n}\nvoid trax_main(void) { trax_printi(deep(0)); }\n";
    let (_, report, line) = crash("overflow", src, "-O0");
    assert!(report.contains("stack overflow"), "{report}");
    assert_line("overflow", &report, line);
}

#[test]
fn integer_divide_by_zero_trap() {
    let src = "#include \"trax.h\"\nint div(int a, int b) {\n  return a / b; // CRASH\n}\nvoid trax_main(void) { volatile int z = 0; trax_printi(div(7, z)); }\n";
    let (f, report, line) = crash("divzero", src, "-O1");
    assert_eq!(f, Fault::Trap { code: 7 });
    assert!(report.contains("integer divide by zero"), "{report}");
    assert_line("divzero", &report, line);
}

#[test]
fn reserved_instruction() {
    let src = "#include \"trax.h\"\nvoid trax_main(void) {\n  __asm__ volatile(\".word 0x7000003f\"); // CRASH\n}\n";
    let (f, report, line) = crash("reserved", src, "-O1");
    assert_eq!(f, Fault::ReservedInstruction(0x7000_003F));
    assert!(
        report.contains("reserved instruction 0x7000003f"),
        "{report}"
    );
    assert_line("reserved", &report, line);
}

#[test]
fn abort_with_message() {
    let src = "#include \"trax.h\"\nstatic const char msg[] = \"index 7 out of range for length 4\";\nvoid check(unsigned i) {\n  if (i >= 4) trax_abort(1, (unsigned)msg, sizeof msg - 1); // CRASH\n}\nvoid trax_main(void) { check(7); }\n";
    let (f, report, line) = crash("abort", src, "-O1");
    assert!(matches!(f, Fault::Abort { code: 1, .. }), "{f:?}");
    assert!(
        report.contains("  what: panicked: index 7 out of range for length 4\n"),
        "{report}"
    );
    assert_line("abort", &report, line);
}

/// A formatted message: an argument record (template, then 8-byte slots) rendered with
/// Rust's `Display`/`Debug`; continuation lines stay in the message column. Each argument
/// in the template is `\0`, its kind (`u`/`i` with a size in bytes, `f`, `s`), a flags
/// byte and its trait (`D` Display, `?` Debug).
#[test]
fn abort_with_formatted_message() {
    let src = "#include \"trax.h\"\nstatic const char tpl[] = \"index out of bounds: the len is 4 but the index is \\0u\\004\\000D\\n  left: \\0f\\000?\\n right: \\0s\\000? \\0\\0 \\0i\\010\\000D\";\nstatic const char s[] = \"a\\\"b\";\nvoid check(unsigned i) {\n  volatile unsigned rec[10] = {(unsigned)tpl, sizeof tpl - 1, i, 0, 0x3f800000, 0, (unsigned)s, 3, 0xfffffffb, 0xffffffff};\n  if (i >= 4) trax_abort(0x101, (unsigned)rec, sizeof rec); // CRASH\n}\nvoid trax_main(void) { check(7); }\n";
    let (f, report, line) = crash("abortfmt", src, "-O1");
    assert!(
        matches!(
            f,
            Fault::Abort {
                code: 1,
                kind: Some(trax_runtime::isa::AbortKind::Bounds),
                ..
            }
        ),
        "{f:?}"
    );
    let want = "  what: panicked: index out of bounds: the len is 4 but the index is 7\n          left: 1.0\n         right: \"a\\\"b\" \0 -5\n";
    assert!(report.contains(want), "{report}");
    assert_line("abortfmt", &report, line);
}

#[test]
fn inline_chain_is_reported() {
    let src = "#include \"trax.h\"\nint *volatile p = 0;\nstatic inline __attribute__((always_inline)) int inner(void) {\n  return *p; // CRASH\n}\nvoid trax_main(void) { trax_printi(inner() + 1); }\n";
    let (_, report, line) = crash("inline", src, "-O2");
    assert_line("inline", &report, line);
    assert!(
        report.contains("in inner, inlined into trax_main"),
        "{report}"
    );
}

/// A store in a branch's delay slot is reported on its own source line (once the line
/// after it).
#[test]
fn store_in_a_delay_slot_names_its_line() {
    let src = "#include \"trax.h\"\nint *volatile p = (int *)0x40000000;\nvoid trax_main(void) {\n  int *q = p;\n  __asm__ volatile(\".set noreorder\\n\\tbeq $0, $0, 1f\\n\\tsw $0, 0(%0)\\n1:\\n\\t.set reorder\" :: \"r\"(q) : \"memory\"); // CRASH\n  trax_printi(1);\n  trax_printi(2);\n}\n";
    let (_, report, line) = crash("slotstore", src, "-O1");
    assert!(report.contains("(in a delay/forbidden slot)"), "{report}");
    assert!(report.contains("sw $0, 0("), "{report}");
    assert_line("slotstore", &report, line);
}

/// The same slot store in timing mode: the report names the line and the cycle of the fault.
#[test]
fn timing_crash_names_the_line_and_cycle() {
    let src = "#include \"trax.h\"\nint *volatile p = (int *)0x40000000;\nvoid trax_main(void) {\n  int *q = p;\n  __asm__ volatile(\".set noreorder\\n\\tbeq $0, $0, 1f\\n\\tsw $0, 0(%0)\\n1:\\n\\t.set reorder\" :: \"r\"(q) : \"memory\"); // CRASH\n  trax_printi(1);\n  trax_printi(2);\n}\n";
    let line = 5;
    let elf = build_c("slotstore_timing", src, "-O1");
    let data = std::fs::read(&elf).unwrap();
    let path = elf.display().to_string();
    let chip = trax_emulator::timing::ChipConfig::preset("tiny").unwrap();
    let mut chip1 = chip.clone();
    chip1.threads_per_tm = 1;
    let mut req = trax_emulator::RunRequest::new(&path, &data, &chip1, trax_emulator::Mode::Timing);
    req.host_threads = Some(1);
    let r = trax_emulator::run(req, &mut std::io::sink()).unwrap();
    let report = r.failure.clone().unwrap_or_default();
    let Outcome::Crashed(c) = &r.outcome else {
        panic!("expected a crash:\n{report}");
    };
    assert!(c.in_slot, "{report}");
    assert!(report.contains("(in a delay/forbidden slot)"), "{report}");
    assert_line("slotstore_timing", &report, line);
    let cycles = r.cycles.unwrap();
    assert!(
        report.contains(&format!("at cycle {cycles}")),
        "the report names the cycle of the fault ({cycles}):\n{report}"
    );
}

/// A kernel that stores through a pointer into its own code, and the report of the fault:
/// program text is read-only (the `text` segment is `r-x`), so the store faults instead of
/// changing the code the machine has predecoded. Built at -O0: at -O1 clang moves the store
/// into `jr $ra`'s delay slot and its line table gives it the line of the `}`.
const CODE_STORE: &str = "#include \"trax.h\"\n__attribute__((noinline)) void patch(volatile unsigned *code) {\n  *code = 0; // CRASH\n}\nvoid trax_main(void) {\n  patch((volatile unsigned *)(void *)&trax_main);\n  trax_printi(1);\n}\n";

fn assert_code_store_report(name: &str, report: &str, line: u32) {
    assert!(report.contains("store to read-only memory"), "{report}");
    assert!(report.contains("segment `text`"), "{report}");
    assert!(report.contains("r-x"), "{report}");
    assert_line(name, report, line);
}

#[test]
fn store_to_code_is_a_fault() {
    let (f, report, line) = crash("codestore", CODE_STORE, "-O0");
    assert!(
        matches!(f, Fault::Memory { fault, .. }
            if fault.kind == trax_emulator::MemFaultKind::ReadOnly && fault.write),
        "{f:?}"
    );
    assert_code_store_report("codestore", &report, line);
}

/// The same store in timing mode (stores reach global memory in the serial phase).
#[test]
fn store_to_code_is_a_fault_in_timing_mode() {
    let line = 3;
    let elf = build_c("codestore_timing", CODE_STORE, "-O0");
    let data = std::fs::read(&elf).unwrap();
    let path = elf.display().to_string();
    let chip = chip(1, 2);
    let mut req = trax_emulator::RunRequest::new(&path, &data, &chip, trax_emulator::Mode::Timing);
    req.host_threads = Some(1);
    let mut out = Vec::new();
    let r = trax_emulator::run(req, &mut out).unwrap();
    let report = r.failure.clone().unwrap_or_default();
    let Outcome::Crashed(c) = &r.outcome else {
        panic!("expected a crash:\n{report}");
    };
    assert!(
        matches!(c.fault, Fault::Memory { fault, .. } if fault.kind == trax_emulator::MemFaultKind::ReadOnly),
        "{:?}",
        c.fault
    );
    assert_code_store_report("codestore_timing", &report, line);
    assert!(out.is_empty(), "nothing runs after the faulting store");
}
