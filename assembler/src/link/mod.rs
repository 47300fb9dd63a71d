//! Static linker for MIPS32r6 little-endian o32 ELF relocatable objects.
//!
//! [`link`] merges objects produced by our compiler (LLVM's MIPS backend) and by
//! `clang --target=mipsel-unknown-elf -mcpu=mips32r6 -G0 -fno-pic -mno-abicalls` into one
//! ELF32 executable with DWARF kept and relocated. The runtime's start-up routine
//! ([`startup::startup_object`]) is linked first unless [`LinkOptions::startup`] is off.
//!
//! Layout (input order within each section):
//!
//! | segment | sections |
//! |---|---|
//! | text, `PT_LOAD` R+X at [`LinkOptions::text_base`] | `.text` (`.text*`), `.rodata` (`.rodata*` and other read-only data), `.MIPS.abiflags` (merged; also `PT_MIPS_ABIFLAGS`), `.eh_frame` |
//! | data, `PT_LOAD` R+W at the next 4 KiB boundary | `.init_array`, `.data` (`.data*`, `.sdata*`), `.bss` (`.bss*`, `.sbss*`, COMMON; `p_memsz > p_filesz`) |
//! | not loaded | `.debug_*` (`SHT_MIPS_DWARF`), `.comment`, `.mdebug.abi32`, then `.symtab`, `.strtab`, `.shstrtab` |
//!
//! Dropped: `.reginfo`, `.pdr`, `.note.GNU-stack`, `.llvm_addrsig`, relocation sections.
//! `e_flags` merge the inputs' (all must be MIPS32r6 o32 with one NaN encoding); the entry
//! is [`LinkOptions::entry`] (`__trax_start`).
//!
//! Scene header fields: an undefined symbol `__trax_scene_<field>` (a field name of
//! [`trax_runtime::abi::scene_header_fields`]) resolves to the field's absolute address and
//! stays in `.symtab` as an `SHN_ABS` global, so the memory-image builder knows which scene
//! components the program uses ([`Linked::scene_components`];
//! `trax_runtime::exe::Executable::referenced` reads them back from the executable).
//!
//! Behaviour worth knowing:
//! - Input order is kept within each output section; `.init_array` is sorted by priority
//!   (`.init_array.N` ascending, plain `.init_array` last, stable), and COMMON symbols are
//!   allocated at the end of `.bss` (largest size and alignment win).
//! - Only the first COMDAT group of each signature is kept; references from debug sections
//!   into dropped sections resolve to 0.
//! - `SHF_MERGE` sections (`.rodata.str*`, `.debug_str`) are concatenated, not deduplicated.
//! - Alignment gaps in `.text` hold `sigrie 1` (a trap), zeros elsewhere.
//! - The linker always defines `__init_array_start`, `__init_array_end`, `__bss_start` and
//!   `_end` (one past the program's last byte: scene data can go from there).
//! - Relocations are checked before symbols are resolved, so a PIC or small-data object is
//!   reported as such, not as an undefined `_gp_disp`.
//!
//! The output layout is reproducible with `ld.lld -O0 -static -T` and the script returned by
//! [`lld_script`]: the tests compare both linkers' disassembly, line tables, section contents
//! and symbols, and run a linked program under qemu-user.

mod error;
mod flags;
mod input;
mod layout;
mod output;
mod reloc;
mod relocate;
pub mod startup;
mod symbols;

pub use error::{LinkError, RelocationOverflow};

use trax_runtime::abi;

pub use trax_runtime::abi::SCENE_SYMBOL_PREFIX;

/// The symbol name for scene header field `field` (e.g. `triangles`).
pub fn scene_symbol_name(field: &str) -> String {
    format!("{SCENE_SYMBOL_PREFIX}{field}")
}

/// One input object.
#[derive(Clone, Debug)]
pub struct Input {
    /// Name used in errors (usually the file path).
    pub name: String,
    /// The ELF relocatable object.
    pub bytes: Vec<u8>,
}

/// Link options.
#[derive(Clone, Debug)]
pub struct LinkOptions {
    /// Link the runtime's start-up object ([`startup::startup_object`]) first.
    pub startup: bool,
    /// Entry symbol (ELF `e_entry`); must be defined.
    pub entry: String,
    /// Address of the first byte of `.text`.
    pub text_base: u32,
}

impl Default for LinkOptions {
    fn default() -> Self {
        LinkOptions {
            startup: true,
            entry: abi::START_SYMBOL.to_string(),
            text_base: abi::TEXT_BASE,
        }
    }
}

/// An output section of the linked program.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SectionInfo {
    /// Section name.
    pub name: String,
    /// Load address (0 for sections not loaded).
    pub addr: u32,
    /// Size in bytes.
    pub size: u32,
    /// True when the section occupies memory at run time.
    pub alloc: bool,
}

/// A scene header field the program references.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneRef {
    /// Field name in [`trax_runtime::abi::scene_header_fields`].
    pub field: String,
    /// Absolute address of the field.
    pub addr: u32,
}

/// A linked executable.
#[derive(Clone, Debug)]
pub struct Linked {
    /// The ELF32 executable.
    pub elf: Vec<u8>,
    /// Entry address.
    pub entry: u32,
    /// Output sections in file order.
    pub sections: Vec<SectionInfo>,
    /// Scene header fields referenced by the program, in first-reference order.
    pub scene_refs: Vec<SceneRef>,
}

impl Linked {
    /// Names of the scene header fields the program references.
    pub fn scene_components(&self) -> Vec<&str> {
        self.scene_refs.iter().map(|r| r.field.as_str()).collect()
    }
}

/// Links `inputs` (in order) into an executable.
pub fn link(inputs: &[Input], opts: &LinkOptions) -> Result<Linked, LinkError> {
    if !opts.text_base.is_multiple_of(4) || opts.text_base < abi::NULL_GUARD_END {
        return Err(LinkError::InvalidOption(format!(
            "text base {:#x} must be 4-byte aligned and above the null guard (>= {:#x})",
            opts.text_base,
            abi::NULL_GUARD_END
        )));
    }
    let mut objs = Vec::with_capacity(inputs.len() + 1);
    if opts.startup {
        objs.push(input::parse(
            startup::STARTUP_OBJECT_NAME,
            &startup::startup_object()?,
        )?);
    }
    for i in inputs {
        objs.push(input::parse(&i.name, &i.bytes)?);
    }
    if objs.is_empty() {
        return Err(LinkError::Malformed {
            file: "<no inputs>".into(),
            detail: "nothing to link".into(),
        });
    }
    discard_duplicate_groups(&mut objs);
    let e_flags = flags::merge_e_flags(&objs)?;
    relocate::check_relocation_types(&objs)?;
    let globals = symbols::resolve(&objs)?;
    let entry_addr = match globals.map.get(&opts.entry) {
        Some(symbols::Resolved::Defined { .. }) => None,
        _ => {
            return Err(LinkError::UndefinedSymbol {
                symbol: opts.entry.clone(),
                file: "<link options>".into(),
                section: "entry point".into(),
            })
        }
    };
    let mut lay = layout::layout(&objs, &globals, opts.text_base)?;
    relocate::relocate(&objs, &globals, &mut lay)?;
    if let Some(a) = flags::merge_abiflags(&objs, &lay.abiflags_inputs)? {
        if let Some(i) = lay.find(&layout::OutKey::AbiFlags) {
            lay.sections[i].data = a.bytes();
        }
    }
    let entry = entry_addr.unwrap_or_else(|| {
        let Some(symbols::Resolved::Defined { file, sym }) = globals.map.get(&opts.entry) else {
            return 0;
        };
        relocate::symbol_address(&objs, &globals, &lay, *file, *sym)
    });
    let elf = output::write(&objs, &globals, &lay, entry, e_flags)?;
    let scene_refs = globals
        .order
        .iter()
        .filter_map(|name| match globals.map.get(name) {
            Some(symbols::Resolved::Scene { addr, .. }) => Some(SceneRef {
                field: name[SCENE_SYMBOL_PREFIX.len()..].to_string(),
                addr: *addr,
            }),
            _ => None,
        })
        .collect();
    let sections = lay
        .sections
        .iter()
        .map(|s| SectionInfo {
            name: s.name.clone(),
            addr: s.addr,
            size: s.size,
            alloc: s.is_alloc(),
        })
        .collect();
    Ok(Linked {
        elf,
        entry,
        sections,
        scene_refs,
    })
}

/// Keeps the first COMDAT group of each signature; members of later copies are dropped.
fn discard_duplicate_groups(objs: &mut [input::InObject]) {
    let mut seen = std::collections::HashSet::new();
    for obj in objs.iter_mut() {
        let groups = std::mem::take(&mut obj.groups);
        for (sig, members) in &groups {
            if !seen.insert(sig.clone()) {
                for &m in members {
                    obj.sections[m].discarded = true;
                }
            }
        }
        obj.groups = groups;
    }
}

/// A GNU linker script that makes `ld.lld -O0 -static -T script` lay out the same inputs
/// (with the start-up object first) exactly as [`link`] does, including the scene header
/// symbols (as `PROVIDE`s, so only referenced ones are defined).
pub fn lld_script(text_base: u32) -> String {
    let mut scene = String::new();
    for (field, _) in abi::scene_header_fields() {
        if let Some((addr, _)) = symbols::scene_field(field) {
            scene.push_str(&format!(
                "PROVIDE({} = {addr:#x});\n",
                scene_symbol_name(field)
            ));
        }
    }
    format!(
        r#"ENTRY({start})
PHDRS {{ text PT_LOAD FLAGS(5); data PT_LOAD FLAGS(6); }}
SECTIONS {{
  . = {text_base:#x};
  .text : {{ *(.text .text.*) }} :text
  .rodata : {{ *(.rodata .rodata.*) }} :text
  .MIPS.abiflags : {{ *(.MIPS.abiflags) }} :text
  .eh_frame : {{ *(.eh_frame) }} :text
  . = ALIGN({page:#x});
  .init_array : {{
    __init_array_start = .;
    KEEP(*(SORT_BY_INIT_PRIORITY(.init_array.*) SORT_BY_INIT_PRIORITY(.init_array)))
    __init_array_end = .;
  }} :data
  .data : {{ *(.data .data.*) }} :data
  .bss : {{ __bss_start = .; *(.bss .bss.*) *(COMMON) }} :data
  _end = .;
  .got : {{ *(.got) }} :data
  /DISCARD/ : {{ *(.reginfo) *(.pdr) *(.note.GNU-stack) }}
}}
{scene}"#,
        start = abi::START_SYMBOL,
        page = layout::PAGE,
    )
}
