//! libFuzzer target: [`tooltouch_fuzz::abi`].
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tooltouch_fuzz::abi(data));
