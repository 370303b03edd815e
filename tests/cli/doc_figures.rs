//! The figures that README.md and docs/*.md quote from a tool's output, checked against
//! that output, so prose cannot drift from the tool.
//!
//! A figure is the text between `<!-- figure: NAME -->` and `<!-- /figure -->`. Two kinds:
//!
//! - **A command figure** holds a fenced block of `$ command` lines, each followed by the
//!   lines of its output that the page shows; a fenced block whose info string names a
//!   file (```` ```toml fast.toml ````) is written to that file first. Every command runs under `bash -euo pipefail`
//!   in one fresh folder per figure, with the built `tooltouch` first on `PATH` and a leading
//!   `cargo run --release --` read as `tooltouch`; `cargo xtask firmware` is not built but
//!   answered with the size gate's figures (`firmware/ci/expected/*.size`) in `llvm-size`'s
//!   layout. A line `...` stands for output lines the page leaves out: the shown lines
//!   before the first `...` are the output's first lines, those after the last `...` its
//!   last lines, and a run between two `...` is found by its shape (digits aside). A shown
//!   line equals its output line word for word, except a wall-clock time (`in 0.31 s`, `N
//!   events/s`, `(N measurements/s)`, `(2 threads)`), which the page may round differently.
//! - **`firmware-gates`** is the markdown table of the size and stack gates' figures
//!   (`firmware/ci/expected/`), rendered whole.
//!
//! `TOOLTOUCH_BLESS_FIGURES=1 cargo test --release --test cli doc_figures` rewrites every
//! figure from the outputs instead of failing; review the result with `git diff`.

use crate::common;

use std::path::{Path, PathBuf};

const OPEN: &str = "<!-- figure: ";
const CLOSE: &str = "<!-- /figure -->";
const ELISION: &str = "...";

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// README.md and every page under docs/, as (path relative to the root, text).
fn pages() -> Vec<(PathBuf, String)> {
    let mut paths = vec![PathBuf::from("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .map(|p| p.strip_prefix(root()).unwrap().to_path_buf())
        .collect();
    docs.sort();
    paths.extend(docs);
    paths
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(root().join(&p))
                .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            (p, text)
        })
        .collect()
}

/// One figure of a page: its name and the byte range of its body (between the markers).
struct Figure {
    name: String,
    body: std::ops::Range<usize>,
}

fn figures(page: &Path, text: &str) -> Vec<Figure> {
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(at) = text[from..].find(OPEN) {
        let start = from + at;
        let name_end = start
            + text[start..]
                .find("-->")
                .unwrap_or_else(|| panic!("{}: an unclosed figure marker", page.display()));
        let name = text[start + OPEN.len()..name_end].trim().to_string();
        let body_start = name_end + "-->".len();
        let body_end = body_start
            + text[body_start..]
                .find(CLOSE)
                .unwrap_or_else(|| panic!("{}: figure `{name}` has no `{CLOSE}`", page.display()));
        out.push(Figure {
            name,
            body: body_start..body_end,
        });
        from = body_end + CLOSE.len();
    }
    out
}

/// `text data bss` of a size gate file (its one line that is not a comment).
fn size_gate(image: &str) -> [u64; 3] {
    let path = root().join(format!("firmware/ci/expected/{image}.size"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let line = text
        .lines()
        .find(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .unwrap_or_else(|| panic!("{}: no figures", path.display()));
    let v: Vec<u64> = line
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    [v[0], v[1], v[2]]
}

/// The stack gate's figure, bytes.
fn stack_gate(name: &str) -> u64 {
    let path = root().join(format!("firmware/ci/expected/{name}.stack"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .find(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .unwrap_or_else(|| panic!("{}: no figure", path.display()))
        .trim()
        .parse()
        .unwrap()
}

const IMAGES: [(&str, &str); 2] = [
    ("qemu", "firmware/target/thumbv7m-none-eabi/release/qemu"),
    (
        "nucleo",
        "firmware/target/thumbv7em-none-eabihf/release/nucleo",
    ),
];

/// What `cargo xtask firmware` prints for the sizes, from the size gate's figures.
fn firmware_sizes() -> String {
    let mut out = format!(
        "{:>7} {:>7} {:>7} {:>7} {:>7} filename\n",
        "text", "data", "bss", "dec", "hex"
    );
    for (image, file) in IMAGES {
        let [t, d, b] = size_gate(image);
        let dec = t + d + b;
        out += &format!("{t:>7} {d:>7} {b:>7} {dec:>7} {dec:>6x} {file}\n");
    }
    out
}

/// 71048 as `71 048`.
fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// The `firmware-gates` figure: sizes and stack high-water marks.
fn firmware_gates() -> String {
    let [qt, qd, qb] = size_gate("qemu");
    let [nt, nd, nb] = size_gate("nucleo");
    format!(
        "\n\n| image | .text | .data | .bss | stack high-water mark |\n\
         | --- | --- | --- | --- | --- |\n\
         | qemu (lm3s6965) | {} | {} | {} | {} |\n\
         | nucleo (flashable) | {} | {} | {} | — (measured on its emulated build) |\n\
         | nucleo, emulated | | | | {} |\n\n",
        grouped(qt),
        grouped(qd),
        grouped(qb),
        grouped(stack_gate("qemu")),
        grouped(nt),
        grouped(nd),
        grouped(nb),
        grouped(stack_gate("nucleo-emulated")),
    )
}

/// The command of a `$` line without its trailing `# comment`.
fn command_of(line: &str) -> &str {
    let cmd = line.strip_prefix("$ ").unwrap();
    match cmd.find("  #").or_else(|| cmd.find(" # ")) {
        Some(at) => cmd[..at].trim(),
        None => cmd.trim(),
    }
}

/// The output of one `$` line, run in `dir`.
fn run(command: &str, dir: &Path) -> String {
    if command == "cargo xtask firmware" {
        return firmware_sizes();
    }
    let script = match command.strip_prefix("cargo run --release -- ") {
        Some(args) => format!("tooltouch {args}"),
        None => command.to_string(),
    };
    let (status, text) = common::bash_with_tooltouch(&script, dir);
    assert!(
        status.success(),
        "figure command `{command}` failed ({status}):\n{text}"
    );
    text
}

/// A word that is a wall-clock figure: the number in `in N s`, `N events/s`, `(N threads)`.
fn volatile(words: &[&str], i: usize) -> bool {
    let next = words.get(i + 1).copied().unwrap_or("");
    let prev = if i > 0 { words[i - 1] } else { "" };
    let number = words[i].trim_start_matches('(').parse::<f64>().is_ok();
    number
        && ((prev == "in" && next.trim_end_matches([';', ',']) == "s")
            || next == "events/s"
            || next == "measurements/s)"
            || next == "threads)")
}

/// Shown and actual lines agree word for word, wall-clock figures aside.
fn same_line(shown: &str, actual: &str) -> bool {
    let a: Vec<&str> = shown.split_whitespace().collect();
    let b: Vec<&str> = actual.split_whitespace().collect();
    a.len() == b.len() && (0..a.len()).all(|i| a[i] == b[i] || (volatile(&a, i) && volatile(&b, i)))
}

/// The shape of a line: its words with every digit run replaced by `#`.
fn shape(line: &str) -> String {
    let mut out = String::new();
    let mut in_digits = false;
    for c in line
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .chars()
    {
        if c.is_ascii_digit() {
            if !in_digits {
                out.push('#');
            }
            in_digits = true;
        } else {
            in_digits = false;
            out.push(c);
        }
    }
    out
}

/// The output line index of every shown line (`None` for `...`), or why they cannot be placed.
fn place(shown: &[&str], actual: &[&str]) -> Result<Vec<Option<usize>>, String> {
    let segments: Vec<&[&str]> = shown.split(|l| l.trim() == ELISION).collect();
    let mut placed = Vec::new();
    let mut next = 0usize;
    for (k, seg) in segments.iter().enumerate() {
        if k > 0 {
            placed.push(None);
        }
        if seg.is_empty() {
            continue;
        }
        let start = if k == 0 {
            0
        } else if k == segments.len() - 1 {
            actual
                .len()
                .checked_sub(seg.len())
                .filter(|&s| s >= next)
                .ok_or("the output is shorter than the lines shown")?
        } else {
            (next..actual.len())
                .find(|&i| shape(actual[i]) == shape(seg[0]))
                .ok_or_else(|| format!("no output line is shaped like `{}`", seg[0]))?
        };
        if start + seg.len() > actual.len() {
            return Err("the output is shorter than the lines shown".into());
        }
        placed.extend((start..start + seg.len()).map(Some));
        next = start + seg.len();
    }
    if segments.len() == 1 && next != actual.len() {
        return Err(format!(
            "the output has {} lines, the page shows {} (mark left-out lines with `...`)",
            actual.len(),
            next
        ));
    }
    Ok(placed)
}

/// Checks (or, blessing, rewrites) a command figure; returns the new body. Its fenced blocks
/// run in order in one folder: a block whose info string names a file (```` ```toml fast.toml
/// ````) is written to that file, any other holds `$` lines and their shown output.
fn command_figure(
    page: &Path,
    name: &str,
    body: &str,
    bless: bool,
    errors: &mut Vec<String>,
) -> String {
    let dir = tempfile::tempdir().unwrap();
    let lines: Vec<&str> = body.split('\n').collect();
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    let mut blocks = 0;
    while i < lines.len() {
        let line = lines[i];
        out.push(line.to_string());
        i += 1;
        let Some(info) = line.strip_prefix("```") else {
            continue;
        };
        blocks += 1;
        let end = i + lines[i..]
            .iter()
            .position(|l| l.starts_with("```"))
            .unwrap_or_else(|| panic!("{}: figure `{name}`: unclosed fence", page.display()));
        if let Some(file) = info.split_whitespace().nth(1) {
            let text = lines[i..end].join("\n") + "\n";
            std::fs::write(dir.path().join(file), text).unwrap();
            out.extend(lines[i..end].iter().map(|l| l.to_string()));
        } else {
            out.extend(command_block(
                page,
                name,
                &lines[i..end],
                dir.path(),
                bless,
                errors,
            ));
        }
        i = end;
        out.push(lines[i].to_string());
        i += 1;
    }
    assert!(
        blocks > 0,
        "{}: figure `{name}` holds no fenced block",
        page.display()
    );
    out.join("\n")
}

/// The lines of one fenced block of `$` commands and their shown output, checked (or blessed).
fn command_block(
    page: &Path,
    name: &str,
    lines: &[&str],
    dir: &Path,
    bless: bool,
    errors: &mut Vec<String>,
) -> Vec<String> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        assert!(
            line.starts_with("$ "),
            "{}: figure `{name}`: `{line}` is neither a `$` command nor its output",
            page.display()
        );
        out.push(line.to_string());
        let shown_end = (i + 1..lines.len())
            .find(|&j| lines[j].starts_with("$ "))
            .unwrap_or(lines.len());
        let shown = &lines[i + 1..shown_end];
        let output = run(command_of(line), dir);
        let actual: Vec<&str> = output.lines().map(str::trim_end).collect();
        let where_ = format!(
            "{}: figure `{name}`, `{}`",
            page.display(),
            command_of(line)
        );
        match place(shown, &actual) {
            Err(why) => {
                errors.push(format!("{where_}: {why}; the output:\n{output}"));
                out.extend(shown.iter().map(|l| l.to_string()));
            }
            Ok(placed) => {
                for (s, p) in shown.iter().zip(placed) {
                    match p {
                        None => out.push(s.to_string()),
                        Some(p) if same_line(s, actual[p]) => out.push(s.to_string()),
                        Some(p) => {
                            if !bless {
                                errors.push(format!(
                                    "{where_}:\n  page:   {s}\n  output: {}",
                                    actual[p]
                                ));
                            }
                            out.push(actual[p].to_string());
                        }
                    }
                }
            }
        }
        i = shown_end;
    }
    out
}

#[test]
fn every_figure_matches_the_tool() {
    let bless = std::env::var_os("TOOLTOUCH_BLESS_FIGURES").is_some();
    let mut errors = Vec::new();
    let mut count = 0;
    for (page, text) in pages() {
        let figs = figures(&page, &text);
        if figs.is_empty() {
            continue;
        }
        let mut new = String::new();
        let mut last = 0;
        for fig in figs {
            count += 1;
            let body = &text[fig.body.clone()];
            let fresh = if fig.name == "firmware-gates" {
                let fresh = firmware_gates();
                if fresh != body && !bless {
                    errors.push(format!(
                        "{}: figure `firmware-gates` differs from firmware/ci/expected:\n{fresh}",
                        page.display()
                    ));
                }
                fresh
            } else {
                command_figure(&page, &fig.name, body, bless, &mut errors)
            };
            new += &text[last..fig.body.start];
            new += &fresh;
            last = fig.body.end;
        }
        new += &text[last..];
        if bless && new != text {
            std::fs::write(root().join(&page), new).unwrap();
        }
    }
    assert!(
        count >= 5,
        "only {count} figures found in README.md and docs/"
    );
    assert!(
        errors.is_empty(),
        "{} figure line(s) differ from the tool's output (TOOLTOUCH_BLESS_FIGURES=1 rewrites them):\n\n{}",
        errors.len(),
        errors.join("\n\n")
    );
}

#[test]
fn the_placement_of_shown_lines_can_fail() {
    let actual = ["a 1", "b 2", "c 3", "d 4"];
    assert_eq!(
        place(&["a 1", "...", "d 4"], &actual).unwrap(),
        [Some(0), None, Some(3)]
    );
    assert_eq!(
        place(&["a 1", "...", "c 9", "..."], &actual).unwrap(),
        [Some(0), None, Some(2), None]
    );
    assert!(place(&["a 1", "b 2"], &actual).is_err());
    assert!(place(&["...", "x 1", "..."], &actual).is_err());
    assert!(same_line(
        "done in 0.31 s; wrote out/",
        "done in 0.35 s; wrote out/"
    ));
    assert!(!same_line("error +2.78 µm", "error +2.79 µm"));
}
