//! Firmware builds and tests, always run from inside firmware/ so its own
//! .cargo/config.toml applies (target, QEMU / probe-rs runners, link arguments). That
//! file sets a thumb target as the default, so the host tests name the host's triple.

use anyhow::{bail, Context, Result};
use std::path::Path;
use std::process::Command;

/// One board: its name, target triple and the cargo arguments that select it.
struct Board {
    name: &'static str,
    target: &'static str,
    features: &'static [&'static str],
}

const BOARDS: [Board; 2] = [
    Board {
        name: "qemu",
        target: "thumbv7m-none-eabi",
        features: &["--features", "qemu"],
    },
    Board {
        name: "nucleo",
        target: "thumbv7em-none-eabihf",
        features: &["--no-default-features", "--features", "nucleo"],
    },
];

fn cargo_args<'a>(verb: &'a str, board: &'a Board, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![verb, "--release", "--target", board.target];
    args.extend_from_slice(board.features);
    args.extend_from_slice(extra);
    args
}

fn firmware_dir() -> Result<std::path::PathBuf> {
    let dir = crate::process::root().join("firmware");
    if !dir.join("Cargo.toml").exists() {
        bail!("firmware/Cargo.toml is missing");
    }
    Ok(dir)
}

/// The variable firmware/build.rs reads: the configuration file to bake in.
const CONFIG_VAR: &str = "TOOLTOUCH_FIRMWARE_CONFIG";

/// `cargo xtask firmware [--config SETTINGS] [--calibration CAL.json]`: builds both boards'
/// images, with the settings file's configuration (and the calibration file's entry for
/// it) baked in (validated by `tooltouch cosim config`, which writes the canonical bytes
/// build.rs reads), or the defaults without either.
pub fn build_command(args: &[String]) -> Result<()> {
    const USAGE: &str =
        "usage: cargo xtask firmware [--config settings.toml] [--calibration cal.json]";
    let (mut config, mut calibration) = (None, None);
    let mut rest = args.iter();
    while let Some(flag) = rest.next() {
        let slot = match flag.as_str() {
            "--config" => &mut config,
            "--calibration" => &mut calibration,
            _ => bail!("{USAGE}"),
        };
        match rest.next() {
            Some(path) if slot.is_none() => *slot = Some(Path::new(path)),
            _ => bail!("{USAGE}"),
        }
    }
    let baked = if config.is_some() || calibration.is_some() {
        let root = crate::process::root();
        let absolute = |p: &Path| {
            std::path::absolute(p)
                .map(|p| p.to_string_lossy().into_owned())
                .with_context(|| format!("{}: not a usable path", p.display()))
        };
        let baked = root.join("target").join("firmware-config.bin");
        std::fs::create_dir_all(root.join("target")).context("creating target/")?;
        let out = baked.to_string_lossy().into_owned();
        let mut cmd: Vec<String> = [
            "run",
            "--release",
            "--quiet",
            "--bin",
            "tooltouch",
            "--",
            "cosim",
            "config",
            "--out",
            &out,
        ]
        .map(String::from)
        .to_vec();
        for (flag, path) in [("--config", config), ("--calibration", calibration)] {
            if let Some(path) = path {
                cmd.push(flag.into());
                cmd.push(absolute(path)?);
            }
        }
        let cmd: Vec<&str> = cmd.iter().map(String::as_str).collect();
        crate::process::run(&root, "cargo", &cmd)?;
        Some(baked)
    } else {
        None
    };
    build_all(baked.as_deref())
}

/// Builds the firmware for every board (with the configuration file `baked` baked in, or
/// the defaults) and prints the image sizes.
pub fn build_all(baked: Option<&Path>) -> Result<()> {
    let dir = firmware_dir()?;
    for board in &BOARDS {
        let args = cargo_args("build", board, &["--bin", board.name]);
        println!(
            "$ (cd {}) {}cargo {}",
            dir.display(),
            baked.map_or_else(String::new, |b| format!("{CONFIG_VAR}={} ", b.display())),
            args.join(" ")
        );
        let mut cargo = Command::new("cargo");
        cargo.args(&args).current_dir(&dir).env_remove(CONFIG_VAR);
        if let Some(b) = baked {
            cargo.env(CONFIG_VAR, b);
        }
        let status = cargo.status().context("could not start `cargo`")?;
        if !status.success() {
            bail!("`cargo {}` failed ({status})", args.join(" "));
        }
        print_size(&dir, board)?;
        println!(
            "board {}: {}",
            board.name,
            image_path(&dir, board).display()
        );
    }
    Ok(())
}

/// fmt and clippy (`-D warnings`) of the firmware for every board, the no-panic link
/// check (with the `panic-check` feature the panic handler refers to an undefined symbol,
/// so the link fails if any panic path is left in the image), clippy of the on-target
/// tests and their board image's build, then the release builds of the shipped images
/// with their sizes.
pub fn check_all() -> Result<()> {
    let dir = firmware_dir()?;
    crate::process::run(&dir, "cargo", &["fmt", "--", "--check"])?;
    for board in &BOARDS {
        crate::process::run(
            &dir,
            "cargo",
            &cargo_args(
                "clippy",
                board,
                &["--bins", "--lib", "--", "-D", "warnings"],
            ),
        )?;
    }
    for board in &BOARDS {
        let features = match board.name {
            "qemu" => "qemu,panic-check",
            _ => "nucleo,panic-check",
        };
        let mut args = vec![
            "build",
            "--release",
            "--target",
            board.target,
            "--no-default-features",
            "--features",
            features,
            "--bin",
            board.name,
        ];
        // The bench's lathe player (src/bin/player) shares the Nucleo's features: checked
        // in the same build, so it costs one more link.
        if board.name == "nucleo" {
            args.extend_from_slice(&["--bin", "player"]);
        }
        crate::process::run(&dir, "cargo", &args).with_context(|| {
            format!(
                "the no-panic check of board `{}` failed: a panic path is linked into the \
                 firmware (look for `tooltouch_firmware_panic_path_linked_into_the_image`)",
                board.name
            )
        })?;
        println!("board {}: no panic path linked", board.name);
    }
    // The Nucleo's load-measuring variant (idle reports the interrupts' CPU load).
    let load_variant = [
        "--release",
        "--target",
        "thumbv7em-none-eabihf",
        "--no-default-features",
        "--features",
        "nucleo,cpu-load",
        "--bin",
        "nucleo",
    ];
    let mut clippy = vec!["clippy"];
    clippy.extend_from_slice(&load_variant);
    clippy.extend_from_slice(&["--", "-D", "warnings"]);
    crate::process::run(&dir, "cargo", &clippy)?;
    // The Nucleo image's and the lathe player's emulated builds (QEMU's netduinoplus2;
    // tests/firmware boots both).
    let emulated = [
        "clippy",
        "--release",
        "--target",
        "thumbv7em-none-eabihf",
        "--no-default-features",
        "--features",
        "emulated",
        "--bin",
        "nucleo",
        "--bin",
        "player",
        "--",
        "-D",
        "warnings",
    ];
    crate::process::run(&dir, "cargo", &emulated)?;
    // The on-target tests (tests/on_target.rs, defmt-test): linted for the board and for
    // the emulated build tests/firmware boots under netduinoplus2, and the board's image
    // linked (defmt-rtt, panic-probe, the Nucleo's memory map) so that `cargo nucleo-test`
    // builds on a bench as it does here; the lathe player's shipped image with it.
    for features in ["nucleo", "emulated"] {
        crate::process::run(
            &dir,
            "cargo",
            &[
                "clippy",
                "--release",
                "--target",
                "thumbv7em-none-eabihf",
                "--no-default-features",
                "--features",
                features,
                "--test",
                "on_target",
                "--",
                "-D",
                "warnings",
            ],
        )?;
    }
    crate::process::run(
        &dir,
        "cargo",
        &[
            "build",
            "--release",
            "--target",
            "thumbv7em-none-eabihf",
            "--no-default-features",
            "--features",
            "nucleo",
            "--test",
            "on_target",
            "--bin",
            "player",
        ],
    )
    .context("the on-target tests' board image or the lathe player's image failed to build")?;
    // …and its handlers, driver and defmt logger link no panic path either.
    crate::process::run(
        &dir,
        "cargo",
        &[
            "build",
            "--release",
            "--target",
            "thumbv7em-none-eabihf",
            "--no-default-features",
            "--features",
            "emulated,panic-check",
            "--bin",
            "nucleo",
            "--bin",
            "player",
        ],
    )
    .context("the no-panic check of the emulated Nucleo image or player failed")?;
    println!("board nucleo, emulated: no panic path linked (controller and player)");
    // The check builds share the release folder: build the shipped images last.
    build_all(None)?;
    crate::gates::check_sizes(&crate::process::root(), &release_images(&dir))
}

/// `cargo xtask bless-firmware`: the release images' sizes and the stack high-water marks
/// measured anew and written to `firmware/ci/expected/`.
pub fn bless_command() -> Result<()> {
    build_all(None)?;
    let dir = firmware_dir()?;
    crate::gates::bless(&crate::process::root(), &release_images(&dir))
}

/// Every board's release image, by board name.
fn release_images(dir: &Path) -> Vec<(&'static str, std::path::PathBuf)> {
    BOARDS
        .iter()
        .map(|b| (b.name, image_path(dir, b)))
        .collect()
}

/// The handlers' host tests (firmware/tests/handlers: event streams in each board's
/// interrupt order against the golden model) and their clippy, built for the host with
/// no board feature (the boards' binaries and crates are thumb-only).
pub fn host_tests() -> Result<()> {
    let dir = firmware_dir()?;
    let host = host_triple()?;
    crate::process::run(
        &dir,
        "cargo",
        &[
            "clippy",
            "--target",
            &host,
            "--no-default-features",
            "--all-targets",
            "--",
            "-D",
            "warnings",
        ],
    )?;
    crate::process::run(
        &dir,
        "cargo",
        &["test", "--target", &host, "--no-default-features"],
    )
}

/// The host's target triple, as `rustc -vV` reports it.
pub(crate) fn host_triple() -> Result<String> {
    let out = Command::new("rustc")
        .arg("-vV")
        .output()
        .context("could not start `rustc -vV`")?;
    if !out.status.success() {
        bail!("`rustc -vV` failed ({})", out.status);
    }
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .find_map(|line| line.strip_prefix("host: "))
        .map(str::to_string)
        .context("`rustc -vV` printed no `host:` line")
}

/// Prints text/data/bss of a board's release image with llvm-size (or
/// arm-none-eabi-size), if one is installed.
fn print_size(dir: &Path, board: &Board) -> Result<()> {
    let image = image_path(dir, board);
    for tool in ["llvm-size", "arm-none-eabi-size"] {
        if let Ok(out) = Command::new(tool).arg(&image).output() {
            if out.status.success() {
                print!("{}", String::from_utf8_lossy(&out.stdout));
                return Ok(());
            }
        }
    }
    println!(
        "(no llvm-size or arm-none-eabi-size: size of {} not printed)",
        image.display()
    );
    Ok(())
}

/// A board's release image.
fn image_path(dir: &Path, board: &Board) -> std::path::PathBuf {
    dir.join("target")
        .join(board.target)
        .join("release")
        .join(board.name)
}
