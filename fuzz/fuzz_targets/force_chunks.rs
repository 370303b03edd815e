//! libFuzzer target: [`tooltouch_fuzz::force_chunks`].
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tooltouch_fuzz::force_chunks(data));
