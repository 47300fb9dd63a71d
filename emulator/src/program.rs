//! Predecoded program text: every word of the text range decoded once at load time, and
//! translated once into the fast engine's micro-operations ([`crate::block`]).

use crate::block::{translate, Uop};
use crate::decode::{decode, Inst};
use crate::memory::Memory;

/// The decoded text section.
#[derive(Clone, Debug, Default)]
pub struct Program {
    /// Address of `insts[0]`.
    pub base: u32,
    /// One decoded instruction per text word.
    pub insts: Vec<Inst>,
    /// Entry point.
    pub entry: u32,
    /// One micro-operation per text word.
    pub(crate) uops: Vec<Uop>,
    /// Per text word: uops in the block starting there (0: the reference runs it).
    pub(crate) runs: Vec<u16>,
}

impl Program {
    /// Decodes the words of `[start, end)` from memory (`start` is rounded down and `end`
    /// up to a word boundary; unmapped words decode as reserved).
    pub fn decode_range(mem: &Memory, start: u32, end: u32, entry: u32) -> Program {
        let base = start & !3;
        let end = (end.max(start) + 3) & !3;
        let insts = (base..end)
            .step_by(4)
            .map(|a| mem.peek_u32(a).map(decode).unwrap_or(Inst::Reserved(0)))
            .collect::<Vec<_>>();
        let (uops, runs) = translate(&insts, base);
        Program {
            base,
            insts,
            entry,
            uops,
            runs,
        }
    }

    /// The predecoded instruction at `pc`, if `pc` is an aligned address inside the text.
    #[inline(always)]
    pub fn get(&self, pc: u32) -> Option<&Inst> {
        // A misaligned pc rotates its low bits to the top: out of range.
        let idx = pc.wrapping_sub(self.base).rotate_right(2) as usize;
        self.insts.get(idx)
    }

    /// One past the last text address.
    pub fn end(&self) -> u32 {
        self.base.wrapping_add(4 * self.insts.len() as u32)
    }
}
