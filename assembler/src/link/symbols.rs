//! Global symbol resolution: strong/weak/common definitions, undefined references, and the
//! symbols the linker itself provides (`.init_array` bounds, bss bounds, scene components).

use std::collections::HashMap;

use trax_runtime::abi;

use super::input::{InObject, SymDef};
use super::{LinkError, SCENE_SYMBOL_PREFIX};

/// A symbol the linker defines from the layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum LinkerSym {
    /// `__init_array_start`.
    InitArrayStart,
    /// `__init_array_end`.
    InitArrayEnd,
    /// `__bss_start`.
    BssStart,
    /// `_end`: first address past the program.
    End,
}

impl LinkerSym {
    /// Names of all linker-defined symbols.
    pub const NAMES: [&'static str; 4] = [
        trax_runtime::startup::INIT_ARRAY_START,
        trax_runtime::startup::INIT_ARRAY_END,
        "__bss_start",
        "_end",
    ];

    fn from_name(name: &str) -> Option<LinkerSym> {
        Some(match name {
            trax_runtime::startup::INIT_ARRAY_START => LinkerSym::InitArrayStart,
            trax_runtime::startup::INIT_ARRAY_END => LinkerSym::InitArrayEnd,
            "__bss_start" => LinkerSym::BssStart,
            "_end" => LinkerSym::End,
            _ => return None,
        })
    }
}

/// What a global name resolved to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Resolved {
    /// Defined by symbol `sym` of input `file` (in a section or absolute).
    Defined { file: usize, sym: usize },
    /// A common block, allocated in `.bss` by the layout.
    Common {
        file: usize,
        sym: usize,
        size: u32,
        align: u32,
    },
    /// Provided by the linker from the layout.
    Linker(LinkerSym),
    /// A scene header field: absolute address, field size in bytes.
    Scene { addr: u32, size: u32 },
    /// Only weak references: resolves to 0.
    WeakUndefined,
}

/// The global symbol table.
#[derive(Debug, Default)]
pub(crate) struct Globals {
    pub map: HashMap<String, Resolved>,
    /// Names in first-seen order (input order, then symbol-table order).
    pub order: Vec<String>,
}

/// Address and size of the scene header field named `field`, if it exists.
pub(crate) fn scene_field(field: &str) -> Option<(u32, u32)> {
    let fields = abi::scene_header_fields();
    let i = fields.iter().position(|(name, _)| *name == field)?;
    let end = fields.get(i + 1).map_or(abi::SCENE_HEADER_SIZE, |f| f.1);
    let (_, off) = fields[i];
    Some((abi::SCENE_HEADER_ADDR + off as u32, (end - off) as u32))
}

fn section_discarded(obj: &InObject, def: SymDef) -> bool {
    matches!(def, SymDef::Section(s) if obj.sections[s].discarded)
}

/// Resolves every global symbol of `objs`.
pub(crate) fn resolve(objs: &[InObject]) -> Result<Globals, LinkError> {
    enum State {
        Undef {
            strong: bool,
            file: usize,
        },
        Def {
            file: usize,
            sym: usize,
            weak: bool,
        },
        Common {
            file: usize,
            sym: usize,
            size: u32,
            align: u32,
        },
    }
    let mut state: HashMap<String, State> = HashMap::new();
    let mut order = Vec::new();
    for (fi, obj) in objs.iter().enumerate() {
        for (si, sym) in obj.symbols.iter().enumerate().skip(1) {
            if sym.is_local() {
                continue;
            }
            let name = &sym.name;
            let weak = sym.is_weak();
            let def = if section_discarded(obj, sym.def) {
                SymDef::Undef
            } else {
                sym.def
            };
            let entry = match state.get_mut(name) {
                Some(e) => e,
                None => {
                    order.push(name.clone());
                    let new = match def {
                        SymDef::Undef => State::Undef {
                            strong: !weak,
                            file: fi,
                        },
                        SymDef::Common => State::Common {
                            file: fi,
                            sym: si,
                            size: sym.size,
                            align: sym.value.max(1),
                        },
                        _ => State::Def {
                            file: fi,
                            sym: si,
                            weak,
                        },
                    };
                    state.insert(name.clone(), new);
                    continue;
                }
            };
            match (def, &mut *entry) {
                (SymDef::Undef, State::Undef { strong, .. }) => *strong |= !weak,
                (SymDef::Undef, _) => {}
                (SymDef::Common, State::Undef { .. }) => {
                    *entry = State::Common {
                        file: fi,
                        sym: si,
                        size: sym.size,
                        align: sym.value.max(1),
                    }
                }
                (
                    SymDef::Common,
                    State::Common {
                        file,
                        sym: s,
                        size,
                        align,
                    },
                ) => {
                    *align = (*align).max(sym.value.max(1));
                    if sym.size > *size {
                        *size = sym.size;
                        *file = fi;
                        *s = si;
                    }
                }
                (SymDef::Common, State::Def { weak: true, .. }) => {
                    *entry = State::Common {
                        file: fi,
                        sym: si,
                        size: sym.size,
                        align: sym.value.max(1),
                    }
                }
                (SymDef::Common, State::Def { .. }) => {}
                (_, State::Undef { .. } | State::Common { .. }) => {
                    *entry = State::Def {
                        file: fi,
                        sym: si,
                        weak,
                    }
                }
                (
                    _,
                    State::Def {
                        weak: old_weak,
                        file,
                        sym: s,
                    },
                ) => {
                    if *old_weak && !weak {
                        *entry = State::Def {
                            file: fi,
                            sym: si,
                            weak,
                        };
                    } else if !*old_weak && !weak {
                        return Err(LinkError::DuplicateSymbol {
                            symbol: name.clone(),
                            first: objs[*file].name.clone(),
                            second: obj.name.clone(),
                        });
                    } else {
                        let _ = s;
                    }
                }
            }
        }
    }

    // The linker's own symbols are always defined (the image builder uses `_end`).
    for name in LinkerSym::NAMES {
        if !state.contains_key(name) {
            order.push(name.to_string());
            state.insert(
                name.to_string(),
                State::Undef {
                    strong: false,
                    file: 0,
                },
            );
        }
    }
    let mut map = HashMap::with_capacity(state.len());
    let mut undefined: Vec<(String, usize)> = Vec::new();
    for name in &order {
        let resolved = match &state[name] {
            State::Def { file, sym, .. } => Resolved::Defined {
                file: *file,
                sym: *sym,
            },
            State::Common {
                file,
                sym,
                size,
                align,
            } => Resolved::Common {
                file: *file,
                sym: *sym,
                size: *size,
                align: *align,
            },
            State::Undef { strong, file } => {
                if let Some(l) = LinkerSym::from_name(name) {
                    Resolved::Linker(l)
                } else if let Some((addr, size)) =
                    name.strip_prefix(SCENE_SYMBOL_PREFIX).and_then(scene_field)
                {
                    Resolved::Scene { addr, size }
                } else if *strong {
                    undefined.push((name.clone(), *file));
                    continue;
                } else {
                    Resolved::WeakUndefined
                }
            }
        };
        map.insert(name.clone(), resolved);
    }
    if let Some((name, file)) = undefined.into_iter().next() {
        return Err(undefined_error(objs, &name, file));
    }
    Ok(Globals { map, order })
}

/// Builds the undefined-symbol error, naming the first section that references `name`.
fn undefined_error(objs: &[InObject], name: &str, first_file: usize) -> LinkError {
    for obj in &objs[first_file..] {
        for sec in &obj.sections {
            if sec.discarded {
                continue;
            }
            if sec.relocs.iter().any(|r| {
                let s = &obj.symbols[r.sym];
                !s.is_local() && s.name == name
            }) {
                return LinkError::UndefinedSymbol {
                    symbol: name.to_string(),
                    file: obj.name.clone(),
                    section: sec.name.clone(),
                };
            }
        }
    }
    LinkError::UndefinedSymbol {
        symbol: name.to_string(),
        file: objs[first_file].name.clone(),
        section: "<symbol table>".to_string(),
    }
}
