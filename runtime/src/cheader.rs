//! Renders `trax_isa.h`, the TRaX extension for C/C++ kernels built with clang: one
//! `static inline` function per instruction (a macro for instructions with an immediate),
//! each emitting the real instruction word, generated from [`TRAX_INSTRUCTIONS`].
//!
//! The words are built by the assembler: a file-scope assembler macro turns the register
//! name the allocator picked for an operand (`$2`, `$sp`, `$f12`...) into its number, and
//! `.word` ORs the numbers into the instruction's fields.

use crate::isa::{Field, OperandKind, TraxInstr, TraxOp, TRAX_INSTRUCTIONS};
use std::fmt::Write;

/// ABI names LLVM may print for general-purpose registers, with their numbers.
const GPR_ALIASES: [(&str, u32); 33] = [
    ("zero", 0),
    ("at", 1),
    ("v0", 2),
    ("v1", 3),
    ("a0", 4),
    ("a1", 5),
    ("a2", 6),
    ("a3", 7),
    ("t0", 8),
    ("t1", 9),
    ("t2", 10),
    ("t3", 11),
    ("t4", 12),
    ("t5", 13),
    ("t6", 14),
    ("t7", 15),
    ("s0", 16),
    ("s1", 17),
    ("s2", 18),
    ("s3", 19),
    ("s4", 20),
    ("s5", 21),
    ("s6", 22),
    ("s7", 23),
    ("t8", 24),
    ("t9", 25),
    ("k0", 26),
    ("k1", 27),
    ("gp", 28),
    ("sp", 29),
    ("fp", 30),
    ("s8", 30),
    ("ra", 31),
];

/// The C name of an instruction: its mnemonic with `.` replaced by `_` (`trax_gid`).
pub fn c_name(i: &TraxInstr) -> String {
    i.mnemonic.replace('.', "_")
}

fn field_name(f: Field) -> &'static str {
    match f {
        Field::Rs => "rs",
        Field::Rt => "rt",
        Field::Rd => "rd",
        Field::Sa => "sa",
    }
}

/// C type of a register operand (`trax.printd` prints a double).
fn c_type(i: &TraxInstr, kind: OperandKind) -> &'static str {
    match kind {
        OperandKind::GprUse | OperandKind::GprDef => "unsigned int",
        OperandKind::FprUse | OperandKind::FprDef if i.op == TraxOp::PrintF64 => "double",
        OperandKind::FprUse | OperandKind::FprDef => "float",
        OperandKind::Imm5 => "unsigned int",
    }
}

fn regnum_macros(out: &mut String) {
    let nums: Vec<String> = (0..32).map(|n| n.to_string()).collect();
    let nums = nums.join(",");
    out.push_str("__asm__(\n");
    out.push_str("    \".macro __trax_gpr var, reg\\n\"\n");
    let _ = writeln!(out, "    \" .irp n,{nums}\\n\"");
    out.push_str("    \"  .ifc \\\\reg,$\\\\n\\n\"\n");
    out.push_str("    \"   \\\\var = \\\\n\\n\"\n");
    out.push_str("    \"  .endif\\n\"\n");
    out.push_str("    \" .endr\\n\"\n");
    for (name, n) in GPR_ALIASES {
        let _ = writeln!(
            out,
            "    \" .ifc \\\\reg,${name}\\n  \\\\var = {n}\\n .endif\\n\""
        );
    }
    out.push_str("    \".endm\\n\"\n");
    out.push_str("    \".macro __trax_fpr var, reg\\n\"\n");
    let _ = writeln!(out, "    \" .irp n,{nums}\\n\"");
    out.push_str("    \"  .ifc \\\\reg,$f\\\\n\\n\"\n");
    out.push_str("    \"   \\\\var = \\\\n\\n\"\n");
    out.push_str("    \"  .endif\\n\"\n");
    out.push_str("    \" .endr\\n\"\n");
    out.push_str("    \".endm\\n\");\n\n");
}

fn render_instr(out: &mut String, i: &TraxInstr) {
    let name = c_name(i);
    let _ = writeln!(out, "/* {}: {} */", i.mnemonic, i.summary);
    let imms = i
        .operands
        .iter()
        .filter(|o| o.kind == OperandKind::Imm5)
        .count();
    if imms > 0 {
        if imms != i.operands.len() || imms > 1 {
            let _ = writeln!(
                out,
                "/* {name}: not available from C (immediate mixed with registers) */\n"
            );
            return;
        }
        let shift = i.operands[0].field.shift();
        let _ = writeln!(
            out,
            "#define {name}(n) __asm__ volatile(\".word %0\" :: \"i\"(0x{:08x}u | (((n) & 31u) << {shift})) : \"memory\")\n",
            i.base_word()
        );
        return;
    }
    let def = i.operands.iter().find(|o| o.kind.is_def());
    let uses: Vec<_> = i.operands.iter().filter(|o| !o.kind.is_def()).collect();
    let ret = def.map(|d| c_type(i, d.kind)).unwrap_or("void");
    let params: Vec<String> = uses
        .iter()
        .map(|o| format!("{} {}", c_type(i, o.kind), field_name(o.field)))
        .collect();
    let params = if params.is_empty() {
        "void".to_string()
    } else {
        params.join(", ")
    };
    let _ = writeln!(out, "static inline {ret} {name}({params}) {{");
    if let Some(d) = def {
        let _ = writeln!(out, "    {ret} {};", field_name(d.field));
    }
    // Asm operand numbers: the output first, then the inputs in assembly order.
    let mut asm = String::new();
    let mut word = format!("0x{:08x}", i.base_word());
    let ordered = def.into_iter().chain(uses.iter().copied());
    for (k, o) in ordered.enumerate() {
        let f = field_name(o.field);
        let mac = match o.kind {
            OperandKind::FprUse | OperandKind::FprDef => "__trax_fpr",
            _ => "__trax_gpr",
        };
        let _ = write!(asm, "{mac} __trax_{f}, %{k}\\n\\t");
        let _ = write!(word, " | (__trax_{f} << {})", o.field.shift());
    }
    let _ = write!(asm, ".word {word}");
    let constraint = |o: &crate::isa::Operand| match o.kind {
        OperandKind::FprUse | OperandKind::FprDef => "f",
        _ => "r",
    };
    let outputs = def
        .map(|d| format!("\"={}\"({})", constraint(d), field_name(d.field)))
        .unwrap_or_default();
    let inputs: Vec<String> = uses
        .iter()
        .map(|o| format!("\"{}\"({})", constraint(o), field_name(o.field)))
        .collect();
    let _ = writeln!(
        out,
        "    __asm__ volatile(\"{asm}\" : {outputs} : {} : \"memory\");",
        inputs.join(", ")
    );
    if let Some(d) = def {
        let _ = writeln!(out, "    return {};", field_name(d.field));
    }
    out.push_str("}\n\n");
}

/// The complete text of `trax_isa.h`.
pub fn render_c_header() -> String {
    let mut out = String::new();
    out.push_str("/* trax_isa.h: the TRaX instruction-set extension for C and C++ kernels.\n");
    out.push_str(" * Generated from trax_runtime::isa::TRAX_INSTRUCTIONS; do not edit.\n");
    out.push_str(" * Target: clang --target=mipsel-linux-gnu -march=mips32r6 -mfp64. */\n");
    out.push_str("#ifndef TRAX_ISA_H\n#define TRAX_ISA_H\n\n");
    regnum_macros(&mut out);
    for i in TRAX_INSTRUCTIONS {
        render_instr(&mut out, i);
    }
    out.push_str("#endif /* TRAX_ISA_H */\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::isa::decode;
    use std::process::Command;

    #[test]
    fn every_instruction_has_a_c_entry() {
        let h = render_c_header();
        for i in TRAX_INSTRUCTIONS {
            let n = c_name(i);
            assert!(
                h.contains(&format!(" {n}(")),
                "{} missing from the header",
                i.mnemonic
            );
        }
        assert!(!h.contains("not available from C"));
        assert!(h.contains("static inline unsigned int trax_atominc(unsigned int rs)"));
        assert!(h.contains("static inline float trax_fmin(float rs, float rt)"));
        assert!(h.contains("static inline void trax_printd(double rs)"));
        assert!(h.contains("#define trax_stat(n)"));
    }

    /// Compiles a C file that calls every instruction with clang-14 for MIPS32r6 and
    /// checks the object holds every instruction, with the allocator's registers.
    #[test]
    fn header_compiles_with_clang_and_emits_the_right_words() {
        // Unit tests get no target-relative scratch directory: this one removes itself.
        struct Scratch(std::path::PathBuf);
        impl Drop for Scratch {
            fn drop(&mut self) {
                let _ = std::fs::remove_dir_all(&self.0);
            }
        }
        let scratch =
            Scratch(std::env::temp_dir().join(format!("trax-cheader-{}", std::process::id())));
        let dir = &scratch.0;
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join("trax_isa.h"), render_c_header()).unwrap();
        let mut c = String::from("#include \"trax_isa.h\"\n");
        c.push_str("unsigned int inc(unsigned int r) { return trax_atominc(r); }\n");
        c.push_str("float mn(float a, float b) { return trax_fmin(a, b); }\n");
        c.push_str("void all(unsigned int a, unsigned int b, unsigned int d, float x, float y, double z) {\n");
        for i in TRAX_INSTRUCTIONS {
            let n = c_name(i);
            if i.operands.iter().any(|o| o.kind == OperandKind::Imm5) {
                let _ = writeln!(c, "    {n}(3);");
                continue;
            }
            let args: Vec<&str> = i
                .operands
                .iter()
                .filter(|o| !o.kind.is_def())
                .map(|o| match (o.kind, o.field) {
                    (OperandKind::FprUse, _) if i.op == TraxOp::PrintF64 => "z",
                    (OperandKind::FprUse, Field::Rs) => "x",
                    (OperandKind::FprUse, _) => "y",
                    (_, Field::Rs) => "a",
                    (_, Field::Rt) => "b",
                    _ => "d",
                })
                .collect();
            let _ = writeln!(c, "    {n}({});", args.join(", "));
        }
        c.push_str("}\n");
        std::fs::write(dir.join("t.c"), c).unwrap();
        let obj = dir.join("t.o");
        let st = Command::new("clang-14")
            .args([
                "--target=mipsel-linux-gnu",
                "-march=mips32r6",
                "-mfp64",
                "-O2",
                "-c",
            ])
            .arg(dir.join("t.c"))
            .arg("-o")
            .arg(&obj)
            .output()
            .expect("clang-14 is installed");
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
        let dis = Command::new("llvm-objdump-14")
            .arg("-d")
            .arg(&obj)
            .output()
            .expect("llvm-objdump-14 is installed");
        let text = String::from_utf8_lossy(&dis.stdout);
        // Lines look like `   0: 08 10 80 70  <unknown>`.
        let mut words = Vec::new();
        for line in text.lines() {
            let Some((_, rest)) = line.split_once(':') else {
                continue;
            };
            let bytes: Vec<u8> = rest
                .split_whitespace()
                .take(4)
                .map_while(|b| u8::from_str_radix(b, 16).ok())
                .collect();
            if bytes.len() == 4 {
                words.push(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]));
            }
        }
        let ops: Vec<TraxOp> = words
            .iter()
            .filter_map(|&w| decode(w))
            .map(|i| i.op)
            .collect();
        for i in TRAX_INSTRUCTIONS {
            assert!(ops.contains(&i.op), "{} not emitted", i.mnemonic);
        }
        // inc(r): argument in $a0 (4), result in $v0 (2).
        let atom = words
            .iter()
            .find(|&&w| decode(w).map(|i| i.op) == Some(TraxOp::AtomicInc))
            .copied()
            .unwrap();
        assert_eq!((Field::Rs.extract(atom), Field::Rd.extract(atom)), (4, 2));
        // mn(a, b): arguments in $f12, $f14, result in $f0.
        let fmin = words
            .iter()
            .find(|&&w| decode(w).map(|i| i.op) == Some(TraxOp::FMin))
            .copied()
            .unwrap();
        assert_eq!(
            (
                Field::Rs.extract(fmin),
                Field::Rt.extract(fmin),
                Field::Rd.extract(fmin)
            ),
            (12, 14, 0)
        );
        let stat = words
            .iter()
            .find(|&&w| decode(w).map(|i| i.op) == Some(TraxOp::Stat))
            .copied()
            .unwrap();
        assert_eq!(Field::Sa.extract(stat), 3);
    }
}
