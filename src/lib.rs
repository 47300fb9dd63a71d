//! The `trax` library: the stages the `trax` command line strings together, as functions
//! the CLI, the tests and the benchmarks share.
//!
//! - [`pipeline`]: a kernel (source or executable), a scene, image parameters and a chip
//!   in; the executable and the machine's initial memory out (compile, link, load the scene,
//!   lay out memory). Runs then go through [`trax_emulator::run()`].
//! - [`compare`]: image error metrics (RMSE, relative MSE, PSNR) of PNGs and raw
//!   framebuffers (`trax compare`, `trax converge`).
//! - [`stats`]: the statistics document of a run (`--stats-json`, schema 1).
//! - [`sweep`]: sweep files and their plans (`trax sweep`).
//! - [`fuzzing`]: the bodies of the fuzz targets of this crate.
//! - [`native`]: native builds and runs (`trax native`), and rustc's check of the
//!   TRaX-Rust kernels the pipeline builds ([`native::check`]).
//! - [`clang`]: C and C++ kernels.

pub mod clang;
pub mod compare;
pub mod fuzzing;
pub mod native;
pub mod pipeline;
pub mod resources;
pub mod stats;
pub mod sweep;
