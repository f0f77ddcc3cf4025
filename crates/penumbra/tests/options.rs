//! The render options' one definition (`penumbra::scene::options`) against
//! the scene file and the docs: every test here fails when one of them
//! drifts from the table.
//!
//! `PENUMBRA_UPDATE_DOCS=1 cargo test --release -p penumbra --test options`
//! rewrites the docs' options tables from the definition.

mod common;

use std::path::Path;

use penumbra::description::{Kind as NodeKind, Node, Value as Prop, RENDER_KEYS};
use penumbra::emitter::choice::LightChoice;
use penumbra::sampling::filter::FILTER_KEYS;
use penumbra::sampling::{Distribution, Filter, PathSampler};
use penumbra::scene::options::markdown::{replace_section, table, View};
use penumbra::scene::options::{Choices, DefaultValue, Kind, RenderOption, Table, Value, MAX_SIDE};
use penumbra::scene::schemas;
use penumbra::scene::{IntegratorChoice, LoadOptions, Scene, SceneSource, StopRule, OPTIONS};

#[test]
fn the_docs_tables_are_the_definitions() {
    let view = |view: View| {
        move |text: &str| {
            replace_section(text, view)
                .ok_or_else(|| format!("no `<!-- options:{} begin/end -->` markers", view.id()))
        }
    };
    let (cli, file, python) = (
        view(View::CommandLine),
        view(View::SceneFile(Table::Render)),
        view(View::Python),
    );
    let stale = common::stale_docs(&[
        ("README.md", &cli),
        ("docs/scene-format.md", &file),
        ("docs/python.md", &python),
    ]);
    assert!(
        stale.is_empty(),
        "the options tables of {stale:?} differ from crates/penumbra/src/scene/options.rs; \
         rerun with PENUMBRA_UPDATE_DOCS=1 to rewrite them:\n{}",
        table(View::CommandLine)
    );
}

fn in_table(t: Table) -> impl Iterator<Item = &'static RenderOption> {
    OPTIONS.iter().filter(move |o| o.table == Some(t))
}

#[test]
fn the_render_table_has_exactly_the_options_keys() {
    // The `aov` and `moment` integrators' own keys are documented with them.
    let mut keys: Vec<&str> = RENDER_KEYS
        .iter()
        .map(|(k, _)| *k)
        .filter(|k| !penumbra::description::INTEGRATOR_KEYS.contains(k))
        .collect();
    let mut names: Vec<&str> = in_table(Table::Render).map(|o| o.name).collect();
    keys.sort();
    names.sort();
    assert_eq!(keys, names);
    let camera = schemas::of(NodeKind::Sensor)[0];
    for o in in_table(Table::Camera) {
        assert!(
            camera.param(o.name).is_some(),
            "[camera] has no `{}`",
            o.name
        );
    }
}

/// An option's fixed default as a scene file writes it.
fn default_toml(o: &RenderOption) -> Option<String> {
    match o.default {
        DefaultValue::Fixed(v) => Some(value_toml(v)),
        DefaultValue::Follows(_) | DefaultValue::Computed(_) => None,
    }
}

fn value_toml(v: Value) -> String {
    match v {
        Value::Int(n) => n.to_string(),
        Value::Number(x) => format!("{x:?}"),
        Value::Switch(b) => b.to_string(),
        Value::Distribution(d) => format!("\"{}\"", d.name()),
        Value::Filter(f) => format!("\"{}\"", f.name()),
        Value::StopRule(r) => format!("\"{}\"", r.name()),
        Value::Integrator(i) => format!("\"{}\"", i.name()),
        Value::PathSampler(p) => format!("\"{}\"", p.name()),
        Value::LightSampler(c) => format!("\"{}\"", c.name()),
        Value::Colour(c) => format!("{c:?}"),
    }
}

fn scene(text: &str) -> Scene {
    let opts = LoadOptions::default();
    SceneSource::from_toml(text, Path::new("s.toml"), Path::new("."), &opts)
        .and_then(|s| s.build())
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// What rays that hit nothing see.
fn background(s: &Scene) -> [f32; 3] {
    let far = s.emitters.iter().filter(|e| e.is_infinite());
    let sky = far
        .map(|e| e.eval_miss(penumbra::math::Vec3::Y))
        .sum::<penumbra::math::Rgb>();
    sky.to_array()
}

/// What a scene file needs beside an option's key for the option to
/// apply: the first integrator that takes it, when the default one does
/// not; the filter that takes a filter's parameter.
fn context(o: &RenderOption) -> String {
    // A crop window must fit the image: one as wide (or tall) as an image
    // may be, of one pixel the other way.
    let side = MAX_SIDE;
    match o.name {
        "crop_offset_x" => return format!("width = {side}\nheight = 1\ncrop_width = 1\n"),
        "crop_width" => return format!("width = {side}\nheight = 1\n"),
        "crop_offset_y" => return format!("height = {side}\nwidth = 1\ncrop_height = 1\n"),
        "crop_height" => return format!("height = {side}\nwidth = 1\n"),
        _ => {}
    }
    if let Some((param, _)) = FILTER_KEYS.iter().find(|(_, k)| *k == o.name) {
        let f = Filter::ALL.into_iter().find(|f| f.params().contains(param));
        return format!("filter = \"{}\"\n", f.unwrap().name());
    }
    let integrators = penumbra::integrator::SCHEMAS;
    if o.table != Some(Table::Render) || integrators[0].param(o.name).is_some() {
        return String::new();
    }
    match integrators.iter().find(|s| s.param(o.name).is_some()) {
        Some(s) => format!("integrator = \"{}\"\n", s.plugin),
        None => String::new(),
    }
}

/// A scene file that leaves a key out builds what one that gives the
/// option's default builds.
#[test]
fn scene_file_defaults_are_the_options_defaults() {
    for o in OPTIONS {
        let (Some(t), Some(v)) = (o.table, default_toml(o)) else {
            continue;
        };
        let extra = context(o);
        let plain = scene(&format!("[render]\n{extra}"));
        let given = scene(&format!("[{}]\n{} = {v}\n{extra}", t.name(), o.name));
        assert_eq!(given.settings, plain.settings, "[{}] {}", t.name(), o.name);
        let config = |s| penumbra::integrator::Config::of(s).unwrap();
        assert_eq!(config(&given), config(&plain), "[{}] {}", t.name(), o.name);
        assert_eq!(given.camera, plain.camera, "[{}] {}", t.name(), o.name);
        assert_eq!(background(&given), background(&plain), "{}", o.name);
    }
}

fn build(text: &str) -> Result<(), String> {
    let opts = LoadOptions::default();
    SceneSource::from_toml(text, Path::new("s.toml"), Path::new("."), &opts)
        .and_then(|s| s.build())
        .map(|_| ())
        .map_err(|e| e.to_string())
}

/// Values just inside and just outside the option's range, as TOML.
fn boundaries(o: &RenderOption) -> (Vec<String>, Vec<String>) {
    let names = Distribution::ALL
        .iter()
        .map(|d| format!("\"{}\"", d.name()));
    match o.kind {
        Kind::Int { min, max } => {
            let mut bad = vec![(i64::from(max) + 1).to_string()];
            bad.extend((min > 0).then(|| (min - 1).to_string()));
            (vec![min.to_string(), max.to_string()], bad)
        }
        Kind::NonNegative => (vec!["0.0".into(), "2.5".into()], vec!["-0.001".into()]),
        Kind::Positive => (vec!["0.001".into()], vec!["0.0".into(), "-1.0".into()]),
        Kind::Switch => (vec!["true".into(), "false".into()], vec!["1".into()]),
        Kind::Distribution => (names.collect(), vec!["\"sobel\"".into()]),
        Kind::Filter => (
            Filter::ALL
                .iter()
                .map(|f| format!("\"{}\"", f.name()))
                .collect(),
            vec!["\"sinc\"".into()],
        ),
        Kind::StopRule => (
            StopRule::ALL
                .iter()
                .map(|r| format!("\"{}\"", r.name()))
                .collect(),
            vec!["\"mitsuba\"".into()],
        ),
        Kind::Integrator => (
            IntegratorChoice::ALL
                .iter()
                .map(|i| format!("\"{}\"", i.name()))
                .collect(),
            vec!["\"prbvolpath\"".into()],
        ),
        Kind::PathSampler => (
            PathSampler::NAMES
                .iter()
                .map(|n| format!("\"{n}\""))
                .collect(),
            vec!["\"jitter\"".into()],
        ),
        Kind::LightSampler => (
            LightChoice::NAMES
                .iter()
                .map(|n| format!("\"{n}\""))
                .collect(),
            vec!["\"spatial\"".into()],
        ),
        Kind::Between(lo, hi) => (
            vec![format!("{lo:?}"), format!("{hi:?}")],
            vec![format!("{:?}", lo - 0.01), format!("{:?}", hi + 0.01)],
        ),
        Kind::Colour => (
            vec!["[0.0, 2.0, 0.5]".into()],
            vec!["[0.0, -1.0, 0.0]".into()],
        ),
        // A file is read only when `custom` needs it: see tests/points.rs.
        Kind::File => (Vec::new(), vec!["7".into()]),
    }
}

/// Every scene-file option accepts its range and refuses what lies outside,
/// with an error located at the value.
#[test]
fn scene_files_accept_exactly_the_options_ranges() {
    for o in OPTIONS {
        let Some(t) = o.table else { continue };
        let (good, bad) = boundaries(o);
        let extra = context(o);
        for v in good {
            let text = format!("[{}]\n{} = {v}\n{extra}", t.name(), o.name);
            assert_eq!(build(&text), Ok(()), "{text}");
        }
        for v in bad {
            let text = format!("[{}]\n{} = {v}\n{extra}", t.name(), o.name);
            let e = build(&text).expect_err(&text);
            assert!(e.starts_with("s.toml:2:"), "{text}: {e}");
            if let Kind::Int { min, max } = o.kind {
                let expected = format!(
                    "{}.{}: must be an integer from {min} to {max}",
                    t.name(),
                    o.name
                );
                assert!(e.contains(&expected), "{text}: {e}");
            }
        }
    }
}

/// The node that holds a scene-file key of `table`.
fn holder<'a>(root: &'a Node, table: Table, key: &str) -> &'a Node {
    let sensor = root.child(NodeKind::Sensor).unwrap();
    if table == Table::Camera {
        return sensor;
    }
    match RENDER_KEYS.iter().find(|(k, _)| *k == key).unwrap().1 {
        kind @ (NodeKind::Film | NodeKind::Sampler) => sensor.child(kind).unwrap(),
        kind => root.child(kind).unwrap(),
    }
}

/// What a scene file holds for a value.
fn prop_of(v: Value) -> Prop {
    match v {
        Value::Int(n) => Prop::Int(i64::from(n)),
        Value::Number(x) => Prop::Float(f64::from(x)),
        Value::Switch(b) => Prop::Bool(b),
        Value::Distribution(d) => Prop::String(d.name().into()),
        Value::Filter(f) => Prop::String(f.name().into()),
        Value::StopRule(r) => Prop::String(r.name().into()),
        Value::PathSampler(p) => Prop::String(p.name().into()),
        Value::LightSampler(c) => Prop::String(c.name().into()),
        Value::Integrator(_) | Value::Colour(_) => unreachable!("not a property"),
    }
}

/// A value given for an option on the command line or in Python lands on
/// the scene-file key of the same name.
#[test]
fn front_end_values_replace_the_key_of_the_same_name() {
    for o in OPTIONS {
        let Some(t) = o.table else { continue };
        if o.set.is_none() {
            continue;
        }
        let v = match o.kind {
            Kind::Int { min, max } => Value::Int(max.min(min.max(7))),
            Kind::NonNegative | Kind::Positive => Value::Number(0.5),
            Kind::Between(lo, _) => Value::Number(lo),
            Kind::StopRule => Value::StopRule(StopRule::Dammertz),
            Kind::Integrator => Value::Integrator(IntegratorChoice::Whitted),
            Kind::PathSampler => Value::PathSampler(PathSampler::Sequence(Distribution::Halton)),
            Kind::LightSampler => Value::LightSampler(LightChoice::Uniform),
            Kind::Switch => Value::Switch(!matches!(
                o.default,
                DefaultValue::Fixed(Value::Switch(true))
            )),
            Kind::Distribution => Value::Distribution(Distribution::Poisson),
            Kind::Filter => Value::Filter(Filter::Gaussian),
            Kind::Colour | Kind::File => continue,
        };
        let mut c = Choices::default();
        o.store(&mut c, v);
        let opts = LoadOptions::default();
        let mut src =
            SceneSource::from_toml("", Path::new("s.toml"), Path::new("."), &opts).unwrap();
        c.overrides.apply(&mut src);
        if o.name == "integrator" {
            assert_eq!(
                src.root.child(NodeKind::Integrator).unwrap().plugin,
                "whitted"
            );
            continue;
        }
        let node = holder(&src.root, t, o.name);
        let got = &node
            .prop(o.name)
            .unwrap_or_else(|| panic!("{} not set", o.name))
            .value
            .value;
        assert_eq!(*got, prop_of(v), "{}", o.name);
    }
}
