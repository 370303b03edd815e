//! Building the QEMU firmware image (with its default configuration, or with one baked
//! in) and booting it on the co-simulation board.

use super::error::CosimError;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use tooltouch_settings::firmware_config::{FirmwareConfig, CONFIG_VAR};

/// The QEMU board's target triple.
pub const TARGET: &str = "thumbv7m-none-eabi";
/// The emulator.
pub const QEMU: &str = "qemu-system-arm";
/// Input file name the firmware opens over semihosting (firmware/src/semihosting.rs).
pub const EVENTS_FILE: &str = "tooltouch-events.bin";
/// Output file name the firmware writes over semihosting.
pub const OUTPUTS_FILE: &str = "tooltouch-outputs.bin";
/// QEMU arguments before the image: the lm3s6965evb, semihosting to the host's files,
/// `-icount shift=0` so that virtual time (and SysTick) advances 1 ns per instruction.
pub const QEMU_ARGS: [&str; 13] = [
    "-cpu",
    "cortex-m3",
    "-machine",
    "lm3s6965evb",
    "-nographic",
    "-monitor",
    "none",
    "-serial",
    "none",
    "-semihosting-config",
    "enable=on,target=native",
    "-icount",
    "shift=0",
];
/// QEMU's exit status at the end of a firmware run (firmware/src/semihosting.rs; the
/// table is in docs/firmware.md).
pub mod exit_code {
    /// Every stream replayed, the whole trace written.
    pub const OK: i32 = 0;
    /// The firmware panicked (a bug: the release image links no panic path).
    pub const FAILURE: i32 = 1;
    /// The events file could not be opened.
    pub const NO_EVENTS_FILE: i32 = 2;
    /// The events file is malformed (the trace ends with an error record).
    pub const MALFORMED_EVENTS: i32 = 3;
    /// Reading the events or writing the trace failed.
    pub const FILE_IO: i32 = 4;
    /// The baked configuration did not decode (never: the build checks it).
    pub const BAD_BAKED_CONFIG: i32 = 5;
}

/// A QEMU run that takes longer is killed (a hung firmware), not a speed assertion.
pub const WATCHDOG: Duration = Duration::from_secs(900);

/// A private working folder for one QEMU run, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new() -> Result<TempDir, CosimError> {
        static NEXT: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let path = std::env::temp_dir().join(format!("tooltouch-cosim-{}-{n}", std::process::id()));
        std::fs::create_dir_all(&path)
            .map_err(|e| CosimError::Io(format!("creating {}: {e}", path.display())))?;
        Ok(TempDir(path))
    }
    fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The firmware/ folder of this repository.
pub fn firmware_dir() -> PathBuf {
    // This crate is host/firmware-runner/ in the workspace.
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../firmware")
}

/// Fails naming `cargo xtask setup` when QEMU or the thumb target is missing.
pub fn check_tools() -> Result<(), CosimError> {
    check_tools_for(TARGET)
}

/// Fails naming `cargo xtask setup` when QEMU or the rustup target `target` is missing.
pub fn check_tools_for(target: &str) -> Result<(), CosimError> {
    let qemu = Command::new(QEMU)
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    if !matches!(qemu, Ok(s) if s.success()) {
        return Err(CosimError::ToolMissing(format!(
            "`{QEMU}` is not installed or does not run"
        )));
    }
    let sysroot = Command::new("rustc")
        .args(["--print", "sysroot"])
        .current_dir(firmware_dir())
        .output()
        .map_err(|e| CosimError::ToolMissing(format!("cannot run rustc: {e}")))?;
    let sysroot = PathBuf::from(String::from_utf8_lossy(&sysroot.stdout).trim());
    if !sysroot.join("lib/rustlib").join(target).exists() {
        return Err(CosimError::ToolMissing(format!(
            "the rustup target {target} is not installed in {}",
            sysroot.display()
        )));
    }
    Ok(())
}

/// Builds the QEMU firmware with its default configuration (release, from inside
/// firmware/ so its .cargo/config.toml applies) and returns the image's path (see
/// [`build_configured_firmware`]).
pub fn build_firmware() -> Result<PathBuf, CosimError> {
    build_image(None)
}

/// Builds the QEMU firmware with `config` baked in and returns the image's path.
///
/// Every image this module builds is copied out of cargo's release folder to
/// `firmware/target/images/qemu-<measure hash>-<force hash>` (written to a temporary name
/// and renamed, under a file lock held for the build and the copy), so a build with
/// another configuration never changes an image another run is booting, and all builds
/// share one target folder (switching configurations rebuilds only the firmware crate).
pub fn build_configured_firmware(config: &FirmwareConfig) -> Result<PathBuf, CosimError> {
    build_image(Some(config))
}

fn build_image(config: Option<&FirmwareConfig>) -> Result<PathBuf, CosimError> {
    check_tools()?;
    // The defaults are what a build without a configuration file bakes in: build that
    // way, so the default image is not rebuilt for an unchanged configuration.
    let config = config.filter(|c| **c != FirmwareConfig::default());
    let name = format!("qemu-{}", config.copied().unwrap_or_default().image_name());
    let baked = config.map(FirmwareConfig::baked_bytes);
    build_into_images(&[], Artifact::Bin("qemu"), &name, baked.as_deref())
}

/// What cargo builds in firmware/: a binary (`--bin`) or a test target (`--test`).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Artifact<'a> {
    /// `--bin <name>`.
    Bin(&'a str),
    /// `--test <name>`.
    Test(&'a str),
}

impl Artifact<'_> {
    fn flag(self) -> &'static str {
        match self {
            Artifact::Bin(_) => "--bin",
            Artifact::Test(_) => "--test",
        }
    }
    fn name(&self) -> &str {
        match self {
            Artifact::Bin(n) | Artifact::Test(n) => n,
        }
    }
}

/// Builds `artifact` (release, from inside firmware/, `selection` before it) with the
/// baked configuration `baked` (its bytes; `None`: the defaults) and copies the executable
/// to `firmware/target/images/<image>` — written to a temporary name and renamed, under a
/// file lock held for the build and the copy, so that a build with another configuration
/// never changes an image another run is booting.
pub(crate) fn build_into_images(
    selection: &[&str],
    artifact: Artifact<'_>,
    image: &str,
    baked: Option<&[u8]>,
) -> Result<PathBuf, CosimError> {
    let dir = firmware_dir();
    let images = dir.join("target").join("images");
    let io = |what: &str, path: &Path, e: std::io::Error| {
        CosimError::Io(format!("{what} {}: {e}", path.display()))
    };
    std::fs::create_dir_all(&images).map_err(|e| io("creating", &images, e))?;
    let lock_path = images.join("build.lock");
    let lock = std::fs::File::create(&lock_path).map_err(|e| io("creating", &lock_path, e))?;
    lock.lock().map_err(|e| io("locking", &lock_path, e))?;
    let baked = match baked {
        Some(bytes) => {
            let path = images.join(format!("{image}.config.bin"));
            std::fs::write(&path, bytes).map_err(|e| io("writing", &path, e))?;
            Some(path)
        }
        None => None,
    };
    let built = cargo_build(&dir, selection, artifact, baked.as_deref())?;
    let path = images.join(image);
    let partial = images.join(format!("{image}.partial"));
    std::fs::copy(&built, &partial).map_err(|e| io("copying the image to", &partial, e))?;
    std::fs::rename(&partial, &path).map_err(|e| io("renaming", &partial, e))?;
    Ok(path)
}

/// `cargo build --release <selection> --bin|--test <name>` in `dir` with
/// `TOOLTOUCH_FIRMWARE_CONFIG` set to `baked` (removed for `None`: the defaults); returns
/// the executable cargo reports.
fn cargo_build(
    dir: &Path,
    selection: &[&str],
    artifact: Artifact<'_>,
    baked: Option<&Path>,
) -> Result<PathBuf, CosimError> {
    let bin = artifact.name();
    let kind = artifact.flag();
    let mut cargo = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cargo
        .args(["build", "--release"])
        .args(selection)
        .args([kind, bin, "--message-format=json-render-diagnostics"])
        .current_dir(dir)
        // The root package's test environment must not leak into the firmware build.
        .env_remove("CARGO_TARGET_DIR")
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .env_remove("CARGO_BUILD_TARGET")
        .env_remove(CONFIG_VAR)
        .stderr(Stdio::inherit());
    if let Some(baked) = baked {
        cargo.env(CONFIG_VAR, baked);
    }
    let out = cargo
        .output()
        .map_err(|e| CosimError::Build(format!("cannot start cargo in {}: {e}", dir.display())))?;
    if !out.status.success() {
        return Err(CosimError::Build(format!(
            "`cargo build --release {} {kind} {bin}` in {} failed ({})",
            selection.join(" "),
            dir.display(),
            out.status
        )));
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    stdout
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter(|v| v["reason"] == "compiler-artifact" && v["target"]["name"] == bin)
        .filter_map(|v| v["executable"].as_str().map(PathBuf::from))
        .next_back()
        .ok_or_else(|| CosimError::Build(format!("cargo reported no `{bin}` executable")))
}

/// Boots `image` in QEMU with `events` as its input file; returns the output trace file's
/// bytes and QEMU's wall time.
pub fn run_image(image: &Path, events: &[u8]) -> Result<(Vec<u8>, Duration), CosimError> {
    let run = run_machine(&QEMU_ARGS, image, events)?;
    Ok((run.trace, run.elapsed))
}

/// What one QEMU run of a co-simulation image left.
#[derive(Clone, Debug)]
pub struct MachineRun {
    /// The output trace file's bytes.
    pub trace: Vec<u8>,
    /// QEMU's wall time (boot included).
    pub elapsed: Duration,
    /// The defmt frames the image wrote (`tooltouch-defmt.bin`; empty if none).
    pub defmt: Vec<u8>,
}

/// The file the emulated Nucleo writes its defmt frames to (firmware/src/semihosting.rs).
pub const DEFMT_FILE: &str = "tooltouch-defmt.bin";

/// One boot of an image: QEMU's exit status and standard error, and the files the image
/// wrote over semihosting.
pub(crate) struct Boot {
    /// QEMU's exit status (the image's semihosting exit).
    pub status: std::process::ExitStatus,
    /// QEMU's standard error.
    pub stderr: String,
    /// The output trace file's bytes (empty if none).
    pub trace: Vec<u8>,
    /// The defmt frames (empty if none).
    pub defmt: Vec<u8>,
    /// QEMU's wall time.
    pub elapsed: Duration,
}

/// Boots `image` in QEMU with the machine arguments `args` and `events` as its input file,
/// in a fresh folder; kills it after `watchdog` and fails with `hung(seconds)`.
pub(crate) fn boot(
    args: &[&str],
    image: &Path,
    events: &[u8],
    watchdog: Duration,
    hung: &dyn Fn(u64) -> String,
) -> Result<Boot, CosimError> {
    let dir = TempDir::new()?;
    let input = dir.path().join(EVENTS_FILE);
    std::fs::write(&input, events)
        .map_err(|e| CosimError::Io(format!("writing {}: {e}", input.display())))?;
    let start = Instant::now();
    let mut child = Command::new(QEMU)
        .args(args)
        .arg("-kernel")
        .arg(image)
        .current_dir(dir.path())
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| CosimError::ToolMissing(format!("cannot start `{QEMU}`: {e}")))?;
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) if start.elapsed() > watchdog => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(CosimError::Qemu(hung(watchdog.as_secs())));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(5)),
            Err(e) => return Err(CosimError::Qemu(format!("waiting for QEMU: {e}"))),
        }
    };
    let elapsed = start.elapsed();
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut stderr);
    }
    Ok(Boot {
        status,
        stderr,
        trace: std::fs::read(dir.path().join(OUTPUTS_FILE)).unwrap_or_default(),
        defmt: std::fs::read(dir.path().join(DEFMT_FILE)).unwrap_or_default(),
        elapsed,
    })
}

/// Boots `image` in QEMU with the machine arguments `args` and `events` as its input file.
pub fn run_machine(args: &[&str], image: &Path, events: &[u8]) -> Result<MachineRun, CosimError> {
    let Boot {
        status,
        stderr,
        trace,
        defmt,
        elapsed,
    } = boot(args, image, events, WATCHDOG, &|s| {
        format!("QEMU ran longer than {s} s and was killed (firmware hung?)")
    })?;
    if !status.success() {
        // The firmware exits with failure after writing an error record: report that.
        if let Err(CosimError::Firmware(why)) = super::trace::parse(&trace) {
            return Err(CosimError::Firmware(why));
        }
        return Err(CosimError::Qemu(format!(
            "QEMU exited with {status}; stderr: {}",
            stderr.trim()
        )));
    }
    Ok(MachineRun {
        trace,
        elapsed,
        defmt,
    })
}
