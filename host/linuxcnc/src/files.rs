//! The files of a `halrun` session of the component: the streamer's text input (one line
//! per period, [`PeriodInputs::streamer_line`]), the two samplers' pin lists, their text
//! output read back into the model's outputs, and both sides as Outputs streams (`.ttv`: a
//! measurement record and a force record per period, time = the period's index) for
//! `tooltouch check`.

use super::period::{PeriodInputs, PeriodKernel};
use tooltouch_model::force::config::ForceConfig;
use tooltouch_model::force::kernel::ForceOutputs;
use tooltouch_model::units::Fx;
use tooltouch_model::wire::{Header, StreamKind};
use tooltouch_model::{MeasureConfig, MeasureOutputs};
use tooltouch_vectors::binary::{encode_output_stream, Output};

/// Sampler 0: the 17 measurement outputs, in the model's field order (pin, sampler type),
/// then the alarm bit `fault` (read back and checked to be `faults != 0`).
pub const MEASURE_PINS: [(&str, char); 18] = [
    ("armed", 'b'),
    ("contact-filtered", 'b'),
    ("register-now", 'b'),
    ("decision-position", 's'),
    ("first-contact", 'b'),
    ("first-contact-position", 's'),
    ("position", 's'),
    ("scale-errors", 'u'),
    ("count", 'u'),
    ("last-window-count", 'u'),
    ("charge", 'u'),
    ("density-armed", 'b'),
    ("density-fired", 'b'),
    ("revolutions", 'u'),
    ("pulses", 'u'),
    ("confirmed", 'b'),
    ("faults", 'u'),
    ("fault", 'b'),
];

/// Sampler 1: the 15 force outputs (each I32F32 value as its high and low words), then the
/// `overruns` health pin.
pub const FORCE_PINS: [(&str, char); 21] = [
    ("override-pct", 'u'),
    ("saturated", 'b'),
    ("fast-estimate", 'b'),
    ("control-enabled", 'b'),
    ("identifying", 'b'),
    ("identified", 'b'),
    ("wear-over", 'b'),
    ("wear-alarm", 'b'),
    ("bad-events", 'u'),
    ("force-estimate-hi", 's'),
    ("force-estimate-lo", 'u'),
    ("force-measured-hi", 's'),
    ("force-measured-lo", 'u'),
    ("wear-power-hi", 's'),
    ("wear-power-lo", 'u'),
    ("wear-allowed-hi", 's'),
    ("wear-allowed-lo", 'u'),
    ("coulomb-hi", 's'),
    ("coulomb-lo", 'u'),
    ("wear-blind", 'b'),
    ("overruns", 'u'),
];

/// A sampler's `cfg=` string for its pins.
pub fn sampler_cfg(pins: &[(&str, char)]) -> String {
    pins.iter().map(|p| p.1).collect()
}

/// The streamer's input file: one line per period.
pub fn streamer_text(rows: &[PeriodInputs]) -> String {
    let mut s = String::with_capacity(rows.len() * 64);
    for r in rows {
        s.push_str(&r.streamer_line());
        s.push('\n');
    }
    s
}

/// A sampler file that cannot be read: its name, line and what is wrong.
#[derive(Debug, thiserror::Error)]
#[error("{file}: line {line}: {what}")]
pub struct SamplerError {
    /// The file.
    pub file: String,
    /// The line, from 1.
    pub line: usize,
    /// What is wrong.
    pub what: String,
}

/// The integer columns of every line of `halsampler` output with `columns` values per line.
/// A first `-t` sample-number column, when present (lines of `columns + 1`), must count up
/// by one from line to line (a jump is a sample the sampler's FIFO dropped) and is dropped.
pub fn sampler_rows(text: &str, file: &str, columns: usize) -> Result<Vec<Vec<i64>>, SamplerError> {
    let mut rows = Vec::new();
    let mut last_tag: Option<i64> = None;
    for (i, line) in text.lines().enumerate() {
        let err = |what: String| SamplerError {
            file: file.to_string(),
            line: i + 1,
            what,
        };
        let words: Vec<&str> = line.split_whitespace().collect();
        let words = match words.len() {
            n if n == columns || n == columns + 1 => &words[..],
            n => return Err(err(format!("{n} values, expected {columns}"))),
        };
        let (tag, words) = match words.len() {
            n if n == columns + 1 => (Some(words[0]), &words[1..]),
            _ => (None, words),
        };
        if let Some(tag) = tag {
            let tag: i64 = tag
                .parse()
                .map_err(|_| err(format!("sample number `{tag}` is not an integer")))?;
            if let Some(last) = last_tag.filter(|&l| tag != l + 1) {
                return Err(err(format!(
                    "sample number {tag} after {last}: the sampler dropped samples (its FIFO overflowed)"
                )));
            }
            last_tag = Some(tag);
        }
        let row = words
            .iter()
            .map(|w| {
                w.parse::<i64>()
                    .map_err(|_| err(format!("`{w}` is not an integer")))
            })
            .collect::<Result<Vec<_>, _>>()?;
        rows.push(row);
    }
    Ok(rows)
}

fn fit<T: TryFrom<i64>>(v: i64, name: &str) -> Result<T, String> {
    T::try_from(v).map_err(|_| format!("{name} = {v} is out of its range"))
}

fn flag(v: i64, name: &str) -> Result<bool, String> {
    match v {
        0 => Ok(false),
        1 => Ok(true),
        _ => Err(format!("{name} = {v} is not a bit")),
    }
}

/// One sampler-0 row as the model's measurement outputs; the `fault` column must be
/// `faults != 0`.
pub fn measure_outputs(r: &[i64]) -> Result<MeasureOutputs, String> {
    let n = |i: usize| MEASURE_PINS[i].0;
    let outputs = MeasureOutputs {
        armed: flag(r[0], n(0))?,
        contact: flag(r[1], n(1))?,
        register_now: flag(r[2], n(2))?,
        decision_position: fit(r[3], n(3))?,
        first_contact: flag(r[4], n(4))?,
        first_contact_position: fit(r[5], n(5))?,
        position: fit(r[6], n(6))?,
        scale_errors: fit(r[7], n(7))?,
        count: fit(r[8], n(8))?,
        last_window_count: fit(r[9], n(9))?,
        charge: fit(r[10], n(10))?,
        density_armed: flag(r[11], n(11))?,
        density_fired: flag(r[12], n(12))?,
        revolutions: fit(r[13], n(13))?,
        pulses: fit(r[14], n(14))?,
        confirmed: flag(r[15], n(15))?,
        faults: fit(r[16], n(16))?,
    };
    let fault = flag(r[17], n(17))?;
    if fault != (outputs.faults != 0) {
        return Err(format!(
            "fault = {} but faults = {}: the alarm bit must be faults != 0",
            u8::from(fault),
            outputs.faults
        ));
    }
    Ok(outputs)
}

/// One sampler-1 row as the model's force outputs (and the `overruns` column).
pub fn force_outputs(r: &[i64]) -> Result<(ForceOutputs, u32), String> {
    let n = |i: usize| FORCE_PINS[i].0;
    let fx = |i: usize| -> Result<Fx, String> {
        let hi: i32 = fit(r[i], n(i))?;
        let lo: u32 = fit(r[i + 1], n(i + 1))?;
        Ok(Fx::from_bits((i64::from(hi) << 32) | i64::from(lo)))
    };
    Ok((
        ForceOutputs {
            override_pct: fit(r[0], n(0))?,
            saturated: flag(r[1], n(1))?,
            fast_estimate: flag(r[2], n(2))?,
            control_enabled: flag(r[3], n(3))?,
            identifying: flag(r[4], n(4))?,
            identified: flag(r[5], n(5))?,
            wear_over: flag(r[6], n(6))?,
            wear_alarm: flag(r[7], n(7))?,
            bad_events: fit(r[8], n(8))?,
            force_estimate: fx(9)?,
            force_measured: fx(11)?,
            wear_power: fx(13)?,
            wear_allowed: fx(15)?,
            coulomb: fx(17)?,
            wear_blind: flag(r[19], n(19))?,
        },
        fit(r[20], n(20))?,
    ))
}

/// The header of both Outputs streams: the configurations' hashes, a tick per period.
pub fn header(measure: &MeasureConfig, force: &ForceConfig) -> Header {
    Header {
        stream: StreamKind::Outputs,
        tick_hz: u32::from(force.settings().sample_hz),
        measure_hash: measure.hash(),
        force_hash: force.hash(),
    }
}

/// The Outputs stream of per-period outputs: a measurement then a force record per
/// period, at the period's index.
pub fn outputs_stream(header: Header, periods: &[PeriodOutputs]) -> Vec<u8> {
    let records: Vec<(u64, Output)> = periods
        .iter()
        .enumerate()
        .flat_map(|(k, (m, f))| {
            [
                (k as u64, Output::Measure(*m)),
                (k as u64, Output::Force(*f)),
            ]
        })
        .collect();
    encode_output_stream(header, &records)
}

/// One period's outputs: the measurement's and the force path's.
pub type PeriodOutputs = (MeasureOutputs, ForceOutputs);

/// The golden outputs of `rows`: the component's period semantics over the model.
pub fn golden_outputs(
    measure: &MeasureConfig,
    force: &ForceConfig,
    rows: &[PeriodInputs],
) -> Vec<PeriodOutputs> {
    let mut k = PeriodKernel::new(measure, force);
    rows.iter().map(|r| k.step(r)).collect()
}

/// The DUT's per-period outputs from the two samplers' files (`measure` and `force`, with
/// their names), period by period; a file with fewer lines ends the trace there (the
/// comparison reports the missing periods).
pub fn dut_outputs(
    measure: (&str, &str),
    force: (&str, &str),
) -> Result<(Vec<PeriodOutputs>, Vec<u32>), SamplerError> {
    let m = sampler_rows(measure.0, measure.1, MEASURE_PINS.len())?;
    let f = sampler_rows(force.0, force.1, FORCE_PINS.len())?;
    let mut out = Vec::with_capacity(m.len().min(f.len()));
    let mut overruns = Vec::with_capacity(f.len());
    for (i, (mr, fr)) in m.iter().zip(&f).enumerate() {
        let at = |file: &str, what: String| SamplerError {
            file: file.to_string(),
            line: i + 1,
            what,
        };
        let mo = measure_outputs(mr).map_err(|w| at(measure.1, w))?;
        let (fo, o) = force_outputs(fr).map_err(|w| at(force.1, w))?;
        out.push((mo, fo));
        overruns.push(o);
    }
    Ok((out, overruns))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sampler_rows_round_trip_the_outputs() {
        let m = MeasureOutputs {
            armed: true,
            decision_position: -5,
            pulses: u32::MAX,
            revolutions: 3,
            ..Default::default()
        };
        let f = ForceOutputs {
            override_pct: 120,
            force_estimate: Fx::lit("-12.5"),
            coulomb: Fx::from_bits(i64::MIN + 7),
            wear_blind: true,
            ..Default::default()
        };
        let mut mline: Vec<i64> = m.fields().iter().map(|x| x.1).collect();
        mline.push(0); // fault
        let bits = |v: Fx| [v.to_bits() >> 32, v.to_bits() & 0xffff_ffff];
        let mut fline = vec![120, 0, 0, 0, 0, 0, 0, 0, 0];
        for v in [
            f.force_estimate,
            f.force_measured,
            f.wear_power,
            f.wear_allowed,
            f.coulomb,
        ] {
            fline.extend(bits(v));
        }
        fline.extend([1, 0]);
        assert_eq!(measure_outputs(&mline).unwrap(), m);
        assert_eq!(force_outputs(&fline).unwrap().0, f);
        let text = format!(
            "0 {}\n",
            mline
                .iter()
                .map(i64::to_string)
                .collect::<Vec<_>>()
                .join(" ")
        );
        assert_eq!(sampler_rows(&text, "s0", 18).unwrap()[0], mline);
        let e = sampler_rows("1 2 3\n", "s0.txt", 18).unwrap_err();
        assert_eq!(e.to_string(), "s0.txt: line 1: 3 values, expected 18");
        let e = sampler_rows("4 1\n5 1\n7 0\n", "s1.txt", 1).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("s1.txt: line 3: sample number 7 after 5"),
            "{e}"
        );
        let mut bad = mline.clone();
        bad[0] = 2;
        assert_eq!(measure_outputs(&bad).unwrap_err(), "armed = 2 is not a bit");
        // The status: confirmed and faults read back, the alarm bit checked against faults.
        let faulted = MeasureOutputs {
            confirmed: true,
            faults: 0x22,
            ..m
        };
        let mut line: Vec<i64> = faulted.fields().iter().map(|x| x.1).collect();
        line.push(1);
        assert_eq!(measure_outputs(&line).unwrap(), faulted);
        *line.last_mut().unwrap() = 0;
        assert_eq!(
            measure_outputs(&line).unwrap_err(),
            "fault = 0 but faults = 34: the alarm bit must be faults != 0"
        );
    }
}
