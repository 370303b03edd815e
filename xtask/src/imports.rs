//! The layering check of `cargo xtask test` (docs/architecture.md): no import cycle between the
//! source files of any crate, and no library crate (nor the Python package) depending on the
//! `tooltouch` command-line crate, and no crate of the command line's alone ([`NOT_IN_THE_WHEEL`]:
//! plots, argument parsing, progress bars) in the Python wheel's dependencies.
//!
//! An import is a path through `crate::` or `super::` (in a `use`, a `use` group or an
//! expression) that names an item of another file of the same crate; a file's `#[cfg(test)]`
//! tail is not read (tests may reach anywhere). A cycle is a strongly connected set of two
//! or more files. Paths are read from the text with comments removed: no macro expansion, so
//! a path built by a macro is not seen (none is in this workspace).

use anyhow::{bail, Context, Result};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The source folders checked, relative to the workspace root: every crate's `src/`.
fn source_roots(root: &Path) -> Result<Vec<PathBuf>> {
    let mut roots: Vec<PathBuf> = ["src", "model/src", "hdl-gen/src", "xtask/src", "fuzz/src"]
        .iter()
        .map(|d| root.join(d))
        .chain(std::iter::once(root.join("python/src")))
        .collect();
    let host = root.join("host");
    let mut crates: Vec<PathBuf> = std::fs::read_dir(&host)
        .with_context(|| format!("reading {}", host.display()))?
        .filter_map(|e| e.ok().map(|e| e.path().join("src")))
        .filter(|p| p.is_dir())
        .collect();
    crates.sort();
    roots.extend(crates);
    roots.retain(|p| p.is_dir());
    Ok(roots)
}

/// Runs the check over the workspace at `root`.
pub fn run(root: &Path) -> Result<()> {
    let mut problems = Vec::new();
    for src in source_roots(root)? {
        for cycle in cycles_in(&src)? {
            let shown: Vec<String> = cycle.iter().map(|p| p.display().to_string()).collect();
            problems.push(format!(
                "import cycle in {}: {}",
                src.display(),
                shown.join(" ↔ ")
            ));
        }
    }
    problems.extend(cli_dependents(root)?);
    problems.extend(wheel_compiles(root)?);
    if !problems.is_empty() {
        bail!("{}", problems.join("\n"));
    }
    println!(
        "imports: no cycle; no library depends on the command line; the Python wheel compiles \
         none of {}",
        NOT_IN_THE_WHEEL.join(", ")
    );
    Ok(())
}

/// The manifests (other than the CLI's own) that depend on the `tooltouch` crate.
fn cli_dependents(root: &Path) -> Result<Vec<String>> {
    let mut manifests = vec![root.join("python/Cargo.toml"), root.join("fuzz/Cargo.toml")];
    for dir in std::fs::read_dir(root.join("host"))? {
        manifests.push(dir?.path().join("Cargo.toml"));
    }
    let mut out = Vec::new();
    for m in manifests.iter().filter(|m| m.is_file()) {
        let text =
            std::fs::read_to_string(m).with_context(|| format!("reading {}", m.display()))?;
        let depends = text.lines().any(|l| {
            let key = l.split(['=', '.']).next().unwrap_or("").trim();
            key == "tooltouch"
        });
        if depends {
            out.push(format!(
                "{} depends on the command-line crate `tooltouch`",
                m.display()
            ));
        }
    }
    Ok(out)
}

/// Crates the Python wheel (python/Cargo.toml) must not compile: the command line's plots,
/// argument parsing and progress bars.
pub const NOT_IN_THE_WHEEL: [&str; 3] = ["plotters", "clap", "indicatif"];

/// Each [`NOT_IN_THE_WHEEL`] crate that a workspace crate the wheel compiles names as a
/// normal dependency (`[dependencies]`, `[target.*.dependencies]`; dev- and build-
/// dependencies are not linked), following path dependencies from python/Cargo.toml.
/// Read from the manifests: no build, no registry. Third-party crates are not opened (the
/// workspace's own dependencies are where a plot or a parser would come in).
fn wheel_compiles(root: &Path) -> Result<Vec<String>> {
    let root_manifest = root.join("Cargo.toml");
    let text = std::fs::read_to_string(&root_manifest)
        .with_context(|| format!("reading {}", root_manifest.display()))?;
    let workspace: BTreeMap<String, PathBuf> =
        section_dependencies(&text, "workspace.dependencies")
            .into_iter()
            .filter_map(|(name, path)| Some((name, root.join(path?))))
            .collect();
    let mut seen = BTreeSet::new();
    let mut todo = vec![root.join("python")];
    let mut out = Vec::new();
    while let Some(dir) = todo.pop() {
        if !seen.insert(dir.clone()) {
            continue;
        }
        let manifest = dir.join("Cargo.toml");
        let text = std::fs::read_to_string(&manifest)
            .with_context(|| format!("reading {}", manifest.display()))?;
        for (name, path) in normal_dependencies(&text) {
            if NOT_IN_THE_WHEEL.contains(&name.as_str()) {
                out.push(format!(
                    "the Python wheel compiles `{name}`: {} depends on it",
                    manifest.display()
                ));
            }
            match path {
                Some(p) => todo.push(dir.join(p)),
                None => todo.extend(workspace.get(&name).cloned()),
            }
        }
    }
    Ok(out)
}

/// The normal dependencies of a manifest's text: `(name, path)`.
fn normal_dependencies(text: &str) -> Vec<(String, Option<String>)> {
    let mut out = section_dependencies(text, "dependencies");
    for header in text.lines().filter_map(section_name) {
        if header.starts_with("target.") && header.ends_with(".dependencies") {
            out.extend(section_dependencies(text, header));
        }
        // `[dependencies.name]`: one dependency as a table.
        if let Some(name) = header.strip_prefix("dependencies.") {
            out.push((name.trim().to_string(), table_path(text, header)));
        }
    }
    out
}

/// The name of a `[section]` header line.
fn section_name(line: &str) -> Option<&str> {
    let line = line.split('#').next().unwrap_or("").trim();
    line.strip_prefix('[')?.strip_suffix(']').map(str::trim)
}

/// The `(name, path)` of each key of the manifest section `[name]` (`a = "1"`,
/// `a.workspace = true`, `a = { path = "x" }`).
fn section_dependencies(text: &str, section: &str) -> Vec<(String, Option<String>)> {
    let mut inside = false;
    let mut out = Vec::new();
    for line in text.lines() {
        if let Some(name) = section_name(line) {
            inside = name == section;
            continue;
        }
        let line = line.split('#').next().unwrap_or("").trim();
        if !inside || line.is_empty() {
            continue;
        }
        let key = line.split(['=', '.']).next().unwrap_or("").trim();
        if !key.is_empty() {
            out.push((key.trim_matches('"').to_string(), path_in(line)));
        }
    }
    out
}

/// The `path = "…"` of the table `[header]`.
fn table_path(text: &str, header: &str) -> Option<String> {
    let mut inside = false;
    for line in text.lines() {
        if let Some(name) = section_name(line) {
            inside = name == header;
        } else if inside && line.trim_start().starts_with("path") {
            return path_in(line);
        }
    }
    None
}

/// The string after `path =` in a manifest line.
fn path_in(line: &str) -> Option<String> {
    let at = line.find("path")?;
    let rest = line[at + 4..].trim_start().strip_prefix('=')?.trim_start();
    let rest = rest.strip_prefix('"')?;
    Some(rest[..rest.find('"')?].to_string())
}

/// The module path of a source file relative to its crate's `src/`.
fn module_of(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .with_extension("")
        .iter()
        .map(|c| c.to_string_lossy().into_owned())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("lib" | "main" | "mod")
    ) {
        parts.pop();
    }
    parts
}

/// The text of a file that the check reads: comments removed, the `#[cfg(test)]` tail cut.
fn code_of(text: &str) -> String {
    let code: String = text
        .lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n");
    match code.find("#[cfg(test)]") {
        Some(i) => code[..i].to_string(),
        None => code,
    }
}

/// Every path named after a `crate::` / `super::` prefix, expanded to module paths
/// (`crate::{a::b, c}` gives `[a, b]` and `[c]`), relative to `here`.
fn imported_paths(code: &str, here: &[String]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let bytes = code.as_bytes();
    let mut i = 0;
    while i < code.len() {
        let rest = &code[i..];
        let at_word = i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
        let (base, skip) = if at_word && rest.starts_with("crate::") {
            (Vec::new(), "crate::".len())
        } else if at_word && rest.starts_with("super::") {
            let mut levels = 0;
            let mut n = 0;
            while code[i + n..].starts_with("super::") {
                levels += 1;
                n += "super::".len();
            }
            (here[..here.len().saturating_sub(levels)].to_vec(), n)
        } else {
            i += rest.chars().next().map_or(1, char::len_utf8);
            continue;
        };
        let tail = &code[i + skip..];
        for path in expand(tail) {
            let mut full = base.clone();
            full.extend(path.into_iter().filter(|s| s != "self"));
            out.push(full);
        }
        i += skip;
    }
    out
}

/// The paths at the start of `tail`: one `a::b::C`, or a `{…}` group of them.
fn expand(tail: &str) -> Vec<Vec<String>> {
    if let Some(group) = tail.strip_prefix('{') {
        let mut depth = 1;
        let mut items = Vec::new();
        let mut current = String::new();
        for c in group.chars() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 1 => {
                    items.push(std::mem::take(&mut current));
                    continue;
                }
                _ => {}
            }
            if depth == 0 {
                items.push(current);
                break;
            }
            current.push(c);
        }
        items.iter().flat_map(|item| expand(item.trim())).collect()
    } else {
        let path: String = tail
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
            .collect();
        let prefix: Vec<String> = path
            .split("::")
            .filter(|s| !s.is_empty())
            .map(str::to_string)
            .collect();
        let after = &tail[path.len()..];
        if path.ends_with("::") && after.starts_with('{') {
            expand(after)
                .into_iter()
                .map(|p| prefix.iter().cloned().chain(p).collect())
                .collect()
        } else {
            vec![prefix]
        }
    }
}

/// The import cycles among the files under `src` (each cycle's files, sorted).
fn cycles_in(src: &Path) -> Result<Vec<Vec<PathBuf>>> {
    let mut files: BTreeMap<Vec<String>, PathBuf> = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in
            std::fs::read_dir(&dir).with_context(|| format!("reading {}", dir.display()))?
        {
            let path = entry?.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let rel = path.strip_prefix(src)?.to_path_buf();
                files.insert(module_of(&rel), rel);
            }
        }
    }
    let mut edges: BTreeMap<PathBuf, BTreeSet<PathBuf>> = BTreeMap::new();
    for (module, rel) in &files {
        let text = std::fs::read_to_string(src.join(rel))?;
        let targets = edges.entry(rel.clone()).or_default();
        for path in imported_paths(&code_of(&text), module) {
            let target = (0..=path.len())
                .rev()
                .find_map(|k| files.get(&path[..k]))
                .filter(|t| *t != rel);
            if let Some(t) = target {
                targets.insert(t.clone());
            }
        }
    }
    Ok(strongly_connected(&edges))
}

/// Tarjan's strongly connected components of two or more nodes.
fn strongly_connected(edges: &BTreeMap<PathBuf, BTreeSet<PathBuf>>) -> Vec<Vec<PathBuf>> {
    struct State<'a> {
        edges: &'a BTreeMap<PathBuf, BTreeSet<PathBuf>>,
        index: BTreeMap<&'a PathBuf, usize>,
        low: BTreeMap<&'a PathBuf, usize>,
        stack: Vec<&'a PathBuf>,
        on_stack: BTreeSet<&'a PathBuf>,
        out: Vec<Vec<PathBuf>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a PathBuf) {
        let n = s.index.len();
        s.index.insert(v, n);
        s.low.insert(v, n);
        s.stack.push(v);
        s.on_stack.insert(v);
        for w in s.edges.get(v).into_iter().flatten() {
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).expect("visited");
                *lv = (*lv).min(lw);
            } else if s.on_stack.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).expect("visited");
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                component.push(w.clone());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                component.sort();
                s.out.push(component);
            }
        }
    }
    let mut s = State {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in edges.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn crate_of(files: &[(&str, &str)]) -> tempfile_dir::Dir {
        let dir = tempfile_dir::Dir::new();
        for (name, text) in files {
            let p = dir.path().join(name);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, text).unwrap();
        }
        dir
    }

    /// A throwaway folder under the target directory (xtask has no tempfile dependency).
    mod tempfile_dir {
        pub struct Dir(std::path::PathBuf);
        impl Dir {
            pub fn new() -> Dir {
                use std::sync::atomic::{AtomicU32, Ordering};
                static N: AtomicU32 = AtomicU32::new(0);
                let p = std::env::temp_dir().join(format!(
                    "xtask-imports-{}-{}",
                    std::process::id(),
                    N.fetch_add(1, Ordering::Relaxed)
                ));
                let _ = std::fs::remove_dir_all(&p);
                std::fs::create_dir_all(&p).unwrap();
                Dir(p)
            }
            pub fn path(&self) -> &std::path::Path {
                &self.0
            }
        }
        impl Drop for Dir {
            fn drop(&mut self) {
                let _ = std::fs::remove_dir_all(&self.0);
            }
        }
    }

    #[test]
    fn the_workspace_has_no_import_cycle_and_no_library_on_the_cli() {
        run(&crate::process::root()).unwrap();
    }

    #[test]
    fn a_plotting_dependency_of_the_wheel_is_found_through_path_dependencies() {
        let dir = crate_of(&[
            (
                "Cargo.toml",
                "[workspace.dependencies]\nlib-b = { path = \"b\" }\nclap = \"4\"\n",
            ),
            (
                "python/Cargo.toml",
                "[package]\nname = \"py\"\n[dependencies]\nlib-a = { path = \"../a\" }\n",
            ),
            (
                "a/Cargo.toml",
                "[dependencies]\nlib-b.workspace = true\n[dev-dependencies]\nclap = \"4\"\n",
            ),
            (
                "b/Cargo.toml",
                "[target.'cfg(unix)'.dependencies]\nindicatif = \"0.17\"\n[dependencies.plotters]\nversion = \"0.3\"\n",
            ),
        ]);
        let found = wheel_compiles(dir.path()).unwrap();
        assert_eq!(found.len(), 2, "{found:?}");
        assert!(
            found.iter().all(|f| f.contains("b/Cargo.toml")),
            "{found:?}"
        );
        assert!(found.iter().any(|f| f.contains("`indicatif`")), "{found:?}");
        assert!(found.iter().any(|f| f.contains("`plotters`")), "{found:?}");
    }

    #[test]
    fn a_sibling_cycle_through_a_use_group_is_found() {
        let dir = crate_of(&[
            ("lib.rs", "pub mod a;\npub mod b;\n"),
            ("a.rs", "use crate::{b::B, lib_item};\npub struct A;\n"),
            (
                "b/mod.rs",
                "use super::a::A; // crate::nothing\npub struct B;\n",
            ),
        ]);
        let cycles = cycles_in(dir.path()).unwrap();
        assert_eq!(
            cycles,
            vec![vec![PathBuf::from("a.rs"), PathBuf::from("b/mod.rs")]]
        );
    }

    #[test]
    fn a_one_way_import_and_a_test_tail_are_not_cycles() {
        let dir = crate_of(&[
            ("lib.rs", "pub mod a;\npub mod b;\npub mod c;\n"),
            ("a.rs", "use crate::b::B;\n"),
            (
                "b.rs",
                "pub struct B;\n#[cfg(test)]\nmod tests { use crate::a::*; }\n",
            ),
            ("c.rs", "fn f() { let _ = super::super::b::B; }\n"),
        ]);
        assert!(cycles_in(dir.path()).unwrap().is_empty());
    }

    #[test]
    fn nested_super_paths_resolve_to_the_right_file() {
        let here = vec!["x".to_string(), "y".to_string()];
        let paths = imported_paths("use super::super::z::{W, self};", &here);
        assert_eq!(
            paths,
            vec![vec!["z".to_string(), "W".into()], vec!["z".to_string()]]
        );
    }
}
