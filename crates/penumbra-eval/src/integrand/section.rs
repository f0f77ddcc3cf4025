//! The study as a document: `distributions.md` and `distributions.html` (the
//! same blocks, the plots inline in the HTML) and `distributions.json` with
//! every number.

use crate::doc::{to_html, to_markdown, Block, Table};
use crate::error::EvalError;
use crate::format::{seconds, signed};
use crate::output::write_file;
use crate::{render_level, stopping};

use super::results::{Curve, DistributionStudy, IntegrandResult, TAIL_FROM, TOLERANCE};
use crate::fit;

const TITLE: &str =
    "Penumbra: the ray distributions on integrals, in renders and under stopping rules";

fn h(level: u8, s: impl Into<String>) -> Block {
    Block::Heading(level, s.into())
}

fn p(s: impl Into<String>) -> Block {
    Block::Paragraph(s.into())
}

/// Writes the three files; `svgs` are the plots' SVG texts in the order of
/// the integrands.
pub fn write(s: &DistributionStudy, svgs: &[String]) -> Result<(), EvalError> {
    let blocks = blocks(s, svgs);
    let json = serde_json::to_string_pretty(s).map_err(|e| EvalError::Write {
        path: s.json_path(),
        message: e.to_string(),
    })?;
    write_file(&s.markdown_path(), to_markdown(&blocks).as_bytes())?;
    write_file(&s.html_path(), to_html(TITLE, &blocks).as_bytes())?;
    write_file(&s.json_path(), json.as_bytes())
}

/// The document in reading order.
pub fn blocks(s: &DistributionStudy, svgs: &[String]) -> Vec<Block> {
    let mode = if s.quick { "quick" } else { "full" };
    let last = s.counts.last().copied().unwrap_or(0);
    let mut out = vec![
        h(1, TITLE),
        p(format!(
            "The study has three levels: integrals with known values (first), renders of six \
             effects against a converged reference, and the stopping rules of adaptive sampling \
             compared at equal RMSE (the last two when they ran: {}). Produced by `penumbra \
             reproduce --study distributions` in {mode} mode in {} s on {} threads.",
            if s.render.is_some() || s.stopping.is_some() {
                "they did"
            } else {
                "they did not"
            },
            seconds(s.elapsed_s),
            s.threads
        )),
        p(format!(
            "Every ray distribution estimates the integral over the unit square of functions whose \
             integral is known in closed form. For each distribution, integrand and number of points \
             N the error is the RMSE of the N-point mean against the exact value, over {} independent \
             sets; N runs over the powers of two from {} to {last}. Integrand level measured in {} s.",
            s.seeds,
            s.counts.first().copied().unwrap_or(0),
            seconds(s.integrand_s),
        )),
        p(format!(
            "How to read it: the slope is the least-squares fit of ln RMSE against ln N, and its \
           95% interval is slope ± t·SE with Student's t for (points − 2) degrees of freedom and \
           SE from the residuals of the fit, so it widens both with the RMSE's sampling noise and \
           with a curve that is not straight. A slope agrees with theory when it is within {TOLERANCE} of \
           the target. `grid`, `jitter` and `semi-jitter` are fitted on the square counts only \
           (4, 16, 64, …), where they have one point per cell; their other counts (hollow dots in \
           the plots) keep a random subset of cells, another estimator. `grid` is deterministic: \
           every set is the same pattern, so its RMSE is the absolute error of that pattern, a \
           bias, and it has no target. `random` gives points in a disk; they are mapped back to \
           the square through the inverse polar map, which makes them independent uniform points \
           of the square. The sets belong to no pixel, so a `zsobol` set is the first block of its \
           sequence scrambled by its seed, statistically a `sobol` set: its difference, how the \
           sets of neighbouring pixels fit together, shows only in renders. Dashed lines in the plots have the theoretical slope and pass through \
           the centre of gravity of the fitted points. Theory's rates are \
             asymptotic: the tables also give the slope fitted from N = {TAIL_FROM} on, which \
             shows whether a miss comes from the smallest sets; the verdict is on the fit over \
             every count."
        )),
    ];
    out.extend(summary(s));
    out.extend(theory(s));
    for (i, r) in s.integrands.iter().enumerate() {
        out.extend(integrand(r, svgs.get(i).map_or("", String::as_str)));
    }
    if let Some(r) = &s.render {
        out.extend(render_level::blocks(r, 2));
    }
    if let Some(st) = &s.stopping {
        out.extend(stopping::blocks(st, 2));
    }
    out
}

fn verdict(c: &Curve) -> String {
    match c.within {
        Some(true) => "yes".into(),
        Some(false) => "no".into(),
        None => "no target".into(),
    }
}

/// All slopes in one table: a row per distribution, a column per integrand.
fn summary(s: &DistributionStudy) -> Vec<Block> {
    let mut head = vec!["distribution".to_string()];
    head.extend(
        s.integrands
            .iter()
            .map(|r| format!("{} ({})", r.name, r.class.name())),
    );
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let mut t = Table::new(&head);
    t.numeric[0] = false;
    let names: Vec<&str> = s
        .integrands
        .first()
        .map(|r| r.curves.iter().map(|c| c.distribution.as_str()).collect())
        .unwrap_or_default();
    let (mut agree, mut targets) = (0, 0);
    for name in names {
        let mut row = vec![name.to_string()];
        for r in &s.integrands {
            let cell = r
                .curves
                .iter()
                .find(|c| c.distribution == name)
                .map_or("–".into(), |c| {
                    let target = c
                        .theory
                        .map_or(String::new(), |t| format!(" (theory {})", signed(t)));
                    let mark = match c.within {
                        Some(true) => " ✓",
                        Some(false) => " ✗",
                        None => "",
                    };
                    targets += usize::from(c.within.is_some());
                    agree += usize::from(c.within == Some(true));
                    format!(
                        "{}{target}{mark}",
                        c.fit.map_or("–".into(), |f| signed(f.slope))
                    )
                });
            row.push(cell);
        }
        t.row(row);
    }
    vec![
        h(2, "Slopes"),
        p(format!(
            "Fitted slopes of log RMSE against log N; ✓ within {} of theory, ✗ not. {agree} of \
             {targets} slopes with a target agree with it.",
            s.tolerance
        )),
        Block::Table(t),
    ]
}

fn theory(s: &DistributionStudy) -> Vec<Block> {
    let mut t = Table::new(&["distributions", "edge", "smooth", "basis"]);
    t.numeric[3] = false;
    t.numeric[0] = false;
    let target = |v: Option<f64>| v.map_or("–".into(), signed);
    for r in &s.theory {
        t.row(vec![
            r.distributions
                .iter()
                .map(|d| format!("`{d}`"))
                .collect::<Vec<_>>()
                .join(", "),
            target(r.edge),
            target(r.smooth),
            r.basis.clone(),
        ]);
    }
    vec![
        h(2, "Theory"),
        p(
            "The slope of log RMSE against log N each distribution should reach, for smooth \
           integrands and for indicator functions of regions with a piecewise smooth boundary \
           (edge). Distributions not listed have no target.",
        ),
        Block::Table(t),
    ]
}

fn integrand(r: &IntegrandResult, svg: &str) -> Vec<Block> {
    let last = r
        .curves
        .first()
        .and_then(|c| c.points.last())
        .map_or(0, |p| p.n);
    let mut t = Table::new(&[
        "distribution",
        "measured slope [95% interval]",
        "theory",
        &format!("within {TOLERANCE}"),
        &format!("slope for N ≥ {TAIL_FROM} [95% interval]"),
        &format!("RMSE at N = {last}"),
    ]);
    t.numeric[0] = false;
    t.numeric[3] = false;
    for c in &r.curves {
        t.row(vec![
            c.distribution.clone(),
            fit::cell(c.fit),
            c.theory.map_or("–".into(), signed),
            verdict(c),
            fit::cell(c.tail_fit),
            c.points
                .last()
                .map_or("–".into(), |p| format!("{:.3e}", p.rmse)),
        ]);
    }
    vec![
        h(2, format!("{} ({})", r.name, r.class.name())),
        p(format!(
            "The integrand is {}: {:.12}.",
            r.description, r.exact
        )),
        Block::Svg {
            src: r.plot.clone(),
            alt: format!("RMSE against N on the {} integrand", r.name),
            caption: format!(
                "{}: RMSE against N, log–log; dashed: the theoretical slopes; hollow dots: counts \
                 left out of the fit.",
                r.name
            ),
            markup: svg.to_string(),
        },
        Block::Table(t),
    ]
}
