//! The milling-wear presets (examples/wear-*.toml) against the paper's figures: Fig. 6's
//! wear thresholds at [VB] = 0.5 mm — mean CUTTING power 3.15 kW at b = 2 mm and 4.35 kW at
//! b = 3 mm (149 m/min, s = 1.00 mm/rev, Z = 5) — within 5 % (the paper reads them off its
//! own mean-power model with constants fitted by least squares to its measurements; 5 %
//! is the scatter of its Fig. 5 points about the model lines); Fig. 5: the mean power grows
//! in proportion to VB; and the updating threshold's verdicts on those presets.

use std::path::Path;
use tooltouch_settings::wear::WearPlan;

fn preset(file: &str) -> WearPlan {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(file);
    let table: toml::Table = toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    WearPlan::from_table(&table["wear"]).unwrap()
}

#[test]
fn fig6_thresholds_are_the_papers_mean_cutting_power_within_5_percent() {
    let plan = preset("wear-fig6.toml");
    let sc = &plan.scenario;
    assert_eq!(sc.vb_limit_mm, 0.5);
    for (cut, paper_w) in sc.cuts.iter().zip([3150.0, 4350.0]) {
        let p = sc.milling.mean_power(sc.vb_limit_mm, &cut.conditions);
        let err = (p - paper_w) / paper_w;
        eprintln!(
            "b = {} mm: [P-bar] = {p:.0} W cutting vs the paper's {paper_w} W ({:+.1} %); motor {:.0} W",
            cut.conditions.depth_mm,
            100.0 * err,
            cut.idle_power + p / sc.milling.efficiency
        );
        assert!(err.abs() < 0.05, "b = {}: {p} W", cut.conditions.depth_mm);
        // The motor power the monitor compares is not the paper's figure: more than 20 %
        // above it with the preset's idle power and efficiency.
        assert!(cut.idle_power + p / sc.milling.efficiency > 1.2 * paper_w);
    }
}

#[test]
fn fig6_mean_cutting_power_over_the_simulated_cut_matches_w7() {
    // The W6 power the plant feeds the monitor, averaged over the cut at VB = [VB], is W7's.
    let plan = preset("wear-fig6.toml");
    let sc = &plan.scenario;
    for cut in &sc.cuts {
        let c = &cut.conditions;
        let n = 200_000;
        let turns = 10.0;
        let mean = (0..n)
            .map(|i| {
                let theta = std::f64::consts::TAU * turns * f64::from(i) / f64::from(n);
                sc.milling.cutting_power(theta, sc.vb_limit_mm, c)
            })
            .sum::<f64>()
            / f64::from(n);
        let w7 = sc.milling.mean_power(sc.vb_limit_mm, c);
        assert!((mean - w7).abs() < 1e-3 * w7, "{mean} vs {w7}");
    }
}

#[test]
fn fig5_mean_power_grows_in_proportion_to_vb() {
    // Equal VB steps add equal power (a straight line), with a positive slope, in every
    // condition set of every preset.
    for file in [
        "wear-fig6.toml",
        "wear-table2-z1.toml",
        "wear-table2-z5.toml",
    ] {
        let sc = preset(file).scenario;
        let (sets, _) = sc.condition_sets();
        for (c, _) in &sets {
            let p: Vec<f64> = (0..=10)
                .map(|i| sc.milling.mean_power(0.1 * f64::from(i), c))
                .collect();
            let slope = p[1] - p[0];
            assert!(slope > 0.0, "{file}");
            for w in p.windows(2) {
                assert!(
                    ((w[1] - w[0]) - slope).abs() < 1e-9 * p[10],
                    "{file}: {p:?}"
                );
            }
        }
    }
}

#[test]
fn the_presets_updating_threshold_passes_the_new_tool_and_stops_the_worn_one() {
    for file in [
        "wear-fig6.toml",
        "wear-table2-z1.toml",
        "wear-table2-z5.toml",
    ] {
        let plan = preset(file);
        let sc = &plan.scenario;
        let config = sc.config(false).unwrap();
        let new = sc.run(&plan.new_tool, &config);
        let worn = sc.run(&plan.worn_tool, &config);
        eprintln!(
            "{file}: new {:?}, worn {:?} (hold {} periods)",
            new.alarm_at,
            worn.alarm_at,
            config.settings().wear.settle_periods
        );
        assert_eq!(new.alarm_at, None, "{file}: the new tool alarmed");
        let t = worn
            .alarm_at
            .unwrap_or_else(|| panic!("{file}: worn tool missed"));
        assert!(
            t < sc.cut_start(1.min(sc.cuts.len() - 1)) + 5.0,
            "{file}: {t} s"
        );
    }
}
