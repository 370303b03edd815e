//! libFuzzer target: [`tooltouch_fuzz::settings`].
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tooltouch_fuzz::settings(data));
