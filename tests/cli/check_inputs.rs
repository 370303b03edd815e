//! `tooltouch check` on inputs that cannot be compared or that stretch the readers: an
//! empty file, a file of neither format, a VCD against a binary file (each named with its
//! role, golden or DUT, and why), a VCD value wider than its signal (named with its line,
//! signal and time), and a DUT value with a 1 above the golden width (a mismatch, not cut
//! off).

use crate::common;

use common::{s, text, tooltouch};
use std::path::{Path, PathBuf};

/// A small golden set (`tooltouch vectors` over six segments of pins) in `dir/v`.
fn golden_set(dir: &Path) -> PathBuf {
    let stim = dir.join("stim.hex");
    std::fs::write(
        &stim,
        "0000000006\n0000000010\n0100000020\n0900000008\n0100000020\n0d00000008\n1300000010\n",
    )
    .unwrap();
    let v = dir.join("v");
    let o = tooltouch(&["vectors", "--stimulus", s(&stim), "--out", s(&v)]);
    assert!(o.status.success(), "{}", text(&o));
    v
}

fn check(expected: &Path, dut: &Path) -> (Option<i32>, String) {
    let o = tooltouch(&["check", "--expected", s(expected), "--dut", s(dut)]);
    (o.status.code(), text(&o))
}

#[test]
fn files_that_cannot_be_compared_are_named_with_their_role_and_why() {
    let w = tempfile::tempdir().unwrap();
    let v = golden_set(w.path());
    let ttv = v.join("expected_outputs.ttv");
    let vcd = v.join("golden.vcd");
    let empty = w.path().join("empty.ttv");
    std::fs::write(&empty, b"").unwrap();
    let (code, out) = check(&empty, &ttv);
    assert_eq!(code, Some(2), "{out}");
    assert!(
        out.contains("empty.ttv (the golden trace): empty file (0 bytes)"),
        "{out}"
    );
    let magic = w.path().join("magic.ttv");
    let mut bytes = std::fs::read(&ttv).unwrap();
    bytes[3] = b'Y';
    std::fs::write(&magic, &bytes).unwrap();
    let (code, out) = check(&ttv, &magic);
    assert_eq!(code, Some(2), "{out}");
    assert!(
        out.contains("magic.ttv (the DUT trace): byte 0: neither a binary vector file")
            && out.contains("54 54 56 59"),
        "{out}"
    );
    let (code, out) = check(&vcd, &ttv);
    assert_eq!(code, Some(2), "{out}");
    assert!(
        out.contains("golden.vcd (the golden trace) is a VCD")
            && out.contains("expected_outputs.ttv (the DUT trace) is a binary vector file"),
        "{out}"
    );
    let empty_vcd = w.path().join("empty.vcd");
    std::fs::write(&empty_vcd, b"  \n").unwrap();
    let (code, out) = check(&vcd, &empty_vcd);
    assert_eq!(code, Some(2), "{out}");
    assert!(out.contains("empty.vcd (the DUT trace): byte 0"), "{out}");
}

/// The golden VCD with the `$var` line of output `name` and its value changes rewritten
/// by `edit(var line, value line) -> (var line, value line)`.
fn edited(golden: &str, name: &str, edit: impl Fn(&str) -> String) -> String {
    let var = golden
        .lines()
        .find(|l| l.starts_with("$var") && l.contains(&format!(" {name} ")))
        .unwrap();
    let id = var.split(' ').nth(3).unwrap().to_string();
    golden
        .lines()
        .map(|l| {
            if l == var || l.ends_with(&format!(" {id}")) {
                edit(l)
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

#[test]
fn vcd_values_of_any_width_are_read_exactly() {
    let w = tempfile::tempdir().unwrap();
    let v = golden_set(w.path());
    let golden_path = v.join("golden.vcd");
    let golden = std::fs::read_to_string(&golden_path).unwrap();
    // `pulses` (32 bits) declared 100 bits wide in the DUT, its values as they are: a match.
    let widen = |l: &str| {
        if l.starts_with("$var") {
            l.replace(" 32 ", " 100 ").replace("[31:0]", "[99:0]")
        } else {
            l.to_string()
        }
    };
    let wide = w.path().join("wide.vcd");
    std::fs::write(&wide, edited(&golden, "pulses", widen)).unwrap();
    let (code, out) = check(&golden_path, &wide);
    assert_eq!(code, Some(0), "{out}");
    // The same with a 1 at bit 80 of every value: a mismatch showing the whole value (21
    // hex digits), not cut off at 64 bits.
    let high = |l: &str| {
        let l = widen(l);
        match l.strip_prefix('b') {
            Some(rest) => {
                let (bits, id) = rest.split_once(' ').unwrap();
                format!("b1{}{bits} {id}", "0".repeat(80 - bits.len()))
            }
            None => l,
        }
    };
    let above = w.path().join("above.vcd");
    std::fs::write(&above, edited(&golden, "pulses", high)).unwrap();
    let (code, out) = check(&golden_path, &above);
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains("signal pulses expected")
            && out.contains(&format!(" got 0x1{}", "0".repeat(12))),
        "{out}"
    );
    // A value with more digits than its own 32-bit `$var`: bad input naming it.
    let long = |l: &str| match l.strip_prefix('b') {
        Some(rest) => format!("b1{}{rest}", "0".repeat(40)),
        None => l.to_string(),
    };
    let too_long = w.path().join("long.vcd");
    std::fs::write(&too_long, edited(&golden, "pulses", long)).unwrap();
    let (code, out) = check(&golden_path, &too_long);
    assert_eq!(code, Some(2), "{out}");
    assert!(
        out.contains("long.vcd: line ")
            && out.contains("bits for `tooltouch.outputs.pulses`, declared 32 bits wide"),
        "{out}"
    );
}
