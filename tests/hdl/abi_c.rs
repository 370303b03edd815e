//! The C ABI (`tooltouch-abi`) from a C program, as a C user builds it: `cc` with the
//! committed header and the static library, the configuration file `tooltouch cosim
//! config` writes; every register, MCU word, event-level output and force output the C
//! program prints equals the Rust model's, and every bad call fails with its status and a
//! message. Also the helpers the DPI and VPI tests share: the library, the tools.

use crate::common::{s, text, tooltouch};
use std::path::{Path, PathBuf};
use std::process::Command;
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceKernel;
use tooltouch_model::force::sampling::AdcCodes;
use tooltouch_model::{FrontEnd, MeasureEvent, Measurement, Pins};
use tooltouch_settings::firmware_config::FirmwareConfig;

/// The repository's root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `host/abi/include`, the committed header's folder.
pub fn include_dir() -> PathBuf {
    root().join("host/abi/include")
}

/// The static library `libtooltouch_abi.a` cargo built beside this test binary (the root
/// package has tooltouch-abi as a dev-dependency, so it is built with the tests).
pub fn static_library() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let deps = exe.parent().expect("the test binary's folder");
    [deps.to_path_buf(), deps.join("..")]
        .into_iter()
        .map(|d| d.join("libtooltouch_abi.a"))
        .find(|p| p.is_file())
        .unwrap_or_else(|| {
            panic!(
                "libtooltouch_abi.a is not in {} (cargo builds it with the root package's tests)",
                deps.display()
            )
        })
}

/// The system libraries a Rust static library needs on Linux.
pub const RUST_STATIC_LIBS: [&str; 3] = ["-lpthread", "-ldl", "-lm"];

/// `tool` on the PATH, or a panic naming `cargo xtask setup`.
pub fn require(tool: &str) {
    if let Err(e) = tooltouch_rtl_sim::runner::find_tool(tool) {
        panic!("{e}");
    }
}

/// Runs `cmd`, panicking with its output if it fails; returns its output.
pub fn run_ok(what: &str, cmd: &mut Command) -> String {
    let o = cmd
        .output()
        .unwrap_or_else(|e| panic!("{what} does not run: {e}"));
    let t = text(&o);
    assert!(o.status.success(), "{what} failed ({}):\n{t}", o.status);
    t
}

/// `tooltouch cosim config --config SETTINGS --out OUT`: the configuration file.
pub fn write_config(settings: &Path, out: &Path) {
    let o = tooltouch(&["cosim", "config", "--config", s(settings), "--out", s(out)]);
    assert!(o.status.success(), "cosim config: {}", text(&o));
}

const SETTINGS: &str = "[measure]\npulses_per_rev = 16\ni_def = 4\nglitch_cycles = 1\n\
                        [force]\ncontroller = \"fuzzy\"\nkp_percent = 80\n";

fn next(state: &mut u64) -> u64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    *state
}

/// As the C program's `pick_pin`.
fn pick_pin(r: u64) -> u8 {
    use tooltouch_model::measure::frontend::pin;
    match r {
        0 => pin::ARM,
        1..=6 => pin::CONTACT,
        7 => pin::INDEX,
        8..=39 => pin::FES,
        40..=51 => pin::SCALE_A,
        _ => pin::SCALE_B,
    }
}

fn hex_words(line: &str) -> Vec<u64> {
    line.split_whitespace()
        .skip(1)
        .map(|w| u64::from_str_radix(w, 16).unwrap_or_else(|_| panic!("not hex: {w} in {line}")))
        .collect()
}

#[test]
fn hdl_abi_a_c_program_gets_the_models_results_bit_for_bit() {
    require("cc");
    let work = tempfile::tempdir().expect("temporary folder");
    let settings = work.path().join("settings.toml");
    std::fs::write(&settings, SETTINGS).unwrap();
    let config_file = work.path().join("config.ttc");
    write_config(&settings, &config_file);
    let exe = work.path().join("abi_test");
    run_ok(
        "cc",
        Command::new("cc")
            .args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-O1", "-I"])
            .arg(include_dir())
            .arg(root().join("tests/hdl/c/abi_test.c"))
            .arg(static_library())
            .args(RUST_STATIC_LIBS)
            .arg("-o")
            .arg(&exe),
    );
    const CYCLES: u64 = 6000;
    const SEED: u64 = 0x9e37_79b9_7f4a_7c15;
    let out = run_ok(
        "abi_test",
        Command::new(&exe)
            .arg(&config_file)
            .arg(CYCLES.to_string())
            .arg(format!("{SEED:x}")),
    );

    let config = FirmwareConfig::load(Some(&settings)).expect("the settings load");
    let measure = config.measure;
    let mut lines = out.lines();
    let first = lines.next().unwrap_or("");
    assert_eq!(
        first,
        format!(
            "hash {:016x} {:016x} {:x}",
            measure.hash(),
            config.force.hash(),
            measure.latency_cycles()
        )
    );

    // Cycle level: the same pins as the C program, every register and MCU word.
    let mut fe = FrontEnd::new(&measure);
    let mut rng = SEED;
    let mut pins = 0u8;
    let mut decided = false;
    let names = tooltouch_hdl_gen::output_fields(&measure);
    for k in 0..CYCLES {
        if next(&mut rng).is_multiple_of(2) {
            pins ^= pick_pin(next(&mut rng) % 64);
        }
        fe.clock(Pins(pins));
        let o = fe.outputs();
        decided |= o.register_now;
        let line = lines
            .next()
            .unwrap_or_else(|| panic!("the C output ends at cycle {k}"));
        let got = hex_words(line);
        assert_eq!(got[..2], [k, u64::from(pins)], "cycle {k}: {line}");
        let want = o.register_bits(&measure);
        for (i, (w, g)) in want.iter().zip(&got[2..17]).enumerate() {
            assert_eq!(
                w, g,
                "cycle {k}: signal {} expected 0x{w:x} got 0x{g:x}",
                names[i].name
            );
        }
        // The MCU words: the register map of hdl-gen, computed from the model's outputs.
        let bits = want;
        let sb = u32::from(measure.settings().scale_bits);
        let sext = |v: u64| (((v as u32) << (32 - sb)) as i32 >> (32 - sb)) as u32 as u64;
        let status = u64::from(o.armed)
            | u64::from(o.contact) << 1
            | u64::from(o.register_now) << 2
            | u64::from(o.first_contact) << 3
            | u64::from(o.density_armed) << 4
            | u64::from(o.density_fired) << 5
            | u64::from(o.confirmed) << 6
            | u64::from(o.faults) << 8;
        let hash = measure.hash();
        let mut mcu = vec![
            status,
            sext(bits[6]),
            sext(bits[3]),
            sext(bits[5]),
            bits[8],
            bits[9],
            bits[10],
            0,
            0,
            bits[7],
            hash & 0xffff_ffff,
            hash >> 32,
        ];
        mcu.resize(16, 0);
        mcu.extend([u64::from(o.revolutions), u64::from(o.pulses)]);
        for (a, (w, g)) in mcu.iter().zip(&got[17..]).enumerate() {
            let name = match tooltouch_hdl_gen::MCU_REGISTERS.get(a) {
                Some(r) => r.name,
                None if a < 16 => "unmapped",
                None => "a diagnostic counter, --mcu-diagnostics",
            };
            assert_eq!(
                w, g,
                "cycle {k}: MCU word {a} ({name}) expected 0x{w:x} got 0x{g:x}"
            );
        }
    }
    assert!(
        decided,
        "the random pins never led to a decision: a weak test"
    );

    // Event level.
    let mut m = Measurement::new(&measure);
    let events = [
        MeasureEvent::Arm(true),
        MeasureEvent::Contact(true),
        MeasureEvent::Fes,
        MeasureEvent::Scale { a: true, b: false },
        MeasureEvent::Scale { a: true, b: true },
        MeasureEvent::Index,
        MeasureEvent::Fes,
        MeasureEvent::Contact(false),
        MeasureEvent::PresetPulses(u32::MAX),
        MeasureEvent::Fes,
        MeasureEvent::Arm(false),
    ];
    for (i, e) in events.iter().enumerate() {
        m.apply(*e);
        let line = lines.next().expect("an event line");
        let got = hex_words(line);
        assert_eq!(got[0], i as u64, "{line}");
        assert_eq!(
            got[1..],
            m.outputs().register_bits(&measure),
            "event {i} ({e:?})"
        );
    }

    // Force kernel.
    let mut kernel = ForceKernel::new(&config.force);
    for period in 0u16..6 {
        for s in 0u16..50 {
            kernel.apply(ForceEvent::Sample(AdcCodes {
                speed: 1200 + 10 * period,
                power: 900 + 40 * period + s,
                force: 2300 + 5 * s,
                volts: [2100, 2000, 2048],
                amps: [2060, 2040],
            }));
        }
        kernel.apply(match period {
            1 => ForceEvent::Control(true),
            5 => ForceEvent::Conditions(200),
            _ => ForceEvent::Tick,
        });
        let o = kernel.outputs();
        let flags = u64::from(o.saturated)
            | u64::from(o.fast_estimate) << 1
            | u64::from(o.control_enabled) << 2
            | u64::from(o.identifying) << 3
            | u64::from(o.identified) << 4
            | u64::from(o.wear_over) << 5
            | u64::from(o.wear_alarm) << 6;
        let want: Vec<u64> = [
            u64::from(period),
            u64::from(o.override_pct),
            flags,
            u64::from(o.bad_events),
        ]
        .into_iter()
        .chain(
            [
                o.force_estimate,
                o.force_measured,
                o.wear_power,
                o.wear_allowed,
                o.coulomb,
            ]
            .map(|v| v.to_bits() as u64),
        )
        .collect();
        let line = lines.next().expect("a force line");
        assert_eq!(hex_words(line), want, "force period {period}: {line}");
    }
    assert_eq!(lines.next(), Some("errors ok"));
    assert_eq!(lines.next(), None);
}
