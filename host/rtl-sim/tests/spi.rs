//! The SPI register interface of the board top `tt_fpga_spi` under Icarus, driven bit by bit
//! (`tooltouch_rtl_sim::spi`) and checked against the golden model:
//! - every readable word after a random stimulus equals the model's
//!   (`tooltouch_hdl_gen::spi::spi_word_values`), with SCK at its limit f_clk / 4;
//! - a threshold written over SPI before a stimulus gives exactly the words of the model
//!   configured with that threshold (and not those of the configured one);
//! - the hostile frames: a write to a read-only word, a threshold out of range, a write
//!   while armed, a torn frame, SCK too fast — each refused with its status bit, nothing
//!   written; the status cleared by writing 1s; CONTROL's reset and restore;
//! - the SPI design with no write is the constant design: yosys proves the tied
//!   `tt_frontend` equal to the constant one (`prove_tied_equals_constant`), for the
//!   default, a configuration taking the generators' other branches, and random ones; and
//!   the proof fails on an SPI design whose reset value is off by one.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::PathBuf;
use tooltouch_hdl_gen::spi::{
    spi_registers, spi_word_values, status, Access, SPI_CONTROL_ADDR, SPI_SETTINGS_CRC_ADDR,
    SPI_STATUS_ADDR, SPI_WRITE,
};
use tooltouch_hdl_gen::{Options, Threshold};
use tooltouch_model::measure::config::{ChargeLaw, DecisionMethod};
use tooltouch_model::measure::frontend::{FrontEnd, Pins};
use tooltouch_model::{MeasureConfig, MeasureSettings};
use tooltouch_plant::random::{random_config, random_stimulus};
use tooltouch_rtl_sim::spi::{
    hold_stimulus, prove_tied_equals_constant, SpiBench, SpiCommand, SpiReply,
};

/// SCK half-period at the limit: two FPGA clocks per phase, SCK = f_clk / 4.
const HALF: u32 = 2;
/// Clocks of a random stimulus.
const STIMULUS_CLOCKS: u64 = 6000;

fn work(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("spi")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("work dir");
    dir
}

/// FPGA clocks the bench spends on a command.
fn clocks_of(c: &SpiCommand) -> u64 {
    match *c {
        SpiCommand::Hold { clocks, .. } => clocks,
        SpiCommand::Frame { bits, half, .. } => {
            4 + u64::from(bits) * 2 * u64::from(half) + u64::from(half) + 4
        }
        SpiCommand::Pins => 0,
    }
}

/// The model run through the same clocks and pins as the bench: its outputs at the start
/// of every frame (the test reads only with the pins held long before, so the outputs do
/// not change during a frame).
fn model_at_frames(
    config: &MeasureConfig,
    commands: &[SpiCommand],
) -> Vec<tooltouch_model::MeasureOutputs> {
    let mut fe = FrontEnd::new(config);
    let mut pins = Pins(0);
    let mut at = Vec::new();
    for c in commands {
        if let SpiCommand::Hold { pins: p, .. } = c {
            pins = Pins(*p);
        }
        if matches!(c, SpiCommand::Frame { .. }) {
            at.push(fe.outputs());
        }
        for _ in 0..clocks_of(c) {
            fe.clock(pins);
        }
    }
    at
}

/// Reads of every readable word of the map.
fn read_all(config: &MeasureConfig, half: u32) -> Vec<SpiCommand> {
    spi_registers(config)
        .iter()
        .map(|r| SpiCommand::read(r.addr, half))
        .collect()
}

fn frames(replies: &[SpiReply]) -> Vec<(u8, u8, u32)> {
    replies
        .iter()
        .filter_map(|r| match *r {
            SpiReply::Frame {
                cmd, status, word, ..
            } => Some((cmd, status, word)),
            SpiReply::Pins { .. } => None,
        })
        .collect()
}

/// The pins of the last hold.
fn last_pins(commands: &[SpiCommand]) -> u8 {
    commands
        .iter()
        .rev()
        .find_map(|c| match c {
            SpiCommand::Hold { pins, .. } => Some(*pins),
            _ => None,
        })
        .unwrap_or(0)
}

/// `writes` over SPI while idle, then `stimulus`'s pins, then every word read: the words
/// as the bench read them and as the model with `model_config` gives them.
#[allow(clippy::type_complexity)]
fn run_case(
    bench: &SpiBench,
    name: &str,
    config: &MeasureConfig,
    model_config: &MeasureConfig,
    writes: &[(Threshold, u32)],
    stimulus: &tooltouch_plant::stimulus::Stimulus,
) -> (Vec<(u8, u32)>, Vec<(u8, u32)>, Vec<u8>) {
    let mut commands = vec![SpiCommand::Hold {
        clocks: 16,
        pins: 0,
    }];
    for (t, v) in writes {
        commands.push(SpiCommand::write(t.addr(), *v, HALF));
    }
    commands.push(SpiCommand::Hold { clocks: 8, pins: 0 });
    commands.extend(hold_stimulus(stimulus));
    let pins = last_pins(&commands);
    commands.push(SpiCommand::Hold { clocks: 64, pins });
    let first_read = commands
        .iter()
        .filter(|c| matches!(c, SpiCommand::Frame { .. }))
        .count();
    commands.extend(read_all(config, HALF));
    let replies = bench.run(name, &commands).expect("the bench runs");
    let got = frames(&replies);
    let model = model_at_frames(model_config, &commands);
    let writes_status = (writes.len() as u32) << status::WRITES_SHIFT;
    let expected = spi_word_values(
        config,
        &model[first_read],
        false,
        model_config.settings(),
        writes_status,
    );
    let read: Vec<(u8, u32)> = got[first_read..]
        .iter()
        .map(|(cmd, _, word)| (cmd & !SPI_WRITE, *word))
        .collect();
    let status_bytes = got.iter().map(|(_, s, _)| *s).collect();
    (read, expected, status_bytes)
}

/// A random configuration with the counter's or the density detector's decision.
fn config_with(seed: u64, method: DecisionMethod) -> MeasureConfig {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let c = random_config(&mut rng);
    MeasureSettings {
        method,
        ..*c.settings()
    }
    .validate()
    .expect("a method change keeps the settings valid")
}

#[test]
fn every_register_reads_the_models_value() {
    for (seed, method) in [(1, DecisionMethod::Counter), (2, DecisionMethod::Density)] {
        let config = config_with(seed, method);
        let bench = SpiBench::build(&config, &Options::default(), &work(&format!("read{seed}")))
            .expect("the SPI design builds");
        let mut rng = ChaCha8Rng::seed_from_u64(100 + seed);
        let stimulus = random_stimulus(&mut rng, &config, 1_000_000, STIMULUS_CLOCKS);
        let (read, expected, status_bytes) =
            run_case(&bench, "read", &config, &config, &[], &stimulus);
        assert_eq!(read, expected, "seed {seed}: {:?}", config.settings());
        assert!(status_bytes.iter().all(|s| *s == 0), "{status_bytes:?}");
        // The map shows the configuration hash and the settings CRC of the reset values.
        let word = |addr: u8| read.iter().find(|(a, _)| *a == addr).map(|(_, w)| *w);
        assert_eq!(word(10), Some(config.hash() as u32));
        assert_eq!(
            word(SPI_SETTINGS_CRC_ADDR),
            Some(tooltouch_hdl_gen::spi::settings_crc(
                &tooltouch_hdl_gen::spi::threshold_words(config.settings())
            ))
        );
    }
}

/// A value of `t` other than the configured one that the FPGA accepts.
fn other_value(config: &MeasureConfig, t: Threshold) -> Option<u32> {
    let s = config.settings();
    let v = t.value(s);
    let mut candidates = vec![
        v + 1,
        v.wrapping_sub(1),
        v / 2,
        v * 2,
        t.max(config),
        t.min(config),
    ];
    if t == Threshold::RearmThreshold {
        // Just below the fire threshold: the detector re-arms and fires again sooner.
        candidates.insert(0, s.fire_threshold - 1);
    }
    candidates
        .into_iter()
        .find(|n| *n != v && t.accepts(config, s, *n))
}

#[test]
fn a_threshold_written_over_spi_acts_as_the_model_with_it() {
    let cases = [
        (Threshold::IDef, DecisionMethod::Counter),
        (Threshold::FireThreshold, DecisionMethod::Density),
        (Threshold::RearmThreshold, DecisionMethod::Density),
        (Threshold::ChargeStep, DecisionMethod::Density),
        (Threshold::DischargeStep, DecisionMethod::Density),
        (Threshold::GlitchCycles, DecisionMethod::Counter),
    ];
    for (t, method) in cases {
        // The first seed whose stimulus ends differently with the other value: the test
        // tells the two settings apart.
        let mut checked = false;
        for seed in 0..40u64 {
            let config = config_with(1000 + seed, method);
            let Some(value) = other_value(&config, t) else {
                continue;
            };
            let Some(changed) = t
                .with(config.settings(), value)
                .and_then(|s| s.validate().ok())
            else {
                continue;
            };
            let mut rng = ChaCha8Rng::seed_from_u64(2000 + seed);
            let stimulus = random_stimulus(&mut rng, &config, 1_000_000, STIMULUS_CLOCKS);
            // Pre-screen on the model alone.
            let run = |c: &MeasureConfig| {
                let mut fe = FrontEnd::new(c);
                for p in stimulus.cycles() {
                    fe.clock(p);
                }
                fe.outputs()
            };
            if run(&config) == run(&changed) {
                continue;
            }
            let bench = SpiBench::build(&config, &Options::default(), &work(t.port()))
                .expect("the SPI design builds");
            let (read, expected, _) =
                run_case(&bench, "write", &config, &changed, &[(t, value)], &stimulus);
            assert_eq!(read, expected, "{t:?} = {value} at {:?}", config.settings());
            let (_, unchanged, _) = run_case(&bench, "no_write", &config, &config, &[], &stimulus);
            assert_ne!(read, unchanged, "{t:?}: the write made no difference");
            checked = true;
            break;
        }
        assert!(checked, "{t:?}: no seed tells the two values apart");
    }
}

/// The status word after `commands` (read at the end).
fn status_after(bench: &SpiBench, name: &str, commands: &[SpiCommand]) -> u32 {
    let mut all = commands.to_vec();
    all.push(SpiCommand::Hold {
        clocks: 8,
        pins: last_pins(commands),
    });
    all.push(SpiCommand::read(SPI_STATUS_ADDR, HALF));
    let replies = bench.run(name, &all).expect("the bench runs");
    let f = frames(&replies);
    f.last().expect("the status read").2
}

#[test]
fn hostile_frames_are_refused_with_their_status_bit() {
    let config = MeasureSettings {
        pulses_per_rev: 64,
        i_def: 20,
        charge_bits: 10,
        charge_law: ChargeLaw::Linear {
            charge_step: 8,
            discharge_step: 4,
        },
        fire_threshold: 600,
        rearm_threshold: 100,
        glitch_cycles: 2,
        ..MeasureSettings::default()
    }
    .validate()
    .expect("valid");
    let bench = SpiBench::build(&config, &Options::default(), &work("hostile"))
        .expect("the SPI design builds");
    let idle = SpiCommand::Hold {
        clocks: 16,
        pins: 0,
    };
    let i_def = Threshold::IDef.addr();
    let clear = SpiCommand::write(SPI_STATUS_ADDR, status::ERRORS, HALF);
    let read_i_def = SpiCommand::read(i_def, HALF);
    let cases: Vec<(&str, Vec<SpiCommand>, u32)> = vec![
        // A write to a read-only word (POSITION), to the hash and to an unmapped address.
        (
            "read_only",
            vec![idle, SpiCommand::write(1, 5, HALF)],
            status::READ_ONLY,
        ),
        (
            "hash",
            vec![idle, SpiCommand::write(10, 5, HALF)],
            status::READ_ONLY,
        ),
        (
            "unmapped",
            vec![idle, SpiCommand::write(0x7f, 5, HALF)],
            status::READ_ONLY,
        ),
        // Out of range: i_def = window_pulses, fire <= rearm, rearm >= fire, step 0,
        // glitch beyond its width, a value beyond the register's width.
        (
            "i_def",
            vec![idle, SpiCommand::write(i_def, 64, HALF)],
            status::RANGE,
        ),
        (
            "fire",
            vec![
                idle,
                SpiCommand::write(Threshold::FireThreshold.addr(), 100, HALF),
            ],
            status::RANGE,
        ),
        (
            "rearm",
            vec![
                idle,
                SpiCommand::write(Threshold::RearmThreshold.addr(), 600, HALF),
            ],
            status::RANGE,
        ),
        (
            "step",
            vec![
                idle,
                SpiCommand::write(Threshold::ChargeStep.addr(), 0, HALF),
            ],
            status::RANGE,
        ),
        (
            "glitch",
            vec![
                idle,
                SpiCommand::write(Threshold::GlitchCycles.addr(), 4, HALF),
            ],
            status::RANGE,
        ),
        (
            "wide",
            vec![idle, SpiCommand::write(i_def, 0x1_0000 | 30, HALF)],
            status::RANGE,
        ),
        // While armed (the arm pin high, filtered).
        (
            "armed",
            vec![
                SpiCommand::Hold {
                    clocks: 16,
                    pins: 1,
                },
                SpiCommand::write(i_def, 30, HALF),
            ],
            status::ARMED,
        ),
        // Torn: CS rises after 20 bits, after 39, after 41.
        (
            "torn20",
            vec![
                idle,
                SpiCommand::Frame {
                    cmd: i_def | SPI_WRITE,
                    data: 30,
                    bits: 20,
                    half: HALF,
                },
            ],
            status::TORN,
        ),
        (
            "torn39",
            vec![
                idle,
                SpiCommand::Frame {
                    cmd: i_def | SPI_WRITE,
                    data: 30 << 1,
                    bits: 39,
                    half: HALF,
                },
            ],
            status::TORN,
        ),
        (
            "torn41",
            vec![
                idle,
                SpiCommand::Frame {
                    cmd: i_def | SPI_WRITE,
                    data: 30,
                    bits: 41,
                    half: HALF,
                },
            ],
            status::TORN,
        ),
        // SCK too fast: one FPGA clock per phase.
        (
            "fast",
            vec![idle, SpiCommand::write(i_def, 30, 1)],
            status::SCK_FAST,
        ),
    ];
    for (name, commands, expected) in cases {
        let word = status_after(&bench, name, &commands);
        assert_eq!(word, expected, "{name}: status");
        // Nothing was written: i_def reads the configured value, the status byte of the
        // next frame shows the error, and writing the bits back clears it.
        let mut more = commands.clone();
        more.extend([idle, read_i_def, clear, read_i_def]);
        let replies2 = bench.run(&format!("{name}_after"), &more).expect("runs");
        let f = frames(&replies2);
        let n = f.len();
        assert_eq!(f[n - 3].2, 20, "{name}: i_def was written");
        assert_eq!(u32::from(f[n - 3].1), expected, "{name}: status byte");
        assert_eq!(f[n - 1].1, 0, "{name}: the status was not cleared");
    }

    // An accepted write counts in the status word, reads back, changes the CRC; CONTROL
    // bit 1 restores the configured value.
    let commands = vec![
        idle,
        SpiCommand::write(i_def, 30, HALF),
        SpiCommand::write(Threshold::FireThreshold.addr(), 90, HALF), // below rearm 100
        SpiCommand::write(Threshold::RearmThreshold.addr(), 50, HALF),
        SpiCommand::write(Threshold::FireThreshold.addr(), 90, HALF),
        idle,
        SpiCommand::read(i_def, HALF),
        SpiCommand::read(Threshold::FireThreshold.addr(), HALF),
        SpiCommand::read(SPI_SETTINGS_CRC_ADDR, HALF),
        SpiCommand::read(SPI_STATUS_ADDR, HALF),
        SpiCommand::write(SPI_CONTROL_ADDR, 2, HALF),
        idle,
        SpiCommand::read(i_def, HALF),
        SpiCommand::read(SPI_SETTINGS_CRC_ADDR, HALF),
        SpiCommand::read(SPI_CONTROL_ADDR, HALF),
    ];
    let f = frames(&bench.run("accepted", &commands).expect("runs"));
    let changed = MeasureSettings {
        i_def: 30,
        fire_threshold: 90,
        rearm_threshold: 50,
        ..*config.settings()
    };
    let crc = |s: &MeasureSettings| {
        tooltouch_hdl_gen::spi::settings_crc(&tooltouch_hdl_gen::spi::threshold_words(s))
    };
    assert_eq!(f[4].2, 30);
    assert_eq!(f[5].2, 90);
    assert_eq!(f[6].2, crc(&changed));
    assert_eq!(f[7].2, status::RANGE | 3 << status::WRITES_SHIFT);
    assert_eq!(f[9].2, 20);
    assert_eq!(f[10].2, crc(config.settings()));
    assert_eq!(f[11].2, 0, "CONTROL reads 0");
    assert!(spi_registers(&config)
        .iter()
        .any(|r| r.addr == SPI_CONTROL_ADDR && r.access == Access::WriteOnly));
}

#[test]
fn control_resets_the_kernel_and_the_pins_follow_the_decision() {
    let config = MeasureSettings {
        pulses_per_rev: 16,
        i_def: 2,
        glitch_cycles: 0,
        ..MeasureSettings::default()
    }
    .validate()
    .expect("valid");
    let bench = SpiBench::build(&config, &Options::default(), &work("control"))
        .expect("the SPI design builds");
    // Arm, then contact with FES pulses: the count exceeds i_def = 2 at the third pulse.
    let arm = 1u8;
    let contact = 2u8;
    let fes = 8u8;
    let mut commands = vec![
        SpiCommand::Hold { clocks: 8, pins: 0 },
        SpiCommand::Hold {
            clocks: 8,
            pins: arm,
        },
        SpiCommand::Hold {
            clocks: 8,
            pins: arm | contact,
        },
    ];
    for _ in 0..4 {
        commands.push(SpiCommand::Hold {
            clocks: 4,
            pins: arm | contact | fes,
        });
        commands.push(SpiCommand::Hold {
            clocks: 4,
            pins: arm | contact,
        });
    }
    commands.extend([
        SpiCommand::Hold {
            clocks: 8,
            pins: arm | contact,
        },
        SpiCommand::Pins,
        SpiCommand::read(0, HALF),
        SpiCommand::write(SPI_CONTROL_ADDR, 1, HALF),
        SpiCommand::Hold { clocks: 8, pins: 0 },
        SpiCommand::Pins,
        SpiCommand::read(0, HALF),
    ]);
    let replies = bench.run("control", &commands).expect("runs");
    let pins: Vec<(bool, bool, bool)> = replies
        .iter()
        .filter_map(|r| match *r {
            SpiReply::Pins {
                register_now,
                irq,
                fault,
                ..
            } => Some((register_now, irq, fault)),
            _ => None,
        })
        .collect();
    assert_eq!(pins, vec![(true, true, false), (false, false, false)]);
    let f = frames(&replies);
    assert_eq!(f[0].2 & 0b111, 0b111, "armed, contact, register_now");
    // The power-on state: only the density detector's armed bit (DensityDetector::new).
    assert_eq!(f[2].2, 1 << 4, "power-on state after CONTROL bit 0");
    // The model agrees on the decision.
    let model = model_at_frames(&config, &commands);
    assert!(model[0].register_now);
}

#[test]
fn with_no_write_the_spi_design_is_the_constant_one() {
    let other = MeasureSettings {
        pulses_per_rev: 500,
        i_def: 0,
        window_revs: 3,
        contact_rule: tooltouch_model::measure::config::ContactRule::Sampled,
        charge_bits: 12,
        charge_law: ChargeLaw::Exponential {
            charge_shift: 3,
            discharge_shift: 6,
        },
        fire_threshold: 3000,
        rearm_threshold: 1000,
        glitch_cycles: 0,
        scale_bits: 20,
        method: DecisionMethod::Density,
        ..MeasureSettings::default()
    }
    .validate()
    .expect("valid");
    let mut configs = vec![MeasureConfig::default(), other];
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    configs.extend((0..2).map(|_| random_config(&mut rng)));
    for (i, config) in configs.iter().enumerate() {
        prove_tied_equals_constant(config, &work(&format!("tied{i}")))
            .unwrap_or_else(|e| panic!("{:?}: {e}", config.settings()));
    }
    // The proof sees a difference: the constant design of i_def + 1 against the SPI
    // design of i_def (its configuration hash is the same, only the logic differs).
    let config = MeasureConfig::default();
    let wrong = Options {
        fault: tooltouch_hdl_gen::Fault::IdefPlusOne,
        ..Options::default()
    };
    assert!(
        tooltouch_rtl_sim::spi::prove_tied_equals_constant_with(
            &config,
            &wrong,
            &work("tied_fault")
        )
        .is_err(),
        "an i_def off by one was proven equal"
    );
}
