//! The Slurm recipes on a real scheduler: a one-node Slurm cluster (munged, slurmctld and
//! slurmd on localhost, from Debian's `munge` and `slurm-wlm`, installed by `cargo xtask
//! setup`) started once by the test in a temporary folder; `examples/scale-out/slurm.sh` (a
//! sharded `tune`) and `examples/scale-out/faults-slurm.sh` (a sharded fault campaign)
//! submitted to it exactly as written, each from its own folder laid out as a checkout; and
//! every file of each merged result compared byte for byte with the unsharded run's (the
//! campaign's table too, from the merge job's `slurm-<job>.out`). Without the daemons the
//! test fails naming `cargo xtask setup`.
//!
//! The cluster is private to the test: its own munge key and socket, free TCP ports, state
//! and spool folders under the temporary folder, no accounting, no cgroups
//! (`proctrack/linuxproc`, `task/none`). The node declares 16 CPUs whatever the machine has
//! (`SlurmdParameters=config_overrides`), so the recipe's `--cpus-per-task=4` is scheduled
//! on a two-core machine too; the tasks then share the real cores.

use crate::common;

use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// How long the recipes' jobs may take on a loaded two-core machine (they take seconds).
const JOBS_TIMEOUT: Duration = Duration::from_secs(600);

/// The daemons and commands the test needs, as installed by `cargo xtask setup`.
const PROGRAMS: [&str; 7] = [
    "munged",
    "slurmctld",
    "slurmd",
    "sbatch",
    "squeue",
    "scontrol",
    "sinfo",
];

/// Where a program is: on PATH or in the sbin folders a non-root PATH may lack.
fn program(name: &str) -> PathBuf {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .chain(["/usr/sbin", "/sbin", "/usr/local/sbin"].map(PathBuf::from))
        .map(|dir| dir.join(name))
        .find(|p| p.is_file())
        .unwrap_or_else(|| {
            panic!(
                "`{name}` is not installed: run `cargo xtask setup` (Debian's munge and slurm-wlm)"
            )
        })
}

/// A TCP port nothing listens on now.
fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free TCP port on localhost")
}

fn user_name() -> String {
    let o = Command::new("id")
        .arg("-un")
        .output()
        .expect("`id -un` runs");
    String::from_utf8_lossy(&o.stdout).trim().to_string()
}

/// A job as `scontrol show job` reports it.
#[derive(Debug)]
struct Job {
    name: String,
    /// `JobState`: `COMPLETED`, `FAILED`, ...
    state: String,
    /// `ExitCode`: the script's exit code and the signal that ended it, `1:0`.
    exit_code: String,
}

/// A one-node Slurm cluster on localhost, stopped (its daemons killed) when dropped.
struct LocalCluster {
    dir: tempfile::TempDir,
}

impl LocalCluster {
    fn start() -> LocalCluster {
        let programs: Vec<PathBuf> = PROGRAMS.iter().map(|p| program(p)).collect();
        let dir = tempfile::Builder::new()
            .prefix("tt-slurm")
            .tempdir()
            .unwrap();
        let cluster = LocalCluster { dir };
        let d = cluster.dir.path();
        for sub in ["state", "spool", "log", "run"] {
            std::fs::create_dir_all(d.join(sub)).unwrap();
        }
        // A private munge key: 1 KiB of random bytes, readable by its owner only.
        let key_path = d.join("munge.key");
        let mut random = vec![0u8; 1024];
        use std::io::Read;
        std::fs::File::open("/dev/urandom")
            .and_then(|mut f| f.read_exact(&mut random))
            .expect("reading /dev/urandom for the munge key");
        std::fs::write(&key_path, &random).unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&key_path, std::fs::Permissions::from_mode(0o600)).unwrap();
        std::fs::set_permissions(d, std::fs::Permissions::from_mode(0o700)).unwrap();
        let socket = d.join("run/munge.socket");
        cluster.daemon(
            &programs[0],
            &[
                "--force".into(),
                format!("--socket={}", socket.display()),
                format!("--key-file={}", key_path.display()),
                format!("--pid-file={}", d.join("run/munged.pid").display()),
                format!("--log-file={}", d.join("log/munged.log").display()),
                format!("--seed-file={}", d.join("run/munge.seed").display()),
            ],
        );
        let user = user_name();
        let conf = format!(
            "ClusterName=tooltouch\n\
             SlurmctldHost=localhost\n\
             SlurmUser={user}\n\
             SlurmdUser={user}\n\
             AuthType=auth/munge\n\
             AuthInfo=socket={socket}\n\
             CredType=cred/munge\n\
             SlurmctldPort={ctld_port}\n\
             SlurmdPort={slurmd_port}\n\
             StateSaveLocation={d}/state\n\
             SlurmdSpoolDir={d}/spool\n\
             SlurmctldPidFile={d}/run/slurmctld.pid\n\
             SlurmdPidFile={d}/run/slurmd.pid\n\
             SlurmctldLogFile={d}/log/slurmctld.log\n\
             SlurmdLogFile={d}/log/slurmd.log\n\
             ProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\n\
             JobAcctGatherType=jobacct_gather/none\n\
             AccountingStorageType=accounting_storage/none\n\
             SelectType=select/cons_tres\n\
             SelectTypeParameters=CR_CPU\n\
             SlurmdParameters=config_overrides\n\
             ReturnToService=2\n\
             MpiDefault=none\n\
             NodeName=localhost CPUs=16 State=UNKNOWN\n\
             PartitionName=local Nodes=localhost Default=YES MaxTime=INFINITE State=UP\n",
            socket = socket.display(),
            ctld_port = free_port(),
            slurmd_port = free_port(),
            d = d.display(),
        );
        std::fs::write(cluster.conf(), conf).unwrap();
        let conf_arg = cluster.conf().display().to_string();
        cluster.daemon(&programs[1], &["-f".into(), conf_arg.clone()]);
        cluster.daemon(
            &programs[2],
            &["-f".into(), conf_arg, "-N".into(), "localhost".into()],
        );
        cluster.wait_until_idle_node();
        cluster
    }

    fn conf(&self) -> PathBuf {
        self.dir.path().join("slurm.conf")
    }

    /// Starts a daemon (it forks into the background and writes its pid file).
    fn daemon(&self, program: &Path, args: &[String]) {
        let o = Command::new(program)
            .args(args)
            .env("SLURM_CONF", self.conf())
            .output()
            .unwrap_or_else(|e| panic!("starting {}: {e}", program.display()));
        assert!(
            o.status.success(),
            "{} {args:?} failed: {}\n{}",
            program.display(),
            common::text(&o),
            self.logs()
        );
    }

    /// A Slurm client command against this cluster.
    fn client(&self, name: &str) -> Command {
        let mut c = Command::new(program(name));
        c.env("SLURM_CONF", self.conf());
        c
    }

    fn output(&self, name: &str, args: &[&str]) -> Output {
        self.client(name)
            .args(args)
            .output()
            .unwrap_or_else(|e| panic!("running {name}: {e}"))
    }

    /// Every daemon's log, for a failure message.
    fn logs(&self) -> String {
        let mut text = String::new();
        for name in ["munged", "slurmctld", "slurmd"] {
            let log = std::fs::read_to_string(self.dir.path().join(format!("log/{name}.log")))
                .unwrap_or_default();
            let tail: Vec<&str> = log.lines().rev().take(15).collect();
            text += &format!("--- {name}.log (last lines)\n");
            for l in tail.into_iter().rev() {
                text += l;
                text += "\n";
            }
        }
        text
    }

    fn wait_until_idle_node(&self) {
        let start = Instant::now();
        loop {
            let o = self.output("sinfo", &["-h", "-o", "%t"]);
            if o.status.success() && String::from_utf8_lossy(&o.stdout).trim() == "idle" {
                return;
            }
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "the Slurm node did not come up idle within 60 s: {}\n{}",
                common::text(&o),
                self.logs()
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    /// Waits until no job is pending or running; fails at once when a job's dependency can
    /// no longer be met.
    fn wait_until_queue_empty(&self) {
        let start = Instant::now();
        loop {
            let o = self.output("squeue", &["-h", "-o", "%i %T %r"]);
            assert!(o.status.success(), "squeue: {}", common::text(&o));
            let queue = String::from_utf8_lossy(&o.stdout).trim().to_string();
            if queue.is_empty() {
                return;
            }
            // A merge whose array task failed waits for ever: say so now.
            assert!(
                !queue.contains("DependencyNeverSatisfied"),
                "a job waits on a task that failed:\n{queue}\n{:?}",
                self.jobs()
            );
            assert!(
                start.elapsed() < JOBS_TIMEOUT,
                "jobs still queued after {JOBS_TIMEOUT:?}:\n{queue}\n{}",
                self.logs()
            );
            std::thread::sleep(Duration::from_millis(250));
        }
    }

    /// Every job the controller still knows (kept 300 s after it ends).
    fn jobs(&self) -> Vec<Job> {
        let o = self.output("scontrol", &["-o", "show", "job"]);
        assert!(o.status.success(), "scontrol: {}", common::text(&o));
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .map(|line| {
                let field = |key: &str| {
                    line.split_whitespace()
                        .find_map(|w| w.strip_prefix(key))
                        .unwrap_or("")
                        .to_string()
                };
                Job {
                    name: field("JobName="),
                    state: field("JobState="),
                    exit_code: field("ExitCode="),
                }
            })
            .collect()
    }
}

impl Drop for LocalCluster {
    fn drop(&mut self) {
        for name in ["slurmd", "slurmctld", "munged"] {
            if let Ok(pid) =
                std::fs::read_to_string(self.dir.path().join(format!("run/{name}.pid")))
            {
                let _ = Command::new("kill").arg(pid.trim()).status();
            }
        }
        // The daemons hold files in the folder: give them a moment to exit before it goes.
        std::thread::sleep(Duration::from_millis(300));
    }
}

/// `PATH` with `tooltouch` first, as the recipes ask (sbatch passes the environment on).
fn path_with_tooltouch() -> std::ffi::OsString {
    let bin = Path::new(env!("CARGO_BIN_EXE_tooltouch"));
    std::env::join_paths(std::iter::once(bin.parent().unwrap().to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))
    .unwrap()
}

/// `recipe` submitted to `cluster` exactly as written (`bash RECIPE`), from a fresh folder
/// laid out as the checkout it expects (`files`, the recipe among them, copied from the
/// repository); returns the folder and what the recipe printed.
fn submit(cluster: &LocalCluster, recipe: &str, files: &[&str]) -> (tempfile::TempDir, String) {
    let work = tempfile::tempdir().unwrap();
    let dir = work.path();
    for f in files.iter().chain([&recipe]) {
        let to = dir.join(f);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(Path::new(ROOT).join(f), to).unwrap();
    }
    let o = Command::new("bash")
        .arg(recipe)
        .current_dir(dir)
        .env("SLURM_CONF", cluster.conf())
        .env("PATH", path_with_tooltouch())
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "submitting {recipe}: {}\n{}",
        common::text(&o),
        cluster.logs()
    );
    (work, String::from_utf8_lossy(&o.stdout).into_owned())
}

/// The arguments of `recipe`'s slice command (the line that runs `command … --shard`) up
/// to `--shard`: the unsharded run of the same spec or campaign, `command`'s words first.
fn unsharded_args(recipe: &str, command: &str) -> Vec<String> {
    let text = std::fs::read_to_string(Path::new(ROOT).join(recipe)).unwrap();
    let line = text
        .lines()
        .find(|l| !l.trim_start().starts_with('#') && l.contains(command) && l.contains("--shard"))
        .unwrap_or_else(|| panic!("{recipe}: no `{command} … --shard` line"));
    let start = line.find(command).unwrap() + "tooltouch ".len();
    let end = line.find(" --shard").unwrap();
    line[start..end]
        .split_whitespace()
        .map(String::from)
        .collect()
}

/// `tooltouch ARGS` in `dir`; returns its exit code and its standard output.
fn tooltouch_in(dir: &Path, args: &[String]) -> (i32, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_tooltouch"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    let code = o.status.code().unwrap_or(-1);
    assert!(
        code == 0 || code == 1,
        "tooltouch {args:?}: exit {code}: {}",
        common::text(&o)
    );
    (code, String::from_utf8_lossy(&o.stdout).into_owned())
}

/// Checks the jobs of one recipe: `tasks` array tasks named `shards`, each `COMPLETED`, and
/// one merge job named `merge` that exited with `merge_exit` (`COMPLETED` for 0).
fn check_jobs(jobs: &[Job], shards: &str, tasks: usize, merge: &str, merge_exit: i32) {
    let array: Vec<&Job> = jobs.iter().filter(|j| j.name == shards).collect();
    let merges: Vec<&Job> = jobs.iter().filter(|j| j.name == merge).collect();
    assert_eq!(array.len(), tasks, "array tasks named {shards}: {jobs:?}");
    assert!(
        array.iter().all(|j| j.state == "COMPLETED"),
        "every task of {shards} completes: {jobs:?}"
    );
    assert_eq!(merges.len(), 1, "merge jobs named {merge}: {jobs:?}");
    let state = if merge_exit == 0 {
        "COMPLETED"
    } else {
        "FAILED"
    };
    assert!(
        merges[0].state == state && merges[0].exit_code == format!("{merge_exit}:0"),
        "the merge job {merge} ends {state} with exit code {merge_exit}, as the unsharded run: {:?}",
        merges[0]
    );
}

/// Where `a` and `b` first differ: the byte, its line (numbered from 1) in each.
fn first_difference(a: &[u8], b: &[u8]) -> String {
    let at = a.iter().zip(b).position(|(x, y)| x != y);
    let Some(at) = at else {
        return format!(
            "{} bytes against {} bytes, equal up to the shorter's end",
            a.len(),
            b.len()
        );
    };
    let line_of = |bytes: &[u8]| {
        let start = bytes[..at]
            .iter()
            .rposition(|&c| c == b'\n')
            .map_or(0, |i| i + 1);
        let end = bytes[at..]
            .iter()
            .position(|&c| c == b'\n')
            .map_or(bytes.len(), |i| at + i);
        let line: String = String::from_utf8_lossy(&bytes[start..end])
            .chars()
            .take(200)
            .collect();
        line
    };
    let line = a[..at].iter().filter(|&&c| c == b'\n').count() + 1;
    format!(
        "first difference at byte {at}, line {line}:\n  Slurm:     {}\n  unsharded: {}",
        line_of(a),
        line_of(b)
    )
}

/// The files of a folder, by name (hidden files left out: none of a result's).
fn files_of(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    names.sort();
    names
}

/// Every file of the Slurm run's merged `merged` and the unsharded `whole` is the same, byte
/// for byte; `expected` are files each must hold. A mismatch names the file and where.
fn assert_same_files(recipe: &str, merged: &Path, whole: &Path, expected: &[&str]) {
    let names = files_of(whole);
    for e in expected {
        assert!(
            names.iter().any(|n| n == e),
            "{recipe}: the unsharded run wrote no {e}: {names:?}"
        );
    }
    assert_eq!(
        files_of(merged),
        names,
        "{recipe}: the Slurm run's merged files are not the unsharded run's"
    );
    for name in &names {
        let a = std::fs::read(merged.join(name)).unwrap();
        let b = std::fs::read(whole.join(name)).unwrap();
        assert!(
            a == b,
            "{recipe}: the Slurm run's merged {name} differs from the unsharded run's: {}",
            first_difference(&a, &b)
        );
    }
}

/// The campaign's table in `output`: its header line (`kind …`) to its summary line
/// (`silent-wrong …`).
fn campaign_table(output: &str) -> String {
    let lines: Vec<&str> = output.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.starts_with("kind "))
        .unwrap_or_else(|| panic!("no campaign table in:\n{output}"));
    let end = start
        + lines[start..]
            .iter()
            .position(|l| l.starts_with("silent-wrong "))
            .unwrap_or_else(|| panic!("no campaign summary line in:\n{output}"));
    lines[start..=end].join("\n") + "\n"
}

/// The job id of the last `Submitted batch job ID` line of what a recipe printed (its
/// merge job, submitted last and without `--parsable`).
fn last_job_id(printed: &str) -> String {
    printed
        .lines()
        .filter_map(|l| l.strip_prefix("Submitted batch job "))
        .next_back()
        .unwrap_or_else(|| panic!("no `Submitted batch job` line in {printed:?}"))
        .trim()
        .to_string()
}

#[test]
fn the_slurm_recipes_run_on_a_one_node_cluster_and_merge_to_the_unsharded_runs() {
    let cluster = LocalCluster::start();
    // Both recipes submitted at once: the scheduler runs the one array after the other
    // (each task asks 4 of the node's 16 CPUs) while the unsharded runs go on here.
    let tune = "examples/scale-out/slurm.sh";
    let (tune_work, _) = submit(&cluster, tune, &["examples/sweep.toml"]);
    let faults = "examples/scale-out/faults-slurm.sh";
    let (faults_work, printed) = submit(&cluster, faults, &["examples/measure.toml"]);

    // The unsharded runs, of the spec and the campaign of the recipes' slices.
    let (tune_dir, faults_dir) = (tune_work.path(), faults_work.path());
    let mut args = unsharded_args(tune, "tooltouch tune");
    args.extend(["--out".into(), "unsharded".into()]);
    let (code, _) = tooltouch_in(tune_dir, &args);
    assert_eq!(code, 0, "the unsharded sweep");
    let mut args = unsharded_args(faults, "tooltouch faults");
    args.extend(["--out".into(), "unsharded".into()]);
    let (faults_exit, faults_stdout) = tooltouch_in(faults_dir, &args);

    cluster.wait_until_queue_empty();
    let jobs = cluster.jobs();
    check_jobs(&jobs, "tooltouch-tune", 4, "tooltouch-tune-merge", 0);
    check_jobs(
        &jobs,
        "tooltouch-faults",
        4,
        "tooltouch-faults-merge",
        faults_exit,
    );
    assert_same_files(
        tune,
        &tune_dir.join("out/tune"),
        &tune_dir.join("unsharded"),
        &["results.json", "results.csv", "force.csv", "pareto.svg"],
    );
    assert_same_files(
        faults,
        &faults_dir.join("out/faults"),
        &faults_dir.join("unsharded"),
        &["faults.json", "faults-chips.svg", "faults-fes-lost.svg"],
    );
    let merge_log = faults_dir.join(format!("slurm-{}.out", last_job_id(&printed)));
    let merge_output = std::fs::read_to_string(&merge_log)
        .unwrap_or_else(|e| panic!("{}: {e}", merge_log.display()));
    let (a, b) = (
        campaign_table(&merge_output),
        campaign_table(&faults_stdout),
    );
    assert!(
        a == b,
        "{faults}: the merge job's table ({}) differs from the unsharded run's: {}",
        merge_log.display(),
        first_difference(a.as_bytes(), b.as_bytes())
    );
}
