//! gdb-multiarch drives the in-process GDB server in batch mode: breakpoints at
//! file:line in an inlined function, backtraces with inline frames, locals, step,
//! continue, run to exit, and a crash stopping at the crashing line.

mod common;
use common::*;

use std::net::TcpListener;
use std::path::Path;
use std::process::Command;
use std::sync::mpsc;
use std::time::Duration;

use trax_emulator::gdb;
use trax_emulator::Executable;
use trax_emulator::{Machine, MachineConfig, Outcome};

fn line_of(src: &str, marker: &str) -> usize {
    src.lines()
        .position(|l| l.contains(marker))
        .expect("marker")
        + 1
}

/// Serves `elf` on a free loopback port and runs gdb-multiarch with `cmds`; returns
/// gdb's output and the outcome the server saw.
fn session(elf: &Path, threads: u32, cmds: &[String]) -> (String, Option<Outcome>) {
    let data = std::fs::read(elf).unwrap();
    let exe = Executable::parse("k", &data).unwrap();
    let config = MachineConfig {
        threads_per_tm: threads,
        ..MachineConfig::default()
    };
    let mut m = Machine::load(&exe, None, config).unwrap();
    let listener: TcpListener = gdb::bind("127.0.0.1:0", false).unwrap();
    let port = listener.local_addr().unwrap().port();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let r = gdb::serve_listener(&mut m, listener, &mut std::io::sink());
        let _ = tx.send(r.map_err(|e| e.to_string()));
    });
    let mut args: Vec<String> = vec![
        "60".into(),
        "gdb-multiarch".into(),
        "-batch".into(),
        "-nx".into(),
    ];
    let mut ex = |c: &str| {
        args.push("-ex".into());
        args.push(c.into());
    };
    ex("set pagination off");
    ex("set confirm off");
    ex("set architecture mips:isa32r6");
    ex(&format!("file {}", elf.display()));
    ex(&format!("target remote 127.0.0.1:{port}"));
    for c in cmds {
        ex(c);
    }
    let out = Command::new("timeout")
        .args(&args)
        .output()
        .expect("run gdb-multiarch");
    let text = format!(
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    eprintln!("{text}");
    let outcome = match rx.recv_timeout(Duration::from_secs(20)) {
        Ok(Ok(o)) => o,
        Ok(Err(e)) => panic!("server error: {e}\n{text}"),
        Err(_) => panic!("server did not finish\n{text}"),
    };
    (text, outcome)
}

const SRC: &str = r#"#include "trax.h"
static inline __attribute__((always_inline)) int scale(int x) {
  int doubled = x * 2;
  return doubled + 1; // BREAK
}
__attribute__((noinline)) int compute(int n) {
  int acc = 0;
  for (int i = 0; i < n; i++) acc += scale(i + 20); // CALL
  return acc; // AFTER
}
void trax_main(void) { trax_printi(compute(3)); }
"#;

#[test]
fn breakpoint_inline_backtrace_locals_step_continue() {
    let elf = build_c("gdbinline", SRC, "-O0");
    let brk = line_of(SRC, "// BREAK");
    let after = line_of(SRC, "// AFTER");
    let cmds: Vec<String> = vec![
        format!("break gdbinline.c:{brk}"),
        "continue".into(),
        "bt".into(),
        "info locals".into(),
        "print doubled".into(),
        "print x".into(),
        "continue".into(),
        "print doubled".into(),
        "delete".into(),
        format!("break gdbinline.c:{after}"),
        "continue".into(),
        "print acc".into(),
        // Returns (a compact `jrc`) into trax_main and steps into the inlined print.
        "step".into(),
        "info threads".into(),
        "delete".into(),
        "continue".into(),
    ];
    let (out, outcome) = session(&elf, 1, &cmds);
    assert!(out.contains(&format!("gdbinline.c:{brk}")), "{out}");
    // Backtrace: the inlined frame, its caller and the caller's caller.
    let bt: Vec<&str> = out.lines().filter(|l| l.starts_with('#')).collect();
    assert!(bt.iter().any(|l| l.contains("scale")), "{out}");
    assert!(bt.iter().any(|l| l.contains("compute")), "{out}");
    assert!(bt.iter().any(|l| l.contains("trax_main")), "{out}");
    assert!(out.contains("doubled = 40"), "info locals:\n{out}");
    assert!(out.contains("$1 = 40"), "{out}");
    assert!(out.contains("$2 = 20"), "{out}");
    // Second hit after `continue`: next iteration.
    assert!(out.contains("$3 = 42"), "{out}");
    // 21 + 43 + 45 = 129 at the line after the loop.
    assert!(out.contains("$4 = 129"), "{out}");
    assert!(out.contains("trax_printi (a0=129)"), "step:\n{out}");
    assert!(out.contains("exited normally"), "{out}");
    assert!(
        matches!(outcome, Some(Outcome::Finished)),
        "{outcome:?}\n{out}"
    );
}

#[test]
fn crash_stops_at_crashing_line_with_sigsegv() {
    let src = "#include \"trax.h\"\nint *volatile p = 0;\n__attribute__((noinline)) int get(int k) {\n  int v = k + 1;\n  return *p + v; // CRASH\n}\nvoid trax_main(void) { trax_printi(get(4)); }\n";
    let elf = build_c("gdbcrash", src, "-O0");
    let line = line_of(src, "// CRASH");
    let cmds: Vec<String> = vec!["continue".into(), "bt".into(), "print v".into()];
    let (out, outcome) = session(&elf, 2, &cmds);
    assert!(out.contains("SIGSEGV"), "{out}");
    assert!(out.contains(&format!("gdbcrash.c:{line}")), "{out}");
    assert!(out.contains("$1 = 5"), "{out}");
    assert!(
        matches!(outcome, Some(Outcome::Crashed(_))),
        "{outcome:?}\n{out}"
    );
}

#[test]
fn refuses_non_loopback() {
    assert!(matches!(
        gdb::bind("0.0.0.0:0", false),
        Err(gdb::GdbError::NotLoopback(_))
    ));
    assert!(gdb::bind("not an address", false).is_err());
}

/// A TRaX-Rust kernel with every scalar type, at -O0: gdb prints each as a number of its
/// type (unsigned integers were described as `DW_ATE_unsigned_char`, so gdb printed
/// `123456 '\u{01e240}'` and a `u64` of 2^40 + 5 as `5 '\005...'`), and `break FUNC`
/// stops on the first body line with every argument already in its slot (it stopped
/// on the signature line, before the parameters were stored, and showed garbage).
#[test]
fn rust_kernel_base_types_and_break_on_function() {
    let kernel =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../compiler/tests/kernels/basetypes.rs");
    let src = std::fs::read_to_string(&kernel).unwrap();
    let linked_elf = build_rust(&kernel, 0);
    let elf = scratch("gdbtypes").join("basetypes.elf");
    std::fs::write(&elf, &linked_elf).unwrap();
    let call = line_of(&src, "// CALL");
    let body = line_of(&src, "// BODY");
    let cmds: Vec<String> = vec![
        format!("break basetypes.rs:{call}"),
        "break take".into(),
        "continue".into(),
        "info locals".into(),
        "continue".into(),
        "info args".into(),
        "print/x d".into(),
        "delete".into(),
        "continue".into(),
    ];
    let (out, outcome) = session(&elf, 1, &cmds);
    let lines: Vec<&str> = out.lines().map(str::trim).collect();
    for want in [
        "v8 = 200",
        "v16 = 60000",
        "v32 = 123456",
        "v64 = 1099511627781",
        "vus = 77",
        "i8v = -100",
        "i16v = -30000",
        "i32v = -123456",
        "i64v = -2199023255552",
        "isz = -77",
        "f = 1.5",
        "d = 2.25",
        "t = true",
        "ch = 90 'Z'",
        "a = 200",
        "b = 60000",
        "c = 123456",
        "d = 1099511627781",
        "e = 77",
        "f = -100",
        "g = -30000",
        "h = -123456",
        "i = -2199023255552",
        "j = -77",
        "k = 1.5",
        "l = 2.25",
        "m = true",
        "n = 90 'Z'",
        "$1 = 0x10000000005",
    ] {
        assert!(lines.contains(&want), "no line `{want}`:\n{out}");
    }
    assert!(
        out.contains(&format!("basetypes.rs:{body}")),
        "`break take` stops at the first body line {body}:\n{out}"
    );
    assert!(
        matches!(outcome, Some(Outcome::Finished)),
        "{outcome:?}\n{out}"
    );
}
