//! Instruction-word decoder for MSA (major opcode 0x1E) and the MSA branches (COP1).

use super::{Df, MsaInst, MsaOp};
use MsaOp::*;

const OP_MSA: u32 = 0x1E;
const OP_COP1: u32 = 0x11;

const DFS: [Df; 4] = [Df::B, Df::H, Df::W, Df::D];

fn bits(w: u32, hi: u32, lo: u32) -> u32 {
    (w >> lo) & ((1 << (hi - lo + 1)) - 1)
}

fn sext(v: u32, width: u32) -> i32 {
    ((v << (32 - width)) as i32) >> (32 - width)
}

fn inst(op: MsaOp, df: Df, w: u32, imm: i32) -> Option<MsaInst> {
    Some(MsaInst {
        op,
        df,
        wd: bits(w, 10, 6) as u8,
        ws: bits(w, 15, 11) as u8,
        wt: bits(w, 20, 16) as u8,
        imm,
    })
}

/// Decodes one instruction word; `None` if it is not an MSA instruction valid on MIPS32r6.
pub fn decode(word: u32) -> Option<MsaInst> {
    match word >> 26 {
        OP_MSA => decode_msa(word),
        OP_COP1 => decode_branch(word),
        _ => None,
    }
}

fn decode_branch(w: u32) -> Option<MsaInst> {
    let (op, df) = match bits(w, 25, 21) {
        0x0B => (Bz, Df::V),
        0x0F => (Bnz, Df::V),
        r @ 0x18..=0x1B => (Bz, DFS[(r - 0x18) as usize]),
        r @ 0x1C..=0x1F => (Bnz, DFS[(r - 0x1C) as usize]),
        _ => return None,
    };
    inst(op, df, w, sext(bits(w, 15, 0), 16) << 2)
}

fn decode_msa(w: u32) -> Option<MsaInst> {
    let minor = bits(w, 5, 0);
    match minor {
        0x00..=0x02 => decode_i8(w, minor),
        0x06 | 0x07 => decode_i5(w, minor),
        0x09 | 0x0A => decode_bit(w, minor),
        0x0D..=0x15 => decode_3r(w, minor),
        0x19 => decode_elm(w),
        0x1A..=0x1C => decode_3rf(w, minor),
        0x1E => decode_vec(w),
        0x20..=0x27 => {
            let df = DFS[(minor & 3) as usize];
            let op = if minor & 4 == 0 { Ld } else { St };
            let scale = (df.bits() / 8) as i32;
            inst(op, df, w, sext(bits(w, 25, 16), 10) * scale)
        }
        _ => None,
    }
}

fn decode_i8(w: u32, minor: u32) -> Option<MsaInst> {
    let op2 = bits(w, 25, 24) as usize;
    let imm = bits(w, 23, 16) as i32;
    let (op, df) = match minor {
        0 => ([Andi, Ori, Nori, Xori][op2], Df::B),
        1 => (*[Bmnzi, Bmzi, Bseli].get(op2)?, Df::B),
        _ => (Shf, *DFS[..3].get(op2)?),
    };
    inst(op, df, w, imm)
}

fn decode_i5(w: u32, minor: u32) -> Option<MsaInst> {
    let op3 = bits(w, 25, 23);
    let df = DFS[bits(w, 22, 21) as usize];
    let u5 = bits(w, 20, 16) as i32;
    let s5 = sext(bits(w, 20, 16), 5);
    match (minor, op3) {
        (6, 0) => inst(Addvi, df, w, u5),
        (6, 1) => inst(Subvi, df, w, u5),
        (6, 2) => inst(MaxiS, df, w, s5),
        (6, 3) => inst(MaxiU, df, w, u5),
        (6, 4) => inst(MiniS, df, w, s5),
        (6, 5) => inst(MiniU, df, w, u5),
        (7, 0) => inst(Ceqi, df, w, s5),
        (7, 2) => inst(CltiS, df, w, s5),
        (7, 3) => inst(CltiU, df, w, u5),
        (7, 4) => inst(CleiS, df, w, s5),
        (7, 5) => inst(CleiU, df, w, u5),
        (7, 6) => inst(Ldi, df, w, sext(bits(w, 20, 11), 10)),
        _ => None,
    }
}

/// Splits the BIT format's df/m field (bits 22..16).
fn bit_dfm(w: u32) -> Option<(Df, i32)> {
    let f = bits(w, 22, 16);
    if f & 0x40 == 0 {
        Some((Df::D, (f & 0x3F) as i32))
    } else if f & 0x20 == 0 {
        Some((Df::W, (f & 0x1F) as i32))
    } else if f & 0x10 == 0 {
        Some((Df::H, (f & 0x0F) as i32))
    } else if f & 0x08 == 0 {
        Some((Df::B, (f & 0x07) as i32))
    } else {
        None
    }
}

fn decode_bit(w: u32, minor: u32) -> Option<MsaInst> {
    let (df, m) = bit_dfm(w)?;
    let op3 = bits(w, 25, 23) as usize;
    let op = if minor == 9 {
        [Slli, Srai, Srli, Bclri, Bseti, Bnegi, Binsli, Binsri][op3]
    } else {
        *[SatS, SatU, Srari, Srlri].get(op3)?
    };
    inst(op, df, w, m)
}

fn decode_3r(w: u32, minor: u32) -> Option<MsaInst> {
    let op3 = bits(w, 25, 23) as usize;
    let df = DFS[bits(w, 22, 21) as usize];
    let op = match minor {
        0x0D => [Sll, Sra, Srl, Bclr, Bset, Bneg, Binsl, Binsr][op3],
        0x0E => [Addv, Subv, MaxS, MaxU, MinS, MinU, MaxA, MinA][op3],
        0x0F => [
            Some(Ceq),
            None,
            Some(CltS),
            Some(CltU),
            Some(CleS),
            Some(CleU),
            None,
            None,
        ][op3]?,
        0x10 => [AddA, AddsA, AddsS, AddsU, AveS, AveU, AverS, AverU][op3],
        0x11 => *[SubsS, SubsU, SubsusU, SubsuuS, AsubS, AsubU].get(op3)?,
        0x12 => [
            Some(Mulv),
            Some(Maddv),
            Some(Msubv),
            None,
            Some(DivS),
            Some(DivU),
            Some(ModS),
            Some(ModU),
        ][op3]?,
        0x13 => {
            if df == Df::B {
                return None;
            }
            *[DotpS, DotpU, DpaddS, DpaddU, DpsubS, DpsubU].get(op3)?
        }
        0x14 => [Sld, Splat, Pckev, Pckod, Ilvl, Ilvr, Ilvev, Ilvod][op3],
        _ => {
            let op = [
                Some(Vshf),
                Some(Srar),
                Some(Srlr),
                None,
                Some(HaddS),
                Some(HaddU),
                Some(HsubS),
                Some(HsubU),
            ][op3]?;
            if op3 >= 4 && df == Df::B {
                return None;
            }
            op
        }
    };
    inst(op, df, w, 0)
}

fn decode_elm(w: u32) -> Option<MsaInst> {
    let op4 = bits(w, 25, 22);
    let f = bits(w, 21, 16);
    if f == 0x3E {
        return match op4 {
            // Only the eight MSA control registers 0..7 exist.
            0 if bits(w, 10, 6) < 8 => inst(Ctcmsa, Df::V, w, 0),
            1 if bits(w, 15, 11) < 8 => inst(Cfcmsa, Df::V, w, 0),
            2 => inst(Move, Df::V, w, 0),
            _ => None,
        };
    }
    let (df, n) = if f & 0x30 == 0 {
        (Df::B, f & 0xF)
    } else if f & 0x38 == 0x20 {
        (Df::H, f & 7)
    } else if f & 0x3C == 0x30 {
        (Df::W, f & 3)
    } else if f & 0x3E == 0x38 {
        (Df::D, f & 1)
    } else {
        return None;
    };
    let op = match op4 {
        0 => Sldi,
        1 => Splati,
        2 if df != Df::D => CopyS,
        3 if df != Df::D && df != Df::W => CopyU,
        4 if df != Df::D => Insert,
        5 => Insve,
        _ => return None,
    };
    inst(op, df, w, n as i32)
}

fn decode_3rf(w: u32, minor: u32) -> Option<MsaInst> {
    let op4 = bits(w, 25, 22) as usize;
    let wide = bits(w, 21, 21) == 1;
    let fdf = if wide { Df::D } else { Df::W };
    let qdf = if wide { Df::W } else { Df::H };
    let (op, df) = match minor {
        0x1A => (
            [
                Fcaf, Fcun, Fceq, Fcueq, Fclt, Fcult, Fcle, Fcule, Fsaf, Fsun, Fseq, Fsueq, Fslt,
                Fsult, Fsle, Fsule,
            ][op4],
            fdf,
        ),
        0x1B => match op4 {
            0 => (Fadd, fdf),
            1 => (Fsub, fdf),
            2 => (Fmul, fdf),
            3 => (Fdiv, fdf),
            4 => (Fmadd, fdf),
            5 => (Fmsub, fdf),
            7 => (Fexp2, fdf),
            8 => (Fexdo, qdf),
            10 => (Ftq, qdf),
            12 => (Fmin, fdf),
            13 => (FminA, fdf),
            14 => (Fmax, fdf),
            15 => (FmaxA, fdf),
            _ => return None,
        },
        _ => match op4 {
            1 => (Fcor, fdf),
            2 => (Fcune, fdf),
            3 => (Fcne, fdf),
            4 => (MulQ, qdf),
            5 => (MaddQ, qdf),
            6 => (MsubQ, qdf),
            9 => (Fsor, fdf),
            10 => (Fsune, fdf),
            11 => (Fsne, fdf),
            12 => (MulrQ, qdf),
            13 => (MaddrQ, qdf),
            14 => (MsubrQ, qdf),
            _ => return None,
        },
    };
    inst(op, df, w, 0)
}

fn decode_vec(w: u32) -> Option<MsaInst> {
    let op5 = bits(w, 25, 21);
    match op5 {
        0..=6 => inst(
            [AndV, OrV, NorV, XorV, BmnzV, BmzV, BselV][op5 as usize],
            Df::V,
            w,
            0,
        ),
        0x18 => {
            // 2R: bits 25..18 = 110000oo, df in 17..16.
            if bits(w, 20, 20) != 0 {
                return None;
            }
            let op = [Fill, Pcnt, Nloc, Nlzc][bits(w, 19, 18) as usize];
            let df = DFS[bits(w, 17, 16) as usize];
            if op == Fill && df == Df::D {
                return None;
            }
            inst(op, df, w, 0)
        }
        0x19 => {
            // 2RF: bits 25..17 = 11001oooo, df in bit 16.
            let op = [
                Fclass, FtruncS, FtruncU, Fsqrt, Frsqrt, Frcp, Frint, Flog2, Fexupl, Fexupr, Ffql,
                Ffqr, FtintS, FtintU, FfintS, FfintU,
            ][bits(w, 20, 17) as usize];
            let df = if bits(w, 16, 16) == 1 { Df::D } else { Df::W };
            inst(op, df, w, 0)
        }
        _ => None,
    }
}
