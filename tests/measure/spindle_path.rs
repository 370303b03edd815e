//! The spindle path from its causes (`tooltouch_plant::lathe::SpindlePath`, docs/accuracy.md
//! "The spindle path"), on `examples/spindle_path.toml`: the error-analysis paper's claim
//! that the difference of the spindle's path while machining and while measuring is the
//! main error, and the budget's term for it against 200 simulated measurements per variant
//! (the bound of `budget.rs`: bias within 0.50 µm + 3 standard errors).

use tooltouch_metrology::budget::{predict, Outcome, TermKind, Variant};
use tooltouch_metrology::simulate::{config_of, simulate};
use tooltouch_model::measure::config::DecisionMethod;
use tooltouch_plant::lathe::SpindlePath;
use tooltouch_settings::Settings;

const REPEATS: u32 = 200;
const BIAS_BOUND_UM: f64 = 0.50;

#[test]
fn the_path_difference_is_the_main_error_and_the_budget_predicts_it() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/spindle_path.toml");
    let settings = Settings::load(&path).unwrap();
    let (_, scenario) = settings.resolve().unwrap();
    assert_eq!(scenario.spindle_path, SpindlePath::typical());
    for variant in Variant::ALL
        .into_iter()
        .filter(|v| v.method != DecisionMethod::Density)
    {
        let config = config_of(&settings.measure, variant).unwrap();
        let Outcome::Predicted(p) = predict(&config, &scenario, variant) else {
            panic!("{}: refused", variant.name());
        };
        let term = |name: &str| {
            p.terms
                .iter()
                .find(|t| t.name == name)
                .unwrap_or_else(|| panic!("{}: no term {name}", variant.name()))
                .value_um
        };
        let loads = term("spindle path from its loads");
        for t in p.terms.iter().filter(|t| t.kind == TermKind::Bias) {
            assert!(
                t.value_um.abs() <= loads.abs(),
                "{}: {} {:+.3} µm larger than the path's {loads:+.3} µm",
                variant.name(),
                t.name,
                t.value_um
            );
        }
        let sim = simulate(
            &settings.measure,
            &scenario,
            variant,
            REPEATS,
            scenario.seed,
        )
        .unwrap();
        assert_eq!(sim.decided, REPEATS as usize);
        let bound = BIAS_BOUND_UM + 3.0 * sim.bias_standard_error_um;
        assert!(
            (p.bias_um - sim.bias_um).abs() <= bound,
            "{}: predicted {:+.2} µm, simulated {:+.2} µm (bound {bound:.2})",
            variant.name(),
            p.bias_um,
            sim.bias_um
        );
    }
}

#[test]
fn the_default_lathe_has_the_loads_and_without_them_the_term_is_zero() {
    let (config, mut scenario) = Settings::default().resolve().unwrap();
    assert_eq!(scenario.spindle_path, SpindlePath::typical());
    let term = |scenario: &tooltouch_plant::lathe::LatheScenario| {
        let Outcome::Predicted(p) = predict(&config, scenario, Variant::ALL[0]) else {
            panic!("refused");
        };
        p.terms
            .iter()
            .find(|t| t.name == "spindle path from its loads")
            .unwrap()
            .value_um
    };
    // The counters' diameter reads the offset twice and part of the orbit (docs/accuracy.md).
    let loaded = term(&scenario);
    assert!((5.0..5.3).contains(&loaded), "{loaded:+.3} µm");
    scenario.spindle_path = SpindlePath::none();
    assert_eq!(term(&scenario), 0.0);
}
