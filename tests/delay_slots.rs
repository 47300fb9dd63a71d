//! No instruction is moved into a delay slot: LLVM writes line-table rows only for the
//! branch of a (branch, slot) bundle, so an instruction moved there from its own line was
//! attributed to the branch's line (a store that faulted in a slot was reported on the
//! line after it, and profiles charged it there). Delay slots hold `nop`s; r6 compact
//! branches (no delay slot) are used wherever they exist.

use std::process::Command;

use trax_emulator::decode;
use trax_emulator::Executable;

mod common;
use common::{root, scratch_dir};

/// Mnemonics of MIPS32r6 control transfers with a delay slot.
const DELAYED: &[&str] = &[
    "b", "bal", "beq", "bne", "beqz", "bnez", "blez", "bgtz", "bltz", "bgez", "j", "jal", "jr",
    "jalr", "bc1eqz", "bc1nez", "bz.b", "bz.h", "bz.w", "bz.d", "bz.v", "bnz.b", "bnz.h", "bnz.w",
    "bnz.d", "bnz.v",
];

fn build(example: &str) -> Vec<u8> {
    let root = root();
    let dir = scratch_dir("delay-slots");
    let elf = dir.join(format!("{example}.elf"));
    let out = Command::new(env!("CARGO_BIN_EXE_trax"))
        .args(["build", &format!("examples/{example}.rs"), "-o"])
        .arg(&elf)
        .current_dir(root)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read(&elf).unwrap()
}

#[test]
fn delay_slots_hold_only_nops() {
    let mut slots = 0;
    let mut moved = Vec::new();
    for example in ["pathtracer", "raycast", "ao"] {
        let data = build(example);
        let exe = Executable::parse(example, &data).unwrap();
        let text = exe
            .segments
            .iter()
            .find(|s| s.addr <= exe.text_start && exe.text_start < s.addr + s.data.len() as u32)
            .unwrap();
        let word = |a: u32| {
            let o = (a - text.addr) as usize;
            u32::from_le_bytes(text.data[o..o + 4].try_into().unwrap())
        };
        for pc in (exe.text_start..exe.text_end - 4).step_by(4) {
            let inst = decode(word(pc)).to_string();
            let mnemonic = inst.split_whitespace().next().unwrap_or("");
            // The hand-written start-up code fills its one slot on purpose.
            let startup = exe
                .symbol_at(pc)
                .is_some_and(|(s, _)| s.name == trax_runtime::abi::START_SYMBOL);
            if DELAYED.contains(&mnemonic) && !startup {
                slots += 1;
                let slot = decode(word(pc + 4)).to_string();
                if slot != "nop" {
                    moved.push(format!("{example} {pc:#x}: {inst} ; {slot}"));
                }
            }
        }
    }
    assert!(
        slots > 0,
        "no delay-slot branches found: the test sees nothing"
    );
    assert!(
        moved.is_empty(),
        "{} instruction(s) moved into delay slots, e.g.\n{}",
        moved.len(),
        moved[..moved.len().min(10)].join("\n")
    );
}
