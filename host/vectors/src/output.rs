//! Output folders that cannot mislead: what a command leaves in its `--out` folder is one
//! whole run's files, never a mix of two runs and never a file cut short.
//!
//! A run writes every file into a hidden staging folder inside the output folder
//! (`.tooltouch-partial-<pid>-<n>`, same file system, so the final step is a rename) under
//! its final name. [`OutputFolder::commit`] then renames each file over its final name and
//! removes the command's other known outputs that this run did not write (e.g. the
//! `measure.vcd` of an earlier run when this one ran with `--vcd none`); files the command
//! does not know are left alone. A run that fails, or is dropped before its commit,
//! removes its staging folder: the output folder is as it was.
//!
//! The choice (replace every known output rather than refuse a folder holding another
//! run's files) keeps a repeated command working in place, as `make`-style loops expect,
//! while `summary.json` and the other files always describe the same run.
//!
//! A run stopped by a signal (Ctrl-C, `kill`, a closed terminal) does not unwind, so
//! `Drop` would not run: every open staging folder is also kept in a process-wide list,
//! and [`remove_open_staging`] removes them (the command line calls it from its signal
//! handler, then exits with 130). A commit holds that list's lock while it renames, so a signal never lands between
//! two renames of one commit.
//!
//! A command that writes one file instead of a folder (`tune point`, `cosim config`,
//! `cosim firmware --trace`) goes through [`write_file`]: the same promise for one file. It
//! writes a hidden temporary file beside the final one and renames it into place, so the
//! path holds the old file or the whole new one, never a cut one; a failed write removes
//! the temporary file, and so does the signal handler.

use anyhow::Context;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Staging folders not yet committed or dropped, and [`write_file`]'s temporary files not
/// yet renamed: removed by the signal handler.
static OPEN_STAGING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Exit code after a signal stopped the run (128 + SIGINT, as shells report Ctrl-C).
pub const INTERRUPTED: i32 = 130;

fn open_staging() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    OPEN_STAGING.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes every staging folder still open and every temporary file of [`write_file`] not
/// yet renamed, so the output folders are as they were: what a signal handler calls before
/// the process exits with [`INTERRUPTED`] (the command line installs it).
pub fn remove_open_staging() {
    let open = open_staging();
    for dir in open.iter() {
        // A writer thread may still create a file in the folder: retry a few times.
        for _ in 0..5 {
            let removed = if dir.is_dir() {
                std::fs::remove_dir_all(dir).is_ok()
            } else {
                std::fs::remove_file(dir).is_ok()
            };
            if removed || !dir.exists() {
                break;
            }
        }
    }
}

/// The hidden temporary name beside `path` that [`write_file`] writes before its rename
/// (same folder, so same file system: the rename is atomic).
fn partial_file(path: &Path) -> PathBuf {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!(".{name}.tooltouch-partial-{}", std::process::id()))
}

/// Checks that the file `path` can be written, before a long run makes its contents: it
/// is not a folder, its folder exists, and a file can be created there (a temporary one,
/// removed at once). Errors name `path`.
pub fn check_output_file(path: &Path) -> anyhow::Result<()> {
    if path.is_dir() {
        anyhow::bail!(
            "output file {}: is a folder, not a file (give a file path)",
            path.display()
        );
    }
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        anyhow::bail!(
            "output file {}: its folder {} {}",
            path.display(),
            folder.display(),
            if folder.exists() {
                "is a file, not a folder"
            } else {
                "does not exist (create it first)"
            }
        );
    }
    let probe = partial_file(path);
    std::fs::File::create(&probe).with_context(|| {
        format!(
            "output file {}: cannot write in its folder {}",
            path.display(),
            folder.display()
        )
    })?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// Writes the file `path` whole or not at all (module documentation): an existing file is
/// replaced only once the new one is complete, and a failed write leaves nothing behind.
pub fn write_file(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    check_output_file(path)?;
    let partial = partial_file(path);
    open_staging().push(partial.clone());
    let written = std::fs::write(&partial, bytes).and_then(|()| std::fs::rename(&partial, path));
    let mut open = open_staging();
    if written.is_err() {
        let _ = std::fs::remove_file(&partial);
    }
    open.retain(|p| *p != partial);
    drop(open);
    written.with_context(|| format!("writing {}", path.display()))
}

/// The output folder of one run. See the module documentation.
#[derive(Debug)]
pub struct OutputFolder {
    dir: PathBuf,
    staging: PathBuf,
    known: Vec<String>,
    committed: bool,
}

impl OutputFolder {
    /// Creates `dir` (and its parents) and a fresh staging folder in it. `known` are the
    /// file names this command can write there (any run, any option).
    pub fn create<S: Into<String>>(
        dir: &Path,
        known: impl IntoIterator<Item = S>,
    ) -> anyhow::Result<OutputFolder> {
        static NEXT: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        if dir.exists() && !dir.is_dir() {
            anyhow::bail!(
                "output folder {}: is a file, not a folder (give a folder path)",
                dir.display()
            );
        }
        std::fs::create_dir_all(dir)
            .with_context(|| format!("creating the output folder {}", dir.display()))?;
        let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let staging = dir.join(format!(".tooltouch-partial-{}-{n}", std::process::id()));
        // A folder left by a killed process of the same id is ours to reuse.
        if staging.exists() {
            std::fs::remove_dir_all(&staging)
                .with_context(|| format!("removing {}", staging.display()))?;
        }
        let mut open = open_staging();
        std::fs::create_dir(&staging).with_context(|| {
            format!(
                "output folder {}: cannot write in it (creating {})",
                dir.display(),
                staging.display()
            )
        })?;
        open.push(staging.clone());
        drop(open);
        Ok(OutputFolder {
            dir: dir.to_path_buf(),
            staging,
            known: known.into_iter().map(Into::into).collect(),
            committed: false,
        })
    }

    /// The output folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The staging folder: a writer that takes a folder writes here; every file in it is
    /// moved to the output folder by [`OutputFolder::commit`].
    pub fn staging(&self) -> &Path {
        &self.staging
    }

    /// Where to write the file `name` now (in the staging folder).
    pub fn path(&self, name: &str) -> PathBuf {
        self.staging.join(name)
    }

    /// Where the file `name` will be once committed (for messages).
    pub fn final_path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Writes the file `name` with `bytes`.
    pub fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> anyhow::Result<()> {
        let path = self.path(name);
        std::fs::write(&path, bytes)
            .with_context(|| format!("writing {}", self.final_path(name).display()))
    }

    /// Creates the file `name` for writing, buffered.
    pub fn create_file(&self, name: &str) -> anyhow::Result<std::io::BufWriter<std::fs::File>> {
        let path = self.path(name);
        let f = std::fs::File::create(&path)
            .with_context(|| format!("creating {}", self.final_path(name).display()))?;
        Ok(std::io::BufWriter::with_capacity(1 << 20, f))
    }

    /// Moves every staged file to the output folder (`summary.json` last, so a reader
    /// that waits for it sees the rest first), removes the known outputs this run did
    /// not write, and removes the staging folder. Returns the final paths, sorted.
    pub fn commit(mut self) -> anyhow::Result<Vec<PathBuf>> {
        let mut open = open_staging();
        let mut names: Vec<String> = std::fs::read_dir(&self.staging)
            .with_context(|| format!("reading {}", self.staging.display()))?
            .map(|e| e.map(|e| e.file_name().to_string_lossy().into_owned()))
            .collect::<Result<_, _>>()
            .with_context(|| format!("reading {}", self.staging.display()))?;
        names.sort_by_key(|n| (n == "summary.json", n.clone()));
        for stale in self.known.iter().filter(|k| !names.contains(k)) {
            let path = self.dir.join(stale);
            match std::fs::remove_file(&path) {
                Ok(()) => {}
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                Err(e) => {
                    return Err(e).with_context(|| format!("removing the stale {}", path.display()))
                }
            }
        }
        let mut paths = Vec::with_capacity(names.len());
        for name in &names {
            let to = self.dir.join(name);
            std::fs::rename(self.staging.join(name), &to)
                .with_context(|| format!("moving {} into place", to.display()))?;
            paths.push(to);
        }
        std::fs::remove_dir(&self.staging)
            .with_context(|| format!("removing {}", self.staging.display()))?;
        self.committed = true;
        open.retain(|d| *d != self.staging);
        paths.sort();
        Ok(paths)
    }
}

impl Drop for OutputFolder {
    fn drop(&mut self) {
        if !self.committed {
            let mut open = open_staging();
            let _ = std::fs::remove_dir_all(&self.staging);
            open.retain(|d| *d != self.staging);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_commit_replaces_known_files_and_removes_stale_ones() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for f in ["a.txt", "b.txt", "mine.txt"] {
            std::fs::write(d.join(f), "old").unwrap();
        }
        let out = OutputFolder::create(d, ["a.txt", "b.txt", "summary.json"]).unwrap();
        out.write("a.txt", "new").unwrap();
        out.write("summary.json", "{}").unwrap();
        assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "old");
        let written = out.commit().unwrap();
        assert_eq!(written, vec![d.join("a.txt"), d.join("summary.json")]);
        assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "new");
        assert!(!d.join("b.txt").exists(), "stale known output removed");
        assert_eq!(std::fs::read_to_string(d.join("mine.txt")).unwrap(), "old");
        let left: Vec<_> = std::fs::read_dir(d).unwrap().collect();
        assert_eq!(left.len(), 3, "no staging folder left");
    }

    #[test]
    fn a_run_dropped_before_its_commit_changes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("a.txt"), "old").unwrap();
        {
            let out = OutputFolder::create(d, ["a.txt"]).unwrap();
            out.write("a.txt", "half").unwrap();
        }
        assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "old");
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 1);
    }

    #[test]
    fn a_file_is_written_whole_and_a_failed_write_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let file = d.join("settings.toml");
        std::fs::write(&file, "old").unwrap();
        write_file(&file, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "new");
        let folder = d.join("a-folder");
        std::fs::create_dir(&folder).unwrap();
        let e = write_file(&folder, b"x").unwrap_err().to_string();
        assert!(e.contains("is a folder"), "{e}");
        let e = write_file(&d.join("missing/x.toml"), b"x").unwrap_err();
        assert!(e.to_string().contains("does not exist"), "{e}");
        let e = write_file(&file.join("x.toml"), b"x").unwrap_err();
        assert!(e.to_string().contains("is a file"), "{e}");
        let mut left: Vec<_> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        left.sort();
        assert_eq!(
            left,
            ["a-folder", "settings.toml"],
            "no temporary file left"
        );
    }
}
