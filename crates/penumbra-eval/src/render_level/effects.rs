//! The six effects on the built-in `showcase` scene, each isolated: every
//! other effect has a single `grid` ray (see the module above) and the
//! camera is a pinhole unless the effect is depth of field.

use penumbra::sampling::{Distribution, Domain};
use penumbra::scene::Overrides;

use crate::convergence::Effect;
use crate::job::{Crop, Variant};

/// An effect of the showcase with the reference its distributions are
/// measured against.
#[derive(Clone, Copy, Debug)]
pub struct Isolated {
    pub effect: Effect,
    /// What the crop shows.
    pub description: &'static str,
    /// The distribution whose many-ray renders are the reference for a
    /// distribution (see the module above).
    pub reference: fn(Distribution) -> Distribution,
}

impl Isolated {
    /// Every effect one `grid` ray (the perfect one), a pinhole camera.
    pub fn overrides() -> Overrides {
        Overrides {
            distribution: Some(Distribution::Grid),
            spp: Some(1),
            shadow_rays: Some(1),
            reflection_rays: Some(1),
            refraction_rays: Some(1),
            aperture: Some(0.0),
            ..Default::default()
        }
    }

    /// The distinct reference distributions, in the order of
    /// `Distribution::ALL`.
    pub fn reference_distributions(&self) -> Vec<Distribution> {
        let mut out: Vec<Distribution> = Vec::new();
        for d in Distribution::ALL.map(self.reference) {
            if !out.contains(&d) {
                out.push(d);
            }
        }
        out
    }
}

fn penumbra(o: &mut Overrides, n: u32, d: Distribution) {
    o.shadow_rays = Some(n);
    o.shadow_distribution = Some(d);
}

fn glossy_reflection(o: &mut Overrides, n: u32, d: Distribution) {
    o.reflection_rays = Some(n);
    o.reflection_distribution = Some(d);
}

/// Two levels of rays: the pane's set, and one more level behind it (a
/// pane's ray reflected by the glossy sphere onto the frosted one would
/// otherwise start a second set of N rays).
fn glossy_refraction(o: &mut Overrides, n: u32, d: Distribution) {
    o.refraction_rays = Some(n);
    o.refraction_distribution = Some(d);
    o.max_depth = Some(2);
}

fn depth_of_field(o: &mut Overrides, n: u32, d: Distribution) {
    o.spp = Some(n);
    o.lens_distribution = Some(d);
    o.pixel_distribution = Some(d);
    o.aperture = Some(0.15);
    o.focal_distance = Some(5.0);
}

fn motion_blur(o: &mut Overrides, n: u32, d: Distribution) {
    o.spp = Some(n);
    o.time_distribution = Some(d);
    o.pixel_distribution = Some(d);
}

fn anti_aliasing(o: &mut Overrides, n: u32, d: Distribution) {
    o.spp = Some(n);
    o.pixel_distribution = Some(d);
}

/// Every distribution converges to the `jitter` reference (lights and
/// lenses).
fn shared(_: Distribution) -> Distribution {
    Distribution::Jitter
}

/// Film positions: `random`'s disk is its own limit.
fn film(d: Distribution) -> Distribution {
    if d.domain() == Domain::Disk {
        d
    } else {
        Distribution::Jitter
    }
}

/// End points of reflected and refracted rays: `random`'s disk and
/// `fast-random`'s cube are their own limits.
fn end_points(d: Distribution) -> Distribution {
    if d.domain() == Domain::Square {
        Distribution::Jitter
    } else {
        d
    }
}

/// The six effects.
pub const EFFECTS: [Isolated; 6] = [
    Isolated {
        effect: Effect {
            name: "penumbra",
            scene: "showcase",
            crop: Crop::new(0.0, 0.56, 0.2, 0.8),
            unit: "shadow rays per hit",
            apply: penumbra,
            variant: Variant::AsIs,
        },
        description: "the floor left of the mirror sphere with the edge of its soft shadow",
        reference: shared,
    },
    Isolated {
        effect: Effect {
            name: "glossy reflection",
            scene: "showcase",
            crop: Crop::new(0.42, 0.36, 0.6, 0.6),
            unit: "reflection rays per hit",
            apply: glossy_reflection,
            variant: Variant::AsIs,
        },
        description:
            "the glossy red sphere, which reflects the mirror sphere, the floor and the sky",
        reference: end_points,
    },
    Isolated {
        effect: Effect {
            name: "glossy refraction",
            scene: "showcase",
            crop: Crop::new(0.5, 0.36, 0.9, 0.72),
            unit: "refraction rays per hit",
            apply: glossy_refraction,
            variant: Variant::FrostedPane,
        },
        description: "a single frosted pane (the showcase's `frosted` material, one interface) \
                      in front of the glossy sphere, the gold ball and the glass sphere; its \
                      Fresnel reflection uses the refraction budget too",
        reference: end_points,
    },
    Isolated {
        effect: Effect {
            name: "depth of field",
            scene: "showcase",
            crop: Crop::new(0.1, 0.28, 0.35, 0.55),
            unit: "primary rays (lens and film)",
            apply: depth_of_field,
            variant: Variant::AsIs,
        },
        description: "the mirror sphere behind the plane in focus (aperture 0.15, focus at 5)",
        reference: film,
    },
    Isolated {
        effect: Effect {
            name: "motion blur",
            scene: "showcase",
            crop: Crop::new(0.52, 0.5, 0.75, 0.72),
            unit: "primary rays (time and film)",
            apply: motion_blur,
            variant: Variant::AsIs,
        },
        description: "the gold ball rolling to the right while the shutter is open",
        reference: film,
    },
    Isolated {
        effect: Effect {
            name: "anti-aliasing",
            scene: "showcase",
            crop: Crop::new(0.7, 0.33, 0.95, 0.6),
            unit: "primary rays (film)",
            apply: anti_aliasing,
            variant: Variant::AsIs,
        },
        description: "the clear glass sphere on the right: its rim, highlight and the refracted \
                      horizon",
        reference: film,
    },
];
