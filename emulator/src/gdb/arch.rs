//! The register set gdb-multiarch expects for a little-endian MIPS32r6 target.
//!
//! Raw register numbers as in GDB's MIPS port: `r0..r31` (0-31), `status` (32), `lo`
//! (33), `hi` (34), `badvaddr` (35), `cause` (36), `pc` (37), `f0..f31` (38-69), `fcsr`
//! (70), `fir` (71); all 32 bits wide (FPU registers carry the low, single-precision
//! word). MIPS32r6 has no HI/LO: they read as 0 and writes are ignored. A target
//! description names the architecture `mips:isa32r6` and these features.

use gdbstub::arch::{Arch, RegId, Registers};

/// Number of raw registers in the `g` packet.
pub const NUM_REGS: usize = 72;

/// Raw register values in GDB order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MipsRegs {
    /// Raw registers 0..72.
    pub r: [u32; NUM_REGS],
}

impl Default for MipsRegs {
    fn default() -> Self {
        MipsRegs { r: [0; NUM_REGS] }
    }
}

/// Index of `pc` in [`MipsRegs::r`].
pub const PC: usize = 37;
/// Index of `f0`.
pub const F0: usize = 38;
/// Index of `fcsr`.
pub const FCSR: usize = 70;
/// Index of `fir`.
pub const FIR: usize = 71;
/// Index of `cause`.
pub const CAUSE: usize = 36;
/// Index of `badvaddr`.
pub const BADVADDR: usize = 35;

impl Registers for MipsRegs {
    type ProgramCounter = u32;

    fn pc(&self) -> u32 {
        self.r[PC]
    }

    fn gdb_serialize(&self, mut write_byte: impl FnMut(Option<u8>)) {
        for v in self.r {
            for b in v.to_le_bytes() {
                write_byte(Some(b));
            }
        }
    }

    fn gdb_deserialize(&mut self, bytes: &[u8]) -> Result<(), ()> {
        if bytes.len() != NUM_REGS * 4 {
            return Err(());
        }
        for (r, c) in self.r.iter_mut().zip(bytes.chunks_exact(4)) {
            *r = u32::from_le_bytes([c[0], c[1], c[2], c[3]]);
        }
        Ok(())
    }
}

/// A raw register number (single-register access is not used; `g`/`G` carry all).
#[derive(Clone, Copy, Debug)]
pub struct MipsRegId(pub usize);

impl RegId for MipsRegId {
    fn from_raw_id(id: usize) -> Option<(Self, Option<std::num::NonZeroUsize>)> {
        (id < NUM_REGS).then(|| (MipsRegId(id), std::num::NonZeroUsize::new(4)))
    }
}

/// The TRaX MIPS32r6 little-endian architecture for `gdbstub`.
#[derive(Debug)]
pub enum TraxMips {}

impl Arch for TraxMips {
    type Usize = u32;
    type Registers = MipsRegs;
    type BreakpointKind = usize;
    type RegId = MipsRegId;

    fn target_description_xml() -> Option<&'static str> {
        Some(TARGET_XML)
    }
}

/// The target description sent to GDB.
pub const TARGET_XML: &str = concat!(
    r#"<?xml version="1.0"?><!DOCTYPE target SYSTEM "gdb-target.dtd"><target version="1.0">"#,
    r#"<architecture>mips:isa32r6</architecture>"#,
    r#"<feature name="org.gnu.gdb.mips.cpu">"#,
    r#"<reg name="r0" bitsize="32" regnum="0"/><reg name="r1" bitsize="32"/><reg name="r2" bitsize="32"/><reg name="r3" bitsize="32"/>"#,
    r#"<reg name="r4" bitsize="32"/><reg name="r5" bitsize="32"/><reg name="r6" bitsize="32"/><reg name="r7" bitsize="32"/>"#,
    r#"<reg name="r8" bitsize="32"/><reg name="r9" bitsize="32"/><reg name="r10" bitsize="32"/><reg name="r11" bitsize="32"/>"#,
    r#"<reg name="r12" bitsize="32"/><reg name="r13" bitsize="32"/><reg name="r14" bitsize="32"/><reg name="r15" bitsize="32"/>"#,
    r#"<reg name="r16" bitsize="32"/><reg name="r17" bitsize="32"/><reg name="r18" bitsize="32"/><reg name="r19" bitsize="32"/>"#,
    r#"<reg name="r20" bitsize="32"/><reg name="r21" bitsize="32"/><reg name="r22" bitsize="32"/><reg name="r23" bitsize="32"/>"#,
    r#"<reg name="r24" bitsize="32"/><reg name="r25" bitsize="32"/><reg name="r26" bitsize="32"/><reg name="r27" bitsize="32"/>"#,
    r#"<reg name="r28" bitsize="32"/><reg name="r29" bitsize="32"/><reg name="r30" bitsize="32"/><reg name="r31" bitsize="32"/>"#,
    r#"<reg name="lo" bitsize="32" regnum="33"/><reg name="hi" bitsize="32" regnum="34"/>"#,
    r#"<reg name="pc" bitsize="32" regnum="37"/>"#,
    r#"</feature><feature name="org.gnu.gdb.mips.cp0">"#,
    r#"<reg name="status" bitsize="32" regnum="32"/><reg name="badvaddr" bitsize="32" regnum="35"/>"#,
    r#"<reg name="cause" bitsize="32" regnum="36"/>"#,
    r#"</feature><feature name="org.gnu.gdb.mips.fpu">"#,
    r#"<reg name="f0" bitsize="32" type="ieee_single" regnum="38"/><reg name="f1" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f2" bitsize="32" type="ieee_single"/><reg name="f3" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f4" bitsize="32" type="ieee_single"/><reg name="f5" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f6" bitsize="32" type="ieee_single"/><reg name="f7" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f8" bitsize="32" type="ieee_single"/><reg name="f9" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f10" bitsize="32" type="ieee_single"/><reg name="f11" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f12" bitsize="32" type="ieee_single"/><reg name="f13" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f14" bitsize="32" type="ieee_single"/><reg name="f15" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f16" bitsize="32" type="ieee_single"/><reg name="f17" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f18" bitsize="32" type="ieee_single"/><reg name="f19" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f20" bitsize="32" type="ieee_single"/><reg name="f21" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f22" bitsize="32" type="ieee_single"/><reg name="f23" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f24" bitsize="32" type="ieee_single"/><reg name="f25" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f26" bitsize="32" type="ieee_single"/><reg name="f27" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f28" bitsize="32" type="ieee_single"/><reg name="f29" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="f30" bitsize="32" type="ieee_single"/><reg name="f31" bitsize="32" type="ieee_single"/>"#,
    r#"<reg name="fcsr" bitsize="32" group="float"/><reg name="fir" bitsize="32" group="float"/>"#,
    r#"</feature></target>"#
);
