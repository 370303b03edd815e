//! The Surfer command file of a mismatch window (`.sucl`, run with `surfer --command-file
//! FILE` from the window's folder): it loads the window VCD, adds the same rows in the same
//! order as the GTKWave save file (the differing outputs first as golden, DUT and
//! difference, then the other outputs, the golden input pins and the DUT's MCU port, each
//! group under a divider) and puts the cursor on the first mismatching clock. Surfer names
//! a variable by its full dotted path without a bit range; times are in the window file's
//! unit (1 ns).

use std::fmt::Write as _;

/// One group of rows: its divider text and the dotted paths of its variables.
pub struct Group {
    /// The divider's text.
    pub title: String,
    /// Full variable paths, e.g. `golden.outputs.count`.
    pub variables: Vec<String>,
}

/// The command file's text: load `vcd_name`, the groups, fit, the cursor at `cursor_ns`.
pub fn command_file(vcd_name: &str, groups: &[Group], cursor_ns: u64) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "load_file {vcd_name}");
    for g in groups {
        let _ = writeln!(s, "divider_add {}", g.title);
        for v in &g.variables {
            let _ = writeln!(s, "variable_add {v}");
        }
    }
    let _ = writeln!(s, "zoom_fit");
    let _ = writeln!(s, "cursor_set {cursor_ns}");
    let _ = writeln!(s, "goto_cursor");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_command_file_loads_adds_in_order_and_sets_the_cursor() {
        let groups = [
            Group {
                title: "differing at cycle 7".into(),
                variables: vec!["golden.outputs.count".into(), "dut.count".into()],
            },
            Group {
                title: "golden input pins".into(),
                variables: vec!["golden.inputs.pin_arm".into()],
            },
        ];
        let text = command_file("w.vcd", &groups, 140);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines,
            [
                "load_file w.vcd",
                "divider_add differing at cycle 7",
                "variable_add golden.outputs.count",
                "variable_add dut.count",
                "divider_add golden input pins",
                "variable_add golden.inputs.pin_arm",
                "zoom_fit",
                "cursor_set 140",
                "goto_cursor",
            ]
        );
    }
}
