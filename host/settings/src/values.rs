//! A sweep parameter's values and the error that names a bad one: the syntax both the
//! measurement sweep ([`super::spec`]) and the force sweep ([`super::force`]) parse.
//!
//! Values are a TOML array (`charge_bits = [8, 12, 16]`) or text, in a file or a flag:
//! `"8,12,16"`, a single value `"16"`, or an inclusive range with an optional step
//! `"8..=16"`, `"8..=16:4"`; names (methods, laws, rules, controllers) a list or
//! comma-separated text. A leaf: it imports neither sweep, so they can both import it.

use serde::{Deserialize, Serialize};

/// A bad sweep specification.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("sweep parameter `{parameter}`: {message}")]
pub struct SpecError {
    /// The parameter, as in the TOML file (flags use the same name with `-` for `_`).
    pub parameter: String,
    /// What is wrong.
    pub message: String,
}

/// Most values one parameter may list (a range's values, a list's entries).
pub const MAX_VALUES: usize = 100_000;

pub fn err(parameter: &str, message: impl Into<String>) -> SpecError {
    SpecError {
        parameter: parameter.to_string(),
        message: message.into(),
    }
}

/// Integer values of one parameter, as written.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Values {
    /// A TOML array.
    List(Vec<i64>),
    /// A single TOML integer.
    One(i64),
    /// Text: `a,b,c`, `a`, `a..=b` or `a..=b:step`.
    Text(String),
}

impl Values {
    pub fn text(s: &str) -> Values {
        Values::Text(s.to_string())
    }

    /// The values, checked to lie in `min..=max`.
    pub fn expand(&self, parameter: &str, min: i64, max: i64) -> Result<Vec<u32>, SpecError> {
        let raw: Vec<i64> = match self {
            Values::List(v) => v.clone(),
            Values::One(v) => vec![*v],
            Values::Text(t) => parse_text(parameter, t)?,
        };
        if raw.is_empty() {
            return Err(err(parameter, "no values (an empty list)"));
        }
        if raw.len() > MAX_VALUES {
            return Err(err(
                parameter,
                format!(
                    "{} values, more than the {MAX_VALUES} a parameter may have",
                    raw.len()
                ),
            ));
        }
        let mut out = Vec::with_capacity(raw.len());
        for v in raw {
            if v < min || v > max {
                return Err(err(
                    parameter,
                    format!("value {v} is out of range: allowed {min}..={max}"),
                ));
            }
            out.push(v as u32);
        }
        out.dedup();
        Ok(out)
    }
}

fn parse_int(parameter: &str, s: &str) -> Result<i64, SpecError> {
    s.trim()
        .parse::<i64>()
        .map_err(|_| err(parameter, format!("`{}` is not an integer", s.trim())))
}

fn parse_text(parameter: &str, t: &str) -> Result<Vec<i64>, SpecError> {
    let t = t.trim();
    if t.is_empty() {
        return Err(err(parameter, "no values (empty text)"));
    }
    if let Some((a, rest)) = t.split_once("..=") {
        let (b, step) = match rest.split_once(':') {
            Some((b, s)) => (b, parse_int(parameter, s)?),
            None => (rest, 1),
        };
        let (a, b) = (parse_int(parameter, a)?, parse_int(parameter, b)?);
        if step <= 0 {
            return Err(err(
                parameter,
                format!("range step {step} must be at least 1"),
            ));
        }
        if a > b {
            return Err(err(parameter, format!("empty range {a}..={b}")));
        }
        // In i128: `b - a` of two i64 can exceed i64 (`-5e18..=5e18`).
        let count = (i128::from(b) - i128::from(a)) / i128::from(step) + 1;
        if count > MAX_VALUES as i128 {
            return Err(err(
                parameter,
                format!(
                    "range {a}..={b}:{step} has {count} values, more than the {MAX_VALUES} a parameter may have"
                ),
            ));
        }
        let step = usize::try_from(step).map_err(|_| err(parameter, "range step too large"))?;
        return Ok((a..=b).step_by(step).collect());
    }
    if t.contains("..") {
        return Err(err(
            parameter,
            format!("`{t}` is not a range: write `a..=b` or `a..=b:step`"),
        ));
    }
    t.split(',').map(|s| parse_int(parameter, s)).collect()
}

/// Names of one parameter (method, law, rule): a TOML array of strings or comma text.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Names {
    /// A TOML array.
    List(Vec<String>),
    /// Comma-separated text.
    Text(String),
}

impl Names {
    /// The named values, each looked up in `known`; an old spelling
    /// ([`crate::RENAMED_VALUES`]) is read as its new one (the command line
    /// warns about it).
    pub fn expand<T: Copy>(
        &self,
        parameter: &str,
        known: &[(&str, T)],
    ) -> Result<Vec<T>, SpecError> {
        let names: Vec<String> = match self {
            Names::List(v) => v.clone(),
            Names::Text(t) => t
                .split(',')
                .map(|s| s.trim().to_string())
                .filter(|s| !s.is_empty())
                .collect(),
        };
        if names.is_empty() {
            return Err(err(parameter, "no values (an empty list)"));
        }
        names
            .iter()
            .map(|n| {
                let n = crate::renamed_value(n).unwrap_or(n);
                known
                    .iter()
                    .find(|(k, _)| *k == n)
                    .map(|&(_, v)| v)
                    .ok_or_else(|| {
                        let list: Vec<&str> = known.iter().map(|(k, _)| *k).collect();
                        err(
                            parameter,
                            format!("unknown value `{n}`: expected one of {}", list.join(", ")),
                        )
                    })
            })
            .collect()
    }
}

/// Most points one sweep (measurement or force) may have: a million points are about
/// 100 MB of points and rows, and hours of work at the default scenarios.
pub const MAX_POINTS: u128 = 1_000_000;

/// Checks that the product of `factors` (parameter, number of values) is at most
/// [`MAX_POINTS`], before any point is made; the error names every factor.
pub fn check_sweep_size(what: &str, factors: &[(&str, usize)]) -> Result<(), SpecError> {
    let product = factors
        .iter()
        .try_fold(1u128, |p, &(_, n)| p.checked_mul(n as u128));
    match product {
        Some(n) if n <= MAX_POINTS => Ok(()),
        _ => {
            let shown = product.map_or_else(|| "more than 10^38".to_string(), |n| n.to_string());
            let list = factors
                .iter()
                .filter(|(_, n)| *n != 1)
                .map(|(p, n)| format!("{p} {n}"))
                .collect::<Vec<_>>()
                .join(" × ");
            let names: Vec<&str> = factors
                .iter()
                .filter(|(_, n)| *n > 1)
                .map(|(p, _)| *p)
                .collect();
            Err(err(
                &names.join(", "),
                format!(
                    "the {what} has {shown} points ({list}), more than the {MAX_POINTS} a sweep may have: give fewer values or wider steps"
                ),
            ))
        }
    }
}
