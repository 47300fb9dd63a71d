//! Renders `trax_isa.h`, the TRaX extension for C/C++ kernels built with clang: one
//! `TRAX_INLINE` function (always inlined, without debug information) per instruction (a
//! macro for instructions with an immediate), each emitting the real instruction word,
//! generated from [`TRAX_INSTRUCTIONS`].
//!
//! The words are built by the assembler: a file-scope assembler macro turns the register
//! name the allocator picked for an operand (`$2`, `$sp`, `$f12`...) into its number, and
//! `.word` ORs the numbers into the instruction's fields.

use crate::abi::{self, Kind, Scalar, Struct, StructLayout};
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
    let _ = writeln!(out, "TRAX_INLINE {ret} {name}({params}) {{");
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
    // Pure operations may be merged and moved like arithmetic; the rest are effects.
    let (volatile, clobber) = if i.op.is_pure() {
        ("", "")
    } else {
        (" volatile", " : \"memory\"")
    };
    let _ = writeln!(
        out,
        "    __asm__{volatile}(\"{asm}\" : {outputs} : {}{clobber});",
        inputs.join(", ")
    );
    if let Some(d) = def {
        let _ = writeln!(out, "    return {};", field_name(d.field));
    }
    out.push_str("}\n\n");
}

/// `TRAX_INLINE`, the storage class of the headers' functions: always inlined and without
/// debug information of their own, so their instructions belong to the caller's source
/// line (a `trax_panic` is reported, profiled and annotated where it is called, like a
/// TRaX-Rust builtin, and the wrappers add no frames).
const TRAX_INLINE_DEF: &str = "#ifndef TRAX_INLINE\n#define TRAX_INLINE static inline __attribute__((always_inline, nodebug))\n#endif\n\n";

/// The complete text of `trax_isa.h`.
pub fn render_c_header() -> String {
    let mut out = String::new();
    out.push_str("/* trax_isa.h: the TRaX instruction-set extension for C and C++ kernels.\n");
    out.push_str(" * Generated from trax_runtime::isa::TRAX_INSTRUCTIONS; do not edit.\n");
    out.push_str(" * Target: clang --target=mipsel-linux-gnu -march=mips32r6 -mfp64. */\n");
    out.push_str("#ifndef TRAX_ISA_H\n#define TRAX_ISA_H\n\n");
    out.push_str(TRAX_INLINE_DEF);
    regnum_macros(&mut out);
    for i in TRAX_INSTRUCTIONS {
        render_instr(&mut out, i);
    }
    out.push_str("#endif /* TRAX_ISA_H */\n");
    out
}

/// The C type of a field or element kind (`unsigned int`, `float`, `trax_camera_t`).
fn c_kind(kind: Kind) -> String {
    match kind {
        Kind::Scalar(Scalar::U32) => "unsigned int".into(),
        Kind::Scalar(Scalar::F32) => "float".into(),
        Kind::Struct(l) => l().c_name.into(),
    }
}

/// The structs of `trax.h` besides the header, in the contract's order: the header's
/// component reference ([`abi::Component`]) and every component's element struct, each
/// rendered from its `abi` layout.
pub fn c_structs() -> Vec<StructLayout> {
    let mut out = vec![abi::Component::layout()];
    for c in abi::SCENE_COMPONENTS {
        if let Kind::Struct(l) = c.element {
            let l = l();
            if !out.iter().any(|s| s.name == l.name) {
                out.push(l);
            }
        }
    }
    out
}

/// The C fields of a contract struct: type, name and array length (0: scalar; arrays of
/// arrays flattened, which keeps the bytes where they are).
fn c_fields(l: &StructLayout) -> Vec<(String, String, usize)> {
    l.fields
        .iter()
        .map(|f| {
            let n = if f.dims.is_empty() {
                0
            } else {
                f.dims.iter().product()
            };
            (c_kind(f.kind), f.name.to_string(), n)
        })
        .collect()
}

/// The C type of scene header field `name` (a name of [`crate::abi::scene_header_fields`])
/// and its array length (0: scalar), from the header's layout; `None` for a field the
/// header does not have.
pub fn header_field_type(name: &str) -> Option<(String, usize)> {
    let h = abi::SceneHeader::layout();
    c_fields(&h)
        .into_iter()
        .find(|(_, f, _)| f == name)
        .map(|(t, _, n)| (t, n))
}

fn render_struct(out: &mut String, name: &str, doc: &str, fields: &[(String, String, usize)]) {
    let _ = writeln!(out, "/* {doc} */\ntypedef struct {name} {{");
    for (ty, f, n) in fields {
        if *n == 0 {
            let _ = writeln!(out, "    {ty} {f};");
        } else {
            let _ = writeln!(out, "    {ty} {f}[{n}];");
        }
    }
    let _ = writeln!(out, "}} {name};\n");
}

/// Friendly wrappers with the Rust prelude's names, over the generated instruction
/// functions of `trax_isa.h`.
const C_API: &str = r#"/* ---- Threads and time (the Rust prelude's names) ---- */
TRAX_INLINE unsigned int trax_thread_id(void) { return trax_tid(); }
TRAX_INLINE unsigned int trax_tm_id(void) { return trax_tmid(); }
TRAX_INLINE unsigned int trax_global_id(void) { return trax_gid(); }
TRAX_INLINE unsigned int trax_num_threads(void) { return trax_nthreads(); }
TRAX_INLINE unsigned int trax_num_tms(void) { return trax_ntms(); }

/* ---- Global registers: atomics, barriers, semaphores ---- */
TRAX_INLINE unsigned int trax_atomic_inc(unsigned int reg) { return trax_atominc(reg); }
TRAX_INLINE unsigned int trax_atomic_dec(unsigned int reg) { return trax_atomdec(reg); }
TRAX_INLINE unsigned int trax_atomic_add(unsigned int reg, unsigned int v) { return trax_atomadd(reg, v); }
TRAX_INLINE unsigned int trax_global_read(unsigned int reg) { return trax_gread(reg); }
TRAX_INLINE void trax_global_write(unsigned int reg, unsigned int v) { trax_gwrite(reg, v); }
TRAX_INLINE unsigned int trax_inc_reset(unsigned int reg) { return trax_increset(reg); }
/* Declares the kernel's work counter for sampled simulation (trax run --sample): ITEMS
 * work items handed out from global register COUNTER, one trax_atomic_inc each. Thread 0
 * records it; call it before the first item is taken (the Rust prelude's declare_work). */
TRAX_INLINE void trax_declare_work(unsigned int counter, unsigned int items) {
    if (trax_gid() == 0) {
        trax_gwrite(TRAX_WORK_ITEMS_REG, items);
        trax_gwrite(TRAX_WORK_COUNTER_REG, counter + 1);
    }
}
TRAX_INLINE void trax_sem_acquire(unsigned int reg) { trax_semacq(reg); }
TRAX_INLINE void trax_sem_release(unsigned int reg) { trax_semrel(reg); }

/* ---- Arithmetic ---- */
TRAX_INLINE float trax_min(float a, float b) { return trax_fmin(a, b); }
TRAX_INLINE float trax_max(float a, float b) { return trax_fmax(a, b); }
TRAX_INLINE float trax_sqrt(float x) { return __builtin_sqrtf(x); }
TRAX_INLINE void trax_count_ray(void) { trax_stat(0); }

/* ---- Statistics counters (the Rust prelude's trax::stat): TRAX_STAT_COUNTERS of them,
 * summed over every thread, reported by trax run and trax native; counter 0 counts rays.
 * Adding is one zero-cost instruction (trax.statadd); an index past the counters stops
 * the program. ---- */
TRAX_INLINE void trax_stat_add(unsigned int counter, unsigned int n) { trax_statadd(counter, n); }

/* ---- Printing: one instruction per value, printed as it runs (a line printed piece by
 * piece by several threads at once interleaves; trax native buffers lines per thread) ---- */
TRAX_INLINE void trax_print_int(int v) { trax_printi((unsigned int)v); }
TRAX_INLINE void trax_print_uint(unsigned int v) { trax_printu(v); }
TRAX_INLINE void trax_print_float(float v) { trax_printf(v); }
TRAX_INLINE void trax_print_double(double v) { trax_printd(v); }
TRAX_INLINE void trax_print_char(unsigned int c) { trax_printc(c); }
TRAX_INLINE void trax_print_bool(int b) { trax_printb(b != 0); }
TRAX_INLINE void trax_print_i64(long long v) {
    trax_printl((unsigned int)v, (unsigned int)((unsigned long long)v >> 32));
}
TRAX_INLINE void trax_print_u64(unsigned long long v) {
    trax_printul((unsigned int)v, (unsigned int)(v >> 32));
}
TRAX_INLINE void trax_print_str(const char *s) {
    unsigned int n = 0;
    while (s[n]) n++;
#ifdef TRAX_HOST
    __trax_host_print_str(s, n);
#else
    trax_prints((unsigned int)s, n);
#endif
}

/* Stops the whole program with MESSAGE, reported like a Rust panic (with the PC's
 * source line and a backtrace). */
TRAX_INLINE __attribute__((noreturn)) void trax_panic(const char *message) {
    unsigned int n = 0;
    while (message[n]) n++;
#ifdef TRAX_HOST
    __trax_host_panic(message, n);
#else
    trax_abort(TRAX_ABORT_PANIC, (unsigned int)message, n);
#endif
    __builtin_unreachable();
}

/* ---- Fused pipelines: inputs and outputs in coprocessor 2 (runtime::isa::COP2_REGS) ---- */
#ifdef TRAX_HOST
#define trax_mtc2(n, x) __trax_host_mtc2(n, x)
#define trax_mfc2(n) __trax_host_mfc2(n)
#else
#define trax_mtc2(n, x) do { float __trax_x = (x); unsigned int __trax_b; \
    __builtin_memcpy(&__trax_b, &__trax_x, 4); \
    __asm__ volatile("mtc2 %0, $" #n :: "r"(__trax_b) : "memory"); } while (0)
#define trax_mfc2(n) __extension__ ({ unsigned int __trax_b; float __trax_x; \
    __asm__ volatile("mfc2 %0, $" #n : "=r"(__trax_b) :: "memory"); \
    __builtin_memcpy(&__trax_x, &__trax_b, 4); __trax_x; })
#endif
TRAX_INLINE void trax_set_pipe_general(void) { trax_setpipe(0); }
TRAX_INLINE void trax_set_pipe_box(void) { trax_setpipe(1); }
TRAX_INLINE void trax_set_pipe_tri(void) { trax_setpipe(2); }
/* Entry distance of the ray (origin o, inverse direction inv) into the box [lo, hi]. */
TRAX_INLINE float trax_pipe_box_test(const float o[3], const float inv[3],
                                       const float lo[3], const float hi[3]) {
    trax_mtc2(0, o[0]); trax_mtc2(1, o[1]); trax_mtc2(2, o[2]);
    trax_mtc2(3, inv[0]); trax_mtc2(4, inv[1]); trax_mtc2(5, inv[2]);
    trax_mtc2(6, lo[0]); trax_mtc2(7, lo[1]); trax_mtc2(8, lo[2]);
    trax_mtc2(9, hi[0]); trax_mtc2(10, hi[1]); trax_mtc2(11, hi[2]);
    return trax_boxtest();
}
/* Hit distance of the ray (o, d) with triangle (a, b, c); barycentrics by
 * trax_pipe_tri_u/v. */
TRAX_INLINE float trax_pipe_tri_test(const float o[3], const float d[3], const float a[3],
                                       const float b[3], const float c[3]) {
    trax_mtc2(0, o[0]); trax_mtc2(1, o[1]); trax_mtc2(2, o[2]);
    trax_mtc2(3, d[0]); trax_mtc2(4, d[1]); trax_mtc2(5, d[2]);
    trax_mtc2(12, a[0]); trax_mtc2(13, a[1]); trax_mtc2(14, a[2]);
    trax_mtc2(15, b[0]); trax_mtc2(16, b[1]); trax_mtc2(17, b[2]);
    trax_mtc2(18, c[0]); trax_mtc2(19, c[1]); trax_mtc2(20, c[2]);
    return trax_tritest();
}
TRAX_INLINE float trax_pipe_tri_u(void) { return trax_mfc2(21); }
TRAX_INLINE float trax_pipe_tri_v(void) { return trax_mfc2(22); }

/* ---- Ray streams (STRaTA; the Rust prelude's trax::stream) ----
 * trax_stream_write(b, rec) writes a ray record to buffer b (LIFO per buffer; a full
 * memory stops the program). trax_stream_schedule() waits until every live thread of the
 * TM calls it, then returns the buffer the TM works on next, or TRAX_STREAM_DONE when
 * every live thread of the chip waits with the memory empty. trax_stream_read(rec) takes
 * the newest ray of that buffer (0 when it is empty). */
#define TRAX_STREAM_DONE 0xFFFFFFFFu
typedef unsigned int trax_stream_record_t[TRAX_STREAM_RECORD_WORDS];
TRAX_INLINE unsigned int trax_stream_capacity(void) { return trax_strcap(); }
TRAX_INLINE unsigned int trax_stream_buffers(void) { return trax_scene_stream_buffers(); }
TRAX_INLINE void trax_stream_write(unsigned int buffer, const unsigned int rec[TRAX_STREAM_RECORD_WORDS]) {
    trax_strwstart(buffer);
    for (unsigned int i = 0; i < TRAX_STREAM_RECORD_WORDS; i++) trax_strw(rec[i]);
    trax_strwend();
}
TRAX_INLINE int trax_stream_read(unsigned int rec[TRAX_STREAM_RECORD_WORDS]) {
    if (!trax_strrstart()) return 0;
    for (unsigned int i = 0; i < TRAX_STREAM_RECORD_WORDS; i++) rec[i] = trax_strr();
    trax_strrend();
    return 1;
}
TRAX_INLINE unsigned int trax_stream_schedule(void) { return trax_strsched(); }
TRAX_INLINE unsigned int trax_stream_size(unsigned int buffer) { return trax_strsize(buffer); }
"#;

/// The complete text of `trax.h`: the instruction functions (`trax_isa.h`), the scene
/// structs, the header fields (each an extern linker symbol `__trax_scene_<field>`, so
/// the image builder lays out only the components the kernel reads) and accessors.
pub fn render_trax_h() -> String {
    let mut out = String::new();
    out.push_str("/* trax.h: the kernel API for C and C++ kernels (clang-14, MIPS32r6).\n");
    out.push_str(" * Generated from trax_runtime (isa.rs, abi.rs, cheader.rs) by `trax header`;\n");
    out.push_str(" * `trax build` puts it on the include path itself. Do not edit. */\n");
    out.push_str("#ifndef TRAX_H\n#define TRAX_H\n\n");
    out.push_str(TRAX_INLINE_DEF);
    out.push_str(
        "/* TRAX_HOST: the same API on the host (`trax native`), over trax_host.h. */\n\
         #ifdef TRAX_HOST\n#include \"trax_host.h\"\n\
         #define TRAX_PTR(T, addr) ((T *)__trax_host_ptr(addr))\n\
         #else\n#include \"trax_isa.h\"\n\
         #define TRAX_PTR(T, addr) ((T *)(__UINTPTR_TYPE__)(addr))\n#endif\n\n",
    );
    out.push_str("#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n");
    out.push_str(
        "/* The kernel entry point, run by every hardware thread. */\nvoid trax_main(void);\n\n",
    );
    for kind in (0..32).filter_map(crate::isa::AbortKind::from_code) {
        let _ = writeln!(
            out,
            "#define TRAX_ABORT_{} {}u /* {} */",
            format!("{kind:?}").to_uppercase(),
            kind as u32,
            kind.describe()
        );
    }
    let _ = writeln!(
        out,
        "#define TRAX_SCENE_MAGIC 0x{:08x}u\n#define TRAX_SCENE_VERSION {}u\n#define TRAX_SCENE_HEADER_ADDR 0x{:08x}u",
        abi::SCENE_MAGIC,
        abi::SCENE_VERSION,
        abi::SCENE_HEADER_ADDR
    );
    let _ = writeln!(
        out,
        "/* Words of a ray record in the stream memory (48-byte rays, thesis 3.2.1). */\n#define TRAX_STREAM_RECORD_WORDS {}u\n",
        abi::STREAM_RECORD_BYTES / 4
    );
    let _ = writeln!(
        out,
        "/* Statistics counters (trax_stat_add). */\n#define TRAX_STAT_COUNTERS {}u\n/* Global registers of the work counter declared for sampled simulation\n * (trax_declare_work): its register plus one, and the items it hands out. */\n#define TRAX_WORK_COUNTER_REG {}u\n#define TRAX_WORK_ITEMS_REG {}u\n",
        crate::counters::NUM_STATS,
        abi::WORK_COUNTER_REG,
        abi::WORK_ITEMS_REG
    );
    for st in c_structs() {
        let doc = st.doc.split_whitespace().collect::<Vec<_>>().join(" ");
        let doc = doc.trim_end_matches('.');
        render_struct(&mut out, st.c_name, doc, &c_fields(&st));
    }
    let fields = c_fields(&abi::SceneHeader::layout());
    render_struct(
        &mut out,
        abi::SceneHeader::layout().c_name,
        "the scene header at TRAX_SCENE_HEADER_ADDR (kernels read fields through the symbols below)",
        &fields,
    );
    out.push_str(
        "/* Header fields: each symbol is the field's address, defined by the trax linker. */\n",
    );
    out.push_str("#ifndef TRAX_HOST\n");
    for (t, f, n) in &fields {
        let arr = if *n == 0 {
            String::new()
        } else {
            format!("[{n}]")
        };
        let _ = writeln!(
            out,
            "extern const {t} {}{f}{arr};",
            abi::SCENE_SYMBOL_PREFIX
        );
    }
    out.push_str("#else\n");
    let offsets = abi::scene_header_fields();
    for ((t, f, n), (_, off)) in fields.iter().zip(&offsets) {
        let addr = abi::SCENE_HEADER_ADDR + *off as u32;
        let p = abi::SCENE_SYMBOL_PREFIX;
        if *n == 0 {
            let _ = writeln!(
                out,
                "#define {p}{f} (*(const {t} *)__trax_host_ptr(0x{addr:08x}u))"
            );
        } else {
            let _ = writeln!(
                out,
                "#define {p}{f} ((const {t} *)__trax_host_ptr(0x{addr:08x}u))"
            );
        }
    }
    out.push_str("#endif\n");
    out.push_str("\n/* ---- Scene access ---- */\n");
    let p = abi::SCENE_SYMBOL_PREFIX;
    for (t, f, n) in &fields {
        match (abi::component(f), *n) {
            (Some(c), _) => {
                let el = c_kind(c.element);
                let cst = match c.access {
                    abi::Access::ReadOnly => "const ",
                    abi::Access::ReadWrite => "",
                };
                // A range's address is its `.addr`; an address slot is the address.
                let addr = match c.slot {
                    abi::Slot::Range => ".addr",
                    abi::Slot::Addr => "",
                };
                let _ = writeln!(
                    out,
                    "TRAX_INLINE {cst}{el} *trax_scene_{f}(void) {{ return TRAX_PTR({cst}{el}, {p}{f}{addr}); }}"
                );
                if c.slot == abi::Slot::Range {
                    let _ = writeln!(
                        out,
                        "TRAX_INLINE unsigned int trax_scene_{f}_count(void) {{ return {p}{f}.count; }}"
                    );
                }
            }
            (None, 0) => {
                let _ = writeln!(
                    out,
                    "TRAX_INLINE {t} trax_scene_{f}(void) {{ return {p}{f}; }}"
                );
            }
            (None, _) if f == "reserved" => {}
            (None, _) => {
                let _ = writeln!(
                    out,
                    "TRAX_INLINE const {t} *trax_scene_{f}(void) {{ return {p}{f}; }}"
                );
            }
        }
    }
    out.push_str(
        "/* Writes pixel (x, y), linear RGB; row 0 is the top of the image. */\n\
         TRAX_INLINE void trax_set_pixel(unsigned int x, unsigned int y, float r, float g, float b) {\n\
         \x20   trax_pixel_t *p = trax_scene_framebuffer() + y * trax_scene_width() + x;\n\
         \x20   p->r = r;\n    p->g = g;\n    p->b = b;\n}\n\n",
    );
    out.push_str(C_API);
    out.push_str(
        "\n/* ---- Elementary functions: the prelude's libm (trax::libm), one implementation\n\
         \x20* for Rust and C, so trax_sinf(x) gives the bits of Rust's x.sin() on the machine\n\
         \x20* and natively (f32 within 0.51 ULP, f64 within 1 ULP, C99 Annex F special\n\
         \x20* values). Linked when called. */\n",
    );
    for f in libm_functions() {
        let _ = writeln!(out, "{}", f.c_decl());
    }
    out.push_str("\n#ifdef __cplusplus\n}\n#endif\n\n#endif /* TRAX_H */\n");
    out
}

/// The complete text of `trax_host.h`: the instruction functions of `trax_isa.h` as
/// extern functions of the host runtime (`trax native` links C kernels with a Rust shim
/// over the host prelude that defines them, see the root crate's `clang::host_shim`).
pub fn render_host_h() -> String {
    let mut out = String::new();
    out.push_str("/* trax_host.h: the TRaX instructions on the host (`trax native`). Generated; do not edit. */\n");
    out.push_str(
        "#ifndef TRAX_HOST_H\n#define TRAX_HOST_H\n#ifdef __cplusplus\nextern \"C\" {\n#endif\n",
    );
    out.push_str("unsigned char *__trax_host_ptr(unsigned int addr);\n");
    out.push_str("void __trax_host_print_str(const char *s, unsigned int n);\n");
    out.push_str(
        "__attribute__((noreturn)) void __trax_host_panic(const char *s, unsigned int n);\n",
    );
    out.push_str("void __trax_host_mtc2(unsigned int reg, float x);\n");
    out.push_str("float __trax_host_mfc2(unsigned int reg);\n");
    for i in TRAX_INSTRUCTIONS {
        let name = c_name(i);
        if i.operands.iter().any(|o| o.kind == OperandKind::Imm5) {
            let _ = writeln!(
                out,
                "void __trax_host_{name}(unsigned int n);\n#define {name}(n) __trax_host_{name}(n)"
            );
            continue;
        }
        let def = i.operands.iter().find(|o| o.kind.is_def());
        let ret = def.map(|d| c_type(i, d.kind)).unwrap_or("void");
        let params: Vec<String> = i
            .operands
            .iter()
            .filter(|o| !o.kind.is_def())
            .map(|o| format!("{} {}", c_type(i, o.kind), field_name(o.field)))
            .collect();
        let params = if params.is_empty() {
            "void".to_string()
        } else {
            params.join(", ")
        };
        let _ = writeln!(out, "{ret} {name}({params});");
    }
    out.push_str("#ifdef __cplusplus\n}\n#endif\n#endif /* TRAX_HOST_H */\n");
    out
}

/// Rust parameter list and return type of instruction `i` as the host shim defines it:
/// `(params, ret)`, e.g. `("rs: u32, rt: u32", " -> u32")`.
pub fn rust_signature(i: &TraxInstr) -> (String, String) {
    let rty = |k: OperandKind| match k {
        OperandKind::FprUse | OperandKind::FprDef if i.op == TraxOp::PrintF64 => "f64",
        OperandKind::FprUse | OperandKind::FprDef => "f32",
        _ => "u32",
    };
    let params: Vec<String> = i
        .operands
        .iter()
        .filter(|o| !o.kind.is_def())
        .map(|o| format!("{}: {}", field_name(o.field), rty(o.kind)))
        .collect();
    let ret = i
        .operands
        .iter()
        .find(|o| o.kind.is_def())
        .map(|d| format!(" -> {}", rty(d.kind)))
        .unwrap_or_default();
    (params.join(", "), ret)
}

/// A type in the signature of a `trax::libm` function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LibmTy {
    /// `f32` / `float`.
    F32,
    /// `f64` / `double`.
    F64,
    /// `i32` / `int`.
    I32,
    /// `&mut f32` / `float *`.
    MutF32,
    /// `&mut f64` / `double *`.
    MutF64,
}

impl LibmTy {
    fn parse(t: &str) -> Option<LibmTy> {
        Some(match t.trim() {
            "f32" => LibmTy::F32,
            "f64" => LibmTy::F64,
            "i32" => LibmTy::I32,
            "&mut f32" => LibmTy::MutF32,
            "&mut f64" => LibmTy::MutF64,
            _ => return None,
        })
    }

    /// The C type.
    pub fn c(self) -> &'static str {
        match self {
            LibmTy::F32 => "float",
            LibmTy::F64 => "double",
            LibmTy::I32 => "int",
            LibmTy::MutF32 => "float *",
            LibmTy::MutF64 => "double *",
        }
    }

    /// The Rust type of an `extern "C"` function (raw pointers for references).
    pub fn rust_ffi(self) -> &'static str {
        match self {
            LibmTy::F32 => "f32",
            LibmTy::F64 => "f64",
            LibmTy::I32 => "i32",
            LibmTy::MutF32 => "*mut f32",
            LibmTy::MutF64 => "*mut f64",
        }
    }
}

/// A public function of the prelude's `libm.rs`, as C kernels call it: `trax_<name>`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LibmFn {
    /// The Rust (and C library) name: `sinf`, `atan2`, `sincosf`, ...
    pub name: String,
    /// Parameters (name, type).
    pub params: Vec<(String, LibmTy)>,
    /// Result type (`None`: nothing).
    pub ret: Option<LibmTy>,
}

impl LibmFn {
    /// The C declaration in `trax.h`: `float trax_sinf(float x);`.
    pub fn c_decl(&self) -> String {
        let params: Vec<String> = self
            .params
            .iter()
            .map(|(n, t)| format!("{} {n}", t.c()).replace("* ", "*"))
            .collect();
        let ret = self.ret.map(LibmTy::c).unwrap_or("void");
        format!("{ret} trax_{}({});", self.name, params.join(", "))
    }

    /// The Rust definition that exports it under its C name (see [`libm_c_exports`]).
    pub fn rust_export(&self) -> String {
        let params: Vec<String> = self
            .params
            .iter()
            .map(|(n, t)| format!("{n}: {}", t.rust_ffi()))
            .collect();
        let args: Vec<String> = self
            .params
            .iter()
            .map(|(n, t)| match t {
                LibmTy::MutF32 | LibmTy::MutF64 => format!("&mut *{n}"),
                _ => n.clone(),
            })
            .collect();
        let ret = self
            .ret
            .map(|t| format!(" -> {}", t.rust_ffi()))
            .unwrap_or_default();
        let call = format!("trax::libm::{}({})", self.name, args.join(", "));
        if self
            .params
            .iter()
            .any(|(_, t)| matches!(t, LibmTy::MutF32 | LibmTy::MutF64))
        {
            format!(
                "/// `trax::libm::{n}` for C.\n///\n/// # Safety\n/// The pointers must be valid for writes (C passes its own variables).\n#[no_mangle]\npub unsafe extern \"C\" fn trax_{n}({}){ret} {{\n    // SAFETY: the caller passes writable pointers (see above).\n    unsafe {{ {call} }}\n}}\n",
                params.join(", "),
                n = self.name
            )
        } else {
            format!(
                "/// `trax::libm::{n}` for C.\n#[no_mangle]\npub extern \"C\" fn trax_{n}({}){ret} {{\n    {call}\n}}\n",
                params.join(", "),
                n = self.name
            )
        }
    }
}

/// The public functions of the prelude's `libm.rs` (`pub fn name(params) -> ret {` on one
/// line each), read from its source: C kernels get each as `trax_<name>` (`trax.h`
/// declares them; [`libm_c_exports`] defines them over `trax::libm`), so there is one
/// implementation for Rust and C, on the machine and natively.
pub fn libm_functions() -> Vec<LibmFn> {
    let src = crate::prelude::file("libm.rs").expect("libm.rs is a prelude file");
    let mut out = Vec::new();
    for line in src.lines() {
        let Some(rest) = line.strip_prefix("pub fn ") else {
            continue;
        };
        let parsed = (|| {
            let (name, rest) = rest.split_once('(')?;
            let (params, rest) = rest.split_once(')')?;
            let ret = match rest.trim().trim_end_matches('{').trim() {
                "" => None,
                r => Some(LibmTy::parse(r.strip_prefix("->")?)?),
            };
            let params = params
                .split(',')
                .filter(|p| !p.trim().is_empty())
                .map(|p| {
                    let (n, t) = p.split_once(':')?;
                    Some((n.trim().to_string(), LibmTy::parse(t)?))
                })
                .collect::<Option<Vec<_>>>()?;
            Some(LibmFn {
                name: name.trim().to_string(),
                params,
                ret,
            })
        })();
        // A signature this reader does not know is a test failure
        // (`libm_functions_cover_every_public_function`), not a silent gap.
        if let Some(f) = parsed {
            out.push(f);
        }
    }
    out
}

/// TRaX-Rust (and Rust) source defining every [`libm_functions`] entry under its C name
/// `trax_<name>` over `trax::libm`: the trax compiler builds it for C kernels on the
/// machine, rustc into `trax native`'s host program.
pub fn libm_c_exports() -> String {
    let mut s = String::from(
        "// The prelude's libm under trax.h's C names (trax_runtime::cheader::libm_c_exports).\n\n",
    );
    for f in libm_functions() {
        s += &f.rust_export();
        s.push('\n');
    }
    s
}

/// The complete text of `trax.hpp`: the C++ layer over `trax.h` (`runtime/cxx/trax.hpp.in`:
/// the prelude's `Vec3`, rays, hits, surface points, camera, scene access, `pixel_share`,
/// triangle and box tests, BVH traversal and sampling, operation for operation), with the
/// prelude's constants ([`HPP_CONSTANTS`]) read from its sources.
pub fn render_trax_hpp() -> String {
    let mut consts = String::new();
    for &(file, name) in HPP_CONSTANTS {
        let c = prelude_const(file, name)
            .unwrap_or_else(|e| panic!("trax.hpp: prelude constant {file}::{name}: {e}"));
        let _ = writeln!(consts, "{}", c.to_cpp());
    }
    TRAX_HPP_IN.replace("@CONSTANTS@\n", &consts)
}

/// The C++ layer, with `@CONSTANTS@` where the constants go.
const TRAX_HPP_IN: &str = include_str!("../cxx/trax.hpp.in");

/// The prelude constants `trax.hpp` uses: (prelude file, name).
pub const HPP_CONSTANTS: &[(&str, &str)] = &[
    ("math.rs", "POW2_126"),
    ("ray.rs", "NO_HIT"),
    ("ray.rs", "POINT_ERROR"),
    ("scene.rs", "NO_PIXEL"),
    ("layout.rs", "PIXEL_COUNTER_REG"),
    ("scene.rs", "PIXEL_BLOCK"),
    ("bvh.rs", "STACK_SIZE"),
    ("bvh.rs", "SLAB_FAR_SCALE"),
    ("bvh.rs", "ERR_T"),
    ("bvh.rs", "ERR_XY"),
    ("bvh.rs", "ERR_Z"),
];

/// A constant of the prelude, evaluated as rustc does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PreludeConst {
    /// `const NAME: u32 = ...`.
    U32(&'static str, u32),
    /// `const NAME: f32 = ...`.
    F32(&'static str, f32),
}

impl PreludeConst {
    /// The C++ definition: `constexpr unsigned int NAME = 0x...u;` or `constexpr float
    /// NAME = <hexadecimal float>f;` (exact: no decimal rounding between the languages).
    pub fn to_cpp(self) -> String {
        match self {
            PreludeConst::U32(n, v) => format!("constexpr unsigned int {n} = {v:#x}u;"),
            PreludeConst::F32(n, v) => {
                format!("constexpr float {n} = {}f; /* {v:e} */", hex_float(v))
            }
        }
    }
}

/// `x` (finite) as a C hexadecimal floating literal without suffix, exactly.
pub fn hex_float(x: f32) -> String {
    let b = x.to_bits();
    let sign = if b >> 31 != 0 { "-" } else { "" };
    let exp = ((b >> 23) & 0xFF) as i32;
    let frac = b & 0x7F_FFFF;
    if exp == 0 && frac == 0 {
        return format!("{sign}0x0p+0");
    }
    // Subnormals as 0x0.fffffep-126, normals as 0x1.fffffep(e).
    let (lead, e) = if exp == 0 { (0, -126) } else { (1, exp - 127) };
    format!("{sign}0x{lead}.{:06x}p{e:+}", frac << 1)
}

/// Reads `const NAME: TYPE = EXPR;` from prelude file `file` and evaluates it: EXPR is a
/// literal or `literal / literal` (f32 division, as rustc's constant evaluation does it);
/// TYPE is `u32` or `f32`.
pub fn prelude_const(file: &str, name: &'static str) -> Result<PreludeConst, String> {
    let src = crate::prelude::file(file).ok_or("no such prelude file")?;
    let key = format!("const {name}: ");
    let at = src
        .lines()
        .map(str::trim_start)
        .find_map(|l| {
            l.strip_prefix("pub ")
                .unwrap_or(l)
                .strip_prefix(key.as_str())
        })
        .ok_or("not found as `const NAME: TYPE = VALUE;` on one line")?;
    let (ty, rest) = at.split_once(" = ").ok_or("no `=`")?;
    let expr = rest
        .split_once(';')
        .map(|(e, _)| e.trim())
        .ok_or("no `;` on the line")?;
    let lit = |t: &str| t.trim().replace('_', "");
    match ty {
        "u32" => {
            let t = lit(expr);
            let v = match t.strip_prefix("0x") {
                Some(h) => u32::from_str_radix(h, 16),
                None => t.parse(),
            }
            .map_err(|e| format!("`{expr}`: {e}"))?;
            Ok(PreludeConst::U32(name, v))
        }
        "f32" => {
            let parse = |t: &str| {
                lit(t)
                    .trim_end_matches("f32")
                    .parse::<f32>()
                    .map_err(|e| format!("`{expr}`: {e}"))
            };
            let v = match expr.split_once(" / ") {
                Some((a, b)) => parse(a)? / parse(b)?,
                None => parse(expr)?,
            };
            if !v.is_finite() {
                return Err(format!("`{expr}` is not finite"));
            }
            Ok(PreludeConst::F32(name, v))
        }
        t => Err(format!("type `{t}` (only u32 and f32 are read)")),
    }
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
        assert!(h.contains("TRAX_INLINE unsigned int trax_atominc(unsigned int rs)"));
        assert!(h.contains("TRAX_INLINE float trax_fmin(float rs, float rt)"));
        assert!(h.contains("TRAX_INLINE void trax_printd(double rs)"));
        assert!(h.contains("#define trax_stat(n)"));
        // Pure operations are ordinary values to the compiler; the rest are effects.
        let body = |name: &str| {
            let at = h.find(&format!(" {name}(")).unwrap();
            h[at..].split("}\n").next().unwrap().to_string()
        };
        for pure in ["trax_fmin", "trax_gid", "trax_invsqrt"] {
            assert!(body(pure).contains("__asm__(\""), "{pure}: {}", body(pure));
            assert!(!body(pure).contains("memory"), "{pure}");
        }
        for effect in ["trax_rand", "trax_atominc", "trax_printu"] {
            assert!(body(effect).contains("__asm__ volatile(\""), "{effect}");
            assert!(body(effect).contains("\"memory\""), "{effect}");
        }
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
        c.push_str("volatile unsigned int usink;\nvolatile float fsink;\n");
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
            // Results go to volatile sinks: a pure operation whose result is unused is
            // (rightly) dropped.
            let sink = match i.operands.iter().find(|o| o.kind.is_def()).map(|d| d.kind) {
                Some(OperandKind::FprDef) => "fsink = ",
                Some(_) => "usink = ",
                None => "",
            };
            let _ = writeln!(c, "    {sink}{n}({});", args.join(", "));
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
