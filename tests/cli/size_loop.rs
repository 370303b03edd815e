//! `tooltouch size-loop` as docs/size_loop.md shows it: its settings and run recipes as
//! written (200 parts with faulted touches, none out of tolerance with the safe rules), and
//! bad values refused with exit 2 naming the key.

use crate::common;
use std::path::Path;

/// The body of the fenced block after `<!-- recipe: name -->` in docs/size_loop.md.
fn recipe(name: &str) -> String {
    let page =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/size_loop.md"))
            .unwrap();
    let marker = format!("<!-- recipe: {name} -->");
    let after = page
        .split_once(&marker)
        .unwrap_or_else(|| panic!("docs/size_loop.md has no `{marker}`"))
        .1;
    let mut lines = after.lines().skip_while(|l| l.trim().is_empty());
    assert!(lines.next().unwrap_or_default().starts_with("```"));
    lines
        .take_while(|l| !l.starts_with("```"))
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

#[test]
fn size_loop_recipes_run_as_written() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("loop.toml"), recipe("size-loop-settings")).unwrap();
    let (status, text) = common::bash_with_tooltouch(&recipe("size-loop-run"), dir.path());
    assert!(status.success(), "{text}");
    let this = text
        .lines()
        .find(|l| l.starts_with("this loop: "))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        this.starts_with("this loop: 0/200 out of tolerance"),
        "{this}"
    );
    assert!(text.contains("uncorrected: 19"), "{text}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("size_loop.json")).unwrap())
            .unwrap();
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(200));
    assert_eq!(json["counts"]["out_of_tolerance"], 0);
    assert!(
        json["counts"]["remeasures"].as_u64() > Some(0),
        "{}",
        json["counts"]
    );
    let svg = std::fs::read_to_string(dir.path().join("size_loop.svg")).unwrap();
    assert!(svg.contains("size loop: Ø40 ± 0.01 mm"));
}

#[test]
fn size_loop_bad_settings_exit_2_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    for (toml, key) in [
        (
            "[size_loop]\ntolerance_mm = -0.01\n",
            "size_loop.tolerance_mm = -0.01",
        ),
        (
            "[size_loop]\ndead_zone_mm = -1\n",
            "size_loop.dead_zone_mm = -1",
        ),
        (
            "[size_loop]\nfeedback_pct = 140\n",
            "size_loop.feedback_pct = 140",
        ),
        ("[size_loop]\nparts = 0\n", "size_loop.parts = 0"),
        (
            "[size_loop]\nparts = 100000000\n",
            "size_loop.parts = 100000000",
        ),
        (
            "[size_loop]\nupper_tolerance_mm = 0\n",
            "size_loop.upper_tolerance_mm = 0",
        ),
        (
            "[size_loop]\nmax_correction_mm = -0.004\n",
            "size_loop.max_correction_mm = -0.004",
        ),
        (
            "[size_loop.faults]\nchip_burst = 2\n",
            "size_loop.faults.chip_burst = 2",
        ),
        (
            "[size_loop.faults]\ntrapped_chip_um = 1e9\n",
            "size_loop.faults.trapped_chip_um",
        ),
        ("[size_loop]\nbogus = 1\n", "unknown field `bogus`"),
        ("[size_loop]\nparts = -3\n", "parts"),
    ] {
        let path = dir.path().join("loop.toml");
        std::fs::write(&path, toml).unwrap();
        let o = common::tooltouch(&["size-loop", "--config", common::s(&path)]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{toml}: {err}");
        assert!(
            err.contains(key) && err.contains("loop.toml"),
            "{toml}: {err}"
        );
        assert!(o.stdout.is_empty(), "{toml}");
    }
}
