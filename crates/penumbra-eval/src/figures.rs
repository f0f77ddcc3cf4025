//! Figures 4.1–4.10 of the thesis, rendered: the same settings side by side,
//! one composed SVG per figure, each panel labelled with its setting.

use std::path::Path;

use penumbra::render::Image;
use penumbra::sampling::Distribution;
use penumbra::scene::Overrides;
use serde::Serialize;

use crate::compose::{difference, enlarge, save_grid, shrink, to_rgb8, Panel};
use crate::error::EvalError;
use crate::format::rays;
use crate::job::{Crop, Job, Variant};
use crate::plan::Plan;
use crate::runner::Runner;
use crate::tables::{frame, metric_jobs};

/// Where the head of the bunny is in the `bunny` frame (Figure 4.1).
const HEAD: Crop = Crop::new(0.26, 0.10, 0.56, 0.50);
/// The bunnies of `bunnies-dof`.
const BUNNIES: Crop = Crop::new(0.1, 0.2, 0.9, 0.8);
/// The bunny's feet and its (blurred) reflection in the floor of
/// `bunny-reflect`: the reflection of the lit back shows near the bottom
/// of the frame.
const REFLECTION: Crop = Crop::new(0.3, 0.68, 0.8, 1.0);
/// The bunny seen through the pane of `bunny-glass`.
const GLASS: Crop = Crop::new(0.2, 0.1, 0.8, 0.9);
/// The shadow around the bunny's feet in `bunny`.
const SHADOW: Crop = Crop::new(0.12, 0.5, 0.82, 0.95);

/// Panels narrower than this are enlarged (whole pixels), wider than
/// [`MAX_PANEL`] shrunk, so that every figure reads at a similar size.
const MIN_PANEL: u32 = 240;
const MAX_PANEL: u32 = 640;

/// A written figure.
#[derive(Clone, Debug, Serialize)]
pub struct Figure {
    pub id: String,
    pub title: String,
    pub caption: String,
    /// Path relative to the output directory.
    pub file: String,
    pub panels: Vec<String>,
}

/// Where a panel's pixels come from (a figure has a few: the size of the
/// two-job variant costs nothing).
#[allow(clippy::large_enum_variant)]
enum Source {
    Render(Job),
    /// |a − b|, amplified.
    Difference(Job, Job, f32),
}

struct PanelSpec {
    label: String,
    source: Source,
    /// Cut out of the rendered image afterwards (for whole frames shared
    /// with a table).
    crop: Option<Crop>,
}

struct FigureSpec {
    id: &'static str,
    title: &'static str,
    caption: String,
    cols: usize,
    panels: Vec<PanelSpec>,
}

fn render(label: impl Into<String>, job: Job) -> PanelSpec {
    PanelSpec {
        label: label.into(),
        source: Source::Render(job),
        crop: None,
    }
}

fn o(plan: &Plan, f: impl FnOnce(&mut Overrides)) -> Overrides {
    let mut o = frame(plan.figure);
    f(&mut o);
    o
}

fn spec_4_1(plan: &Plan) -> FigureSpec {
    let panels = [1u32, 4, 8, 16]
        .into_iter()
        .map(|n| {
            let label = if n == 1 {
                "1 ray".to_string()
            } else {
                format!("{n}x supersampling")
            };
            let job = Job::new(
                format!("Figure 4.1: {label}"),
                "bunny",
                o(plan, |o| o.spp = Some(n)),
            );
            render(label, job.with_crop(HEAD))
        })
        .collect();
    FigureSpec {
        id: "4.1",
        title: "Supersampling",
        caption: "A crop of the bunny's head with 1, 4, 8 and 16 primary rays per pixel (grid). \
                  Without supersampling every edge shows staircases; 4x removes almost all of \
                  them and 8x or 16x add little, as the thesis found."
            .into(),
        cols: 2,
        panels,
    }
}

/// (aperture, focal distance) of Figure 4.2: small/wide aperture, focus on
/// the middle bunny (short, distance 5) or the rear one (long, 8). The
/// front bunny is mostly outside the frame of `bunnies-dof`.
const DOF: [(&str, f32, f32); 4] = [
    ("small aperture, short focus", 0.04, 5.0),
    ("small aperture, long focus", 0.04, 8.0),
    ("wide aperture, short focus", 0.15, 5.0),
    ("wide aperture, long focus", 0.15, 8.0),
];

fn dof_job(plan: &Plan, what: &str, aperture: f32, focus: f32, spp: u32) -> Job {
    let ov = o(plan, |o| {
        o.spp = Some(spp);
        o.aperture = Some(aperture);
        o.focal_distance = Some(focus);
    });
    Job::new(
        format!(
            "{what}: aperture {aperture}, focus {focus}, {}",
            rays(spp, "")
        ),
        "bunnies-dof",
        ov,
    )
    .with_crop(BUNNIES)
}

fn spec_4_2(plan: &Plan) -> FigureSpec {
    let panels = DOF
        .iter()
        .map(|&(label, a, f)| {
            render(
                format!("{label} ({a}, {f})"),
                dof_job(plan, "Figure 4.2", a, f, 4),
            )
        })
        .collect();
    FigureSpec {
        id: "4.2",
        title: "Depth of field settings",
        caption: "Thin lens with 4 primary rays (grid): aperture radius 0.04 (top) or 0.15 \
                  (bottom), focused at distance 5 on the middle bunny (left) or 8 on the rear \
                  one (right); the bunny at the left edge is nearer still. Panel labels give (aperture, focal distance)."
            .into(),
        cols: 2,
        panels,
    }
}

fn spec_4_3(plan: &Plan) -> FigureSpec {
    let (_, a, f) = DOF[2];
    let panels = [8u32, 16]
        .into_iter()
        .map(|n| {
            render(
                format!("{n} primary rays"),
                dof_job(plan, "Figure 4.3", a, f, n),
            )
        })
        .collect();
    FigureSpec {
        id: "4.3",
        title: "Wide aperture needs more primary rays",
        caption: format!(
            "The wide aperture ({a}) focused on the middle bunny with 8 (left) and 16 (right) \
             primary rays (grid; 8 uses 8 of the 9 points of a 3×3 grid). With 8 the copies of \
             the blurred bunnies are still distinct; 16 is the least that looks smooth."
        ),
        cols: 2,
        panels,
    }
}

fn reflect_job(plan: &Plan, fig: &str, rays: u32, d: Distribution) -> Job {
    let ov = o(plan, |o| {
        o.spp = Some(4);
        o.reflection_rays = Some(rays);
        o.reflection_distribution = Some(d);
    });
    Job::new(
        format!("Figure {fig}: {} reflection, {rays} rays", d.name()),
        "bunny-reflect",
        ov,
    )
    .with_crop(REFLECTION)
}

fn spec_4_4(plan: &Plan) -> FigureSpec {
    let mut panels = vec![render(
        "1 ray (standard)",
        reflect_job(plan, "4.4", 1, Distribution::Grid),
    )];
    for d in Distribution::THESIS {
        panels.push(render(
            format!("{}, 4 rays", d.name()),
            reflect_job(plan, "4.4", 4, d),
        ));
    }
    FigureSpec {
        id: "4.4",
        title: "Blurry reflection with each distribution, 4 rays",
        caption: "The floor reflects the bunny (4x supersampling, 4 reflection rays) with each \
                  of the six distributions, and one mirror ray for comparison (top left). Grid \
                  shows four distinct copies of the reflection, semi-jitter softer copies; \
                  jitter, Poisson and random trade the copies for noise."
            .into(),
        cols: 4,
        panels,
    }
}

fn spec_4_5(plan: &Plan) -> FigureSpec {
    let panels = Distribution::THESIS
        .into_iter()
        .map(|d| {
            render(
                format!("{}, 32 rays", d.name()),
                reflect_job(plan, "4.5", 32, d),
            )
        })
        .collect();
    FigureSpec {
        id: "4.5",
        title: "Blurry reflection with each distribution, 32 rays",
        caption: "The same with 32 reflection rays: every distribution gives a smooth blur \
                  (grid and semi-jitter use 32 of the 36 points of a 6×6 grid)."
            .into(),
        cols: 3,
        panels,
    }
}

fn spec_4_6(plan: &Plan) -> FigureSpec {
    let panels = [1u32, 4]
        .into_iter()
        .map(|n| {
            let ov = o(plan, |o| o.refraction_rays = Some(n));
            let label = if n == 1 {
                "1 ray (standard)".to_string()
            } else {
                format!("{n} rays, grid")
            };
            render(
                label.clone(),
                Job::new(format!("Figure 4.6: {label}"), "bunny-glass", ov).with_crop(GLASS),
            )
        })
        .collect();
    FigureSpec {
        id: "4.6",
        title: "Blurry transmission",
        caption: "The bunny behind a pane of glass: one refraction ray (left) shows it sharp \
                  and magnified; 4 refraction rays with the grid distribution blur it (right)."
            .into(),
        cols: 2,
        panels,
    }
}

fn spec_4_7_4_8(plan: &Plan) -> Vec<FigureSpec> {
    // The renders of Table 4.4's first and last rows, shared with the table.
    let (Some((on, Some(off))), Some((right, _))) =
        (metric_jobs(plan, 0, 0), metric_jobs(plan, 0, 2))
    else {
        return Vec::new();
    };
    let h = plan.heavy_metric_rays;
    let cropped = |label: &str, source| PanelSpec {
        label: label.into(),
        source,
        crop: Some(REFLECTION),
    };
    let fig_4_7 = FigureSpec {
        id: "4.7",
        title: "Reflection metric on and off",
        caption: "The first row of Table 4.4 (4 reflection and 4 shadow rays, 4x supersampling), \
                  cropped: with the reflection metric (left), without (middle), and their \
                  difference amplified ten times (right). The metric's wrong decisions are \
                  scattered single pixels near edges."
            .into(),
        cols: 3,
        panels: vec![
            cropped("with metric", Source::Render(on.clone())),
            cropped("without metric", Source::Render(off.clone())),
            cropped("difference x10", Source::Difference(on.clone(), off, 10.0)),
        ],
    };
    let fig_4_8 = FigureSpec {
        id: "4.8",
        title: "The two scenes of the performance tests",
        caption: format!(
            "Whole frames of the metric tables, both with metric and 4x supersampling: the \
             reflective floor with 4 reflection and 4 shadow rays (left) and the reflective \
             floor and bunny with {h} of each (right)."
        ),
        cols: 2,
        panels: vec![
            render("4r 4s 4x, metric", on),
            render(format!("{h}r {h}s 4x, metric"), right),
        ],
    };
    vec![fig_4_7, fig_4_8]
}

fn shadow_job(
    plan: &Plan,
    label: &str,
    rays: u32,
    d: Distribution,
    spp: u32,
    v: Variant,
) -> PanelSpec {
    let ov = o(plan, |o| {
        o.spp = Some(spp);
        o.shadow_rays = Some(rays);
        o.shadow_distribution = Some(d);
    });
    let job = Job::new(format!("Figure 4.9/4.10: {label}"), "bunny", ov)
        .with_crop(SHADOW)
        .with_variant(v);
    render(label, job)
}

fn spec_4_9_4_10(plan: &Plan) -> [FigureSpec; 2] {
    use Distribution::{Grid, Jitter, Random};
    let fig_4_9 = FigureSpec {
        id: "4.9",
        title: "Penumbra with 9 shadow rays",
        caption: "Top left: a point light (1 shadow ray, 4x supersampling) casts a hard shadow. \
                  Top right: 9 shadow rays, grid, no supersampling: the penumbra is banded. \
                  Bottom: 9 shadow rays, jitter, with 4x supersampling (left) and without \
                  (right): noisy, smoother with supersampling, but not smooth."
            .into(),
        cols: 2,
        panels: vec![
            shadow_job(plan, "point light, 4x", 1, Grid, 4, Variant::PointLight),
            shadow_job(plan, "9 rays grid, 1x", 9, Grid, 1, Variant::AsIs),
            shadow_job(plan, "9 rays jitter, 4x", 9, Jitter, 4, Variant::AsIs),
            shadow_job(plan, "9 rays jitter, 1x", 9, Jitter, 1, Variant::AsIs),
        ],
    };
    let fig_4_10 = FigureSpec {
        id: "4.10",
        title: "Penumbra with 32 shadow rays",
        caption: "32 shadow rays with the random distribution and 4x supersampling: a smooth \
                  penumbra with little visible noise."
            .into(),
        cols: 1,
        panels: vec![shadow_job(
            plan,
            "32 rays random, 4x",
            32,
            Random,
            4,
            Variant::AsIs,
        )],
    };
    [fig_4_9, fig_4_10]
}

fn specs(plan: &Plan) -> Vec<FigureSpec> {
    let mut v = vec![
        spec_4_1(plan),
        spec_4_2(plan),
        spec_4_3(plan),
        spec_4_4(plan),
        spec_4_5(plan),
        spec_4_6(plan),
    ];
    v.extend(spec_4_7_4_8(plan));
    v.extend(spec_4_9_4_10(plan));
    v
}

/// Every job the figures need, for planning.
pub fn jobs(plan: &Plan) -> Vec<Job> {
    let mut out = Vec::new();
    for f in specs(plan) {
        for p in f.panels {
            match p.source {
                Source::Render(j) => out.push(j),
                Source::Difference(a, b, _) => out.extend([a, b]),
            }
        }
    }
    out
}

/// Renders and writes every figure into `dir` (`figures/fig-4.N.svg`).
pub fn run(runner: &mut Runner, plan: &Plan, dir: &Path) -> Result<Vec<Figure>, EvalError> {
    let mut out = Vec::new();
    for spec in specs(plan) {
        let mut panels = Vec::new();
        for p in &spec.panels {
            let image = match &p.source {
                Source::Render(j) => runner.run(j)?.image.clone(),
                Source::Difference(a, b, gain) => {
                    difference(&runner.run(a)?.image, &runner.run(b)?.image, *gain)
                }
            };
            let image = p.crop.map_or(image.clone(), |c| crop_image(&image, c));
            panels.push(Panel {
                label: p.label.clone(),
                image: to_rgb8(&image),
            });
        }
        let panels = display_size(panels);
        let file = format!("figures/fig-{}.svg", spec.id);
        save_grid(&dir.join(&file), &panels, spec.cols)?;
        out.push(Figure {
            id: spec.id.into(),
            title: spec.title.into(),
            caption: spec.caption,
            file,
            panels: panels.into_iter().map(|p| p.label).collect(),
        });
    }
    Ok(out)
}

/// Cuts a crop (fractions of the image) out of a whole-frame render.
pub fn crop_image(image: &Image, c: Crop) -> Image {
    let r = c.region(image.width, image.height);
    let mut out = Image::new(r.width(), r.height());
    for y in 0..r.height() {
        for x in 0..r.width() {
            out.pixels[(y * r.width() + x) as usize] = image.get(r.x0 + x, r.y0 + y);
        }
    }
    out
}

/// Enlarges small panels and shrinks large ones by a whole factor shared by
/// the figure, so that panels of one figure keep their relative size.
fn display_size(panels: Vec<Panel>) -> Vec<Panel> {
    let widest = panels
        .iter()
        .map(|p| p.image.width())
        .max()
        .unwrap_or(MIN_PANEL);
    let resize: Box<dyn Fn(&image::RgbImage) -> image::RgbImage> = if widest < MIN_PANEL {
        let k = MIN_PANEL.div_ceil(widest.max(1)).min(4);
        Box::new(move |i| enlarge(i, k))
    } else if widest > MAX_PANEL {
        let k = widest.div_ceil(MAX_PANEL);
        Box::new(move |i| shrink(i, k))
    } else {
        Box::new(|i| i.clone())
    };
    panels
        .into_iter()
        .map(|p| Panel {
            image: resize(&p.image),
            label: p.label,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ten_figures_in_order_with_their_panels() {
        let s = specs(&Plan::new(true));
        let ids: Vec<&str> = s.iter().map(|f| f.id).collect();
        assert_eq!(
            ids,
            ["4.1", "4.2", "4.3", "4.4", "4.5", "4.6", "4.7", "4.8", "4.9", "4.10"]
        );
        let count: Vec<usize> = s.iter().map(|f| f.panels.len()).collect();
        assert_eq!(count, [4, 4, 2, 7, 6, 2, 3, 2, 4, 1]);
    }

    #[test]
    fn figures_4_7_and_4_8_reuse_the_table_renders() {
        let plan = Plan::new(true);
        let tables: std::collections::HashSet<String> =
            crate::tables::jobs(&plan).iter().map(Job::key).collect();
        let figs = specs(&plan);
        for f in figs.iter().filter(|f| f.id == "4.7" || f.id == "4.8") {
            for p in &f.panels {
                let keys = match &p.source {
                    Source::Render(j) => vec![j.key()],
                    Source::Difference(a, b, _) => vec![a.key(), b.key()],
                };
                assert!(
                    keys.iter().all(|k| tables.contains(k)),
                    "{}: {}",
                    f.id,
                    p.label
                );
            }
        }
    }

    #[test]
    fn panels_are_brought_to_a_readable_size() {
        let small = Panel {
            label: "s".into(),
            image: image::RgbImage::new(80, 60),
        };
        let out = display_size(vec![small]);
        assert_eq!(out[0].image.width(), 240);
        let big = Panel {
            label: "b".into(),
            image: image::RgbImage::new(800, 600),
        };
        assert_eq!(display_size(vec![big])[0].image.width(), 400);
        let fits = Panel {
            label: "f".into(),
            image: image::RgbImage::new(640, 360),
        };
        assert_eq!(display_size(vec![fits])[0].image.width(), 640);
    }
}
