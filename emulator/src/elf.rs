//! Loading a linked MIPS32r6 executable: the runtime's one executable reader
//! ([`trax_runtime::exe`]) under the names the emulator's callers know.

pub use trax_runtime::exe::{ExeError as ElfError, ExeSymbol as Symbol, Executable};
