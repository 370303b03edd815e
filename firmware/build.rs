//! Puts the board's memory map on the linker's search path. The QEMU board's `memory.x`
//! comes with the `lm3s6965` device crate; the Nucleo's is `memory-nucleo.x` here.

use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory-nucleo.x");
    if std::env::var_os("CARGO_FEATURE_NUCLEO").is_some() {
        let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
        std::fs::copy("memory-nucleo.x", out.join("memory.x")).expect("copying memory-nucleo.x");
        println!("cargo:rustc-link-search={}", out.display());
    }
}
