//! The machine: MIPS32r6 + FPU + MSA + TRaX execution, threads, timing, tooling.
