//! A small campaign on a fast lathe: each fault flagged, the clean lathe silent and right,
//! shards merged into the whole.

use super::*;
use tooltouch_plant::lathe::SpindlePath;

/// A fast verification lathe (1 MHz, 4800 rpm: FES pulses long enough for the default
/// glitch filter), no path loads.
fn fast_lathe() -> LatheScenario {
    let mut s = LatheScenario {
        clock_hz: 1_000_000,
        rpm: 4800.0,
        spindle_path: SpindlePath::none(),
        ..Default::default()
    };
    s.cycle.clearance_um = 3.0;
    s.cycle.z_dwell_ms = 0.2;
    s.cycle.retract_mm_per_s = 2.0;
    s
}

fn spec() -> CampaignSpec {
    CampaignSpec {
        kinds: vec![
            FaultKind::FesLost,
            FaultKind::CoolantBridge,
            FaultKind::BrokenContact,
        ],
        levels: vec![1.0 / 3.0],
        methods: vec![DecisionMethod::Counter],
        measurements: 4,
    }
}

#[test]
fn every_faulted_measurement_is_flagged_and_the_clean_ones_are_right() {
    let r = run(
        &spec(),
        &fast_lathe(),
        &MeasureSettings::default(),
        None,
        &|| {},
    )
    .unwrap();
    assert_eq!(r.cells_total, 3);
    assert_eq!(r.clean.len(), 1);
    let clean = &r.clean[0];
    assert_eq!(clean.counts.silent_harmless, 4, "{clean:?}");
    // The budget refuses this lathe's regime (a 3 µm clearance), so the σ is the clean run's.
    assert!(
        clean.tolerance_um > 0.0 && clean.tolerance_um < 5.0,
        "{clean:?}"
    );
    for c in &r.cells {
        assert_eq!(c.counts.total(), 4);
        // A third of the FES pulses lost, a bridge at a third of the arms (the others
        // clean and right), the contact wire broken.
        assert_eq!(c.counts.silent_wrong, 0, "{c:?}");
        assert_eq!(c.counts.no_decision_unflagged, 0, "{c:?}");
        match c.key.kind {
            FaultKind::CoolantBridge => assert!(c.counts.flagged >= 1, "{c:?}"),
            _ => assert_eq!(c.counts.flagged, 4, "{c:?}"),
        }
    }
}

#[test]
fn shards_merge_into_the_whole_campaign() {
    let base = fast_lathe();
    let m = MeasureSettings::default();
    let whole = run(&spec(), &base, &m, None, &|| {}).unwrap();
    let parts: Vec<CampaignResults> = (0..2)
        .map(|k| run(&spec(), &base, &m, Some((k, 2)), &|| {}).unwrap())
        .collect();
    assert_eq!(merge(&parts).unwrap(), whole);
    assert!(merge(&parts[..1])
        .unwrap_err()
        .to_string()
        .contains("slice 1/2 is missing"));
    assert!(merge(std::slice::from_ref(&whole)).is_err());
}

#[test]
fn bad_specs_are_named() {
    let mut s = spec();
    s.measurements = 0;
    assert!(s
        .validate()
        .unwrap_err()
        .to_string()
        .contains("measurements"));
    let mut s = spec();
    s.levels = vec![1.5];
    let e = s.validate().unwrap_err().to_string();
    assert!(e.contains("levels") && e.contains("at most 1"), "{e}");
    let mut s = spec();
    s.methods.clear();
    assert!(s.validate().unwrap_err().to_string().contains("methods"));
    assert_eq!(FaultKind::named("chips"), Some(FaultKind::Chips));
    assert_eq!(FaultKind::named("gremlins"), None);
}
