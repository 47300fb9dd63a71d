//! Copying input sections into the output sections and applying their relocations.

use super::input::{InObject, InReloc, SymDef};
use super::layout::{Layout, OutKey};
use super::reloc::{self, Action, Refusal};
use super::symbols::{Globals, Resolved};
use super::{LinkError, RelocationOverflow};

/// Final address of symbol `sym` of input `file`. Symbols in dropped sections resolve to 0
/// (as other linkers do for debug references to discarded code).
pub(crate) fn symbol_address(
    objs: &[InObject],
    globals: &Globals,
    layout: &Layout,
    file: usize,
    sym: usize,
) -> u32 {
    let s = &objs[file].symbols[sym];
    if s.is_local() || sym == 0 {
        return local_address(objs, layout, file, sym);
    }
    match globals.map.get(&s.name) {
        Some(Resolved::Defined { file, sym }) => local_address(objs, layout, *file, *sym),
        Some(Resolved::Common { .. }) => layout
            .commons
            .get(&s.name)
            .map_or(0, |&(out, off)| layout.sections[out].addr + off),
        Some(Resolved::Linker(l)) => layout.linker_symbol(*l).0,
        Some(Resolved::Scene { addr, .. }) => *addr,
        Some(Resolved::WeakUndefined) | None => 0,
    }
}

fn local_address(objs: &[InObject], layout: &Layout, file: usize, sym: usize) -> u32 {
    let s = &objs[file].symbols[sym];
    match s.def {
        SymDef::Undef | SymDef::Common => 0,
        SymDef::Abs => s.value,
        SymDef::Section(sec) => layout.place[file][sec].map_or(0, |(out, off)| {
            layout.sections[out]
                .addr
                .wrapping_add(off)
                .wrapping_add(s.value)
        }),
    }
}

/// The action for relocation `r` of section `section` in `obj`, or the error refusing it.
fn classify(obj: &InObject, section: &str, r: &InReloc) -> Result<Action, LinkError> {
    reloc::classify(r.r_type).map_err(|refusal| match refusal {
        Refusal::GpRelative => {
            let s = &obj.symbols[r.sym];
            let target = match s.def {
                SymDef::Section(x) if s.name.is_empty() => obj.sections[x].name.as_str(),
                _ => s.name.as_str(),
            };
            LinkError::GpRelative {
                file: obj.name.clone(),
                what: format!(
                    "{} in section `{section}` at {:#x} against `{target}`",
                    reloc::type_name(r.r_type),
                    r.offset
                ),
            }
        }
        Refusal::Unsupported(hint) => LinkError::UnsupportedRelocation {
            kind: reloc::type_name(r.r_type),
            file: obj.name.clone(),
            section: section.to_string(),
            offset: r.offset,
            hint: hint.to_string(),
        },
    })
}

/// Refuses unsupported and `$gp`-relative relocations before symbols are resolved, so PIC
/// or small-data objects get that diagnosis rather than "undefined `_gp_disp`".
pub(crate) fn check_relocation_types(objs: &[InObject]) -> Result<(), LinkError> {
    for obj in objs {
        for sec in obj.sections.iter().filter(|s| !s.discarded) {
            for r in &sec.relocs {
                classify(obj, &sec.name, r)?;
            }
        }
    }
    Ok(())
}

/// `sigrie 1`: the MIPS32r6 trap that fills alignment gaps in `.text`.
const TRAP: u32 = 0x0417_0001;

fn read_word(data: &[u8], offset: u32) -> u32 {
    let o = offset as usize;
    u32::from_le_bytes([data[o], data[o + 1], data[o + 2], data[o + 3]])
}

/// Fills every output section's data and applies all relocations.
pub(crate) fn relocate(
    objs: &[InObject],
    globals: &Globals,
    layout: &mut Layout,
) -> Result<(), LinkError> {
    for sec in layout.sections.iter_mut() {
        if sec.is_nobits() {
            continue;
        }
        sec.data = if sec.key == OutKey::Text {
            // Alignment gaps in code trap if executed (as ld.lld fills them).
            TRAP.to_le_bytes()
                .iter()
                .copied()
                .cycle()
                .take(sec.size as usize)
                .collect()
        } else {
            vec![0; sec.size as usize]
        };
    }
    let mut patches: Vec<(usize, u32, u32)> = Vec::new();
    for (fi, obj) in objs.iter().enumerate() {
        for (si, sec) in obj.sections.iter().enumerate() {
            let Some((out, off)) = layout.place[fi][si] else {
                continue;
            };
            let out_sec = &layout.sections[out];
            if out_sec.is_nobits() {
                continue;
            }
            let base = out_sec.addr.wrapping_add(off);
            patches.clear();
            for (ri, r) in sec.relocs.iter().enumerate() {
                let sym_name = || {
                    let s = &obj.symbols[r.sym];
                    match s.def {
                        SymDef::Section(x) if s.name.is_empty() => obj.sections[x].name.clone(),
                        _ => s.name.clone(),
                    }
                };
                let action = classify(obj, &sec.name, r)?;
                if action == Action::Skip {
                    continue;
                }
                let word = read_word(&sec.data, r.offset);
                let mut addend = reloc::implicit_addend(action, word);
                if matches!(action, Action::Hi16 | Action::PcHi16) {
                    let (pair, pair_name) = if action == Action::Hi16 {
                        (reloc::R_MIPS_LO16, "R_MIPS_LO16")
                    } else {
                        (reloc::R_MIPS_PCLO16, "R_MIPS_PCLO16")
                    };
                    let lo = sec.relocs[ri + 1..]
                        .iter()
                        .find(|l| l.r_type == pair && l.sym == r.sym)
                        .ok_or_else(|| LinkError::UnpairedHi16 {
                            file: obj.name.clone(),
                            section: sec.name.clone(),
                            offset: r.offset,
                            kind: reloc::type_name(r.r_type),
                            pair: pair_name.to_string(),
                            symbol: sym_name(),
                        })?;
                    addend += reloc::lo_addend(read_word(&sec.data, lo.offset));
                }
                let s = symbol_address(objs, globals, layout, fi, r.sym);
                let p = base.wrapping_add(r.offset);
                let patched =
                    reloc::apply(action, word, i64::from(s) + addend, p).map_err(|o| {
                        LinkError::RelocationOverflow(Box::new(RelocationOverflow {
                            kind: reloc::type_name(r.r_type),
                            file: obj.name.clone(),
                            section: sec.name.clone(),
                            offset: r.offset,
                            address: p,
                            symbol: sym_name(),
                            value: o.value,
                            reason: o.reason,
                        }))
                    })?;
                patches.push((out, off + r.offset, patched));
            }
            let out_sec = &mut layout.sections[out];
            let start = off as usize;
            out_sec.data[start..start + sec.data.len()].copy_from_slice(&sec.data);
            for &(_, at, w) in &patches {
                out_sec.data[at as usize..at as usize + 4].copy_from_slice(&w.to_le_bytes());
            }
        }
    }
    Ok(())
}
