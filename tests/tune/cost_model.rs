//! The committed tuning cost model against a fresh yosys synthesis: every calibration
//! point (`tooltouch_tune::cost::CALIBRATION_POINTS`, all 14: each varies one feature of
//! the model, so a subset would leave a coefficient unchecked) is synthesized with yosys
//! `synth_ice40`, and each committed measurement must be within 2 % of the fresh one, for
//! flip-flops and logic cells. The model's coefficients are the least-squares fit of the
//! committed measurements (checked exactly by `host/tune/src/cost.rs`'s unit tests), so a
//! generator change that moves the cost fails here until the model is refitted.
//!
//! Run with `TOOLTOUCH_BLESS=1` (as `cargo xtask hdl-report` does) it refits instead:
//! writes the fresh measurements and their fit to `host/tune/src/cost_model.json`.
//!
//! yosys is required: without it the test fails naming `cargo xtask setup`.

use std::time::Instant;
use tooltouch_tune::cost::synthesis::{synthesize_all, yosys_version};
use tooltouch_tune::cost::{CostModel, CostModelFile, CALIBRATION_POINTS, COST_MODEL_PATH};

/// Largest allowed deviation of a committed measurement from a fresh synthesis, relative
/// to the fresh one.
const TOLERANCE: f64 = 0.02;

/// Set to `1` to refit and rewrite the committed model instead of checking it.
const BLESS_VAR: &str = "TOOLTOUCH_BLESS";

#[test]
fn committed_cost_model_is_within_two_percent_of_a_fresh_yosys_synthesis() {
    let version = yosys_version().unwrap_or_else(|e| panic!("{e}"));
    let work = tempfile::tempdir().expect("temporary folder");
    let t = Instant::now();
    let fresh = synthesize_all(&CALIBRATION_POINTS, work.path()).unwrap_or_else(|e| panic!("{e}"));
    let wall = t.elapsed().as_secs_f64();
    let yosys_seconds: f64 = fresh.iter().map(|s| s.seconds).sum();
    let yosys_cpu: f64 = fresh.iter().map(|s| s.cpu_seconds).sum();
    let committed = CostModelFile::committed();
    let model = CostModel::fitted();
    let refit = CostModelFile::refit(fresh.iter().map(|s| s.calibration).collect(), &version);
    let refit_model = refit.model();

    println!(
        "{version}: {} calibration points in {wall:.1} s wall; yosys runs {yosys_seconds:.1} s \
         wall, {yosys_cpu:.1} s CPU in all",
        fresh.len()
    );
    println!(
        "columns: committed/fresh measurement (c/f), its deviation, committed model/refit \
         estimate (m/r), yosys wall/CPU seconds (w/c)"
    );
    let row = |cells: [String; 13]| {
        let [i, charge, scale, glitch, ppr, revs, ff, lc, dff, dlc, ffm, lcm, sec] = cells;
        println!(
            "{i:>2} {charge:>6} {scale:>5} {glitch:>6} {ppr:>5} {revs:>4} | {ff:>9} {lc:>9} \
             {dff:>6} {dlc:>6} | {ffm:>9} {lcm:>9} | {sec:>9}"
        );
    };
    row([
        "#",
        "charge",
        "scale",
        "glitch",
        "ppr",
        "revs",
        "FF c/f",
        "LC c/f",
        "dFF %",
        "dLC %",
        "FF m/r",
        "LC m/r",
        "yosys w/c",
    ]
    .map(String::from));
    let deviation = |committed: u32, fresh: u32| {
        (f64::from(committed) - f64::from(fresh)) / f64::from(fresh.max(1))
    };
    let mut off = Vec::new();
    for (i, s) in fresh.iter().enumerate() {
        let f = s.calibration;
        let p = f.point;
        let c = committed.measurements.get(i);
        let (cff, clc) = c.map_or((0, 0), |c| (c.flip_flops, c.logic_cells));
        let (dff, dlc) = (deviation(cff, f.flip_flops), deviation(clc, f.logic_cells));
        let e = model.estimate_point(&p);
        let r = refit_model.estimate_point(&p);
        row([
            i.to_string(),
            format!("{}{}", p.charge_bits, if p.exponential { "e" } else { "l" }),
            p.scale_bits.to_string(),
            p.glitch_cycles.to_string(),
            p.pulses_per_rev.to_string(),
            p.window_revs.to_string(),
            format!("{cff}/{}", f.flip_flops),
            format!("{clc}/{}", f.logic_cells),
            format!("{:+.2}", 100.0 * dff),
            format!("{:+.2}", 100.0 * dlc),
            format!("{}/{}", e.flip_flops, r.flip_flops),
            format!("{}/{}", e.logic_cells, r.logic_cells),
            format!("{:.1}/{:.1}", s.seconds, s.cpu_seconds),
        ]);
        if c.map(|c| c.point) != Some(p) || dff.abs() > TOLERANCE || dlc.abs() > TOLERANCE {
            off.push(format!(
                "point {i} {p:?}: committed {:?}, fresh {} FF {} LC",
                c, f.flip_flops, f.logic_cells
            ));
        }
    }

    if std::env::var(BLESS_VAR).is_ok_and(|v| v == "1") {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(COST_MODEL_PATH);
        std::fs::write(&path, refit.to_json()).expect("writing the cost model");
        println!("refitted: wrote {}", path.display());
        println!("flip-flop coefficients  {:?}", refit.flip_flops);
        println!("logic-cell coefficients {:?}", refit.logic_cells);
        return;
    }
    assert!(
        off.is_empty(),
        "{COST_MODEL_PATH} is more than {:.0} % off a fresh yosys synthesis:\n  {}\n\
         Refit it with `cargo xtask hdl-report` and review the diff.",
        100.0 * TOLERANCE,
        off.join("\n  ")
    );
}
