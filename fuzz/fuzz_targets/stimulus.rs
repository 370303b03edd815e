//! libFuzzer target: [`tooltouch_fuzz::stimulus`].
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tooltouch_fuzz::stimulus(data));
