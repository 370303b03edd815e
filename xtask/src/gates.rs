//! The firmware's size and stack gates, in the style of RTIC's `ci/expected/`: the
//! expected `.text`, `.data`, `.bss` of both release images (`llvm-size`) and the measured
//! stack high-water marks (cortex-m-rt's stack painting, read back by the co-simulations)
//! are committed in `firmware/ci/expected/` (`<board>.size`: text data bss;
//! `<image>.stack`: bytes, checked by tests/firmware); CI fails when a figure grows beyond
//! [`MARGIN_PERCENT`] (at least [`MARGIN_MIN_BYTES`]) over its expected value, and
//! `cargo xtask bless-firmware` rewrites both files from a fresh measurement.

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::process::Command;

/// How much a figure may grow over its committed value, % (rounded up)…
pub const MARGIN_PERCENT: u64 = 2;
/// …but at least this many bytes.
pub const MARGIN_MIN_BYTES: u64 = 64;

/// The folder of the committed figures.
pub const EXPECTED_DIR: &str = "firmware/ci/expected";
/// The variable that makes the co-simulation tests rewrite their `<image>.stack` files
/// instead of checking them (tests/firmware/gates.rs).
pub const BLESS_STACK_VAR: &str = "TOOLTOUCH_BLESS_STACK";
/// The tests that measure the stack high-water marks (one per image).
const STACK_TESTS: &str = "random_scenarios";

/// The largest value `expected` may grow to.
pub fn allowed(expected: u64) -> u64 {
    expected
        + (expected * MARGIN_PERCENT)
            .div_ceil(100)
            .max(MARGIN_MIN_BYTES)
}

/// `(text, data, bss)` of an ELF image, bytes (llvm-size, Berkeley format).
pub fn sizes(image: &Path) -> Result<(u64, u64, u64)> {
    let out = Command::new("llvm-size")
        .arg(image)
        .output()
        .context("running `llvm-size` (run `cargo xtask setup` to install Debian's llvm)")?;
    if !out.status.success() {
        bail!("`llvm-size {}` failed ({})", image.display(), out.status);
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .nth(1)
        .with_context(|| format!("llvm-size printed no sizes for {}", image.display()))?;
    let n: Vec<u64> = line
        .split_whitespace()
        .take(3)
        .map(str::parse)
        .collect::<Result<_, _>>()
        .with_context(|| format!("llvm-size's line {line:?} is not `text data bss …`"))?;
    match n[..] {
        [t, d, b] => Ok((t, d, b)),
        _ => bail!("llvm-size's line {line:?} is not `text data bss …`"),
    }
}

/// The figures of a committed file: the numbers of its first line that is not a `#`
/// comment.
pub fn read_figures(path: &Path) -> Result<Vec<u64>> {
    let text = std::fs::read_to_string(path).with_context(|| {
        format!(
            "reading {} (`cargo xtask bless-firmware` writes it)",
            path.display()
        )
    })?;
    let line = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
        .with_context(|| format!("{} holds no figures", path.display()))?;
    line.split_whitespace()
        .map(str::parse)
        .collect::<Result<Vec<u64>, _>>()
        .with_context(|| format!("{}: {line:?} is not a line of byte counts", path.display()))
}

fn size_file(root: &Path, board: &str) -> PathBuf {
    root.join(EXPECTED_DIR).join(format!("{board}.size"))
}

/// Checks the release images `images` (board name, path) against their `<board>.size`.
pub fn check_sizes(root: &Path, images: &[(&str, PathBuf)]) -> Result<()> {
    let mut problems = Vec::new();
    for (board, image) in images {
        let (t, d, b) = sizes(image)?;
        let path = size_file(root, board);
        let want = read_figures(&path)?;
        if want.len() != 3 {
            bail!("{}: expected `text data bss`", path.display());
        }
        for ((section, got), want) in [(".text", t), (".data", d), (".bss", b)].iter().zip(&want) {
            let limit = allowed(*want);
            let verdict = if *got > limit {
                problems.push(format!(
                    "board {board}: {section} is {got} bytes, over the gate of {limit} \
                     (expected {want} + {MARGIN_PERCENT} %, at least {MARGIN_MIN_BYTES} bytes)"
                ));
                "OVER THE GATE"
            } else if got != want {
                "within the gate (`cargo xtask bless-firmware` records it)"
            } else {
                "as expected"
            };
            println!(
                "size gate: board {board} {section} {got} bytes, expected {want}, gate {limit}: {verdict}"
            );
        }
    }
    if !problems.is_empty() {
        bail!(
            "{}\nIf the growth is intended, `cargo xtask bless-firmware` records the new \
             figures in {EXPECTED_DIR}/.",
            problems.join("\n")
        );
    }
    Ok(())
}

/// `cargo xtask bless-firmware`: writes the release images' sizes to `<board>.size`, and
/// has the co-simulation tests that measure the stack high-water marks rewrite
/// `<image>.stack`.
pub fn bless(root: &Path, images: &[(&str, PathBuf)]) -> Result<()> {
    for (board, image) in images {
        let (t, d, b) = sizes(image)?;
        let path = size_file(root, board);
        let text = format!(
            "# text data bss of the {board} release image, bytes (llvm-size). The size gate of\n\
             # `cargo xtask test` fails on growth beyond {MARGIN_PERCENT} % (at least \
             {MARGIN_MIN_BYTES} bytes) of a figure;\n# `cargo xtask bless-firmware` rewrites this file.\n\
             {t} {d} {b}\n"
        );
        std::fs::create_dir_all(root.join(EXPECTED_DIR))?;
        std::fs::write(&path, &text).with_context(|| format!("writing {}", path.display()))?;
        println!("{}: {t} {d} {b}", path.display());
    }
    let status = Command::new("cargo")
        .args([
            "test",
            "--release",
            "--test",
            "firmware",
            STACK_TESTS,
            "--",
            "--nocapture",
        ])
        .current_dir(root)
        .env(BLESS_STACK_VAR, "1")
        .status()
        .context("could not start `cargo test`")?;
    if !status.success() {
        bail!("measuring the stack high-water marks failed ({status})");
    }
    Ok(())
}
