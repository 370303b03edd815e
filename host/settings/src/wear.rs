//! The `[wear]` table: the face-milling wear scenario of `tooltouch wear` and the wear
//! monitor's condition sets of a firmware image (docs/wear.md, "Settings"). One rule for
//! both: the distinct conditions of the cuts, in order of first use, are the condition sets
//! (at most [`MAX_CONDITION_SETS`], the firmware's capacity), each with `[P̄]` from W7 at
//! `vb_limit_mm` and the idle power of its speed.
//!
//! Every key is optional (the defaults are `tooltouch wear`'s built-in scenario); an
//! unknown key is an error naming it. Units: mm, s, W; a cut's speed is `rpm` or
//! `speed_m_per_min` (v = π·D·n), its feed `feed_per_tooth_mm` or `feed_mm_per_rev`
//! (s = Z·s_z) — exactly one of each.

use serde::Deserialize;
use tooltouch_model::force::config::ForceSettings;
use tooltouch_model::force::wear::{WearSettings, MAX_CONDITION_SETS};
use tooltouch_plant::milling::{Conditions, Cut, MillingParams, Tool, WearScenario};
use tooltouch_plant::milling_transients::ToothTransients;

/// One cut as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CutKeys {
    depth_mm: f64,
    rpm: Option<f64>,
    speed_m_per_min: Option<f64>,
    feed_per_tooth_mm: Option<f64>,
    feed_mm_per_rev: Option<f64>,
    seconds: f64,
}

/// One entry of `idle_power`: a speed and the spindle's idle power at it.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct IdleKeys {
    rpm: Option<f64>,
    speed_m_per_min: Option<f64>,
    watts: f64,
}

/// The `[wear]` table as written.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct WearKeys {
    seed: Option<u64>,
    teeth: Option<u32>,
    diameter_mm: Option<f64>,
    width_mm: Option<f64>,
    vb_limit_mm: Option<f64>,
    efficiency: Option<f64>,
    power_lag_s: Option<f64>,
    lowpass_shift: Option<u8>,
    debounce_periods: Option<u8>,
    idle_s: Option<f64>,
    new_vb_mm: Option<f64>,
    worn_vb_mm: Option<f64>,
    vb_rate_mm_per_s: Option<f64>,
    idle_power: Option<Vec<IdleKeys>>,
    cuts: Option<Vec<CutKeys>>,
    transients: Option<TransientKeys>,
}

/// The per-tooth transient plant as written (its presence selects it).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct TransientKeys {
    natural_hz: Option<f64>,
    damping: Option<f64>,
    noise_w: Option<f64>,
}

/// A wear plan: the scenario and its two tools.
#[derive(Clone, Debug, PartialEq)]
pub struct WearPlan {
    /// Cutter, machine, cuts, [VB], lag, noise seed.
    pub scenario: WearScenario,
    /// The new tool (`new_vb_mm`).
    pub new_tool: Tool,
    /// The worn tool (`worn_vb_mm`).
    pub worn_tool: Tool,
}

impl Default for WearPlan {
    fn default() -> Self {
        WearPlan {
            scenario: WearScenario::default(),
            new_tool: tooltouch_plant::milling::NEW_TOOL,
            worn_tool: tooltouch_plant::milling::WORN_TOOL,
        }
    }
}

fn in_range(key: &str, v: f64, lo: f64, hi: f64) -> Result<f64, String> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(format!("[wear] {key} = {v}: allowed {lo}..={hi}"))
    }
}

fn positive(key: &str, v: f64, hi: f64) -> Result<f64, String> {
    if v.is_finite() && v > 0.0 && v <= hi {
        Ok(v)
    } else {
        Err(format!(
            "[wear] {key} = {v}: allowed more than 0, at most {hi}"
        ))
    }
}

/// The spindle speed of `rpm` / `speed_m_per_min` (exactly one), rpm.
fn speed(key: &str, rpm: Option<f64>, v: Option<f64>, diameter_mm: f64) -> Result<f64, String> {
    match (rpm, v) {
        (Some(n), None) => positive(&format!("{key}.rpm"), n, 100_000.0),
        (None, Some(v)) => Ok(
            positive(&format!("{key}.speed_m_per_min"), v, 10_000.0)? * 1000.0
                / (std::f64::consts::PI * diameter_mm),
        ),
        _ => Err(format!(
            "[wear] {key}: give exactly one of rpm and speed_m_per_min"
        )),
    }
}

/// The cutter and machine keys over [`MillingParams::default`].
fn milling(k: &WearKeys) -> Result<MillingParams, String> {
    let mut m = MillingParams::default();
    if let Some(z) = k.teeth {
        m.teeth = z;
        if !(1..=64).contains(&z) {
            return Err(format!("[wear] teeth = {z}: allowed 1..=64"));
        }
    }
    if let Some(v) = k.diameter_mm {
        m.diameter_mm = positive("diameter_mm", v, 2000.0)?;
    }
    if let Some(v) = k.width_mm {
        m.width_mm = positive("width_mm", v, m.diameter_mm)?;
    }
    if let Some(v) = k.efficiency {
        m.efficiency = positive("efficiency", v, 1.0)?;
    }
    Ok(m)
}

/// The monitor's and the run's scalar keys (seed, limit, lag, filter, debounce, idle time)
/// into `sc`.
fn scenario_scalars(k: &WearKeys, sc: &mut WearScenario) -> Result<(), String> {
    if let Some(v) = k.seed {
        sc.seed = v;
    }
    if let Some(v) = k.vb_limit_mm {
        sc.vb_limit_mm = positive("vb_limit_mm", v, 10.0)?;
    }
    if let Some(v) = k.power_lag_s {
        sc.power_lag = positive("power_lag_s", v, 10.0)?;
    }
    if let Some(v) = k.lowpass_shift {
        if v > 8 {
            return Err(format!("[wear] lowpass_shift = {v}: allowed 0..=8"));
        }
        sc.monitor_lowpass_shift = v;
    }
    if let Some(v) = k.debounce_periods {
        if v == 0 {
            return Err("[wear] debounce_periods = 0: allowed 1..=255".into());
        }
        sc.debounce_periods = v;
    }
    if let Some(v) = k.idle_s {
        sc.idle_s = in_range("idle_s", v, 0.0, 600.0)?;
    }
    Ok(())
}

/// `idle_power` as `(rpm, watts)` pairs.
fn idle_table(k: &WearKeys, m: &MillingParams) -> Result<Vec<(f64, f64)>, String> {
    let mut idle = Vec::new();
    for (i, e) in k.idle_power.iter().flatten().enumerate() {
        let key = format!("idle_power[{i}]");
        let n = speed(&key, e.rpm, e.speed_m_per_min, m.diameter_mm)?;
        idle.push((n, in_range(&format!("{key}.watts"), e.watts, 0.0, 1e6)?));
    }
    Ok(idle)
}

/// One cut as written (`key` = `cuts[i]`), its idle power from `idle` (or the cutter's).
fn cut(key: &str, c: &CutKeys, m: &MillingParams, idle: &[(f64, f64)]) -> Result<Cut, String> {
    let rpm = speed(key, c.rpm, c.speed_m_per_min, m.diameter_mm)?;
    let feed_per_tooth_mm = match (c.feed_per_tooth_mm, c.feed_mm_per_rev) {
        (Some(f), None) => positive(&format!("{key}.feed_per_tooth_mm"), f, 10.0)?,
        (None, Some(f)) => {
            positive(&format!("{key}.feed_mm_per_rev"), f, 100.0)? / f64::from(m.teeth)
        }
        _ => {
            return Err(format!(
                "[wear] {key}: give exactly one of feed_per_tooth_mm and feed_mm_per_rev"
            ))
        }
    };
    let idle_power = if idle.is_empty() {
        m.idle_power
    } else {
        idle.iter()
            .find(|(n, _)| (n - rpm).abs() <= 1e-6 * rpm)
            .map(|(_, w)| *w)
            .ok_or_else(|| {
                format!("[wear] {key}: its speed ({rpm:.1} rpm) has no idle_power entry")
            })?
    };
    let seconds = positive(&format!("{key}.seconds"), c.seconds, 3600.0)?;
    Ok(Cut {
        conditions: Conditions {
            depth_mm: positive(&format!("{key}.depth_mm"), c.depth_mm, 100.0)?,
            feed_per_tooth_mm,
            rpm,
        },
        seconds,
        idle_power,
    })
}

/// The cuts (when given) into `sc`, their run at most an hour with `sc.idle_s`.
fn cuts(k: &WearKeys, m: &MillingParams, sc: &mut WearScenario) -> Result<(), String> {
    let idle = idle_table(k, m)?;
    let Some(cuts) = &k.cuts else {
        if !idle.is_empty() {
            return Err(
                "[wear] idle_power: give the cuts too (their speeds pick the entry)".into(),
            );
        }
        return Ok(());
    };
    if cuts.is_empty() {
        return Err("[wear] cuts: at least one cut".into());
    }
    sc.cuts = Vec::with_capacity(cuts.len().min(1024));
    let mut total = sc.idle_s;
    for (i, c) in cuts.iter().enumerate() {
        let cut = cut(&format!("cuts[{i}]"), c, m, &idle)?;
        total += cut.seconds;
        sc.cuts.push(cut);
    }
    // Memory: one row per 50 ms period of the run.
    if total > 3600.0 {
        return Err(format!(
            "[wear] cuts: {total} s in all, at most 3600 s (idle_s and every cut's seconds)"
        ));
    }
    Ok(())
}

/// The new and the worn tool over the defaults `d`.
fn tools(k: &WearKeys, d: &WearPlan) -> Result<(Tool, Tool), String> {
    let rate = match k.vb_rate_mm_per_s {
        Some(v) => in_range("vb_rate_mm_per_s", v, 0.0, 1.0)?,
        None => d.new_tool.vb_rate,
    };
    let new_tool = Tool {
        vb_start: match k.new_vb_mm {
            Some(v) => in_range("new_vb_mm", v, 0.0, 10.0)?,
            None => d.new_tool.vb_start,
        },
        vb_rate: rate,
        ..d.new_tool
    };
    let worn_tool = Tool {
        vb_start: match k.worn_vb_mm {
            Some(v) => in_range("worn_vb_mm", v, 0.0, 10.0)?,
            None => d.worn_tool.vb_start,
        },
        vb_rate: rate,
        ..d.worn_tool
    };
    Ok((new_tool, worn_tool))
}

impl WearPlan {
    /// Reads a `[wear]` table; the error names the key.
    pub fn from_table(table: &toml::Value) -> Result<WearPlan, String> {
        let k: WearKeys = table
            .clone()
            .try_into()
            .map_err(|e: toml::de::Error| format!("[wear] {}", e.message()))?;
        let d = WearPlan::default();
        let m = milling(&k)?;
        let mut sc = WearScenario {
            milling: m,
            ..d.scenario.clone()
        };
        scenario_scalars(&k, &mut sc)?;
        cuts(&k, &m, &mut sc)?;
        if let Some(t) = &k.transients {
            let d = ToothTransients::default();
            let t = ToothTransients {
                natural_hz: t.natural_hz.unwrap_or(d.natural_hz),
                damping: t.damping.unwrap_or(d.damping),
                noise_w: t.noise_w.unwrap_or(d.noise_w),
            };
            t.validate().map_err(|e| format!("[wear] transients.{e}"))?;
            sc.transients = Some(t);
        }
        let (sets, _) = sc.condition_sets();
        if sets.len() > MAX_CONDITION_SETS {
            return Err(format!(
                "[wear] cuts: {} distinct conditions, the firmware holds at most {MAX_CONDITION_SETS} condition sets (MAX_CONDITION_SETS)",
                sets.len()
            ));
        }
        let (new_tool, worn_tool) = tools(&k, &d)?;
        let plan = WearPlan {
            scenario: sc,
            new_tool,
            worn_tool,
        };
        // The monitor must take it (a hold that fits, values the model accepts), and the
        // threshold must be able to tell the new tool from a worn one.
        plan.scenario
            .config(false)
            .map_err(|e| format!("[wear] {e}"))?;
        plan.scenario
            .check_new_tool_margin(plan.new_tool.vb_start)
            .map_err(|e| format!("[wear] {e}"))?;
        Ok(plan)
    }

    /// The wear monitor's settings for the force path `base` (updating threshold): what a
    /// firmware image built from the same file runs.
    pub fn monitor_settings(&self, base: &ForceSettings) -> Result<WearSettings, String> {
        self.scenario
            .wear_settings(base, false)
            .map_err(|e| format!("[wear] {e}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(text: &str) -> Result<WearPlan, String> {
        let t: toml::Table = toml::from_str(text).unwrap();
        WearPlan::from_table(&toml::Value::Table(t))
    }

    #[test]
    fn an_empty_table_is_the_default_scenario() {
        assert_eq!(plan("").unwrap(), WearPlan::default());
    }

    #[test]
    fn speeds_and_feeds_in_either_unit() {
        let p = plan(
            "teeth = 5\ncuts = [{ depth_mm = 2, speed_m_per_min = 149, feed_mm_per_rev = 1.0, seconds = 5 }]\nidle_power = [{ speed_m_per_min = 149, watts = 320 }]",
        )
        .unwrap();
        let c = p.scenario.cuts[0];
        assert!(
            (c.conditions.rpm - 474.28).abs() < 0.01,
            "{}",
            c.conditions.rpm
        );
        assert!((c.conditions.feed_per_tooth_mm - 0.2).abs() < 1e-12);
        assert_eq!(c.idle_power, 320.0);
    }

    #[test]
    fn bad_keys_are_named() {
        for (text, key) in [
            ("colour = 1", "colour"),
            ("teeth = 0", "teeth"),
            ("efficiency = 1.5", "efficiency"),
            ("cuts = []", "cuts"),
            ("cuts = [{ depth_mm = 2, rpm = 300, seconds = 5 }]", "cuts[0]"),
            ("cuts = [{ depth_mm = -2, rpm = 300, feed_per_tooth_mm = 0.2, seconds = 5 }]", "cuts[0].depth_mm"),
            ("idle_power = [{ rpm = 300, watts = 300 }]\ncuts = [{ depth_mm = 2, rpm = 400, feed_per_tooth_mm = 0.2, seconds = 5 }]", "cuts[0]"),
            ("power_lag_s = 9", "power lag"),
        ] {
            let e = plan(text).unwrap_err();
            assert!(e.contains(key), "{text}: {e}");
        }
    }

    #[test]
    fn more_condition_sets_than_the_firmware_holds_are_refused_naming_the_limit() {
        let cuts: Vec<String> = (0..=MAX_CONDITION_SETS)
            .map(|i| {
                format!(
                    "{{ depth_mm = {}, rpm = 300, feed_per_tooth_mm = 0.2, seconds = 1 }}",
                    1 + i
                )
            })
            .collect();
        let e = plan(&format!("cuts = [{}]", cuts.join(", "))).unwrap_err();
        assert!(
            e.contains("at most 8") && e.contains("MAX_CONDITION_SETS"),
            "{e}"
        );
        let ok = plan(&format!(
            "cuts = [{}]",
            cuts[..MAX_CONDITION_SETS].join(", ")
        ))
        .unwrap();
        let w = ok.monitor_settings(&ForceSettings::default()).unwrap();
        assert_eq!(usize::from(w.set_count), MAX_CONDITION_SETS);
    }

    #[test]
    fn a_new_tool_inside_the_models_scatter_is_refused() {
        // The Table-2 Z = 1 preset at [VB] = 0.5 mm: the new tool 31 W (5.0 %) under [P].
        let text = "teeth = 1\nvb_limit_mm = 0.5\nnew_vb_mm = 0.0\nworn_vb_mm = 1.1\nlowpass_shift = 5\nidle_power = [{ speed_m_per_min = 18, watts = 150 }]\ncuts = [{ depth_mm = 4, speed_m_per_min = 18, feed_mm_per_rev = 0.8, seconds = 30 }]\n";
        let e = plan(text).unwrap_err();
        assert!(e.contains("scatter") && e.contains("cut 1"), "{e}");
        assert!(plan(&text.replace("vb_limit_mm = 0.5", "vb_limit_mm = 0.55")).is_ok());
    }
}
