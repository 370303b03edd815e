//! A hand-worked session of the force kernel on measured force with a PI of
//! K_p = 1/4 %/N, K_i·h = 1/8 %/N (1024 Hz, 64 samples: h = 1/16 s), reference 500 N and a
//! manual override of 100 %: the outputs after each CNC command and control tick.

use super::*;
use crate::force::config::ForceSettings;
use crate::force::control::{ControllerSettings, PiSettings};
use crate::force::sampling::{AdcCodes, ADC_MID};
use crate::units::Fx;

fn kernel() -> ForceKernel {
    let s = ForceSettings {
        sample_hz: 1024,
        samples_per_period: 64,
        force_source: ForceSource::Measured,
        reference: Fx::const_from_int(500),
        manual_override: 100,
        controller: ControllerSettings::Pi(PiSettings {
            kp: Fx::lit("0.25"),
            ki: Fx::const_from_int(2),
            integrator_min: Fx::ZERO,
            integrator_max: Fx::const_from_int(255),
        }),
        ..ForceSettings::default()
    };
    ForceKernel::new(&s.validate().unwrap())
}

/// A period of samples with the dynamometer at `newtons` (1 N per LSB) and the power
/// channel at `power_code`, then the tick.
fn period(k: &mut ForceKernel, newtons: i32, power_code: u16) -> ForceOutputs {
    let codes = AdcCodes {
        force: (ADC_MID + newtons) as u16,
        power: power_code,
        ..AdcCodes::default()
    };
    for _ in 0..4 {
        k.apply(ForceEvent::Sample(codes));
    }
    k.apply(ForceEvent::Tick);
    k.outputs()
}

#[test]
fn a_session_by_hand() {
    // The dynamometer reads 420 N throughout (the low-pass holds it exactly): e = 80 N.
    let mut k = kernel();
    let o = k.outputs();
    assert_eq!(
        (o.override_pct, o.control_enabled, o.saturated),
        (100, false, false)
    );
    // Control off: the manual override stays whatever the force.
    let o = period(&mut k, 420, 0);
    assert_eq!(
        (o.override_pct, o.force_measured),
        (100, Fx::const_from_int(420))
    );
    // On: u = 20 + 100 = 120, I = 110.
    k.apply(ForceEvent::Control(true));
    assert!(k.outputs().control_enabled);
    assert_eq!(period(&mut k, 420, 0).override_pct, 120);
    // Switching on again while on does not restart the PI: u = 20 + 110, I = 120.
    k.apply(ForceEvent::Control(true));
    assert_eq!(period(&mut k, 420, 0).override_pct, 130);
    // Off restores the manual override; on again restarts from it: 20 + 100.
    k.apply(ForceEvent::Control(false));
    assert_eq!(k.outputs().override_pct, 100);
    assert_eq!(period(&mut k, 420, 0).override_pct, 100);
    k.apply(ForceEvent::Control(true));
    assert_eq!(period(&mut k, 420, 0).override_pct, 120);
    // A large error saturates; off clears the flag.
    let o = period(&mut k, -2000, 0);
    assert_eq!((o.override_pct, o.saturated), (255, true));
    k.apply(ForceEvent::Control(false));
    let o = k.outputs();
    assert_eq!(
        (o.override_pct, o.saturated, o.control_enabled),
        (100, false, false)
    );
}

#[test]
fn cnc_commands_by_hand() {
    let mut k = kernel();
    // The default monitor: one set, [P] = 300 + 1800/0.8 = 2550 W (0.8 is inexact in
    // binary: within a few LSBs).
    let allowed = k.outputs().wear_allowed;
    assert!((allowed - Fx::const_from_int(2550)).abs() < Fx::lit("0.00001"));
    k.apply(ForceEvent::Conditions(1));
    k.apply(ForceEvent::Conditions(200));
    assert_eq!(k.outputs().bad_events, 2, "only set 0 exists");
    k.apply(ForceEvent::Conditions(0));
    assert_eq!(k.outputs().bad_events, 2);
    // Power code 1100 at 2.5 W per LSB: 2750 W ≥ [P], the first period sets p̄ as is.
    let o = period(&mut k, 0, 1100);
    assert_eq!(
        (o.wear_power, o.wear_over),
        (Fx::const_from_int(2750), true)
    );
    assert!(!o.wear_alarm, "debounce of 10 periods");
    for _ in 0..9 {
        period(&mut k, 0, 1100);
    }
    assert!(k.outputs().wear_alarm);
    k.apply(ForceEvent::ToolChanged);
    assert!(!k.outputs().wear_alarm);
    // Identification on and off with no period between: nothing identified.
    k.apply(ForceEvent::Identify(true));
    assert!(k.outputs().identifying);
    k.apply(ForceEvent::Identify(false));
    let o = k.outputs();
    assert_eq!((o.identifying, o.identified), (false, false));
    assert_eq!(o.coulomb, Fx::ONE, "the nominal T_fco");
}
