//! libFuzzer target: [`tooltouch_fuzz::tune_merge`].
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tooltouch_fuzz::tune_merge(data));
