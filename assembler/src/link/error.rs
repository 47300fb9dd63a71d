//! Typed link errors. Every error names the input object (and section) it comes from.

use thiserror::Error;

/// Why a link failed.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum LinkError {
    /// An input is not a MIPS32 little-endian ELF relocatable object, or is corrupt.
    #[error("malformed input `{file}`: {detail}")]
    Malformed {
        /// Input name.
        file: String,
        /// What is wrong.
        detail: String,
    },
    /// Inputs were compiled for incompatible targets (ISA level, NaN encoding, FP ABI).
    #[error("incompatible input `{file}`: {detail}")]
    Incompatible {
        /// Input name.
        file: String,
        /// What differs, and from what.
        detail: String,
    },
    /// A symbol is referenced but defined nowhere.
    #[error("undefined symbol `{symbol}`, referenced from `{file}` section `{section}`")]
    UndefinedSymbol {
        /// Symbol name.
        symbol: String,
        /// First object that references it.
        file: String,
        /// Section holding the reference.
        section: String,
    },
    /// A symbol is defined (non-weak) in two objects.
    #[error("duplicate symbol `{symbol}`: defined in `{first}` and in `{second}`")]
    DuplicateSymbol {
        /// Symbol name.
        symbol: String,
        /// Object with the first definition.
        first: String,
        /// Object with the second definition.
        second: String,
    },
    /// A relocated value does not fit its field.
    #[error("{0}")]
    RelocationOverflow(Box<RelocationOverflow>),
    /// A relocation type the linker does not implement (e.g. GOT or TLS relocations).
    #[error(
        "unsupported relocation {kind} in `{file}` section `{section}` offset {offset:#x}{hint}"
    )]
    UnsupportedRelocation {
        /// Relocation type name or number.
        kind: String,
        /// Input object.
        file: String,
        /// Input section.
        section: String,
        /// Offset within the input section.
        offset: u32,
        /// How to avoid it, if known (starts with "; ").
        hint: String,
    },
    /// Code addresses data relative to `$gp` (small-data sections or GP-relative relocations).
    #[error(
        "`{file}` uses $gp-relative addressing ({what}); TRaX programs have no small-data \
         area: rebuild with `-G0` (clang/gcc) or without small data \
         (llc: `-mattr=+noabicalls -relocation-model=static`, no `-mgpopt`)"
    )]
    GpRelative {
        /// Input object.
        file: String,
        /// The relocation or section that uses `$gp`.
        what: String,
    },
    /// An `R_MIPS_HI16`/`R_MIPS_PCHI16` has no matching low-half relocation.
    #[error("`{file}` section `{section}` offset {offset:#x}: {kind} has no matching {pair} against `{symbol}`")]
    UnpairedHi16 {
        /// Input object.
        file: String,
        /// Input section.
        section: String,
        /// Offset of the high-half relocation.
        offset: u32,
        /// `R_MIPS_HI16` or `R_MIPS_PCHI16`.
        kind: String,
        /// The missing pair type.
        pair: String,
        /// Target symbol.
        symbol: String,
    },
    /// The linked program does not fit the 32-bit address space or overlaps the stack window.
    #[error("program too large: {0}")]
    TooLarge(String),
    /// A [`LinkOptions`](super::LinkOptions) value is unusable.
    #[error("invalid link option: {0}")]
    InvalidOption(String),
    /// The output ELF could not be written.
    #[error("cannot write the executable: {0}")]
    Write(String),
}

/// Details of [`LinkError::RelocationOverflow`].
#[derive(Debug, Error, Clone, PartialEq, Eq)]
#[error(
    "relocation {kind} overflow at `{file}` section `{section}` offset {offset:#x} \
     (address {address:#010x}) against `{symbol}`: value {value:#x} {reason}"
)]
pub struct RelocationOverflow {
    /// Relocation type name (e.g. `R_MIPS_PC16`).
    pub kind: String,
    /// Input object.
    pub file: String,
    /// Input section.
    pub section: String,
    /// Offset within the input section.
    pub offset: u32,
    /// Final address of the patched location.
    pub address: u32,
    /// Target symbol.
    pub symbol: String,
    /// The out-of-range value.
    pub value: i64,
    /// Which limit was exceeded.
    pub reason: String,
}
