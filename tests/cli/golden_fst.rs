//! `--golden-format fst`: `tooltouch vectors` and `tooltouch measure` write the golden trace
//! as FST (golden.fst / measure.fst, not the VCD), which `check` compares with the VCD of the
//! same run either way round, and a flipped VCD against the FST is the VCD path's mismatch.

use crate::common::{s, text, tooltouch};

#[test]
fn vectors_and_measure_write_a_golden_fst_that_check_reads_like_the_vcd() {
    let w = tempfile::tempdir().unwrap();
    let (vcd_dir, fst_dir) = (w.path().join("vcd"), w.path().join("fst"));
    for (dir, format) in [(&vcd_dir, "vcd"), (&fst_dir, "fst")] {
        let o = tooltouch(&[
            "vectors",
            "--stress",
            "3",
            "--golden-format",
            format,
            "--out",
            s(dir),
        ]);
        assert!(o.status.success(), "{}", text(&o));
    }
    assert!(!fst_dir.join("golden.vcd").exists() && vcd_dir.join("golden.vcd").is_file());
    let (vcd, fst) = (vcd_dir.join("golden.vcd"), fst_dir.join("golden.fst"));
    assert_eq!(std::fs::read(&fst).unwrap().first(), Some(&0), "not an FST");
    let check = |e: &std::path::Path, d: &std::path::Path| {
        let o = tooltouch(&["check", "--expected", s(e), "--dut", s(d)]);
        (o.status.code(), text(&o))
    };
    for (e, d) in [(&vcd, &fst), (&fst, &vcd)] {
        let (code, out) = check(e, d);
        assert!(code == Some(0) && out.contains("17 signals"), "{out}");
    }
    // register_now's first rise flipped in the VCD: the same first mismatch whether the
    // golden side is the VCD or the FST.
    let text_vcd = std::fs::read_to_string(&vcd).unwrap();
    let line = text_vcd
        .lines()
        .position(|l| l.ends_with(')') && l.len() == 2 && l.starts_with('1'))
        .expect("a rise of the signal with code `)`");
    let mut lines: Vec<&str> = text_vcd.lines().collect();
    lines[line] = "0)";
    let broken = w.path().join("broken.vcd");
    std::fs::write(&broken, lines.join("\n") + "\n").unwrap();
    let (code_v, out_v) = check(&vcd, &broken);
    let (code_f, out_f) = check(&fst, &broken);
    assert_eq!((code_v, code_f), (Some(1), Some(1)), "{out_v}\n{out_f}");
    let first = |t: &str| t.lines().next().unwrap_or("").to_string();
    assert_eq!(first(&out_v), first(&out_f));
    // measure: measure.fst instead of measure.vcd.
    let m = w.path().join("m");
    let o = tooltouch(&[
        "measure",
        "--no-progress",
        "--golden-format",
        "fst",
        "--out",
        s(&m),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(m.join("measure.fst").is_file() && !m.join("measure.vcd").exists());
    let (code, out) = check(&m.join("measure.fst"), &m.join("measure.fst"));
    assert!(code == Some(0) && out.contains("66410001 cycles"), "{out}");
}
