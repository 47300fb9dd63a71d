//! The contract between kernels and the machine: the TRaX instruction table ([`isa`]),
//! the memory map and scene header ABI ([`abi`]), and the kernel prelude sources.

pub mod abi;
pub mod isa;
