//! STRaTA (thesis §3.2): the ray stream memory (capacity, LIFO buffers, banks, latency)
//! and the phase-specific pipelines (`trax.setpipe`, unit reservation, II and latency),
//! against analytic figures, in both modes.

mod common;

use std::path::Path;

use trax_emulator::timing::{pipe_op_energy_nj, ChipConfig, TimingStats};
use trax_emulator::{run, Limits, Mode, Outcome, RunReport, RunRequest};
use trax_runtime::isa::{instr, TraxOp};

/// Runs `elf` on `chip` in `mode`: the report, the timing statistics and the output.
fn go(elf: &Path, chip: &ChipConfig, mode: Mode) -> (RunReport, Option<TimingStats>, String) {
    go_on(elf, chip, mode, 1)
}

fn go_on(
    elf: &Path,
    chip: &ChipConfig,
    mode: Mode,
    host_threads: usize,
) -> (RunReport, Option<TimingStats>, String) {
    let data = std::fs::read(elf).unwrap();
    let path = elf.display().to_string();
    let mut out = Vec::new();
    let mut req = RunRequest::new(&path, &data, chip, mode);
    req.host_threads = Some(host_threads);
    if mode == Mode::Timing {
        req.limits = Limits {
            max_cycles: Some(10_000_000),
            ..Limits::default()
        };
    }
    let mut r = run(req, &mut out).unwrap();
    let t = r.timing.take();
    (r, t, String::from_utf8(out).unwrap())
}

fn finished(elf: &Path, chip: &ChipConfig, mode: Mode) -> (Option<TimingStats>, String) {
    let (r, t, out) = go(elf, chip, mode);
    assert!(
        matches!(r.outcome, Outcome::Finished),
        "{:?}: {:?}\n{out}",
        r.outcome,
        r.failure
    );
    (t, out)
}

fn numbers(out: &str) -> Vec<u64> {
    out.split_whitespace().map(|w| w.parse().unwrap()).collect()
}

/// The tiny chip with `threads` threads and a stream memory of `buffers` buffers holding
/// exactly `rays` rays of 48 bytes in `banks` banks.
fn stream_chip(threads: u32, buffers: u32, rays: u32, banks: u32) -> ChipConfig {
    let mut c = common::chip(1, threads);
    let sm = &mut c.stream_memory;
    sm.buffers = buffers;
    sm.capacity_bytes = 4 * (buffers + 1) + rays * (48 + 4);
    sm.banks = banks;
    c.validate().unwrap();
    c
}

const FILL: &str = r#"
#include "trax.h"
void trax_main(void) {
    unsigned n = trax_strcap();
    trax_printu(n);
    trax_printc(' ');
    for (unsigned i = 0; i < n + EXTRA; i++) {
        trax_strwstart(i % 3);
        trax_strw(i);
        trax_strwend(); // the write that overflows
    }
    trax_printu(trax_strsize(0) + trax_strsize(1) + trax_strsize(2));
}
"#;

#[test]
fn capacity_is_exact_and_overflow_is_a_fault_naming_the_line() {
    // 4 buffers + the free list: 20 bytes of head pointers, then 52 bytes per ray.
    let chip = stream_chip(1, 4, 10, 4);
    let fits = common::build_c("s_fill0", &FILL.replace("EXTRA", "0"), "-O1");
    for mode in [Mode::Functional, Mode::Timing] {
        let (_, out) = finished(&fits, &chip, mode);
        assert_eq!(numbers(&out), [10, 10], "{mode:?}");
    }
    // One byte less: nine rays.
    let mut small = chip.clone();
    small.stream_memory.capacity_bytes -= 1;
    assert_eq!(
        numbers(&finished(&fits, &small, Mode::Functional).1),
        [9, 9]
    );
    let over = common::build_c("s_fill1", &FILL.replace("EXTRA", "1"), "-O1");
    for mode in [Mode::Functional, Mode::Timing] {
        let (r, _, out) = go(&over, &chip, mode);
        assert!(matches!(r.outcome, Outcome::Crashed(_)), "{mode:?}: {out}");
        let report = r.failure.unwrap_or_default();
        assert!(
            report.contains("ray stream memory full: writing a ray to stream 1, but all 10 slots of 48-byte rays are taken"),
            "{report}"
        );
        assert!(report.contains("s_fill1.c:10"), "{report}");
        assert!(report.contains("thread 0"), "{report}");
    }
    // A chip without a stream memory says so.
    let (r, _, _) = go(&over, &common::chip(1, 1), Mode::Functional);
    let report = r.failure.unwrap_or_default();
    assert!(
        report.contains("this chip has no ray stream memory"),
        "{report}"
    );
}

const LIFO: &str = r#"
#include "trax.h"
void trax_main(void) {
    for (unsigned i = 1; i <= 5; i++) {
        trax_strwstart(2);
        trax_strw(i);
        trax_strw(100 * i);
        trax_strwend();
    }
    trax_strwstart(0);
    trax_strw(77);
    trax_strwend();
    unsigned s;
    while ((s = trax_strsched()) != 0xFFFFFFFFu) {
        trax_printu(s);
        trax_printc(':');
        while (trax_strrstart()) {
            unsigned a = trax_strr(), b = trax_strr(), c = trax_strr();
            trax_strrend();
            trax_printu(a);
            trax_printc('/');
            trax_printu(b);
            trax_printc('/');
            trax_printu(c);
            trax_printc(' ');
        }
    }
}
"#;

#[test]
fn buffers_are_lifo_and_both_modes_agree() {
    let elf = common::build_c("s_lifo", LIFO, "-O1");
    let chip = stream_chip(1, 4, 100, 4);
    let (_, f) = finished(&elf, &chip, Mode::Functional);
    let (t, tm) = finished(&elf, &chip, Mode::Timing);
    // The fullest stream first; newest ray first; records zero-padded.
    assert_eq!(f, "2:5/500/0 4/400/0 3/300/0 2/200/0 1/100/0 0:77/0/0 ");
    assert_eq!(f, tm);
    let s = t.unwrap().stream;
    assert_eq!((s.writes, s.reads, s.max_rays_in_flight), (6, 6, 6));
    assert_eq!(s.capacity_rays, 100);
    assert!(s.mean_rays_in_flight > 0.0 && s.mean_rays_in_flight < 6.0);
}

/// Every thread writes one ray; all threads run in lockstep (a stream unit and fetch
/// slots for each), so the writes reach the stream memory in the same cycle.
const WRITE_ONE: &str = r#"
#include "trax.h"
void trax_main(void) {
    trax_strwstart(0);
    trax_strw(trax_tid());
    trax_strwend();
}
"#;

#[test]
fn simultaneous_writes_conflict_in_shared_banks() {
    let elf = common::build_c("s_banks", WRITE_ONE, "-O1");
    for (banks, busy) in [(8u32, 1u32), (4, 1), (2, 1), (1, 1), (1, 3)] {
        let mut chip = stream_chip(8, 4, 64, banks);
        chip.units.get_mut("stream").unwrap().count = 8;
        chip.icache.fetches_per_bank = 8;
        chip.stream_memory.bank_busy_cycles = busy;
        let (t, _) = finished(&elf, &chip, Mode::Timing);
        let s = t.unwrap().stream;
        // Slots 0..7 in banks slot % banks: m = 8 / banks writes per bank, each waiting
        // `busy` cycles for each one before it.
        let m = u64::from(8 / banks);
        let b = u64::from(banks);
        assert_eq!(s.writes, 8);
        assert_eq!(s.bank_conflicts, b * (m - 1), "{banks} banks");
        assert_eq!(
            s.bank_conflict_cycles,
            b * u64::from(busy) * m * (m - 1) / 2,
            "{banks} banks, busy {busy}"
        );
    }
}

const READ_LATENCY: &str = r#"
#include "trax.h"
void trax_main(void) {
    trax_strwstart(1);
    trax_strw(5);
    trax_strwend();
    trax_strsched();
    unsigned t0 = trax_clock();
    unsigned got = trax_strrstart();
    __asm__ volatile("addu %0, %0, $0" : "+r"(got));
    unsigned t1 = trax_clock();
    trax_printu(t1 - t0);
    trax_printc(' ');
    trax_printu(got);
}
"#;

#[test]
fn a_read_is_ready_after_the_configured_latency() {
    let elf = common::build_c("s_latency", READ_LATENCY, "-O1");
    let mut dts = Vec::new();
    for lat in [40u32, 70] {
        let mut chip = stream_chip(1, 4, 8, 4);
        chip.stream_memory.latency = lat;
        let (_, out) = finished(&elf, &chip, Mode::Timing);
        let v = numbers(&out);
        assert_eq!(v[1], 1);
        // The read, then its consumer `latency` cycles later, then the clock (at most two
        // compiler-scheduled instructions between the clock reads).
        let base = u64::from(lat) + 1;
        assert!((base..=base + 2).contains(&v[0]), "latency {lat}: {out}");
        dts.push(v[0]);
    }
    assert_eq!(dts[1] - dts[0], 30);
}

/// TM 1 schedules with every buffer empty and idles; TM 0 writes a ray after 50
/// dependent adds and halts; TM 1 wakes with that buffer, reads the ray, and its next
/// schedule ends the frame (every live thread waits, the memory is empty).
const IDLE_WAKE: &str = r#"
#include "trax.h"
void trax_main(void) {
    if (trax_tmid() == 0) {
        float a = 1.0f, b = 0.5f;
        __asm__ volatile(".rept 50\n add.s %0, %0, %1\n .endr\n mov.s %0, %0" : "+f"(a) : "f"(b));
        trax_strwstart(3);
        trax_strw(7);
        unsigned t = trax_clock();
        trax_strwend();
        trax_printu(t);
        trax_printc(' ');
        return;
    }
    unsigned t = trax_clock();
    unsigned s = trax_strsched();
    unsigned got = trax_strrstart(), w = trax_strr();
    trax_strrend();
    unsigned s2 = trax_strsched();
    trax_printu(t);
    trax_printc(' ');
    trax_printu(s);
    trax_printc(' ');
    trax_printu(got * w);
    trax_printc(' ');
    trax_printu(s2);
}
"#;

#[test]
fn an_idle_tm_wakes_when_another_tm_writes_a_ray() {
    let elf = common::build_c("s_idle", IDLE_WAKE, "-O1");
    let mut chip = stream_chip(1, 4, 8, 4);
    chip.tms = 2;
    chip.tms_per_l2 = 2;
    let (_, f) = finished(&elf, &chip, Mode::Functional);
    let (t, out) = finished(&elf, &chip, Mode::Timing);
    let v = numbers(&out);
    assert_eq!(&v[2..], [3, 7, u64::from(u32::MAX)], "{out}");
    assert_eq!(&numbers(&f)[2..], &v[2..], "functional: {f}");
    // TM 1's strsched issues in the cycle its clock read (v[1]), TM 0's strwend in the
    // cycle of its own (v[0]): TM 1 idles from the one to the other.
    let t = t.unwrap();
    let idle = v[0] - v[1];
    assert!(idle > 50, "{out}");
    assert_eq!(t.stream.idle_tm_cycles, idle, "{out}");
    // Its thread waits from the end of its strsched's quantum (until then: global_sync)
    // to the end of the push's quantum, so by less than a quantum either way.
    let q = u64::from(chip.memory.l1.hit_latency + chip.memory.l2.hit_latency);
    let st = t.thread_cycles.stream_idle;
    assert!(st + q > idle && st < idle + q, "{st} vs {idle}");
    // One schedule that gave a buffer (the wake), then the end of the frame.
    assert_eq!((t.stream.schedules, t.stream.switches), (1, 1));
}

/// `report(v)`: thread 0 prints every thread's `v` in thread order, after all arrive
/// (prints of different threads would interleave).
const REPORT: &str = r#"
static unsigned values[64];
static void report(unsigned v) {
    values[trax_tid()] = v;
    trax_barrier(1);
    if (trax_tid() == 0)
        for (unsigned i = 0; i < trax_nthreads(); i++) {
            trax_printu(values[i]);
            trax_printc(' ');
        }
}
"#;

/// A `trax.boxtest`/`trax.tritest` word writing `$f<fd>`.
fn pipe_word(op: TraxOp, fd: u32) -> String {
    format!(".word {:#x}\\n", instr(op).encode(&[fd]))
}

/// One thread: `k` independent pipeline tests back to back, then a consumer of the last;
/// prints the cycles from the first test's issue to the cycle after the consumer's.
fn pipe_kernel(op: TraxOp, mode: u32, k: u32) -> String {
    let clock = |rd: u32| format!(".word {:#x}\\n", instr(TraxOp::Clock).encode(&[rd]));
    let tests: String = (1..=k).map(|f| pipe_word(op, f)).collect();
    format!(
        r#"
#include "trax.h"
{REPORT}
void trax_main(void) {{
    trax_setpipe({mode});
    unsigned t0, t1;
    __asm__ volatile(".rept 4\n nop\n .endr\n" "{c0}" "{tests}" "mov.s $f20, $f{k}\n" "{c1}"
        "move %0, $8\n move %1, $9\n"
        : "=r"(t0), "=r"(t1) : : "$8", "$9", "$f1", "$f2", "$f3", "$f4", "$f5", "$f6", "$f7",
          "$f8", "$f9", "$f10", "$f11", "$f12", "$f13", "$f14", "$f15", "$f16", "$f20");
    report(t1 - t0);
}}
"#,
        c0 = clock(8),
        c1 = clock(9),
    )
    .replace("{REPORT}", REPORT)
}

fn pipe_chip(threads: u32) -> ChipConfig {
    // A baseline TM (8 FP multipliers, 8 adders) with `threads` threads in lockstep.
    let mut c = common::chip(1, threads);
    c.units.get_mut("fp_mul").unwrap().count = 8;
    c.units.get_mut("fp_add").unwrap().count = 8;
    c.icache.fetches_per_bank = threads.max(2);
    c
}

#[test]
fn box_tests_pipeline_with_ii_1_and_latency_8() {
    let chip = pipe_chip(1);
    for k in [1u32, 8, 16] {
        let elf = common::build_c(
            &format!("p_box{k}"),
            &pipe_kernel(TraxOp::BoxTest, 1, k),
            "-O1",
        );
        let (t, out) = finished(&elf, &chip, Mode::Timing);
        // K tests take K + 7 cycles from the first issue to the last result; the consumer
        // issues then, the clock reads the cycle after.
        assert_eq!(numbers(&out), [u64::from(k) + 7 + 1], "{k} box tests");
        let t = t.unwrap();
        assert_eq!(t.pipelines.box_ops, u64::from(k));
        let e = pipe_op_energy_nj(&chip, &chip.pipelines.box_pipe);
        let (em, ea) = (
            chip.units["fp_mul"].energy_nj,
            chip.units["fp_add"].energy_nj,
        );
        assert!(
            (e - 6.0 * (em + ea)).abs() < 1e-15,
            "6 mul + 6 add per box test"
        );
        assert!((t.energy.pipelines - f64::from(k) * e * 1e-9).abs() < 1e-18);
        // 6 + 6 units reserved from the mode change to the end of the run.
        let r = t.pipelines.reserved_unit_cycles;
        assert!(
            r % 12 == 0 && r > 12 * u64::from(k + 7) && r <= 12 * t.cycles,
            "{r}"
        );
    }
}

#[test]
fn triangle_tests_issue_18_apart_two_per_initiation() {
    for (threads, k) in [(1u32, 1u32), (1, 4), (2, 4), (3, 2)] {
        let chip = pipe_chip(threads);
        let elf = common::build_c(
            &format!("p_tri{threads}_{k}"),
            &pipe_kernel(TraxOp::TriTest, 2, k),
            "-O1",
        );
        let (t, out) = finished(&elf, &chip, Mode::Timing);
        let dts = numbers(&out);
        // A thread issues every 18 cycles (II 18), the last result 31 cycles after its
        // issue. Two threads share each initiation (width 2); a third waits for the next.
        let expect = 18 * u64::from(k - 1) + 31 + 1;
        if threads <= 2 {
            assert_eq!(
                dts,
                vec![expect; threads as usize],
                "{threads} threads, {k} tests"
            );
        } else {
            let slowest = *dts.iter().max().unwrap();
            assert!(
                slowest >= expect + 18,
                "{threads} threads, {k} tests: {dts:?}"
            );
        }
        let t = t.unwrap();
        assert_eq!(t.pipelines.tri_ops, u64::from(threads * k));
        let e = pipe_op_energy_nj(&chip, &chip.pipelines.tri);
        let (em, ea) = (
            chip.units["fp_mul"].energy_nj,
            chip.units["fp_add"].energy_nj,
        );
        assert!((e - (4.0 * em + 2.0 * ea) * 9.0).abs() < 1e-15);
        assert!((t.energy.pipelines - f64::from(threads * k) * e * 1e-9).abs() < 1e-18);
    }
}

const FP_WORK: &str = r#"
#include "trax.h"
REPORT
void trax_main(void) {
    trax_setpipe(MODE);
    float a, b, c, d, x = 1.0f;
    // Wait for x (loaded from memory) before starting the clock.
    __asm__ volatile("mov.s %0, %0\n .rept 4\n nop\n .endr" : "+f"(x));
    unsigned t0 = trax_clock();
    __asm__ volatile(".rept 50\n mul.s %0, %4, %4\n mul.s %1, %4, %4\n mul.s %2, %4, %4\n mul.s %3, %4, %4\n .endr"
        : "=&f"(a), "=&f"(b), "=&f"(c), "=&f"(d) : "f"(x));
    unsigned t1 = trax_clock();
    if (a + b + c + d != 4.0f) trax_printc('X');
    report(t1 - t0);
}
"#;

#[test]
fn reserved_units_slow_ordinary_fp_work() {
    // 8 threads, 8 FP multipliers: 200 independent multiplies each. General mode: a
    // multiplier per thread; box mode leaves 2 (4 threads each), triangle mode 4 (2 each).
    let chip = pipe_chip(8);
    let mut dt = Vec::new();
    for mode in 0..3 {
        let elf = common::build_c(
            &format!("p_fp{mode}"),
            &FP_WORK
                .replace("MODE", &mode.to_string())
                .replace("REPORT", REPORT),
            "-O1",
        );
        let (t, out) = finished(&elf, &chip, Mode::Timing);
        assert!(!out.contains('X'));
        // The slowest thread: round-robin arbitration is not fair among the threads
        // sharing a unit, but the group's multiplies take (threads per unit) x 200 cycles.
        dt.push(*numbers(&out).iter().max().unwrap() as f64);
        let t = t.unwrap();
        if mode == 0 {
            assert_eq!(t.pipelines.reserved_unit_cycles, 0);
        }
    }
    let (g, b, tr) = (dt[0], dt[1], dt[2]);
    // The slowest thread also waits up to a few dozen cycles for its start (threads
    // reach the clock at slightly different cycles).
    assert!((200.0..=225.0).contains(&g), "{dt:?}");
    assert!((800.0..=825.0).contains(&b), "box mode: {dt:?}");
    assert!((400.0..=425.0).contains(&tr), "triangle mode: {dt:?}");
}

const WRONG_MODE: &str = r#"
#include "trax.h"
void trax_main(void) {
    trax_setpipe(2);
    float r = trax_boxtest();
    trax_printf(r);
}
"#;

#[test]
fn a_pipeline_test_in_the_wrong_mode_is_a_fault_naming_the_line() {
    let elf = common::build_c("p_wrong", WRONG_MODE, "-O1");
    let chip = pipe_chip(1);
    for mode in [Mode::Functional, Mode::Timing] {
        let (r, _, _) = go(&elf, &chip, mode);
        let report = r.failure.unwrap_or_default();
        assert!(
            report.contains("trax.boxtest while this TM's units are in triangle-pipeline mode (needs trax.setpipe 1, box-pipeline mode)"),
            "{mode:?}: {report}"
        );
        assert!(report.contains("p_wrong.c:5"), "{report}");
    }
    // The tiny chip's single FP multiplier cannot host a pipeline.
    let (r, _, _) = go(&elf, &common::chip(1, 1), Mode::Functional);
    let report = r.failure.unwrap_or_default();
    assert!(
        report.contains(
            "pipeline mode (pipelines disabled, or the TM lacks the FP units it reserves) index 2"
        ),
        "{report}"
    );
}

const MANY: &str = r#"
#include "trax.h"
void trax_main(void) {
    unsigned g = trax_gid();
    for (unsigned i = 0; i < 3; i++) {
        trax_strwstart((g + i) % 5);
        trax_strw(g * 10 + i);
        trax_strwend();
    }
    unsigned sum = 0, n = 0;
    for (unsigned k = 0; k < 4; k++) {
        if (trax_strsched() == 0xFFFFFFFFu) break;
        while (n < 3 && trax_strrstart()) {
            sum += trax_strr();
            trax_strrend();
            n++;
        }
    }
    trax_atomadd(2, sum);
}
"#;

#[test]
fn streams_are_deterministic_over_host_threads() {
    let elf = common::build_c("s_many", MANY, "-O1");
    let mut chip = stream_chip(4, 8, 200, 2);
    chip.tms = 3;
    chip.tms_per_l2 = 3;
    let (r1, t1, o1) = go_on(&elf, &chip, Mode::Timing, 1);
    let (r2, t2, o2) = go_on(&elf, &chip, Mode::Timing, 2);
    assert!(matches!(r1.outcome, Outcome::Finished), "{:?}", r1.failure);
    assert!(matches!(r2.outcome, Outcome::Finished), "{:?}", r2.failure);
    let (t1, t2) = (t1.unwrap(), t2.unwrap());
    assert_eq!(o1, o2);
    assert_eq!(t1.cycles, t2.cycles);
    assert_eq!(t1.stream, t2.stream);
    assert_eq!(t1.stream.writes, 36);
    assert!(t1.stream.bank_conflicts > 0, "{:?}", t1.stream);
}

/// Statistics over time on a chip with a stream memory: the intervals' mean rays in flight
/// integrate to the run's, and the intervals do not depend on the host threads.
#[test]
fn stream_intervals_integrate_rays_in_flight() {
    let elf = common::build_c("s_many", MANY, "-O1");
    let mut chip = stream_chip(4, 8, 200, 2);
    chip.tms = 3;
    chip.tms_per_l2 = 3;
    let q = u64::from(chip.memory.l1.hit_latency + chip.memory.l2.hit_latency);
    let n = 25 * q;
    let data = std::fs::read(&elf).unwrap();
    let path = elf.display().to_string();
    let go = |threads: usize| {
        let mut req = RunRequest::new(&path, &data, &chip, Mode::Timing);
        req.host_threads = Some(threads);
        req.stats_interval = Some(n);
        let mut intervals = Vec::new();
        let mut keep = |iv: &trax_emulator::timing::Interval| intervals.push(iv.clone());
        req.interval_sink = Some(&mut keep);
        let r = run(req, &mut Vec::new()).unwrap();
        assert!(matches!(r.outcome, Outcome::Finished), "{:?}", r.failure);
        (r.timing.unwrap(), intervals)
    };
    let ((t1, i1), (_, i2)) = (go(1), go(2));
    assert_eq!(i1, i2);
    assert_eq!(i1.len() as u64, t1.cycles.div_ceil(n));
    let integral: f64 = i1
        .iter()
        .map(|i| i.mean_rays_in_flight.unwrap() * i.cycles as f64)
        .sum();
    let total = t1.stream.mean_rays_in_flight * t1.cycles as f64;
    assert!(total > 0.0);
    assert!(
        (integral - total).abs() < 1e-6 * total,
        "{integral} vs {total}"
    );
}

/// One thread: `trax.setpipe MODE` (a real change, or none for mode 0), then eight more
/// to the same mode between two clock reads.
fn setpipe_kernel(mode: u32) -> String {
    let word = |op: TraxOp, v: u32| format!(".word {:#x}\\n", instr(op).encode(&[v]));
    let eight = word(TraxOp::SetPipe, mode).repeat(8);
    format!(
        r#"
#include "trax.h"
void trax_main(void) {{
    trax_setpipe({mode});
    unsigned t0, t1;
    __asm__ volatile(".rept 4\n nop\n .endr\n" "{c0}" "{eight}" "{c1}"
        "move %0, $8\n move %1, $9\n" : "=r"(t0), "=r"(t1) : : "$8", "$9");
    trax_printu(t1 - t0);
}}
"#,
        c0 = word(TraxOp::Clock, 8),
        c1 = word(TraxOp::Clock, 9),
    )
}

#[test]
fn setpipe_to_the_current_mode_is_free() {
    let chip = pipe_chip(1);
    for mode in [0u32, 1, 2] {
        let elf = common::build_c(&format!("p_same{mode}"), &setpipe_kernel(mode), "-O1");
        let (t, out) = finished(&elf, &chip, Mode::Timing);
        // One cycle each (no chip-wide ordering, no reconfiguration): the second clock
        // reads 8 cycles after the first.
        assert_eq!(numbers(&out), [8], "mode {mode}");
        let t = t.unwrap();
        assert_eq!(t.instruction_mix["trax.setpipe"], 9, "mode {mode}");
        // The one real change (modes 1, 2) reserves the pipeline's units from then on.
        assert_eq!(
            t.pipelines.reserved_unit_cycles == 0,
            mode == 0,
            "mode {mode}"
        );
    }
}

// ---------------------------------------------------------------------------------------
// `trax.strsched`: the TM's stream scheduler.

/// Thread 0 writes three rays to buffer 2; thread 3 halts at once; threads 0..2 work for
/// 40 x tid dependent adds, then schedule. Thread 0 prints, per thread, the cycle before
/// its strsched and the cycle after it returned, and the buffer it got.
const RENDEZVOUS: &str = r#"
#include "trax.h"
static unsigned arrive[8], resume[8], got[8];
void trax_main(void) {
    unsigned tid = trax_tid();
    if (tid == 0)
        for (unsigned i = 0; i < 3; i++) {
            trax_strwstart(2);
            trax_strw(i);
            trax_strwend();
        }
    if (tid == 3) return;
    float a = 1.0f, b = 0.5f;
    for (unsigned i = 0; i < tid * 40; i++) __asm__ volatile("add.s %0, %0, %1" : "+f"(a) : "f"(b));
    unsigned t0 = trax_clock();
    unsigned s = trax_strsched();
    unsigned t1 = trax_clock();
    arrive[tid] = t0;
    resume[tid] = t1;
    got[tid] = s;
    trax_barrier(1);
    if (tid == 0)
        for (unsigned i = 0; i < 3; i++) {
            trax_printu(arrive[i]); trax_printc(' ');
            trax_printu(resume[i]); trax_printc(' ');
            trax_printu(got[i]); trax_printc(' ');
        }
}
"#;

#[test]
fn strsched_resumes_no_thread_before_every_live_peer_arrived() {
    let elf = common::build_c("s_rendezvous", RENDEZVOUS, "-O1");
    let chip = stream_chip(4, 4, 16, 4);
    let (_, f) = finished(&elf, &chip, Mode::Functional);
    let (t, out) = finished(&elf, &chip, Mode::Timing);
    let v = numbers(&out);
    let (arrive, resume, got): (Vec<u64>, Vec<u64>, Vec<u64>) = (
        v.iter().step_by(3).copied().collect(),
        v.iter().skip(1).step_by(3).copied().collect(),
        v.iter().skip(2).step_by(3).copied().collect(),
    );
    // Every thread got buffer 2, the fullest; the halted thread 3 was not waited for.
    assert_eq!(got, [2, 2, 2], "{out}");
    assert_eq!(
        numbers(&f).iter().skip(2).step_by(3).collect::<Vec<_>>(),
        [&2, &2, &2]
    );
    // The workers arrive over about 80 cycles; nobody resumes before the last one arrives.
    let last = *arrive.iter().max().unwrap();
    assert!(last - arrive.iter().min().unwrap() >= 80, "{out}");
    assert!(resume.iter().all(|&r| r > last), "{out}");
    let t = t.unwrap();
    // Threads 0 and 1 waited for thread 2 (draining), nobody idled.
    assert!(
        t.thread_cycles.stream_drain >= 2 * 40,
        "{:?}",
        t.thread_cycles
    );
    assert_eq!(
        (t.thread_cycles.stream_idle, t.stream.idle_tm_cycles),
        (0, 0)
    );
    assert_eq!((t.stream.schedules, t.stream.switches), (1, 1));
}

/// Each of the chip's threads writes 3 rays (value 10 * gid + k) to buffer (gid + k) % 5
/// and then drains: schedule, read every ray of the buffer, until the frame is done. A
/// ray's value tells the buffer it was written to; thread 0 prints the sum of the values
/// read, the rays read, the threads that got "done" and whether any ray was read from
/// another buffer than the one scheduled.
const DRAIN: &str = r#"
#include "trax.h"
void trax_main(void) {
    unsigned g = trax_gid();
    for (unsigned k = 0; k < 3; k++) {
        trax_strwstart((g + k) % 5);
        trax_strw(10 * g + k);
        for (unsigned i = 1; i < 11; i++) trax_strw(0);
        trax_strw(1);
        trax_strwend();
    }
    unsigned b;
    while ((b = trax_strsched()) != 0xFFFFFFFFu) {
        while (trax_strrstart()) {
            unsigned v = trax_strr();
            for (unsigned i = 1; i < 11; i++) trax_strr();
            unsigned one = trax_strr();
            trax_strrend();
            if ((v / 10 + v % 10) % 5 != b) trax_atominc(4);
            trax_atomadd(1, v);
            trax_atomadd(2, one);
        }
    }
    trax_atominc(3);
    trax_barrier(5);
    if (g == 0) {
        for (unsigned i = 1; i <= 4; i++) { trax_printu(trax_gread(i)); trax_printc(' '); }
        trax_printu(trax_strsize(0) + trax_strsize(4));
    }
}
"#;

#[test]
fn a_drain_loop_reads_every_ray_and_ends_for_every_thread_in_both_modes() {
    let elf = common::build_c("s_drain", DRAIN, "-O2");
    let mut chip = stream_chip(4, 5, 64, 4);
    chip.tms = 3;
    chip.tms_per_l2 = 3;
    let n = 12u64;
    // Sum of 10 g + k over g < 12, k < 3.
    let sum = 3 * 10 * n * (n - 1) / 2 + n * 3;
    let expect = [sum, 3 * n, n, 0, 0];
    let (_, f) = finished(&elf, &chip, Mode::Functional);
    assert_eq!(numbers(&f), expect, "functional");
    for policy in ["fullest", "sticky", "round-robin", "claimed"] {
        let mut c = chip.clone();
        c.set_field("stream_memory.schedule", toml::Value::String(policy.into()))
            .unwrap();
        let (_, t1, o1) = go_on(&elf, &c, Mode::Timing, 1);
        let (r2, t2, o2) = go_on(&elf, &c, Mode::Timing, 2);
        assert!(r2.finished(), "{policy}: {:?}", r2.failure);
        assert_eq!(numbers(&o1), expect, "{policy}");
        assert_eq!(o1, o2, "{policy}");
        let (t1, t2) = (t1.unwrap(), t2.unwrap());
        assert_eq!(t1.cycles, t2.cycles, "{policy}");
        assert_eq!(t1.stream, t2.stream, "{policy}");
        assert_eq!(t1.thread_cycles, t2.thread_cycles, "{policy}");
        // Every thread-cycle lands in exactly one bucket, the stream waits included.
        let tc = &t1.thread_cycles;
        let buckets = tc.issued
            + tc.data_dependence
            + tc.unit_conflict
            + tc.icache_conflict
            + tc.l1_bank_conflict
            + tc.l1_mshr_full
            + tc.sync_wait
            + tc.stream_drain
            + tc.stream_idle
            + tc.global_sync
            + tc.halted;
        assert_eq!(buckets, t1.cycles * 12, "{policy}: {tc:?}");
        assert!(tc.stream_drain > 0, "{policy}: {tc:?}");
        let s = &t1.stream;
        assert_eq!(s.reads, 3 * n);
        assert!(s.schedules >= 5 && s.switches <= s.schedules, "{s:?}");
        assert!((s.rays_per_visit - s.reads as f64 / s.schedules as f64).abs() < 1e-12);
    }
}

/// One thread: buffer 0 gets 1 ray, buffer 1 gets 3, buffer 2 gets 2; then it schedules,
/// reads one ray, and schedules again, printing each buffer it gets.
const ONE_PER_VISIT: &str = r#"
#include "trax.h"
void trax_main(void) {
    unsigned n[3] = {1, 3, 2};
    for (unsigned b = 0; b < 3; b++)
        for (unsigned i = 0; i < n[b]; i++) {
            trax_strwstart(b);
            trax_strwend();
        }
    unsigned b;
    while ((b = trax_strsched()) != 0xFFFFFFFFu) {
        trax_printu(b);
        trax_printc(' ');
        trax_strrstart();
        trax_strrend();
    }
}
"#;

#[test]
fn schedule_policies_choose_as_documented() {
    let elf = common::build_c("s_policy", ONE_PER_VISIT, "-O1");
    // Counts (1, 3, 2) before each visit, one ray read per visit.
    for (policy, order, switches) in [
        // The most rays, lowest id on ties: (1,3,2) (1,2,2) (1,1,2) (1,1,1) (0,1,1) (0,0,1).
        ("fullest", [1, 1, 2, 0, 1, 2], 5),
        // Buffer 1 until it is empty, then the fullest.
        ("sticky", [1, 1, 1, 2, 2, 0], 3),
        // The next non-empty buffer after the current one.
        ("round-robin", [0, 1, 2, 1, 2, 1], 6),
        // One TM: its claim ends as it drains, so it chooses as `fullest`.
        ("claimed", [1, 1, 2, 0, 1, 2], 5),
    ] {
        let mut chip = stream_chip(1, 4, 16, 4);
        chip.set_field("stream_memory.schedule", toml::Value::String(policy.into()))
            .unwrap();
        let (_, f) = finished(&elf, &chip, Mode::Functional);
        let (t, o) = finished(&elf, &chip, Mode::Timing);
        assert_eq!(numbers(&f), order, "{policy}");
        assert_eq!(o, f, "{policy}");
        let s = t.unwrap().stream;
        assert_eq!(
            (s.schedules, s.switches, s.rays_per_visit),
            (6, switches, 1.0),
            "{policy}"
        );
    }
    let mut chip = stream_chip(1, 4, 16, 4);
    let err = chip
        .set_field(
            "stream_memory.schedule",
            toml::Value::String("random".into()),
        )
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(
            "unknown schedule policy `random` (expected one of fullest, sticky, round-robin, claimed)"
        ),
        "{err}"
    );
}

/// One thread writes a ray and schedules, between two clock reads.
const SCHED_COST: &str = r#"
#include "trax.h"
void trax_main(void) {
    trax_strwstart(1);
    trax_strwend();
    unsigned t0 = trax_clock();
    unsigned s = trax_strsched();
    __asm__ volatile("addu %0, %0, $0" : "+r"(s));
    unsigned t1 = trax_clock();
    trax_printu(t1 - t0);
    trax_printc(' ');
    trax_printu(s);
}
"#;

#[test]
fn the_scheduling_decision_costs_schedule_cycles() {
    let elf = common::build_c("s_cost", SCHED_COST, "-O1");
    let mut dts = Vec::new();
    for cost in [0u32, 100, 250] {
        let mut chip = stream_chip(1, 4, 8, 4);
        chip.stream_memory.schedule_cycles = cost;
        let (t, out) = finished(&elf, &chip, Mode::Timing);
        let v = numbers(&out);
        assert_eq!(v[1], 1);
        let t = t.unwrap();
        // The wait after the quantum of the strsched is drain time (the decision).
        if cost > 0 {
            assert!(t.thread_cycles.stream_drain > 0, "{:?}", t.thread_cycles);
        }
        dts.push(v[0]);
    }
    // Past the quantum in which it issued, the thread resumes `cost` cycles after it.
    assert_eq!(dts[2] - dts[1], 150, "{dts:?}");
    let q = 4;
    assert!(dts[0] <= q + 2 && dts[1] >= 100, "{dts:?}");
}

/// TM 0's threads wait at a barrier while TM 1's wait in strsched with nothing to read.
const DEADLOCK: &str = r#"
#include "trax.h"
void trax_main(void) {
    if (trax_tmid() == 0)
        trax_barrier(4);
    else
        while (trax_strsched() != 0xFFFFFFFFu) {}
}
"#;

#[test]
fn a_barrier_against_strsched_deadlock_names_the_threads() {
    let elf = common::build_c("s_dead", DEADLOCK, "-O1");
    let mut chip = stream_chip(2, 4, 8, 4);
    chip.tms = 2;
    chip.tms_per_l2 = 2;
    for mode in [Mode::Functional, Mode::Timing] {
        let (r, _, _) = go(&elf, &chip, mode);
        assert!(
            matches!(r.outcome, Outcome::Deadlock { waiting: 4 }),
            "{mode:?}: {:?}",
            r.outcome
        );
        let report = r.failure.unwrap();
        assert!(report.contains("deadlock"), "{report}");
        assert!(
            report.contains("threads 0-1 (TM 0): trax.barrier G[4] (2 of 4 live threads arrived) in trax_barrier"),
            "{mode:?}: {report}"
        );
        assert!(
            report.contains("threads 2-3 (TM 1): trax.strsched (its TM drained and every ray buffer is empty: waiting for a ray)"),
            "{mode:?}: {report}"
        );
        assert!(
            report.contains("s_dead.c:5") && report.contains("s_dead.c:7"),
            "{report}"
        );
    }
}
