//! The start-up routine `__trax_start`, the ELF entry point of every TRaX program.
//!
//! The runtime owns this code as data: machine words plus the relocations they need. The
//! assembler's linker turns it into a tiny relocatable object and links it first, so
//! `__trax_start` sits at the start of `.text` (at [`crate::abi::TEXT_BASE`]).
//!
//! What it does, on every hardware thread:
//!
//! ```text
//! __trax_start:
//!     lui   $sp, %hi(STACK_TOP)          # every thread: its own local-store stack
//!     ori   $sp, $sp, %lo(STACK_TOP)     # (only when the low half is non-zero)
//!     lui   $s0, %hi(__init_array_start)
//!     addiu $s0, $s0, %lo(__init_array_start)
//!     lui   $s1, %hi(__init_array_end)
//!     addiu $s1, $s1, %lo(__init_array_end)
//! 1:  beq   $s0, $s1, 2f                 # each .init_array entry, in order
//!     nop
//!     lw    $t9, 0($s0)
//!     jalr  $t9
//!     addiu $s0, $s0, 4                  # (delay slot)
//!     b     1b
//!     nop
//! 2:  jal   trax_main
//!     nop
//!     trax.halt
//! ```
//!
//! `$s0`/`$s1` are callee-saved in o32, so they survive the constructor calls. The linker
//! defines `__init_array_start`/`__init_array_end` around the merged `.init_array`.

use crate::abi;
use crate::isa::{instr, TraxOp};

/// Symbol the linker defines at the first `.init_array` entry.
pub const INIT_ARRAY_START: &str = "__init_array_start";
/// Symbol the linker defines one past the last `.init_array` entry.
pub const INIT_ARRAY_END: &str = "__init_array_end";

/// How a start-up relocation patches its instruction (MIPS ELF semantics).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StartupRelocKind {
    /// `R_MIPS_HI16`: high half of the symbol address (paired with the next `Lo16`).
    Hi16,
    /// `R_MIPS_LO16`: low half of the symbol address.
    Lo16,
    /// `R_MIPS_26`: 26-bit jump target (`jal`).
    Jump26,
}

/// One relocation of the start-up code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StartupReloc {
    /// Byte offset of the patched instruction from `__trax_start`.
    pub offset: u32,
    /// Relocation kind.
    pub kind: StartupRelocKind,
    /// Referenced symbol.
    pub symbol: &'static str,
}

/// The start-up routine: instruction words (addends are zero) and their relocations.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StartupCode {
    /// Instruction words, in order, starting at `__trax_start`.
    pub words: Vec<u32>,
    /// Relocations against the words, in ascending offset order (each `Hi16` is followed by
    /// its `Lo16`).
    pub relocs: Vec<StartupReloc>,
}

impl StartupCode {
    /// The code as little-endian bytes.
    pub fn bytes(&self) -> Vec<u8> {
        self.words.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    /// Size of the code in bytes.
    pub fn size(&self) -> u32 {
        self.words.len() as u32 * 4
    }
}

const SP: u32 = 29;
const S0: u32 = 16;
const S1: u32 = 17;
const T9: u32 = 25;
const RA: u32 = 31;

fn i_type(op: u32, rs: u32, rt: u32, imm: u16) -> u32 {
    (op << 26) | (rs << 21) | (rt << 16) | u32::from(imm)
}

fn lui(rt: u32, imm: u16) -> u32 {
    i_type(0x0F, 0, rt, imm)
}

fn ori(rt: u32, rs: u32, imm: u16) -> u32 {
    i_type(0x0D, rs, rt, imm)
}

fn addiu(rt: u32, rs: u32, imm: u16) -> u32 {
    i_type(0x09, rs, rt, imm)
}

fn lw(rt: u32, base: u32, off: u16) -> u32 {
    i_type(0x23, base, rt, off)
}

/// `beq rs, rt, target` where `from` and `to` are word indices of the branch and target.
fn beq(rs: u32, rt: u32, from: usize, to: usize) -> u32 {
    let off = to as i32 - (from as i32 + 1);
    i_type(0x04, rs, rt, off as i16 as u16)
}

fn jalr(rd: u32, rs: u32) -> u32 {
    (rs << 21) | (rd << 11) | 0x09
}

const NOP: u32 = 0;

/// Builds the start-up routine.
pub fn startup_code() -> StartupCode {
    let mut words = Vec::new();
    let mut relocs = Vec::new();
    let (hi, lo) = ((abi::STACK_TOP >> 16) as u16, abi::STACK_TOP as u16);
    words.push(lui(SP, hi));
    if lo != 0 {
        words.push(ori(SP, SP, lo));
    }
    for (reg, sym) in [(S0, INIT_ARRAY_START), (S1, INIT_ARRAY_END)] {
        let at = words.len() as u32 * 4;
        relocs.push(StartupReloc {
            offset: at,
            kind: StartupRelocKind::Hi16,
            symbol: sym,
        });
        relocs.push(StartupReloc {
            offset: at + 4,
            kind: StartupRelocKind::Lo16,
            symbol: sym,
        });
        words.push(lui(reg, 0));
        words.push(addiu(reg, reg, 0));
    }
    let top = words.len();
    // Word indices of the loop: top: beq, nop, lw, jalr, addiu, b, nop; done: jal ...
    let done = top + 7;
    words.push(beq(S0, S1, top, done));
    words.push(NOP);
    words.push(lw(T9, S0, 0));
    words.push(jalr(RA, T9));
    words.push(addiu(S0, S0, 4));
    let here = words.len();
    words.push(beq(0, 0, here, top));
    words.push(NOP);
    debug_assert_eq!(words.len(), done);
    relocs.push(StartupReloc {
        offset: words.len() as u32 * 4,
        kind: StartupRelocKind::Jump26,
        symbol: abi::ENTRY_SYMBOL,
    });
    words.push(0x03 << 26); // jal trax_main
    words.push(NOP);
    words.push(instr(TraxOp::Halt).encode(&[]));
    StartupCode { words, relocs }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_with_call_then_halt() {
        let code = startup_code();
        let n = code.words.len();
        assert_eq!(code.words[n - 1], instr(TraxOp::Halt).encode(&[]));
        assert_eq!(code.words[n - 2], NOP, "jal delay slot must be a nop");
        assert_eq!(code.words[n - 3] >> 26, 0x03, "jal");
        let jal = code.relocs.last().unwrap();
        assert_eq!(jal.kind, StartupRelocKind::Jump26);
        assert_eq!(jal.offset, (n as u32 - 3) * 4);
        assert_eq!(jal.symbol, "trax_main");
    }

    #[test]
    fn sets_stack_pointer_first() {
        let code = startup_code();
        assert_eq!(code.words[0], 0x3C1D_0000 | (abi::STACK_TOP >> 16));
    }

    #[test]
    fn loop_branches_land_on_instructions() {
        let code = startup_code();
        for (i, w) in code.words.iter().enumerate() {
            if w >> 26 == 0x04 {
                let off = i64::from(*w as u16 as i16);
                let target = i as i64 + 1 + off;
                assert!(target >= 0 && (target as usize) < code.words.len());
            }
        }
        // The exit branch goes to the jal.
        let first_beq = code.words.iter().position(|w| w >> 26 == 0x04).unwrap();
        let off = code.words[first_beq] as u16 as i16 as i64;
        assert_eq!(
            code.words[(first_beq as i64 + 1 + off) as usize] >> 26,
            0x03
        );
    }

    #[test]
    fn hi16_is_followed_by_its_lo16() {
        let code = startup_code();
        for (i, r) in code.relocs.iter().enumerate() {
            if r.kind == StartupRelocKind::Hi16 {
                let lo = code.relocs[i + 1];
                assert_eq!(lo.kind, StartupRelocKind::Lo16);
                assert_eq!(lo.symbol, r.symbol);
            }
        }
        assert_eq!(code.bytes().len() as u32, code.size());
    }
}
