//! The wear scenario (docs/domain.md §4): the updating threshold alarms for the worn tool and not
//! for the new one at both depths; the constant threshold (set for the first conditions)
//! raises a false alarm on the new tool when the depth grows — its failure mode.

use tooltouch_plant::milling::{MillingParams, WearScenario, NEW_TOOL, WORN_TOOL};
use tooltouch_plant::reference::WearF;

#[test]
fn updating_threshold_separates_new_and_worn_tools() {
    let sc = WearScenario::default();
    let config = sc.config(false).unwrap();
    let new = sc.run(&NEW_TOOL, &config);
    let worn = sc.run(&WORN_TOOL, &config);
    assert_eq!(new.alarm_at, None, "new tool must not alarm");
    let t = worn.alarm_at.expect("worn tool must alarm");
    assert!(
        t < sc.cut_start(1),
        "worn tool alarms in the first cut, got {t} s"
    );
    // the threshold follows the conditions: higher in the 3 mm cut
    let a1 = new.allowed[100];
    let a2 = *new.allowed.last().unwrap();
    assert!(a2 > a1 * 1.3, "{a1} -> {a2}");
}

#[test]
fn constant_threshold_false_alarms_when_the_depth_grows() {
    let sc = WearScenario::default();
    let config = sc.config(true).unwrap();
    let new = sc.run(&NEW_TOOL, &config);
    let t = new
        .alarm_at
        .expect("the constant threshold's failure mode: a false alarm");
    assert!(t > sc.cut_start(1), "only after the depth step, got {t} s");
    let worn = sc.run(&WORN_TOOL, &config);
    assert!(worn.alarm_at.is_some());
}

#[test]
fn mean_power_w7_is_the_mean_of_w6() {
    let m = MillingParams::default();
    let sc = WearScenario::default();
    for vb in [0.0, 0.3] {
        let c = sc.cuts[1].conditions;
        let n = 100_000;
        let mean: f64 = (0..n)
            .map(|i| {
                m.cutting_power(
                    2.0 * std::f64::consts::PI * f64::from(i) / f64::from(n),
                    vb,
                    &c,
                )
            })
            .sum::<f64>()
            / f64::from(n);
        let w7 = m.mean_power(vb, &c);
        assert!(
            (mean - w7).abs() < 1e-3 * w7,
            "VB {vb}: W6 mean {mean} vs W7 {w7}"
        );
    }
}

#[test]
fn fixed_point_monitor_matches_its_float_reference() {
    use tooltouch_model::force::wear::WearMonitor;
    use tooltouch_model::units::Fx;
    let sc = WearScenario::default();
    let config = sc.config(false).unwrap();
    let run = sc.run(&WORN_TOOL, &config);
    let settings = config.settings().wear;
    let shift = config.settings().lowpass_shift;
    let mut fixed = WearMonitor::new(&settings, shift);
    let mut float = WearF::new(&settings, shift);
    let spp = config.settings().samples_per_period;
    // the true period-mean motor power of the worn-tool run as the monitor's input
    for (i, &p) in run.power_true.iter().enumerate() {
        if i == run.t.len() / 2 {
            fixed.select(1);
            float.select(1);
        }
        for _ in 0..spp {
            fixed.on_sample();
            float.on_sample();
        }
        let st = fixed.step(Fx::from_num(p));
        let y = float.step(p);
        assert!(
            (st.power.to_num::<f64>() - y).abs() < 0.01,
            "period {i}: {} vs {y}",
            st.power
        );
        assert!((st.allowed.to_num::<f64>() - float.allowed).abs() < 0.01);
        assert_eq!(st.alarm, float.alarm, "period {i}");
        assert_eq!(st.blind, float.blind, "period {i}");
    }
    // replaying the recorded events through a fresh kernel reproduces the run's alarm
    let mut k = tooltouch_model::force::kernel::ForceKernel::new(&config);
    for (_, ev) in &run.events {
        k.apply(*ev);
    }
    assert_eq!(k.outputs().wear_alarm, *run.alarm.last().unwrap());
}

/// The false alarm of the updating threshold when the conditions get lighter (3 mm, then
/// 2 mm): the threshold drops at once while the monitored power still decays through the
/// power lag and the filters. A new tool must not alarm.
#[test]
fn updating_threshold_does_not_false_alarm_when_the_depth_shrinks() {
    let mut sc = WearScenario::default();
    sc.cuts.reverse();
    let config = sc.config(false).unwrap();
    let new = sc.run(&NEW_TOOL, &config);
    assert_eq!(new.alarm_at, None, "new tool must not alarm");
    let worn = sc.run(&WORN_TOOL, &config);
    assert!(worn.alarm_at.is_some());
}
