//! libFuzzer target: [`tooltouch_fuzz::ttv_outputs`].
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tooltouch_fuzz::ttv_outputs(data));
