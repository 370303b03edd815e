//! The hostile-input table: the built `tooltouch` binary run as a careless or hostile user
//! would, one row per case, each under a memory limit (`prlimit --as`) and a time limit.
//! A row passes when the exit code is the documented one (docs/cli.md: 0 success, 1 a
//! verdict that is not a pass, 2 bad input, 130 interrupted), the message names the culprit
//! (the flag, the key or the file as the user gave it), nothing panicked (101),
//! aborted (134, e.g. an allocation failure under the limit), or ran past the time limit,
//! and, where the row says so, a failed run left its output as it was.
//!
//! Every subcommand is walked (read from the clap definition: a new subcommand or flag is
//! covered without touching this file). The rows are
//! - every argument that takes a number or a value list (flags and positionals such as
//!   `tune point`'s INDEX), with the classes zero, negative, huge, u32 max, NaN, inf,
//!   -inf, not a number and empty;
//! - every input file argument (the `PathBuf` arguments that are not outputs) with the
//!   classes missing, empty, directory, corrupt, truncated, unreadable;
//! - every output folder (`--out`) with an existing file, a path under a file, a read-only
//!   folder and an existing folder holding other files;
//! - every output file (an argument whose clap `value_hint` is `FilePath`: `tune point
//!   --out`, `cosim config --out`, `cosim firmware --trace`) in a folder that does not
//!   exist, under a file, that is a folder, in a read-only folder, and an existing file.
//!   Every row of a subcommand that writes a file (these, and its numeric and input-file
//!   rows) has a folder of its own, holding an earlier file at the output path where the
//!   class allows, and a run that fails must leave that folder byte for byte as it was
//!   (no partial or temporary file, no folder made, the earlier file intact);
//! - the cases found by hand: sweep ranges that overflow, merge counts that lie, a run too
//!   large to hold, oversized and binary settings files, messages that blamed the wrong
//!   field, `cosim firmware` settings that are not the stream's, a closed pipe, Ctrl-C.
//!
//! `cosim firmware` builds and boots a QEMU image, which this table never does: its rows
//! give `--image` a text file ([`Fixtures::image_guard`]), so a run that accepts every
//! input stops at "not an ELF image", which counts as success. The image is read (or,
//! without `--image`, built) only after the stimulus, the settings and the trace's path
//! are checked, so every row of bad input must fail before that guard, which shows that a
//! user's typo costs no firmware build. Not covered here, because they need a boot: a
//! corrupt or truncated ELF (it keeps its magic number and is booted), a firmware that
//! crashes or differs, an image built with another configuration, and a trace that cannot
//! be written after all (a disk that fills during the run); tests/firmware/ boots images.
//! `bench collect` gets the same text file as its `--elf`: its accepted runs stop there,
//! before probe-rs starts (its collection runs against a fake probe-rs in tests/cli/bench.rs).
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
    /// A folder that must hold the same files with the same bytes after a run that did not
    /// exit 0 as before it: a failed run leaves no partial output and destroys no earlier
    /// file.
    unchanged: Option<PathBuf>,
    /// A message that means the run got past every input and stopped at a guard the row
    /// set up on purpose (`cosim firmware`'s non-ELF `--image`, so that no row boots
    /// QEMU): such a run counts as exit 0.
    accepted: Option<String>,
}

fn case(name: impl Into<String>, args: &[&str], expect: Expect, culprit: &[&str]) -> Case {
    Case {
        name: name.into(),
        args: args.iter().map(|a| a.to_string()).collect(),
        expect,
        culprit: culprit.iter().map(|a| a.to_string()).collect(),
        absent: Vec::new(),
        once: Vec::new(),
        unchanged: None,
        accepted: None,
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

/// Every file and folder under `dir` (paths relative to it) with its bytes (`None` for a
/// folder).
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Option<Vec<u8>>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Option<Vec<u8>>>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.filter_map(Result::ok) {
            let p = e.path();
            let rel = p.strip_prefix(root).unwrap().to_path_buf();
            if p.is_dir() {
                out.insert(rel, None);
                walk(root, &p, out);
            } else {
                out.insert(rel, std::fs::read(&p).ok());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// Whether `dir` is as [`snapshot`] saw it before a failed run.
fn left_as_it_was(dir: &Path, before: &BTreeMap<PathBuf, Option<Vec<u8>>>) -> Verdict {
    let after = snapshot(dir);
    let changed: Vec<String> = before
        .keys()
        .chain(after.keys())
        .filter(|k| before.get(*k) != after.get(*k))
        .map(|k| k.display().to_string())
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    if changed.is_empty() {
        Ok(())
    } else {
        Err((
            Failure::HalfWritten,
            format!(
                "a failed run changed {changed:?} in {}: {:?}",
                dir.display(),
                after.keys().collect::<Vec<_>>()
            ),
        ))
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
    /// A failed run left a partial output or changed an earlier file.
    HalfWritten,
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
    let code = match &c.accepted {
        Some(guard) if code == 2 && text.contains(guard.as_str()) => 0,
        _ => code,
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
    /// A sweep's folder (`tune point` reads it).
    tuned: PathBuf,
    /// An optimizer spec (`tune optimize --spec`).
    optimize_spec: PathBuf,
    results: PathBuf,
    /// A fault campaign's one slice (`faults merge` reads it).
    faults_slice: PathBuf,
    /// A controller log holding exactly the golden decision lines of `events`
    /// (`bench check --log`), written by `bench expect`.
    bench_log: PathBuf,
    /// `cosim firmware --image` of every row that does not test `--image` itself: a text
    /// file, so a run that gets past its inputs stops with "not an ELF image" instead of
    /// booting QEMU (or building the firmware, which it does without `--image`).
    image_guard: PathBuf,
}

impl Fixtures {
    /// What `cosim firmware` says when it reaches [`Fixtures::image_guard`]: every input
    /// was accepted.
    fn image_guard_reached(&self) -> String {
        format!("{}: not an ELF image", self.image_guard.display())
    }
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
    let optimize_spec = dir.join("optimize.toml");
    std::fs::write(
        &optimize_spec,
        "path = \"measure\"\n[space]\nscenarios = 1\nmethod = [\"counter\"]\n\
         contact_rule = [\"sticky\"]\nlaw = [\"linear\"]\ncharge_bits = [6]\nscale_bits = [16]\n\
         glitch_cycles = [0]\n[constraints]\n\
         diameter_error_um = 100.0\n",
    )
    .unwrap();
    let bench_log = dir.join("controller.log");
    must(
        &[
            "bench",
            "expect",
            "--stream",
            m.join("events.ttv").to_str().unwrap(),
            "--config",
            settings.to_str().unwrap(),
            "--out",
            bench_log.to_str().unwrap(),
        ],
        dir,
    );
    let faults_slice = dir.join("faults-slice");
    must(
        &[
            "faults",
            "--config",
            settings.to_str().unwrap(),
            "--kinds",
            "fes-lost",
            "--levels",
            "0.5",
            "--methods",
            "counter",
            "--measurements",
            "2",
            "--shard",
            "0/1",
            "--out",
            faults_slice.to_str().unwrap(),
        ],
        dir,
    );
    Fixtures {
        optimize_spec,
        bench_log,
        faults_slice,
        dir: dir.to_path_buf(),
        settings,
        events: m.join("events.ttv"),
        expected: m.join("expected_outputs.ttv"),
        vcd: m.join("measure.vcd"),
        spec,
        results: t.join("results.json"),
        tuned: t,
        image_guard: {
            let g = dir.join("not-an-image.elf");
            std::fs::write(&g, "the hostile-input test's guard: never boot QEMU\n").unwrap();
            g
        },
    }
}

/// Whether this process runs as root (permission bits then stop nothing).
fn running_as_root() -> bool {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata("/proc/self").is_ok_and(|m| m.uid() == 0)
}

/// The arguments that make each subcommand's run short, as `(flag, value)` (a positional
/// as `(<id>, value)`, in its place); the argument under test replaces its entry. `out` is
/// the row's own output: a folder, or the file of a subcommand that writes one
/// ([`writes_a_file`]).
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
        "budget" => vec![("--out", o.clone()), ("--sweep-values", v("1"))],
        "calibrate" => vec![
            ("--config", p(&f.settings)),
            ("--reference-mm", v("40")),
            ("--repeats", v("2")),
            ("--out", o),
        ],
        "check" => vec![("--expected", p(&f.expected)), ("--dut", p(&f.expected))],
        "vectors" => vec![("--stimulus", p(&f.events)), ("--out", o)],
        "coverage" => vec![("--stimulus", p(&f.events))],
        "control" | "wear" | "hdl" => vec![("--out", o)],
        "tune" => vec![("--spec", p(&f.spec)), ("--out", o)],
        "faults" => vec![
            ("--config", p(&f.settings)),
            ("--kinds", v("fes-lost")),
            ("--levels", v("0.5")),
            ("--methods", v("counter")),
            ("--measurements", v("2")),
            ("--out", o),
        ],
        "faults merge" => vec![("<dirs>", p(&f.faults_slice)), ("--out", o)],
        "tune merge" => vec![("<dirs>", p(&f.results)), ("--out", o)],
        "tune optimize" => vec![("--spec", p(&f.optimize_spec)), ("--out", o)],
        "ranges" => vec![("--scenarios", v("1")), ("--out", o)],
        "tune point" => vec![
            ("<results>", p(&f.tuned)),
            ("<index>", v("0")),
            ("--out", o),
        ],
        "cosim config" => vec![("--config", p(&f.settings)), ("--out", o)],
        "formal" => vec![("--dut", p(&f.settings)), ("--out", o)],
        "bench expect" => vec![
            ("--stream", p(&f.events)),
            ("--config", p(&f.settings)),
            ("--out", o),
        ],
        "bench check" => vec![
            ("--stream", p(&f.events)),
            ("--config", p(&f.settings)),
            ("--log", p(&f.bench_log)),
        ],
        // Every accepted run stops at the non-ELF guard: probe-rs is never started.
        "bench collect" => vec![
            ("--stream", p(&f.events)),
            ("--config", p(&f.settings)),
            ("--elf", p(&f.image_guard)),
            ("--out", o),
        ],
        "cosim firmware" => vec![
            ("--stimulus", p(&f.events)),
            ("--image", p(&f.image_guard)),
            ("--trace", o),
        ],
        _ => vec![],
    };
    list.into_iter().map(|(k, v)| (k.to_string(), v)).collect()
}

/// The command line `sub` + `base` with the argument `flag` (`--long`, or `<id>` for a
/// positional) given `values`: in the place of its base entry if it has one, else last.
/// An empty `flag` is the base alone.
fn with_base(
    sub: &str,
    base: &[(String, Option<String>)],
    flag: &str,
    values: &[&str],
) -> Vec<String> {
    let positional = |k: &str| k.starts_with('<');
    let given = |args: &mut Vec<String>| {
        if !positional(flag) {
            args.push(flag.to_string());
        }
        args.extend(values.iter().map(|v| v.to_string()));
    };
    let mut args: Vec<String> = sub.split(' ').map(String::from).collect();
    let mut placed = flag.is_empty();
    for (k, v) in base {
        if k == flag {
            given(&mut args);
            placed = true;
            continue;
        }
        if !positional(k) {
            args.push(k.clone());
        }
        args.extend(v.clone());
    }
    if !placed {
        given(&mut args);
    }
    args
}

/// How the argument `a` is spelled in [`base_args`] and in clap's messages: `--long`, or
/// `<id>` for a positional.
fn spelled(a: &clap::Arg) -> String {
    match a.get_long() {
        Some(long) => format!("--{long}"),
        None => format!("<{}>", a.get_id()),
    }
}

/// A file the command writes (one file, not an output folder): marked in the clap
/// definition with `value_hint = ValueHint::FilePath` (input paths keep clap's `AnyPath`).
fn is_output_file(a: &clap::Arg) -> bool {
    is_path(a) && a.get_value_hint() == clap::ValueHint::FilePath
}

/// An output folder: `--out`, unless it is an output file.
fn is_output_folder(a: &clap::Arg) -> bool {
    a.get_long() == Some("out") && !is_output_file(a)
}

/// Whether `cmd` writes one file ([`is_output_file`]), which [`base_args`] then gets as
/// `out`.
fn writes_a_file(cmd: &clap::Command) -> bool {
    cmd.get_arguments().any(is_output_file)
}

/// The output of one row: for a subcommand that writes a file, `dir/out` in a fresh folder
/// `dir`, holding an earlier run's file at that path, and `dir` as the folder a failed run
/// must leave [`Case::unchanged`]; for the others, the output folder `dir`.
fn row_output(cmd: &clap::Command, dir: PathBuf) -> (PathBuf, Option<PathBuf>) {
    if writes_a_file(cmd) {
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("out");
        std::fs::write(&out, "an earlier run's file\n").unwrap();
        (out, Some(dir))
    } else {
        (dir, None)
    }
}

/// The guard message of `sub`'s rows ([`Case::accepted`]).
fn guard_of(sub: &str, f: &Fixtures) -> Option<String> {
    match sub {
        "cosim firmware" | "bench collect" => Some(f.image_guard_reached()),
        // Every input accepted: the run reached the design (the settings file, not Verilog).
        "formal" => Some(format!("reading --dut {} with --top", f.settings.display())),
        _ => None,
    }
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
        && (a.get_long().is_some() || a.is_positional())
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
            let id = a.get_id().as_str();
            let flag = spelled(a);
            // The names of the argument in its messages: the flag or the TOML key; for a
            // positional, clap's `<INDEX>` or the value itself as a range check quotes it
            // (`point 4294967295: ...`).
            let names = |value: &str| match a.get_long() {
                Some(long) => vec![flag.clone(), long.replace('-', "_")],
                None => vec![format!("<{}>", id.to_uppercase()), format!("{value}:")],
            };
            for (class, value) in NUMERIC {
                let dir = f
                    .dir
                    .join(format!("o-{}-{id}-{class}", sub.replace(' ', "-")));
                let (out, unchanged) = row_output(&cmd, dir);
                let base = base_args(&sub, f, &out);
                let args = with_base(&sub, &base, &flag, &[value]);
                let args: Vec<&str> = args.iter().map(String::as_str).collect();
                let names = names(value);
                let names: Vec<&str> = names.iter().map(String::as_str).collect();
                let mut c = case(
                    format!("{sub} {flag} {class} ({value:?})"),
                    &args,
                    Expect::AnyOf(&[0, 1, 2]),
                    &names,
                );
                c.unchanged = unchanged;
                c.accepted = guard_of(&sub, f);
                rows.push(c);
            }
        }
    }
}

/// A valid file of the kind an argument reads, for its truncated and corrupt rows.
fn valid_file_for<'a>(sub: &str, long: &str, f: &'a Fixtures) -> &'a Path {
    match (sub, long) {
        (_, "config") => &f.settings,
        ("tune optimize", "spec") => &f.optimize_spec,
        (_, "spec") => &f.spec,
        ("vectors" | "cosim firmware" | "coverage", "stimulus") | ("hdl", "vectors") => &f.events,
        ("bench expect" | "bench check" | "bench collect", "stream") => &f.events,
        ("bench check", "log") => &f.bench_log,
        ("check", _) => &f.expected,
        ("tune merge" | "tune point", _) => &f.results,
        _ => &f.settings,
    }
}

fn file_rows(f: &Fixtures, rows: &mut Vec<Case>, skipped: &mut Vec<String>) {
    let root = running_as_root();
    let files = f.dir.join("files");
    std::fs::create_dir_all(&files).unwrap();
    for (sub, cmd) in subcommands() {
        for a in cmd.get_arguments() {
            let takes_file = (is_path(a) && !is_output_folder(a) && !is_output_file(a))
                || (sub == "hdl" && a.get_long() == Some("vectors"));
            if !takes_file {
                continue;
            }
            let long = a.get_long().unwrap_or("");
            let flag = spelled(a);
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
            if (sub == "cosim firmware" && long == "image")
                || (sub == "bench collect" && long == "elf")
            {
                // A corrupt or truncated ELF keeps its magic number and would be booted:
                // QEMU is not run here, so the image's rows are the ones refused before a
                // boot (tests/firmware/ boots real images).
                let text = files.join(format!("{tag}-not-elf"));
                std::fs::write(&text, &bytes).unwrap();
                classes.push(("not an ELF file", text));
            } else {
                let c = files.join(format!("{tag}-corrupt"));
                std::fs::write(&c, &corrupt).unwrap();
                classes.push(("corrupt", c));
                let t = files.join(format!("{tag}-truncated"));
                std::fs::write(&t, &bytes[..bytes.len() / 2]).unwrap();
                classes.push(("truncated", t));
            }
            if root {
                skipped.push(format!(
                    "{sub} {flag} unreadable: running as root, permission bits do not stop reads"
                ));
            } else {
                let u = files.join(format!("{tag}-unreadable"));
                std::fs::write(&u, &bytes).unwrap();
                use std::os::unix::fs::PermissionsExt;
                std::fs::set_permissions(&u, std::fs::Permissions::from_mode(0o000)).unwrap();
                classes.push(("unreadable", u));
            }
            for (class, path) in classes {
                let (out, unchanged) = row_output(&cmd, f.dir.join(format!("o-{tag}-{class}")));
                let base = base_args(&sub, f, &out);
                let ps = path.to_str().unwrap();
                let args = with_base(&sub, &base, &flag, &[ps]);
                let args: Vec<&str> = args.iter().map(String::as_str).collect();
                // A truncated device-under-test trace is a mismatch (1), the rest bad
                // input (2); every message names the file.
                let expect = if sub == "check" && class == "truncated" {
                    Expect::AnyOf(&[1, 2])
                } else if sub == "bench check"
                    && long == "log"
                    && matches!(class, "truncated" | "corrupt")
                {
                    // Half a log, or a mutated one that is still text, is a controller
                    // that logged other lines (1); bytes that are not text are bad input.
                    Expect::AnyOf(&[1, 2])
                } else if matches!(class, "truncated" | "corrupt")
                    && (long == "config" || long == "spec")
                {
                    // Half a TOML file can still be valid TOML, and so can a mutated one.
                    Expect::AnyOf(&[0, 2])
                } else {
                    Expect::AnyOf(&[2])
                };
                let mut c = case(format!("{sub} {flag} {class}"), &args, expect, &[ps]);
                c.unchanged = unchanged;
                c.accepted = guard_of(&sub, f);
                rows.push(c);
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
        if !cmd.get_arguments().any(is_output_folder) {
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
            let mut c = case(format!("{sub} --out {class}"), &args, expect, &named);
            c.accepted = guard_of(&sub, f);
            rows.push(c);
        }
    }
}

/// Every file a command writes ([`is_output_file`]: `tune point --out`, `cosim config
/// --out`, `cosim firmware --trace`) with a path in a folder that does not exist, under a
/// file, that is a folder, in a read-only folder, and an existing file (replaced by a run
/// that succeeds). Each row has a folder of its own that a failed run must leave as it was
/// ([`Case::unchanged`]): no partial file, no temporary file, no folder made, the earlier
/// file intact (a run that succeeds replaces it). `cosim firmware` stops at [`Fixtures::image_guard`], so its rows show that
/// the trace's path is checked before the image is read or built.
fn output_file_rows(
    f: &Fixtures,
    rows: &mut Vec<Case>,
    skipped: &mut Vec<String>,
    immutable: &mut Immutable,
) {
    let root = running_as_root();
    let outs = f.dir.join("out-files");
    for (sub, cmd) in subcommands() {
        for a in cmd.get_arguments().filter(|a| is_output_file(a)) {
            let flag = spelled(a);
            let tag = format!("{}-{}", sub.replace(' ', "-"), a.get_id());
            let folder = |class: &str| {
                let d = outs.join(format!("{tag}-{class}"));
                std::fs::create_dir_all(&d).unwrap();
                d
            };
            let mut classes: Vec<(&str, PathBuf, PathBuf, Expect)> = Vec::new();
            let d = folder("missing-folder");
            classes.push((
                "in a folder that does not exist",
                d.join("no-such-folder").join("out"),
                d,
                Expect::Code(2),
            ));
            let d = folder("under-a-file");
            std::fs::write(d.join("a-file"), "mine").unwrap();
            classes.push((
                "under a file",
                d.join("a-file").join("out"),
                d,
                Expect::Code(2),
            ));
            let d = folder("a-folder");
            std::fs::create_dir_all(d.join("a-folder")).unwrap();
            std::fs::write(d.join("a-folder").join("notes.txt"), "mine").unwrap();
            classes.push(("a folder", d.join("a-folder"), d, Expect::Code(2)));
            let d = folder("existing");
            std::fs::write(d.join("out"), "an earlier run's file\n").unwrap();
            classes.push(("an existing file", d.join("out"), d, Expect::AnyOf(&[0])));
            let d = folder("read-only");
            std::fs::write(d.join("out"), "an earlier run's file\n").unwrap();
            if !root {
                use std::os::unix::fs::PermissionsExt;
                std::fs::set_permissions(&d, std::fs::Permissions::from_mode(0o555)).unwrap();
                classes.push(("in a read-only folder", d.join("out"), d, Expect::Code(2)));
            } else if immutable.add(&d) {
                classes.push((
                    "in a read-only (immutable) folder",
                    d.join("out"),
                    d,
                    Expect::Code(2),
                ));
            } else {
                skipped.push(format!(
                    "{sub} {flag} in a read-only folder: running as root (permission bits do \
                     not stop writes) on a file system without `chattr +i`"
                ));
            }
            for (class, path, dir, expect) in classes {
                let base = base_args(&sub, f, &path);
                let ps = path.to_str().unwrap();
                // The flag under test gets the path (in place of its base entry if it has
                // one: `check --json`, `--window`, `coverage --json` have none).
                let args = with_base(&sub, &base, &flag, &[ps]);
                let args: Vec<&str> = args.iter().map(String::as_str).collect();
                let ps = path.to_str().unwrap();
                let mut c = case(format!("{sub} {flag} {class}"), &args, expect, &[ps]);
                c.unchanged = Some(dir);
                c.accepted = guard_of(&sub, f);
                rows.push(c);
            }
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
    // `SUB --config|--spec SETTINGS` and the rest of a short run; `o` is its output.
    let with_settings = |sub: &str, settings: &str, o: &str| -> Vec<String> {
        let mut a: Vec<&str> = sub.split(' ').collect();
        a.extend([if sub == "tune" { "--spec" } else { "--config" }, settings]);
        let events = f.events.to_str().unwrap();
        match sub {
            "vectors" => a.extend(["--stimulus", events, "--out", o]),
            "cosim firmware" => a.extend([
                "--stimulus",
                events,
                "--image",
                f.image_guard.to_str().unwrap(),
                "--trace",
                o,
            ]),
            _ => a.extend(["--out", o]),
        }
        a.into_iter().map(String::from).collect()
    };
    // A row of bad input (exit 2) naming `culprit`.
    let settings_case = |name: String, args: &[String], culprit: &[&str]| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let mut c = case(name, &args, Expect::Code(2), culprit);
        c.accepted = guard_of(args[..2].join(" ").as_str(), f);
        c
    };
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

    // A run too large to hold (1.6 GB in the events' encoding before).
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
    for sub in [
        "measure",
        "vectors",
        "hdl",
        "cosim config",
        "cosim firmware",
    ] {
        let o = out(&format!("n-big-{}", sub.replace(' ', "-")));
        r(settings_case(
            format!("{sub} 39 MB settings file"),
            &with_settings(sub, &p, &o),
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
    for sub in [
        "measure",
        "vectors",
        "hdl",
        "tune",
        "cosim config",
        "cosim firmware",
    ] {
        let o = out(&format!("n-bin-{}", sub.replace(' ', "-")));
        let mut c = settings_case(
            format!("{sub} binary settings file"),
            &with_settings(sub, &bin, &o),
            &[&bin],
        );
        c.once = vec!["UTF-8".into()];
        r(c);
        let missing = d.join("no-such.toml");
        let ms = missing.to_str().unwrap();
        let mut c = settings_case(
            format!("{sub} missing settings file"),
            &with_settings(sub, ms, &o),
            &[ms],
        );
        c.once = vec!["No such file".into()];
        r(c);
        // Unknown tables are errors everywhere.
        let bogus = w(
            &format!("bogus-{}.toml", sub.replace(' ', "-")),
            if sub == "tune" {
                b"scenarios = 1\n[bogus]\nx = 1\n"
            } else {
                b"[measure]\ni_def = 512\n[bogus]\nx = 1\n"
            },
        );
        r(settings_case(
            format!("{sub} unknown table [bogus]"),
            &with_settings(sub, &bogus, &o),
            &["bogus"],
        ));
    }
    // `cosim firmware`'s conflicting inputs, refused before the image is read or built: a
    // settings file whose configuration is not the stream's (`--clock-hz` against the
    // stream's tick rate is a numeric row).
    let other = w("other-measure.toml", b"[measure]\nglitch_cycles = 3\n");
    let o = out("n-conflict.trace");
    r(settings_case(
        "cosim firmware --config not the stream's configuration".into(),
        &with_settings("cosim firmware", &other, &o),
        &[f.events.to_str().unwrap()],
    ));
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
    output_file_rows(&f, &mut rows, &mut skipped, &mut immutable);
    let output_files = rows.len() - numeric - files - outputs;
    named_rows(&f, &mut rows);
    let named = rows.len() - numeric - files - outputs - output_files;

    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<(String, Verdict)>> = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..WORKERS {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(c) = rows.get(i) else { break };
                let before = c.unchanged.as_deref().map(snapshot);
                let o = run(&c.args, &f.dir);
                let verdict = judge(c, &o).and_then(|()| match (&c.unchanged, before) {
                    (Some(dir), Some(before)) if !matches!(o, Outcome::Exited(0, _)) => {
                        left_as_it_was(dir, &before)
                    }
                    _ => Ok(()),
                });
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
         {output_files} output-file, {named} named, 4 pipe/signal) in {:.1} s: {} passed; \
         panics {}, hangs {}, aborts {}, wrong exit code {}, culprit not named {}, \
         half-written {}; {} classes skipped",
        results.len(),
        started.elapsed().as_secs_f64(),
        results.len() - failures.len(),
        count(Failure::Panic),
        count(Failure::Hang),
        count(Failure::Abort),
        count(Failure::WrongCode),
        count(Failure::Unnamed),
        count(Failure::HalfWritten),
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
