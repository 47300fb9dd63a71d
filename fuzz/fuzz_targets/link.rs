#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| trax_assembler::fuzzing::link(data));
