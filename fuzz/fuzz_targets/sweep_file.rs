#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| trax::fuzzing::sweep_file(data));
