//! The Nucleo's on-target tests (firmware/tests/on_target.rs, defmt-test) under QEMU's
//! `netduinoplus2`: their `emulated` build, booted with semihosting, their defmt log
//! decoded with defmt's own decoder ([`crate::nucleo::decode_defmt`]) and split into one
//! [`TestReport`] per test as defmt-test announces them (`(i/n) running `name`...`).
//!
//! On a board the same tests run under probe-rs (`cd firmware && cargo nucleo-test`);
//! here the tests that need what the machine does not emulate log why they are skipped
//! (firmware/tests/on_target.rs: `skipped under QEMU netduinoplus2: <reason>`).

use super::error::CosimError;
use super::nucleo::{self, EMULATED_BUILD, MACHINE_ARGS, TARGET};
use super::qemu::{self, DEFMT_FILE, QEMU};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The test target's name (firmware/Cargo.toml `[[test]]`).
pub const TEST: &str = "on_target";
/// What a test logs under emulation in place of running.
pub const SKIP_PREFIX: &str = "skipped under QEMU netduinoplus2: ";
/// defmt-test's last line when every test passed.
pub const ALL_PASSED: &str = "all tests passed!";
/// A run that takes longer is killed (the tests take well under a second of QEMU).
pub const WATCHDOG: Duration = Duration::from_secs(120);

/// Builds the on-target tests' emulated image (release, from inside firmware/) and
/// returns its path, copied to `firmware/target/images/on-target-emulated` under the
/// images' build lock.
pub fn build_emulated() -> Result<PathBuf, CosimError> {
    qemu::check_tools_for(TARGET)?;
    let dir = qemu::firmware_dir();
    let images = dir.join("target").join("images");
    let io = |what: &str, path: &Path, e: std::io::Error| {
        CosimError::Io(format!("{what} {}: {e}", path.display()))
    };
    std::fs::create_dir_all(&images).map_err(|e| io("creating", &images, e))?;
    let lock_path = images.join("build.lock");
    let lock = std::fs::File::create(&lock_path).map_err(|e| io("creating", &lock_path, e))?;
    lock.lock().map_err(|e| io("locking", &lock_path, e))?;
    let mut cargo = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cargo
        .args(["build", "--release"])
        .args(EMULATED_BUILD)
        .args(["--test", TEST, "--message-format=json-render-diagnostics"])
        .current_dir(&dir)
        // The root package's test environment must not leak into the firmware build.
        .env_remove("CARGO_TARGET_DIR")
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .env_remove("CARGO_BUILD_TARGET")
        .env_remove("TOOLTOUCH_FIRMWARE_CONFIG")
        .stderr(Stdio::inherit());
    let out = cargo
        .output()
        .map_err(|e| CosimError::Build(format!("cannot start cargo in {}: {e}", dir.display())))?;
    if !out.status.success() {
        return Err(CosimError::Build(format!(
            "`cargo build --release {} --test {TEST}` in {} failed ({})",
            EMULATED_BUILD.join(" "),
            dir.display(),
            out.status
        )));
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    let built = stdout
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter(|v| v["reason"] == "compiler-artifact" && v["target"]["name"] == TEST)
        .filter_map(|v| v["executable"].as_str().map(PathBuf::from))
        .next_back()
        .ok_or_else(|| CosimError::Build(format!("cargo reported no `{TEST}` executable")))?;
    let image = images.join("on-target-emulated");
    let partial = images.join("on-target-emulated.partial");
    std::fs::copy(&built, &partial).map_err(|e| io("copying the image to", &partial, e))?;
    std::fs::rename(&partial, &image).map_err(|e| io("renaming", &partial, e))?;
    Ok(image)
}

/// One on-target test as its log shows it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TestReport {
    /// Its name (the function's).
    pub name: String,
    /// Its number and the count defmt-test announced (`(i/n)`).
    pub number: (usize, usize),
    /// The lines it logged (a skipped test: the skip line only).
    pub lines: Vec<String>,
}

impl TestReport {
    /// The reason it was skipped under emulation, if it was.
    pub fn skipped(&self) -> Option<&str> {
        match &self.lines[..] {
            [line] => line.strip_prefix(SKIP_PREFIX),
            _ => None,
        }
    }
}

/// One QEMU run of the on-target tests.
#[derive(Clone, Debug)]
pub struct OnTargetRun {
    /// QEMU's exit status (the image's semihosting exit: 0 when every test passed; `None`
    /// if QEMU was killed by a signal).
    pub status: Option<i32>,
    /// The whole decoded log.
    pub log: Vec<String>,
    /// The log ended with defmt-test's [`ALL_PASSED`].
    pub all_passed: bool,
    /// The lines before the first test (`#[init]`'s).
    pub init: Vec<String>,
    /// Every test announced, in order.
    pub tests: Vec<TestReport>,
    /// QEMU's wall time.
    pub elapsed: Duration,
}

/// Boots the tests' `image` on netduinoplus2 and decodes its log; a test that failed is
/// no error here (the run's status and log say so), a QEMU that cannot start or hangs is.
pub fn run(image: &Path) -> Result<OnTargetRun, CosimError> {
    static NEXT: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("tooltouch-on-target-{}-{n}", std::process::id()));
    let io = |what: &str, path: &Path, e: std::io::Error| {
        CosimError::Io(format!("{what} {}: {e}", path.display()))
    };
    std::fs::create_dir_all(&dir).map_err(|e| io("creating", &dir, e))?;
    let start = Instant::now();
    let result = (|| {
        let mut child = Command::new(QEMU)
            .args(MACHINE_ARGS)
            .arg("-kernel")
            .arg(image)
            .current_dir(&dir)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| CosimError::ToolMissing(format!("cannot start `{QEMU}`: {e}")))?;
        let status = loop {
            match child.try_wait() {
                Ok(Some(status)) => break status,
                Ok(None) if start.elapsed() > WATCHDOG => {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err(CosimError::Qemu(format!(
                        "the on-target tests ran longer than {} s under QEMU and were killed",
                        WATCHDOG.as_secs()
                    )));
                }
                Ok(None) => std::thread::sleep(Duration::from_millis(5)),
                Err(e) => return Err(CosimError::Qemu(format!("waiting for QEMU: {e}"))),
            }
        };
        let frames = std::fs::read(dir.join(DEFMT_FILE)).unwrap_or_default();
        Ok((status.code(), frames))
    })();
    let elapsed = start.elapsed();
    let _ = std::fs::remove_dir_all(&dir);
    let (status, frames) = result?;
    let elf = std::fs::read(image).map_err(|e| io("reading", image, e))?;
    let log = nucleo::decode_defmt(&elf, &frames)?;
    let all_passed = log.last().is_some_and(|l| l == ALL_PASSED);
    let (init, tests) = split(&log[..log.len() - usize::from(all_passed)])?;
    Ok(OnTargetRun {
        status,
        log,
        all_passed,
        init,
        tests,
        elapsed,
    })
}

/// `(i/n) running `name`...` → (i, n, name).
fn announcement(line: &str) -> Option<(usize, usize, &str)> {
    let rest = line.strip_prefix('(')?;
    let (numbers, rest) = rest.split_once(") running `")?;
    let name = rest.strip_suffix("`...")?;
    let (i, n) = numbers.split_once('/')?;
    Some((i.parse().ok()?, n.parse().ok()?, name))
}

/// The log split at defmt-test's announcements: `#[init]`'s lines, then each test's.
fn split(log: &[String]) -> Result<(Vec<String>, Vec<TestReport>), CosimError> {
    let mut init = Vec::new();
    let mut tests: Vec<TestReport> = Vec::new();
    for line in log {
        if let Some((i, n, name)) = announcement(line) {
            if i != tests.len() + 1 {
                return Err(CosimError::Trace {
                    offset: 0,
                    why: format!("test {i} of {n} ({name}) announced after {}", tests.len()),
                });
            }
            tests.push(TestReport {
                name: name.to_string(),
                number: (i, n),
                lines: Vec::new(),
            });
        } else if let Some(t) = tests.last_mut() {
            t.lines.push(line.clone());
        } else {
            init.push(line.clone());
        }
    }
    Ok((init, tests))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_log_splits_at_the_announcements() {
        let log: Vec<String> = [
            "SYSCLK 16000000 Hz",
            "(1/2) running `a`...",
            "a's line",
            "(2/2) running `b_c`...",
            "skipped under QEMU netduinoplus2: no DWT",
        ]
        .map(String::from)
        .to_vec();
        let (init, tests) = split(&log).unwrap();
        assert_eq!(init, ["SYSCLK 16000000 Hz"]);
        assert_eq!(tests.len(), 2);
        assert_eq!(tests[0].name, "a");
        assert_eq!(tests[0].lines, ["a's line"]);
        assert_eq!(tests[0].skipped(), None);
        assert_eq!(tests[1].number, (2, 2));
        assert_eq!(tests[1].skipped(), Some("no DWT"));
    }

    #[test]
    fn an_announcement_out_of_order_is_an_error() {
        let log = ["(2/2) running `b`...".to_string()];
        assert!(split(&log).is_err());
        assert_eq!(
            announcement("(3/10) running `x_y`..."),
            Some((3, 10, "x_y"))
        );
        assert_eq!(announcement("(3/10) ignoring `x`..."), None);
    }
}
