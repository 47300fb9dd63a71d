//! Disassembly of [`Inst`] in LLVM's MIPS syntax (as printed by `llvm-mc --disassemble`).
//!
//! Branch operands are printed like LLVM does: the byte offset from the branch itself
//! (`offset field * 4 + 4`); `j`/`jal` print the 28-bit region offset.

use std::fmt;

use crate::decode::{Conv, Inst, F2, F3};
use trax_runtime::isa::{self, OperandKind};

const GPR_NAMES: [&str; 32] = [
    "$zero", "$1", "$2", "$3", "$4", "$5", "$6", "$7", "$8", "$9", "$10", "$11", "$12", "$13",
    "$14", "$15", "$16", "$17", "$18", "$19", "$20", "$21", "$22", "$23", "$24", "$25", "$26",
    "$27", "$gp", "$sp", "$fp", "$ra",
];

/// The assembler name of general-purpose register `r` (`$zero`, `$2`, `$sp`, ...).
pub fn gpr_name(r: u8) -> &'static str {
    GPR_NAMES[(r & 31) as usize]
}

struct G(u8);
impl fmt::Display for G {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(gpr_name(self.0))
    }
}
struct Fr(u8);
impl fmt::Display for Fr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "$f{}", self.0)
    }
}

const CMP_NAMES: [&str; 32] = [
    "af", "un", "eq", "ueq", "lt", "ult", "le", "ule", "saf", "sun", "seq", "sueq", "slt", "sult",
    "sle", "sule", "?", "or", "une", "ne", "?", "?", "?", "?", "?", "sor", "sune", "sne", "?", "?",
    "?", "?",
];

impl Conv {
    /// Mnemonic, e.g. `cvt.s.w`.
    pub fn mnemonic(self) -> &'static str {
        use Conv::*;
        match self {
            CvtSD => "cvt.s.d",
            CvtSW => "cvt.s.w",
            CvtSL => "cvt.s.l",
            CvtDS => "cvt.d.s",
            CvtDW => "cvt.d.w",
            CvtDL => "cvt.d.l",
            CvtWS => "cvt.w.s",
            CvtWD => "cvt.w.d",
            CvtLS => "cvt.l.s",
            CvtLD => "cvt.l.d",
            RoundWS => "round.w.s",
            RoundWD => "round.w.d",
            RoundLS => "round.l.s",
            RoundLD => "round.l.d",
            TruncWS => "trunc.w.s",
            TruncWD => "trunc.w.d",
            TruncLS => "trunc.l.s",
            TruncLD => "trunc.l.d",
            CeilWS => "ceil.w.s",
            CeilWD => "ceil.w.d",
            CeilLS => "ceil.l.s",
            CeilLD => "ceil.l.d",
            FloorWS => "floor.w.s",
            FloorWD => "floor.w.d",
            FloorLS => "floor.l.s",
            FloorLD => "floor.l.d",
        }
    }
}

fn f3(f: &mut fmt::Formatter<'_>, m: &str, x: F3) -> fmt::Result {
    write!(f, "{m}\t{}, {}, {}", Fr(x.fd), Fr(x.fs), Fr(x.ft))
}
fn f2(f: &mut fmt::Formatter<'_>, m: &str, x: F2) -> fmt::Result {
    write!(f, "{m}\t{}, {}", Fr(x.fd), Fr(x.fs))
}

impl fmt::Display for Inst {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use Inst::*;
        macro_rules! r3 {
            ($m:literal, $a:expr, $b:expr, $c:expr) => {
                write!(f, concat!($m, "\t{}, {}, {}"), G($a), G($b), G($c))
            };
        }
        macro_rules! r2 {
            ($m:literal, $a:expr, $b:expr) => {
                write!(f, concat!($m, "\t{}, {}"), G($a), G($b))
            };
        }
        macro_rules! mem {
            ($m:literal, $r:expr, $base:expr, $off:expr) => {
                write!(f, concat!($m, "\t{}, {}({})"), G($r), $off, G($base))
            };
        }
        macro_rules! fmem {
            ($m:literal, $r:expr, $base:expr, $off:expr) => {
                write!(f, concat!($m, "\t{}, {}({})"), Fr($r), $off, G($base))
            };
        }
        // PC-relative branches print `Inst::branch_offset` (from the branch itself).
        let boff = self.branch_offset().unwrap_or_default();
        macro_rules! br2 {
            ($m:literal, $a:expr, $b:expr) => {
                write!(f, concat!($m, "\t{}, {}, {}"), G($a), G($b), boff)
            };
        }
        macro_rules! br1 {
            ($m:literal, $a:expr) => {
                write!(f, concat!($m, "\t{}, {}"), G($a), boff)
            };
        }
        macro_rules! br0 {
            ($m:literal) => {
                write!(f, concat!($m, "\t{}"), boff)
            };
        }
        match *self {
            Add { rd, rs, rt } => r3!("add", rd, rs, rt),
            Addu { rd, rs, rt: 0 } => r2!("move", rd, rs),
            Addu { rd, rs, rt } => r3!("addu", rd, rs, rt),
            Sub { rd, rs: 0, rt } => r2!("neg", rd, rt),
            Sub { rd, rs, rt } => r3!("sub", rd, rs, rt),
            Subu { rd, rs: 0, rt } => r2!("negu", rd, rt),
            Subu { rd, rs, rt } => r3!("subu", rd, rs, rt),
            And { rd, rs, rt } => r3!("and", rd, rs, rt),
            Or { rd, rs, rt: 0 } => r2!("move", rd, rs),
            Or { rd, rs, rt } => r3!("or", rd, rs, rt),
            Xor { rd, rs, rt } => r3!("xor", rd, rs, rt),
            Nor { rd, rs, rt: 0 } => r2!("not", rd, rs),
            Nor { rd, rs, rt } => r3!("nor", rd, rs, rt),
            Slt { rd, rs, rt } => r3!("slt", rd, rs, rt),
            Sltu { rd, rs, rt } => r3!("sltu", rd, rs, rt),
            Mul { rd, rs, rt } => r3!("mul", rd, rs, rt),
            Muh { rd, rs, rt } => r3!("muh", rd, rs, rt),
            Mulu { rd, rs, rt } => r3!("mulu", rd, rs, rt),
            Muhu { rd, rs, rt } => r3!("muhu", rd, rs, rt),
            Div { rd, rs, rt } => r3!("div", rd, rs, rt),
            Mod { rd, rs, rt } => r3!("mod", rd, rs, rt),
            Divu { rd, rs, rt } => r3!("divu", rd, rs, rt),
            Modu { rd, rs, rt } => r3!("modu", rd, rs, rt),
            Seleqz { rd, rs, rt } => r3!("seleqz", rd, rs, rt),
            Selnez { rd, rs, rt } => r3!("selnez", rd, rs, rt),
            Sllv { rd, rt, rs } => r3!("sllv", rd, rt, rs),
            Srlv { rd, rt, rs } => r3!("srlv", rd, rt, rs),
            Srav { rd, rt, rs } => r3!("srav", rd, rt, rs),
            Rotrv { rd, rt, rs } => r3!("rotrv", rd, rt, rs),
            Sll {
                rd: 0,
                rt: 0,
                sa: 0,
            } => f.write_str("nop"),
            Sll {
                rd: 0,
                rt: 0,
                sa: 1,
            } => f.write_str("ssnop"),
            Sll {
                rd: 0,
                rt: 0,
                sa: 3,
            } => f.write_str("ehb"),
            Sll {
                rd: 0,
                rt: 0,
                sa: 5,
            } => f.write_str("pause"),
            Sll { rd, rt, sa } => write!(f, "sll\t{}, {}, {sa}", G(rd), G(rt)),
            Srl { rd, rt, sa } => write!(f, "srl\t{}, {}, {sa}", G(rd), G(rt)),
            Sra { rd, rt, sa } => write!(f, "sra\t{}, {}, {sa}", G(rd), G(rt)),
            Rotr { rd, rt, sa } => write!(f, "rotr\t{}, {}, {sa}", G(rd), G(rt)),
            Lsa { rd, rs, rt, sa } => write!(f, "lsa\t{}, {}, {}, {sa}", G(rd), G(rs), G(rt)),
            Clz { rd, rs } => r2!("clz", rd, rs),
            Clo { rd, rs } => r2!("clo", rd, rs),
            Addiu { rt, rs, imm } => write!(f, "addiu\t{}, {}, {imm}", G(rt), G(rs)),
            Slti { rt, rs, imm } => write!(f, "slti\t{}, {}, {imm}", G(rt), G(rs)),
            Sltiu { rt, rs, imm } => write!(f, "sltiu\t{}, {}, {imm}", G(rt), G(rs)),
            Andi { rt, rs, imm } => write!(f, "andi\t{}, {}, {imm}", G(rt), G(rs)),
            Ori { rt, rs, imm } => write!(f, "ori\t{}, {}, {imm}", G(rt), G(rs)),
            Xori { rt, rs, imm } => write!(f, "xori\t{}, {}, {imm}", G(rt), G(rs)),
            Aui { rt, rs, imm } => write!(f, "aui\t{}, {}, {imm}", G(rt), G(rs)),
            Align { rd, rs, rt, bp } => write!(f, "align\t{}, {}, {}, {bp}", G(rd), G(rs), G(rt)),
            Bitswap { rd, rt } => r2!("bitswap", rd, rt),
            Wsbh { rd, rt } => r2!("wsbh", rd, rt),
            Seb { rd, rt } => r2!("seb", rd, rt),
            Seh { rd, rt } => r2!("seh", rd, rt),
            Ext { rt, rs, pos, size } => write!(f, "ext\t{}, {}, {pos}, {size}", G(rt), G(rs)),
            Ins { rt, rs, pos, size } => write!(f, "ins\t{}, {}, {pos}, {size}", G(rt), G(rs)),
            Addiupc { rs, off } => write!(f, "lapc\t{}, {off}", G(rs)),
            Lwpc { rs, off } => write!(f, "lwpc\t{}, {off}", G(rs)),
            Auipc { rs, imm } => write!(f, "auipc\t{}, {}", G(rs), imm as i16),
            Aluipc { rs, imm } => write!(f, "aluipc\t{}, {}", G(rs), imm as i16),
            Lb { rt, base, off } => mem!("lb", rt, base, off),
            Lbu { rt, base, off } => mem!("lbu", rt, base, off),
            Lh { rt, base, off } => mem!("lh", rt, base, off),
            Lhu { rt, base, off } => mem!("lhu", rt, base, off),
            Lw { rt, base, off } => mem!("lw", rt, base, off),
            Sb { rt, base, off } => mem!("sb", rt, base, off),
            Sh { rt, base, off } => mem!("sh", rt, base, off),
            Sw { rt, base, off } => mem!("sw", rt, base, off),
            Ll { rt, base, off } => mem!("ll", rt, base, off),
            Sc { rt, base, off } => mem!("sc", rt, base, off),
            Lwc1 { ft, base, off } => fmem!("lwc1", ft, base, off),
            Swc1 { ft, base, off } => fmem!("swc1", ft, base, off),
            Ldc1 { ft, base, off } => fmem!("ldc1", ft, base, off),
            Sdc1 { ft, base, off } => fmem!("sdc1", ft, base, off),
            Pref { hint, base, off } => write!(f, "pref\t{hint}, {off}({})", G(base)),
            Synci { base, off } => write!(f, "synci\t{off}({})", G(base)),
            Sigrie { code } => write!(f, "sigrie\t{code}"),
            Teq { rs, rt, code } => write!(f, "teq\t{}, {}, {code}", G(rs), G(rt)),
            Tne { rs, rt, code } => write!(f, "tne\t{}, {}, {code}", G(rs), G(rt)),
            Tge { rs, rt, code } => write!(f, "tge\t{}, {}, {code}", G(rs), G(rt)),
            Tgeu { rs, rt, code } => write!(f, "tgeu\t{}, {}, {code}", G(rs), G(rt)),
            Tlt { rs, rt, code } => write!(f, "tlt\t{}, {}, {code}", G(rs), G(rt)),
            Tltu { rs, rt, code } => write!(f, "tltu\t{}, {}, {code}", G(rs), G(rt)),
            Syscall { code: 0 } => f.write_str("syscall"),
            Syscall { code } => write!(f, "syscall\t{code}"),
            Break { code: 0 } => f.write_str("break"),
            Break { code } => write!(f, "break\t{}, {}", code >> 10, code & 0x3FF),
            Sdbbp { code: 0 } => f.write_str("sdbbp"),
            Sdbbp { code } => write!(f, "sdbbp\t{code}"),
            Sync { stype: 0 } => f.write_str("sync"),
            Sync { stype } => write!(f, "sync {stype}"),
            Rdhwr { rt, rd, sel: 0 } => write!(f, "rdhwr\t{}, ${rd}", G(rt)),
            Rdhwr { rt, rd, sel } => write!(f, "rdhwr\t{}, ${rd}, {sel}", G(rt)),
            Beq { rs: 0, rt: 0, .. } => br0!("b"),
            Beq { rs, rt: 0, .. } => br1!("beqz", rs),
            Beq { rs, rt, .. } => br2!("beq", rs, rt),
            Bne { rs, rt: 0, .. } => br1!("bnez", rs),
            Bne { rs, rt, .. } => br2!("bne", rs, rt),
            Blez { rs, .. } => br1!("blez", rs),
            Bgtz { rs, .. } => br1!("bgtz", rs),
            Bltz { rs, .. } => br1!("bltz", rs),
            Bgez { rs, .. } => br1!("bgez", rs),
            Bal { .. } => br0!("bal"),
            J { target } => write!(f, "j\t{target}"),
            Jal { target } => write!(f, "jal\t{target}"),
            Jalr {
                rd: 0,
                rs,
                hb: false,
            } => write!(f, "jr\t{}", G(rs)),
            Jalr {
                rd: 0,
                rs,
                hb: true,
            } => write!(f, "jr.hb\t{}", G(rs)),
            Jalr {
                rd: 31,
                rs,
                hb: false,
            } => write!(f, "jalr\t{}", G(rs)),
            Jalr {
                rd: 31,
                rs,
                hb: true,
            } => write!(f, "jalr.hb\t{}", G(rs)),
            Jalr { rd, rs, hb } => {
                write!(
                    f,
                    "jalr{}\t{}, {}",
                    if hb { ".hb" } else { "" },
                    G(rd),
                    G(rs)
                )
            }
            Bc1eqz { ft, .. } => write!(f, "bc1eqz {}, {boff}", Fr(ft)),
            Bc1nez { ft, .. } => write!(f, "bc1nez {}, {boff}", Fr(ft)),
            Bc { .. } => br0!("bc"),
            Balc { .. } => br0!("balc"),
            Beqc { rs, rt, .. } => br2!("beqc", rs, rt),
            Bnec { rs, rt, .. } => br2!("bnec", rs, rt),
            Bltc { rs, rt, .. } => br2!("bltc", rs, rt),
            Bgec { rs, rt, .. } => br2!("bgec", rs, rt),
            Bltuc { rs, rt, .. } => br2!("bltuc", rs, rt),
            Bgeuc { rs, rt, .. } => br2!("bgeuc", rs, rt),
            Bovc { rs, rt, .. } => br2!("bovc", rs, rt),
            Bnvc { rs, rt, .. } => br2!("bnvc", rs, rt),
            Beqzc { rs, .. } => br1!("beqzc", rs),
            Bnezc { rs, .. } => br1!("bnezc", rs),
            Blezc { rt, .. } => br1!("blezc", rt),
            Bgezc { rt, .. } => br1!("bgezc", rt),
            Bgtzc { rt, .. } => br1!("bgtzc", rt),
            Bltzc { rt, .. } => br1!("bltzc", rt),
            Blezalc { rt, .. } => br1!("blezalc", rt),
            Bgezalc { rt, .. } => br1!("bgezalc", rt),
            Bgtzalc { rt, .. } => br1!("bgtzalc", rt),
            Bltzalc { rt, .. } => br1!("bltzalc", rt),
            Beqzalc { rt, .. } => br1!("beqzalc", rt),
            Bnezalc { rt, .. } => br1!("bnezalc", rt),
            // LLVM prints the jic/jialc offset unsigned.
            Jic { rt, off } => write!(f, "jic\t{}, {}", G(rt), off as u16),
            Jialc { rt, off } => write!(f, "jialc\t{}, {}", G(rt), off as u16),
            AddS(x) => f3(f, "add.s", x),
            AddD(x) => f3(f, "add.d", x),
            SubS(x) => f3(f, "sub.s", x),
            SubD(x) => f3(f, "sub.d", x),
            MulS(x) => f3(f, "mul.s", x),
            MulD(x) => f3(f, "mul.d", x),
            DivS(x) => f3(f, "div.s", x),
            DivD(x) => f3(f, "div.d", x),
            SqrtS(x) => f2(f, "sqrt.s", x),
            SqrtD(x) => f2(f, "sqrt.d", x),
            AbsS(x) => f2(f, "abs.s", x),
            AbsD(x) => f2(f, "abs.d", x),
            MovS(x) => f2(f, "mov.s", x),
            MovD(x) => f2(f, "mov.d", x),
            NegS(x) => f2(f, "neg.s", x),
            NegD(x) => f2(f, "neg.d", x),
            RecipS(x) => f2(f, "recip.s", x),
            RecipD(x) => f2(f, "recip.d", x),
            RsqrtS(x) => f2(f, "rsqrt.s", x),
            RsqrtD(x) => f2(f, "rsqrt.d", x),
            RintS(x) => f2(f, "rint.s", x),
            RintD(x) => f2(f, "rint.d", x),
            ClassS(x) => f2(f, "class.s", x),
            ClassD(x) => f2(f, "class.d", x),
            MaddfS(x) => f3(f, "maddf.s", x),
            MaddfD(x) => f3(f, "maddf.d", x),
            MsubfS(x) => f3(f, "msubf.s", x),
            MsubfD(x) => f3(f, "msubf.d", x),
            SelS(x) => f3(f, "sel.s", x),
            SelD(x) => f3(f, "sel.d", x),
            SeleqzS(x) => f3(f, "seleqz.s", x),
            SeleqzD(x) => f3(f, "seleqz.d", x),
            SelnezS(x) => f3(f, "selnez.s", x),
            SelnezD(x) => f3(f, "selnez.d", x),
            MinS(x) => f3(f, "min.s", x),
            MinD(x) => f3(f, "min.d", x),
            MaxS(x) => f3(f, "max.s", x),
            MaxD(x) => f3(f, "max.d", x),
            MinaS(x) => f3(f, "mina.s", x),
            MinaD(x) => f3(f, "mina.d", x),
            MaxaS(x) => f3(f, "maxa.s", x),
            MaxaD(x) => f3(f, "maxa.d", x),
            CmpS { cond, f: x } => {
                let m = format!("cmp.{}.s", CMP_NAMES[cond as usize & 31]);
                f3(f, &m, x)
            }
            CmpD { cond, f: x } => {
                let m = format!("cmp.{}.d", CMP_NAMES[cond as usize & 31]);
                f3(f, &m, x)
            }
            Cvt { op, f: x } => f2(f, op.mnemonic(), x),
            Mfc1 { rt, fs } => write!(f, "mfc1\t{}, {}", G(rt), Fr(fs)),
            Mtc1 { rt, fs } => write!(f, "mtc1\t{}, {}", G(rt), Fr(fs)),
            Mfhc1 { rt, fs } => write!(f, "mfhc1\t{}, {}", G(rt), Fr(fs)),
            Mthc1 { rt, fs } => write!(f, "mthc1\t{}, {}", G(rt), Fr(fs)),
            Cfc1 { rt, fs } => write!(f, "cfc1\t{}, ${fs}", G(rt)),
            Ctc1 { rt, fs } => write!(f, "ctc1\t{}, ${fs}", G(rt)),
            Mfc2 { rt, rd, sel } => write!(f, "mfc2\t{}, ${rd}, {sel}", G(rt)),
            Mtc2 { rt, rd, sel } => write!(f, "mtc2\t{}, ${rd}, {sel}", G(rt)),
            Trax { op, rd, rs, rt, sa } => {
                let row = isa::instr(op);
                f.write_str(row.mnemonic)?;
                for (i, o) in row.operands.iter().enumerate() {
                    f.write_str(if i == 0 { "\t" } else { ", " })?;
                    let v = match o.field {
                        isa::Field::Rs => rs,
                        isa::Field::Rt => rt,
                        isa::Field::Rd => rd,
                        isa::Field::Sa => sa,
                    };
                    match o.kind {
                        OperandKind::GprUse | OperandKind::GprDef => write!(f, "{}", G(v))?,
                        OperandKind::FprUse | OperandKind::FprDef => write!(f, "{}", Fr(v))?,
                        OperandKind::Imm5 => write!(f, "{v}")?,
                    }
                }
                Ok(())
            }
            Msa(m) => write!(f, "{m}"),
            Reserved(w) => write!(f, ".word\t{w:#010x}"),
        }
    }
}
