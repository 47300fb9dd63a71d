//! The exact profiler on kernels whose costs are known: `work_a` (not inlined) does
//! exactly twice the calls of `work_b` (always inlined) to the same helper, so their
//! inclusive costs are in a 2:1 ratio; the tree must be consistent and the profiled
//! run must retire exactly the instructions of an ordinary run.

mod common;
use common::*;

use trax_emulator::profile::{profile_run, Profile};
use trax_emulator::DebugInfo;
use trax_emulator::Executable;
use trax_emulator::{Machine, MachineConfig, Outcome};

const SRC: &str = r#"#include "trax.h"
volatile int seed = 3;
__attribute__((noinline)) int helper(int x) {
  int s = x;
  for (int i = 0; i < 20; i++) s += seed * i; // HELPER
  return s;
}
__attribute__((noinline)) int work_a(int n) {
  int s = 0;
  for (int i = 0; i < 2 * n; i++) s += helper(i);
  return s;
}
static inline __attribute__((always_inline)) int work_b(int n) {
  int s = 0;
  for (int i = 0; i < n; i++) s += helper(i); // INLINED
  return s;
}
void trax_main(void) {
  int a = work_a(300);
  int b = work_b(300);
  trax_printi(a + b);
}
"#;

fn machine(elf: &std::path::Path, threads: u32) -> (Machine, Executable, DebugInfo) {
    let data = std::fs::read(elf).unwrap();
    let path = elf.display().to_string();
    let exe = Executable::parse(&path, &data).unwrap();
    let config = MachineConfig {
        threads_per_tm: threads,
        quantum: 37,
        ..MachineConfig::default()
    };
    let m = Machine::load(&exe, None, config).unwrap();
    let dbg = DebugInfo::parse(&path, &data).unwrap();
    (m, exe, dbg)
}

fn check(opt: &str) {
    let name = format!("prof{}", opt.trim_start_matches('-'));
    let elf = build_c(&name, SRC, opt);
    let (plain, plain_out) = run_elf(&elf, 1, 2);
    let (mut m, exe, dbg) = machine(&elf, 2);
    let mut out = Vec::new();
    let (summary, prof) = profile_run(&mut m, &mut out, None);
    let (outcome, retired) = (summary.outcome, summary.instructions);
    assert!(matches!(outcome, Outcome::Finished), "{outcome:?}");
    assert_eq!(String::from_utf8(out).unwrap(), plain_out);
    // Same scheduling as an ordinary run (quantum differs: counts do not depend on it).
    assert_eq!(retired, plain.instructions);
    let p = Profile::build(&prof, Some(&dbg), Some(&exe));
    let tree = p.render_tree(0.0);
    eprintln!("{opt}:\n{tree}\n{}", p.annotate(Some(&dbg)));
    assert_eq!(p.total(), retired, "{tree}");
    assert!((p.percent(p.total()) - 100.0).abs() < 1e-9);

    // Consistency: inclusive = self + children, so parent >= sum of children.
    for (i, n) in p.tree.iter().enumerate() {
        let kids: u64 = n
            .children
            .iter()
            .map(|&c| p.weight(&p.tree[c].inclusive))
            .sum();
        assert_eq!(
            p.weight(&n.inclusive),
            p.weight(&n.self_cost) + kids,
            "node {i} {}\n{tree}",
            n.name
        );
    }

    let one = |name: &str| -> usize {
        let v = p.find(name);
        assert!(!v.is_empty(), "{name} missing from\n{tree}");
        v.iter()
            .map(|&i| p.weight(&p.tree[i].inclusive))
            .sum::<u64>() as usize
    };
    let (a, b) = (one("work_a") as f64, one("work_b") as f64);
    let ratio = a / b;
    assert!(
        (ratio - 2.0).abs() / 2.0 < 0.01,
        "work_a/work_b = {ratio}\n{tree}"
    );
    // work_b is inlined into trax_main: it is a child of trax_main in the tree.
    let main = p.find("trax_main");
    assert!(
        p.find("work_b")
            .iter()
            .all(|&i| main.contains(&p.tree[i].parent)),
        "{tree}"
    );
    // helper runs only under its two callers (delay slots charged to the caller).
    let callers: Vec<&str> = p
        .find("helper")
        .iter()
        .map(|&i| p.tree[p.tree[i].parent].name.as_str())
        .collect();
    assert!(
        callers.len() == 2 && callers.contains(&"work_a") && callers.contains(&"work_b"),
        "{tree}"
    );

    // Folded stacks and speedscope carry the same total.
    let folded: u64 = p
        .folded()
        .lines()
        .map(|l| l.rsplit(' ').next().unwrap().parse::<u64>().unwrap())
        .sum();
    assert_eq!(folded, p.total());
    assert!(p.folded().contains("work_b;helper"), "{}", p.folded());
    let ss = p.speedscope("prof");
    assert!(ss.starts_with("{\"$schema\":\"https://www.speedscope.app/file-format-schema.json\""));
    assert!(ss.contains("\"name\":\"work_a\""), "{ss}");

    // Annotate: the helper's loop line carries its cost next to its source text.
    let ann = p.annotate(Some(&dbg));
    let line = ann
        .lines()
        .find(|l| l.contains("// HELPER"))
        .unwrap_or_else(|| panic!("{ann}"));
    let cost: u64 = line.split_whitespace().next().unwrap().parse().unwrap();
    assert!(cost as f64 > 0.3 * p.total() as f64, "{line}\n{ann}");
}

#[test]
fn known_ratio_o2() {
    check("-O2");
}

#[test]
fn known_ratio_o0() {
    check("-O0");
}

/// The per-cycle API the timing model uses: charging each retired instruction one
/// issue cycle (plus a stall on every call) through [`Profiler::charge`] gives the same
/// tree as the block-chunked functional profiler, in cycle mode with a breakdown.
#[test]
fn charge_api_matches_chunked_profile() {
    use trax_emulator::profile::{CostKind, Profiler};
    use trax_emulator::Stop;
    use trax_emulator::{Driven, Executor, Scheduler};
    use trax_emulator::{Shared, Thread};

    struct PerCycle<'a>(&'a mut Profiler);
    impl Executor for PerCycle<'_> {
        fn exec(&mut self, idx: usize, t: &mut Thread, sh: &mut Shared, budget: u64) -> Stop {
            for _ in 0..budget {
                let depth = t.calls.len();
                // Charge before executing: the cycle belongs to the instruction at pc.
                let snapshot = t.clone();
                let before = t.retired;
                let stop = t.run(sh, 1);
                if t.retired > before {
                    self.0.charge(idx, &snapshot, CostKind::Issue, 1);
                    if t.calls.len() > depth {
                        self.0.charge(idx, &snapshot, CostKind::DataStall, 2);
                    }
                }
                if stop != Stop::Budget {
                    return stop;
                }
            }
            Stop::Budget
        }
    }

    let elf = build_c("profcharge", SRC, "-O2");
    let (mut m, exe, dbg) = machine(&elf, 2);
    let (summary, chunked) = profile_run(&mut m, &mut Vec::new(), None);
    let (mut m2, _, _) = machine(&elf, 2);
    let mut prof = Profiler::new(&m2.shared.program, m2.threads.len());
    let mut sched = Scheduler::new(&m2);
    let outcome = loop {
        if let Driven::Done(o) = sched.run(&mut m2, &mut Vec::new(), &mut PerCycle(&mut prof)) {
            break o;
        }
    };
    assert!(matches!(outcome, Outcome::Finished));
    let a = Profile::build(&chunked, Some(&dbg), Some(&exe));
    let b = Profile::build(&prof, Some(&dbg), Some(&exe));
    assert!(b.cycles && !a.cycles);
    assert_eq!(
        b.tree[0].inclusive[CostKind::Issue.index()],
        summary.instructions
    );
    // Same stacks, same instruction counts per stack.
    let issue: Vec<(Vec<String>, u64)> = b
        .stacks
        .iter()
        .map(|(s, c)| {
            (
                s.iter().map(|f| f.name.clone()).collect(),
                c[CostKind::Issue.index()],
            )
        })
        .collect();
    let instr: Vec<(Vec<String>, u64)> = a
        .stacks
        .iter()
        .map(|(s, c)| {
            (
                s.iter().map(|f| f.name.clone()).collect(),
                c[CostKind::Instruction.index()],
            )
        })
        .collect();
    assert_eq!(issue, instr);
    let tree = b.render_tree(0.0);
    assert!(tree.contains("data-stall"), "{tree}");
    assert!(
        tree.starts_with(&format!("# {} thread-cycles", b.total())),
        "{tree}"
    );
}
