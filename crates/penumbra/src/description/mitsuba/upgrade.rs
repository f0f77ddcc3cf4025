//! Scenes of Mitsuba 0.5 and 0.6 (a `version` below 2.0), upgraded as
//! Mitsuba 3 upgrades them: every parameter name from camelCase to
//! snake_case (`maxDepth` → `max_depth`), a diffuse material's
//! `diffuse_reflectance` named `reflectance`, and `uoffset`, `voffset`,
//! `uscale`, `vscale` made one `to_uv` transform (scale · translate).

use super::parse::{Attr, Element};

/// `fooBarBAZ` → `foo_barbaz`: an upper-case letter after a lower-case one
/// starts a new word, and the upper-case letters after it join that word.
pub fn snake_case(name: &str) -> String {
    let chars: Vec<char> = name.chars().collect();
    let mut out = String::with_capacity(name.len() + 4);
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if i > 0 && chars[i - 1].is_ascii_lowercase() && c.is_ascii_uppercase() {
            out.push('_');
            out.push(c.to_ascii_lowercase());
            while i + 1 < chars.len() && chars[i + 1].is_ascii_uppercase() {
                i += 1;
                out.push(chars[i].to_ascii_lowercase());
            }
        } else {
            out.push(c);
        }
        i += 1;
    }
    out
}

/// Upgrades the elements of old files in `e` and below.
pub fn upgrade(e: &mut Element) {
    if e.old {
        for a in e.attrs.iter_mut().filter(|a| a.name == "name") {
            a.value = snake_case(&a.value);
        }
    }
    for child in &mut e.children {
        upgrade(child);
    }
    if !e.old {
        return;
    }
    if e.get("type") == Some("diffuse") {
        for child in &mut e.children {
            for a in child.attrs.iter_mut() {
                if a.name == "name" && a.value == "diffuse_reflectance" {
                    a.value = "reflectance".into();
                }
            }
        }
    }
    to_uv(e);
}

/// `uoffset`, `voffset`, `uscale`, `vscale` (floats) into a `to_uv`
/// transform: translate by the offsets, then scale.
fn to_uv(e: &mut Element) {
    let named = |c: &Element, n: &str| c.tag == "float" && c.get("name") == Some(n);
    let take = |e: &mut Element, n: &str| -> Option<Attr> {
        let i = e.children.iter().position(|c| named(c, n))?;
        e.children.remove(i).attr("value").cloned()
    };
    let (uo, vo, us, vs) = (
        take(e, "uoffset"),
        take(e, "voffset"),
        take(e, "uscale"),
        take(e, "vscale"),
    );
    let Some(first) = [&uo, &vo, &us, &vs].into_iter().flatten().next().cloned() else {
        return;
    };
    let at = first.at.clone();
    let op = |tag: &str, x: Option<Attr>, y: Option<Attr>| {
        let mut attrs = Vec::new();
        for (axis, v) in [("x", x), ("y", y)] {
            if let Some(mut v) = v {
                v.name = axis.into();
                attrs.push(v);
            }
        }
        Element {
            tag: tag.into(),
            attrs,
            children: Vec::new(),
            at: at.clone(),
            dir: e.dir.clone(),
            old: true,
        }
    };
    let translate = op("translate", uo, vo);
    let scale = op("scale", us, vs);
    e.children.push(Element {
        tag: "transform".into(),
        attrs: vec![Attr {
            name: "name".into(),
            value: "to_uv".into(),
            at: at.clone(),
        }],
        children: vec![translate, scale],
        at,
        dir: e.dir.clone(),
        old: true,
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camel_case_becomes_snake_case() {
        assert_eq!(snake_case("maxDepth"), "max_depth");
        assert_eq!(snake_case("diffuseReflectance"), "diffuse_reflectance");
        assert_eq!(snake_case("sampleCount"), "sample_count");
        assert_eq!(snake_case("fovAxis"), "fov_axis");
        assert_eq!(snake_case("toWorld"), "to_world");
        assert_eq!(snake_case("intIOR"), "int_ior");
        assert_eq!(snake_case("already_snake"), "already_snake");
        assert_eq!(snake_case("URL"), "URL");
    }
}
