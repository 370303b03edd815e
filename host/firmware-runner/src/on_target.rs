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
use super::qemu::{self, Artifact};
use std::path::{Path, PathBuf};
use std::time::Duration;

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
    qemu::build_into_images(
        &EMULATED_BUILD,
        Artifact::Test(TEST),
        "on-target-emulated",
        None,
    )
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
    let boot = qemu::boot(&MACHINE_ARGS, image, &[], WATCHDOG, &|s| {
        format!("the on-target tests ran longer than {s} s under QEMU and were killed")
    })?;
    let (status, frames, elapsed) = (boot.status.code(), boot.defmt, boot.elapsed);
    let elf = std::fs::read(image)
        .map_err(|e| CosimError::Io(format!("reading {}: {e}", image.display())))?;
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
