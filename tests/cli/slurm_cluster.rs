//! The Slurm recipe on a real scheduler: a one-node Slurm cluster (munged, slurmctld and
//! slurmd on localhost, from Debian's `munge` and `slurm-wlm`, installed by `cargo xtask
//! setup`) started by the test in a temporary folder, `examples/scale-out/slurm.sh` submitted
//! to it exactly as written, and the merged sweep compared byte for byte with the unsharded
//! run. Without the daemons the test fails naming `cargo xtask setup`.
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

/// How long the recipe's jobs may take on a loaded two-core machine (they take seconds).
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

    /// Waits until no job is pending or running.
    fn wait_until_queue_empty(&self) {
        let start = Instant::now();
        loop {
            let o = self.output("squeue", &["-h", "-o", "%i %T %r"]);
            assert!(o.status.success(), "squeue: {}", common::text(&o));
            let queue = String::from_utf8_lossy(&o.stdout).trim().to_string();
            if queue.is_empty() {
                return;
            }
            assert!(
                start.elapsed() < JOBS_TIMEOUT,
                "jobs still queued after {JOBS_TIMEOUT:?}:\n{queue}\n{}",
                self.logs()
            );
            std::thread::sleep(Duration::from_millis(250));
        }
    }

    /// `JobState` of every job the controller still knows (kept 300 s after it ends), by
    /// job name.
    fn job_states(&self) -> Vec<(String, String)> {
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
                (field("JobName="), field("JobState="))
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

#[test]
fn the_slurm_recipe_runs_on_a_one_node_cluster_and_merges_to_the_unsharded_sweep() {
    let cluster = LocalCluster::start();
    let work = tempfile::tempdir().unwrap();
    let dir = work.path();
    // The checkout layout the recipe expects: its spec under examples/.
    std::fs::create_dir_all(dir.join("examples/scale-out")).unwrap();
    for f in ["examples/sweep.toml", "examples/scale-out/slurm.sh"] {
        std::fs::copy(Path::new(ROOT).join(f), dir.join(f)).unwrap();
    }
    // `tooltouch` on the PATH, as the recipe asks (sbatch passes the environment on).
    let bin = Path::new(env!("CARGO_BIN_EXE_tooltouch"));
    let path = std::env::join_paths(std::iter::once(bin.parent().unwrap().to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))
    .unwrap();
    let submit = Command::new("bash")
        .arg("examples/scale-out/slurm.sh")
        .current_dir(dir)
        .env("SLURM_CONF", cluster.conf())
        .env("PATH", &path)
        .output()
        .unwrap();
    assert!(
        submit.status.success(),
        "submitting the recipe: {}\n{}",
        common::text(&submit),
        cluster.logs()
    );
    cluster.wait_until_queue_empty();
    let states = cluster.job_states();
    let shards: Vec<&(String, String)> = states
        .iter()
        .filter(|(n, _)| n == "tooltouch-tune")
        .collect();
    let merges: Vec<&(String, String)> = states
        .iter()
        .filter(|(n, _)| n == "tooltouch-tune-merge")
        .collect();
    assert_eq!(shards.len(), 4, "array tasks of the recipe: {states:?}");
    assert_eq!(merges.len(), 1, "merge jobs of the recipe: {states:?}");
    assert!(
        states.iter().all(|(_, s)| s == "COMPLETED"),
        "every job completes: {states:?}\n{}",
        cluster.logs()
    );
    let whole = dir.join("unsharded");
    let o = Command::new(bin)
        .args(["tune", "--spec", "examples/sweep.toml", "--out"])
        .arg(&whole)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "unsharded tune: {}", common::text(&o));
    let merged = dir.join("out/tune");
    for name in ["results.json", "results.csv", "force.csv", "pareto.svg"] {
        let (a, b) = (merged.join(name), whole.join(name));
        assert!(
            std::fs::read(&a).ok() == std::fs::read(&b).ok(),
            "the Slurm run's merged {name} differs from the unsharded run's"
        );
    }
}
