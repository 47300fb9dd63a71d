#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| trax_emulator::fuzzing::decode_words(data));
