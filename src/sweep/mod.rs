//! Sweep files and plans, shared by `trax sweep` (the command line's `cli/sweep`) and the
//! fuzz target for sweep files ([`crate::fuzzing`]): [`spec`] parses and checks a sweep
//! file and enumerates its points; [`plan`] turns them into `trax run` commands.

pub mod plan;
pub mod spec;
