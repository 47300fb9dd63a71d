//! Definitions of `memset`, `memcpy` and `memmove`, added to a module only when LLVM's
//! optimiser or code generator introduced calls to them (TRaX has no libc).
//!
//! The bodies are loops over words when every address and the length are word-aligned,
//! else over bytes (memmove backwards when the destination is above the source), built
//! directly in SSA form with the pointers as induction variables: they are added after the
//! optimisation pipeline. Internal linkage, marked `no-builtins` so they are not turned
//! back into calls to themselves.

use inkwell::attributes::AttributeLoc;
use inkwell::basic_block::BasicBlock;
use inkwell::builder::{Builder, BuilderError};
use inkwell::context::Context;
use inkwell::module::{Linkage, Module};
use inkwell::values::{BasicValue, FunctionValue, IntValue, PointerValue};
use inkwell::{AddressSpace, IntPredicate};

/// Defines every referenced but undefined memory function of `module`.
pub fn provide<'ctx>(ctx: &'ctx Context, module: &Module<'ctx>) -> Result<(), String> {
    // Memory intrinsics may become library calls during code generation.
    let mut wanted: Vec<&str> = Vec::new();
    for f in module.get_functions() {
        let n = f.get_name().to_string_lossy().into_owned();
        for name in ["memset", "memcpy", "memmove"] {
            if n == name || n.starts_with(&format!("llvm.{name}.")) {
                wanted.push(name);
            }
        }
    }
    let i8p = ctx.i8_type().ptr_type(inkwell::AddressSpace::default());
    let i32t = ctx.i32_type();
    for name in ["memset", "memcpy", "memmove"] {
        if !wanted.contains(&name) {
            continue;
        }
        if module.get_function(name).is_none() {
            let second = if name == "memset" {
                i32t.into()
            } else {
                i8p.into()
            };
            let fty = i8p.fn_type(&[i8p.into(), second, i32t.into()], false);
            module.add_function(name, fty, None);
        }
        if let Some(f) = module.get_function(name) {
            if f.count_basic_blocks() == 0 {
                define(ctx, f, name).map_err(|e| format!("defining {name}: {e}"))?;
            }
        }
    }
    Ok(())
}

fn define<'ctx>(
    ctx: &'ctx Context,
    f: FunctionValue<'ctx>,
    name: &str,
) -> Result<(), BuilderError> {
    f.set_linkage(Linkage::Internal);
    let attr = ctx.create_string_attribute("no-builtins", "");
    f.add_attribute(AttributeLoc::Function, attr);
    let nounwind = ctx.create_enum_attribute(
        inkwell::attributes::Attribute::get_named_enum_kind_id("nounwind"),
        0,
    );
    f.add_attribute(AttributeLoc::Function, nounwind);
    let b = ctx.create_builder();
    let i32t = ctx.i32_type();
    let entry = ctx.append_basic_block(f, "entry");
    let start = ctx.append_basic_block(f, "start");
    let exit = ctx.append_basic_block(f, "exit");
    let dst = f.get_nth_param(0).expect("dst").into_pointer_value();
    let len = f.get_last_param().expect("len").into_int_value();
    let it = len.get_type();
    b.position_at_end(entry);
    let empty = b.build_int_compare(IntPredicate::EQ, len, it.const_zero(), "")?;
    b.build_conditional_branch(empty, exit, start)?;
    b.position_at_end(start);
    let d = b.build_ptr_to_int(dst, it, "")?;
    let (src, fill) = if name == "memset" {
        let v = f.get_nth_param(1).expect("val").into_int_value();
        (
            None,
            Some(b.build_int_truncate_or_bit_cast(v, ctx.i8_type(), "")?),
        )
    } else {
        (
            Some(f.get_nth_param(1).expect("src").into_pointer_value()),
            None,
        )
    };
    // Whole words when every address and the length are word-aligned (the common case:
    // zeroing or copying a local array): four times fewer iterations.
    let s = match src {
        Some(s) => Some(b.build_ptr_to_int(s, it, "")?),
        None => None,
    };
    let mut bits = b.build_or(d, len, "")?;
    if let Some(s) = s {
        bits = b.build_or(bits, s, "")?;
    }
    let low = b.build_and(bits, it.const_int(3, false), "")?;
    let aligned = b.build_int_compare(IntPredicate::EQ, low, it.const_zero(), "")?;
    let aligned_len = ctx.append_basic_block(f, "aligned");
    let quads = ctx.append_basic_block(f, "quads");
    let words = ctx.append_basic_block(f, "words");
    let bytes = ctx.append_basic_block(f, "bytes");
    let body = Body {
        ctx,
        b: &b,
        f,
        exit,
        dst,
        len,
    };
    match (name, s) {
        // memmove copies backwards when the destination is above the source.
        ("memmove", Some(s)) => {
            let back = ctx.append_basic_block(f, "back");
            let fwd = ctx.append_basic_block(f, "fwd");
            let up = b.build_int_compare(IntPredicate::UGT, d, s, "")?;
            b.build_conditional_branch(up, back, fwd)?;
            body.backward(back, s)?;
            b.position_at_end(fwd);
            b.build_conditional_branch(aligned, aligned_len, bytes)?;
        }
        _ => {
            b.build_conditional_branch(aligned, aligned_len, bytes)?;
        }
    }
    // Four words an iteration when the length allows (a local array of 16-byte multiples:
    // the traversal stacks of the prelude).
    b.position_at_end(aligned_len);
    let tail = b.build_and(len, it.const_int(15, false), "")?;
    let by_four = b.build_int_compare(IntPredicate::EQ, tail, it.const_zero(), "")?;
    // A word of the fill byte, made before the loops.
    let word = match fill {
        Some(v) => {
            let byte = b.build_int_z_extend(v, i32t, "")?;
            Some(b.build_int_mul(byte, i32t.const_int(0x0101_0101, false), "")?)
        }
        None => None,
    };
    b.build_conditional_branch(by_four, quads, words)?;
    body.forward(quads, src, Unit::Word(word), 4)?;
    body.forward(words, src, Unit::Word(word), 1)?;
    body.forward(bytes, src, Unit::Byte(fill), 1)?;
    b.position_at_end(exit);
    b.build_return(Some(&dst))?;
    Ok(())
}

/// What one iteration of a forward loop stores: a word or a byte, of the fill value
/// (`Some`) or copied from the source (`None`).
enum Unit<'ctx> {
    Word(Option<IntValue<'ctx>>),
    Byte(Option<IntValue<'ctx>>),
}

/// What the loops of one memory function share: the function, its builder, its exit
/// block, and the destination and length (> 0) parameters.
struct Body<'a, 'ctx> {
    ctx: &'ctx Context,
    b: &'a Builder<'ctx>,
    f: FunctionValue<'ctx>,
    exit: BasicBlock<'ctx>,
    dst: PointerValue<'ctx>,
    len: IntValue<'ctx>,
}

impl<'ctx> Body<'_, 'ctx> {
    /// Block `from`: a loop storing `per_turn` `unit`s an iteration from `dst` up to
    /// `dst + len` (a multiple of that), then a branch to the exit. A copy loads an
    /// iteration's units before it stores them (safe for memmove's forward direction). The
    /// pointers are the induction variables.
    fn forward(
        &self,
        from: BasicBlock<'ctx>,
        src: Option<PointerValue<'ctx>>,
        unit: Unit<'ctx>,
        per_turn: u64,
    ) -> Result<(), BuilderError> {
        let Body {
            ctx,
            b,
            f,
            exit,
            dst,
            len,
        } = *self;
        let it = len.get_type();
        let (elem, step, fill) = match unit {
            Unit::Word(v) => (ctx.i32_type(), 4, v),
            Unit::Byte(v) => (ctx.i8_type(), 1, v),
        };
        let ptr = elem.ptr_type(AddressSpace::default());
        let body = ctx.append_basic_block(f, "loop");
        b.position_at_end(from);
        let end = b.build_int_add(b.build_ptr_to_int(dst, it, "")?, len, "")?;
        let d0 = b.build_pointer_cast(dst, ptr, "")?;
        let s0 = match src {
            Some(s) => Some(b.build_pointer_cast(s, ptr, "")?),
            None => None,
        };
        b.build_unconditional_branch(body)?;
        b.position_at_end(body);
        let p = b.build_phi(ptr, "p")?;
        let q = match s0 {
            Some(_) => Some(b.build_phi(ptr, "q")?),
            None => None,
        };
        let pv = p.as_basic_value().into_pointer_value();
        let qv = q.map(|q| q.as_basic_value().into_pointer_value());
        let mut vals = Vec::new();
        for k in 0..per_turn {
            vals.push(match (qv, fill) {
                (Some(q), _) => {
                    // SAFETY: `k < per_turn` elements before the end, within the source
                    // buffer (the C contract).
                    let at = unsafe { b.build_gep(q, &[it.const_int(k, false)], "")? };
                    let load = b.build_load(at, "")?;
                    if let Some(i) = load.as_instruction_value() {
                        // Only fails for non-memory instructions.
                        let _ = i.set_alignment(step);
                    }
                    load
                }
                (None, Some(v)) => v.into(),
                (None, None) => unreachable!("a copy has a source, a fill a value"),
            });
        }
        for (k, v) in (0..per_turn).zip(vals) {
            // SAFETY: as above, within the destination buffer.
            let at = unsafe { b.build_gep(pv, &[it.const_int(k, false)], "")? };
            let store = b.build_store(at, v)?;
            // Only fails for non-memory instructions; a store always accepts an alignment.
            let _ = store.set_alignment(step);
        }
        let next = [it.const_int(per_turn, false)];
        // SAFETY: at most one past the last element stored, within or one past the caller's
        // buffers (the C contract).
        let pn = unsafe { b.build_gep(pv, &next, "")? };
        let qn = match qv {
            // SAFETY: as above, for the source buffer.
            Some(q) => Some(unsafe { b.build_gep(q, &next, "")? }),
            None => None,
        };
        let at = b.build_ptr_to_int(pn, it, "")?;
        let done = b.build_int_compare(IntPredicate::EQ, at, end, "")?;
        b.build_conditional_branch(done, exit, body)?;
        p.add_incoming(&[(&d0, from), (&pn, body)]);
        if let (Some(q), Some(s0), Some(qn)) = (q, s0, qn) {
            q.add_incoming(&[(&s0, from), (&qn, body)]);
        }
        Ok(())
    }

    /// Block `from`: copies `len` bytes from `src` (an address) to `dst`, last byte first
    /// (memmove with the destination above the source), then branches to the exit.
    fn backward(&self, from: BasicBlock<'ctx>, src: IntValue<'ctx>) -> Result<(), BuilderError> {
        let (b, dst, len) = (self.b, self.dst, self.len);
        let it = len.get_type();
        let i8p = self.ctx.i8_type().ptr_type(AddressSpace::default());
        let body = self.ctx.append_basic_block(self.f, "back.loop");
        b.position_at_end(from);
        let s = b.build_int_to_ptr(src, i8p, "")?;
        b.build_unconditional_branch(body)?;
        b.position_at_end(body);
        let i = b.build_phi(it, "i")?;
        let iv = i.as_basic_value().into_int_value();
        let j = b.build_int_sub(iv, it.const_int(1, false), "")?;
        // SAFETY: `j < len`, within the caller's buffers (the C contract).
        let sp = unsafe { b.build_gep(s, &[j], "")? };
        let v = b.build_load(sp, "")?;
        // SAFETY: as above.
        let dp = unsafe { b.build_gep(dst, &[j], "")? };
        b.build_store(dp, v)?;
        let done = b.build_int_compare(IntPredicate::EQ, j, it.const_zero(), "")?;
        b.build_conditional_branch(done, self.exit, body)?;
        i.add_incoming(&[(&len, from), (&j, body)]);
        Ok(())
    }
}
