//! Static linker, memory image and scene pipeline.
