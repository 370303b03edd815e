//! The force path's cost in firmware instructions (`cost = "firmware_instructions"`): every
//! point of a force space small enough to sweep executed on the Nucleo image under QEMU
//! (its force outputs checked bit for bit on the way), and the optimizer's answer against
//! that sweep: it meets the constraints, costs what the sweep measured for the same point,
//! is within a stated margin of the cheapest swept point meeting them, and took fewer
//! evaluations than the grid.

use std::process::Command;
use tooltouch_tune::firmware_cost::{force_case, CostImage};
use tooltouch_tune::optimize::{
    force_metrics, optimize, Constraints, CostKind, Limits, OptimizeSpec, TunedPath,
};
use tooltouch_tune::{Overrides, SweepSpec};

/// The three controllers on the estimated force, kp and ki at 50/100/200 % of the design
/// (the adaptive controller has no ki): 9 + 3 + 9 = 21 points.
fn force_space() -> SweepSpec {
    let mut space = SweepSpec::default();
    space
        .apply(&Overrides {
            values: vec![
                ("force.controller".into(), "pi,adaptive,fuzzy".into()),
                ("force.force_source".into(), "estimated".into()),
                ("force.kp_percent".into(), "50,100,200".into()),
                ("force.ki_percent".into(), "50,100,200".into()),
            ],
            ..Default::default()
        })
        .unwrap();
    space
}

fn image() -> CostImage {
    CostImage::build().unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_recorded_scenario_is_the_one_the_iae_comes_from() {
    let config = tooltouch_model::force::config::ForceSettings::default()
        .validate()
        .unwrap();
    let case = force_case(&config);
    // 13 s at 1 kHz, a control period every 50 samples, two identification commands and
    // the engagement.
    let samples = case
        .force_events
        .iter()
        .filter(|(_, e)| matches!(e, tooltouch_model::force::events::ForceEvent::Sample(_)))
        .count();
    assert_eq!(samples, 13_000);
    assert_eq!(case.force_events.len(), 13_000 + 260 + 3);
    assert!(case.force_events.windows(2).all(|w| w[0].0 <= w[1].0));
    assert!(case.events.is_empty());
    // Replaying the recorded events through the golden kernel gives the run's overrides:
    // the firmware that agrees bit for bit has run the closed loop.
    let golden = tooltouch_firmware_runner::golden_force(&case);
    assert_eq!(golden.len(), 260 + 3);
}

#[test]
fn optimizer_answer_is_the_cheapest_swept_point_within_two_percent() {
    let space = force_space();
    let points = space.force.points().unwrap();
    let configs: Vec<_> = points
        .iter()
        .map(|p| p.settings.validate().unwrap())
        .collect();
    let image = image();
    let t = std::time::Instant::now();
    let costs = image.measure(&configs).unwrap_or_else(|e| panic!("{e}"));
    let sweep_s = t.elapsed().as_secs_f64();
    println!(
        "the sweep's {} points in one QEMU boot: {sweep_s:.1} s",
        points.len()
    );
    let metrics: Vec<_> = points.iter().map(force_metrics).collect();
    for ((p, c), m) in points.iter().zip(&costs).zip(&metrics) {
        println!(
            "{:9} kp {:3} % ki {:3} %: {:7.1} instructions per control period ({:5.1} per sample, {:6.1} per control interrupt), IAE {:.2} N·s",
            p.controller,
            p.kp_percent,
            p.ki_percent,
            c.per_period,
            c.per_sample,
            c.per_control,
            m.iae_model.unwrap()
        );
        assert_eq!((c.periods, c.samples), (260, 13_000));
        assert!((c.per_period - (c.per_sample * 50.0 + c.per_control)).abs() < 1e-6 * c.per_period);
    }
    // The controllers' code differs, and so does what it costs.
    let mean = |name: &str| {
        let v: Vec<f64> = points
            .iter()
            .zip(&costs)
            .filter(|(p, _)| p.controller == name)
            .map(|(_, c)| c.per_period)
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let (pi, adaptive, fuzzy) = (mean("pi"), mean("adaptive"), mean("fuzzy"));
    println!("mean per control period: pi {pi:.1}, adaptive {adaptive:.1}, fuzzy {fuzzy:.1}");
    assert!(pi != adaptive && pi != fuzzy && adaptive != fuzzy);
    // A tolerance on the IAE that some points of every controller meet and others miss.
    let mut iaes: Vec<f64> = metrics.iter().map(|m| m.iae_model.unwrap()).collect();
    iaes.sort_by(f64::total_cmp);
    let tolerance = iaes[iaes.len() / 2];
    let feasible = |m: &tooltouch_tune::optimize::Metrics| m.iae_model.unwrap() <= tolerance;
    let cheapest = costs
        .iter()
        .zip(&metrics)
        .filter(|(_, m)| feasible(m))
        .map(|(c, _)| c.per_period)
        .fold(f64::INFINITY, f64::min);
    let spec = OptimizeSpec {
        path: TunedPath::Force,
        cost: Some(CostKind::FirmwareInstructions),
        space: space.clone(),
        constraints: Constraints {
            iae: Some(tolerance),
            ..Default::default()
        },
        limits: Limits::default(),
    };
    let o = optimize(&spec, &|_| {}).unwrap_or_else(|e| panic!("{}: {}", e.parameter, e.message));
    let best = &o.evaluations[o.best.expect("an answer")];
    let i = points
        .iter()
        .position(|p| {
            best.family.starts_with(p.controller)
                && best.parameters["kp_percent"] == p.kp_percent
                && best
                    .parameters
                    .get("ki_percent")
                    .is_none_or(|&ki| ki == p.ki_percent)
        })
        .unwrap();
    assert!(feasible(&metrics[i]), "{:?}", metrics[i]);
    // The same point executed again, alone, costs the same within the SysTick
    // quantization (one tick per interrupt; QEMU's instruction count itself is exact).
    assert_eq!(best.metrics.firmware_instructions, Some(best.cost));
    assert!(
        (best.cost - costs[i].per_period).abs() <= costs[i].resolution,
        "{} alone, {} in the sweep's boot (resolution {})",
        best.cost,
        costs[i].per_period,
        costs[i].resolution
    );
    // The compass search is local within a family: within 2 % of the swept optimum.
    assert!(
        best.cost <= cheapest * 1.02 + costs[i].resolution,
        "{} instructions against the swept cheapest {cheapest}",
        best.cost
    );
    println!(
        "answer: {} {:?}: {:.1} instructions per control period, IAE {:.2} ≤ {tolerance:.2} N·s \
         (swept cheapest {cheapest:.1}) in {} evaluations of {} ({:.1} s; the sweep's QEMU run {sweep_s:.1} s)",
        best.family,
        best.parameters,
        best.cost,
        metrics[i].iae_model.unwrap(),
        o.evaluations.len(),
        points.len(),
        o.seconds
    );
    // The other controllers' start points cost 5–6 % more: only PI's gains are searched.
    assert!(o.evaluations.len() * 2 <= points.len());
}

#[test]
fn firmware_instructions_is_a_cost_of_the_force_path_only() {
    let dir = tempfile::tempdir().unwrap();
    for (spec, key) in [
        (
            "path = \"measure\"\ncost = \"firmware_instructions\"\n",
            "`cost`",
        ),
        (
            "path = \"measure\"\n[constraints]\niae = 100.0\n",
            "`constraints.iae`",
        ),
        (
            "path = \"force\"\n[constraints]\niae = -1.0\n",
            "`constraints.iae`",
        ),
    ] {
        std::fs::write(dir.path().join("spec.toml"), spec).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_tooltouch"))
            .args(["tune", "optimize", "--spec"])
            .arg(dir.path().join("spec.toml"))
            .arg("--out")
            .arg(dir.path().join("best.toml"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{spec}: {err}");
        assert!(err.contains(key), "{spec}: {err}");
    }
}
