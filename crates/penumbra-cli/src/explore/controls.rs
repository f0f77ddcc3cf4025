//! The explorer's controls: render options of the table
//! ([`penumbra::scene::OPTIONS`]) chosen by name, each described to the
//! page by its entry (kind, range, default, doc, the names an enumeration
//! takes) and set through the same parser and setter as its flag.

use penumbra::scene::options::{self, DefaultValue, Kind, Value};
use penumbra::scene::RenderOption;
use serde_json::{json, Value as Json};

use crate::flags::{choice_names, parse_value};

/// The options the page offers, in its order: what the thesis's study
/// varies (the integrator, the ray sets of each effect and their
/// distributions, the metrics) and what keeps a render quick (size, depth,
/// passes).
pub const CONTROLS: &[&str] = &[
    "integrator",
    "spp",
    "passes",
    "width",
    "height",
    "max_depth",
    "distribution",
    "pixel_distribution",
    "lens_distribution",
    "shadow_rays",
    "shadow_distribution",
    "reflection_rays",
    "reflection_distribution",
    "refraction_rays",
    "refraction_distribution",
    "aperture",
    "metric",
    "shadow_metric",
    "shadow_metric_rays",
    "reflection_metric",
    "metric_min_rays",
    "metric_threshold",
];

/// The option of a control, `None` for a name that is none.
pub fn control(name: &str) -> Option<&'static RenderOption> {
    CONTROLS
        .iter()
        .find(|c| **c == name)
        .and_then(|c| options::find(c))
}

/// `GET /schema`'s `controls`: every control as its table entry says.
pub fn schema() -> Json {
    let controls: Vec<Json> = CONTROLS
        .iter()
        .filter_map(|name| options::find(name))
        .map(describe)
        .collect();
    Json::Array(controls)
}

fn describe(o: &RenderOption) -> Json {
    let mut c = json!({
        "name": o.name,
        "doc": o.doc,
        "default": default_json(o.default),
    });
    let (kind, extra) = match o.kind {
        Kind::Int { min, max } => ("int", json!({ "min": min, "max": max })),
        Kind::NonNegative => ("number", json!({ "min": 0.0 })),
        Kind::Positive => ("number", json!({ "min": 0.0, "exclusive_min": true })),
        Kind::Between(lo, hi) => ("number", json!({ "min": lo, "max": hi })),
        Kind::Switch => ("switch", json!({})),
        kind => match choice_names(kind) {
            Some(names) => ("choice", json!({ "choices": names })),
            None => ("text", json!({})),
        },
    };
    c["kind"] = json!(kind);
    if let (Some(c), Json::Object(extra)) = (c.as_object_mut(), extra) {
        c.extend(extra);
    }
    c
}

/// A default as the page shows it: a value, `{"follows": name}` or
/// `{"computed": text}`.
fn default_json(d: DefaultValue) -> Json {
    match d {
        DefaultValue::Fixed(v) => value_json(v),
        DefaultValue::Follows(name) => json!({ "follows": name }),
        DefaultValue::Computed(text) => json!({ "computed": text }),
    }
}

/// A value of an option as JSON: a number, a boolean or a name.
pub fn value_json(v: Value) -> Json {
    match v {
        Value::Int(n) => json!(n),
        Value::Number(x) => json!(x),
        Value::Switch(b) => json!(b),
        Value::Distribution(d) => json!(d.name()),
        Value::Filter(f) => json!(f.name()),
        Value::StopRule(r) => json!(r.name()),
        Value::Integrator(i) => json!(i.name()),
        Value::PathSampler(p) => json!(p.name()),
        Value::LightSampler(l) => json!(l.name()),
        Value::Colour(c) => json!(c),
    }
}

/// The control `name` set to `value` (a JSON string, number or boolean),
/// checked as the command line checks its flag; the message says why not.
pub fn parse(name: &str, value: &Json) -> Result<(&'static RenderOption, Value), String> {
    let o = control(name).ok_or_else(|| {
        format!(
            "`{}` is not a control; the controls are: {}",
            penumbra::input::quote::clip(name, 40),
            CONTROLS.join(", ")
        )
    })?;
    let text = match value {
        Json::String(s) => s.clone(),
        Json::Number(n) => n.to_string(),
        Json::Bool(b) => b.to_string(),
        _ => return Err(format!("`{name}` takes a string, a number or a boolean")),
    };
    let v = parse_value(o, &text).map_err(|e| format!("{name}: {e}"))?;
    Ok((o, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn explore_controls_are_options_with_setters() {
        for name in CONTROLS {
            let o = options::find(name).unwrap_or_else(|| panic!("{name} is no option"));
            assert!(o.set.is_some(), "{name} cannot be set");
        }
    }

    #[test]
    fn explore_parse_checks_as_the_flag_does() {
        let (o, v) = parse("shadow_distribution", &json!("poisson")).unwrap();
        assert_eq!(o.name, "shadow_distribution");
        assert_eq!(value_json(v), json!("poisson"));
        assert_eq!(parse("spp", &json!(16)).unwrap().1, Value::Int(16));
        assert_eq!(
            parse("metric", &json!(true)).unwrap().1,
            Value::Switch(true)
        );
        let e = parse("shadow_distribution", &json!("sobel")).unwrap_err();
        assert!(e.contains("unknown distribution `sobel`"), "{e}");
        assert!(parse("spp", &json!(0)).is_err());
        assert!(parse("seed", &json!(1))
            .unwrap_err()
            .contains("not a control"));
        assert!(parse("spp", &json!([1])).is_err());
    }
}
