//! Built-in scenes, usable wherever a scene path is accepted. They are
//! ordinary scene files (in `crates/penumbra/scenes/`) compiled into the
//! binary, so they double as examples of the format.

/// A scene shipped with the renderer.
pub struct Builtin {
    pub name: &'static str,
    pub description: &'static str,
    pub toml: &'static str,
    /// True if the scene needs the Stanford bunny.
    pub needs_bunny: bool,
}

macro_rules! builtin {
    ($name:literal, $bunny:literal, $desc:literal) => {
        Builtin {
            name: $name,
            description: $desc,
            toml: include_str!(concat!("../../scenes/", $name, ".toml")),
            needs_bunny: $bunny,
        }
    };
}

pub const SCENES: &[Builtin] = &[
    builtin!(
        "showcase",
        false,
        "the default: every effect at once, no external files"
    ),
    builtin!(
        "cornell-box",
        false,
        "the Cornell box, rendered by the path tracer"
    ),
    builtin!(
        "materials",
        false,
        "every scattering model on a sphere, under a procedural sky, path traced"
    ),
    builtin!(
        "fog",
        false,
        "the thesis's glass, mirror and diffuse spheres in fog under a spot light: light shafts, volpath"
    ),
    builtin!(
        "bunny",
        true,
        "the thesis's setting: Stanford bunny on a ground quad under a rectangle light"
    ),
    builtin!(
        "bunny-reflect",
        true,
        "the bunny on a reflective floor (thesis Fig. 4.4)"
    ),
    builtin!(
        "bunny-mirror",
        true,
        "reflective floor and reflective bunny: exponential ray growth (Table 4.3)"
    ),
    builtin!(
        "bunny-glass",
        true,
        "a frosted glass pane in front of the bunny (Fig. 4.6)"
    ),
    builtin!(
        "bunnies-dof",
        true,
        "three bunnies at different depths, thin-lens depth of field (Figs. 4.2-4.3)"
    ),
    builtin!(
        "bunny-gi",
        true,
        "the bunny in a corner of coloured walls, path traced: colour bleeding, soft shadows"
    ),
    builtin!(
        "bunny-motion",
        true,
        "the bunny sliding and turning during the exposure: motion blur"
    ),
];

/// The built-in scene with this name.
pub fn find(name: &str) -> Option<&'static Builtin> {
    SCENES.iter().find(|b| b.name == name)
}
