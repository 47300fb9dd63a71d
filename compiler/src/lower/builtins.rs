//! Lowering of builtin methods, builtin macros and TRaX instructions (inline asm).

use super::{LResult, LowerError, Lowerer, V};
use crate::ty::{FloatTy, IntTy, SimdTy, Ty};
use crate::typeck::{key, Builtin, FmtPiece, MacroCall, TraxArg};
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
        name: &str,
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
            "trunc" => trunc,
            "floor" => {
                let gt = b.build_float_compare(FloatPredicate::OGT, trunc, x, "")?;
                let m = b.build_float_sub(trunc, one, "")?;
                b.build_select(gt, m, trunc, "")?.into_float_value()
            }
            "ceil" => {
                let lt = b.build_float_compare(FloatPredicate::OLT, trunc, x, "")?;
                let p = b.build_float_add(trunc, one, "")?;
                b.build_select(lt, p, trunc, "")?.into_float_value()
            }
            "round" => {
                let frac = b.build_float_sub(fabs, tabs, "")?;
                let half =
                    b.build_float_compare(FloatPredicate::OGE, frac, ft.const_float(0.5), "")?;
                let up = b.build_float_add(tabs, one, "")?;
                let m = b.build_select(half, up, tabs, "")?.into_float_value();
                copysign(self, m)?
            }
            "fract" => b.build_float_sub(x, trunc, "")?,
            _ => return Err(LowerError::Internal(format!("float op {name}"))),
        };
        // NaN and infinities pass through.
        let fin = self.b.build_float_compare(
            FloatPredicate::OLT,
            fabs,
            ft.const_float(f64::INFINITY),
            "",
        )?;
        let keep = if name == "fract" {
            ft.const_float(f64::NAN)
        } else {
            x
        };
        Ok(self.b.build_select(fin, out, keep, "")?)
    }

    /// Lowers a builtin method or function; `vals[0]` is the receiver for methods.
    pub(super) fn builtin(
        &mut self,
        b: Builtin,
        vals: &[BasicValueEnum<'ctx>],
        tys: &[Ty],
        ret: &Ty,
    ) -> LResult<V<'ctx>> {
        let rt = self.llty(ret);
        let v = match b {
            Builtin::Float(name) => {
                let t = &tys[0];
                let sfx = Self::fsuffix(t);
                let x = vals[0];
                let ft = x.get_type();
                match name {
                    "sqrt" | "abs" => {
                        let n = if name == "abs" { "fabs" } else { "sqrt" };
                        self.intrinsic(&format!("llvm.{n}.{sfx}"), ft, &[x])?
                    }
                    "min" | "max" => self.float_minmax(
                        name == "min",
                        x.into_float_value(),
                        vals[1].into_float_value(),
                    )?,
                    "copysign" => {
                        self.intrinsic(&format!("llvm.copysign.{sfx}"), ft, &[x, vals[1]])?
                    }
                    "mul_add" => {
                        // r6 `maddf.fmt fd, fs, ft`: fd = fd + fs * ft, one rounding. LLVM 14
                        // does not select it for `llvm.fma`, which would call `fmaf`.
                        let fty = ft.fn_type(&[ft.into(), ft.into(), ft.into()], false);
                        let fmt = if sfx == "f64" { "d" } else { "s" };
                        let ia = self.ctx.create_inline_asm(
                            fty,
                            format!("maddf.{fmt} $0, $1, $2"),
                            "=f,f,f,0".into(),
                            false,
                            false,
                            None,
                            false,
                        );
                        let callable = CallableValue::try_from(ia)
                            .map_err(|_| LowerError::Internal("inline asm callable".into()))?;
                        let args: [BasicMetadataValueEnum; 3] =
                            [x.into(), vals[1].into(), vals[2].into()];
                        self.b
                            .build_call(callable, &args, "")?
                            .try_as_basic_value()
                            .basic()
                            .ok_or_else(|| LowerError::Internal("maddf".into()))?
                    }
                    "powi" => self.float_powi(x.into_float_value(), vals[1].into_int_value())?,
                    "floor" | "ceil" | "round" | "trunc" | "fract" => {
                        self.float_unary(name, x, t)?
                    }
                    "clamp" => {
                        let xv = x.into_float_value();
                        let lo = vals[1].into_float_value();
                        let hi = vals[2].into_float_value();
                        let lt = self
                            .b
                            .build_float_compare(FloatPredicate::OLT, xv, lo, "")?;
                        let y = self.b.build_select(lt, lo, xv, "")?.into_float_value();
                        let gt = self.b.build_float_compare(FloatPredicate::OGT, y, hi, "")?;
                        self.b.build_select(gt, hi, y, "")?
                    }
                    "is_nan" => self
                        .b
                        .build_float_compare(
                            FloatPredicate::UNO,
                            x.into_float_value(),
                            x.into_float_value(),
                            "",
                        )?
                        .into(),
                    "is_finite" | "is_infinite" => {
                        let a = self
                            .intrinsic(&format!("llvm.fabs.{sfx}"), ft, &[x])?
                            .into_float_value();
                        let inf = a.get_type().const_float(f64::INFINITY);
                        let pred = if name == "is_finite" {
                            FloatPredicate::OLT
                        } else {
                            FloatPredicate::OEQ
                        };
                        self.b.build_float_compare(pred, a, inf, "")?.into()
                    }
                    "is_sign_negative" | "is_sign_positive" => {
                        let it = self.int_ty(if sfx == "f64" { 64 } else { 32 });
                        let bits = self.b.build_bit_cast(x, it, "")?.into_int_value();
                        let pred = if name == "is_sign_negative" {
                            IntPredicate::SLT
                        } else {
                            IntPredicate::SGE
                        };
                        self.b
                            .build_int_compare(pred, bits, it.const_zero(), "")?
                            .into()
                    }
                    "to_bits" => self.b.build_bit_cast(x, rt, "")?,
                    "signum" => {
                        let one = x.into_float_value().get_type().const_float(1.0);
                        let s =
                            self.intrinsic(&format!("llvm.copysign.{sfx}"), ft, &[one.into(), x])?;
                        let nan = self.b.build_float_compare(
                            FloatPredicate::UNO,
                            x.into_float_value(),
                            x.into_float_value(),
                            "",
                        )?;
                        self.b.build_select(nan, x, s, "")?
                    }
                    "recip" => {
                        let one = x.into_float_value().get_type().const_float(1.0);
                        self.b
                            .build_float_div(one, x.into_float_value(), "")?
                            .into()
                    }
                    "to_degrees" | "to_radians" => {
                        let k = if name == "to_degrees" {
                            180.0 / std::f64::consts::PI
                        } else {
                            std::f64::consts::PI / 180.0
                        };
                        let k = x.into_float_value().get_type().const_float(k);
                        self.b.build_float_mul(x.into_float_value(), k, "")?.into()
                    }
                    _ => return Err(LowerError::Internal(format!("float builtin {name}"))),
                }
            }
            Builtin::FromBits(_) => self.b.build_bit_cast(vals[0], rt, "")?,
            Builtin::Int(name) => self.int_builtin(name, vals, &tys[0])?,
            Builtin::Ptr(name) | Builtin::StdPtr(name) => {
                let p = vals[0].into_pointer_value();
                match name {
                    "add" | "sub" | "offset" => {
                        let mut i = vals[1].into_int_value();
                        if name == "sub" {
                            i = self.b.build_int_neg(i, "")?;
                        }
                        // SAFETY: pointer arithmetic on a raw pointer, as in the source program.
                        unsafe { self.b.build_gep(p, &[i], "")? }.into()
                    }
                    "is_null" => self.b.build_is_null(p, "")?.into(),
                    "read" => self.b.build_load(p, "")?,
                    "read_volatile" => {
                        let v = self.b.build_load(p, "")?;
                        if let Some(i) = v.as_instruction_value() {
                            i.set_volatile(true)
                                .map_err(|e| LowerError::Internal(e.to_string()))?;
                        }
                        v
                    }
                    "write" | "write_volatile" => {
                        let s = self.b.build_store(p, vals[1])?;
                        if name == "write_volatile" {
                            s.set_volatile(true)
                                .map_err(|e| LowerError::Internal(e.to_string()))?;
                        }
                        return Ok(None);
                    }
                    _ => return Err(LowerError::Internal(format!("pointer builtin {name}"))),
                }
            }
            Builtin::Simd(s, name) => self.simd_builtin(s, name, vals, rt)?,
            Builtin::Len(n) => self.ctx.i32_type().const_int(n as u64, false).into(),
        };
        Ok(if ret.is_zst() { None } else { Some(v) })
    }

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
        name: &str,
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
            "min" => sel(
                self,
                if signed {
                    IntPredicate::SLT
                } else {
                    IntPredicate::ULT
                },
                x,
                vals[1].into_int_value(),
            )?,
            "max" => sel(
                self,
                if signed {
                    IntPredicate::SGT
                } else {
                    IntPredicate::UGT
                },
                x,
                vals[1].into_int_value(),
            )?,
            "clamp" => {
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
            "abs" => {
                let neg = b.build_int_neg(x, "")?;
                let isneg = b.build_int_compare(IntPredicate::SLT, x, lt.const_zero(), "")?;
                b.build_select(isneg, neg, x, "")?
            }
            "wrapping_add" => b.build_int_add(x, vals[1].into_int_value(), "")?.into(),
            "wrapping_sub" => b.build_int_sub(x, vals[1].into_int_value(), "")?.into(),
            "wrapping_mul" => b.build_int_mul(x, vals[1].into_int_value(), "")?.into(),
            "wrapping_neg" => b.build_int_neg(x, "")?.into(),
            "count_ones" | "leading_zeros" | "trailing_zeros" => {
                let n = match name {
                    "count_ones" => format!("llvm.ctpop.i{bits}"),
                    "leading_zeros" => format!("llvm.ctlz.i{bits}"),
                    _ => format!("llvm.cttz.i{bits}"),
                };
                let mut args = vec![x.into()];
                if name != "count_ones" {
                    args.push(self.ctx.bool_type().const_zero().into());
                }
                let r = self.intrinsic(&n, lt.into(), &args)?.into_int_value();
                self.b
                    .build_int_cast_sign_flag(r, self.ctx.i32_type(), false, "")?
                    .into()
            }
            "is_power_of_two" => {
                let r = self
                    .intrinsic(&format!("llvm.ctpop.i{bits}"), lt.into(), &[x.into()])?
                    .into_int_value();
                self.b
                    .build_int_compare(IntPredicate::EQ, r, lt.const_int(1, false), "")?
                    .into()
            }
            "rotate_left" | "rotate_right" => {
                let amt =
                    self.b
                        .build_int_cast_sign_flag(vals[1].into_int_value(), lt, false, "")?;
                let n = if name == "rotate_left" {
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
            "swap_bytes" => {
                if bits == 8 {
                    x.into()
                } else {
                    self.intrinsic(&format!("llvm.bswap.i{bits}"), lt.into(), &[x.into()])?
                }
            }
            "pow" => {
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
            _ => return Err(LowerError::Internal(format!("int builtin {name}"))),
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
        name: &str,
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
            "splat" => lanes(self, rt, &[vals[0]; 4])?,
            "new" => lanes(self, rt, &vals[..4])?,
            "get" => {
                let idx = vals[1].into_int_value();
                let ok = self.b.build_int_compare(
                    IntPredicate::ULT,
                    idx,
                    i32t.const_int(4, false),
                    "",
                )?;
                self.check_with(ok, |l| l.bounds_abort(4, idx))?;
                self.b
                    .build_extract_element(vals[0].into_vector_value(), idx, "")?
            }
            "min" | "max" => self.simd_minmax(
                name == "min",
                vals[0].into_vector_value(),
                vals[1].into_vector_value(),
            )?,
            "sqrt" => self.intrinsic("llvm.sqrt.v4f32", rt, &[vals[0]])?,
            // Not `llvm.fabs.v4f32`: LLVM 14 selects `fmax_a.w x, x` for it, which keeps
            // the sign. Clearing the sign bit is exact for every input, NaNs included.
            "abs" => self.simd_sign_bit(vals[0].into_vector_value(), false)?,
            "mul_add" => {
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
            "lt" | "le" | "gt" | "ge" | "eq" => {
                let pred = match name {
                    "lt" => FloatPredicate::OLT,
                    "le" => FloatPredicate::OLE,
                    "gt" => FloatPredicate::OGT,
                    "ge" => FloatPredicate::OGE,
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
            "select" => {
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
            "to_i32x4" => self.intrinsic("llvm.fptosi.sat.v4i32.v4f32", rt, &[vals[0]])?,
            "to_f32x4" => self
                .b
                .build_signed_int_to_float(
                    vals[0].into_vector_value(),
                    self.ctx.f32_type().vec_type(4),
                    "",
                )?
                .into(),
            "any" | "all" if !f => {
                let nz = self.b.build_int_compare(
                    IntPredicate::NE,
                    vals[0].into_vector_value(),
                    v4i.const_zero(),
                    "",
                )?;
                let n = if name == "any" {
                    "llvm.vector.reduce.or.v4i1"
                } else {
                    "llvm.vector.reduce.and.v4i1"
                };
                self.intrinsic(n, self.ctx.bool_type().into(), &[nz.into()])?
            }
            _ => return Err(LowerError::Internal(format!("simd builtin {name}"))),
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

    fn print_str(&mut self, s: &str) -> LResult<()> {
        if s.is_empty() {
            return Ok(());
        }
        let i32t = self.ctx.i32_type();
        let g = self.string_global(s);
        let addr = g.as_pointer_value().const_to_int(i32t);
        let len = i32t.const_int(s.len() as u64, false);
        self.trax(instr(TraxOp::PrintStr), &[addr.into(), len.into()], &[])?;
        Ok(())
    }

    fn print_value(&mut self, v: BasicValueEnum<'ctx>, t: &Ty) -> LResult<()> {
        let i32t = self.ctx.i32_type();
        match t {
            Ty::Ref(_, inner) => {
                let x = self.b.build_load(v.into_pointer_value(), "")?;
                self.print_value(x, inner)?;
            }
            Ty::Str => {
                let sv = v.into_struct_value();
                let a = self.b.build_extract_value(sv, 0, "")?;
                let l = self.b.build_extract_value(sv, 1, "")?;
                self.trax(instr(TraxOp::PrintStr), &[a, l], &[])?;
            }
            Ty::Float(FloatTy::F32) => {
                self.trax(instr(TraxOp::PrintF32), &[v], &[])?;
            }
            Ty::Float(FloatTy::F64) => {
                self.trax(instr(TraxOp::PrintF64), &[v], &[])?;
            }
            Ty::Bool => {
                self.trax(instr(TraxOp::PrintBool), &[v], &[])?;
            }
            Ty::Char => {
                self.trax(instr(TraxOp::PrintChar), &[v], &[])?;
            }
            Ty::Int(it) if it.bits() == 64 => {
                let x = v.into_int_value();
                let lo = self.b.build_int_truncate(x, i32t, "")?;
                let hi =
                    self.b
                        .build_right_shift(x, x.get_type().const_int(32, false), false, "")?;
                let hi = self.b.build_int_truncate(hi, i32t, "")?;
                let op = if it.signed() {
                    TraxOp::PrintI64
                } else {
                    TraxOp::PrintU64
                };
                self.trax(instr(op), &[lo.into(), hi.into()], &[])?;
            }
            Ty::Int(it) => {
                let x =
                    self.b
                        .build_int_cast_sign_flag(v.into_int_value(), i32t, it.signed(), "")?;
                let op = if it.signed() {
                    TraxOp::PrintInt
                } else {
                    TraxOp::PrintUint
                };
                self.trax(instr(op), &[x.into()], &[])?;
            }
            other => {
                return Err(LowerError::Internal(format!(
                    "print {}",
                    self.p.ty_str(other)
                )))
            }
        }
        Ok(())
    }

    /// Lowers a builtin macro.
    pub(super) fn mac(&mut self, m: &syn::Macro) -> LResult<V<'ctx>> {
        let body = self.body;
        let call = body
            .macros
            .get(&key(m))
            .ok_or_else(|| LowerError::Internal("unchecked macro".into()))?;
        match call {
            MacroCall::Print(pieces) => {
                // Merge adjacent literal pieces.
                let mut lit = String::new();
                for p in pieces {
                    match p {
                        FmtPiece::Lit(s) => lit.push_str(s),
                        // `{:?}` prints as `{}` (the print instructions render `Display`).
                        FmtPiece::Arg(e) | FmtPiece::Debug(e) => {
                            let t = self.ty_of(e);
                            let v = self.expr(e)?;
                            self.print_str(&std::mem::take(&mut lit))?;
                            if let Some(v) = v {
                                self.print_value(v, &t)?;
                            }
                        }
                    }
                }
                self.print_str(&lit)?;
                Ok(None)
            }
            MacroCall::Abort { .. } => {
                self.abort_macro(m, call)?;
                Ok(None)
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
            MacroCall::Mtc2(n, x) => {
                let v = self.expr(x)?;
                let v = self.val(v, &Ty::Float(FloatTy::F32));
                let i32t = self.ctx.i32_type();
                let bits = self.b.build_bit_cast(v, i32t, "")?;
                let fty = self.ctx.void_type().fn_type(&[i32t.into()], false);
                let ia = self.ctx.create_inline_asm(
                    fty,
                    format!("mtc2 $0, $${n}"),
                    "r".into(),
                    true,
                    false,
                    None,
                    false,
                );
                let callable = CallableValue::try_from(ia)
                    .map_err(|_| LowerError::Internal("inline asm".into()))?;
                self.b.build_call(callable, &[bits.into()], "")?;
                Ok(None)
            }
            MacroCall::Mfc2(n) => {
                let i32t = self.ctx.i32_type();
                let fty = i32t.fn_type(&[], false);
                let ia = self.ctx.create_inline_asm(
                    fty,
                    format!("mfc2 $0, $${n}"),
                    "=r".into(),
                    true,
                    false,
                    None,
                    false,
                );
                let callable = CallableValue::try_from(ia)
                    .map_err(|_| LowerError::Internal("inline asm".into()))?;
                let r = self
                    .b
                    .build_call(callable, &[], "")?
                    .try_as_basic_value()
                    .basic()
                    .ok_or_else(|| LowerError::Internal("mfc2".into()))?;
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
