//! The options tables of the docs, made from [`OPTIONS`].
//!
//! Each table sits in its document between two markers,
//! `<!-- options:VIEW begin ... -->` and `<!-- options:VIEW end -->`;
//! [`replace_section`] puts a fresh table there.

use super::{DefaultValue, Kind, RenderOption, Table, Value, OPTIONS};
use crate::emitter::choice::LightChoice;
use crate::sampling::PathSampler;
use crate::scene::IntegratorChoice;

/// Whose spelling a table uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// The keys of one scene-file table (docs/scene-format.md).
    SceneFile(Table),
    /// The flags of `penumbra render` (README.md).
    CommandLine,
    /// The keyword arguments of the Python render functions (docs/python.md).
    Python,
}

impl View {
    /// The word in the markers.
    pub fn id(self) -> &'static str {
        match self {
            View::SceneFile(Table::Render) => "render",
            View::SceneFile(Table::Camera) => "camera",
            View::CommandLine => "cli",
            View::Python => "python",
        }
    }

    fn shows(self, o: &RenderOption) -> bool {
        match self {
            View::SceneFile(t) => o.table == Some(t),
            View::CommandLine => o.flag.is_some(),
            View::Python => o.python,
        }
    }
}

/// The markdown table of the options `view` shows, one row each.
pub fn table(view: View) -> String {
    let mut out = String::from(match view {
        View::SceneFile(_) => "| key | type | default | meaning |\n|---|---|---|---|\n",
        View::CommandLine => "| option | value | default | meaning |\n|---|---|---|---|\n",
        View::Python => "| keyword | value | default | meaning |\n|---|---|---|---|\n",
    });
    for o in OPTIONS.iter().filter(|o| view.shows(o)) {
        let cells = match view {
            View::SceneFile(_) => vec![
                format!("`{}`", o.name),
                value_type(o.kind),
                default(o, view),
                o.doc.to_string(),
            ],
            View::CommandLine => {
                let mut flag = format!("`--{}`", o.long());
                if let Some(off) = o.long_off() {
                    flag += &format!(", `--{off}`");
                }
                let value = match o.kind {
                    Kind::Switch => "switch".into(),
                    k => value_type(k),
                };
                vec![flag, value, default(o, view), o.doc.to_string()]
            }
            View::Python => vec![
                format!("`{}`", o.name),
                value_type(o.kind),
                default(o, view),
                o.doc.to_string(),
            ],
        };
        out += &format!("| {} |\n", cells.join(" | "));
    }
    out
}

/// `text` with the table of `view` between its markers replaced by a fresh
/// one; `None` if the markers are missing.
pub fn replace_section(text: &str, view: View) -> Option<String> {
    let begin = format!("<!-- options:{} begin", view.id());
    let end = format!("<!-- options:{} end -->", view.id());
    let start = text.find(&begin)?;
    let body = start + text[start..].find('\n')? + 1;
    let stop = body + text[body..].find(&end)?;
    Some(format!("{}{}{}", &text[..body], table(view), &text[stop..]))
}

fn value_type(kind: Kind) -> String {
    match kind {
        Kind::Int {
            min: 0,
            max: u32::MAX,
        } => "integer 0–2³²−1".into(),
        Kind::Int { min, max } => format!("integer {min}–{max}"),
        Kind::NonNegative => "number ≥ 0".into(),
        Kind::Positive => "number > 0".into(),
        Kind::Switch => "bool".into(),
        Kind::Distribution => "distribution".into(),
        Kind::Filter => "box, tent, gaussian, mitchell, catmullrom or lanczos".into(),
        Kind::StopRule => "calibrated, cycles, povray or dammertz".into(),
        Kind::Integrator => IntegratorChoice::NAMES.join(", "),
        Kind::PathSampler => PathSampler::NAMES.join(", "),
        Kind::LightSampler => LightChoice::NAMES.join(", "),
        Kind::Between(lo, hi) => format!("number {lo}–{hi}"),
        Kind::Colour => "colour ≥ 0".into(),
        Kind::File => "file".into(),
    }
}

/// The default's table cell: values and names as code, prose as it is.
fn default(o: &RenderOption, view: View) -> String {
    let text = default_text(o, view);
    match o.default {
        DefaultValue::Fixed(Value::Switch(_)) if view == View::CommandLine => text,
        DefaultValue::Fixed(_) | DefaultValue::Follows(_) => format!("`{text}`"),
        DefaultValue::Computed(_) => text,
    }
}

/// An option's default as the view's users write it (`on`, `800`,
/// `--distribution`, `all cores` for the command line).
pub fn default_text(o: &RenderOption, view: View) -> String {
    let cli = view == View::CommandLine;
    match o.default {
        DefaultValue::Fixed(Value::Switch(on)) if cli => (if on { "on" } else { "off" }).into(),
        DefaultValue::Fixed(v) => value_text(v, view),
        DefaultValue::Follows(name) => match super::find(name) {
            Some(other) if cli => format!("--{}", other.long()),
            _ => name.into(),
        },
        DefaultValue::Computed(text) => text.into(),
    }
}

/// A value as the view's users write it.
pub fn value_text(v: Value, view: View) -> String {
    match v {
        Value::Int(n) => n.to_string(),
        Value::Number(x) => x.to_string(),
        Value::Switch(b) if view == View::Python => (if b { "True" } else { "False" }).into(),
        Value::Switch(b) => b.to_string(),
        Value::Distribution(d) if view == View::CommandLine => d.name().into(),
        Value::Distribution(d) => format!("\"{}\"", d.name()),
        Value::Filter(f) if view == View::CommandLine => f.name().into(),
        Value::Filter(f) => format!("\"{}\"", f.name()),
        Value::StopRule(r) if view == View::CommandLine => r.name().into(),
        Value::StopRule(r) => format!("\"{}\"", r.name()),
        Value::Integrator(i) if view == View::CommandLine => i.name().into(),
        Value::Integrator(i) => format!("\"{}\"", i.name()),
        Value::PathSampler(p) if view == View::CommandLine => p.name().into(),
        Value::PathSampler(p) => format!("\"{}\"", p.name()),
        Value::LightSampler(c) if view == View::CommandLine => c.name().into(),
        Value::LightSampler(c) => format!("\"{}\"", c.name()),
        Value::Colour(c) => format!("[{}, {}, {}]", c[0], c[1], c[2]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_section_is_replaced_between_its_markers_only() {
        let text = "intro\n<!-- options:python begin: generated -->\nstale row\n<!-- options:python end -->\nrest\n";
        let new = replace_section(text, View::Python).unwrap();
        assert!(new.starts_with("intro\n<!-- options:python begin: generated -->\n| keyword |"));
        assert!(new.ends_with("|\n<!-- options:python end -->\nrest\n"));
        assert!(!new.contains("stale row"));
        assert_eq!(replace_section(text, View::CommandLine), None);
    }

    #[test]
    fn rows_spell_the_option_as_the_view_does() {
        let cli = table(View::CommandLine);
        assert!(cli.contains("| `--metric`, `--no-metric` | switch | off |"));
        assert!(cli.contains("| `--pixel-distribution` | distribution | `--distribution` |"));
        let toml = table(View::SceneFile(Table::Render));
        assert!(toml.contains("| `distribution` | distribution | `\"grid\"` |"));
        assert!(toml.contains("| `background` | colour ≥ 0 | `[0, 0, 0]` |"));
        assert!(!toml.contains("`threads`") && !toml.contains("`aperture`"));
        assert!(!table(View::Python).contains("`background`"));
    }
}
