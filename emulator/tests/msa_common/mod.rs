//! Shared helpers for the MSA semantic tests: encoders (written from the MSA encoding
//! tables, independent of the decoder), a flat test memory, a PRNG and edge-value pools.

#![allow(dead_code)]

use trax_emulator::msa::{decode, execute, MsaMemory, MsaOutcome};
use trax_emulator::RegFile;

/// Deterministic xorshift64* generator.
pub struct Rng(pub u64);

impl Rng {
    pub fn u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    pub fn below(&mut self, n: u64) -> u64 {
        self.u64() % n
    }

    /// A lane value of `bits` bits: an edge value or random bits.
    pub fn int_lane(&mut self, bits: u32) -> u64 {
        let m = if bits == 64 {
            u64::MAX
        } else {
            (1u64 << bits) - 1
        };
        let min = 1u64 << (bits - 1);
        let edges = [
            0,
            1,
            2,
            m,
            m - 1,
            min,
            min - 1,
            min + 1,
            3,
            bits as u64 - 1,
            bits as u64,
        ];
        match self.below(4) {
            0 => edges[self.below(edges.len() as u64) as usize] & m,
            1 => self.below(16) & m,
            2 => (self.below(16) as i64).wrapping_neg() as u64 & m,
            _ => self.u64() & m,
        }
    }

    /// A 128-bit vector of `bits`-wide lanes from `int_lane`.
    pub fn int_vec(&mut self, bits: u32) -> u128 {
        let mut v = 0u128;
        for i in 0..128 / bits {
            v |= (self.int_lane(bits) as u128) << (i * bits);
        }
        v
    }

    /// An f32 bit pattern biased towards special values.
    pub fn f32_bits(&mut self) -> u32 {
        let edges: [u32; 16] = [
            0,
            0x8000_0000,
            0x7F80_0000,
            0xFF80_0000,
            0x7FC0_0000,
            0x7F80_0001, // sNaN
            0xFFC1_2345,
            0x0000_0001, // smallest subnormal
            0x807F_FFFF,
            0x0080_0000, // smallest normal
            0x7F7F_FFFF,
            0x3F80_0000,
            0xBF80_0000,
            0x4F00_0000, // 2^31
            0xCF00_0000,
            0x3F00_0000,
        ];
        match self.below(5) {
            0 => edges[self.below(16) as usize],
            1 => (self.below(2000) as f32 - 1000.0).to_bits() ^ (self.below(2) as u32) << 31,
            2 => (self.u64() as u32 & 0x807F_FFFF) | 0x3F00_0000,
            _ => self.u64() as u32,
        }
    }

    /// An f64 bit pattern biased towards special values.
    pub fn f64_bits(&mut self) -> u64 {
        let edges: [u64; 14] = [
            0,
            0x8000_0000_0000_0000,
            0x7FF0_0000_0000_0000,
            0xFFF0_0000_0000_0000,
            0x7FF8_0000_0000_0000,
            0x7FF0_0000_0000_0001,
            0x0000_0000_0000_0001,
            0x0010_0000_0000_0000,
            0x7FEF_FFFF_FFFF_FFFF,
            0x3FF0_0000_0000_0000,
            0xBFF0_0000_0000_0000,
            0x43E0_0000_0000_0000, // 2^63
            0x41E0_0000_0000_0000, // 2^31
            0x3FE0_0000_0000_0000,
        ];
        match self.below(5) {
            0 => edges[self.below(14) as usize],
            1 => (self.below(2000) as f64 - 1000.0).to_bits() ^ self.below(2) << 63,
            2 => (self.u64() & 0x800F_FFFF_FFFF_FFFF) | 0x3FE0_0000_0000_0000,
            _ => self.u64(),
        }
    }
}

/// Flat little-endian memory of 4 KiB at address 0x1000 for load/store tests.
pub struct FlatMem(pub Vec<u8>);

pub const MEM_BASE: u32 = 0x1000;

impl MsaMemory for FlatMem {
    type Error = u32;
    fn load(&mut self, addr: u32, buf: &mut [u8]) -> Result<(), u32> {
        let off = addr.checked_sub(MEM_BASE).ok_or(addr)? as usize;
        let src = self.0.get(off..off + buf.len()).ok_or(addr)?;
        buf.copy_from_slice(src);
        Ok(())
    }
    fn store(&mut self, addr: u32, data: &[u8]) -> Result<(), u32> {
        let off = addr.checked_sub(MEM_BASE).ok_or(addr)? as usize;
        let dst = self.0.get_mut(off..off + data.len()).ok_or(addr)?;
        dst.copy_from_slice(data);
        Ok(())
    }
}

/// Decodes and executes `word`; panics (test failure) if it does not decode.
pub fn run(word: u32, regs: &mut RegFile, mem: &mut FlatMem) -> MsaOutcome<u32> {
    let inst = decode(word).unwrap_or_else(|| panic!("{word:#010x} does not decode"));
    execute(&inst, regs, mem)
}

pub fn mnemonic(word: u32) -> String {
    decode(word)
        .map(|i| i.to_string())
        .unwrap_or_else(|| format!("<invalid {word:#x}>"))
}

const MSA: u32 = 0x1E << 26;

/// 3R format: op3 at 25..23, df at 22..21.
pub fn enc_3r(minor: u32, op3: u32, df: u32, wt: u32, ws: u32, wd: u32) -> u32 {
    MSA | op3 << 23 | df << 21 | wt << 16 | ws << 11 | wd << 6 | minor
}

/// 3RF format: op4 at 25..22, one df bit at 21.
pub fn enc_3rf(minor: u32, op4: u32, df1: u32, wt: u32, ws: u32, wd: u32) -> u32 {
    MSA | op4 << 22 | df1 << 21 | wt << 16 | ws << 11 | wd << 6 | minor
}

/// VEC format (minor 0x1E): op5 at 25..21.
pub fn enc_vec(op5: u32, wt: u32, ws: u32, wd: u32) -> u32 {
    MSA | op5 << 21 | wt << 16 | ws << 11 | wd << 6 | 0x1E
}

/// 2R format: 8-bit op at 25..18, df at 17..16.
pub fn enc_2r(op8: u32, df: u32, ws: u32, wd: u32) -> u32 {
    MSA | op8 << 18 | df << 16 | ws << 11 | wd << 6 | 0x1E
}

/// 2RF format: 9-bit op at 25..17, df bit at 16.
pub fn enc_2rf(op9: u32, df1: u32, ws: u32, wd: u32) -> u32 {
    MSA | op9 << 17 | df1 << 16 | ws << 11 | wd << 6 | 0x1E
}

/// I5 format.
pub fn enc_i5(minor: u32, op3: u32, df: u32, imm5: u32, ws: u32, wd: u32) -> u32 {
    MSA | op3 << 23 | df << 21 | (imm5 & 31) << 16 | ws << 11 | wd << 6 | minor
}

/// BIT format: df/m field built from element bits and m.
pub fn enc_bit(minor: u32, op3: u32, bits: u32, m: u32, ws: u32, wd: u32) -> u32 {
    let dfm = match bits {
        8 => 0x70 | m,
        16 => 0x60 | m,
        32 => 0x40 | m,
        _ => m,
    };
    MSA | op3 << 23 | dfm << 16 | ws << 11 | wd << 6 | minor
}

/// ELM format: df/n field built from element bits and n.
pub fn enc_elm(op4: u32, bits: u32, n: u32, ws: u32, wd: u32) -> u32 {
    let dfn = match bits {
        8 => n,
        16 => 0x20 | n,
        32 => 0x30 | n,
        _ => 0x38 | n,
    };
    MSA | op4 << 22 | dfn << 16 | ws << 11 | wd << 6 | 0x19
}

/// I8 format.
pub fn enc_i8(minor: u32, op2: u32, imm: u32, ws: u32, wd: u32) -> u32 {
    MSA | op2 << 24 | (imm & 0xFF) << 16 | ws << 11 | wd << 6 | minor
}

/// MI10 format: s10 offset in elements.
pub fn enc_mi10(st: bool, df: u32, s10: i32, rs: u32, wd: u32) -> u32 {
    MSA | ((s10 as u32) & 0x3FF) << 16 | rs << 11 | wd << 6 | 0x20 | (st as u32) << 2 | df
}

/// Element `i` of `v` with `bits`-wide lanes.
pub fn get(v: u128, bits: u32, i: u32) -> u64 {
    let m = if bits == 64 {
        u64::MAX
    } else {
        (1u64 << bits) - 1
    };
    (v >> (i * bits)) as u64 & m
}

/// Vector from lanes.
pub fn from_lanes(bits: u32, lanes: &[u64]) -> u128 {
    let m = if bits == 64 {
        u64::MAX
    } else {
        (1u64 << bits) - 1
    };
    lanes.iter().enumerate().fold(0u128, |v, (i, &x)| {
        v | ((x & m) as u128) << (i as u32 * bits)
    })
}

pub const DF_BITS: [u32; 4] = [8, 16, 32, 64];
