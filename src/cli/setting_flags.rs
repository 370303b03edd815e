//! The settings' flags of `measure`, `budget` and `calibrate` as clap arguments, built from
//! the one table [`tooltouch_settings::flags::SETTING_FLAGS`]: this module only parses
//! (each flag's value into a [`FlagValue`]); the settings crate applies and explains.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Arg, ArgAction, ArgMatches};
use tooltouch_settings::flags::{
    Choice, FlagValue, GivenFlags, SettingFlag, ValueKind, SETTING_FLAGS,
};

/// The settings' flags as given (flatten into a subcommand's arguments).
#[derive(Clone, Debug, Default)]
pub struct SettingFlags(GivenFlags);

impl std::ops::Deref for SettingFlags {
    type Target = GivenFlags;
    fn deref(&self) -> &GivenFlags {
        &self.0
    }
}

/// The argument id and value name of each flag of [`SETTING_FLAGS`] (`i-def` → `i_def`,
/// `I_DEF`), made once.
fn names(index: usize) -> (&'static str, &'static str) {
    static NAMES: std::sync::OnceLock<Vec<(String, String)>> = std::sync::OnceLock::new();
    let all = NAMES.get_or_init(|| {
        SETTING_FLAGS
            .iter()
            .map(|f| {
                let id = f.flag.replace('-', "_");
                let value_name = id.to_uppercase();
                (id, value_name)
            })
            .collect()
    });
    let (id, value_name) = &all[index];
    (id, value_name)
}

/// A [`ValueKind::Choice`] flag's values, parsed as a `clap::ValueEnum` would be (a value
/// that is not UTF-8 is an invalid value, shown lossily).
#[derive(Clone)]
struct ChoiceParser(&'static [Choice]);

impl ChoiceParser {
    fn values(&self) -> impl Iterator<Item = PossibleValue> + '_ {
        self.0
            .iter()
            .map(|c| PossibleValue::new(c.name).help(c.help).hide(c.hidden))
    }
}

impl TypedValueParser for ChoiceParser {
    type Value = &'static str;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<&'static str, clap::Error> {
        let text = value.to_string_lossy().into_owned();
        let parsed = PossibleValuesParser::new(self.values()).parse(cmd, arg, text.into())?;
        let ignore_case = arg.is_some_and(Arg::is_ignore_case_set);
        self.0
            .iter()
            .zip(self.values())
            .find(|(_, v)| v.matches(&parsed, ignore_case))
            .map(|(c, _)| c.name)
            .ok_or_else(|| clap::Error::new(clap::error::ErrorKind::InvalidValue).with_cmd(cmd))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(self.values()))
    }
}

/// The clap argument of one flag (as `#[arg(long)]` on an `Option<T>` field would be).
fn arg(index: usize, f: &'static SettingFlag) -> Arg {
    let (id, value_name) = names(index);
    let a = Arg::new(id)
        .long(f.flag)
        .value_name(value_name)
        .action(ArgAction::Set)
        .help(f.help)
        .help_heading(f.heading);
    match f.kind {
        ValueKind::U8 => a.value_parser(clap::value_parser!(u8)),
        ValueKind::U16 => a.value_parser(clap::value_parser!(u16)),
        ValueKind::U32 => a.value_parser(clap::value_parser!(u32)),
        ValueKind::U64 => a.value_parser(clap::value_parser!(u64)),
        ValueKind::F64 => a.value_parser(clap::value_parser!(f64)),
        ValueKind::Bool => a.value_parser(clap::builder::BoolishValueParser::new()),
        ValueKind::Choice(choices) => a.value_parser(ChoiceParser(choices)),
    }
}

/// The value of `f` in `m`, if given.
fn value(m: &ArgMatches, index: usize, f: &SettingFlag) -> Option<FlagValue> {
    let id = names(index).0;
    let int = |v: Option<u64>| v.map(FlagValue::Int);
    match f.kind {
        ValueKind::U8 => int(m.get_one::<u8>(id).map(|&v| v.into())),
        ValueKind::U16 => int(m.get_one::<u16>(id).map(|&v| v.into())),
        ValueKind::U32 => int(m.get_one::<u32>(id).map(|&v| v.into())),
        ValueKind::U64 => int(m.get_one::<u64>(id).copied()),
        ValueKind::F64 => m.get_one::<f64>(id).map(|&v| FlagValue::Float(v)),
        ValueKind::Bool => m.get_one::<bool>(id).map(|&v| FlagValue::Bool(v)),
        ValueKind::Choice(_) => m.get_one::<&'static str>(id).map(|&v| FlagValue::Choice(v)),
    }
}

impl clap::FromArgMatches for SettingFlags {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let mut given = GivenFlags::default();
        for (index, f) in SETTING_FLAGS.iter().enumerate() {
            if let Some(v) = value(m, index, f) {
                given.push(f, v);
            }
        }
        Ok(SettingFlags(given))
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

impl clap::Args for SettingFlags {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        cmd.args(SETTING_FLAGS.iter().enumerate().map(|(i, f)| arg(i, f)))
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}
