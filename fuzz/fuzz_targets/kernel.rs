#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| trax_compiler::fuzzing::kernel(data));
