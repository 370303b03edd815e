//! The hostile-input table: the built `tooltouch` binary run as a careless or hostile user
//! would, one row per case, each under a memory limit (`prlimit --as`) and a time limit.
//! A row passes when the exit code is the documented one (docs/cli.md: 0 success, 1 a
//! verdict that is not a pass, 2 bad input, 130 interrupted), the message names the culprit
//! (the flag, the key or the file as the user gave it), and nothing panicked (101),
//! aborted (134, e.g. an allocation failure under the limit), or ran past the time limit.
//!
//! The rows are
//! - every flag that takes a number or a value list, of every subcommand, read from the
//!   clap definition (a new flag is covered without touching this file), with the classes
//!   zero, negative, huge, NaN, inf, -inf, not a number and empty;
//! - every file argument (read from clap too: the `PathBuf` arguments other than `--out`)
//!   with the classes missing, empty, directory, corrupt, truncated, unreadable;
//! - every `--out` with an existing file, a path under a file, a read-only folder and an
//!   existing folder holding other files;
//! - the cases found by hand: sweep ranges that overflow, merge counts that lie, a run too
//!   large to hold, oversized and binary settings files, messages that blamed the wrong
//!   field, a closed pipe, Ctrl-C.
//!
//! Running as root, permission bits do not stop reads or writes: the read-only folders are
//! then made immutable (`chattr +i`, which stops root too, where the file system has it),
//! and the unreadable-file rows (nothing stops root from reading) are skipped, each skip
//! printed with its reason beside the counts. Run `cargo test --release --test cli hostile_inputs:: -- --nocapture` to see the counts.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Address-space limit of every run, bytes: a bug that allocates without bound fails
/// here as an abort instead of eating the machine.
const MEMORY_LIMIT: u64 = 1 << 30;
/// Time limit of every run.
const TIME_LIMIT: Duration = Duration::from_secs(30);
/// Runs in flight at once.
const WORKERS: usize = 4;

/// The expected exit codes of a row.
#[derive(Clone, Debug)]
enum Expect {
    /// Exactly this code.
    Code(i32),
    /// One of these codes; when 2, the message must name the culprit.
    AnyOf(&'static [i32]),
}

/// One row of the table.
#[derive(Clone, Debug)]
struct Case {
    /// Class and flag or file, for the report.
    name: String,
    args: Vec<String>,
    expect: Expect,
    /// The output (stdout + stderr) must contain one of these when the code is 2 (or, for
    /// [`Expect::Code`], always).
    culprit: Vec<String>,
    /// The output must not contain these.
    absent: Vec<String>,
    /// Substrings that must appear exactly once (a message printed twice is a bug).
    once: Vec<String>,
}

fn case(name: impl Into<String>, args: &[&str], expect: Expect, culprit: &[&str]) -> Case {
    Case {
        name: name.into(),
        args: args.iter().map(|a| a.to_string()).collect(),
        expect,
        culprit: culprit.iter().map(|a| a.to_string()).collect(),
        absent: Vec::new(),
        once: Vec::new(),
    }
}

/// What a run did.
#[derive(Debug)]
enum Outcome {
    Exited(i32, String),
    Signalled(i32, String),
    TimedOut,
}

fn tooltouch_bin() -> &'static str {
    env!("CARGO_BIN_EXE_tooltouch")
}

/// `prlimit --as=LIMIT tooltouch args...`, in `cwd`.
fn limited(args: &[String], cwd: &Path) -> Command {
    let mut c = Command::new("prlimit");
    c.arg(format!("--as={MEMORY_LIMIT}"))
        .arg("--")
        .arg(tooltouch_bin())
        .args(args)
        .current_dir(cwd)
        .stdin(Stdio::null());
    c
}

/// Runs `args` under the limits, killing it after [`TIME_LIMIT`].
fn run(args: &[String], cwd: &Path) -> Outcome {
    let mut child = limited(args, cwd)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("prlimit (util-linux) runs: install it with `cargo xtask setup` or apt-get");
    // Drain both pipes on threads, so a chatty run does not block on a full pipe.
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let t_out = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = out.read_to_end(&mut s);
        s
    });
    let t_err = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = err.read_to_end(&mut s);
        s
    });
    let start = Instant::now();
    let status = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break Some(st);
        }
        if start.elapsed() > TIME_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&t_out.join().unwrap()),
        String::from_utf8_lossy(&t_err.join().unwrap())
    );
    use std::os::unix::process::ExitStatusExt;
    match status {
        None => Outcome::TimedOut,
        Some(st) => match (st.code(), st.signal()) {
            (Some(c), _) => Outcome::Exited(c, text),
            (None, Some(sig)) => Outcome::Signalled(sig, text),
            (None, None) => Outcome::Signalled(0, text),
        },
    }
}

/// The failure kinds the report counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Failure {
    Panic,
    Hang,
    Abort,
    WrongCode,
    Unnamed,
}

/// A row's verdict: passed, or the failure kind and what happened.
type Verdict = Result<(), (Failure, String)>;

fn judge(c: &Case, o: &Outcome) -> Verdict {
    let (code, text) = match o {
        Outcome::TimedOut => {
            return Err((Failure::Hang, format!("ran past {TIME_LIMIT:?}")));
        }
        Outcome::Signalled(sig, text) => {
            return Err((Failure::Abort, format!("killed by signal {sig}: {text}")));
        }
        Outcome::Exited(code, text) => (*code, text),
    };
    if code == 101 || text.contains("panicked at") {
        return Err((Failure::Panic, text.clone()));
    }
    if code == 134 || text.contains("memory allocation of") {
        return Err((Failure::Abort, text.clone()));
    }
    let (ok, must_name) = match &c.expect {
        Expect::Code(want) => (code == *want, true),
        Expect::AnyOf(codes) => (codes.contains(&code), code == 2),
    };
    if !ok {
        return Err((
            Failure::WrongCode,
            format!("exit {code}, expected {:?}: {text}", c.expect),
        ));
    }
    if must_name && !c.culprit.is_empty() && !c.culprit.iter().any(|n| text.contains(n.as_str())) {
        return Err((
            Failure::Unnamed,
            format!("the message names none of {:?}: {text}", c.culprit),
        ));
    }
    if let Some(a) = c.absent.iter().find(|a| text.contains(a.as_str())) {
        return Err((Failure::Unnamed, format!("says `{a}`: {text}")));
    }
    if let Some(s) = c
        .once
        .iter()
        .find(|s| text.matches(s.as_str()).count() != 1)
    {
        return Err((Failure::Unnamed, format!("`{s}` not exactly once: {text}")));
    }
    Ok(())
}

use crate::common::FAST_LATHE as FAST;

/// Valid files of every kind the commands read, made by the binary itself.
struct Fixtures {
    dir: PathBuf,
    settings: PathBuf,
    events: PathBuf,
    expected: PathBuf,
    vcd: PathBuf,
    spec: PathBuf,
    results: PathBuf,
}

fn must(args: &[&str], cwd: &Path) {
    let args: Vec<String> = args.iter().map(|a| a.to_string()).collect();
    match run(&args, cwd) {
        Outcome::Exited(0, _) => {}
        o => panic!("fixture run {args:?}: {o:?}"),
    }
}

fn fixtures(dir: &Path) -> Fixtures {
    let settings = dir.join("fast.toml");
    std::fs::write(&settings, FAST).unwrap();
    let m = dir.join("measured");
    must(
        &[
            "measure",
            "--config",
            settings.to_str().unwrap(),
            "--out",
            m.to_str().unwrap(),
            "--no-progress",
        ],
        dir,
    );
    let spec = dir.join("spec.toml");
    std::fs::write(
        &spec,
        "scenarios = 1\nmethod = [\"counter\"]\ncontact_rule = [\"sticky\"]\nlaw = [\"linear\"]\n\
         charge_bits = [6]\nscale_bits = [16]\nglitch_cycles = [0]\n[approach]\nrevolutions = 1\n\
         [force]\ncontroller = []\n",
    )
    .unwrap();
    let t = dir.join("tuned");
    must(
        &[
            "tune",
            "--spec",
            spec.to_str().unwrap(),
            "--out",
            t.to_str().unwrap(),
        ],
        dir,
    );
    Fixtures {
        dir: dir.to_path_buf(),
        settings,
        events: m.join("events.ttv"),
        expected: m.join("expected_outputs.ttv"),
        vcd: m.join("measure.vcd"),
        spec,
        results: t.join("results.json"),
    }
}

/// Whether this process runs as root (permission bits then stop nothing).
fn running_as_root() -> bool {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata("/proc/self").is_ok_and(|m| m.uid() == 0)
}

/// The arguments that make each subcommand's run short, as `(flag, value)`; the flag under
/// test is left out of them. `out` is the row's own output folder.
fn base_args(sub: &str, f: &Fixtures, out: &Path) -> Vec<(String, Option<String>)> {
    let p = |x: &Path| Some(x.to_str().unwrap().to_string());
    let o = p(out);
    let v = |x: &str| Some(x.to_string());
    let list: Vec<(&str, Option<String>)> = match sub {
        "measure" => vec![
            ("--config", p(&f.settings)),
            ("--out", o),
            ("--vcd", v("none")),
            ("--no-progress", None),
        ],
        "check" => vec![("--expected", p(&f.expected)), ("--dut", p(&f.expected))],
        "vectors" => vec![("--stimulus", p(&f.events)), ("--out", o)],
        "control" | "wear" | "hdl" => vec![("--out", o)],
        "tune" => vec![("--spec", p(&f.spec)), ("--out", o)],
        "tune merge" => vec![("", p(&f.results)), ("--out", o)],
        _ => vec![],
    };
    list.into_iter().map(|(k, v)| (k.to_string(), v)).collect()
}

fn with_base(
    sub: &str,
    base: &[(String, Option<String>)],
    flag: &str,
    values: &[&str],
) -> Vec<String> {
    let mut args: Vec<String> = sub.split(' ').map(String::from).collect();
    for (k, v) in base.iter().filter(|(k, _)| flag.is_empty() || k != flag) {
        if !k.is_empty() {
            args.push(k.clone());
        }
        if let Some(v) = v {
            args.push(v.clone());
        }
    }
    if !flag.is_empty() {
        args.push(flag.to_string());
    }
    args.extend(values.iter().map(|v| v.to_string()));
    args
}

/// Every subcommand path (`tune merge` too) with its command.
fn subcommands() -> Vec<(String, clap::Command)> {
    let mut out = Vec::new();
    fn walk(prefix: &str, c: &clap::Command, out: &mut Vec<(String, clap::Command)>) {
        for s in c.get_subcommands() {
            let name = if prefix.is_empty() {
                s.get_name().to_string()
            } else {
                format!("{prefix} {}", s.get_name())
            };
            out.push((name.clone(), s.clone()));
            walk(&name, s, out);
        }
    }
    walk("", &tooltouch::cli::Cli::definition(), &mut out);
    // Their own tests cover these (tests/firmware/convention.rs, tests/firmware/configured.rs):
    // `cosim firmware` builds and boots a QEMU image, and `cosim config` and `tune point`
    // write one file, not an output folder, so the folder and input-file classes here do
    // not describe them.
    out.retain(|(name, _)| {
        !matches!(
            name.as_str(),
            "cosim firmware" | "cosim config" | "tune point"
        )
    });
    out
}

fn is_path(a: &clap::Arg) -> bool {
    a.get_value_parser().type_id() == std::any::TypeId::of::<PathBuf>()
}

/// An argument that takes a value and is neither a path nor a named choice: a number or
/// a value list (tune's `8..=16:4`), so the numeric classes apply.
fn is_numeric_like(a: &clap::Arg) -> bool {
    a.get_action().takes_values()
        && !is_path(a)
        && a.get_possible_values().is_empty()
        && a.get_long().is_some()
        && a.get_long() != Some("help")
        && a.get_long() != Some("version")
}

/// Numeric classes: (class, value).
const NUMERIC: [(&str, &str); 9] = [
    ("zero", "0"),
    ("negative", "-1"),
    ("huge", "99999999999999999999999"),
    ("u32 max", "4294967295"),
    ("NaN", "NaN"),
    ("inf", "inf"),
    ("-inf", "-inf"),
    ("not a number", "abc"),
    ("empty", ""),
];

fn numeric_rows(f: &Fixtures, rows: &mut Vec<Case>) {
    for (sub, cmd) in subcommands() {
        for a in cmd.get_arguments().filter(|a| is_numeric_like(a)) {
            let long = a.get_long().unwrap();
            let flag = format!("--{long}");
            for (class, value) in NUMERIC {
                let out = f
                    .dir
                    .join(format!("o-{}-{long}-{class}", sub.replace(' ', "-")));
                let base = base_args(&sub, f, &out);
                let args = with_base(&sub, &base, &flag, &[value]);
                let args: Vec<&str> = args.iter().map(String::as_str).collect();
                rows.push(case(
                    format!("{sub} {flag} {class} ({value:?})"),
                    &args,
                    Expect::AnyOf(&[0, 1, 2]),
                    &[&flag, &long.replace('-', "_")],
                ));
            }
        }
    }
}

/// A valid file of the kind an argument reads, for its truncated and corrupt rows.
fn valid_file_for<'a>(sub: &str, long: &str, f: &'a Fixtures) -> &'a Path {
    match (sub, long) {
        (_, "config") => &f.settings,
        (_, "spec") => &f.spec,
        ("vectors", "stimulus") | ("hdl", "vectors") => &f.events,
        ("check", _) => &f.expected,
        ("tune merge", _) => &f.results,
        _ => &f.settings,
    }
}

fn file_rows(f: &Fixtures, rows: &mut Vec<Case>, skipped: &mut Vec<String>) {
    let root = running_as_root();
    let files = f.dir.join("files");
    std::fs::create_dir_all(&files).unwrap();
    for (sub, cmd) in subcommands() {
        for a in cmd.get_arguments() {
            let takes_file = (is_path(a) && a.get_long() != Some("out"))
                || (sub == "hdl" && a.get_long() == Some("vectors"));
            if !takes_file {
                continue;
            }
            let long = a.get_long().unwrap_or("");
            let flag = if long.is_empty() {
                String::new()
            } else {
                format!("--{long}")
            };
            let tag = format!("{}-{}", sub.replace(' ', "-"), a.get_id());
            let valid = valid_file_for(&sub, long, f);
            let bytes = std::fs::read(valid).unwrap();
            let mut corrupt = bytes.clone();
            let mut x = 0x9e37_79b9u32;
            for (i, b) in corrupt.iter_mut().enumerate().skip(8) {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                if i % 7 == 0 {
                    *b = x as u8;
                }
            }
            let mut classes: Vec<(&str, PathBuf)> = Vec::new();
            let missing = files.join(format!("{tag}-missing"));
            classes.push(("missing", missing));
            let empty = files.join(format!("{tag}-empty"));
            std::fs::write(&empty, b"").unwrap();
            classes.push(("empty", empty));
            let dir = files.join(format!("{tag}-dir"));
            std::fs::create_dir_all(&dir).unwrap();
            classes.push(("directory", dir));
            let c = files.join(format!("{tag}-corrupt"));
            std::fs::write(&c, &corrupt).unwrap();
            classes.push(("corrupt", c));
            let t = files.join(format!("{tag}-truncated"));
            std::fs::write(&t, &bytes[..bytes.len() / 2]).unwrap();
            classes.push(("truncated", t));
            if root {
                skipped.push(format!(
                    "{sub} {} unreadable: running as root, permission bits do not stop reads",
                    if flag.is_empty() {
                        a.get_id().as_str()
                    } else {
                        &flag
                    }
                ));
            } else {
                let u = files.join(format!("{tag}-unreadable"));
                std::fs::write(&u, &bytes).unwrap();
                use std::os::unix::fs::PermissionsExt;
                std::fs::set_permissions(&u, std::fs::Permissions::from_mode(0o000)).unwrap();
                classes.push(("unreadable", u));
            }
            for (class, path) in classes {
                let out = f.dir.join(format!("o-{tag}-{class}"));
                let base = base_args(&sub, f, &out);
                let ps = path.to_str().unwrap();
                let args = if flag.is_empty() {
                    // A positional (tune merge's DIR...): the bad one alone.
                    with_base(&sub, &base[1..], "", &[ps])
                } else {
                    with_base(&sub, &base, &flag, &[ps])
                };
                let args: Vec<&str> = args.iter().map(String::as_str).collect();
                // A truncated device-under-test trace is a mismatch (1), the rest bad
                // input (2); every message names the file.
                let expect = if sub == "check" && class == "truncated" {
                    Expect::AnyOf(&[1, 2])
                } else if matches!(class, "truncated" | "corrupt")
                    && (long == "config" || long == "spec")
                {
                    // Half a TOML file can still be valid TOML, and so can a mutated one.
                    Expect::AnyOf(&[0, 2])
                } else {
                    Expect::AnyOf(&[2])
                };
                rows.push(case(
                    format!(
                        "{sub} {} {class}",
                        if flag.is_empty() { "DIR" } else { &flag }
                    ),
                    &args,
                    expect,
                    &[ps],
                ));
            }
        }
    }
}

/// Folders made immutable (`chattr +i`, which stops root too), made mutable again when
/// dropped so the temporary folder can be removed.
#[derive(Default)]
struct Immutable(Vec<PathBuf>);

impl Immutable {
    /// Makes `dir` immutable; false where the file system or `chattr` does not allow it.
    fn add(&mut self, dir: &Path) -> bool {
        let ok = Command::new("chattr")
            .arg("+i")
            .arg(dir)
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        if ok {
            self.0.push(dir.to_path_buf());
        }
        ok
    }
}

impl Drop for Immutable {
    fn drop(&mut self) {
        for d in &self.0 {
            let _ = Command::new("chattr").arg("-i").arg(d).status();
        }
    }
}

fn output_rows(
    f: &Fixtures,
    rows: &mut Vec<Case>,
    skipped: &mut Vec<String>,
    immutable: &mut Immutable,
) {
    let root = running_as_root();
    let outs = f.dir.join("outs");
    std::fs::create_dir_all(&outs).unwrap();
    for (sub, cmd) in subcommands() {
        if !cmd.get_arguments().any(|a| a.get_long() == Some("out")) {
            continue;
        }
        let tag = sub.replace(' ', "-");
        let file = outs.join(format!("{tag}-a-file"));
        std::fs::write(&file, "not a folder").unwrap();
        let under = file.join("sub");
        let existing = outs.join(format!("{tag}-existing"));
        std::fs::create_dir_all(&existing).unwrap();
        std::fs::write(existing.join("notes.txt"), "mine").unwrap();
        let mut classes: Vec<(&str, PathBuf, Expect)> = vec![
            ("an existing file", file.clone(), Expect::Code(2)),
            ("a path under a file", under, Expect::Code(2)),
            (
                "an existing folder with other files",
                existing,
                Expect::Code(0),
            ),
        ];
        let ro = outs.join(format!("{tag}-read-only"));
        std::fs::create_dir_all(&ro).unwrap();
        if !root {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
            classes.push(("a read-only folder", ro, Expect::Code(2)));
        } else if immutable.add(&ro) {
            // Root writes through permission bits, not through the immutable attribute.
            classes.push(("a read-only (immutable) folder", ro, Expect::Code(2)));
        } else {
            skipped.push(format!(
                "{sub} --out read-only: running as root (permission bits do not stop writes) \
                 on a file system without `chattr +i`"
            ));
        }
        for (class, path, expect) in classes {
            let base = base_args(&sub, f, &path);
            let args = with_base(&sub, &base, "", &[]);
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let named = if matches!(expect, Expect::Code(0)) {
                vec![]
            } else {
                vec![file.to_str().unwrap(), path.to_str().unwrap()]
            };
            rows.push(case(format!("{sub} --out {class}"), &args, expect, &named));
        }
    }
}

/// The cases found by hand (one row each).
fn named_rows(f: &Fixtures, rows: &mut Vec<Case>) {
    let d = &f.dir;
    let w = |name: &str, text: &[u8]| {
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let out = |name: &str| d.join(name).to_str().unwrap().to_string();
    let fast = f.settings.to_str().unwrap().to_string();
    let tune_small = [
        "tune",
        "--scenarios",
        "1",
        "--revolutions",
        "1",
        "--force-controller",
        "none",
    ];
    let mut r = |c: Case| rows.push(c);

    // Sweep sizes: a range whose width overflows i64, from a flag and from a spec file.
    let o = out("n-wrap");
    let mut a = tune_small.to_vec();
    a.extend([
        "--glitch-cycles=-5000000000000000000..=5000000000000000000",
        "--out",
        &o,
    ]);
    r(case(
        "tune range width overflows (flag)",
        &a,
        Expect::Code(2),
        &["glitch_cycles"],
    ));
    let spec = w(
        "wrap.toml",
        b"glitch_cycles = \"-5000000000000000000..=5000000000000000000\"\n[force]\ncontroller = []\n",
    );
    r(case(
        "tune range width overflows (spec)",
        &["tune", "--spec", &spec, "--out", &o],
        Expect::Code(2),
        &["glitch_cycles"],
    ));
    // The product of the ranges (5.4 GB before).
    let mut a = tune_small.to_vec();
    a.extend([
        "--i-def",
        "0..=1023",
        "--glitch-cycles",
        "0..=255",
        "--charge-bits",
        "4..=24",
        "--scale-bits",
        "8..=32",
        "--method",
        "counter,density,single_pulse",
        "--charge-pulses",
        "1..=100",
        "--out",
        &o,
    ]);
    r(case(
        "tune product of ranges over the cap",
        &a,
        Expect::Code(2),
        &["1000000"],
    ));
    // A force sweep over the cap.
    let spec = w(
        "force-big.toml",
        b"scenarios = 1\nmethod = [\"counter\"]\ncontact_rule = [\"sticky\"]\nlaw = [\"linear\"]\n\
          charge_bits = [6]\nscale_bits = [16]\nglitch_cycles = [0]\n[force]\n\
          kp_percent = \"1..=1000\"\nki_percent = \"1..=1000\"\n",
    );
    r(case(
        "tune force sweep over the cap",
        &["tune", "--spec", &spec, "--out", &o],
        Expect::Code(2),
        &["force.kp_percent"],
    ));

    // Merge counts that lie.
    let results: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&f.results).unwrap()).unwrap();
    for (field, value) in [
        ("points", serde_json::json!(1_000_000_000_000_000_000u64)),
        ("force_points", serde_json::json!(1u64 << 40)),
        ("points", serde_json::json!(u64::MAX)),
    ] {
        let mut v = results.clone();
        v[field] = value.clone();
        let p = w(
            &format!("lie-{field}-{value}.json"),
            &serde_json::to_vec(&v).unwrap(),
        );
        // u64::MAX: the sum of points + force_points must not overflow.
        r(case(
            format!("tune merge `{field}` = {value}"),
            &["tune", "merge", &p, "--out", &out("n-merge")],
            Expect::Code(2),
            &["points"],
        ));
    }

    // A run too large to hold (1.6 GB in encode_events before).
    r(case(
        "measure tiny feed, huge approach",
        &[
            "measure",
            "--repeats",
            "1",
            "--feed-mm-per-rev",
            "0.000001",
            "--max-approach-revs",
            "100000",
            "--clearance-um",
            "10000",
            "--vcd",
            "none",
            "--no-progress",
            "--out",
            &out("n-huge"),
        ],
        Expect::Code(2),
        &["--max-approach-revs"],
    ));

    // Harmonic lists: 300 (a small file, over the list cap) and 100 000 (over the file
    // size cap); a 39 MB settings file.
    let harmonics = |n: usize| {
        let mut s = String::from("[lathe]\nprofile = [\n");
        for i in 0..n {
            s.push_str(&format!(
                "{{ order = {}, amplitude_um = 0.01, phase_rad = 0.0 }},\n",
                i % 500 + 1
            ));
        }
        s.push_str("]\n");
        s
    };
    let p = w("h300.toml", harmonics(300).as_bytes());
    r(case(
        "[lathe] profile of 300 harmonics",
        &["measure", "--config", &p, "--out", &out("n-h")],
        Expect::Code(2),
        &["profile"],
    ));
    let p = w("h100k.toml", harmonics(100_000).as_bytes());
    r(case(
        "[lathe] profile of 100 000 harmonics",
        &["measure", "--config", &p, "--out", &out("n-h")],
        Expect::Code(2),
        &[&p],
    ));
    let big = {
        let mut s = FAST.to_string();
        let line = "# a comment line to make a large settings file................\n";
        while s.len() < 39_000_000 {
            s.push_str(line);
        }
        s
    };
    let p = w("big.toml", big.as_bytes());
    for sub in ["measure", "vectors", "hdl"] {
        let mut a = vec![sub, "--config", &p];
        let o = out(&format!("n-big-{sub}"));
        if sub == "vectors" {
            a.extend(["--stimulus", f.events.to_str().unwrap()]);
        }
        a.extend(["--out", &o]);
        r(case(
            format!("{sub} 39 MB settings file"),
            &a,
            Expect::Code(2),
            &[&p],
        ));
    }
    let mut s = big.into_bytes();
    s.truncate(2 << 20);
    let p = w("big-spec.toml", &s);
    r(case(
        "tune 2 MB spec file",
        &["tune", "--spec", &p, "--out", &out("n-bigspec")],
        Expect::Code(2),
        &[&p],
    ));

    // Messages that blamed the wrong thing.
    r(case(
        "measure --profile-gain -1",
        &["measure", "--profile-gain", "-1", "--out", &out("n-g")],
        Expect::Code(2),
        &["--profile-gain"],
    ));
    r(case(
        "measure --profile-gain 1e6",
        &["measure", "--profile-gain", "1e6", "--out", &out("n-g")],
        Expect::Code(2),
        &["--profile-gain"],
    ));
    let mut c = case(
        "measure --scale-resolution-um 0.001 --diameter-mm 2000",
        &[
            "measure",
            "--scale-resolution-um",
            "0.001",
            "--diameter-mm",
            "2000",
            "--out",
            &out("n-g"),
        ],
        Expect::Code(2),
        &["scale_resolution_um 0.001"],
    );
    c.once = vec!["retract_mm_per_s".into()];
    r(c);
    let bin = w("binary.toml", b"\xff\xfe\x00\x01binary\x00\x00");
    for sub in ["measure", "vectors", "hdl", "tune"] {
        let flag = if sub == "tune" { "--spec" } else { "--config" };
        let o = out(&format!("n-bin-{sub}"));
        let mut a = vec![sub, flag, &bin];
        if sub == "vectors" {
            a.extend(["--stimulus", f.events.to_str().unwrap()]);
        }
        a.extend(["--out", &o]);
        let mut c = case(
            format!("{sub} binary settings file"),
            &a,
            Expect::Code(2),
            &[&bin],
        );
        c.once = vec!["UTF-8".into()];
        r(c);
        let missing = d.join("no-such.toml");
        let ms = missing.to_str().unwrap();
        let mut a = vec![sub, flag, ms];
        if sub == "vectors" {
            a.extend(["--stimulus", f.events.to_str().unwrap()]);
        }
        a.extend(["--out", &o]);
        let mut c = case(
            format!("{sub} missing settings file"),
            &a,
            Expect::Code(2),
            &[ms],
        );
        c.once = vec!["No such file".into()];
        r(c);
        // Unknown tables are errors everywhere.
        let bogus = w(
            &format!("bogus-{sub}.toml"),
            if sub == "tune" {
                b"scenarios = 1\n[bogus]\nx = 1\n"
            } else {
                b"[measure]\ni_def = 512\n[bogus]\nx = 1\n"
            },
        );
        let mut a = vec![sub, flag, &bogus];
        if sub == "vectors" {
            a.extend(["--stimulus", f.events.to_str().unwrap()]);
        }
        a.extend(["--out", &o]);
        r(case(
            format!("{sub} unknown table [bogus]"),
            &a,
            Expect::Code(2),
            &["bogus"],
        ));
    }
    let mut c = case(
        "hdl --out a file",
        &["hdl", "--out", f.settings.to_str().unwrap()],
        Expect::Code(2),
        &["is a file"],
    );
    c.once = vec![f.settings.to_str().unwrap().to_string()];
    r(c);
    r(case(
        "tune --shard 18446744073709551615/2",
        &["tune", "--shard", "18446744073709551615/2", "--out", &o],
        Expect::Code(2),
        &["out of range"],
    ));
    let mut c = case(
        "tune --shard 18446744073709551615/2",
        &["tune", "--shard", "18446744073709551615/2", "--out", &o],
        Expect::Code(2),
        &["--shard"],
    );
    c.absent = vec!["not a whole number".into()];
    r(c);
    r(case(
        "hdl --stim-depth 4294967295",
        &[
            "hdl",
            "--stim-depth",
            "4294967295",
            "--out",
            &out("n-depth"),
        ],
        Expect::Code(2),
        &["--stim-depth"],
    ));
    // measure: a range error and a parse error, both bad input.
    r(case(
        "measure range error",
        &["measure", "--i-def", "5000", "--out", &out("n-m")],
        Expect::Code(2),
        &["--i-def"],
    ));
    r(case(
        "measure parse error",
        &["measure", "--i-def", "x", "--out", &out("n-m")],
        Expect::Code(2),
        &["--i-def"],
    ));
    r(case(
        "vectors --stimulus missing.vcd",
        &[
            "vectors",
            "--stimulus",
            &out("missing.vcd"),
            "--out",
            &out("n-v"),
        ],
        Expect::Code(2),
        &["missing.vcd"],
    ));
    for (name, bytes) in [
        ("empty.ttv", &b""[..]),
        ("badmagic.ttv", &b"NOTMAGIC\0\0\0\0"[..]),
    ] {
        let p = w(name, bytes);
        r(case(
            format!("check --dut {name}"),
            &[
                "check",
                "--expected",
                f.expected.to_str().unwrap(),
                "--dut",
                &p,
            ],
            Expect::Code(2),
            &[&p],
        ));
    }
    // Undecided: exit 1, and the table says no diameter was decided.
    let mut c = case(
        "measure undecided",
        &[
            "measure",
            "--config",
            &fast,
            "--max-approach-revs",
            "1",
            "--vcd",
            "none",
            "--no-progress",
            "--out",
            &out("n-undecided"),
        ],
        Expect::Code(1),
        &["no measurement decided"],
    );
    c.absent = vec!["diameter 0.0000 mm".into()];
    r(c);
    let _ = &f.vcd;
}

/// `tooltouch ... | head -1`: the reader goes away before the first line.
fn closed_pipe_rows(f: &Fixtures) -> Vec<(String, Verdict)> {
    let mut out = Vec::new();
    for (name, args) in [
        ("control | head", vec!["control", "--controller", "all"]),
        (
            "tune | head",
            vec!["tune", "--spec", f.spec.to_str().unwrap()],
        ),
        (
            "measure | head",
            vec![
                "measure",
                "--config",
                f.settings.to_str().unwrap(),
                "--no-progress",
                "--vcd",
                "none",
            ],
        ),
    ] {
        let o = f
            .dir
            .join(format!("pipe-{}", name.split(' ').next().unwrap()));
        let mut args: Vec<String> = args.into_iter().map(String::from).collect();
        args.extend(["--out".to_string(), o.to_str().unwrap().to_string()]);
        let mut child = limited(&args, &f.dir)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take()); // the reader closes the pipe at once
        let mut err = String::new();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut err)
            .unwrap();
        let st = child.wait().unwrap();
        let verdict = if err.contains("panicked") || st.code() == Some(101) {
            Err((Failure::Panic, err))
        } else if st.code() != Some(0) {
            Err((Failure::WrongCode, format!("{st}: {err}")))
        } else {
            Ok(())
        };
        out.push((name.to_string(), verdict));
    }
    out
}

/// Ctrl-C in the middle of a run: exit 130, nothing left in the output folder.
fn interrupt_row(f: &Fixtures) -> (String, Verdict) {
    let name = "measure interrupted by SIGINT".to_string();
    let o = f.dir.join("interrupted");
    let args: Vec<String> = [
        "measure",
        "--config",
        f.settings.to_str().unwrap(),
        "--repeats",
        "500",
        "--no-progress",
        "--out",
        o.to_str().unwrap(),
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let mut child = limited(&args, &f.dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let staged = loop {
        let found = std::fs::read_dir(&o).ok().is_some_and(|mut d| {
            d.any(|e| {
                e.is_ok_and(|e| {
                    e.file_name()
                        .to_string_lossy()
                        .starts_with(".tooltouch-partial")
                })
            })
        });
        if found || start.elapsed() > TIME_LIMIT {
            break found;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    std::thread::sleep(Duration::from_millis(300));
    let _ = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    let st = child.wait().unwrap();
    let left: Vec<String> = std::fs::read_dir(&o)
        .map(|d| {
            d.filter_map(Result::ok)
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    let verdict = if !staged {
        Err((Failure::Hang, "no staging folder appeared".to_string()))
    } else if st.code() != Some(130) {
        Err((Failure::WrongCode, format!("{st}, expected exit 130")))
    } else if !left.is_empty() {
        Err((Failure::WrongCode, format!("left behind: {left:?}")))
    } else {
        Ok(())
    };
    (name, verdict)
}

#[test]
fn hostile_inputs_neither_panic_nor_hang_nor_blow_up_and_name_the_culprit() {
    let started = Instant::now();
    let tmp = tempfile::tempdir().unwrap();
    let f = fixtures(tmp.path());
    let mut rows = Vec::new();
    let mut skipped = Vec::new();
    numeric_rows(&f, &mut rows);
    let numeric = rows.len();
    file_rows(&f, &mut rows, &mut skipped);
    let files = rows.len() - numeric;
    // Declared after `tmp`, so dropped before it: the folders are mutable again in time.
    let mut immutable = Immutable::default();
    output_rows(&f, &mut rows, &mut skipped, &mut immutable);
    let outputs = rows.len() - numeric - files;
    named_rows(&f, &mut rows);
    let named = rows.len() - numeric - files - outputs;

    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<(String, Verdict)>> = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..WORKERS {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(c) = rows.get(i) else { break };
                let o = run(&c.args, &f.dir);
                let verdict = judge(c, &o);
                results.lock().unwrap().push((c.name.clone(), verdict));
            });
        }
        s.spawn(|| {
            let mut special = closed_pipe_rows(&f);
            special.push(interrupt_row(&f));
            results.lock().unwrap().extend(special);
        });
    });
    let results = results.into_inner().unwrap();
    let mut counts: BTreeMap<Failure, usize> = BTreeMap::new();
    let mut failures = Vec::new();
    for (name, v) in &results {
        if let Err((kind, why)) = v {
            *counts.entry(*kind).or_default() += 1;
            failures.push(format!("[{kind:?}] {name}: {why}"));
        }
    }
    let count = |k| counts.get(&k).copied().unwrap_or(0);
    eprintln!(
        "hostile inputs: {} cases ({numeric} numeric-flag, {files} file, {outputs} output-folder, \
         {named} named, 4 pipe/signal) in {:.1} s: {} passed; panics {}, hangs {}, aborts {}, \
         wrong exit code {}, culprit not named {}; {} classes skipped",
        results.len(),
        started.elapsed().as_secs_f64(),
        results.len() - failures.len(),
        count(Failure::Panic),
        count(Failure::Hang),
        count(Failure::Abort),
        count(Failure::WrongCode),
        count(Failure::Unnamed),
        skipped.len()
    );
    for s in &skipped {
        eprintln!("  skipped: {s}");
    }
    assert!(
        failures.is_empty(),
        "{} of {} hostile-input cases failed:\n{}",
        failures.len(),
        results.len(),
        failures.join("\n")
    );
}
