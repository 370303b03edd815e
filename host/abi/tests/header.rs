//! The committed header `include/tooltouch.h` is what cbindgen writes from the crate now:
//! a change of the ABI without the header (or the reverse) fails here.
//! `TOOLTOUCH_BLESS=1 cargo test -p tooltouch-abi --test header` rewrites it.

use std::path::Path;

#[test]
fn the_committed_header_is_what_cbindgen_writes() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_config(config)
        .with_src(dir.join("src/lib.rs"))
        .generate()
        .expect("cbindgen reads src/lib.rs")
        .write(&mut generated);
    let path = dir.join("include/tooltouch.h");
    if std::env::var_os("TOOLTOUCH_BLESS").is_some() {
        std::fs::write(&path, &generated).expect("writing the header");
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    if committed != generated {
        let (c, g) = (
            String::from_utf8_lossy(&committed),
            String::from_utf8_lossy(&generated),
        );
        let line = c
            .lines()
            .zip(g.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(c.lines().count().min(g.lines().count()));
        panic!(
            "{} differs from what cbindgen writes now, from line {}:\n  committed: {:?}\n  generated: {:?}\n\
             rewrite it with TOOLTOUCH_BLESS=1 cargo test -p tooltouch-abi --test header",
            path.display(),
            line + 1,
            c.lines().nth(line).unwrap_or("<end>"),
            g.lines().nth(line).unwrap_or("<end>")
        );
    }
}
