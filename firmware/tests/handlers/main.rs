//! Host tests of the interrupt handlers (`tooltouch_firmware::handlers`): event streams
//! replayed through the handlers on a simulated board ([`sim`]) in each board's interrupt
//! order (`interrupts::QEMU`, `interrupts::NUCLEO`), checked after every burst of events
//! against the golden model's event level stepped one event at a time.
//!
//! The QEMU co-simulation (the root's `tests/firmware/cosim.rs`) runs the same handlers
//! on an emulated Cortex-M3, one event at a time and in QEMU's interrupt order only; here
//! events also arrive together, so the order in which the NVIC takes them matters, and
//! the Nucleo's order is tested too. Random streams are drawn by proptest from a fixed
//! seed (set `PROPTEST_RNG_SEED` to explore, `PROPTEST_CASES` for more cases).
//!
//! Run from inside firmware/ on the host: `cargo test --target <host triple>
//! --no-default-features` (`cargo xtask test` does).

//! The lathe player's schedule (`tooltouch_firmware::player`) is tested here too
//! ([`player`]), in the same test binary.

mod player;
mod sim;
mod streams;

use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use sim::{Action, Burst, ForceSim, Sim, SimBoard};
use tooltouch_firmware::handlers::{self, SampleQueue, FES_FOLD_LIMIT};
use tooltouch_firmware::interrupts::{self, MeasureInterrupts};
use tooltouch_firmware::model::force::config::ForceSettings;
use tooltouch_firmware::model::force::events::ForceEvent;
use tooltouch_firmware::model::force::kernel::ForceKernel;
use tooltouch_firmware::model::force::sampling::AdcCodes;
use tooltouch_firmware::model::measure::config::{ContactRule, DecisionMethod};
use tooltouch_firmware::model::{
    fault, MeasureChecks, MeasureConfig, MeasureEvent, MeasureSettings, Measurement,
};

/// Every board, by name, with its measurement tasks' IRQ numbers.
const BOARDS: [(&str, MeasureInterrupts); 2] =
    [("qemu", interrupts::QEMU), ("nucleo", interrupts::NUCLEO)];

/// proptest's configuration: its defaults and environment, but a fixed seed unless
/// `PROPTEST_RNG_SEED` is set (so a CI run is repeatable), and no regression files.
fn proptest_config() -> ProptestConfig {
    let mut config = ProptestConfig::default();
    if config.rng_seed == RngSeed::Random {
        config.rng_seed = RngSeed::Fixed(0x7007_70c4);
    }
    config.failure_persistence = None;
    config
}

/// The pulse counter deciding when a window holds more than `i_def` contact pulses
/// (16 pulses per revolution, sampled contact). The revolution check is off: these
/// streams run many revolutions' pulses without an index, whose `index_missing` pulse
/// the compare would fire on too ([`revolution_config`] tests that).
fn counter_config(i_def: u32) -> MeasureConfig {
    MeasureSettings {
        pulses_per_rev: 16,
        i_def,
        method: DecisionMethod::Counter,
        contact_rule: ContactRule::Sampled,
        checks: MeasureChecks {
            revolutions: false,
            ..Default::default()
        },
        ..Default::default()
    }
    .validate()
    .unwrap_or_else(|e| panic!("{e}"))
}

/// [`counter_config`] with the revolution check on (16 ± 2 pulses per revolution).
fn revolution_config() -> MeasureConfig {
    MeasureSettings {
        pulses_per_rev: 16,
        i_def: 8,
        method: DecisionMethod::Counter,
        contact_rule: ContactRule::Sampled,
        ..Default::default()
    }
    .validate()
    .unwrap_or_else(|e| panic!("{e}"))
}

/// How many more FES pulses the model needs to raise "register now" (at most 1000).
fn pulses_to_decision(model: &Measurement) -> u32 {
    let mut m = *model;
    (1..=1000)
        .find(|_| m.on_fes_raises())
        .unwrap_or_else(|| panic!("no decision within 1000 pulses"))
}

/// The interrupts the NVIC took, in order.
fn taken(actions: &[Action]) -> Vec<u16> {
    actions
        .iter()
        .filter_map(|a| match a {
            Action::Taken(irq) => Some(*irq),
            _ => None,
        })
        .collect()
}

proptest! {
    #![proptest_config(proptest_config())]

    /// Random streams through QEMU's interrupt order: the handlers agree with the model.
    #[test]
    fn random_streams_agree_with_the_model_in_qemu_order(
        config in streams::config(),
        count in streams::start_count(),
        bursts in streams::stream(200),
    ) {
        Sim::new("qemu", interrupts::QEMU, &config, count).replay_all(&bursts);
    }

    /// The same streams through the Nucleo's interrupt order (the FES compare after the
    /// scale edge).
    #[test]
    fn random_streams_agree_with_the_model_in_nucleo_order(
        config in streams::config(),
        count in streams::start_count(),
        bursts in streams::stream(200),
    ) {
        Sim::new("nucleo", interrupts::NUCLEO, &config, count).replay_all(&bursts);
    }

    /// The force path: the control period applies the samples the ADC task queued, in
    /// order, then its tick, and drives the feed override and the wear alarm; a CNC
    /// command applies its event. Every step as the model's.
    #[test]
    fn force_handlers_agree_with_the_model(
        periods in prop::collection::vec(
            (
                prop::collection::vec(any::<[u16; 8]>(), 0..=60),
                prop::option::of(prop_oneof![
                    any::<bool>().prop_map(ForceEvent::Identify),
                    any::<bool>().prop_map(ForceEvent::Control),
                    Just(ForceEvent::Conditions(0)),
                    Just(ForceEvent::ToolChanged),
                ]),
            ),
            1..=8,
        ),
    ) {
        let config = ForceSettings::default().validate().unwrap_or_else(|e| panic!("{e:?}"));
        let mut kernel = ForceKernel::new(&config);
        let mut model = kernel;
        let mut queue = SampleQueue::new();
        let (mut samples_in, mut samples_out) = queue.split();
        let board = ForceSim::new();
        for (samples, command) in periods {
            if let Some(event) = command {
                board.set_command(event);
                handlers::force_command::<SimBoard>(&mut kernel);
                model.apply(event);
                prop_assert_eq!(kernel, model);
            }
            for raw in samples {
                let code = |i: usize| raw[i] & 0x0fff;
                let codes = AdcCodes {
                    speed: code(0),
                    power: code(1),
                    force: code(2),
                    volts: [code(3), code(4), code(5)],
                    amps: [code(6), code(7)],
                };
                board.set_adc(codes);
                prop_assert!(handlers::adc_sample::<SimBoard>(&mut samples_in));
                model.apply(ForceEvent::Sample(codes));
            }
            handlers::control_period::<SimBoard>(&mut kernel, &mut samples_out);
            model.apply(ForceEvent::Tick);
            prop_assert_eq!(kernel, model);
            let o = model.outputs();
            prop_assert_eq!(board.outputs(), (o.override_pct, o.wear_alarm));
        }
    }
}

/// The compare is set at the pulse that decides: that pulse, and no earlier one, raises
/// the compare interrupt and "register now".
#[test]
fn the_compare_interrupt_fires_at_the_deciding_pulse() {
    for (name, irqs) in BOARDS {
        let mut sim = Sim::new(name, irqs, &counter_config(8), 1000);
        sim.replay(Burst::edge(MeasureEvent::Arm(true)).observed());
        sim.replay(Burst::edge(MeasureEvent::Contact(true)).observed());
        let deciding = pulses_to_decision(sim.model());
        assert_eq!(
            deciding, 9,
            "{name}: the 9th contact pulse exceeds i_def = 8"
        );
        assert_eq!(sim.compare(), sim.count().wrapping_add(deciding), "{name}");
        sim.take_actions();
        for k in 1..=deciding {
            sim.replay(Burst::pulses(1));
            let fired = taken(&sim.take_actions()).contains(&irqs.fes_compare);
            assert_eq!(
                fired,
                k == deciding,
                "{name}: compare interrupt at pulse {k}"
            );
            assert_eq!(
                sim.register_now(),
                k == deciding,
                "{name}: pin at pulse {k}"
            );
        }
        sim.replay(Burst::pulses(0).observed());
    }
}

/// A deciding pulse counted before a scale edge, both pending at once: the decision
/// latches the position from before the edge, as the model's same-clock order has it,
/// whichever interrupt the board takes first (QEMU: the compare; the Nucleo: the scale,
/// whose task therefore folds first).
#[test]
fn a_deciding_pulse_pending_with_a_scale_edge_latches_the_position_before_it() {
    for (name, irqs) in BOARDS {
        let mut sim = Sim::new(name, irqs, &counter_config(8), 0);
        sim.replay(Burst::edge(MeasureEvent::Arm(true)));
        sim.replay(Burst::edge(MeasureEvent::Scale { a: true, b: false }));
        sim.replay(Burst::edge(MeasureEvent::Contact(true)).observed());
        let deciding = pulses_to_decision(sim.model());
        sim.take_actions();
        sim.replay(
            Burst::edge(MeasureEvent::Scale { a: true, b: true })
                .after_pulses(deciding)
                .observed(),
        );
        let o = sim.model().outputs();
        assert!(o.register_now, "{name}");
        assert_eq!((o.decision_position, o.position), (1, 2), "{name}");
        let first = if irqs.fes_compare < irqs.scale {
            [irqs.fes_compare, irqs.scale]
        } else {
            [irqs.scale, irqs.fes_compare]
        };
        assert_eq!(taken(&sim.take_actions())[..2], first, "{name}: NVIC order");
    }
}

/// The hardware counter wraps at 2^32 like the kernel's count: the fold limit and the
/// deciding pulse are found across the wrap.
#[test]
fn the_fes_counter_wraps_past_2_pow_32() {
    for (name, irqs) in BOARDS {
        let start = u32::MAX - 4;
        let mut sim = Sim::new(name, irqs, &counter_config(8), start);
        assert_eq!(sim.compare(), start.wrapping_add(FES_FOLD_LIMIT), "{name}");
        sim.replay(Burst::pulses(FES_FOLD_LIMIT - 1));
        assert!(
            !taken(&sim.take_actions()).contains(&irqs.fes_compare),
            "{name}"
        );
        sim.replay(Burst::pulses(1).observed());
        assert!(
            taken(&sim.take_actions()).contains(&irqs.fes_compare),
            "{name}"
        );

        let mut sim = Sim::new(name, irqs, &counter_config(8), start);
        sim.replay(Burst::edge(MeasureEvent::Arm(true)));
        sim.replay(Burst::edge(MeasureEvent::Contact(true)));
        let actions = sim.take_actions();
        let wrapped = actions.iter().any(
            |a| matches!(a, Action::SetCompare { at, count } if at < count && *count == start),
        );
        assert!(
            wrapped,
            "{name}: the compare value past the wrap: {actions:?}"
        );
        for _ in 0..9 {
            sim.replay(Burst::pulses(1));
        }
        assert!(sim.register_now(), "{name}");
        assert_eq!(sim.count(), 4, "{name}");
        sim.replay(Burst::pulses(0).observed());
        assert_eq!(sim.model().outputs().pulses, 9, "{name}");
    }
}

/// Pulses that arrive in a handler after its fold but before it writes the compare can
/// reach the new compare value before it is set: the timer would not match it until the
/// count wraps, so the handler pends the compare interrupt by hand.
#[test]
fn a_compare_value_the_count_has_reached_is_pended_by_hand() {
    for (name, irqs) in BOARDS {
        for (in_handler, hand_pended) in [(8, false), (9, true), (12, true), (64, true), (70, true)]
        {
            let mut sim = Sim::new(name, irqs, &counter_config(8), 40);
            sim.replay(Burst::edge(MeasureEvent::Arm(true)));
            sim.take_actions();
            // The contact's task sets the compare 9 pulses on (the deciding pulse).
            sim.replay(
                Burst::edge(MeasureEvent::Contact(true))
                    .with_pulses_in_handler(in_handler)
                    .observed(),
            );
            let actions = sim.take_actions();
            assert_eq!(
                actions.contains(&Action::HandPend),
                hand_pended,
                "{name}, {in_handler} pulses in the handler: {actions:?}"
            );
            assert_eq!(sim.register_now(), hand_pended, "{name}, {in_handler}");
        }
    }
}

/// With no decision possible (disarmed, or armed without contact), the compare interrupt
/// fires every [`FES_FOLD_LIMIT`] pulses and at no other pulse.
#[test]
fn the_compare_interrupt_fires_every_fold_limit_pulses() {
    for (name, irqs) in BOARDS {
        for armed in [false, true] {
            let mut sim = Sim::new(name, irqs, &counter_config(8), 7);
            if armed {
                sim.replay(Burst::edge(MeasureEvent::Arm(true)));
            }
            sim.take_actions();
            for k in 1..=3 * FES_FOLD_LIMIT {
                sim.replay(Burst::pulses(1));
                let fired = taken(&sim.take_actions()).contains(&irqs.fes_compare);
                assert_eq!(
                    fired,
                    k % FES_FOLD_LIMIT == 0,
                    "{name}, armed {armed}: pulse {k}"
                );
            }
            sim.replay(Burst::pulses(0).observed());
        }
    }
}

/// Armed without an index, the compare interrupt fires on the pulse that raises
/// `index_missing` (`pulses_per_rev + pulse_tolerance + 1` = 19 since the arm), so the
/// fault output rises on that pulse, not at the next fold; then every
/// [`FES_FOLD_LIMIT`] pulses again.
#[test]
fn the_compare_interrupt_fires_on_the_pulse_raising_index_missing() {
    for (name, irqs) in BOARDS {
        let mut sim = Sim::new(name, irqs, &revolution_config(), 5);
        sim.replay(Burst::edge(MeasureEvent::Arm(true)));
        sim.take_actions();
        for k in 1..=19 + FES_FOLD_LIMIT {
            sim.replay(Burst::pulses(1));
            let fired = taken(&sim.take_actions()).contains(&irqs.fes_compare);
            assert_eq!(
                fired,
                k == 19 || k == 19 + FES_FOLD_LIMIT,
                "{name}: pulse {k}"
            );
            // The burst's check holds the fault output to the model's faults.
            assert_eq!(
                sim.model().outputs().faults & fault::INDEX_MISSING != 0,
                k >= 19,
                "{name}: pulse {k}"
            );
        }
        sim.replay(Burst::pulses(0).observed());
    }
}

/// A scale edge with no deciding pulse counted does not fold (scale edges change no count,
/// and they are the most frequent edge): its task drives nothing and leaves the compare
/// where the last fold set it, so the fold-limit interrupt still fires [`FES_FOLD_LIMIT`]
/// pulses after that fold, not after the scale edge.
#[test]
fn a_scale_edge_folds_only_when_a_counted_pulse_may_decide() {
    for (name, irqs) in BOARDS {
        // Armed without contact: no pulse can decide, the compare is the fold limit.
        let mut sim = Sim::new(name, irqs, &counter_config(8), 7);
        sim.replay(Burst::edge(MeasureEvent::Arm(true)));
        let limit = sim.count().wrapping_add(FES_FOLD_LIMIT);
        assert_eq!(sim.compare(), limit, "{name}");
        sim.take_actions();
        sim.replay(Burst::edge(MeasureEvent::Scale { a: true, b: false }).after_pulses(10));
        assert_eq!(
            sim.take_actions(),
            [Action::Taken(irqs.scale)],
            "{name}: the scale task only steps the decoder"
        );
        assert_eq!(sim.compare(), limit, "{name}: the compare is not moved");
        for k in 11..=FES_FOLD_LIMIT {
            sim.replay(Burst::pulses(1));
            let fired = taken(&sim.take_actions()).contains(&irqs.fes_compare);
            assert_eq!(
                fired,
                k == FES_FOLD_LIMIT,
                "{name}: pulse {k} since the fold"
            );
        }
        sim.replay(Burst::pulses(0).observed());
        assert_eq!(sim.model().outputs().position, 1, "{name}");
    }
}

/// The index closes the counting window after the pulses counted before it, whether they
/// came in the same burst or earlier without an interrupt.
#[test]
fn the_index_folds_the_pulses_counted_before_it() {
    for (name, irqs) in BOARDS {
        let mut sim = Sim::new(name, irqs, &counter_config(15), 0);
        sim.replay(Burst::edge(MeasureEvent::Arm(true)));
        sim.replay(Burst::edge(MeasureEvent::Contact(true)));
        sim.replay(Burst::edge(MeasureEvent::Index).after_pulses(5).observed());
        assert_eq!(sim.model().outputs().last_window_count, 5, "{name}");
        sim.replay(Burst::pulses(3));
        sim.replay(Burst::edge(MeasureEvent::Index).observed());
        let o = sim.model().outputs();
        assert_eq!((o.last_window_count, o.revolutions), (3, 2), "{name}");
    }
}

/// The co-simulation's pulse-count preset (QEMU only) lets the kernel's count wrap.
#[test]
fn the_pulse_count_preset_wraps_the_kernels_count() {
    for (name, irqs) in BOARDS {
        if irqs.preset_pulses.is_none() {
            continue;
        }
        let mut sim = Sim::new(name, irqs, &counter_config(8), 0);
        sim.replay(Burst::edge(MeasureEvent::Arm(true)));
        sim.replay(Burst::edge(MeasureEvent::PresetPulses(u32::MAX - 1)).after_pulses(2));
        sim.replay(Burst::pulses(3).observed());
        assert_eq!(sim.model().outputs().pulses, 1, "{name}");
    }
}

/// The boards' tables: one priority's worth of distinct IRQ numbers, observe last (idle
/// pends it, and it must follow every edge pending with it).
#[test]
fn every_board_has_distinct_measurement_interrupts_with_observe_last() {
    for (name, irqs) in BOARDS {
        let mut all = vec![
            irqs.arm,
            irqs.contact,
            irqs.index,
            irqs.fes_compare,
            irqs.scale,
        ];
        all.extend(irqs.preset_pulses);
        assert!(all.iter().all(|&irq| irq < irqs.observe), "{name}");
        all.push(irqs.observe);
        let n = all.len();
        all.sort_unstable();
        all.dedup();
        assert_eq!(all.len(), n, "{name}: an IRQ number twice");
    }
}
