//! The stopping comparison as blocks of the study's document.

use crate::doc::{Block, Table};
use crate::format::{approx, pct, seconds};

use super::results::{SceneResult, StoppingStudy};
use super::{TARGET_COVERAGE, TARGET_FALSE_STOPS, TARGET_SAVING, TARGET_WORST};

fn p(s: impl Into<String>) -> Block {
    Block::Paragraph(s.into())
}

fn verdict(met: Option<bool>) -> &'static str {
    match met {
        Some(true) => "met",
        Some(false) => "not met",
        None => "not measured",
    }
}

/// The comparison's blocks, headed at `level`.
pub fn blocks(s: &StoppingStudy, level: u8) -> Vec<Block> {
    let mut out = vec![
        Block::Heading(level, "Stopping rules at equal RMSE".into()),
        p(format!(
            "Five settings of the built-in `showcase` (whole {}×{} frames), each with another \
             integrand per pixel. Every rule draws its camera rays from `{}`, at most {} per \
             pixel, with its own minimum; the calibrated rule has {} replicas at confidence {}. \
             Each rule's threshold is swept (the sweeps are in the tables), and each step's rays \
             traced (every kind) and RMSE against the reference are measured; the reference is \
             the mean of two `jitter` renders of {} rays per pixel with other seeds, and its own \
             noise is taken out of each RMSE as in the render level. `pixel metric` is the \
             thesis's α/threshold rule on a pixel's camera rays (the two other metrics act on \
             shadow and reflection sets, not pixels); `uniform` gives every pixel the same \
             rays. Comparison measured in {} s.",
            s.frame.0,
            s.frame.1,
            super::PIXELS.name(),
            s.spp,
            s.replicas,
            s.confidence,
            s.reference_spp,
            seconds(s.elapsed_s)
        )),
        p(
            "How to read it: the target RMSEs of a scene are spaced evenly in log RMSE over the \
             RMSEs both the calibrated rule and at least one anchor (cycles, povray, dammertz, \
             the pixel metric) reach, and above twice the reference's noise. The rays a rule \
             needs for a target are interpolated linearly on log–log axes between the two steps \
             of its sweep that bracket it (never extrapolated: a dash means the sweep does not \
             reach it). The ratio is the calibrated rule's rays over the best anchor's at that \
             target; a scene's ratio is the median over its targets, and the saving is one \
             minus it. Coverage is the share of pixels whose largest channel error against the \
             reference is within the calibrated rule's last interval half-width (the largest \
             channel's, which the rule compares); per channel, the share of channels within \
             their own. A false stop is a pixel stopped before the budget whose largest \
             channel error exceeds 3T, with T the threshold times the pixel's largest channel \
             (or times the floor, noise_floor = 1, below it).",
        ),
    ];
    out.extend(summary(s));
    for scene in &s.scenes {
        out.extend(scene_blocks(s, scene, level + 1));
    }
    out
}

fn summary(s: &StoppingStudy) -> Vec<Block> {
    let m = &s.summary;
    let c = &m.coverage;
    let mut t = Table::new(&["figure", "measured", "target", "verdict"]);
    t.numeric = vec![false, true, false, false];
    let saving = m.median_saving;
    t.row(vec![
        "median over scenes of the calibrated rule's rays over the best anchor's, at equal \
         RMSE (the saving)"
            .into(),
        saving.map_or("–".into(), |v| {
            format!("{:.2} ({})", 1.0 - v, pct(100.0 * v))
        }),
        format!(
            "≤ {:.2} (≥ {})",
            1.0 - TARGET_SAVING,
            pct(100.0 * TARGET_SAVING)
        ),
        verdict(saving.map(|v| v >= TARGET_SAVING)).into(),
    ]);
    t.row(vec![
        format!(
            "worst scene's ratio of rays ({})",
            m.worst_scene.as_deref().unwrap_or("–")
        ),
        m.worst_ratio.map_or("–".into(), |v| format!("{v:.2}")),
        format!("≤ {TARGET_WORST:.2}"),
        verdict(m.worst_ratio.map(|v| v <= TARGET_WORST)).into(),
    ]);
    let covered = (c.pixels > 0).then(|| c.rate());
    t.row(vec![
        format!(
            "coverage at confidence {} (all calibrated pixels)",
            s.confidence
        ),
        covered.map_or("–".into(), |v| pct(100.0 * v)),
        format!("≥ {}", pct(100.0 * TARGET_COVERAGE)),
        verdict(covered.map(|v| v >= TARGET_COVERAGE)).into(),
    ]);
    t.row(vec![
        "coverage per channel".into(),
        if c.channels > 0 {
            pct(100.0 * c.channel_rate())
        } else {
            "–".into()
        },
        "–".into(),
        "–".into(),
    ]);
    t.row(vec![
        "smallest coverage of one render".into(),
        m.coverage_min.map_or("–".into(), |v| pct(100.0 * v)),
        "–".into(),
        "–".into(),
    ]);
    let false_stops = (c.total > 0).then(|| c.false_stop_rate());
    t.row(vec![
        "false stops (share of all pixels)".into(),
        false_stops.map_or("–".into(), |v| format!("{:.2}%", 100.0 * v)),
        format!("≤ {}", pct(100.0 * TARGET_FALSE_STOPS)),
        verdict(false_stops.map(|v| v <= TARGET_FALSE_STOPS)).into(),
    ]);
    t.row(vec![
        "largest false-stop share of one render".into(),
        m.false_stops_max
            .map_or("–".into(), |v| format!("{:.2}%", 100.0 * v)),
        "–".into(),
        "–".into(),
    ]);
    let mut per = Table::new(&[
        "scene",
        "targets",
        "calibrated / best anchor (median)",
        "saving",
        "best anchors",
        "coverage",
        "false stops",
    ]);
    per.numeric[0] = false;
    per.numeric[4] = false;
    for sc in &s.scenes {
        let mut anchors: Vec<&str> = sc
            .equal
            .iter()
            .filter_map(|e| e.best_anchor.as_deref())
            .collect();
        anchors.dedup();
        per.row(vec![
            sc.name.clone(),
            sc.equal.len().to_string(),
            sc.ratio.map_or("–".into(), |r| format!("{r:.2}")),
            sc.ratio.map_or("–".into(), |r| pct(100.0 * (1.0 - r))),
            anchors.join(", "),
            pct(100.0 * sc.coverage.rate()),
            format!("{:.2}%", 100.0 * sc.coverage.false_stop_rate()),
        ]);
    }
    vec![
        p(format!(
            "The targets set for the calibrated rule against the measured figures ({} of {} \
             scenes had common targets):",
            m.scenes_compared,
            s.scenes.len()
        )),
        Block::Table(t),
        Block::Table(per),
    ]
}

fn scene_blocks(s: &StoppingStudy, sc: &SceneResult, level: u8) -> Vec<Block> {
    let mut head = vec!["target RMSE".to_string()];
    head.extend(sc.variants.iter().map(|v| v.name.clone()));
    head.push("calibrated / best anchor".into());
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let mut equal = Table::new(&head);
    for e in &sc.equal {
        let mut row = vec![format!("{:.3e}", e.target)];
        row.extend(e.rays.iter().map(|r| r.map_or("–".into(), approx)));
        row.push(match (&e.ratio, &e.best_anchor) {
            (Some(r), Some(a)) => format!("{r:.2} ({a})"),
            _ => "–".into(),
        });
        equal.row(row);
    }
    let mut sweeps = Table::new(&[
        "rule",
        "value",
        "rays",
        "camera rays per pixel",
        "RMSE",
        "time (s)",
        "coverage",
        "stopped",
        "false stops",
    ]);
    sweeps.numeric[0] = false;
    let pixels = f64::from(s.frame.0 * s.frame.1);
    for v in &sc.variants {
        for r in &v.runs {
            let cov = r.coverage;
            sweeps.row(vec![
                v.name.clone(),
                format!("{}", r.value),
                approx(r.rays as f64),
                format!("{:.1}", r.primary as f64 / pixels),
                format!("{:.3e}", r.rmse),
                format!("{:.2}", r.seconds),
                cov.map_or("–".into(), |c| pct(100.0 * c.rate())),
                cov.map_or("–".into(), |c| {
                    pct(100.0 * c.stopped as f64 / c.total.max(1) as f64)
                }),
                cov.map_or("–".into(), |c| pct(100.0 * c.false_stop_rate())),
            ]);
        }
    }
    let measures = sc
        .variants
        .iter()
        .map(|v| format!("{}: {}", v.name, v.measure))
        .collect::<Vec<_>>();
    vec![
        Block::Heading(level, sc.name.clone()),
        p(format!(
            "{}; the reference's own RMSE is {:.2e}.",
            sc.description, sc.reference_rmse
        )),
        Block::Svg {
            src: sc.plot.clone(),
            alt: format!("{}: RMSE against rays per rule", sc.name),
            caption: format!(
                "{}: RMSE against rays traced, one line per rule (its sweep); grey dashed: the \
                 target RMSEs.",
                sc.name
            ),
            markup: s.svg(&sc.plot).to_string(),
        },
        p("Rays at equal RMSE (interpolated; – outside a sweep):"),
        Block::Table(equal),
        p("The sweeps; what each value is:"),
        Block::List(measures),
        Block::Table(sweeps),
    ]
}
