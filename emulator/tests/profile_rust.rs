//! The profiler on a TRaX-Rust kernel built with the project's compiler and linker:
//! methods appear as `Type::method`; `Work::heavy` (never inlined) makes exactly twice
//! the calls of `Work::light` (always inlined) to the same `Work::step`, so their
//! inclusive costs are in a 2:1 ratio within 1%, at -O2 and -O0.

mod common;
use common::build_rust;
use trax_emulator::profile::{profile_run, Profile};
use trax_emulator::DebugInfo;
use trax_emulator::Executable;
use trax_emulator::{Machine, MachineConfig, Outcome};

const KERNEL: &str = r#"
struct Work {
    seed: u32,
}

impl Work {
    #[inline(never)]
    fn step(&self, i: u32) -> u32 {
        let mut s = i;
        let mut k = 0;
        while k < 20 {
            s = ((s ^ self.seed) + k) & 0xffff;
            k += 1;
        }
        s
    }

    #[inline(never)]
    fn heavy(&self, n: u32) -> u32 {
        let mut s = 0;
        let mut i = 0;
        while i < 2 * n {
            s = (s + self.step(i)) & 0xffffff;
            i += 1;
        }
        s
    }

    #[inline(always)]
    fn light(&self, n: u32) -> u32 {
        let mut s = 0;
        let mut i = 0;
        while i < n {
            s = (s + self.step(i)) & 0xffffff;
            i += 1;
        }
        s
    }
}

fn trax_main() {
    let w = Work { seed: trax::global_id() + 3 };
    let a = w.heavy(200);
    let b = w.light(200);
    println!("{}", a ^ b);
}
"#;

fn check(opt: u8) {
    let dir =
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("trax-prof-rust-{opt}"));
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join("work.rs");
    std::fs::write(&src, KERNEL).unwrap();
    let elf = build_rust(&src, opt);
    let exe = Executable::parse("work", &elf).unwrap();
    let config = MachineConfig {
        threads_per_tm: 2,
        ..MachineConfig::default()
    };
    let mut m = Machine::load(&exe, None, config).unwrap();
    let (summary, prof) = profile_run(&mut m, &mut std::io::sink(), None);
    let (outcome, retired) = (summary.outcome, summary.instructions);
    assert!(matches!(outcome, Outcome::Finished), "{outcome:?}");
    let dbg = DebugInfo::parse("work", &elf).unwrap();
    let p = Profile::build(&prof, Some(&dbg), Some(&exe));
    let tree = p.render_tree(0.0);
    eprintln!("-O{opt}:\n{tree}");
    assert_eq!(p.total(), retired);
    for n in &p.tree {
        let kids: u64 = n
            .children
            .iter()
            .map(|&c| p.weight(&p.tree[c].inclusive))
            .sum();
        assert_eq!(
            p.weight(&n.inclusive),
            p.weight(&n.self_cost) + kids,
            "{}\n{tree}",
            n.name
        );
    }
    let incl = |name: &str| -> f64 {
        let v = p.find(name);
        assert!(!v.is_empty(), "{name} missing from\n{tree}");
        v.iter()
            .map(|&i| p.weight(&p.tree[i].inclusive))
            .sum::<u64>() as f64
    };
    let ratio = incl("Work::heavy") / incl("Work::light");
    assert!(
        (ratio - 2.0).abs() / 2.0 < 0.01,
        "heavy/light = {ratio}\n{tree}"
    );
    assert!(!p.find("Work::step").is_empty(), "{tree}");
}

#[test]
fn rust_kernel_known_ratio_o2() {
    check(2);
}

#[test]
fn rust_kernel_known_ratio_o0() {
    check(0);
}
