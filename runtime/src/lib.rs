//! The contract between kernels and the machine: the TRaX instruction table ([`isa`]),
//! the memory map and the scene contract ([`abi`]: header, element structs, the component
//! table, the only encoders), the memory image ([`image`]), the executable reader
//! ([`exe`]), exact semantics shared with the host prelude ([`rng`], [`fops`], [`pipes`],
//! [`streams`], [`counters`]) and the kernel prelude sources.

pub mod abi;
pub mod abortmsg;
pub mod cheader;
pub mod counters;
pub mod exe;
pub mod fops;
pub mod host;
pub mod image;
pub mod isa;
pub mod pipes;
pub mod prelude;
pub mod rng;
pub mod startup;
pub mod streams;
