//! Target compatibility: merging ELF `e_flags` and `.MIPS.abiflags` of the inputs.

use object::elf;

use super::input::InObject;
use super::LinkError;

const ARCH_MASK: u32 = elf::EF_MIPS_ARCH;
const ABI_MASK: u32 = elf::EF_MIPS_ABI;

fn incompatible(file: &str, detail: String) -> LinkError {
    LinkError::Incompatible {
        file: file.to_string(),
        detail,
    }
}

/// Checks every input is MIPS32r6 o32 with one NaN encoding and returns the output `e_flags`.
pub(crate) fn merge_e_flags(objs: &[InObject]) -> Result<u32, LinkError> {
    let mut out = elf::EF_MIPS_ARCH_32R6.0 | elf::EF_MIPS_ABI_O32.0;
    let mut nan: Option<(bool, &str)> = None;
    for obj in objs {
        let f = obj.e_flags;
        if f & ARCH_MASK != elf::EF_MIPS_ARCH_32R6.0 {
            return Err(incompatible(
                &obj.name,
                format!(
                    "ISA field of e_flags is {:#x}; TRaX runs MIPS32 Release 6 code \
                     (compile with -mcpu=mips32r6)",
                    f & ARCH_MASK
                ),
            ));
        }
        let abi = f & ABI_MASK;
        if abi != 0 && abi != elf::EF_MIPS_ABI_O32.0 || f & elf::EF_MIPS_ABI2.0 != 0 {
            return Err(incompatible(
                &obj.name,
                format!("ABI is not o32 (e_flags {f:#x})"),
            ));
        }
        let n = f & elf::EF_MIPS_NAN2008.0 != 0;
        match nan {
            None => nan = Some((n, &obj.name)),
            Some((m, first)) if m != n => {
                return Err(incompatible(
                    &obj.name,
                    format!("NaN encoding (-mnan=2008) differs from `{first}`"),
                ))
            }
            _ => {}
        }
        out |= f & (elf::EF_MIPS_NOREORDER.0 | elf::EF_MIPS_NAN2008.0 | elf::EF_MIPS_FP64.0);
    }
    Ok(out)
}

/// `Elf_MIPS_ABIFlags_v0`, the contents of `.MIPS.abiflags`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct AbiFlags {
    pub version: u16,
    pub isa_level: u8,
    pub isa_rev: u8,
    pub gpr_size: u8,
    pub cpr1_size: u8,
    pub cpr2_size: u8,
    pub fp_abi: u8,
    pub isa_ext: u32,
    pub ases: u32,
    pub flags1: u32,
    pub flags2: u32,
}

const FP_ANY: u8 = 0;
const FP_DOUBLE: u8 = 1;
const FP_XX: u8 = 5;
const FP_64: u8 = 6;
const FP_64A: u8 = 7;

impl AbiFlags {
    fn parse(file: &str, data: &[u8]) -> Result<AbiFlags, LinkError> {
        if data.len() < 24 {
            return Err(LinkError::Malformed {
                file: file.to_string(),
                detail: format!(".MIPS.abiflags is {} bytes, expected 24", data.len()),
            });
        }
        let w = |o: usize| u32::from_le_bytes([data[o], data[o + 1], data[o + 2], data[o + 3]]);
        Ok(AbiFlags {
            version: u16::from_le_bytes([data[0], data[1]]),
            isa_level: data[2],
            isa_rev: data[3],
            gpr_size: data[4],
            cpr1_size: data[5],
            cpr2_size: data[6],
            fp_abi: data[7],
            isa_ext: w(8),
            ases: w(12),
            flags1: w(16),
            flags2: w(20),
        })
    }

    /// The 24-byte section contents.
    pub fn bytes(&self) -> Vec<u8> {
        let mut v = Vec::with_capacity(24);
        v.extend_from_slice(&self.version.to_le_bytes());
        v.extend_from_slice(&[
            self.isa_level,
            self.isa_rev,
            self.gpr_size,
            self.cpr1_size,
            self.cpr2_size,
            self.fp_abi,
        ]);
        for x in [self.isa_ext, self.ases, self.flags1, self.flags2] {
            v.extend_from_slice(&x.to_le_bytes());
        }
        v
    }
}

fn merge_fp_abi(old: u8, new: u8) -> Option<u8> {
    Some(match (old, new) {
        (a, b) if a == b => a,
        (FP_ANY, b) => b,
        (a, FP_ANY) => a,
        (FP_XX, b @ (FP_DOUBLE | FP_64 | FP_64A)) => b,
        (a @ (FP_DOUBLE | FP_64 | FP_64A), FP_XX) => a,
        (FP_64, FP_64A) | (FP_64A, FP_64) => FP_64,
        _ => return None,
    })
}

/// Merges the inputs' `.MIPS.abiflags` sections (`(file, section)` pairs).
pub(crate) fn merge_abiflags(
    objs: &[InObject],
    inputs: &[(usize, usize)],
) -> Result<Option<AbiFlags>, LinkError> {
    let mut merged: Option<(AbiFlags, &str)> = None;
    for &(f, s) in inputs {
        let name = &objs[f].name;
        let a = AbiFlags::parse(name, &objs[f].sections[s].data)?;
        merged = Some(match merged {
            None => (a, name),
            Some((m, first)) => {
                let fp_abi = merge_fp_abi(m.fp_abi, a.fp_abi).ok_or_else(|| {
                    incompatible(
                        name,
                        format!(
                            "floating-point ABI {} conflicts with {} of `{first}`",
                            a.fp_abi, m.fp_abi
                        ),
                    )
                })?;
                (
                    AbiFlags {
                        version: m.version.max(a.version),
                        isa_level: m.isa_level.max(a.isa_level),
                        isa_rev: m.isa_rev.max(a.isa_rev),
                        gpr_size: m.gpr_size.max(a.gpr_size),
                        cpr1_size: m.cpr1_size.max(a.cpr1_size),
                        cpr2_size: m.cpr2_size.max(a.cpr2_size),
                        fp_abi,
                        isa_ext: m.isa_ext.max(a.isa_ext),
                        ases: m.ases | a.ases,
                        flags1: m.flags1 | a.flags1,
                        flags2: m.flags2 | a.flags2,
                    },
                    first,
                )
            }
        });
    }
    Ok(merged.map(|m| m.0))
}
