//! The plugin reference of the docs, written from the schemas: one table of
//! keys per plugin in `docs/scene-format.md` and the table of Mitsuba's
//! plugins in `docs/mitsuba.md`, each between markers that name it
//! (`<!-- plugin:bsdf/diffuse begin … -->` … `<!-- plugin:bsdf/diffuse end
//! -->`, `<!-- mitsuba:bsdf begin … -->`). The `reference` test fails when
//! the docs differ from what this writes, and rewrites them with
//! `PENUMBRA_UPDATE_DOCS=1`.

use super::schemas;
use crate::description::mitsuba::{Plugin, Registry};
use crate::description::{Kind, MitsubaKey, Param, Range, Schema, Type};
use crate::medium::Phase;

/// The kinds whose plugins the scene-format reference documents one by one
/// (the integrators, the film and the sampler are the `[render]` table's).
pub const DOCUMENTED: [Kind; 7] = [
    Kind::Sensor,
    Kind::Bsdf,
    Kind::Texture,
    Kind::Volume,
    Kind::Shape,
    Kind::Emitter,
    Kind::Medium,
];

/// Every plugin documented, as (kind, schema): the scene's plugins of each
/// kind of [`DOCUMENTED`], the `area` emitter shapes carry and the phase
/// functions media hold.
pub fn documented() -> Vec<(Kind, &'static Schema)> {
    let mut all: Vec<(Kind, &'static Schema)> = DOCUMENTED
        .iter()
        .flat_map(|&k| schemas::of(k).iter().map(move |&s| (k, s)))
        .collect();
    all.push((Kind::Emitter, schemas::area_schema()));
    // The phase functions media hold.
    all.extend(Phase::SCHEMAS.iter().map(|&s| (Kind::Phase, s)));
    all
}

/// The marker's name of a plugin: `bsdf/diffuse`.
pub fn block_id(kind: Kind, schema: &Schema) -> String {
    format!("{}/{}", kind.name(), schema.plugin)
}

/// A markdown table cell: pipes escaped.
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

/// A parameter's type as the reference writes it, with its range.
pub fn type_text(p: &Param) -> String {
    let range = match p.range {
        Range::Any => String::new(),
        r => format!(" {}", r.markdown()),
    };
    match p.ty {
        Type::Colour => format!("colour{range}"),
        Type::ColourTexture => format!("colour{range} or texture"),
        Type::Number => format!("number{range}"),
        Type::NumberTexture => format!("number{range} or texture"),
        Type::Volume => format!("number or colour{range}, or volume"),
        Type::Int => format!("integer{range}"),
        Type::NumberOrChoice(what, _) => format!("number{range} or {what} name"),
        ref ty => format!("{}{range}", ty.markdown_name()),
    }
}

/// A parameter's default as the reference writes it: a value as code,
/// prose as it is.
fn default_text(p: &Param) -> String {
    match p.default {
        "required" => "**required**".into(),
        "" => "—".into(),
        d if d.contains('`') || (d.contains(' ') && !d.starts_with('[')) => cell(d),
        d => format!("`{}`", cell(d)),
    }
}

/// The table of a plugin's keys.
pub fn table(schema: &Schema) -> String {
    if schema.params.is_empty() {
        return "No keys.\n".into();
    }
    let mut out = String::from("| key | type | default | meaning |\n|---|---|---|---|\n");
    for p in schema.params {
        out += &format!(
            "| `{}` | {} | {} | {} |\n",
            p.name,
            cell(&type_text(p)),
            default_text(p),
            cell(p.doc)
        );
    }
    out
}

/// What the reference says of Mitsuba beside a plugin's table: the Mitsuba
/// plugins read as it, the keys under other names or Penumbra's own, and
/// what differs. Only for the kinds the Mitsuba reader maps through their
/// schemas.
fn mitsuba_note(kind: Kind, schema: &Schema) -> Option<String> {
    let plugins: Vec<&Plugin> = schemas::plugins(kind)
        .iter()
        .filter(|p| p.schema == schema)
        .collect();
    if plugins.is_empty() {
        return None;
    }
    if schema.mitsuba.is_empty() {
        return Some("Penumbra's own: no Mitsuba 3 plugin reads as it.\n".into());
    }
    let names: Vec<String> = schema.mitsuba.iter().map(|n| format!("`{n}`")).collect();
    let mut note = format!("Mitsuba 3: the {} {} ", kind.name(), names.join(", "));
    let mut parts = Vec::new();
    let renamed: Vec<String> = schema
        .params
        .iter()
        .filter_map(|p| match p.mitsuba {
            MitsubaKey::Named(n) => Some(format!("`{}` as `{n}`", p.name)),
            MitsubaKey::Any => Some(format!("`{}` as its one texture", p.name)),
            _ => None,
        })
        .collect();
    if !renamed.is_empty() {
        parts.push(format!("names {}", renamed.join(", ")));
    }
    let held: Vec<String> = schema
        .params
        .iter()
        .filter(|p| p.ty == Type::Material)
        .map(|p| format!("`{}`", p.name))
        .collect();
    if !held.is_empty() {
        parts.push(format!(
            "sets {} from its nested `<bsdf>`s, in order",
            held.join(", ")
        ));
    }
    let phases: Vec<String> = schema
        .params
        .iter()
        .filter(|p| p.ty == Type::Phase)
        .map(|p| format!("`{}`", p.name))
        .collect();
    if !phases.is_empty() {
        parts.push(format!(
            "sets {} from its nested `<phase>`s, in order",
            phases.join(", ")
        ));
    }
    let own: Vec<String> = schema
        .params
        .iter()
        .filter(|p| p.mitsuba == MitsubaKey::None && !p.ty.is_held())
        .map(|p| format!("`{}`", p.name))
        .collect();
    let mut reads: Vec<String> = Vec::new();
    for n in plugins.iter().flat_map(|p| p.mitsuba.reads) {
        let n = format!("`{n}`");
        if !reads.contains(&n) {
            reads.push(n);
        }
    }
    if own.len() == schema.params.len() && !reads.is_empty() {
        // An adapter makes every key of what Mitsuba's plugin reads.
        note += &format!(
            "has none of these keys: they are made from its {}",
            reads.join(", ")
        );
    } else {
        if !own.is_empty() {
            parts.push(format!("has no {}", own.join(", ")));
        }
        if parts.is_empty() {
            note += "takes these keys under the same names";
        } else {
            note += &format!("takes these keys but {}", parts.join("; "));
        }
    }
    note += ".";
    let differing: Vec<&&Plugin> = plugins
        .iter()
        .filter(|p| !p.mitsuba.differences.is_empty())
        .collect();
    for p in &differing {
        let of = if plugins.len() == 1 {
            String::new()
        } else {
            let names: Vec<String> = p.names.iter().map(|n| format!("`{n}`")).collect();
            format!(" of {}", names.join(", "))
        };
        note += &format!(" Differences{of}: {}.", p.mitsuba.differences);
    }
    Some(note + "\n")
}

/// The generated block of a plugin.
pub fn block(kind: Kind, schema: &Schema) -> String {
    let mut out = table(schema);
    if let Some(note) = mitsuba_note(kind, schema) {
        out += "\n";
        out += &note;
    }
    out
}

/// `text` with the body between the markers `<!-- ID begin…-->` and
/// `<!-- ID end -->` replaced by `body`; `None` without the markers.
pub fn replace_block(text: &str, id: &str, body: &str) -> Option<String> {
    let begin = format!("<!-- {id} begin");
    let end = format!("<!-- {id} end -->");
    let start = text.find(&begin)?;
    let inner = start + text[start..].find('\n')? + 1;
    let stop = inner + text[inner..].find(&end)?;
    Some(format!("{}{}{}", &text[..inner], body, &text[stop..]))
}

/// The scene-format reference `text` with every plugin's block written
/// afresh, and the blocks it lacks (by marker name).
pub fn scene_format(text: &str) -> (String, Vec<String>) {
    scene_format_with(text, &[])
}

/// [`scene_format`], with the blocks of `integrators` too: those whose
/// keys are not render options, whose schemas the integrator layer (above
/// this one) hands over.
pub fn scene_format_with(text: &str, integrators: &[&'static Schema]) -> (String, Vec<String>) {
    let mut out = text.to_string();
    let mut missing = Vec::new();
    let held = integrators.iter().map(|&s| (Kind::Integrator, s));
    for (kind, schema) in documented().into_iter().chain(held) {
        let id = format!("plugin:{}", block_id(kind, schema));
        match replace_block(&out, &id, &block(kind, schema)) {
            Some(t) => out = t,
            None => missing.push(id),
        }
    }
    (out, missing)
}

/// The table of the Mitsuba plugins of `kind` that the reader maps
/// through their schemas, as `registry` lists them.
pub fn mitsuba_table(kind: Kind, registry: Registry) -> String {
    let mut out =
        String::from("| Mitsuba | parameters read | Penumbra | differences |\n|---|---|---|---|\n");
    for Plugin {
        schema,
        names,
        mitsuba,
    } in registry(kind)
    {
        if names.is_empty() {
            continue;
        }
        let tags: Vec<String> = names
            .iter()
            .map(|n| format!("`<{} type=\"{n}\">`", kind.name()))
            .collect();
        let mut read: Vec<String> = schema
            .params
            .iter()
            .filter_map(|p| {
                let name = match p.mitsuba {
                    MitsubaKey::Any => "any nested texture".to_string(),
                    _ if p.ty == Type::Material => format!("a nested `<bsdf>` as `{}`", p.name),
                    _ if p.ty == Type::Phase => format!("a nested `<phase>` as `{}`", p.name),
                    _ => format!("`{}`", p.mitsuba_name()?),
                };
                // Required in Penumbra, and in Mitsuba unless the
                // plugin's adapter supplies Mitsuba's default.
                let default = match p.default {
                    "required" if mitsuba.adapt.is_none() => " (required)".to_string(),
                    _ => String::new(),
                };
                let texture = if p.texturable() { ", texture" } else { "" };
                Some(format!("{name}{default}{texture}"))
            })
            .collect();
        read.extend(mitsuba.reads.iter().map(|n| format!("`{n}`")));
        let read = if read.is_empty() {
            "none".to_string()
        } else {
            read.join("; ")
        };
        let differences = if mitsuba.differences.is_empty() {
            "—"
        } else {
            mitsuba.differences
        };
        out += &format!(
            "| {} | {} | `{}` | {} |\n",
            tags.join(", "),
            cell(&read),
            schema.plugin,
            cell(differences)
        );
    }
    out
}

/// The Mitsuba reference `text` with the table of every kind `registry`
/// maps through the schemas written afresh, and the tables it lacks. The
/// registry is the reader's (`integrator::plugins::registry`), whose
/// integrators sit above the scene.
pub fn mitsuba(text: &str, registry: Registry) -> (String, Vec<String>) {
    let mut out = text.to_string();
    let mut missing = Vec::new();
    for kind in Kind::ALL {
        if registry(kind).is_empty() {
            continue;
        }
        let id = format!("mitsuba:{}", kind.name());
        match replace_block(&out, &id, &mitsuba_table(kind, registry)) {
            Some(t) => out = t,
            None => missing.push(id),
        }
    }
    (out, missing)
}
