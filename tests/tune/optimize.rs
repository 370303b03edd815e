//! `tooltouch tune optimize` against the full sweep of spaces small enough to sweep: the
//! answer meets the constraints (checked on the sweep's own row of that point), costs no
//! more than the cheapest swept point that meets them, lies on its method's swept Pareto
//! front, and took far fewer evaluations than the grid. The CLI's exit codes: 1 naming
//! the constraint and the best value reached, 2 naming a malformed key.

use std::process::Command;
use tooltouch_model::MeasureSettings;
use tooltouch_tune::optimize::{optimize, Constraints, Limits, OptimizeSpec, TunedPath};
use tooltouch_tune::{self as tune, point_settings, Overrides, Row, SweepSpec};

/// 1008 front-end points (3 methods × 2 rules × 7 capacitor widths × 6 glitch filters ×
/// 4 scale widths, linear law) on 4 scenarios.
fn measure_space() -> SweepSpec {
    let mut spec = SweepSpec {
        scenarios: 4,
        ..Default::default()
    };
    spec.apply(&Overrides {
        values: vec![
            ("law".into(), "linear".into()),
            ("charge_bits".into(), "4..=16:2".into()),
            ("glitch_cycles".into(), "0..=5".into()),
            ("scale_bits".into(), "12..=24:4".into()),
            ("force.controller".into(), "none".into()),
        ],
        ..Default::default()
    })
    .unwrap();
    spec
}

fn meets(r: &Row, c: &Constraints) -> bool {
    let le = |v: Option<f64>, t: Option<f64>| t.is_none_or(|t| v.is_some_and(|v| v <= t));
    r.misses == 0
        && r.decided > 0
        && le(r.diameter_error_um, c.diameter_error_um)
        && le(r.max_diameter_error_um, c.max_diameter_error_um)
        && le(r.revolution_error, c.revolution_error)
}

#[derive(serde::Deserialize)]
struct MeasureFile {
    measure: MeasureSettings,
}

#[test]
fn front_end_answers_are_the_swept_constrained_optima_on_the_pareto_front() {
    let space = measure_space();
    let t = std::time::Instant::now();
    let sweep = tune::run(&space, None, &|| {}).unwrap();
    let sweep_s = t.elapsed().as_secs_f64();
    let points = space.points().unwrap();
    let cases = [
        Constraints {
            diameter_error_um: Some(0.05),
            ..Default::default()
        },
        Constraints {
            diameter_error_um: Some(0.2),
            ..Default::default()
        },
        Constraints {
            diameter_error_um: Some(1.0),
            ..Default::default()
        },
        Constraints {
            diameter_error_um: Some(0.2),
            max_diameter_error_um: Some(0.3),
            revolution_error: Some(0.5),
            ..Default::default()
        },
    ];
    for c in cases {
        let spec = OptimizeSpec {
            path: TunedPath::Measure,
            cost: None,
            space: space.clone(),
            constraints: c.clone(),
            limits: Limits::default(),
        };
        let o = optimize(&spec, &|_| {}).unwrap();
        let best = o.best.expect("an answer");
        let text = o.settings_toml.as_deref().unwrap();
        let file: MeasureFile = toml::from_str(text).unwrap();
        let index = points
            .iter()
            .position(|p| p.settings == file.measure)
            .expect("the answer is a point of the space");
        let row = &sweep.rows[index];
        assert!(
            meets(row, &c),
            "{c:?}: the answer's swept row misses: {row:?}"
        );
        assert_eq!(f64::from(row.logic_cells), o.evaluations[best].cost);
        let optimum = sweep
            .rows
            .iter()
            .filter(|r| meets(r, &c))
            .map(|r| r.logic_cells)
            .min()
            .unwrap();
        assert_eq!(
            row.logic_cells, optimum,
            "{c:?}: the answer costs more than the swept optimum"
        );
        // On its method's swept Pareto front (no swept point of the method has an error as
        // small and fewer cells, or a smaller error and as few), a margin of 0.
        let dominated = sweep.rows.iter().any(|r| {
            r.method == row.method
                && r.misses == 0
                && r.logic_cells <= row.logic_cells
                && r.diameter_error_um <= row.diameter_error_um
                && (r.logic_cells < row.logic_cells || r.diameter_error_um < row.diameter_error_um)
        });
        assert!(
            !dominated && row.pareto,
            "{c:?}: point {index} is off the swept front"
        );
        // The same settings file `tune point` writes for that point, but the comment line.
        let swept = point_settings::settings_toml(&sweep, index).unwrap();
        let body = |t: &str| t.split_once('\n').unwrap().1.to_string();
        assert_eq!(body(text), body(&swept));
        let n = o.evaluations.len();
        println!(
            "{c:?}: point {index} ({} {} LC, {:.3} µm) in {n} evaluations of {} ({:.1} s; the sweep: {sweep_s:.1} s)",
            row.method,
            row.logic_cells,
            row.diameter_error_um.unwrap(),
            o.grid_points,
            o.seconds
        );
        assert!(
            n * 8 <= sweep.rows.len(),
            "{n} evaluations of {}",
            sweep.rows.len()
        );
    }
}

#[test]
fn force_gains_answer_is_within_three_percent_of_the_swept_optimum() {
    let mut space = SweepSpec::default();
    space
        .apply(&Overrides {
            values: vec![
                ("force.controller".into(), "pi".into()),
                ("force.kp_percent".into(), "25..=300:25".into()),
                ("force.ki_percent".into(), "25..=300:25".into()),
            ],
            ..Default::default()
        })
        .unwrap();
    let c = Constraints {
        iae_difference: Some(0.5),
        override_difference: Some(2.0),
        ..Default::default()
    };
    let spec = OptimizeSpec {
        path: TunedPath::Force,
        cost: None,
        space: space.clone(),
        constraints: c,
        limits: Limits::default(),
    };
    let o = optimize(&spec, &|_| {}).unwrap();
    let best = &o.evaluations[o.best.expect("an answer")];
    let swept: Vec<_> = space
        .force
        .points()
        .unwrap()
        .iter()
        .map(|p| (p.kp_percent, p.ki_percent, tune::optimize::force_metrics(p)))
        .collect();
    let feasible = |m: &tune::optimize::Metrics| {
        m.iae_difference.unwrap() <= 0.5 && m.override_difference.unwrap() <= 2.0
    };
    let (okp, oki, optimum) = swept
        .iter()
        .filter(|(_, _, m)| feasible(m))
        .map(|(kp, ki, m)| (*kp, *ki, m.iae_model.unwrap()))
        .min_by(|a, b| a.2.total_cmp(&b.2))
        .unwrap();
    let (_, _, mine) = swept
        .iter()
        .find(|(kp, ki, _)| {
            best.parameters["kp_percent"] == *kp && best.parameters["ki_percent"] == *ki
        })
        .unwrap();
    assert!(feasible(mine), "{mine:?}");
    assert_eq!(mine.iae_model, best.metrics.iae_model);
    // Compass search finds a local optimum: within 3 % of the swept one (2.3 % here).
    assert!(
        best.cost <= optimum * 1.03,
        "IAE {} against the swept optimum {optimum}",
        best.cost
    );
    println!(
        "force: kp {} % ki {} %: IAE {:.3} N·s (swept optimum kp {okp} % ki {oki} %: {optimum:.3}) in {} evaluations of {} ({:.1} s)",
        best.parameters["kp_percent"],
        best.parameters["ki_percent"],
        best.cost,
        o.evaluations.len(),
        swept.len(),
        o.seconds
    );
    assert!(o.evaluations.len() * 3 <= swept.len());
}

fn tooltouch(dir: &std::path::Path, spec: &str) -> std::process::Output {
    std::fs::write(dir.join("spec.toml"), spec).unwrap();
    Command::new(env!("CARGO_BIN_EXE_tooltouch"))
        .args(["tune", "optimize", "--spec"])
        .arg(dir.join("spec.toml"))
        .arg("--out")
        .arg(dir.join("best.toml"))
        .output()
        .unwrap()
}

#[test]
fn cli_exits_1_naming_the_unmet_constraint_and_2_naming_a_bad_key() {
    let dir = tempfile::tempdir().unwrap();
    let small = "[space]\nscenarios = 2\nmethod = \"counter\"\ncontact_rule = \"sampled\"\nlaw = \"linear\"\n";
    let out = tooltouch(
        dir.path(),
        &format!("path = \"measure\"\n{small}[constraints]\ndiameter_error_um = 0.001\n"),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("`constraints.diameter_error_um` ≤ 0.001: the best value reached is 0.0"),
        "{err}"
    );
    assert!(!dir.path().join("best.toml").exists());
    let log = std::fs::read_to_string(dir.path().join("best.jsonl")).unwrap();
    assert!(log.lines().count() >= 1);
    for line in log.lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        assert!(
            v["violated"][0] == "constraints.diameter_error_um",
            "{line}"
        );
    }
    for (spec, key) in [
        (
            "path = \"measure\"\n[constraints]\ndiameter_error_um = \"a\"\n",
            "`constraints.diameter_error_um`",
        ),
        (
            "path = \"measure\"\n[constraints]\ndiameter = 1.0\n",
            "`constraints.diameter`",
        ),
        (
            "path = \"measure\"\n[constraints]\niae_difference = 1.0\n",
            "`constraints.iae_difference`",
        ),
        (
            "path = \"measure\"\n[space]\ncharge_bits = [3]\n",
            "`space.charge_bits`",
        ),
        (
            "path = \"force\"\n[limits]\nevaluations = 0\n",
            "`limits.evaluations`",
        ),
        ("path = \"lathe\"\n", "`path`"),
        ("cost = \"logic_cells\"\n", "`path`"),
    ] {
        let out = tooltouch(dir.path(), spec);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{spec}: {err}");
        assert!(err.contains(key), "{spec}: {err}");
    }
    let out = tooltouch(
        dir.path(),
        &format!("path = \"measure\"\n{small}[constraints]\ndiameter_error_um = 0.2\n"),
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(dir.path().join("best.toml")).unwrap();
    assert!(
        text.starts_with("# tooltouch tune optimize, measurement point: counter sampled linear"),
        "{text}"
    );
}

#[test]
fn ranges_of_the_default_configuration_name_what_saturates() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_tooltouch"))
        .args(["ranges", "--scenarios", "2", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let r: tune::ranges::Ranges =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("ranges.json")).unwrap())
            .unwrap();
    let reg = |n: &str| r.registers.iter().find(|x| x.name == n).unwrap();
    // The default capacitor (16 bits) fills on contact: it saturates at full scale, and
    // the warning names it; revolutions (u16) never come near 65535 in 12 revolutions.
    let charge = reg("charge");
    assert_eq!(charge.max, 65535.0);
    assert!(
        charge.saturations > 0 && charge.headroom_bits == 0,
        "{charge:?}"
    );
    assert!(err.contains("register `charge`"), "{err}");
    let revs = reg("revolutions");
    assert!(
        revs.max >= 12.0 && revs.max < 20.0 && revs.headroom_bits >= 11,
        "{revs:?}"
    );
    assert_eq!(revs.saturations, 0);
    assert!(!err.contains("`revolutions`"));
    // Every warned register saturated or wrapped, and every such register is warned.
    for x in &r.registers {
        let warned = err.contains(&format!("register `{}`", x.name));
        assert_eq!(warned, x.saturations > 0 || x.wraps > 0, "{x:?}");
        assert!(x.samples > 0 && x.min <= x.max, "{x:?}");
    }
    assert!(reg("force_estimate").format == "I32F32");
}
