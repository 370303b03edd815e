//! The stack gate: the deepest stack a co-simulation batch used (cortex-m-rt's stack
//! painting, read back in the trace's status record) against the committed
//! `firmware/ci/expected/<image>.stack`, with the size gate's margin (xtask/src/gates.rs:
//! 2 %, at least 64 bytes). With `TOOLTOUCH_BLESS_STACK=1` (`cargo xtask bless-firmware`)
//! the measurement is written there instead.

use std::path::PathBuf;

/// How much the stack may grow over its committed value, % (rounded up), at least
/// [`MARGIN_MIN_BYTES`] (the same margin as the size gate's).
const MARGIN_PERCENT: u32 = 2;
/// The least margin, bytes.
const MARGIN_MIN_BYTES: u32 = 64;

fn stack_file(image: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("firmware/ci/expected")
        .join(format!("{image}.stack"))
}

/// Checks (or, blessing, records) `bytes`, the stack high-water mark of `image` over
/// `batch`.
pub(crate) fn check_stack(image: &str, batch: &str, bytes: u32) {
    let path = stack_file(image);
    if std::env::var_os("TOOLTOUCH_BLESS_STACK").is_some_and(|v| v == "1") {
        let text = format!(
            "# Stack high-water mark of the {image} image, bytes: the deepest painted word\n\
             # overwritten during {batch} (tests/firmware). The gate fails on growth beyond\n\
             # {MARGIN_PERCENT} % (at least {MARGIN_MIN_BYTES} bytes); `cargo xtask bless-firmware` rewrites this file.\n\
             {bytes}\n"
        );
        std::fs::write(&path, text).unwrap_or_else(|e| panic!("writing {}: {e}", path.display()));
        eprintln!("stack gate: {} blessed with {bytes} bytes", path.display());
        return;
    }
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "reading {}: {e} (`cargo xtask bless-firmware` writes it)",
            path.display()
        )
    });
    let want: u32 = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
        .and_then(|l| l.parse().ok())
        .unwrap_or_else(|| panic!("{}: no byte count", path.display()));
    let limit = want + (want * MARGIN_PERCENT).div_ceil(100).max(MARGIN_MIN_BYTES);
    assert!(
        bytes <= limit,
        "stack gate: the {image} image used {bytes} bytes of stack in {batch}, over the gate \
         of {limit} (committed {want}, {}); if intended, `cargo xtask bless-firmware`",
        path.display()
    );
    eprintln!("stack gate: {image} used {bytes} bytes, committed {want}, gate {limit}");
}
