//! The contract between kernels and the machine: the TRaX instruction table ([`isa`]),
//! the memory map and scene header ABI ([`abi`]), and the kernel prelude sources.

pub mod abi;
pub mod abortmsg;
pub mod cheader;
pub mod fops;
pub mod host;
pub mod isa;
pub mod pipes;
pub mod prelude;
pub mod rng;
pub mod startup;
