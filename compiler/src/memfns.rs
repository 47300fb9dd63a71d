//! Definitions of `memset`, `memcpy` and `memmove`, added to a module only when LLVM's
//! optimiser or code generator introduced calls to them (TRaX has no libc).
//!
//! The bodies are byte loops (plus a word loop for aligned `memset`) with internal linkage,
//! marked `no-builtins` so they are not turned back into calls to themselves.

use inkwell::attributes::AttributeLoc;
use inkwell::context::Context;
use inkwell::module::{Linkage, Module};
use inkwell::values::FunctionValue;
use inkwell::IntPredicate;

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
) -> Result<(), inkwell::builder::BuilderError> {
    f.set_linkage(Linkage::Internal);
    let attr = ctx.create_string_attribute("no-builtins", "");
    f.add_attribute(AttributeLoc::Function, attr);
    let nounwind = ctx.create_enum_attribute(
        inkwell::attributes::Attribute::get_named_enum_kind_id("nounwind"),
        0,
    );
    f.add_attribute(AttributeLoc::Function, nounwind);
    let b = ctx.create_builder();
    let entry = ctx.append_basic_block(f, "entry");
    let fwd_head = ctx.append_basic_block(f, "fwd.cond");
    let fwd_body = ctx.append_basic_block(f, "fwd.body");
    let back_head = ctx.append_basic_block(f, "back.cond");
    let back_body = ctx.append_basic_block(f, "back.body");
    let exit = ctx.append_basic_block(f, "exit");
    let i8t = ctx.i8_type();
    let dst = f.get_nth_param(0).expect("dst").into_pointer_value();
    let len = f.get_last_param().expect("len").into_int_value();
    let it = len.get_type();
    b.position_at_end(entry);
    let idx = b.build_alloca(it, "i")?;
    b.build_store(idx, it.const_zero())?;
    let (src, val) = if name == "memset" {
        let v = f.get_nth_param(1).expect("val").into_int_value();
        (None, Some(b.build_int_truncate_or_bit_cast(v, i8t, "")?))
    } else {
        (
            Some(f.get_nth_param(1).expect("src").into_pointer_value()),
            None,
        )
    };
    // memmove copies backwards when the destination is above the source.
    let backwards = match (name, src) {
        ("memmove", Some(s)) => {
            let d = b.build_ptr_to_int(dst, it, "")?;
            let s = b.build_ptr_to_int(s, it, "")?;
            b.build_int_compare(IntPredicate::UGT, d, s, "")?
        }
        _ => ctx.bool_type().const_zero(),
    };
    b.build_store(idx, it.const_zero())?;
    if let Some(v) = val {
        // memset of a word-aligned, whole-word region (the common case: zeroing a local
        // array) stores words: four times fewer iterations than the byte loop.
        let word_head = ctx.append_basic_block(f, "word.cond");
        let word_body = ctx.append_basic_block(f, "word.body");
        let i32t = ctx.i32_type();
        let d = b.build_ptr_to_int(dst, it, "")?;
        let bits = b.build_or(d, len, "")?;
        let low = b.build_and(bits, it.const_int(3, false), "")?;
        let aligned = b.build_int_compare(IntPredicate::EQ, low, it.const_zero(), "")?;
        b.build_conditional_branch(aligned, word_head, fwd_head)?;
        b.position_at_end(word_head);
        let i = b.build_load(idx, "")?.into_int_value();
        let more = b.build_int_compare(IntPredicate::ULT, i, len, "")?;
        b.build_conditional_branch(more, word_body, exit)?;
        b.position_at_end(word_body);
        let byte = b.build_int_z_extend(v, i32t, "")?;
        let word = b.build_int_mul(byte, i32t.const_int(0x0101_0101, false), "")?;
        // SAFETY: `i + 4 <= len` (len is a multiple of 4), within the caller's buffer.
        let bp = unsafe { b.build_gep(dst, &[i], "")? };
        let wp = b.build_pointer_cast(bp, i32t.ptr_type(inkwell::AddressSpace::default()), "")?;
        let store = b.build_store(wp, word)?;
        // Only fails for non-memory instructions; a store always accepts an alignment.
        let _ = store.set_alignment(4);
        let n = b.build_int_add(i, it.const_int(4, false), "")?;
        b.build_store(idx, n)?;
        b.build_unconditional_branch(word_head)?;
        b.position_at_end(fwd_head);
    } else {
        b.build_conditional_branch(backwards, back_head, fwd_head)?;
    }
    let copy = |i: inkwell::values::IntValue<'ctx>| -> Result<(), inkwell::builder::BuilderError> {
        // SAFETY: `i < len`, within the caller-provided buffers, as the C contract requires.
        let dp = unsafe { b.build_gep(dst, &[i], "")? };
        let v = match (src, val) {
            (Some(s), _) => {
                // SAFETY: as above.
                let sp = unsafe { b.build_gep(s, &[i], "")? };
                b.build_load(sp, "")?.into_int_value()
            }
            (None, Some(v)) => v,
            _ => unreachable!("memset has a value, copies a source"),
        };
        b.build_store(dp, v)?;
        Ok(())
    };
    // Forward loop.
    b.position_at_end(fwd_head);
    let i = b.build_load(idx, "")?.into_int_value();
    let more = b.build_int_compare(IntPredicate::ULT, i, len, "")?;
    b.build_conditional_branch(more, fwd_body, exit)?;
    b.position_at_end(fwd_body);
    copy(i)?;
    let n = b.build_int_add(i, it.const_int(1, false), "")?;
    b.build_store(idx, n)?;
    b.build_unconditional_branch(fwd_head)?;
    // Backward loop (index counts down from len).
    b.position_at_end(back_head);
    let i = b.build_load(idx, "")?.into_int_value();
    let more = b.build_int_compare(IntPredicate::ULT, i, len, "")?;
    b.build_conditional_branch(more, back_body, exit)?;
    b.position_at_end(back_body);
    let j = b.build_int_sub(len, b.build_int_add(i, it.const_int(1, false), "")?, "")?;
    copy(j)?;
    let n = b.build_int_add(i, it.const_int(1, false), "")?;
    b.build_store(idx, n)?;
    b.build_unconditional_branch(back_head)?;
    b.position_at_end(exit);
    b.build_return(Some(&dst))?;
    Ok(())
}
