//! Lowering of the builtin catalogue (`crate::builtins`), builtin macros and TRaX
//! instructions (inline asm).

use super::{internal, LResult, LowerError, Lowerer, V};
use crate::builtins::Builtin;
use crate::ty::{FloatTy, IntTy, SimdTy, Ty};
use crate::typeck::{key, MacroCall, TraxArg};
use inkwell::types::{BasicMetadataTypeEnum, BasicType, BasicTypeEnum, VectorType};
use inkwell::values::BasicValue;
use inkwell::values::{
    BasicMetadataValueEnum, BasicValueEnum, CallableValue, FloatValue, IntValue, VectorValue,
};
use inkwell::{FloatPredicate, IntPredicate};
use trax_runtime::isa::{instr, AbortKind, Field, OperandKind, TraxInstr, TraxOp};

/// ABI names of the general-purpose registers, by number.
const GPR_NAMES: [&str; 32] = [
    "zero", "at", "v0", "v1", "a0", "a1", "a2", "a3", "t0", "t1", "t2", "t3", "t4", "t5", "t6",
    "t7", "s0", "s1", "s2", "s3", "s4", "s5", "s6", "s7", "t8", "t9", "k0", "k1", "gp", "sp", "fp",
    "ra",
];

/// Operations whose result depends only on their operands or fixed thread identity.
fn is_pure(op: TraxOp) -> bool {
    matches!(
        op,
        TraxOp::ThreadId
            | TraxOp::TmId
            | TraxOp::GlobalId
            | TraxOp::NumThreads
            | TraxOp::NumTms
            | TraxOp::FMin
            | TraxOp::FMax
            | TraxOp::InvSqrt
    )
}

impl<'ctx> Lowerer<'ctx, '_, '_> {
    fn intrinsic(
        &mut self,
        name: &str,
        ret: BasicTypeEnum<'ctx>,
        args: &[BasicValueEnum<'ctx>],
    ) -> LResult<BasicValueEnum<'ctx>> {
        let ptys: Vec<BasicMetadataTypeEnum> = args.iter().map(|a| a.get_type().into()).collect();
        let f = match self.module.get_function(name) {
            Some(f) => f,
            None => self
                .module
                .add_function(name, ret.fn_type(&ptys, false), None),
        };
        let args: Vec<BasicMetadataValueEnum> = args.iter().map(|a| (*a).into()).collect();
        self.b
            .build_call(f, &args, "")?
            .try_as_basic_value()
            .basic()
            .ok_or_else(|| LowerError::Internal(format!("{name} returned void")))
    }

    fn fsuffix(t: &Ty) -> &'static str {
        match t {
            Ty::Float(FloatTy::F64) => "f64",
            Ty::Simd(_) => "v4f32",
            _ => "f32",
        }
    }

    /// Float functions that have no libm dependency on MIPS: rounding is done with the
    /// 2^(mantissa bits) trick so no `floorf`-style libcall is emitted.
    pub(super) fn float_unary(
        &mut self,
        name: Builtin,
        v: BasicValueEnum<'ctx>,
        t: &Ty,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let x = v.into_float_value();
        let ft = x.get_type();
        let sfx = Self::fsuffix(t);
        let big = if sfx == "f64" {
            4503599627370496.0
        } else {
            8388608.0
        };
        let fabs = self
            .intrinsic(&format!("llvm.fabs.{sfx}"), ft.into(), &[x.into()])?
            .into_float_value();
        let b = &self.b;
        // r = round-to-nearest-even(|x|) for |x| < big; exact otherwise.
        let bigc = ft.const_float(big);
        let r = b.build_float_sub(b.build_float_add(fabs, bigc, "")?, bigc, "")?;
        let small = b.build_float_compare(FloatPredicate::OLT, fabs, bigc, "")?;
        let r = b.build_select(small, r, fabs, "")?.into_float_value();
        let one = ft.const_float(1.0);
        // t = trunc(|x|)
        let gt = b.build_float_compare(FloatPredicate::OGT, r, fabs, "")?;
        let rm1 = b.build_float_sub(r, one, "")?;
        let tabs = b.build_select(gt, rm1, r, "")?.into_float_value();
        let copysign = |s: &mut Self, mag: FloatValue<'ctx>| -> LResult<FloatValue<'ctx>> {
            Ok(s.intrinsic(
                &format!("llvm.copysign.{sfx}"),
                ft.into(),
                &[mag.into(), x.into()],
            )?
            .into_float_value())
        };
        let trunc = copysign(self, tabs)?;
        let b = &self.b;
        let out = match name {
            Builtin::FTrunc => trunc,
            Builtin::FFloor => {
                let gt = b.build_float_compare(FloatPredicate::OGT, trunc, x, "")?;
                let m = b.build_float_sub(trunc, one, "")?;
                b.build_select(gt, m, trunc, "")?.into_float_value()
            }
            Builtin::FCeil => {
                let lt = b.build_float_compare(FloatPredicate::OLT, trunc, x, "")?;
                let p = b.build_float_add(trunc, one, "")?;
                b.build_select(lt, p, trunc, "")?.into_float_value()
            }
            Builtin::FRound => {
                let frac = b.build_float_sub(fabs, tabs, "")?;
                let half =
                    b.build_float_compare(FloatPredicate::OGE, frac, ft.const_float(0.5), "")?;
                let up = b.build_float_add(tabs, one, "")?;
                let m = b.build_select(half, up, tabs, "")?.into_float_value();
                copysign(self, m)?
            }
            Builtin::FFract => b.build_float_sub(x, trunc, "")?,
            _ => return Err(LowerError::Internal(format!("float op {name:?}"))),
        };
        // NaN and infinities pass through.
        let fin = self.b.build_float_compare(
            FloatPredicate::OLT,
            fabs,
            ft.const_float(f64::INFINITY),
            "",
        )?;
        let keep = if name == Builtin::FFract {
            ft.const_float(f64::NAN)
        } else {
            x
        };
        Ok(self.b.build_select(fin, out, keep, "")?)
    }

    /// Lowers a builtin method or function; `vals[0]` is the receiver for methods.
    /// IEEE minNum/maxNum (Rust's `f32::min`/`max`) without a libm call.
    fn float_minmax(
        &mut self,
        min: bool,
        x: FloatValue<'ctx>,
        y: FloatValue<'ctx>,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let b = &self.b;
        let pred = if min {
            FloatPredicate::OLT
        } else {
            FloatPredicate::OGT
        };
        let c = b.build_float_compare(pred, x, y, "")?;
        let r = b.build_select(c, x, y, "")?.into_float_value();
        let xnan = b.build_float_compare(FloatPredicate::UNO, x, x, "")?;
        let r = b.build_select(xnan, y, r, "")?.into_float_value();
        let ynan = b.build_float_compare(FloatPredicate::UNO, y, y, "")?;
        Ok(b.build_select(ynan, x, r, "")?)
    }

    /// `x.powi(n)` by square-and-multiply (no `__powisf2` runtime call).
    fn float_powi(
        &mut self,
        x: FloatValue<'ctx>,
        n: IntValue<'ctx>,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let ft = x.get_type();
        let i32t = self.ctx.i32_type();
        let t = if ft == self.ctx.f64_type() {
            Ty::Float(FloatTy::F64)
        } else {
            Ty::Float(FloatTy::F32)
        };
        let base = self.alloca(&t, "powi.base")?;
        let acc = self.alloca(&t, "powi.acc")?;
        let e = self.alloca(&Ty::Int(IntTy::U32), "powi.exp")?;
        self.b.build_store(base, x)?;
        self.b.build_store(acc, ft.const_float(1.0))?;
        let neg = self
            .b
            .build_int_compare(IntPredicate::SLT, n, i32t.const_zero(), "")?;
        let nn = self.b.build_int_neg(n, "")?;
        let mag = self.b.build_select(neg, nn, n, "")?;
        self.b.build_store(e, mag)?;
        let head = self.new_block("powi.cond");
        let body = self.new_block("powi.body");
        let exit = self.new_block("powi.end");
        self.b.build_unconditional_branch(head)?;
        self.b.position_at_end(head);
        let ev = self.b.build_load(e, "")?.into_int_value();
        let more = self
            .b
            .build_int_compare(IntPredicate::NE, ev, i32t.const_zero(), "")?;
        self.b.build_conditional_branch(more, body, exit)?;
        self.b.position_at_end(body);
        let bv = self.b.build_load(base, "")?.into_float_value();
        let av = self.b.build_load(acc, "")?.into_float_value();
        let odd = self.b.build_and(ev, i32t.const_int(1, false), "")?;
        let odd = self
            .b
            .build_int_compare(IntPredicate::NE, odd, i32t.const_zero(), "")?;
        let m = self.b.build_float_mul(av, bv, "")?;
        let a2 = self.b.build_select(odd, m, av, "")?;
        self.b.build_store(acc, a2)?;
        let sq = self.b.build_float_mul(bv, bv, "")?;
        self.b.build_store(base, sq)?;
        let e2 = self
            .b
            .build_right_shift(ev, i32t.const_int(1, false), false, "")?;
        self.b.build_store(e, e2)?;
        self.b.build_unconditional_branch(head)?;
        self.b.position_at_end(exit);
        let r = self.b.build_load(acc, "")?.into_float_value();
        let inv = self.b.build_float_div(ft.const_float(1.0), r, "")?;
        Ok(self.b.build_select(neg, inv, r, "")?)
    }

    fn int_builtin(
        &mut self,
        name: Builtin,
        vals: &[BasicValueEnum<'ctx>],
        t: &Ty,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let Ty::Int(it) = t else {
            return Err(LowerError::Internal("int builtin".into()));
        };
        let x = vals[0].into_int_value();
        let lt = x.get_type();
        let bits = it.bits();
        let signed = it.signed();
        let b = &self.b;
        let sel = |s: &Self,
                   pred: IntPredicate,
                   a: IntValue<'ctx>,
                   c: IntValue<'ctx>|
         -> LResult<BasicValueEnum<'ctx>> {
            let cmp = s.b.build_int_compare(pred, a, c, "")?;
            Ok(s.b.build_select(cmp, a, c, "")?)
        };
        Ok(match name {
            Builtin::IMin => sel(
                self,
                if signed {
                    IntPredicate::SLT
                } else {
                    IntPredicate::ULT
                },
                x,
                vals[1].into_int_value(),
            )?,
            Builtin::IMax => sel(
                self,
                if signed {
                    IntPredicate::SGT
                } else {
                    IntPredicate::UGT
                },
                x,
                vals[1].into_int_value(),
            )?,
            Builtin::IClamp => {
                let lo = sel(
                    self,
                    if signed {
                        IntPredicate::SGT
                    } else {
                        IntPredicate::UGT
                    },
                    x,
                    vals[1].into_int_value(),
                )?
                .into_int_value();
                sel(
                    self,
                    if signed {
                        IntPredicate::SLT
                    } else {
                        IntPredicate::ULT
                    },
                    lo,
                    vals[2].into_int_value(),
                )?
            }
            Builtin::IAbs => {
                let neg = b.build_int_neg(x, "")?;
                let isneg = b.build_int_compare(IntPredicate::SLT, x, lt.const_zero(), "")?;
                b.build_select(isneg, neg, x, "")?
            }
            Builtin::IWrappingAdd => b.build_int_add(x, vals[1].into_int_value(), "")?.into(),
            Builtin::IWrappingSub => b.build_int_sub(x, vals[1].into_int_value(), "")?.into(),
            Builtin::IWrappingMul => b.build_int_mul(x, vals[1].into_int_value(), "")?.into(),
            Builtin::IWrappingNeg => b.build_int_neg(x, "")?.into(),
            Builtin::ICountOnes | Builtin::ILeadingZeros | Builtin::ITrailingZeros => {
                let n = match name {
                    Builtin::ICountOnes => format!("llvm.ctpop.i{bits}"),
                    Builtin::ILeadingZeros => format!("llvm.ctlz.i{bits}"),
                    _ => format!("llvm.cttz.i{bits}"),
                };
                let mut args = vec![x.into()];
                if name != Builtin::ICountOnes {
                    args.push(self.ctx.bool_type().const_zero().into());
                }
                let r = self.intrinsic(&n, lt.into(), &args)?.into_int_value();
                self.b
                    .build_int_cast_sign_flag(r, self.ctx.i32_type(), false, "")?
                    .into()
            }
            Builtin::IIsPowerOfTwo => {
                let r = self
                    .intrinsic(&format!("llvm.ctpop.i{bits}"), lt.into(), &[x.into()])?
                    .into_int_value();
                self.b
                    .build_int_compare(IntPredicate::EQ, r, lt.const_int(1, false), "")?
                    .into()
            }
            Builtin::IRotateLeft | Builtin::IRotateRight => {
                let amt =
                    self.b
                        .build_int_cast_sign_flag(vals[1].into_int_value(), lt, false, "")?;
                let n = if name == Builtin::IRotateLeft {
                    "fshl"
                } else {
                    "fshr"
                };
                self.intrinsic(
                    &format!("llvm.{n}.i{bits}"),
                    lt.into(),
                    &[x.into(), x.into(), amt.into()],
                )?
            }
            Builtin::ISwapBytes => {
                if bits == 8 {
                    x.into()
                } else {
                    self.intrinsic(&format!("llvm.bswap.i{bits}"), lt.into(), &[x.into()])?
                }
            }
            Builtin::IPow => {
                // Square-and-multiply loop, wrapping.
                let base_slot = self.alloca(t, "pow.base")?;
                let acc_slot = self.alloca(t, "pow.acc")?;
                let e_slot = self.alloca(&Ty::Int(IntTy::U32), "pow.exp")?;
                self.b.build_store(base_slot, x)?;
                self.b.build_store(acc_slot, lt.const_int(1, false))?;
                self.b.build_store(e_slot, vals[1])?;
                let head = self.new_block("pow.cond");
                let body = self.new_block("pow.body");
                let exit = self.new_block("pow.end");
                self.b.build_unconditional_branch(head)?;
                self.b.position_at_end(head);
                let i32t = self.ctx.i32_type();
                let e = self.b.build_load(e_slot, "")?.into_int_value();
                let more = self
                    .b
                    .build_int_compare(IntPredicate::NE, e, i32t.const_zero(), "")?;
                self.b.build_conditional_branch(more, body, exit)?;
                self.b.position_at_end(body);
                let base = self.b.build_load(base_slot, "")?.into_int_value();
                let acc = self.b.build_load(acc_slot, "")?.into_int_value();
                let odd = self.b.build_and(e, i32t.const_int(1, false), "")?;
                let odd = self
                    .b
                    .build_int_compare(IntPredicate::NE, odd, i32t.const_zero(), "")?;
                let m = self.b.build_int_mul(acc, base, "")?;
                let acc2 = self.b.build_select(odd, m, acc, "")?;
                self.b.build_store(acc_slot, acc2)?;
                let sq = self.b.build_int_mul(base, base, "")?;
                self.b.build_store(base_slot, sq)?;
                let e2 = self
                    .b
                    .build_right_shift(e, i32t.const_int(1, false), false, "")?;
                self.b.build_store(e_slot, e2)?;
                self.b.build_unconditional_branch(head)?;
                self.b.position_at_end(exit);
                self.b.build_load(acc_slot, "")?
            }
            _ => return self.int_builtin2(name, vals, t),
        })
    }

    /// `f32x4` lanes with the sign bit cleared (`neg == false`, `abs`) or flipped
    /// (`neg`, unary minus), as integer operations: exact for every input, NaNs
    /// included. (LLVM 14 lowers vector `fneg` as `fsub.w -0.0, x`, which turns a NaN
    /// into a positive quiet NaN, and `fabs` as `fmax_a.w x, x`, which keeps the sign.)
    pub(super) fn simd_sign_bit(
        &mut self,
        x: VectorValue<'ctx>,
        neg: bool,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let i32t = self.ctx.i32_type();
        let v4i = i32t.vec_type(4);
        let xi = self.b.build_bit_cast(x, v4i, "")?.into_vector_value();
        let r = if neg {
            let sign = VectorType::const_vector(&[i32t.const_int(0x8000_0000, false); 4]);
            self.b.build_xor(xi, sign, "")?
        } else {
            let mag = VectorType::const_vector(&[i32t.const_int(0x7FFF_FFFF, false); 4]);
            self.b.build_and(xi, mag, "")?
        };
        Ok(self.b.build_bit_cast(r, x.get_type(), "")?)
    }

    /// Lane-wise IEEE minNum/maxNum with exactly the host's semantics
    /// (`trax_runtime::fops::fmin`/`fmax`): a NaN loses against a number, two NaNs give
    /// the first quieted, `min(-0, +0) = -0` and `max(-0, +0) = +0` in either order.
    /// Compares and selects on the lanes' bits, no libm call.
    fn simd_minmax(
        &mut self,
        min: bool,
        x: VectorValue<'ctx>,
        y: VectorValue<'ctx>,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let i32t = self.ctx.i32_type();
        let v4i = i32t.vec_type(4);
        let b = &self.b;
        let xi = b.build_bit_cast(x, v4i, "")?.into_vector_value();
        let yi = b.build_bit_cast(y, v4i, "")?.into_vector_value();
        let pred = if min {
            FloatPredicate::OLT
        } else {
            FloatPredicate::OGT
        };
        let x_wins = b.build_float_compare(pred, x, y, "")?;
        let y_wins = b.build_float_compare(pred, y, x, "")?;
        // Equal numbers have equal bits except for zeros of opposite sign: OR prefers -0,
        // AND +0.
        let tie = if min {
            b.build_or(xi, yi, "")?
        } else {
            b.build_and(xi, yi, "")?
        };
        let r = b.build_select(y_wins, yi, tie, "")?.into_vector_value();
        let r = b.build_select(x_wins, xi, r, "")?.into_vector_value();
        let xnan = b.build_float_compare(FloatPredicate::UNO, x, x, "")?;
        let ynan = b.build_float_compare(FloatPredicate::UNO, y, y, "")?;
        let quiet = VectorType::const_vector(&[i32t.const_int(0x0040_0000, false); 4]);
        let xq = b.build_or(xi, quiet, "")?;
        let nan_r = b.build_select(ynan, xq, yi, "")?.into_vector_value();
        let r = b.build_select(ynan, xi, r, "")?.into_vector_value();
        let r = b.build_select(xnan, nan_r, r, "")?.into_vector_value();
        Ok(b.build_bit_cast(r, x.get_type(), "")?)
    }

    fn simd_builtin(
        &mut self,
        s: SimdTy,
        name: Builtin,
        vals: &[BasicValueEnum<'ctx>],
        rt: BasicTypeEnum<'ctx>,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let i32t = self.ctx.i32_type();
        let v4i = i32t.vec_type(4);
        let lanes = |s: &Self,
                     vt: BasicTypeEnum<'ctx>,
                     xs: &[BasicValueEnum<'ctx>]|
         -> LResult<BasicValueEnum<'ctx>> {
            let mut v = super::undef(vt).into_vector_value();
            for (i, x) in xs.iter().enumerate() {
                v =
                    s.b.build_insert_element(v, *x, i32t.const_int(i as u64, false), "")?;
            }
            Ok(v.into())
        };
        let f = s == SimdTy::F32x4;
        Ok(match name {
            Builtin::SimdSplat => lanes(self, rt, &[vals[0]; 4])?,
            Builtin::SimdNew => lanes(self, rt, &vals[..4])?,
            Builtin::SimdGet => {
                let idx = vals[1].into_int_value();
                let ok = self.b.build_int_compare(
                    IntPredicate::ULT,
                    idx,
                    i32t.const_int(4, false),
                    "",
                )?;
                let four = i32t.const_int(4, false);
                self.check_with(ok, |l| l.bounds_abort(four, idx))?;
                self.b
                    .build_extract_element(vals[0].into_vector_value(), idx, "")?
            }
            Builtin::SimdMin | Builtin::SimdMax => self.simd_minmax(
                name == Builtin::SimdMin,
                vals[0].into_vector_value(),
                vals[1].into_vector_value(),
            )?,
            Builtin::SimdSqrt => self.intrinsic("llvm.sqrt.v4f32", rt, &[vals[0]])?,
            // Not `llvm.fabs.v4f32`: LLVM 14 selects `fmax_a.w x, x` for it, which keeps
            // the sign. Clearing the sign bit is exact for every input, NaNs included.
            Builtin::SimdAbs => self.simd_sign_bit(vals[0].into_vector_value(), false)?,
            Builtin::SimdMulAdd => {
                // `fmadd.w wd, ws, wt`: wd = wd + ws * wt, one rounding. Not `llvm.fma.v4f32`:
                // LLVM 14 selects `fmadd.w` for it with the addend and a factor swapped
                // (computing a + b * c for a * b + c) whenever the operands are not
                // constants.
                let vt = self.ctx.f32_type().vec_type(4);
                let fty = vt.fn_type(&[vt.into(), vt.into(), vt.into()], false);
                let ia = self.ctx.create_inline_asm(
                    fty,
                    "fmadd.w $0, $1, $2".into(),
                    "=f,f,f,0".into(),
                    false,
                    false,
                    None,
                    false,
                );
                let callable = CallableValue::try_from(ia)
                    .map_err(|_| LowerError::Internal("inline asm callable".into()))?;
                let args: [BasicMetadataValueEnum; 3] =
                    [vals[0].into(), vals[1].into(), vals[2].into()];
                self.b
                    .build_call(callable, &args, "")?
                    .try_as_basic_value()
                    .basic()
                    .ok_or_else(|| LowerError::Internal("fmadd.w".into()))?
            }
            Builtin::SimdLt
            | Builtin::SimdLe
            | Builtin::SimdGt
            | Builtin::SimdGe
            | Builtin::SimdEq => {
                let pred = match name {
                    Builtin::SimdLt => FloatPredicate::OLT,
                    Builtin::SimdLe => FloatPredicate::OLE,
                    Builtin::SimdGt => FloatPredicate::OGT,
                    Builtin::SimdGe => FloatPredicate::OGE,
                    _ => FloatPredicate::OEQ,
                };
                let m = self.b.build_float_compare(
                    pred,
                    vals[0].into_vector_value(),
                    vals[1].into_vector_value(),
                    "",
                )?;
                self.b.build_int_s_extend(m, v4i, "")?.into()
            }
            Builtin::SimdSelect => {
                let mask = vals[0].into_vector_value();
                let nz = self
                    .b
                    .build_int_compare(IntPredicate::NE, mask, v4i.const_zero(), "")?;
                self.b.build_select(
                    nz,
                    vals[1].into_vector_value(),
                    vals[2].into_vector_value(),
                    "",
                )?
            }
            Builtin::SimdToI32x4 => {
                self.intrinsic("llvm.fptosi.sat.v4i32.v4f32", rt, &[vals[0]])?
            }
            Builtin::SimdToF32x4 => self
                .b
                .build_signed_int_to_float(
                    vals[0].into_vector_value(),
                    self.ctx.f32_type().vec_type(4),
                    "",
                )?
                .into(),
            Builtin::SimdAny | Builtin::SimdAll if !f => {
                let nz = self.b.build_int_compare(
                    IntPredicate::NE,
                    vals[0].into_vector_value(),
                    v4i.const_zero(),
                    "",
                )?;
                let n = if name == Builtin::SimdAny {
                    "llvm.vector.reduce.or.v4i1"
                } else {
                    "llvm.vector.reduce.and.v4i1"
                };
                self.intrinsic(n, self.ctx.bool_type().into(), &[nz.into()])?
            }
            _ => return Err(LowerError::Internal(format!("simd builtin {name:?}"))),
        })
    }

    // ---------------------------------------------------------------- TRaX instructions

    /// Emits one TRaX extension instruction as a `.word` through inline asm.
    ///
    /// `regs` are the register use operands in operand order; `imms` the immediates.
    pub(super) fn trax(
        &mut self,
        ins: &TraxInstr,
        regs: &[BasicValueEnum<'ctx>],
        imms: &[u32],
    ) -> LResult<V<'ctx>> {
        let mut constraints = Vec::new();
        let mut asm = String::from(".set push\n.set noat\n");
        let mut word = format!("{:#010x}", ins.base_word());
        let mut ret_ty: Option<BasicTypeEnum<'ctx>> = None;
        let mut args: Vec<BasicMetadataValueEnum<'ctx>> = Vec::new();
        let mut arg_tys: Vec<BasicMetadataTypeEnum<'ctx>> = Vec::new();
        let (mut ri, mut ii) = (0, 0);
        let mut opnd = 0;
        // Outputs must come first in the constraint list.
        let mut ordered: Vec<_> = ins.operands.iter().filter(|o| o.kind.is_def()).collect();
        ordered.extend(ins.operands.iter().filter(|o| !o.kind.is_def()));
        for o in ordered {
            let shift = o.field.shift();
            let fld = match o.field {
                Field::Rs => "rs",
                Field::Rt => "rt",
                Field::Rd => "rd",
                Field::Sa => "sa",
            };
            match o.kind {
                OperandKind::Imm5 => {
                    let v = imms
                        .get(ii)
                        .copied()
                        .ok_or_else(|| LowerError::Internal("imm count".into()))?;
                    ii += 1;
                    word.push_str(&format!(" | ({} << {shift})", v & 0x1F));
                    continue;
                }
                OperandKind::GprDef => {
                    constraints.push("=r".to_string());
                    ret_ty = Some(self.ctx.i32_type().into());
                }
                OperandKind::FprDef => {
                    constraints.push("=f".to_string());
                    ret_ty = Some(self.ctx.f32_type().into());
                }
                OperandKind::GprUse => {
                    let v = regs
                        .get(ri)
                        .copied()
                        .ok_or_else(|| LowerError::Internal("reg count".into()))?;
                    ri += 1;
                    let v = self.gpr_operand(v)?;
                    constraints.push("r".to_string());
                    arg_tys.push(v.get_type().into());
                    args.push(v.into());
                }
                OperandKind::FprUse => {
                    let v = regs
                        .get(ri)
                        .copied()
                        .ok_or_else(|| LowerError::Internal("reg count".into()))?;
                    ri += 1;
                    constraints.push("f".to_string());
                    arg_tys.push(v.get_type().into());
                    args.push(v.into());
                }
            }
            let prefix = if matches!(o.kind, OperandKind::FprDef | OperandKind::FprUse) {
                "f"
            } else {
                ""
            };
            let sym = format!(".Ltrax_{fld}_${{:uid}}");
            asm.push_str(&format!(
                ".irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\n.ifc ${opnd},$${prefix}\\r\n.set {sym}, \\r\n.endif\n.endr\n"
            ));
            if prefix.is_empty() {
                // The printer may use ABI names (e.g. `$zero` for a constant 0 operand).
                for (n, name) in GPR_NAMES.iter().enumerate() {
                    asm.push_str(&format!(".ifc ${opnd},$${name}\n.set {sym}, {n}\n.endif\n"));
                }
            }
            word.push_str(&format!(" | ({sym} << {shift})"));
            opnd += 1;
        }
        asm.push_str(&format!(".word {word}\n.set pop"));
        let fty = match ret_ty {
            Some(t) => t.fn_type(&arg_tys, false),
            None => self.ctx.void_type().fn_type(&arg_tys, false),
        };
        let ia = self.ctx.create_inline_asm(
            fty,
            asm,
            constraints.join(","),
            !is_pure(ins.op),
            false,
            None,
            false,
        );
        let callable = CallableValue::try_from(ia)
            .map_err(|_| LowerError::Internal("inline asm callable".into()))?;
        let cs = self.b.build_call(callable, &args, "")?;
        Ok(cs.try_as_basic_value().basic())
    }

    fn gpr_operand(&mut self, v: BasicValueEnum<'ctx>) -> LResult<BasicValueEnum<'ctx>> {
        let i32t = self.ctx.i32_type();
        Ok(match v {
            BasicValueEnum::IntValue(i) if i.get_type().get_bit_width() == 32 => v,
            BasicValueEnum::IntValue(i) if i.get_type().get_bit_width() == 1 => {
                self.b.build_int_z_extend(i, i32t, "")?.into()
            }
            BasicValueEnum::IntValue(i) => {
                self.b.build_int_cast_sign_flag(i, i32t, false, "")?.into()
            }
            BasicValueEnum::PointerValue(p) => self.b.build_ptr_to_int(p, i32t, "")?.into(),
            other => other,
        })
    }

    /// Stops the program: `trax.abort` with a constant message, then `unreachable`.
    pub(super) fn abort(&mut self, kind: AbortKind, msg: &str) -> LResult<()> {
        let i32t = self.ctx.i32_type();
        let g = self.string_global(msg);
        let addr = g.as_pointer_value().const_to_int(i32t);
        let len = i32t.const_int(msg.len() as u64, false);
        let code = i32t.const_int(kind as u64, false);
        self.trax(
            instr(TraxOp::Abort),
            &[code.into(), addr.into(), len.into()],
            &[],
        )?;
        self.b.build_unreachable()?;
        Ok(())
    }

    /// Calls a function of the prelude's `libm` module.
    fn libm_call(
        &mut self,
        name: &str,
        args: &[BasicValueEnum<'ctx>],
        t: &Ty,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let f = self
            .p
            .libm_fn(name)
            .ok_or_else(|| internal(format!("libm function {name} missing")))?;
        let r = self.call_fn(f, &[], args.to_vec(), t)?;
        r.ok_or_else(|| internal("libm call returned nothing"))
    }

    /// An `Option` value of type `t` (`Some(v)` or `None`).
    fn option(&mut self, t: &Ty, v: Option<BasicValueEnum<'ctx>>) -> LResult<BasicValueEnum<'ctx>> {
        let Ty::Adt(a, _) = t else {
            return Err(internal("Option type"));
        };
        let name = if v.is_some() { "Some" } else { "None" };
        let var = self.p.adts[*a]
            .variant(name)
            .ok_or_else(|| internal("Option variant"))?;
        let fields: Vec<Option<BasicValueEnum>> = v.into_iter().map(Some).collect();
        self.build_adt(t, var, &fields)
    }

    /// An `Ordering` value from `lt`/`gt` flags (equal otherwise).
    fn ordering(
        &mut self,
        t: &Ty,
        lt: IntValue<'ctx>,
        gt: IntValue<'ctx>,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let Ty::Adt(a, _) = t else {
            return Err(internal("Ordering type"));
        };
        let var = |l: &Self, n: &str| -> LResult<IntValue<'ctx>> {
            let v = l.p.adts[*a]
                .variant(n)
                .ok_or_else(|| internal("Ordering variant"))?;
            Ok(l.tag_val(*a, v))
        };
        let (less, equal, greater) = (
            var(self, "Less")?,
            var(self, "Equal")?,
            var(self, "Greater")?,
        );
        let g = self.b.build_select(gt, greater, equal, "")?;
        Ok(self.b.build_select(lt, less.into(), g, "")?)
    }

    /// `Option<Ordering>` from flags and a "comparable" flag.
    fn opt_ordering(
        &mut self,
        t: &Ty,
        ok: IntValue<'ctx>,
        lt: IntValue<'ctx>,
        gt: IntValue<'ctx>,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let Ty::Adt(_, args) = t else {
            return Err(internal("Option<Ordering> type"));
        };
        let ot = args[0].clone();
        let o = self.ordering(&ot, lt, gt)?;
        let some = self.option(t, Some(o))?;
        let none = self.option(t, None)?;
        Ok(self.b.build_select(ok, some, none, "")?)
    }

    /// Lowers a builtin; for methods `vals[0]` is the receiver (for sequence builtins a
    /// pointer to the array or the slice reference, with `tys[0]` the array or slice).
    pub(super) fn builtin(
        &mut self,
        b: Builtin,
        vals: &[BasicValueEnum<'ctx>],
        tys: &[Ty],
        ret: &Ty,
    ) -> LResult<V<'ctx>> {
        use Builtin as B;
        let rt = self.llty(ret);
        let v: BasicValueEnum<'ctx> = match b {
            B::FSqrt
            | B::FAbs
            | B::FMin
            | B::FMax
            | B::FFloor
            | B::FCeil
            | B::FRound
            | B::FTrunc
            | B::FFract
            | B::FClamp
            | B::FPowi
            | B::FMulAdd
            | B::FIsNan
            | B::FIsFinite
            | B::FIsInfinite
            | B::FIsSignNegative
            | B::FIsSignPositive
            | B::FToBits
            | B::FSignum
            | B::FRecip
            | B::FCopysign
            | B::FToDegrees
            | B::FToRadians
            | B::FRemEuclid
            | B::FDivEuclid
            | B::FPartialCmp
            | B::FTotalCmp
            | B::FLogBase
            | B::FSinCos => self.float_builtin(b, vals, &tys[0], ret)?,
            B::FFromBits => self.b.build_bit_cast(vals[0], rt, "")?,
            B::Libm(..) => return Err(internal("libm builtins are calls")),
            B::IMin
            | B::IMax
            | B::IAbs
            | B::IClamp
            | B::IWrappingAdd
            | B::IWrappingSub
            | B::IWrappingMul
            | B::IWrappingNeg
            | B::IPow
            | B::ICountOnes
            | B::ILeadingZeros
            | B::ITrailingZeros
            | B::IIsPowerOfTwo
            | B::IRotateLeft
            | B::IRotateRight
            | B::ISwapBytes
            | B::IRemEuclid
            | B::IDivEuclid
            | B::ISignum
            | B::IAbsDiff
            | B::IIsPositive
            | B::IIsNegative => self.int_builtin(b, vals, &tys[0])?,
            B::IPartialCmp | B::ICmp => {
                let x = vals[0].into_int_value();
                let y = self
                    .b
                    .build_load(vals[1].into_pointer_value(), "")?
                    .into_int_value();
                let signed = matches!(tys[0], Ty::Int(i) if i.signed());
                let (pl, pg) = if signed {
                    (IntPredicate::SLT, IntPredicate::SGT)
                } else {
                    (IntPredicate::ULT, IntPredicate::UGT)
                };
                let lt = self.b.build_int_compare(pl, x, y, "")?;
                let gt = self.b.build_int_compare(pg, x, y, "")?;
                if b == B::ICmp {
                    self.ordering(ret, lt, gt)?
                } else {
                    let t = self.ctx.bool_type().const_int(1, false);
                    self.opt_ordering(ret, t, lt, gt)?
                }
            }
            B::PtrAdd | B::PtrSub | B::PtrOffset => {
                let p = vals[0].into_pointer_value();
                let mut i = vals[1].into_int_value();
                if b == B::PtrSub {
                    i = self.b.build_int_neg(i, "")?;
                }
                // SAFETY: pointer arithmetic on a raw pointer, as in the source program.
                unsafe { self.b.build_gep(p, &[i], "")? }.into()
            }
            B::PtrIsNull => self
                .b
                .build_is_null(vals[0].into_pointer_value(), "")?
                .into(),
            B::PtrRead => self.b.build_load(vals[0].into_pointer_value(), "")?,
            B::PtrReadVolatile => {
                let v = self.b.build_load(vals[0].into_pointer_value(), "")?;
                if let Some(i) = v.as_instruction_value() {
                    i.set_volatile(true).map_err(|e| internal(e.to_string()))?;
                }
                v
            }
            B::PtrWrite | B::PtrWriteVolatile => {
                let s = self.b.build_store(vals[0].into_pointer_value(), vals[1])?;
                if b == B::PtrWriteVolatile {
                    s.set_volatile(true).map_err(|e| internal(e.to_string()))?;
                }
                return Ok(None);
            }
            B::StdNull => rt.into_pointer_type().const_null().into(),
            B::MemSwap => {
                let (a, c) = (vals[0].into_pointer_value(), vals[1].into_pointer_value());
                if !matches!(&tys[0], Ty::Ref(_, t) if t.is_zst()) {
                    let x = self.b.build_load(a, "")?;
                    let y = self.b.build_load(c, "")?;
                    self.b.build_store(a, y)?;
                    self.b.build_store(c, x)?;
                }
                return Ok(None);
            }
            B::MemReplace => {
                let a = vals[0].into_pointer_value();
                if ret.is_zst() {
                    return Ok(None);
                }
                let old = self.b.build_load(a, "")?;
                self.b.build_store(a, vals[1])?;
                old
            }
            B::MemTake => {
                let a = vals[0].into_pointer_value();
                if ret.is_zst() {
                    return Ok(None);
                }
                let old = self.b.build_load(a, "")?;
                let d = self.default_value(ret)?;
                let d = self.val(d, ret);
                self.b.build_store(a, d)?;
                old
            }
            B::CmpMin | B::CmpMax => {
                let (x, y) = (vals[0].into_int_value(), vals[1].into_int_value());
                let signed = matches!(tys[0], Ty::Int(i) if i.signed());
                // Rust: min returns the first on equality, max the second.
                let pred = match (b == B::CmpMin, signed) {
                    (true, true) => IntPredicate::SLE,
                    (true, false) => IntPredicate::ULE,
                    (false, true) => IntPredicate::SGT,
                    (false, false) => IntPredicate::UGT,
                };
                let c = self.b.build_int_compare(pred, x, y, "")?;
                self.b.build_select(c, x, y, "")?
            }
            B::SimdSplat
            | B::SimdNew
            | B::SimdSelect
            | B::SimdGet
            | B::SimdMin
            | B::SimdMax
            | B::SimdSqrt
            | B::SimdAbs
            | B::SimdMulAdd
            | B::SimdLt
            | B::SimdLe
            | B::SimdGt
            | B::SimdGe
            | B::SimdEq
            | B::SimdToI32x4
            | B::SimdToF32x4
            | B::SimdAny
            | B::SimdAll => {
                let s = match (&tys.first(), ret) {
                    (Some(Ty::Simd(s)), _) => *s,
                    (_, Ty::Simd(s)) => *s,
                    _ => SimdTy::F32x4,
                };
                let s = if matches!(b, B::SimdSplat | B::SimdNew | B::SimdSelect) {
                    match ret {
                        Ty::Simd(s) => *s,
                        _ => s,
                    }
                } else {
                    s
                };
                self.simd_builtin(s, b, vals, rt)?
            }
            B::Len
            | B::IsEmpty
            | B::First
            | B::Last
            | B::Swap
            | B::Fill
            | B::Contains
            | B::AsSlice => return self.seq_builtin(b, vals, tys, ret),
        };
        Ok(if ret.is_zst() { None } else { Some(v) })
    }

    fn float_builtin(
        &mut self,
        b: Builtin,
        vals: &[BasicValueEnum<'ctx>],
        t: &Ty,
        ret: &Ty,
    ) -> LResult<BasicValueEnum<'ctx>> {
        use Builtin as B;
        let rt = self.llty(ret);
        let sfx = Self::fsuffix(t);
        let x = vals[0];
        let ft = x.get_type();
        let xf = x.into_float_value();
        let fty = xf.get_type();
        Ok(match b {
            B::FSqrt | B::FAbs => {
                let n = if b == B::FAbs { "fabs" } else { "sqrt" };
                self.intrinsic(&format!("llvm.{n}.{sfx}"), ft, &[x])?
            }
            B::FMin | B::FMax => self.float_minmax(b == B::FMin, xf, vals[1].into_float_value())?,
            B::FCopysign => self.intrinsic(&format!("llvm.copysign.{sfx}"), ft, &[x, vals[1]])?,
            B::FMulAdd => {
                // r6 `maddf.fmt fd, fs, ft`: fd = fd + fs * ft, one rounding. LLVM 14
                // does not select it for `llvm.fma`, which would call `fmaf`.
                let fnty = ft.fn_type(&[ft.into(), ft.into(), ft.into()], false);
                let fmt = if sfx == "f64" { "d" } else { "s" };
                let ia = self.ctx.create_inline_asm(
                    fnty,
                    format!("maddf.{fmt} $0, $1, $2"),
                    "=f,f,f,0".into(),
                    false,
                    false,
                    None,
                    false,
                );
                let callable =
                    CallableValue::try_from(ia).map_err(|_| internal("inline asm callable"))?;
                let args: [BasicMetadataValueEnum; 3] = [x.into(), vals[1].into(), vals[2].into()];
                self.b
                    .build_call(callable, &args, "")?
                    .try_as_basic_value()
                    .basic()
                    .ok_or_else(|| internal("maddf"))?
            }
            B::FPowi => self.float_powi(xf, vals[1].into_int_value())?,
            B::FFloor | B::FCeil | B::FRound | B::FTrunc | B::FFract => {
                self.float_unary(b, x, t)?
            }
            B::FClamp => {
                let lo = vals[1].into_float_value();
                let hi = vals[2].into_float_value();
                let lt = self
                    .b
                    .build_float_compare(FloatPredicate::OLT, xf, lo, "")?;
                let y = self.b.build_select(lt, lo, xf, "")?.into_float_value();
                let gt = self.b.build_float_compare(FloatPredicate::OGT, y, hi, "")?;
                self.b.build_select(gt, hi, y, "")?
            }
            B::FIsNan => self
                .b
                .build_float_compare(FloatPredicate::UNO, xf, xf, "")?
                .into(),
            B::FIsFinite | B::FIsInfinite => {
                let a = self
                    .intrinsic(&format!("llvm.fabs.{sfx}"), ft, &[x])?
                    .into_float_value();
                let inf = a.get_type().const_float(f64::INFINITY);
                let pred = if b == B::FIsFinite {
                    FloatPredicate::OLT
                } else {
                    FloatPredicate::OEQ
                };
                self.b.build_float_compare(pred, a, inf, "")?.into()
            }
            B::FIsSignNegative | B::FIsSignPositive => {
                let it = self.int_ty(if sfx == "f64" { 64 } else { 32 });
                let bits = self.b.build_bit_cast(x, it, "")?.into_int_value();
                let pred = if b == B::FIsSignNegative {
                    IntPredicate::SLT
                } else {
                    IntPredicate::SGE
                };
                self.b
                    .build_int_compare(pred, bits, it.const_zero(), "")?
                    .into()
            }
            B::FToBits => self.b.build_bit_cast(x, rt, "")?,
            B::FSignum => {
                let one = fty.const_float(1.0);
                let s = self.intrinsic(&format!("llvm.copysign.{sfx}"), ft, &[one.into(), x])?;
                let nan = self
                    .b
                    .build_float_compare(FloatPredicate::UNO, xf, xf, "")?;
                self.b.build_select(nan, x, s, "")?
            }
            B::FRecip => self.b.build_float_div(fty.const_float(1.0), xf, "")?.into(),
            B::FToDegrees | B::FToRadians => {
                // Rust: f32 multiplies by a rounded f32 constant; f64 as well.
                let k = if b == B::FToDegrees {
                    if sfx == "f64" {
                        180.0f64 / std::f64::consts::PI
                    } else {
                        57.295_78_f32 as f64
                    }
                } else if sfx == "f64" {
                    std::f64::consts::PI / 180.0
                } else {
                    (std::f32::consts::PI / 180.0) as f64
                };
                let k = fty.const_float(k);
                self.b.build_float_mul(xf, k, "")?.into()
            }
            B::FRemEuclid => {
                // r = self % rhs; if r < 0 { r + |rhs| } else { r }
                let y = vals[1];
                let r = self
                    .arith(crate::ops::BinOp::Rem, x, y, t, t)?
                    .into_float_value();
                let neg =
                    self.b
                        .build_float_compare(FloatPredicate::OLT, r, fty.const_zero(), "")?;
                let ay = self
                    .intrinsic(&format!("llvm.fabs.{sfx}"), ft, &[y])?
                    .into_float_value();
                let s = self.b.build_float_add(r, ay, "")?;
                self.b.build_select(neg, s, r, "")?
            }
            B::FDivEuclid => {
                // q = trunc(self / rhs); if self % rhs < 0 { if rhs > 0 { q - 1 } else { q + 1 } } else { q }
                let y = vals[1];
                let yf = y.into_float_value();
                let d = self.b.build_float_div(xf, yf, "")?;
                let q = self.float_unary(B::FTrunc, d.into(), t)?.into_float_value();
                let r = self
                    .arith(crate::ops::BinOp::Rem, x, y, t, t)?
                    .into_float_value();
                let neg =
                    self.b
                        .build_float_compare(FloatPredicate::OLT, r, fty.const_zero(), "")?;
                let pos =
                    self.b
                        .build_float_compare(FloatPredicate::OGT, yf, fty.const_zero(), "")?;
                let qm = self.b.build_float_sub(q, fty.const_float(1.0), "")?;
                let qp = self.b.build_float_add(q, fty.const_float(1.0), "")?;
                let adj = self.b.build_select(pos, qm, qp, "")?.into_float_value();
                self.b.build_select(neg, adj, q, "")?
            }
            B::FPartialCmp => {
                let y = self
                    .b
                    .build_load(vals[1].into_pointer_value(), "")?
                    .into_float_value();
                let ok = self.b.build_float_compare(FloatPredicate::ORD, xf, y, "")?;
                let lt = self.b.build_float_compare(FloatPredicate::OLT, xf, y, "")?;
                let gt = self.b.build_float_compare(FloatPredicate::OGT, xf, y, "")?;
                self.opt_ordering(ret, ok, lt, gt)?
            }
            B::FTotalCmp => {
                let y = self.b.build_load(vals[1].into_pointer_value(), "")?;
                let bits = if sfx == "f64" { 64 } else { 32 };
                let it = self.int_ty(bits);
                let key = |l: &mut Self, v: BasicValueEnum<'ctx>| -> LResult<IntValue<'ctx>> {
                    let i = l.b.build_bit_cast(v, it, "")?.into_int_value();
                    let s =
                        l.b.build_right_shift(i, it.const_int(bits as u64 - 1, false), true, "")?;
                    let s =
                        l.b.build_right_shift(s, it.const_int(1, false), false, "")?;
                    Ok(l.b.build_xor(i, s, "")?)
                };
                let kx = key(self, x)?;
                let ky = key(self, y)?;
                let lt = self.b.build_int_compare(IntPredicate::SLT, kx, ky, "")?;
                let gt = self.b.build_int_compare(IntPredicate::SGT, kx, ky, "")?;
                self.ordering(ret, lt, gt)?
            }
            B::FLogBase => {
                let name = if sfx == "f64" { "log" } else { "logf" };
                let a = self.libm_call(name, &[x], t)?.into_float_value();
                let c = self.libm_call(name, &[vals[1]], t)?.into_float_value();
                self.b.build_float_div(a, c, "")?.into()
            }
            B::FSinCos => {
                let (sn, cn) = if sfx == "f64" {
                    ("sin", "cos")
                } else {
                    ("sinf", "cosf")
                };
                let s = self.libm_call(sn, &[x], t)?;
                let c = self.libm_call(cn, &[x], t)?;
                let st = self.llty(ret).into_struct_type();
                let mut agg = st.get_undef();
                agg = self
                    .b
                    .build_insert_value(agg, s, 0, "")?
                    .into_struct_value();
                agg = self
                    .b
                    .build_insert_value(agg, c, 1, "")?
                    .into_struct_value();
                agg.into()
            }
            other => return Err(internal(format!("float builtin {other:?}"))),
        })
    }

    /// Integer builtins added with the catalogue.
    fn int_builtin2(
        &mut self,
        name: Builtin,
        vals: &[BasicValueEnum<'ctx>],
        t: &Ty,
    ) -> LResult<BasicValueEnum<'ctx>> {
        use Builtin as B;
        let x = vals[0].into_int_value();
        let it = x.get_type();
        let zero = it.const_zero();
        let signed = matches!(t, Ty::Int(i) if i.signed());
        Ok(match name {
            B::ISignum => {
                let pos = self.b.build_int_compare(IntPredicate::SGT, x, zero, "")?;
                let neg = self.b.build_int_compare(IntPredicate::SLT, x, zero, "")?;
                let one = self
                    .b
                    .build_select(pos, it.const_int(1, false), zero, "")?
                    .into_int_value();
                self.b.build_select(neg, it.const_all_ones(), one, "")?
            }
            B::IIsPositive => self
                .b
                .build_int_compare(IntPredicate::SGT, x, zero, "")?
                .into(),
            B::IIsNegative => self
                .b
                .build_int_compare(IntPredicate::SLT, x, zero, "")?
                .into(),
            B::IAbsDiff => {
                let y = vals[1].into_int_value();
                let pred = if signed {
                    IntPredicate::SLT
                } else {
                    IntPredicate::ULT
                };
                let lt = self.b.build_int_compare(pred, x, y, "")?;
                let d1 = self.b.build_int_sub(y, x, "")?;
                let d2 = self.b.build_int_sub(x, y, "")?;
                self.b.build_select(lt, d1, d2, "")?
            }
            B::IRemEuclid | B::IDivEuclid => {
                let y = vals[1].into_int_value();
                let r = self.int_div(crate::ops::BinOp::Rem, x, y, signed)?;
                if !signed {
                    if name == B::IRemEuclid {
                        return Ok(r.into());
                    }
                    return Ok(self.int_div(crate::ops::BinOp::Div, x, y, false)?.into());
                }
                let q = self.b.build_int_signed_div(x, y, "")?;
                let rneg = self.b.build_int_compare(IntPredicate::SLT, r, zero, "")?;
                let ypos = self.b.build_int_compare(IntPredicate::SGT, y, zero, "")?;
                if name == B::IRemEuclid {
                    // r < 0: r + |y| (wrapping).
                    let ny = self.b.build_int_neg(y, "")?;
                    let ay = self.b.build_select(ypos, y, ny, "")?.into_int_value();
                    let s = self.b.build_int_add(r, ay, "")?;
                    self.b.build_select(rneg, s, r, "")?
                } else {
                    let one = it.const_int(1, false);
                    let qm = self.b.build_int_sub(q, one, "")?;
                    let qp = self.b.build_int_add(q, one, "")?;
                    let adj = self.b.build_select(ypos, qm, qp, "")?.into_int_value();
                    self.b.build_select(rneg, adj, q, "")?
                }
            }
            other => return Err(internal(format!("int builtin {other:?}"))),
        })
    }

    /// Array and slice builtins: `vals[0]` is a pointer to the array, or the slice
    /// reference `{ptr, len}`.
    fn seq_builtin(
        &mut self,
        b: Builtin,
        vals: &[BasicValueEnum<'ctx>],
        tys: &[Ty],
        ret: &Ty,
    ) -> LResult<V<'ctx>> {
        use Builtin as B;
        let i32t = self.ctx.i32_type();
        let s = match &tys[0] {
            Ty::Array(el, n) => super::place::Seq {
                ptr: vals[0].into_pointer_value(),
                len: i32t.const_int(*n as u64, false),
                elem: (**el).clone(),
                array: true,
            },
            Ty::Slice(el) => {
                let (ptr, len) = self.slice_parts(vals[0].into_struct_value())?;
                super::place::Seq {
                    ptr,
                    len,
                    elem: (**el).clone(),
                    array: false,
                }
            }
            other => {
                return Err(internal(format!(
                    "sequence builtin on {}",
                    self.p.ty_str(other)
                )))
            }
        };
        Ok(match b {
            B::Len => Some(s.len.into()),
            B::IsEmpty => Some(
                self.b
                    .build_int_compare(IntPredicate::EQ, s.len, i32t.const_zero(), "")?
                    .into(),
            ),
            B::AsSlice => {
                let first = self.seq_elem(&s, i32t.const_zero())?;
                Some(self.make_slice(first, &s.elem, s.len)?.into())
            }
            B::First | B::Last => {
                let nonempty =
                    self.b
                        .build_int_compare(IntPredicate::NE, s.len, i32t.const_zero(), "")?;
                let idx = if b == B::First {
                    i32t.const_zero()
                } else {
                    self.b.build_int_sub(s.len, i32t.const_int(1, false), "")?
                };
                // The address is only formed, not read, when the sequence is empty.
                let p = self.seq_elem(&s, idx)?;
                let some = self.option(ret, Some(p.into()))?;
                let none = self.option(ret, None)?;
                Some(self.b.build_select(nonempty, some, none, "")?)
            }
            B::Swap => {
                let (i, j) = (vals[1].into_int_value(), vals[2].into_int_value());
                let len = s.len;
                for k in [i, j] {
                    let ok = self.b.build_int_compare(IntPredicate::ULT, k, len, "")?;
                    self.check_with(ok, |l| l.bounds_abort(len, k))?;
                }
                let pi = self.seq_elem(&s, i)?;
                let pj = self.seq_elem(&s, j)?;
                if !s.elem.is_zst() {
                    let a = self.b.build_load(pi, "")?;
                    let c = self.b.build_load(pj, "")?;
                    self.b.build_store(pi, c)?;
                    self.b.build_store(pj, a)?;
                }
                None
            }
            B::Fill | B::Contains => {
                let idx = self.alloca(&Ty::Int(IntTy::Usize), "seq.i")?;
                let found = self.alloca(&Ty::Bool, "seq.found")?;
                self.b
                    .build_store(found, self.ctx.bool_type().const_zero())?;
                self.b.build_store(idx, i32t.const_zero())?;
                let head = self.new_block("seq.cond");
                let body = self.new_block("seq.body");
                let exit = self.new_block("seq.end");
                self.b.build_unconditional_branch(head)?;
                self.b.position_at_end(head);
                let k = self.b.build_load(idx, "")?.into_int_value();
                let more = self.b.build_int_compare(IntPredicate::ULT, k, s.len, "")?;
                self.b.build_conditional_branch(more, body, exit)?;
                self.b.position_at_end(body);
                let ep = self.seq_elem(&s, k)?;
                if b == B::Fill {
                    if !s.elem.is_zst() {
                        self.b.build_store(ep, vals[1])?;
                    }
                } else {
                    let eq = self.derived_eq(ep, vals[1].into_pointer_value(), &s.elem)?;
                    let hit = self.new_block("seq.hit");
                    let next = self.new_block("seq.next");
                    self.b.build_conditional_branch(eq, hit, next)?;
                    self.b.position_at_end(hit);
                    self.b
                        .build_store(found, self.ctx.bool_type().const_int(1, false))?;
                    self.b.build_unconditional_branch(exit)?;
                    self.b.position_at_end(next);
                }
                let nx = self.b.build_int_add(k, i32t.const_int(1, false), "")?;
                self.b.build_store(idx, nx)?;
                self.b.build_unconditional_branch(head)?;
                self.b.position_at_end(exit);
                if b == B::Contains {
                    Some(self.b.build_load(found, "")?)
                } else {
                    None
                }
            }
            other => return Err(internal(format!("sequence builtin {other:?}"))),
        })
        .map(|v| if ret.is_zst() { None } else { v })
    }

    /// Lowers a builtin macro.
    pub(super) fn mac(&mut self, m: &syn::Macro) -> LResult<V<'ctx>> {
        let body = self.body;
        let call = body
            .macros
            .get(&key(m))
            .ok_or_else(|| internal("unchecked macro"))?;
        match call {
            MacroCall::Print(pieces) => {
                self.print_pieces(pieces)?;
                Ok(None)
            }
            MacroCall::Abort { .. } => {
                self.abort_macro(m, call)?;
                Ok(None)
            }
            MacroCall::Matches { expr, pat, guard } => {
                self.matches_macro(expr, pat, guard.as_deref())
            }
            MacroCall::Nothing => Ok(None),
            MacroCall::TraxOp { instr, args } => {
                let mut regs = Vec::new();
                let mut imms = Vec::new();
                for a in args {
                    match a {
                        TraxArg::Reg(e) => {
                            let t = self.ty_of(e);
                            let v = self.expr(e)?;
                            regs.push(self.val(v, &t));
                        }
                        TraxArg::Imm(i) => imms.push(*i),
                    }
                }
                self.trax(instr, &regs, &imms)
            }
            // `.set noat`: the register allocator may pick `$at` ($1) for the operand,
            // which the assembler otherwise warns about (it would use `$at` only for
            // macro instructions, and these are none).
            MacroCall::Mtc2(n, x) => {
                let v = self.expr(x)?;
                let v = self.val(v, &Ty::Float(FloatTy::F32));
                let i32t = self.ctx.i32_type();
                let bits = self.b.build_bit_cast(v, i32t, "")?;
                let fty = self.ctx.void_type().fn_type(&[i32t.into()], false);
                let ia = self.ctx.create_inline_asm(
                    fty,
                    format!(".set push\n.set noat\nmtc2 $0, $${n}\n.set pop"),
                    "r".into(),
                    true,
                    false,
                    None,
                    false,
                );
                let callable = CallableValue::try_from(ia).map_err(|_| internal("inline asm"))?;
                self.b.build_call(callable, &[bits.into()], "")?;
                Ok(None)
            }
            MacroCall::Mfc2(n) => {
                let i32t = self.ctx.i32_type();
                let fty = i32t.fn_type(&[], false);
                let ia = self.ctx.create_inline_asm(
                    fty,
                    format!(".set push\n.set noat\nmfc2 $0, $${n}\n.set pop"),
                    "=r".into(),
                    true,
                    false,
                    None,
                    false,
                );
                let callable = CallableValue::try_from(ia).map_err(|_| internal("inline asm"))?;
                let r = self
                    .b
                    .build_call(callable, &[], "")?
                    .try_as_basic_value()
                    .basic()
                    .ok_or_else(|| internal("mfc2"))?;
                Ok(Some(self.b.build_bit_cast(r, self.ctx.f32_type(), "")?))
            }
            MacroCall::SymbolAddr(name) => {
                let g = match self.module.get_global(name) {
                    Some(g) => g,
                    None => {
                        let g = self.module.add_global(self.ctx.i8_type(), None, name);
                        g.set_linkage(inkwell::module::Linkage::External);
                        g
                    }
                };
                Ok(Some(
                    g.as_pointer_value()
                        .const_to_int(self.ctx.i32_type())
                        .into(),
                ))
            }
        }
    }
}
