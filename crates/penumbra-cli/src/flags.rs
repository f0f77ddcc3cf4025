//! The render options' flags, made from the library's table
//! ([`penumbra::scene::OPTIONS`]), and the value parsers of the command line.

use std::path::PathBuf;

use clap::{Arg, ArgAction, ArgMatches, Args, Command, FromArgMatches};
use penumbra::emitter::choice::LightChoice;
use penumbra::sampling::{Distribution, Filter, PathSampler};
use penumbra::scene::options::markdown::{default_text, View};
use penumbra::scene::options::{Flag, Kind, Value};
use penumbra::scene::{Choices, IntegratorChoice, RenderOption, StopRule, OPTIONS};

/// What the render options' flags say: `--width 320`, `--no-metric`, ...
/// Flags not given leave the scene's values alone.
#[derive(Debug, Default)]
pub struct OptionFlags(pub Choices);

impl Args for OptionFlags {
    fn augment_args(cmd: Command) -> Command {
        let flagged = OPTIONS.iter().filter_map(|o| o.flag.map(|f| (o, f)));
        cmd.args(flagged.flat_map(|(o, f)| args(o, f)))
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

impl FromArgMatches for OptionFlags {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let mut flags = OptionFlags::default();
        flags.update_from_arg_matches(m)?;
        Ok(flags)
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        for o in OPTIONS.iter().filter(|o| o.flag.is_some()) {
            if let Some(v) = given(o, m) {
                o.store(&mut self.0, v);
            }
            if o.kind == Kind::File {
                if let Some(path) = m.get_one::<PathBuf>(o.name) {
                    o.store_file(&mut self.0, path.clone());
                }
            }
        }
        Ok(())
    }
}

/// The flag of an option, and a switch's `--no-` flag.
fn args(o: &'static RenderOption, flag: Flag) -> Vec<Arg> {
    let arg = Arg::new(o.name).long(o.long()).help(help(o));
    let with_value = |arg: Arg| arg.value_name(o.metavar()).action(ArgAction::Set);
    match o.kind {
        Kind::Switch => {
            let on = arg.action(ArgAction::SetTrue);
            match (flag.off, o.long_off()) {
                (Some(off_help), Some(long)) => vec![
                    on.overrides_with(off_id(o)),
                    Arg::new(off_id(o))
                        .long(long)
                        .action(ArgAction::SetTrue)
                        .help(capitalised(off_help)),
                ],
                _ => vec![on],
            }
        }
        // Colours are set in scene files only.
        Kind::Colour => Vec::new(),
        Kind::File => vec![with_value(arg.value_parser(clap::value_parser!(PathBuf)))],
        _ => vec![with_value(
            arg.value_parser(move |s: &str| parse_value(o, s)),
        )],
    }
}

/// A value of option `o` written as text, checked as its flag checks it:
/// what the command line and the explorer's controls store with
/// [`RenderOption::store`]. Switches take `true` or `false`; colours and
/// files are no such value.
pub fn parse_value(o: &RenderOption, s: &str) -> Result<Value, String> {
    match o.kind {
        Kind::Int { min, max } => match s.parse::<u32>() {
            Ok(n) if (min..=max).contains(&n) => Ok(Value::Int(n)),
            _ => Err(format!("`{s}` is not a whole number from {min} to {max}")),
        },
        Kind::NonNegative => parse_nonneg(s).map(Value::Number),
        Kind::Positive => parse_positive(s).map(Value::Number),
        Kind::Between(lo, hi) => parse_between(s, lo, hi).map(Value::Number),
        Kind::Switch => match s {
            "true" => Ok(Value::Switch(true)),
            "false" => Ok(Value::Switch(false)),
            _ => Err(format!("`{s}` is not true or false")),
        },
        Kind::Distribution => parse_distribution(s).map(Value::Distribution),
        Kind::Filter => parse_filter(s).map(Value::Filter),
        Kind::StopRule => parse_stop_rule(s).map(Value::StopRule),
        Kind::Integrator => parse_integrator(s).map(Value::Integrator),
        Kind::PathSampler => parse_path_sampler(s).map(Value::PathSampler),
        Kind::LightSampler => parse_light_sampler(s).map(Value::LightSampler),
        Kind::Colour | Kind::File => Err(format!("`{}` is set in scene files only", o.name)),
    }
}

/// The names an option of `kind` takes, for a kind chosen by name.
pub fn choice_names(kind: Kind) -> Option<Vec<&'static str>> {
    let names = |v: &[&'static str]| Some(v.to_vec());
    match kind {
        Kind::Distribution => Some(Distribution::SELECTABLE.iter().map(|d| d.name()).collect()),
        Kind::Filter => Some(Filter::ALL.iter().map(|f| f.name()).collect()),
        Kind::StopRule => Some(StopRule::ALL.iter().map(|r| r.name()).collect()),
        Kind::Integrator => names(&IntegratorChoice::NAMES),
        Kind::PathSampler => names(&PathSampler::NAMES),
        Kind::LightSampler => names(&LightChoice::NAMES),
        _ => None,
    }
}

/// The option's value if its flag was given; for a switch, of `--x` and
/// `--no-x` the last one given (clap keeps only that one).
fn given(o: &RenderOption, m: &ArgMatches) -> Option<Value> {
    match o.kind {
        Kind::Switch => {
            let off = o.long_off().is_some() && m.get_flag(&off_id(o));
            match (m.get_flag(o.name), off) {
                (true, _) => Some(Value::Switch(true)),
                (_, true) => Some(Value::Switch(false)),
                _ => None,
            }
        }
        Kind::Colour | Kind::File => None,
        _ => m.get_one::<Value>(o.name).copied(),
    }
}

fn off_id(o: &RenderOption) -> String {
    format!("no_{}", o.name)
}

/// The one-line doc, capitalised, with the default a scene that does not
/// set the option gets.
fn help(o: &RenderOption) -> String {
    format!(
        "{} [default: {}]",
        capitalised(o.doc),
        default_text(o, View::CommandLine)
    )
}

fn capitalised(s: &str) -> String {
    let mut chars = s.chars();
    chars
        .next()
        .map(|c| c.to_uppercase().chain(chars).collect())
        .unwrap_or_default()
}

pub fn parse_distribution(s: &str) -> Result<Distribution, String> {
    by_name(
        "distribution",
        s,
        Distribution::from_name(s),
        &Distribution::SELECTABLE,
        Distribution::name,
    )
}

pub fn parse_stop_rule(s: &str) -> Result<StopRule, String> {
    by_name(
        "stop rule",
        s,
        StopRule::from_name(s),
        &StopRule::ALL,
        StopRule::name,
    )
}

pub fn parse_integrator(s: &str) -> Result<IntegratorChoice, String> {
    by_name(
        "integrator",
        s,
        IntegratorChoice::from_name(s),
        &IntegratorChoice::ALL,
        IntegratorChoice::name,
    )
}

pub fn parse_path_sampler(s: &str) -> Result<PathSampler, String> {
    by_name(
        "path sampler",
        s,
        PathSampler::from_name(s),
        &PathSampler::ALL,
        PathSampler::name,
    )
}

pub fn parse_light_sampler(s: &str) -> Result<LightChoice, String> {
    by_name(
        "light sampler",
        s,
        LightChoice::from_name(s),
        &LightChoice::ALL,
        LightChoice::name,
    )
}

pub fn parse_filter(s: &str) -> Result<Filter, String> {
    by_name(
        "filter",
        s,
        Filter::from_name(s),
        &Filter::ALL,
        Filter::name,
    )
}

/// `found`, the `what` named `s`, or a message listing the valid names.
fn by_name<T: Copy>(
    what: &str,
    s: &str,
    found: Option<T>,
    all: &[T],
    name: fn(T) -> &'static str,
) -> Result<T, String> {
    found.ok_or_else(|| {
        let names: Vec<&str> = all.iter().map(|&x| name(x)).collect();
        format!(
            "unknown {what} `{s}`; valid choices are: {}",
            names.join(", ")
        )
    })
}

/// A file size: bytes, or a number with K, M, G or T (binary multiples).
pub fn parse_size(s: &str) -> Result<u64, String> {
    penumbra::input::parse_size(s).ok_or_else(|| {
        format!("`{s}` is not a size: give bytes, or a number with K, M, G or T (for example 8G)")
    })
}

pub fn parse_nonneg(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("`{s}` is not a finite number >= 0")),
    }
}

pub fn parse_between(s: &str, lo: f32, hi: f32) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if (lo..=hi).contains(&v) => Ok(v),
        _ => Err(format!("`{s}` is not a number from {lo} to {hi}")),
    }
}

pub fn parse_positive(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("`{s}` is not a finite number > 0")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra::scene::options::DefaultValue;

    fn parse(args: &[&str]) -> Result<Choices, clap::Error> {
        let cmd = OptionFlags::augment_args(Command::new("render").no_binary_name(true));
        let m = cmd.try_get_matches_from(args)?;
        Ok(OptionFlags::from_arg_matches(&m)?.0)
    }

    /// Every option with a flag has it, documented, and nothing else is
    /// made: the flags are the table's.
    #[test]
    fn the_flags_are_the_tables() {
        let cmd = OptionFlags::augment_args(Command::new("render"));
        let mut expected = Vec::new();
        for o in OPTIONS.iter().filter(|o| o.flag.is_some()) {
            expected.push(o.long());
            expected.extend(o.long_off());
        }
        let longs: Vec<String> = cmd
            .get_arguments()
            .map(|a| a.get_long().unwrap_or_default().to_string())
            .collect();
        assert_eq!(longs, expected);
        for a in cmd.get_arguments() {
            let help = a.get_help().map(|h| h.to_string()).unwrap_or_default();
            assert!(help.len() > 10, "--{:?} has no help", a.get_long());
        }
    }

    /// A value given as a flag lands where the library stores that option.
    #[test]
    fn each_flag_stores_its_option() {
        for o in OPTIONS.iter().filter(|o| o.flag.is_some()) {
            let (text, value) = match o.kind {
                Kind::Int { min, .. } => (min.to_string(), Value::Int(min)),
                Kind::NonNegative | Kind::Positive => ("0.5".into(), Value::Number(0.5)),
                Kind::Distribution => {
                    ("poisson".into(), Value::Distribution(Distribution::Poisson))
                }
                Kind::Filter => ("gaussian".into(), Value::Filter(Filter::Gaussian)),
                Kind::StopRule => ("povray".into(), Value::StopRule(StopRule::Povray)),
                Kind::Integrator => (
                    "whitted".into(),
                    Value::Integrator(IntegratorChoice::Whitted),
                ),
                Kind::PathSampler => (
                    "halton".into(),
                    Value::PathSampler(PathSampler::Sequence(Distribution::Halton)),
                ),
                Kind::LightSampler => ("power".into(), Value::LightSampler(LightChoice::Power)),
                Kind::Between(lo, _) => (lo.to_string(), Value::Number(lo)),
                Kind::Switch | Kind::Colour | Kind::File => continue,
            };
            let mut expected = Choices::default();
            o.store(&mut expected, value);
            let got = parse(&[&format!("--{}", o.long()), &text]).unwrap();
            assert_eq!(got, expected, "--{}", o.long());
        }
    }

    /// Each flag takes exactly its option's values.
    #[test]
    fn each_flag_accepts_exactly_its_range() {
        for o in OPTIONS.iter().filter(|o| o.flag.is_some()) {
            let (good, bad): (Vec<String>, Vec<String>) = match o.kind {
                Kind::Int { min, max } => {
                    let mut bad = vec![(u64::from(max) + 1).to_string()];
                    bad.extend(min.checked_sub(1).map(|m| m.to_string()));
                    (vec![min.to_string(), max.to_string()], bad)
                }
                Kind::NonNegative => (
                    vec!["0".into(), "3.5".into()],
                    vec!["-0.5".into(), "inf".into()],
                ),
                Kind::Positive => (vec!["0.001".into()], vec!["0".into(), "nan".into()]),
                Kind::Distribution => (
                    Distribution::ALL
                        .iter()
                        .map(|d| d.name().to_string())
                        .collect(),
                    vec!["sobel".into()],
                ),
                Kind::Filter => (
                    Filter::ALL.iter().map(|f| f.name().to_string()).collect(),
                    vec!["sinc".into()],
                ),
                Kind::StopRule => (
                    StopRule::ALL.iter().map(|r| r.name().to_string()).collect(),
                    vec!["mitsuba".into()],
                ),
                Kind::Integrator => (
                    IntegratorChoice::NAMES
                        .iter()
                        .map(|n| n.to_string())
                        .collect(),
                    vec!["prbvolpath".into()],
                ),
                Kind::PathSampler => (
                    PathSampler::NAMES.iter().map(|n| n.to_string()).collect(),
                    vec!["jitter".into(), "stratified".into()],
                ),
                Kind::LightSampler => (
                    LightChoice::NAMES.iter().map(|n| n.to_string()).collect(),
                    vec!["spatial".into(), "Power".into()],
                ),
                Kind::Between(lo, hi) => (
                    vec![lo.to_string(), hi.to_string()],
                    vec![
                        (lo - 0.01).to_string(),
                        (hi + 0.01).to_string(),
                        "nan".into(),
                    ],
                ),
                Kind::Switch | Kind::Colour | Kind::File => continue,
            };
            for v in good {
                let arg = format!("--{}={v}", o.long());
                assert!(parse(&[&arg]).is_ok(), "{arg}");
            }
            for v in bad {
                let arg = format!("--{}={v}", o.long());
                assert!(parse(&[&arg]).is_err(), "{arg}");
            }
        }
    }

    #[test]
    fn of_a_switch_and_its_off_flag_the_last_wins() {
        for o in OPTIONS.iter().filter(|o| o.kind == Kind::Switch) {
            let on = format!("--{}", o.long());
            let stored = |b: bool| {
                let mut c = Choices::default();
                o.store(&mut c, Value::Switch(b));
                c
            };
            assert_eq!(parse(&[&on]).unwrap(), stored(true));
            assert_eq!(parse(&[]).unwrap(), Choices::default());
            if let Some(off) = o.long_off() {
                let off = format!("--{off}");
                assert_eq!(parse(&[&off]).unwrap(), stored(false));
                assert_eq!(parse(&[&on, &off]).unwrap(), stored(false));
                assert_eq!(parse(&[&off, &on]).unwrap(), stored(true));
            }
        }
    }

    #[test]
    fn help_states_the_scene_default() {
        let o = OPTIONS.iter().find(|o| o.name == "max_depth").unwrap();
        assert_eq!(o.default, DefaultValue::Fixed(Value::Int(3)));
        assert!(help(o).ends_with("[default: 3]"), "{}", help(o));
        assert!(help(o).starts_with("Whitted: levels of"), "{}", help(o));
    }
}
