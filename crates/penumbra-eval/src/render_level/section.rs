//! The render level as blocks of the study's document.

use crate::doc::{Block, Table};
use crate::fit;
use crate::format::{seconds, signed};

use super::results::{EffectResult, RenderLevel};

fn p(s: impl Into<String>) -> Block {
    Block::Paragraph(s.into())
}

/// The level's blocks, headed at `level`.
pub fn blocks(r: &RenderLevel, level: u8) -> Vec<Block> {
    let counts = r
        .counts
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(", ");
    let mut out = vec![
        Block::Heading(level, "Renders: RMSE against a converged reference".into()),
        p(format!(
            "Six effects of the built-in `showcase` scene, each isolated: every other effect has \
             one `grid` ray (the perfect one) and the camera is a pinhole unless the effect is \
             depth of field. For each effect, distribution and N = {counts} rays of the effect \
             (`poisson` up to {}), a crop of a {}×{} frame is rendered with {} seed(s); the RMSE \
             over its pixels and channels against the reference is averaged over the seeds (as \
             the root of the mean MSE). The reference is the mean of two renders of {} rays \
             each with seeds no trial uses: `jitter` for every distribution that converges to \
             the same image, and the distribution itself for `random` (disk) and `fast-random` \
             (world-aligned cube) where an effect uses the points as they are, since they blur \
             with another kernel. The reference's own mean squared error, a quarter of the mean \
             squared difference of its halves, is subtracted from each trial's; points whose MSE \
             is below four times the reference's are drawn hollow and left out of the fits. \
             Render level measured in {} s.",
            r.poisson_max,
            r.frame.0,
            r.frame.1,
            r.seeds,
            r.reference_rays,
            seconds(r.elapsed_s)
        )),
        p(
            "How to read it: the slope against rays is the convergence rate, −0.5 for \
             independent samples and steeper for stratified and low-discrepancy ones where the \
             integrand allows (a pixel's integrand has edges, so −0.75 is the most a 2D set can \
             reach on them); a biased distribution (`grid`) flattens towards its bias. The slope \
             against time includes what the rays cost: set generation (slow for `poisson`), \
             tracing and shading. Each interval is the 95% Student-t interval of the fitted \
             slope.",
        ),
    ];
    out.extend(summary(r));
    for e in &r.effects {
        out.extend(effect(r, e, level + 1));
    }
    out
}

/// Slopes against rays: a row per distribution, a column per effect.
fn summary(r: &RenderLevel) -> Vec<Block> {
    let mut head = vec!["distribution".to_string()];
    head.extend(r.effects.iter().map(|e| e.name.clone()));
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let mut t = Table::new(&head);
    t.numeric[0] = false;
    let names: Vec<String> = r
        .effects
        .first()
        .map(|e| e.curves.iter().map(|c| c.distribution.clone()).collect())
        .unwrap_or_default();
    for name in names {
        let mut row = vec![name.clone()];
        for e in &r.effects {
            row.push(
                r.curve(&e.name, &name)
                    .map_or("–".into(), |c| fit::cell(c.fit)),
            );
        }
        t.row(row);
    }
    vec![
        p("Fitted slopes of log RMSE against log rays, with their 95% intervals:"),
        Block::Table(t),
    ]
}

fn effect(r: &RenderLevel, e: &EffectResult, level: u8) -> Vec<Block> {
    let references = e
        .references
        .iter()
        .map(|x| {
            format!(
                "`{}` (for {}; its own RMSE {:.2e})",
                x.distribution,
                x.serves.join(", "),
                x.rmse
            )
        })
        .collect::<Vec<_>>()
        .join("; ");
    let mut t = Table::new(&[
        "distribution",
        "slope against rays [95%]",
        "slope against time [95%]",
        "largest N",
        "RMSE there",
        "render time there (s)",
    ]);
    t.numeric[0] = false;
    for c in &e.curves {
        let last = c.points.last();
        t.row(vec![
            c.distribution.clone(),
            fit::cell(c.fit),
            fit::cell(c.time_fit),
            last.map_or("–".into(), |p| p.n.to_string()),
            last.map_or("–".into(), |p| format!("{:.3e}", p.rmse)),
            last.map_or("–".into(), |p| format!("{:.3}", p.seconds)),
        ]);
    }
    let random = r
        .curve(&e.name, "random")
        .and_then(|c| c.fit)
        .map_or(String::new(), |f| {
            format!(" `random` has slope {} here.", signed(f.slope))
        });
    let svg = |src: &str, what: &str| Block::Svg {
        src: src.to_string(),
        alt: format!("{}: RMSE against {what}", e.name),
        caption: format!(
            "{}: RMSE against {what}, log–log, one line per distribution; hollow dots: left out \
             of the fit (within twice the reference's noise); grey dashed: the reference's noise \
             and slope −0.5 through `random`.",
            e.name
        ),
        markup: r.svg(src).to_string(),
    };
    vec![
        Block::Heading(level, e.name.clone()),
        p(format!(
            "The crop ({}×{} pixels) shows {}; N counts {}. References: {references}.{random}",
            e.pixels.0, e.pixels.1, e.description, e.unit
        )),
        svg(&e.plot_rays, "rays"),
        svg(&e.plot_time, "render time"),
        Block::Table(t),
    ]
}
