//! The execution units of a TM, declared once: the registry [`UNITS`].
//!
//! A unit's declaration ([`UnitDecl`], written with [`unit_decl!`]) is its config key
//! (`[units.NAME]`, checked by `ChipConfig::validate` against this table), its doc line
//! (`trax config show`), the instructions it executes, its statistics names
//! (`timing.class_mix.NAME`, `timing.unit_conflicts.NAME`) and its sweep column
//! (`NAME_ops`). Everything else walks the table: the timing engine gives every unit a
//! counter index and a claim (count, latency, busy cycles from `[units.NAME]`), the
//! energy of its operations and its area go into `execution_units`, and the sweep metrics
//! get a column per unit.
//!
//! A unit either executes the instructions of one ISA class ([`UnitClass`]), or *takes*
//! some instructions of a class from the unit that would execute them, on chips whose
//! config has a `[units.NAME]` table for it (a special-purpose unit beside the general
//! ones). Adding a unit: one file declaring it (see `toy.rs`) and one line in [`UNITS`].

use trax_runtime::isa::UnitClass;

use crate::decode::Inst;

#[cfg(test)]
mod toy;

/// One execution unit kind.
#[derive(Clone, Copy, Debug)]
pub struct UnitDecl {
    /// Config key (`units.NAME`) and statistics name (`class_mix.NAME`).
    pub name: &'static str,
    /// What it is, one sentence (shown by `trax config show`).
    pub doc: &'static str,
    /// The ISA class of the instructions it executes.
    pub class: UnitClass,
    /// `None`: every instruction of `class`. `Some(f)`: the instructions of `class` that
    /// `f` accepts, taken from `class`'s unit when the chip config lists this unit.
    pub takes: Option<fn(&Inst) -> bool>,
    /// Its sweep column (`results.csv`, `trax plot --y`): operations issued to it.
    pub ops_column: &'static str,
    /// That column's label.
    pub ops_label: &'static str,
    /// That column's path in the statistics document.
    pub ops_path: &'static str,
}

/// Declares a [`UnitDecl`]: `unit_decl!(name, Class, "doc")`, or
/// `unit_decl!(name, Class, "doc", takes = fn)` for a unit that takes instructions.
macro_rules! unit_decl {
    ($name:ident, $class:ident, $doc:literal $(, takes = $takes:expr)?) => {
        $crate::timing::units::UnitDecl {
            name: stringify!($name),
            doc: $doc,
            class: trax_runtime::isa::UnitClass::$class,
            takes: unit_decl!(@takes $($takes)?),
            ops_column: concat!(stringify!($name), "_ops"),
            ops_label: concat!("Operations on ", stringify!($name), " units"),
            ops_path: concat!("timing.class_mix.", stringify!($name)),
        }
    };
    (@takes) => { None };
    (@takes $f:expr) => { Some($f) };
}
// Unit files declare with it (`toy.rs`); the registry below uses it by textual scope.
#[allow(unused_imports)]
pub(crate) use unit_decl;

/// The registry: every execution unit a TM can have.
pub const UNITS: &[UnitDecl] = &[
    unit_decl!(int_add, IntAdd, "Integer add, subtract and compare."),
    unit_decl!(int_mul, IntMul, "Integer multiply."),
    unit_decl!(int_div, IntDiv, "Integer divide and modulo."),
    unit_decl!(bitwise, Bitwise, "Logic, shifts, bit fields and selects."),
    unit_decl!(branch, Branch, "Branches and jumps."),
    unit_decl!(
        fp_add,
        FpAdd,
        "FP add and subtract (and the random-number generator, as in simtrax)."
    ),
    unit_decl!(fp_mul, FpMul, "FP multiply and fused multiply-add."),
    unit_decl!(fp_min_max, FpMinMax, "FP minimum and maximum."),
    unit_decl!(
        fp_cmp,
        FpCmp,
        "FP compares, absolute value, negation, class."
    ),
    unit_decl!(fp_div, FpDiv, "FP divide and reciprocal."),
    unit_decl!(
        fp_inv_sqrt,
        FpInvSqrt,
        "FP square root and inverse square root."
    ),
    unit_decl!(
        conv,
        Conv,
        "Conversions between integer and FP formats, rounding."
    ),
    unit_decl!(
        stream,
        Stream,
        "The ray stream memory's port (STRaTA; its capacity and banks are [stream_memory])."
    ),
    #[cfg(test)]
    toy::UNIT,
];

/// Statistics names of the classes that have no configurable unit.
fn other_class_name(c: UnitClass) -> Option<&'static str> {
    use UnitClass::*;
    match c {
        RegFile => Some("reg_file"),
        Memory => Some("memory"),
        LocalStore => Some("local_store"),
        GlobalRegs => Some("global_regs"),
        Debug => Some("debug"),
        BoxPipe => Some("box_pipe"),
        TriPipe => Some("tri_pipe"),
        IntAdd | IntMul | IntDiv | Bitwise | Branch | FpAdd | FpMul | FpMinMax | FpCmp | FpDiv
        | FpInvSqrt | Conv | Stream => None,
    }
}

/// Units that take instructions from another class's unit.
const fn takers() -> usize {
    let mut n = 0;
    let mut i = 0;
    while i < UNITS.len() {
        if UNITS[i].takes.is_some() {
            n += 1;
        }
        i += 1;
    }
    n
}

/// Number of counter indices: one per ISA class (`UnitClass as usize`), then one per unit
/// that takes instructions, in registry order.
pub const NUM_CLASSES: usize = UnitClass::COUNT + takers();

/// The unit executing every instruction of class `c`, if it has one.
pub fn of_class(c: UnitClass) -> Option<&'static UnitDecl> {
    UNITS.iter().find(|u| u.class == c && u.takes.is_none())
}

/// The unit named `name`.
pub fn named(name: &str) -> Option<&'static UnitDecl> {
    UNITS.iter().find(|u| u.name == name)
}

/// Config key / statistics name of class `c`.
pub fn class_name(c: UnitClass) -> &'static str {
    other_class_name(c)
        .or_else(|| of_class(c).map(|u| u.name))
        .unwrap_or("other")
}

/// The unit behind counter index `k`, if any.
pub fn unit_at(k: usize) -> Option<&'static UnitDecl> {
    if k < UnitClass::COUNT {
        of_class(UnitClass::ALL[k])
    } else {
        UNITS
            .iter()
            .filter(|u| u.takes.is_some())
            .nth(k - UnitClass::COUNT)
    }
}

/// Statistics name of counter index `k`.
pub fn counter_name(k: usize) -> &'static str {
    match unit_at(k) {
        Some(u) => u.name,
        None if k < UnitClass::COUNT => class_name(UnitClass::ALL[k]),
        None => "other",
    }
}

/// Counter index of unit `u`.
pub fn index_of(u: &UnitDecl) -> usize {
    (0..NUM_CLASSES)
        .find(|&k| unit_at(k).is_some_and(|v| v.name == u.name))
        .expect("every registered unit has a counter index")
}

/// For a chip whose config lists the units `present`: the counter index of instruction
/// `inst` of class `class` — the first unit present that takes it, else its class's.
pub fn counter_of(present: &[usize], inst: &Inst, class: UnitClass) -> usize {
    for &k in present {
        if let Some(u) = unit_at(k) {
            if u.class == class && u.takes.is_some_and(|f| f(inst)) {
                return k;
            }
        }
    }
    class as usize
}

/// Counter indices of the taking units a chip config with unit tables `names` has.
pub fn takers_present<'a>(names: impl Iterator<Item = &'a String>) -> Vec<usize> {
    let names: Vec<&String> = names.collect();
    (UnitClass::COUNT..NUM_CLASSES)
        .filter(|&k| unit_at(k).is_some_and(|u| names.iter().any(|n| *n == u.name)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names are unique, every class has exactly one name, every counter index one unit
    /// or class, and a taking unit takes from a class with a unit of its own (so the
    /// instruction keeps a plain unit claim and the class's special handling — memory,
    /// global registers, pipelines, the stream port — is never bypassed).
    #[test]
    fn the_registry_is_consistent() {
        let mut names: Vec<&str> = UNITS.iter().map(|u| u.name).collect();
        names.extend(UnitClass::ALL.iter().filter_map(|c| other_class_name(*c)));
        let n = names.len();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), n, "a name is used twice");
        for c in UnitClass::ALL {
            assert!(
                other_class_name(c).is_some() != of_class(c).is_some(),
                "{c:?} needs exactly one of a unit or a name"
            );
        }
        for (k, u) in (0..NUM_CLASSES).filter_map(|k| unit_at(k).map(|u| (k, u))) {
            assert_eq!(index_of(u), k);
            assert_eq!(counter_name(k), u.name);
            if u.takes.is_some() {
                assert!(
                    of_class(u.class).is_some(),
                    "{} takes from {:?}",
                    u.name,
                    u.class
                );
                assert!(u.class != UnitClass::Stream, "{}", u.name);
            }
        }
        assert_eq!(
            (0..NUM_CLASSES).filter(|&k| unit_at(k).is_some()).count(),
            UNITS.len()
        );
    }
}
