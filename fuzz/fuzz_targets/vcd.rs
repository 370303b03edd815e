//! libFuzzer target: [`tooltouch_fuzz::vcd`].
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tooltouch_fuzz::vcd(data));
