//! Disassembly of MSA instructions in LLVM's syntax.

use std::fmt;

use super::{Form, MsaInst};

/// A GPR as LLVM's MIPS printer names it (`$zero`, `$sp`, `$4`, ...).
struct Gpr(u8);

impl fmt::Display for Gpr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            0 => f.write_str("$zero"),
            28 => f.write_str("$gp"),
            29 => f.write_str("$sp"),
            30 => f.write_str("$fp"),
            31 => f.write_str("$ra"),
            n => write!(f, "${n}"),
        }
    }
}

impl fmt::Display for MsaInst {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (wd, ws, wt, imm) = (self.wd, self.ws, self.wt, self.imm);
        let name = self.op.name();
        let sfx = self.df.suffix();
        match self.op.form() {
            Form::R3 => write!(f, "{name}.{sfx} $w{wd}, $w{ws}, $w{wt}"),
            Form::R3Gpr => write!(f, "{name}.{sfx} $w{wd}, $w{ws}[{}]", Gpr(wt)),
            Form::Imm => write!(f, "{name}.{sfx} $w{wd}, $w{ws}, {imm}"),
            Form::Ldi => write!(f, "{name}.{sfx} $w{wd}, {imm}"),
            Form::Elm => write!(f, "{name}.{sfx} $w{wd}, $w{ws}[{imm}]"),
            Form::Copy => write!(f, "{name}.{sfx} {}, $w{ws}[{imm}]", Gpr(wd)),
            Form::Insert => write!(f, "{name}.{sfx} $w{wd}[{imm}], {}", Gpr(ws)),
            Form::Insve => write!(f, "{name}.{sfx} $w{wd}[{imm}], $w{ws}[0]"),
            Form::Ctc => write!(f, "{name} ${wd}, {}", Gpr(ws)),
            Form::Cfc => write!(f, "{name} {}, ${ws}", Gpr(wd)),
            Form::R2 => write!(f, "{name}.{sfx} $w{wd}, $w{ws}"),
            Form::Fill => write!(f, "{name}.{sfx} $w{wd}, {}", Gpr(ws)),
            Form::Mem => write!(f, "{name}.{sfx} $w{wd}, {imm}({})", Gpr(ws)),
            // LLVM prints the branch offset relative to the branch itself.
            Form::Branch => {
                let off = self.branch_offset().unwrap_or_default();
                write!(f, "{name}.{sfx} $w{wt}, {off}")
            }
        }
    }
}
