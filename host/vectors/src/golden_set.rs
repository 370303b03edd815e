//! The golden response to one stimulus as every file a device under test is checked
//! with: the golden VCD (inputs and outputs, docs/CONTRACT.md), `stim.hex` + `expect.hex`
//! for the generated testbench, `events.ttv` + `expected_outputs.ttv` for the firmware, and
//! `summary.json`. `tooltouch vectors` writes it; `tooltouch hdl --vectors` writes its
//! testbench part.
//!
//! The measurement path comes from pins (a cycle-level stimulus): the cycle model makes
//! the VCD and the hex vectors, the events it acted on make the event-level files, so all
//! of them describe the same run. An input event stream is turned into pins first when it
//! has measurement events ([`super::stimulus_file::pins_from_events`]); its force events
//! (ADC samples and CNC commands) have no pins and give event-level files only.

use super::binary::{self, Input, InputStream, Output};
use super::vcd;
use crate::hex::{self, Vectors};
use crate::output::OutputFolder;
use anyhow::Context;
use std::io::Write;
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceKernel;
use tooltouch_model::{Faults, MeasureConfig, MeasureEvent, MeasureOutputs, Measurement};
use tooltouch_plant::stimulus::Stimulus;

/// The golden VCD's file name.
pub const GOLDEN_VCD: &str = "golden.vcd";
/// The golden trace's file name as FST ([`GoldenFormat::Fst`]).
pub const GOLDEN_FST: &str = "golden.fst";

/// The file format of the golden trace.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GoldenFormat {
    /// A VCD ([`vcd::write_golden`]).
    #[default]
    Vcd,
    /// An FST ([`crate::fst::write_golden_fst`]): the same signals and times, a file a few
    /// times smaller, which `check` reads as it reads the VCD.
    Fst,
}
/// The firmware's input stream.
pub const EVENTS: &str = "events.ttv";
/// The firmware's expected output stream.
pub const EXPECTED_OUTPUTS: &str = "expected_outputs.ttv";
/// The summary.
pub const SUMMARY: &str = "summary.json";
/// Every file a golden set can hold.
pub const FILES: [&str; 7] = [
    GOLDEN_VCD,
    GOLDEN_FST,
    tooltouch_hdl_gen::STIM_HEX,
    tooltouch_hdl_gen::EXPECT_HEX,
    EVENTS,
    EXPECTED_OUTPUTS,
    SUMMARY,
];

/// The cycle-level part of a golden set.
#[derive(Clone, Debug)]
pub struct CycleLevel {
    /// The configuration.
    pub config: MeasureConfig,
    /// The pins, clock by clock.
    pub stimulus: Stimulus,
    /// The testbench vectors, or why they cannot be written (an empty stimulus, more than
    /// 2^31 clocks).
    pub hex: Result<Vectors, String>,
}

/// The golden response to one stimulus.
#[derive(Clone, Debug)]
pub struct GoldenSet {
    /// Pins and testbench vectors, when the stimulus has a measurement path.
    pub cycle: Option<CycleLevel>,
    /// The input event stream (`events.ttv`).
    pub inputs: InputStream,
    /// The expected outputs after each event (`expected_outputs.ttv`).
    pub outputs: Vec<(u64, Output)>,
    /// Why an event stream with measurement events has no cycle-level files (no pins make
    /// the front end act on exactly its events, e.g. a synthetic stream).
    pub no_cycle_level: Option<String>,
}

/// The outputs a device must write after each event of `stream`: measurement outputs
/// after every measurement event (each applied at its time, the FES watchdog's clock) (but FES pulses when the stream's `FIRMWARE_OBSERVE`
/// says so), force outputs after every force event but ADC samples.
pub fn expected_outputs(stream: &InputStream) -> Vec<(u64, Output)> {
    let mut measure = stream.measure.as_ref().map(Measurement::new);
    let mut force = stream.force.as_ref().map(ForceKernel::new);
    let mut out = Vec::with_capacity(stream.events.len());
    for &(time, e) in &stream.events {
        match (e, measure.as_mut(), force.as_mut()) {
            (Input::Measure(e), Some(m), _) => {
                m.apply_at(time, e);
                if stream.observe_fes || e != MeasureEvent::Fes {
                    out.push((time, Output::Measure(m.outputs())));
                }
            }
            (Input::Force(e), _, Some(f)) => {
                f.apply(e);
                if !matches!(e, ForceEvent::Sample(_)) {
                    out.push((time, Output::Force(f.outputs())));
                }
            }
            // The decoder admits no event without its configuration.
            _ => {}
        }
    }
    out
}

impl GoldenSet {
    /// The golden set of a pin stimulus under `config`.
    pub fn from_pins(config: &MeasureConfig, stimulus: Stimulus) -> GoldenSet {
        let events = super::events_from_stimulus(&stimulus, config);
        let inputs = InputStream::of_measure_events(config, stimulus.clock_hz, &events);
        let hex = hex::golden_vectors(config, &stimulus).map_err(|e| e.to_string());
        GoldenSet {
            outputs: expected_outputs(&inputs),
            cycle: Some(CycleLevel {
                config: *config,
                stimulus,
                hex,
            }),
            inputs,
            no_cycle_level: None,
        }
    }

    /// The golden set of an input event stream read from `file`: its measurement events
    /// turned into pins (when it has any and pins can make them; else
    /// [`GoldenSet::no_cycle_level`] says why), every event replayed for the expected
    /// outputs.
    pub fn from_events(inputs: InputStream, file: &str) -> GoldenSet {
        let mut no_cycle_level = None;
        let cycle = inputs.measure.and_then(|config| {
            let offsets: Vec<usize> = inputs
                .events
                .iter()
                .zip(&inputs.offsets)
                .filter(|(e, _)| matches!(e.1, Input::Measure(_)))
                .map(|(_, &o)| o)
                .collect();
            match super::stimulus_file::pins_from_events(
                &inputs.measure_events(),
                &offsets,
                &config,
                inputs.header.tick_hz,
                inputs.end_time + 1,
                file,
            ) {
                Ok(stimulus) => {
                    let hex = hex::golden_vectors(&config, &stimulus).map_err(|e| e.to_string());
                    Some(CycleLevel {
                        config,
                        stimulus,
                        hex,
                    })
                }
                Err(e) => {
                    no_cycle_level = Some(e.to_string());
                    None
                }
            }
        });
        GoldenSet {
            outputs: expected_outputs(&inputs),
            cycle,
            inputs,
            no_cycle_level,
        }
    }

    /// The summary: hashes, counts, the decisions (`register_now` rising: its clock and
    /// the latched position) and the measurement cycles (from each arm rise: its time and
    /// its status as the cycle's last outputs show it — decided, confirmed, the faults by
    /// name; the CNC accepts a cycle decided, confirmed and without fault). `source`
    /// describes the stimulus.
    pub fn summary(&self, source: serde_json::Value) -> serde_json::Value {
        let h = self.inputs.header;
        let mut measure_records = 0usize;
        let mut force_records = 0usize;
        let mut decisions = Vec::new();
        let mut deciding = false;
        // Per measurement cycle (arm rise to the next): its arm time and its last outputs.
        let mut cycles: Vec<(u64, MeasureOutputs)> = Vec::new();
        let mut armed = false;
        let mut last_force = None;
        for (time, o) in &self.outputs {
            match o {
                Output::Measure(o) => {
                    measure_records += 1;
                    if o.armed && !armed {
                        cycles.push((*time, *o));
                    } else if let Some(c) = cycles.last_mut() {
                        c.1 = *o;
                    }
                    armed = o.armed;
                    if o.register_now && !deciding {
                        decisions.push(serde_json::json!({
                            "clock": time,
                            "decision_position": o.decision_position,
                            "first_contact_position": o.first_contact_position,
                            "count": o.count,
                            "charge": o.charge,
                        }));
                    }
                    deciding = o.register_now;
                }
                Output::Force(o) => {
                    force_records += 1;
                    last_force = Some(*o);
                }
            }
        }
        let force_events = self
            .inputs
            .events
            .iter()
            .filter(|e| matches!(e.1, Input::Force(_)))
            .count();
        let mut s = serde_json::json!({
            "tooltouch": env!("CARGO_PKG_VERSION"),
            "stimulus": source,
            "tick_hz": h.tick_hz,
            "measure_hash": (h.measure_hash != 0).then(|| format!("{:016x}", h.measure_hash)),
            "force_hash": (h.force_hash != 0).then(|| format!("{:016x}", h.force_hash)),
            "events": self.inputs.events.len() - force_events,
            "force_events": force_events,
            "output_records": measure_records,
            "force_output_records": force_records,
            "decisions": decisions,
            "measurements": cycles.iter().map(|(armed_at, o)| serde_json::json!({
                "armed_at": armed_at,
                "decided": o.register_now,
                "confirmed": o.confirmed,
                "faults": Faults(o.faults).names().collect::<Vec<_>>(),
            })).collect::<Vec<_>>(),
        });
        if let Some(c) = &self.cycle {
            s["settings"] = serde_json::to_value(c.config.settings()).unwrap_or_default();
            s["clock_hz"] = c.stimulus.clock_hz.into();
            s["cycles"] = c.stimulus.total_cycles().into();
            s["segments"] = c.stimulus.segments.len().into();
            match &c.hex {
                Ok(v) => {
                    s["stim_words"] = v.stim_words.into();
                    s["expect_words"] = v.expect_words.into();
                }
                Err(why) => s["testbench_vectors"] = format!("not written: {why}").into(),
            }
        }
        if let Some(why) = &self.no_cycle_level {
            s["cycle_level"] = format!("not written: {why}").into();
        }
        if let Some(f) = last_force {
            s["force_final"] = serde_json::json!({
                "override_pct": f.override_pct,
                "control_enabled": f.control_enabled,
                "wear_alarm": f.wear_alarm,
                "bad_events": f.bad_events,
            });
        }
        s
    }

    /// Writes the set into `out` (not committed): the golden VCD and the testbench vectors
    /// when there is a measurement path, the event streams, and `summary.json` from
    /// [`GoldenSet::summary`]. Returns the summary.
    pub fn write(
        &self,
        out: &OutputFolder,
        source: serde_json::Value,
    ) -> anyhow::Result<serde_json::Value> {
        self.write_as(out, source, GoldenFormat::Vcd)
    }

    /// [`GoldenSet::write`] with the golden trace in `format` (`golden.vcd` or
    /// `golden.fst`).
    pub fn write_as(
        &self,
        out: &OutputFolder,
        source: serde_json::Value,
        format: GoldenFormat,
    ) -> anyhow::Result<serde_json::Value> {
        if let Some(c) = &self.cycle {
            let name = match format {
                GoldenFormat::Vcd => GOLDEN_VCD,
                GoldenFormat::Fst => GOLDEN_FST,
            };
            let mut w = out.create_file(name)?;
            match format {
                GoldenFormat::Vcd => {
                    vcd::write_golden(&mut w, &c.stimulus, &c.config, None).and_then(|_| w.flush())
                }
                GoldenFormat::Fst => {
                    crate::fst::write_golden_fst(&mut w, &c.stimulus, &c.config, None)
                        .and_then(|_| w.flush())
                }
            }
            .with_context(|| format!("writing {}", out.final_path(name).display()))?;
            if let Ok(v) = &c.hex {
                out.write(tooltouch_hdl_gen::STIM_HEX, &v.stim_hex)?;
                out.write(tooltouch_hdl_gen::EXPECT_HEX, &v.expect_hex)?;
            }
        }
        out.write(EVENTS, binary::encode_event_stream(&self.inputs))?;
        out.write(
            EXPECTED_OUTPUTS,
            binary::encode_output_stream(self.inputs.header, &self.outputs),
        )?;
        let summary = self.summary(source);
        out.write(
            SUMMARY,
            serde_json::to_vec_pretty(&summary).context("encoding summary.json")?,
        )?;
        Ok(summary)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tooltouch_model::measure::frontend::{pin, Pins};

    /// The summary lists each measurement cycle with its status: a clean one, then one
    /// armed with the contact closed.
    #[test]
    fn the_summary_lists_each_measurement_cycle_with_its_faults() {
        let config = MeasureConfig::default();
        let mut s = Stimulus::new(50_000_000);
        s.push(Pins(0), 10);
        s.push(Pins(pin::ARM), 100);
        s.push(Pins(0), 100);
        s.push(Pins(pin::CONTACT), 100);
        s.push(Pins(pin::CONTACT | pin::ARM), 100);
        let summary = GoldenSet::from_pins(&config, s).summary(serde_json::Value::Null);
        let l = u64::from(config.latency_cycles());
        assert_eq!(
            summary["measurements"],
            serde_json::json!([
                {"armed_at": 10 + l, "decided": false, "confirmed": false, "faults": []},
                {"armed_at": 310 + l, "decided": false, "confirmed": false, "faults": ["contact_at_arm"]},
            ])
        );
    }
}
