//! Static linker, memory image and scene pipeline.

pub mod bvh;
pub mod fuzzing;
pub mod image;
pub mod link;
pub mod scene;
