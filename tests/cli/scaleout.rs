//! The scale-out recipes of `examples/scale-out/` (a Slurm job array, a Kubernetes Indexed
//! Job, a GitHub Actions matrix): the test takes the `tooltouch tune --shard K/N` command
//! each recipe runs and its `tooltouch tune merge` command, runs them here for every K (the
//! scheduler's index variable replaced by K, in a folder laid out as the recipe expects),
//! and checks that the recipe starts N tasks and that the merge is byte-identical to the
//! unsharded sweep of the same spec.

use crate::common;

use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The scheduler variables that hold a task's index, as the recipes write them.
const INDEX_VARIABLES: [&str; 3] = [
    "${SLURM_ARRAY_TASK_ID}",
    "${JOB_COMPLETION_INDEX}",
    "${{ matrix.shard }}",
];

/// The command that starts with `tooltouch tune` on the first line of `recipe` that
/// holds `marker`, up to the line's end (quotes and YAML list dashes dropped).
fn command_line(recipe: &str, marker: &str) -> String {
    let line = recipe
        .lines()
        .find(|l| l.contains(marker) && !l.trim_start().starts_with('#'))
        .unwrap_or_else(|| panic!("no line with `{marker}`"));
    let start = line.find("tooltouch tune").unwrap();
    line[start..]
        .trim_end()
        .trim_end_matches(['\'', '"', ')'])
        .to_string()
}

/// The arguments of `command` (after `tooltouch`), a trailing `*` of a path expanded to
/// the matching folders under `dir`, sorted.
fn arguments(command: &str, dir: &Path) -> Vec<String> {
    let mut args = Vec::new();
    for word in command.split_whitespace().skip(1) {
        let word = word.trim_matches(['\'', '"']);
        match word.strip_suffix('*') {
            Some(prefix) => {
                let (parent, stem) = prefix.rsplit_once('/').unwrap_or((".", prefix));
                let mut found: Vec<String> = std::fs::read_dir(dir.join(parent))
                    .unwrap()
                    .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                    .filter(|n| n.starts_with(stem))
                    .map(|n| format!("{parent}/{n}"))
                    .collect();
                found.sort();
                assert!(!found.is_empty(), "`{word}` matches nothing");
                args.extend(found);
            }
            None => args.push(word.to_string()),
        }
    }
    args
}

fn run_in(dir: &Path, args: &[String]) {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_tooltouch"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "tooltouch {args:?}: {}",
        common::text(&o)
    );
}

/// The value after `flag` in `args`.
fn value_of<'a>(args: &'a [String], flag: &str) -> &'a str {
    let i = args.iter().position(|a| a == flag).unwrap();
    &args[i + 1]
}

/// Runs `recipe`'s shards and merge in a fresh folder; returns `tasks(recipe, N)`'s
/// check of the task count the recipe declares.
fn check_recipe(file: &str, declares_tasks: impl Fn(&str, u32) -> bool) {
    let recipe = std::fs::read_to_string(Path::new(ROOT).join(file)).unwrap();
    let work = tempfile::tempdir().unwrap();
    let dir = work.path();
    let shard_command = command_line(&recipe, "--shard");
    let variable = INDEX_VARIABLES
        .iter()
        .find(|v| shard_command.contains(*v))
        .unwrap_or_else(|| panic!("{file}: no index variable in `{shard_command}`"));
    let template = arguments(&shard_command.replace(variable, "@INDEX@"), dir);
    let (_, n) = value_of(&template, "--shard").split_once('/').unwrap();
    let n: u32 = n.parse().unwrap();
    assert!(n >= 2, "{file}: {n} shards");
    assert!(
        declares_tasks(&recipe, n),
        "{file}: does not start {n} tasks"
    );
    // The spec where the recipe reads it.
    let spec: PathBuf = dir.join(value_of(&template, "--spec"));
    std::fs::create_dir_all(spec.parent().unwrap()).unwrap();
    std::fs::copy(Path::new(ROOT).join("examples/sweep.toml"), &spec).unwrap();
    for k in 0..n {
        let args: Vec<String> = template
            .iter()
            .map(|a| a.replace("@INDEX@", &k.to_string()))
            .collect();
        let out = dir.join(value_of(&args, "--out"));
        std::fs::create_dir_all(out.parent().unwrap()).unwrap();
        run_in(dir, &args);
    }
    let merge = arguments(&command_line(&recipe, "tooltouch tune merge"), dir);
    assert_eq!(
        merge.iter().filter(|a| a.contains("shard-")).count(),
        n as usize
    );
    run_in(dir, &merge);
    let merged = dir.join(value_of(&merge, "--out"));
    let whole = dir.join("unsharded");
    run_in(
        dir,
        &[
            "tune".into(),
            "--spec".into(),
            spec.display().to_string(),
            "--out".into(),
            whole.display().to_string(),
        ],
    );
    for name in ["results.json", "results.csv", "force.csv", "pareto.svg"] {
        let (a, b) = (merged.join(name), whole.join(name));
        assert!(
            std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(),
            "{file}: merged {name} differs from the unsharded run's"
        );
    }
}

#[test]
fn the_slurm_job_array_merges_to_the_unsharded_sweep() {
    check_recipe("examples/scale-out/slurm.sh", |r, n| {
        r.contains(&format!("--array=0-{}", n - 1))
    });
}

#[test]
fn the_kubernetes_indexed_job_merges_to_the_unsharded_sweep() {
    check_recipe("examples/scale-out/kubernetes.yaml", |r, n| {
        r.contains("completionMode: Indexed") && r.contains(&format!("completions: {n}"))
    });
}

#[test]
fn the_github_actions_matrix_merges_to_the_unsharded_sweep() {
    check_recipe("examples/scale-out/github-actions.yml", |r, n| {
        let list: Vec<String> = (0..n).map(|k| k.to_string()).collect();
        r.contains(&format!("shard: [{}]", list.join(", ")))
    });
}
