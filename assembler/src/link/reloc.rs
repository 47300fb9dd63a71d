//! MIPS32 REL relocations: which ones the linker applies and how (System V MIPS ABI and the
//! MIPS32r6 PC-relative additions). Addends are implicit: read from the patched word.

/// How one relocation type is applied.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Action {
    /// No effect (`R_MIPS_NONE`, the `R_MIPS_JALR` optimisation hint).
    Skip,
    /// `R_MIPS_32`: S + A.
    Abs32,
    /// `R_MIPS_26`: (S + A) >> 2 in the 256 MiB region of the delay slot.
    Jump26,
    /// `R_MIPS_HI16`: high half of S + AHL, AHL formed with the paired `R_MIPS_LO16`.
    Hi16,
    /// `R_MIPS_LO16`: low half of S + A.
    Lo16,
    /// PC-relative field of `bits` bits holding the offset shifted right by `shift`.
    PcField { bits: u32, shift: u32 },
    /// `R_MIPS_PCHI16`: high half of S + AHL - P (paired with `R_MIPS_PCLO16`).
    PcHi16,
    /// `R_MIPS_PCLO16`: low half of S + A - P.
    PcLo16,
    /// `R_MIPS_PC32`: S + A - P.
    Pc32,
}

/// Why a relocation type is refused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Refusal {
    /// The relocation addresses data relative to `$gp`.
    GpRelative,
    /// Not implemented; the string is a hint for the user (may be empty).
    Unsupported(&'static str),
}

pub(crate) const R_MIPS_LO16: u32 = 6;
pub(crate) const R_MIPS_PCLO16: u32 = 65;

/// The name of a MIPS relocation type, for messages.
pub(crate) fn type_name(r_type: u32) -> String {
    let name = match r_type {
        0 => "R_MIPS_NONE",
        1 => "R_MIPS_16",
        2 => "R_MIPS_32",
        3 => "R_MIPS_REL32",
        4 => "R_MIPS_26",
        5 => "R_MIPS_HI16",
        6 => "R_MIPS_LO16",
        7 => "R_MIPS_GPREL16",
        8 => "R_MIPS_LITERAL",
        9 => "R_MIPS_GOT16",
        10 => "R_MIPS_PC16",
        11 => "R_MIPS_CALL16",
        12 => "R_MIPS_GPREL32",
        18 => "R_MIPS_64",
        19 => "R_MIPS_GOT_DISP",
        20 => "R_MIPS_GOT_PAGE",
        21 => "R_MIPS_GOT_OFST",
        22 => "R_MIPS_GOT_HI16",
        23 => "R_MIPS_GOT_LO16",
        24 => "R_MIPS_SUB",
        28 => "R_MIPS_HIGHER",
        29 => "R_MIPS_HIGHEST",
        30 => "R_MIPS_CALL_HI16",
        31 => "R_MIPS_CALL_LO16",
        37 => "R_MIPS_JALR",
        38 => "R_MIPS_TLS_DTPMOD32",
        39 => "R_MIPS_TLS_DTPREL32",
        42 => "R_MIPS_TLS_GD",
        43 => "R_MIPS_TLS_LDM",
        44 => "R_MIPS_TLS_DTPREL_HI16",
        45 => "R_MIPS_TLS_DTPREL_LO16",
        46 => "R_MIPS_TLS_GOTTPREL",
        47 => "R_MIPS_TLS_TPREL32",
        49 => "R_MIPS_TLS_TPREL_HI16",
        50 => "R_MIPS_TLS_TPREL_LO16",
        60 => "R_MIPS_PC21_S2",
        61 => "R_MIPS_PC26_S2",
        62 => "R_MIPS_PC18_S3",
        63 => "R_MIPS_PC19_S2",
        64 => "R_MIPS_PCHI16",
        65 => "R_MIPS_PCLO16",
        126 => "R_MIPS_COPY",
        127 => "R_MIPS_JUMP_SLOT",
        248 => "R_MIPS_PC32",
        _ => return format!("relocation type {r_type}"),
    };
    name.to_string()
}

/// Classifies a relocation type.
pub(crate) fn classify(r_type: u32) -> Result<Action, Refusal> {
    const PIC: &str = "; the object uses the GOT: rebuild with `-fno-pic -mno-abicalls` \
                       (llc: `-relocation-model=static -mattr=+noabicalls`)";
    const TLS: &str = "; thread-local storage is not supported (use per-thread stack data)";
    Ok(match r_type {
        0 | 37 => Action::Skip,
        2 => Action::Abs32,
        4 => Action::Jump26,
        5 => Action::Hi16,
        6 => Action::Lo16,
        10 => Action::PcField { bits: 16, shift: 2 },
        60 => Action::PcField { bits: 21, shift: 2 },
        61 => Action::PcField { bits: 26, shift: 2 },
        62 => Action::PcField { bits: 18, shift: 3 },
        63 => Action::PcField { bits: 19, shift: 2 },
        64 => Action::PcHi16,
        65 => Action::PcLo16,
        248 => Action::Pc32,
        7 | 8 | 12 => return Err(Refusal::GpRelative),
        9 | 11 | 19..=23 | 30 | 31 => return Err(Refusal::Unsupported(PIC)),
        38..=50 => return Err(Refusal::Unsupported(TLS)),
        _ => return Err(Refusal::Unsupported("")),
    })
}

fn sext(value: u32, bits: u32) -> i64 {
    let shift = 64 - bits;
    ((i64::from(value)) << shift) >> shift
}

/// The implicit addend stored in `word` for a relocation of this kind (for `Hi16`/`PcHi16`
/// only the high part; add the paired low part with [`lo_addend`]).
pub(crate) fn implicit_addend(action: Action, word: u32) -> i64 {
    match action {
        Action::Skip => 0,
        Action::Abs32 | Action::Pc32 => i64::from(word as i32),
        Action::Jump26 => sext((word & 0x03FF_FFFF) << 2, 28),
        Action::Hi16 | Action::PcHi16 => i64::from(((word & 0xFFFF) << 16) as i32),
        Action::Lo16 | Action::PcLo16 => lo_addend(word),
        Action::PcField { bits, shift } => sext((word & ((1 << bits) - 1)) << shift, bits + shift),
    }
}

/// The addend of a `R_MIPS_LO16`/`R_MIPS_PCLO16` word: its sign-extended immediate.
pub(crate) fn lo_addend(word: u32) -> i64 {
    sext(word & 0xFFFF, 16)
}

/// A value that does not fit a relocation field.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Overflow {
    pub value: i64,
    pub reason: String,
}

/// Patches `word` for `action`, given `sa` = S + A (with AHL for the high halves) and the
/// address `p` of the word.
pub(crate) fn apply(action: Action, word: u32, sa: i64, p: u32) -> Result<u32, Overflow> {
    let p = i64::from(p);
    Ok(match action {
        Action::Skip => word,
        Action::Abs32 => sa as u32,
        Action::Pc32 => (sa - p) as u32,
        Action::Jump26 => {
            let target = sa as u32;
            let region = (p as u32).wrapping_add(4) & 0xF000_0000;
            if target & 3 != 0 {
                return Err(Overflow {
                    value: sa,
                    reason: "is not 4-byte aligned".into(),
                });
            }
            if target & 0xF000_0000 != region {
                return Err(Overflow {
                    value: sa,
                    reason: format!("lies outside the 256 MiB jump region at {region:#010x}"),
                });
            }
            (word & 0xFC00_0000) | ((target >> 2) & 0x03FF_FFFF)
        }
        Action::Hi16 => (word & 0xFFFF_0000) | ((((sa + 0x8000) >> 16) as u32) & 0xFFFF),
        Action::Lo16 => (word & 0xFFFF_0000) | (sa as u32 & 0xFFFF),
        Action::PcHi16 => (word & 0xFFFF_0000) | ((((sa - p + 0x8000) >> 16) as u32) & 0xFFFF),
        Action::PcLo16 => (word & 0xFFFF_0000) | ((sa - p) as u32 & 0xFFFF),
        Action::PcField { bits, shift } => {
            let v = sa - p;
            if v & ((1 << shift) - 1) != 0 {
                return Err(Overflow {
                    value: v,
                    reason: format!("is not {}-byte aligned", 1 << shift),
                });
            }
            let range = bits + shift;
            let min = -(1i64 << (range - 1));
            let max = (1i64 << (range - 1)) - 1;
            if v < min || v > max {
                return Err(Overflow {
                    value: v,
                    reason: format!("does not fit a signed {range}-bit PC-relative offset"),
                });
            }
            let mask = (1u32 << bits) - 1;
            (word & !mask) | (((v >> shift) as u32) & mask)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hi_lo_carry() {
        // lui/addiu of 0x1234_8000: hi must round up because lo is negative.
        let hi = apply(Action::Hi16, 0x3C04_0000, 0x1234_8000, 0).unwrap();
        let lo = apply(Action::Lo16, 0x2484_0000, 0x1234_8000, 0).unwrap();
        assert_eq!(hi & 0xFFFF, 0x1235);
        assert_eq!(lo & 0xFFFF, 0x8000);
    }

    #[test]
    fn pc16_range_and_alignment() {
        let f = Action::PcField { bits: 16, shift: 2 };
        assert_eq!(implicit_addend(f, 0x1000_FFFF), -4);
        assert!(apply(f, 0x1000_0000, 0x1_0000 + 0x2_0000, 0x1_0000).is_err());
        assert!(apply(f, 0x1000_0000, 0x1_0002, 0x1_0000).is_err());
        let w = apply(f, 0x1000_0000, 0x1_0000 - 0x2_0000, 0x1_0000).unwrap();
        assert_eq!(w & 0xFFFF, 0x8000);
    }

    #[test]
    fn jump26_region() {
        assert!(apply(Action::Jump26, 0x0C00_0000, 0x1000_0000, 0x0FFF_FFF0).is_err());
        let w = apply(Action::Jump26, 0x0C00_0000, 0x0010_0040, 0x0010_0000).unwrap();
        assert_eq!(w, 0x0C00_0000 | (0x0010_0040 >> 2));
    }
}
