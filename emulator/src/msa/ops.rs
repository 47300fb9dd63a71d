//! The MSA operation table: mnemonic, operand form and execution-unit class of each op.

use trax_runtime::isa::UnitClass;

/// Data format: element size (`.b .h .w .d`) or whole vector (`.v`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Df {
    /// 8-bit elements.
    B,
    /// 16-bit elements.
    H,
    /// 32-bit elements (or single-precision floats).
    W,
    /// 64-bit elements (or double-precision floats).
    D,
    /// The whole 128-bit vector.
    V,
}

impl Df {
    /// Element size in bits (128 for `.v`).
    pub fn bits(self) -> u32 {
        match self {
            Df::B => 8,
            Df::H => 16,
            Df::W => 32,
            Df::D => 64,
            Df::V => 128,
        }
    }

    /// Number of elements in a 128-bit vector.
    pub fn lanes(self) -> usize {
        (128 / self.bits()) as usize
    }

    /// Mnemonic suffix letter.
    pub fn suffix(self) -> &'static str {
        match self {
            Df::B => "b",
            Df::H => "h",
            Df::W => "w",
            Df::D => "d",
            Df::V => "v",
        }
    }

    /// The format with elements twice as wide (`.d` and `.v` map to themselves).
    pub fn half(self) -> Df {
        match self {
            Df::H => Df::B,
            Df::W => Df::H,
            Df::D => Df::W,
            other => other,
        }
    }
}

/// Operand layout of an instruction, for disassembly and for the executor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Form {
    /// `op.df $wd, $ws, $wt`.
    R3,
    /// `op.df $wd, $ws[$rt]` (GPR in the `wt` field).
    R3Gpr,
    /// `op.df $wd, $ws, imm`: 5-bit immediate (I5), bit count (BIT) or 8-bit immediate (I8).
    Imm,
    /// `ldi.df $wd, s10`.
    Ldi,
    /// `op.df $wd, $ws[n]` (sldi, splati).
    Elm,
    /// `copy_x.df $rd, $ws[n]` (GPR in the `wd` field).
    Copy,
    /// `insert.df $wd[n], $rs` (GPR in the `ws` field).
    Insert,
    /// `insve.df $wd[n], $ws[0]`.
    Insve,
    /// `ctcmsa $cd, $rs`.
    Ctc,
    /// `cfcmsa $rd, $cs`.
    Cfc,
    /// `op.df $wd, $ws` (2R/2RF and move.v).
    R2,
    /// `fill.df $wd, $rs` (GPR in the `ws` field).
    Fill,
    /// `ld.df`/`st.df $wd, off($rs)` (GPR in the `ws` field).
    Mem,
    /// `bz.df`/`bnz.df $wt, off`.
    Branch,
}

macro_rules! msa_ops {
    ($($v:ident = $name:literal, $form:ident, $unit:ident;)*) => {
        /// One MSA operation (the data format is kept separately in [`Df`]).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[allow(missing_docs)]
        pub enum MsaOp { $($v,)* }

        impl MsaOp {
            /// Mnemonic without the data-format suffix.
            pub fn name(self) -> &'static str {
                match self { $(MsaOp::$v => $name,)* }
            }

            /// Operand layout.
            pub fn form(self) -> Form {
                match self { $(MsaOp::$v => Form::$form,)* }
            }

            /// Execution-unit class for the timing model.
            pub fn unit(self) -> UnitClass {
                match self { $(MsaOp::$v => UnitClass::$unit,)* }
            }
        }
    };
}

msa_ops! {
    // I8
    Andi = "andi", Imm, Bitwise;
    Ori = "ori", Imm, Bitwise;
    Nori = "nori", Imm, Bitwise;
    Xori = "xori", Imm, Bitwise;
    Bmnzi = "bmnzi", Imm, Bitwise;
    Bmzi = "bmzi", Imm, Bitwise;
    Bseli = "bseli", Imm, Bitwise;
    Shf = "shf", Imm, Bitwise;
    // I5
    Addvi = "addvi", Imm, IntAdd;
    Subvi = "subvi", Imm, IntAdd;
    MaxiS = "maxi_s", Imm, IntAdd;
    MaxiU = "maxi_u", Imm, IntAdd;
    MiniS = "mini_s", Imm, IntAdd;
    MiniU = "mini_u", Imm, IntAdd;
    Ceqi = "ceqi", Imm, IntAdd;
    CltiS = "clti_s", Imm, IntAdd;
    CltiU = "clti_u", Imm, IntAdd;
    CleiS = "clei_s", Imm, IntAdd;
    CleiU = "clei_u", Imm, IntAdd;
    Ldi = "ldi", Ldi, RegFile;
    // BIT
    Slli = "slli", Imm, Bitwise;
    Srai = "srai", Imm, Bitwise;
    Srli = "srli", Imm, Bitwise;
    Bclri = "bclri", Imm, Bitwise;
    Bseti = "bseti", Imm, Bitwise;
    Bnegi = "bnegi", Imm, Bitwise;
    Binsli = "binsli", Imm, Bitwise;
    Binsri = "binsri", Imm, Bitwise;
    SatS = "sat_s", Imm, IntAdd;
    SatU = "sat_u", Imm, IntAdd;
    Srari = "srari", Imm, Bitwise;
    Srlri = "srlri", Imm, Bitwise;
    // 3R
    Sll = "sll", R3, Bitwise;
    Sra = "sra", R3, Bitwise;
    Srl = "srl", R3, Bitwise;
    Bclr = "bclr", R3, Bitwise;
    Bset = "bset", R3, Bitwise;
    Bneg = "bneg", R3, Bitwise;
    Binsl = "binsl", R3, Bitwise;
    Binsr = "binsr", R3, Bitwise;
    Addv = "addv", R3, IntAdd;
    Subv = "subv", R3, IntAdd;
    MaxS = "max_s", R3, IntAdd;
    MaxU = "max_u", R3, IntAdd;
    MinS = "min_s", R3, IntAdd;
    MinU = "min_u", R3, IntAdd;
    MaxA = "max_a", R3, IntAdd;
    MinA = "min_a", R3, IntAdd;
    Ceq = "ceq", R3, IntAdd;
    CltS = "clt_s", R3, IntAdd;
    CltU = "clt_u", R3, IntAdd;
    CleS = "cle_s", R3, IntAdd;
    CleU = "cle_u", R3, IntAdd;
    AddA = "add_a", R3, IntAdd;
    AddsA = "adds_a", R3, IntAdd;
    AddsS = "adds_s", R3, IntAdd;
    AddsU = "adds_u", R3, IntAdd;
    AveS = "ave_s", R3, IntAdd;
    AveU = "ave_u", R3, IntAdd;
    AverS = "aver_s", R3, IntAdd;
    AverU = "aver_u", R3, IntAdd;
    SubsS = "subs_s", R3, IntAdd;
    SubsU = "subs_u", R3, IntAdd;
    SubsusU = "subsus_u", R3, IntAdd;
    SubsuuS = "subsuu_s", R3, IntAdd;
    AsubS = "asub_s", R3, IntAdd;
    AsubU = "asub_u", R3, IntAdd;
    Mulv = "mulv", R3, IntMul;
    Maddv = "maddv", R3, IntMul;
    Msubv = "msubv", R3, IntMul;
    DivS = "div_s", R3, IntDiv;
    DivU = "div_u", R3, IntDiv;
    ModS = "mod_s", R3, IntDiv;
    ModU = "mod_u", R3, IntDiv;
    DotpS = "dotp_s", R3, IntMul;
    DotpU = "dotp_u", R3, IntMul;
    DpaddS = "dpadd_s", R3, IntMul;
    DpaddU = "dpadd_u", R3, IntMul;
    DpsubS = "dpsub_s", R3, IntMul;
    DpsubU = "dpsub_u", R3, IntMul;
    Sld = "sld", R3Gpr, Bitwise;
    Splat = "splat", R3Gpr, Bitwise;
    Pckev = "pckev", R3, Bitwise;
    Pckod = "pckod", R3, Bitwise;
    Ilvl = "ilvl", R3, Bitwise;
    Ilvr = "ilvr", R3, Bitwise;
    Ilvev = "ilvev", R3, Bitwise;
    Ilvod = "ilvod", R3, Bitwise;
    Vshf = "vshf", R3, Bitwise;
    Srar = "srar", R3, Bitwise;
    Srlr = "srlr", R3, Bitwise;
    HaddS = "hadd_s", R3, IntAdd;
    HaddU = "hadd_u", R3, IntAdd;
    HsubS = "hsub_s", R3, IntAdd;
    HsubU = "hsub_u", R3, IntAdd;
    // ELM
    Sldi = "sldi", Elm, Bitwise;
    Splati = "splati", Elm, Bitwise;
    CopyS = "copy_s", Copy, RegFile;
    CopyU = "copy_u", Copy, RegFile;
    Insert = "insert", Insert, RegFile;
    Insve = "insve", Insve, RegFile;
    Ctcmsa = "ctcmsa", Ctc, RegFile;
    Cfcmsa = "cfcmsa", Cfc, RegFile;
    Move = "move", R2, RegFile;
    // 3RF
    Fcaf = "fcaf", R3, FpCmp;
    Fcun = "fcun", R3, FpCmp;
    Fceq = "fceq", R3, FpCmp;
    Fcueq = "fcueq", R3, FpCmp;
    Fclt = "fclt", R3, FpCmp;
    Fcult = "fcult", R3, FpCmp;
    Fcle = "fcle", R3, FpCmp;
    Fcule = "fcule", R3, FpCmp;
    Fsaf = "fsaf", R3, FpCmp;
    Fsun = "fsun", R3, FpCmp;
    Fseq = "fseq", R3, FpCmp;
    Fsueq = "fsueq", R3, FpCmp;
    Fslt = "fslt", R3, FpCmp;
    Fsult = "fsult", R3, FpCmp;
    Fsle = "fsle", R3, FpCmp;
    Fsule = "fsule", R3, FpCmp;
    Fadd = "fadd", R3, FpAdd;
    Fsub = "fsub", R3, FpAdd;
    Fmul = "fmul", R3, FpMul;
    Fdiv = "fdiv", R3, FpDiv;
    Fmadd = "fmadd", R3, FpMul;
    Fmsub = "fmsub", R3, FpMul;
    Fexp2 = "fexp2", R3, FpMul;
    Fexdo = "fexdo", R3, Conv;
    Ftq = "ftq", R3, Conv;
    Fmin = "fmin", R3, FpMinMax;
    FminA = "fmin_a", R3, FpMinMax;
    Fmax = "fmax", R3, FpMinMax;
    FmaxA = "fmax_a", R3, FpMinMax;
    Fcor = "fcor", R3, FpCmp;
    Fcune = "fcune", R3, FpCmp;
    Fcne = "fcne", R3, FpCmp;
    MulQ = "mul_q", R3, IntMul;
    MaddQ = "madd_q", R3, IntMul;
    MsubQ = "msub_q", R3, IntMul;
    Fsor = "fsor", R3, FpCmp;
    Fsune = "fsune", R3, FpCmp;
    Fsne = "fsne", R3, FpCmp;
    MulrQ = "mulr_q", R3, IntMul;
    MaddrQ = "maddr_q", R3, IntMul;
    MsubrQ = "msubr_q", R3, IntMul;
    // VEC
    AndV = "and", R3, Bitwise;
    OrV = "or", R3, Bitwise;
    NorV = "nor", R3, Bitwise;
    XorV = "xor", R3, Bitwise;
    BmnzV = "bmnz", R3, Bitwise;
    BmzV = "bmz", R3, Bitwise;
    BselV = "bsel", R3, Bitwise;
    // 2R
    Fill = "fill", Fill, RegFile;
    Pcnt = "pcnt", R2, Bitwise;
    Nloc = "nloc", R2, Bitwise;
    Nlzc = "nlzc", R2, Bitwise;
    // 2RF
    Fclass = "fclass", R2, FpCmp;
    FtruncS = "ftrunc_s", R2, Conv;
    FtruncU = "ftrunc_u", R2, Conv;
    Fsqrt = "fsqrt", R2, FpInvSqrt;
    Frsqrt = "frsqrt", R2, FpInvSqrt;
    Frcp = "frcp", R2, FpDiv;
    Frint = "frint", R2, Conv;
    Flog2 = "flog2", R2, Conv;
    Fexupl = "fexupl", R2, Conv;
    Fexupr = "fexupr", R2, Conv;
    Ffql = "ffql", R2, Conv;
    Ffqr = "ffqr", R2, Conv;
    FtintS = "ftint_s", R2, Conv;
    FtintU = "ftint_u", R2, Conv;
    FfintS = "ffint_s", R2, Conv;
    FfintU = "ffint_u", R2, Conv;
    // MI10
    Ld = "ld", Mem, Memory;
    St = "st", Mem, Memory;
    // Branches (COP1 encodings)
    Bz = "bz", Branch, Branch;
    Bnz = "bnz", Branch, Branch;
}
