//! Whole programs (C via clang-14) on the functional machine: output, threads,
//! global registers, barriers and the TRaX extension.

mod common;
use common::*;
use trax_emulator::Outcome;

#[test]
fn hello_integer_float_and_recursion() {
    let src = r#"
#include "trax.h"
int data[10] = {1,2,3,4,5,6,7,8,9,10};
float fdata[4] = {1.5f, 2.25f, -3.0f, 0.1f};
int fib(int n) { return n < 2 ? n : fib(n-1) + fib(n-2); }
void trax_main(void) {
  int s = 0;
  for (int i = 0; i < 10; i++) s += data[i] * i;
  trax_printi(s); trax_printc('\n');
  trax_printi(fib(15)); trax_printc('\n');
  float f = 0; for (int i = 0; i < 4; i++) f += fdata[i] * fdata[i];
  trax_printf(f); trax_printc('\n');
  trax_printf(1.0f / 3.0f); trax_printc(' '); trax_printf(1e20f); trax_printc(' '); trax_printf(-0.0f);
  trax_printc('\n');
  trax_printd(0.1); trax_printc('\n');
  const char *msg = "héllo\n"; int n = 0; while (msg[n]) n++;
  trax_prints((unsigned)msg, n);
  trax_printb(3); trax_printc('\n');
}
"#;
    let elf = build_c("hello", src, "-O2");
    let (r, out) = run_elf(&elf, 1, 1);
    assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
    let f: f32 = [1.5f32, 2.25, -3.0, 0.1].iter().fold(0.0, |a, x| a + x * x);
    let expect = format!(
        "330\n610\n{f}\n{} {} {}\n0.1\nhéllo\ntrue\n",
        1.0f32 / 3.0,
        1e20f32,
        -0.0f32
    );
    assert_eq!(out, expect);
}

#[test]
fn threads_atomics_and_barriers() {
    let src = r#"
#include "trax.h"
unsigned slots[64];
void trax_main(void) {
  unsigned gid = trax_gid();
  unsigned n = trax_nthreads();
  if (gid != trax_tmid() * 4 + trax_tid()) trax_abort(0, 0, 0);
  slots[gid] = gid * 2 + 1;
  trax_atominc(3);
  for (int i = 0; i < 100 * (gid + 1); i++) __asm__ volatile("nop");
  trax_barrier(5);
  if (gid == 0) {
    unsigned s = 0;
    for (unsigned i = 0; i < n; i++) s += slots[i];
    trax_printu(s); trax_printc(' ');
    trax_printu(trax_gread(3)); trax_printc(' ');
    trax_printu(trax_ntms()); trax_printc('\n');
  }
  trax_barrier(5);
  /* A second use of the same barrier works (it resets). */
  unsigned old = trax_atomadd(7, 10);
  trax_barrier(5);
  if (gid == n - 1) { trax_printu(trax_gread(7)); trax_printc('\n'); }
  (void)old;
}
"#;
    let elf = build_c("threads", src, "-O2");
    let (r, out) = run_elf(&elf, 3, 4);
    assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
    // sum of 2g+1 for g in 0..12 = 144; 12 increments; 3 TMs; 12 * 10.
    assert_eq!(out, "144 12 3\n120\n");
}

#[test]
fn threads_halting_early_release_barriers() {
    let src = r#"
#include "trax.h"
void trax_main(void) {
  if (trax_gid() % 2 == 1) return;   /* odd threads halt without reaching the barrier */
  trax_barrier(1);
  trax_atominc(2);
  trax_barrier(1);
  if (trax_gid() == 0) { trax_printu(trax_gread(2)); trax_printc('\n'); }
}
"#;
    let elf = build_c("halting", src, "-O2");
    let (r, out) = run_elf(&elf, 2, 3);
    assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
    assert_eq!(out, "3\n");
}

#[test]
fn semaphore_deadlock_is_reported() {
    let src = r#"
#include "trax.h"
void trax_main(void) {
  trax_semacq(9);   /* nobody ever releases */
}
"#;
    let elf = build_c("deadlock", src, "-O2");
    let (r, _) = run_elf(&elf, 1, 2);
    assert!(
        matches!(r.outcome, Outcome::Deadlock { waiting: 2 }),
        "{:?}",
        r.outcome
    );
    assert!(r.failure.unwrap().contains("deadlock"));
}

#[test]
fn semaphores_hand_over() {
    let src = r#"
#include "trax.h"
void trax_main(void) {
  unsigned gid = trax_gid();
  if (gid == 0) {
    for (int i = 0; i < 5000; i++) __asm__ volatile("nop");
    trax_printc('A');
    trax_semrel(4);
  } else {
    trax_semacq(4);
    trax_printc('B');
  }
}
"#;
    let elf = build_c("sem", src, "-O2");
    let (r, out) = run_elf(&elf, 1, 2);
    assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
    assert_eq!(out, "AB");
}

/// `trax.seed rs, rt` replaces the thread's stream with the one of pixel `rs`, sample `rt`:
/// every thread then draws the same numbers, `trax_runtime::rng::Rng::for_sample`'s.
#[test]
fn seed_gives_every_thread_the_sample_stream() {
    let src = r#"
#include "trax.h"
void trax_main(void) {
  unsigned id = trax_gid();
  float own = trax_rand();
  trax_seed(1000, 3);
  float a = trax_rand();
  float b = trax_rand();
  trax_seed(1001, 3);
  float c = trax_rand();
  while (trax_gread(1) != id) {}
  trax_printu(id); trax_printc(' ');
  trax_printf(own); trax_printc(' ');
  trax_printf(a); trax_printc(' ');
  trax_printf(b); trax_printc(' ');
  trax_printf(c); trax_printc('\n');
  trax_atominc(1);
}
"#;
    let elf = build_c("seed", src, "-O2");
    let (r, out) = run_elf(&elf, 1, 3);
    assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
    use trax_runtime::rng::Rng;
    let mut s = Rng::for_sample(0, 1000, 3);
    let (a, b) = (s.next_f32(), s.next_f32());
    let c = Rng::for_sample(0, 1001, 3).next_f32();
    let mut want = String::new();
    for id in 0..3 {
        let own = Rng::new(0, id).next_f32();
        want += &format!("{id} {own} {a} {b} {c}\n");
    }
    assert_eq!(out, want);
    // Not vacuous: the threads' own streams differ, the sample streams are distinct.
    assert_ne!(Rng::new(0, 0).next_f32(), Rng::new(0, 1).next_f32());
    assert_ne!(a, c);
}

#[test]
fn rand_clock_and_fops_match_the_runtime() {
    let src = r#"
#include "trax.h"
void trax_main(void) {
  trax_printf(trax_rand()); trax_printc(' ');
  trax_printf(trax_rand()); trax_printc(' ');
  trax_printf(trax_fmin(2.0f, -0.0f)); trax_printc(' ');
  trax_printf(trax_fmax(__builtin_nanf(""), 3.5f)); trax_printc(' ');
  trax_printf(trax_invsqrt(4.0f)); trax_printc(' ');
  unsigned c0 = trax_clock(); unsigned c1 = trax_clock();
  trax_printu(c1 - c0); trax_printc('\n');
  trax_stat(0); trax_stat(0); trax_stat(3);
}
"#;
    let elf = build_c("randfops", src, "-O2");
    let (r, out) = run_elf(&elf, 1, 1);
    assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
    let mut rng = trax_runtime::rng::Rng::new(0, 0);
    let (a, b) = (rng.next_f32(), rng.next_f32());
    // The clock counts retired instructions: the two reads are 1-3 instructions apart
    // depending on register allocation.
    let (head, delta) = out.trim_end().rsplit_once(' ').unwrap();
    assert_eq!(head, format!("{a} {b} -0 3.5 0.5"));
    let delta: u32 = delta.parse().unwrap();
    assert!((1..=3).contains(&delta), "{delta}");
    assert_eq!(r.counters[0], 2);
    assert_eq!(r.counters[3], 1);
}

/// ARCHITECTURE invariant: every thread sees its own stack at the same addresses; stack
/// data is never shared. 12 threads keep a local at one address, each with its own value
/// across a barrier (while the others write theirs there).
#[test]
fn every_thread_has_its_own_stack_at_the_same_addresses() {
    let src = r#"
#include "trax.h"
unsigned addrs[64];
void trax_main(void) {
  unsigned gid = trax_gid();
  volatile unsigned local = gid * 7 + 1;
  addrs[gid] = (unsigned)&local;
  trax_barrier(1);
  if (local != gid * 7 + 1) trax_abort(0, 0, 0);
  if (gid == 0) {
    unsigned same = 1;
    for (unsigned i = 1; i < trax_nthreads(); i++) same &= addrs[i] == addrs[0];
    trax_printu(same); trax_printc(' ');
    trax_printu(addrs[0] >= 0x7f000000u); trax_printc('\n');
  }
}
"#;
    let elf = build_c("ownstack", src, "-O2");
    let (r, out) = run_elf(&elf, 3, 4);
    assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
    assert_eq!(
        out, "1 1\n",
        "same address on every thread, in the stack window"
    );
}
