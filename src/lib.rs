//! The `trax` library: the stages the `trax` command line strings together, as functions
//! the CLI, the tests and the benchmarks share.
//!
//! - [`pipeline`]: a kernel (source or executable), a scene, image parameters and a chip
//!   in; the executable and the machine's initial memory out (compile, link, load the scene,
//!   lay out memory). Runs then go through [`trax_emulator::run()`].
//! - [`compare`]: image error metrics (RMSE, relative MSE, PSNR) of PNGs and raw
//!   framebuffers (`trax compare`, `trax converge`).
//! - [`stats`]: the statistics document of a run (`--stats-json`, schema 1).

pub mod clang;
pub mod compare;
pub mod pipeline;
pub mod resources;
pub mod stats;
