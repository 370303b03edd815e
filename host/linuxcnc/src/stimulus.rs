//! The golden stimulus of the HAL test: one row of component input pins per servo period
//! ([`PeriodInputs`]), from a seed.
//!
//! - **Measurement**: the spindle's FES and index pulses as hardware counts (1024 ppr by
//!   default; 800, 3 000 and 12 000 rpm in turn, 13.7 to 204.8 pulses per 1 ms period, plus a
//!   slow square wave on the `fes` bit pin), and measurement cycles: the cross slide feeds
//!   toward the part, the contact line chatters more and more as the tool reaches the
//!   surface (a random level per period, its probability rising over a band of counts),
//!   the CNC raises arm and drops it after a fixed time, then retracts. Not a physical model
//!   of the contact (the lathe simulator is, at the FPGA's clock): a servo-rate stream that
//!   exercises every path of the component.
//! - **Force path**: the spindle-drive plant of the co-simulation ([`random_plant`]) closed
//!   around the golden force kernel one ADC sample per period ([`ClosedLoop`]), with the CNC
//!   timeline as pin levels: identification, condition sets (some out of range), force
//!   control during the cut, a tool change. The recorded codes are what the plant produces
//!   when the device's feed override equals the model's.

use super::period::{adc_pins, PeriodInputs};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tooltouch_model::force::config::ForceConfig;
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::MeasureConfig;
use tooltouch_plant::drive::scenario::ClosedLoop;
use tooltouch_plant::drive::Plant;
use tooltouch_stimuli::force_scenario::random_plant;

/// Spindle speeds of the stimulus' three segments, rpm.
pub const SEGMENT_RPM: [f64; 3] = [800.0, 3000.0, 12_000.0];

/// Periods of one measurement cycle: approach, arm, retract.
pub const CYCLE_PERIODS: u32 = 400;

/// The stimulus: `periods` rows for the two configurations, drawn from `seed`.
pub fn golden_stimulus(
    measure: &MeasureConfig,
    force: &ForceConfig,
    periods: u32,
    seed: u64,
) -> Vec<PeriodInputs> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let ppr = f64::from(measure.settings().pulses_per_rev);
    let s = force.settings();
    let sample_hz = f64::from(s.sample_hz.max(1));
    let setup = random_plant(&mut rng);
    let plant = Plant::new(
        setup.drive,
        setup.process,
        tooltouch_plant::drive::DepthProfile {
            step_at: 0.7 * f64::from(periods) / sample_hz,
            ..setup.depth
        },
        &s.scales,
        sample_hz,
        setup.speed,
        rng.random(),
    );
    let mut lp = ClosedLoop::new(force, plant);
    let set_count = u32::from(s.wear.set_count);
    let at = |f: f64| (f * f64::from(periods)) as u32;
    let mut rows = Vec::with_capacity(periods as usize);
    let mut row = PeriodInputs {
        // Hardware counters start anywhere: the first period is the baseline.
        fes_counts: rng.random_range(-1000..1000),
        index_counts: rng.random_range(0..10),
        scale_counts: rng.random_range(-5000..5000),
        ..Default::default()
    };
    let mut spindle = 0.0f64; // FES pulses since the start, fractional
    let (fes0, index0) = (row.fes_counts, row.index_counts);
    let home = row.scale_counts;
    let mut surface = home + 300;
    for k in 0..periods {
        // Measurement: the spindle's counts.
        let rpm = SEGMENT_RPM[(k as usize * SEGMENT_RPM.len()) / periods as usize];
        spindle += ppr * rpm / 60.0 / sample_hz;
        let pulses = spindle.floor() as i64;
        row.fes_counts = fes0.wrapping_add(pulses as i32);
        row.index_counts = index0.wrapping_add((pulses / ppr as i64) as i32);
        row.fes = (k / 7) % 2 == 1;
        // A measurement cycle every CYCLE_PERIODS: approach 2 counts a period, arm from
        // period 20 to 300, retract from 300.
        let phase = k % CYCLE_PERIODS;
        if phase == 0 {
            surface = home + rng.random_range(200..400);
            row.scale_counts = home;
        }
        if phase < 300 {
            row.scale_counts = row.scale_counts.wrapping_add(rng.random_range(1..=3));
        } else {
            row.scale_counts = row
                .scale_counts
                .wrapping_sub(row.scale_counts.wrapping_sub(home).min(40));
        }
        row.arm = (20..300).contains(&phase);
        let depth = row.scale_counts.wrapping_sub(surface);
        let p_contact = (f64::from(depth) / 60.0).clamp(0.0, 0.95);
        row.contact = phase < 300 && rng.random_bool(p_contact);
        // Force path: the CNC's timeline as pin levels, then one sample (and the tick).
        let before = row;
        row.identify = (at(0.05)..at(0.25)).contains(&k);
        row.force_control = (at(0.38)..at(0.92)).contains(&k);
        if k == at(0.26) {
            row.conditions = 0;
        } else if k > at(0.38) && rng.random_bool(0.01) {
            row.conditions = rng.random_range(0..set_count + 2);
        }
        row.tool_changed = (at(0.8)..at(0.8) + 3).contains(&k);
        if row.identify != before.identify {
            lp.command(ForceEvent::Identify(row.identify));
        }
        if row.force_control != before.force_control {
            lp.command(ForceEvent::Control(row.force_control));
        }
        if row.conditions != before.conditions {
            lp.command(ForceEvent::Conditions(row.conditions.min(255) as u8));
        }
        if row.tool_changed && !before.tool_changed {
            lp.command(ForceEvent::ToolChanged);
        }
        row.adc = adc_pins(&lp.step(|c| c));
        rows.push(row);
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::super::period::PeriodKernel;
    use super::*;
    use tooltouch_model::force::config::ForceSettings;
    use tooltouch_model::MeasureSettings;

    #[test]
    fn the_stimulus_decides_and_drives_the_force_path() {
        let m = MeasureSettings::default().validate().unwrap();
        let f = ForceSettings::default().validate().unwrap();
        let rows = golden_stimulus(&m, &f, 3000, 7);
        let mut k = PeriodKernel::new(&m, &f);
        let (mut decisions, mut last, mut controlled) = (0, false, 0);
        let mut max_fes = 0;
        for (i, r) in rows.iter().enumerate() {
            let (mo, fo) = k.step(r);
            decisions += usize::from(mo.register_now && !last);
            last = mo.register_now;
            controlled += usize::from(fo.control_enabled);
            if i > 0 {
                max_fes = max_fes.max(r.fes_counts.wrapping_sub(rows[i - 1].fes_counts));
            }
        }
        assert!(decisions >= 5, "{decisions} decisions in 3000 periods");
        assert!(controlled > 1000);
        assert_eq!(max_fes, 205); // 1024 ppr at 12 000 rpm, 1 ms periods
        assert_eq!(k.health().overruns, 0);
    }
}
