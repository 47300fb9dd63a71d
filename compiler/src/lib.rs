//! TRaX-Rust compiler: kernel source → MIPS32r6 ELF relocatable object with DWARF.
