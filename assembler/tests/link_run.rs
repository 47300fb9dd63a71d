//! Runs a linked program under qemu-user (MIPS32r6): the start-up code must set up, run the
//! constructors in priority order and enter `trax_main`, with every relocation applied.
//! The program ends with a Linux `exit` system call before reaching `trax.halt`. qemu does
//! not map the TRaX stack window below `STACK_TOP`, so the first constructor (a leaf, on a
//! scratch stack) maps it with `mmap2` before anything else uses `$sp`.

mod link_common;

use std::os::unix::fs::PermissionsExt;
use std::process::Command;

use link_common::*;
use trax_assembler::link::{link, LinkOptions};

const MAIN: &str = r#"
extern int finish(int code);
extern const int weights[4];
extern const char *const label;
static int a, b;
int order;
__attribute__((used, aligned(8))) static char scratch_stack[64];
/* mmap2(0x7fff0000, 0x10000, RW, MAP_PRIVATE|MAP_FIXED|MAP_ANONYMOUS, -1, 0): o32 passes
   arguments 5 and 6 on the stack, so switch to a scratch stack around the call. */
__attribute__((constructor(101))) static void map_stack(void) {
  asm volatile(".set push\n.set noreorder\n"
               "move $t0, $sp\n"
               "la $sp, scratch_stack + 32\n"
               "li $a0, 0x7fff0000\n"
               "li $a1, 0x10000\n"
               "li $a2, 3\n"
               "li $a3, 0x812\n"
               "li $t1, -1\n"
               "sw $t1, 16($sp)\n"
               "sw $zero, 20($sp)\n"
               "li $v0, 4210\n"
               "syscall\n"
               "move $sp, $t0\n"
               ".set pop\n"
               ::: "$2", "$4", "$5", "$6", "$7", "$8", "$9", "memory");
}
__attribute__((constructor(200))) static void second(void) { b = 5; order = order * 10 + 2; }
__attribute__((constructor(102))) static void first(void) { a = 30; order = order * 10 + 1; }
__attribute__((constructor)) static void last(void) { order = order * 10 + 3; }
int trax_main(void) {
  int s = a + b + weights[order % 4] + label[1];
  switch (order - 120) {
  case 0: s += 11; break;
  case 1: s += 13; break;
  case 2: s += 17; break;
  case 3: s += 7; break;
  case 4: s += 19; break;
  case 5: s += 23; break;
  default: s = 1; break;
  }
  return finish(s & 0xff);
}
"#;

const LIB: &str = r#"
const int weights[4] = {1, 2, 3, 4};
const char *const label = "xy";
int finish(int code) {
  register int a0 asm("$4") = code;
  register int v0 asm("$2") = 4001; /* exit */
  asm volatile("syscall" : "+r"(v0) : "r"(a0) : "memory");
  for (;;) {
  }
}
"#;

/// Compiles and links the test program into `dir/run.elf` (executable).
fn build(dir: &std::path::Path) -> std::path::PathBuf {
    let mut flags = CLANG_FLAGS.to_vec();
    flags.push("-fomit-frame-pointer");
    let main = clang_text(dir, "main", MAIN, &flags);
    let lib = clang_text(dir, "lib", LIB, &flags);
    let linked = link(&inputs(&[main, lib]), &LinkOptions::default()).unwrap();
    let exe = dir.join("run.elf");
    std::fs::write(&exe, &linked.elf).unwrap();
    std::fs::set_permissions(&exe, std::fs::Permissions::from_mode(0o755)).unwrap();
    exe
}

#[test]
fn startup_runs_constructors_then_trax_main_under_qemu() {
    let dir = scratch("run");
    let exe = build(&dir);
    let status = Command::new("qemu-mipsel")
        .args(["-cpu", "mips32r6-generic"])
        .arg(&exe)
        .status()
        .expect("qemu-mipsel is required (qemu-user, see .ci/run)");
    // order = 123 (constructors 102, 200, then default priority); weights[3] = 4;
    // label[1] = 'y' (121); switch case 3 adds 7: 30 + 5 + 4 + 121 + 7 = 167.
    assert_eq!(status.code(), Some(167), "{status:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// gdb-multiarch debugs the linked program through qemu's gdbstub: a breakpoint by function
/// resolves to a source line, and the backtrace ends at `__trax_start` (its CFI marks the
/// return address undefined).
#[test]
fn gdb_backtrace_ends_at_trax_start() {
    let dir = scratch("rungdb");
    let exe = build(&dir);
    let port = 20000 + (std::process::id() % 20000) as u16;
    let mut qemu = Command::new("qemu-mipsel")
        .args(["-cpu", "mips32r6-generic", "-g", &port.to_string()])
        .arg(&exe)
        .spawn()
        .expect("qemu-mipsel is required (qemu-user, see .ci/run)");
    std::thread::sleep(std::time::Duration::from_millis(300));
    let out = Command::new("timeout")
        .args(["60", "gdb-multiarch", "-nx", "-batch"])
        .args(["-ex", &format!("target remote :{port}")])
        .args([
            "-ex",
            "break finish",
            "-ex",
            "continue",
            "-ex",
            "bt",
            "-ex",
            "kill",
        ])
        .arg(&exe)
        .output()
        .expect("gdb-multiarch is required (see .ci/run)");
    let _ = qemu.kill();
    let _ = qemu.wait();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("Breakpoint 1, finish (code=167)"),
        "gdb output:\n{text}"
    );
    assert!(text.contains("lib.c:7"), "gdb output:\n{text}");
    let frames: Vec<&str> = text.lines().filter(|l| l.starts_with('#')).collect();
    assert_eq!(frames.len(), 3, "gdb output:\n{text}");
    assert!(
        frames[1].contains("in trax_main ()") && frames[1].contains("main.c:"),
        "{text}"
    );
    assert!(frames[2].contains("in __trax_start ()"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}
