//! Running the component under `halrun`: build it with LinuxCNC's rules and the model's
//! static library, install it where `loadrt` finds it, and run a HAL file as an
//! unprivileged user (halrun refuses root).

use crate::common::{s, text, tooltouch};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::{Mutex, OnceLock};

/// The user `halrun` runs as when the tests run as root.
pub const HAL_USER: &str = "tooltouch-hal";

/// LinuxCNC's module folder (uspace builds: `loadrt NAME` opens `NAME.so` there, and
/// refuses a path).
pub const RTLIB_DIR: &str = "/usr/lib/linuxcnc/modules";

/// The repository's root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `tool` on the PATH, or a panic naming `cargo xtask setup`.
pub fn require(tool: &str) {
    if let Err(e) = tooltouch_rtl_sim::runner::find_tool(tool) {
        panic!("{e} (the LinuxCNC tests need linuxcnc-uspace and linuxcnc-uspace-dev)");
    }
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

/// The static library `libtooltouch_abi.a` cargo built beside this test binary.
pub fn static_library() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let deps = exe.parent().expect("the test binary's folder");
    [deps.to_path_buf(), deps.join("..")]
        .into_iter()
        .map(|d| d.join("libtooltouch_abi.a"))
        .find(|p| p.is_file())
        .unwrap_or_else(|| panic!("libtooltouch_abi.a is not in {}", deps.display()))
}

/// Builds the component and installs it into [`RTLIB_DIR`] once per test binary (its
/// build folder is returned); the tests run as root, or this fails saying so.
pub fn installed_component() -> &'static Path {
    static BUILD: OnceLock<PathBuf> = OnceLock::new();
    BUILD.get_or_init(|| {
        for tool in ["halrun", "halcompile", "make", "cc"] {
            require(tool);
        }
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("linuxcnc-build");
        std::fs::create_dir_all(&dir).unwrap();
        let o = Command::new("make")
            .arg("-C")
            .arg(&dir)
            .arg("-f")
            .arg(root().join("host/linuxcnc/hal/Makefile"))
            .arg(format!("ABI_LIB={}", static_library().display()))
            .arg("modules")
            .output()
            .expect("make runs");
        assert!(o.status.success(), "building the HAL component failed:\n{}", text(&o));
        assert!(
            is_root(),
            "the LinuxCNC tests install the component into {RTLIB_DIR} and create the user {HAL_USER}: run them as root (CI does), or install {} there by hand",
            dir.join("tooltouch.so").display()
        );
        // Whole or not at all: copy beside, then rename over the old one.
        let tmp = Path::new(RTLIB_DIR).join(format!(".tooltouch.so.{}", std::process::id()));
        std::fs::copy(dir.join("tooltouch.so"), &tmp).expect("copying into the module folder");
        std::fs::rename(&tmp, Path::new(RTLIB_DIR).join("tooltouch.so")).unwrap();
        dir
    })
}

/// The unprivileged user's uid, the user created when missing (once per test binary), with
/// a home folder it owns (`rtapi_app` puts its socket there).
fn hal_user_uid() -> u32 {
    static UID: OnceLock<u32> = OnceLock::new();
    *UID.get_or_init(|| {
        let id = |u: &str| Command::new("id").args(["-u", u]).output().unwrap();
        let mut o = id(HAL_USER);
        if !o.status.success() {
            let c = Command::new("useradd")
                .args(["--create-home", "--shell", "/bin/sh", HAL_USER])
                .output()
                .expect("useradd runs");
            assert!(c.status.success(), "useradd {HAL_USER}: {}", text(&c));
            o = id(HAL_USER);
        }
        let uid: u32 = String::from_utf8_lossy(&o.stdout).trim().parse().unwrap();
        let home = PathBuf::from(format!("/home/{HAL_USER}"));
        std::fs::create_dir_all(&home).unwrap();
        std::os::unix::fs::chown(&home, Some(uid), Some(uid)).unwrap();
        uid
    })
}

/// A work folder the HAL user owns (the samplers write into it).
pub fn work_dir() -> tempfile::TempDir {
    installed_component();
    let dir = tempfile::Builder::new()
        .prefix("tooltouch-hal-")
        .tempdir()
        .unwrap();
    std::os::unix::fs::chown(dir.path(), Some(hal_user_uid()), None).unwrap();
    dir
}

/// `command` in `dir` as [`HAL_USER`] (`su USER -c …`), one session at a time (HAL
/// sessions share realtime and its shared memory), a clean HAL after it.
pub fn as_hal_user(dir: &Path, command: &str) -> Output {
    static SESSION: Mutex<()> = Mutex::new(());
    let _session = SESSION.lock().unwrap_or_else(|e| e.into_inner());
    let cmd = format!("export HOME=/home/{HAL_USER}; cd '{}' && {command}", s(dir));
    let o = Command::new("su")
        .args([HAL_USER, "-c", &cmd])
        .output()
        .expect("su runs");
    // A failed run can leave realtime running: stop it (as the same user).
    let _ = Command::new("su")
        .args([
            HAL_USER,
            "-c",
            &format!("export HOME=/home/{HAL_USER}; halrun -U"),
        ])
        .output();
    o
}

/// `halrun -f FILE` in `dir` as [`HAL_USER`].
pub fn halrun(dir: &Path, hal_file: &str) -> Output {
    std::fs::write(dir.join("run.hal"), hal_file).unwrap();
    as_hal_user(dir, "halrun -f run.hal")
}

/// `tooltouch cosim config --config SETTINGS --out OUT` (the component's configuration
/// file), readable by the HAL user.
pub fn write_config(settings: &Path, out: &Path) {
    let o = tooltouch(&["cosim", "config", "--config", s(settings), "--out", s(out)]);
    assert!(o.status.success(), "cosim config: {}", text(&o));
}

/// A HAL file that runs the component over `periods` rows of `stim.txt` in `dir`: the
/// streamer feeds its inputs, two samplers record every output (`measure.txt`,
/// `force.txt`, tagged with sample numbers), all in one servo thread of `period_ns`, in
/// this order: streamer, tooltouch, samplers.
pub fn stream_hal_file(
    dir: &Path,
    config: &Path,
    hashes: (u64, u64),
    periods: usize,
    period_ns: u32,
) -> String {
    use tooltouch_linuxcnc::files::{sampler_cfg, FORCE_PINS, MEASURE_PINS};
    use tooltouch_linuxcnc::period::PeriodInputs;
    let depth = periods + 16;
    let mut h = format!(
        "loadrt threads name1=servo period1={period_ns}\n\
         loadrt tooltouch config={} measure_hash={:016x} force_hash={:016x}\n\
         loadrt streamer depth={depth} cfg={}\n\
         loadrt sampler depth={depth},{depth} cfg={},{}\n",
        s(config),
        hashes.0,
        hashes.1,
        PeriodInputs::STREAMER_CFG,
        sampler_cfg(&MEASURE_PINS),
        sampler_cfg(&FORCE_PINS)
    );
    for (i, pin) in PeriodInputs::PINS.iter().enumerate() {
        h.push_str(&format!(
            "net in-{pin} streamer.0.pin.{i} => tooltouch.0.{pin}\n"
        ));
    }
    for (channel, pins) in [(0, &MEASURE_PINS[..]), (1, &FORCE_PINS[..])] {
        for (i, (pin, _)) in pins.iter().enumerate() {
            h.push_str(&format!(
                "net out-{pin} tooltouch.0.{pin} => sampler.{channel}.pin.{i}\n"
            ));
        }
    }
    h.push_str(&format!(
        "addf streamer.0 servo\naddf tooltouch.0.update servo\naddf sampler.0 servo\naddf sampler.1 servo\n\
         loadusr -w halstreamer -c 0 {stim}\n\
         start\n\
         loadusr -w halsampler -c 0 -t -n {periods} {measure}\n\
         loadusr -w halsampler -c 1 -t -n {periods} {force}\n\
         stop\n\
         show pin tooltouch.0.overruns\nshow pin tooltouch.0.abi-errors\nshow pin tooltouch.0.exec-time\nshow param tooltouch.0.update.tmax\n",
        stim = s(&dir.join("stim.txt")),
        measure = s(&dir.join("measure.txt")),
        force = s(&dir.join("force.txt")),
    ));
    h
}
