//! The force path's outputs as named signals, in the order `check` and the firmware
//! co-simulation compare and report them.

use tooltouch_model::force::kernel::ForceOutputs;

/// Every force output as `(name, value)`; fixed-point values as their raw I32F32 bits.
pub fn force_signals(o: &ForceOutputs) -> [(&'static str, i64); 15] {
    [
        ("override_pct", o.override_pct.into()),
        ("saturated", o.saturated.into()),
        ("fast_estimate", o.fast_estimate.into()),
        ("control_enabled", o.control_enabled.into()),
        ("identifying", o.identifying.into()),
        ("identified", o.identified.into()),
        ("wear_over", o.wear_over.into()),
        ("wear_alarm", o.wear_alarm.into()),
        ("wear_blind", o.wear_blind.into()),
        ("bad_events", o.bad_events.into()),
        ("force_estimate (I32F32 bits)", o.force_estimate.to_bits()),
        ("force_measured (I32F32 bits)", o.force_measured.to_bits()),
        ("wear_power (I32F32 bits)", o.wear_power.to_bits()),
        ("wear_allowed (I32F32 bits)", o.wear_allowed.to_bits()),
        ("coulomb (I32F32 bits)", o.coulomb.to_bits()),
    ]
}
