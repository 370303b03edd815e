//! The transient milling plant (`tooltouch_plant::milling_transients`): per-tooth entry and
//! exit ringing and noise on top of W6. The paper's observation: its model predicts the
//! measured power well except where teeth enter and leave the cut, so the mean power is
//! predicted better than the instantaneous one — checked here on its Table 2 groups 1
//! (Z = 1) and 2 (Z = 5) and Fig. 6's conditions, over whole revolutions.

use tooltouch_plant::milling::{cutting_trace, Conditions, MillingParams};
use tooltouch_plant::milling_transients::ToothTransients;

struct Case {
    name: &'static str,
    teeth: u32,
    speed_m_per_min: f64,
    depth_mm: f64,
    feed_mm_per_rev: f64,
    vb_mm: f64,
}

const CASES: [Case; 3] = [
    Case {
        name: "group 1 (Z = 1)",
        teeth: 1,
        speed_m_per_min: 18.0,
        depth_mm: 4.0,
        feed_mm_per_rev: 0.8,
        vb_mm: 1.1,
    },
    Case {
        name: "group 2 (Z = 5)",
        teeth: 5,
        speed_m_per_min: 9.0,
        depth_mm: 4.0,
        feed_mm_per_rev: 0.8,
        vb_mm: 0.98,
    },
    Case {
        name: "Fig. 6, b = 3 mm",
        teeth: 5,
        speed_m_per_min: 149.0,
        depth_mm: 3.0,
        feed_mm_per_rev: 1.0,
        vb_mm: 0.0,
    },
];

#[test]
fn the_mean_is_predicted_better_than_the_instantaneous_power() {
    let fs = 1000.0;
    for case in &CASES {
        let m = MillingParams {
            teeth: case.teeth,
            ..MillingParams::default()
        };
        let rpm = case.speed_m_per_min * 1000.0 / (std::f64::consts::PI * m.diameter_mm);
        let c = Conditions {
            depth_mm: case.depth_mm,
            feed_per_tooth_mm: case.feed_mm_per_rev / f64::from(case.teeth),
            rpm,
        };
        let turns = 4.0;
        let seconds = turns * 60.0 / rpm;
        let t = ToothTransients::default();
        let (model, measured) = cutting_trace(&m, &c, case.vb_mm, &t, fs, seconds, 3);
        let n = model.len() as f64;
        let w7 = m.mean_power(case.vb_mm, &c);
        let mean_measured = measured.iter().sum::<f64>() / n;
        let mean_error = (mean_measured - w7).abs() / w7;
        let rms = |it: &mut dyn Iterator<Item = f64>| {
            let (s, k) = it.fold((0.0, 0.0), |(s, k), e| (s + e * e, k + 1.0));
            (s / f64::max(k, 1.0)).sqrt()
        };
        let errors: Vec<f64> = model.iter().zip(&measured).map(|(a, b)| b - a).collect();
        let inst_error = rms(&mut errors.iter().copied()) / w7;
        // Where the model jumps (a tooth enters or leaves) versus elsewhere: the ringing's
        // envelope lasts 1/(ζ·ω_n) ≈ 9 ms; 25 ms after a jump counts as "near".
        let jump = 0.2 * model.iter().cloned().fold(0.0, f64::max);
        let mut near = vec![false; model.len()];
        for k in 1..model.len() {
            if (model[k] - model[k - 1]).abs() > jump {
                for flag in near.iter_mut().skip(k).take(25) {
                    *flag = true;
                }
            }
        }
        let near_err = rms(&mut errors
            .iter()
            .zip(&near)
            .filter(|(_, &f)| f)
            .map(|(e, _)| *e));
        let far_err = rms(&mut errors
            .iter()
            .zip(&near)
            .filter(|(_, &f)| !f)
            .map(|(e, _)| *e));
        eprintln!(
            "{}: W7 {w7:.0} W, measured mean {mean_measured:.0} W: mean error {:.2} %, instantaneous rms error {:.1} %; rms error near entry/exit {near_err:.0} W, elsewhere {far_err:.0} W",
            case.name,
            100.0 * mean_error,
            100.0 * inst_error
        );
        assert!(mean_error < 0.01, "{}: mean error {mean_error}", case.name);
        assert!(
            inst_error > 5.0 * mean_error && inst_error > 0.05,
            "{}: instantaneous {inst_error} vs mean {mean_error}",
            case.name
        );
        assert!(
            near_err > 2.0 * far_err,
            "{}: {near_err} vs {far_err}",
            case.name
        );
    }
}

#[test]
fn bad_transient_settings_are_named() {
    let ok = ToothTransients::default();
    assert!(ok.validate().is_ok());
    for (t, field) in [
        (
            ToothTransients {
                natural_hz: 0.0,
                ..ok
            },
            "natural_hz",
        ),
        (
            ToothTransients {
                damping: f64::NAN,
                ..ok
            },
            "damping",
        ),
        (
            ToothTransients {
                noise_w: -1.0,
                ..ok
            },
            "noise_w",
        ),
    ] {
        assert!(t.validate().unwrap_err().contains(field));
    }
}
