//! The fast engine against the reference interpreter, instruction by instruction, on
//! random programs.

use super::*;
use crate::exec::Stop;
use crate::memory::{Perms, Segment};
use crate::thread::Shared;

const TEXT: u32 = 0x10_0000;
const DATA: u32 = 0x20_0000;
const DATA_BYTES: u32 = 0x1_0000;

/// xorshift64*: deterministic, seedable, no dependencies.
struct Rand(u64);

impl Rand {
    fn next(&mut self) -> u32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 32) as u32
    }
    fn below(&mut self, n: u32) -> u32 {
        self.next() % n
    }
}

/// A random instruction word for the word at index `i` of a `len`-word program: any
/// decodable instruction but MSA and the TRaX operations that touch chip state, with
/// branch and jump targets inside the program (mostly).
fn word(r: &mut Rand, i: u32, len: u32) -> u32 {
    loop {
        let w = r.next();
        let inst = crate::decode::decode(w);
        let keep = match inst {
            Inst::Msa(_) => false,
            Inst::Trax { op, .. } => {
                matches!(op, TraxOp::FMin | TraxOp::FMax | TraxOp::InvSqrt)
                    || r.below(20) == 0
                        && matches!(op, TraxOp::GlobalId | TraxOp::Clock | TraxOp::Rand)
            }
            Inst::Syscall { .. }
            | Inst::Break { .. }
            | Inst::Sdbbp { .. }
            | Inst::Sigrie { .. }
            | Inst::Reserved(_) => r.below(50) == 0,
            // Few: they stop a run (most often by a trap).
            Inst::Teq { .. }
            | Inst::Tne { .. }
            | Inst::Tge { .. }
            | Inst::Tgeu { .. }
            | Inst::Tlt { .. }
            | Inst::Tltu { .. }
            | Inst::Add { .. }
            | Inst::Sub { .. } => r.below(4) == 0,
            _ => true,
        };
        if !keep {
            continue;
        }
        // Targets inside the program: a word offset from the next instruction.
        let to = r.below(len) as i32 - i as i32 - 1;
        let w = match inst.branch_offset() {
            Some(_) => match w >> 26 {
                0x32 | 0x3A => (w & !0x03FF_FFFF) | (to as u32 & 0x03FF_FFFF),
                0x36 | 0x3E if (w >> 21) & 31 != 0 => (w & !0x1F_FFFF) | (to as u32 & 0x1F_FFFF),
                _ => (w & !0xFFFF) | (to as u32 & 0xFFFF),
            },
            None => match inst {
                Inst::J { .. } | Inst::Jal { .. } => {
                    (w & !0x03FF_FFFF) | (((TEXT >> 2) + r.below(len)) & 0x03FF_FFFF)
                }
                // Jumps through a register: small offsets from the text addresses in
                // registers 8..12.
                Inst::Jic { .. } | Inst::Jialc { .. } => {
                    (w & !0x001F_FFFF) | ((8 + r.below(4)) << 16) | (4 * r.below(8))
                }
                _ => w,
            },
        };
        return w;
    }
}

/// A chip running `words` then `trax.halt`, and a thread at its start with registers
/// pointing into the data segment, at the text, or random.
fn setup(words: &[u32], r: &mut Rand) -> (Thread, Shared) {
    let mut w = words.to_vec();
    w.push(0x7000_0007); // trax.halt
    let data: Vec<u8> = w.iter().flat_map(|x| x.to_le_bytes()).collect();
    let bytes: Vec<u8> = (0..DATA_BYTES).map(|_| r.next() as u8).collect();
    let segs = vec![
        Segment::new("text", TEXT, data, Perms::RX),
        Segment::new("data", DATA, bytes, Perms::RW),
    ];
    let n = w.len() as u32;
    let sh = Shared::one_thread(&segs, TEXT, n);
    let mut t = Thread::new(TEXT, 0, 0, 0, 4096, 7);
    for g in 1..32 {
        t.regs.gpr[g] = match g {
            1..=7 => DATA + DATA_BYTES / 2 + 4 * r.below(64),
            8..=11 | 31 => TEXT + 4 * r.below(n),
            29 => crate::thread::Thread::new(0, 0, 0, 0, 4096, 0).regs.gpr[29] - 64,
            _ => match r.below(4) {
                0 => r.below(8),
                1 => r.next(),
                2 => (r.below(16) as i32 - 8) as u32,
                _ => 0x7FFF_FFFF + r.below(3),
            },
        };
    }
    for f in 0..32 {
        let bits = match r.below(6) {
            0 => (r.below(64) as f32 - 32.0).to_bits() as u128,
            1 => (r.below(64) as f64 * 0.37).to_bits() as u128,
            2 => r.next() as u128 | (r.next() as u128) << 32,
            3 => [0x7FC0_0000u128, 0x7F80_0001, 1, 0x8000_0000, 0x7F80_0000][r.below(5) as usize],
            _ => (r.next() as f32 / 1e3).to_bits() as u128,
        };
        t.regs.fpr[f] = bits | (r.next() as u128) << 64;
    }
    (t, sh)
}

/// What a run leaves that the other engine must match.
fn state(t: &Thread, sh: &Shared) -> String {
    format!(
        "pc {:#x} npc {:#x} slot {:#x} retired {} regs {:?} calls {:?} {} cop2 {:?} data {:x} local {:x} fault {:?}",
        t.pc,
        t.npc,
        t.slot_pc,
        t.retired,
        t.regs,
        t.calls,
        t.dropped_calls,
        t.cop2,
        fnv(sh.mem.global_slice(DATA, DATA_BYTES).unwrap()),
        fnv(&t.local),
        t.pending_fault,
    )
}

fn fnv(b: &[u8]) -> u64 {
    b.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &x| {
        (h ^ x as u64).wrapping_mul(0x100_0000_01b3)
    })
}

/// At most this many instructions per program (random branches make loops).
const LIMIT: u64 = 3000;

/// Runs with the reference, one instruction per call: the stops and the final state.
fn reference(words: &[u32], seed: u64) -> (Vec<(u64, Stop)>, String) {
    let mut r = Rand(seed);
    let (mut t, mut sh) = setup(words, &mut r);
    let mut stops = Vec::new();
    while t.retired < LIMIT {
        let s = t.step_once(&mut sh);
        if s != Stop::Budget {
            stops.push((t.retired, s.clone()));
            if !matches!(s, Stop::Retry | Stop::Blocked) {
                break;
            }
        }
    }
    (stops, state(&t, &sh))
}

/// Runs with the fast engine in turns of `budgets` (cycled).
fn fast(words: &[u32], seed: u64, budgets: &[u64]) -> (Vec<(u64, Stop)>, String) {
    let mut r = Rand(seed);
    let (mut t, mut sh) = setup(words, &mut r);
    let mut stops = Vec::new();
    let mut i = 0;
    while t.retired < LIMIT {
        let b = budgets[i % budgets.len()].min(LIMIT - t.retired);
        i += 1;
        let s = t.run(&mut sh, b);
        if s != Stop::Budget {
            stops.push((t.retired, s.clone()));
            if !matches!(s, Stop::Retry | Stop::Blocked) {
                break;
            }
        }
    }
    (stops, state(&t, &sh))
}

/// Random programs run alike in both engines: the same stops at the same instruction
/// counts, the same registers, slots, shadow call stack, memory and fault, whatever the
/// turn lengths (which cut blocks anywhere, delay slots included).
#[test]
fn fast_engine_matches_the_reference_on_random_programs() {
    let mut r = Rand(0x5EED_0001);
    let (mut fast_words, mut complex_words) = (0u64, 0u64);
    for case in 0..1500u64 {
        let len = 8 + r.below(56);
        let words: Vec<u32> = (0..len).map(|i| word(&mut r, i, len)).collect();
        let seed = 0x1234_5678 + case;
        let want = reference(&words, seed);
        for budgets in [&[1000][..], &[1], &[3, 1, 7], &[17, 2]] {
            let got = fast(&words, seed, budgets);
            assert_eq!(
                got, want,
                "case {case}, budgets {budgets:?}, words {words:08x?}"
            );
        }
        let mut rr = Rand(seed);
        let (_, sh) = setup(&words, &mut rr);
        fast_words += sh.program.runs.iter().filter(|&&n| n > 0).count() as u64;
        complex_words += sh.program.runs.iter().filter(|&&n| n == 0).count() as u64;
    }
    // The test exercises mostly the engine, not the reference: random words are dense in
    // branches (about one in six), which make their neighbours the reference's, yet most
    // words have uops.
    assert!(
        fast_words > 2 * complex_words,
        "{fast_words} fast words, {complex_words} complex"
    );
}

/// Every uop that writes a GPR destination has a non-zero one: `gpr[0]` is never written.
#[test]
fn no_uop_writes_register_zero() {
    let mut r = Rand(99);
    for _ in 0..200_000 {
        let w = r.next();
        let inst = crate::decode::decode(w);
        let (uops, _) = translate(
            &[
                Inst::Addiu {
                    rt: 1,
                    rs: 0,
                    imm: 0,
                },
                inst,
            ],
            TEXT,
        );
        let u = uops[1];
        if u.k.pure_gpr() || u.k.faulting_gpr() {
            assert_ne!(u.a, 0, "{inst:?} -> {u:?}");
        }
    }
}

/// Block lengths: straight-line code up to a branch and its delay slot, or a compact
/// branch; words the reference runs have none; a branch right after a branch is the
/// reference's (it may sit in a slot), and so is the branch before it (its slot is).
#[test]
fn blocks_end_at_branches_and_slots() {
    let addiu = Inst::Addiu {
        rt: 1,
        rs: 1,
        imm: 1,
    };
    let beq = Inst::Beq {
        rs: 1,
        rt: 2,
        off: 8,
    };
    let bnezc = Inst::Bnezc { rs: 1, off: 8 };
    let halt = crate::decode::decode(0x7000_0007);
    let insts = [
        addiu, addiu, beq, addiu, addiu, bnezc, addiu, beq, bnezc, halt,
    ];
    let (uops, runs) = translate(&insts, TEXT);
    assert_eq!(runs, [4, 3, 2, 3, 2, 1, 1, 0, 0, 0]);
    assert_eq!(uops[0].k, K::AddImm);
    assert_eq!(uops[8].k, K::Complex, "a branch in a delay slot");
    assert_eq!(
        uops[7].k,
        K::Complex,
        "a branch whose slot the engine does not run"
    );
    // The first word of the text may follow a branch outside it.
    let (uops, runs) = translate(&[beq, addiu], TEXT);
    assert_eq!((uops[0].k, runs[0]), (K::Complex, 0));
}
