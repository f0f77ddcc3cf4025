//! The quick reproduction end to end: every file and section is there, and
//! the thesis's findings hold in the measured numbers — linear growth for
//! supersampling, depth of field and penumbra, faster-than-linear growth for
//! mutual reflection, and savings from both metrics.
//!
//! Needs the Stanford bunny (`$PENUMBRA_BUNNY` or the shared data folder next
//! to the repository); without it the test says so and passes.

use std::error::Error;
use std::path::PathBuf;
use std::time::Instant;

use penumbra_eval::{reproduce, CountTable, Report, ReproduceOptions};

/// The bunny the test command passes in `$PENUMBRA_BUNNY` (nothing looks
/// for it elsewhere).
fn bunny() -> Option<PathBuf> {
    let p = PathBuf::from(std::env::var_os("PENUMBRA_BUNNY")?);
    p.is_file().then_some(p)
}

/// Total rays of a table's row in `mode` with `rays` per effect.
fn total(t: &CountTable, mode: &str, rays: u32) -> Result<f64, String> {
    t.rows
        .iter()
        .find(|r| r.mode == mode && r.rays == rays)
        .map(|r| r.measured.total as f64)
        .ok_or_else(|| format!("table {} has no {mode} row with {rays} rays", t.id))
}

fn table<'a>(r: &'a Report, id: &str) -> Result<&'a CountTable, String> {
    r.tables.count(id).ok_or_else(|| format!("no table {id}"))
}

#[test]
fn quick_reproduction() -> Result<(), Box<dyn Error>> {
    let Some(bunny) = bunny() else {
        eprintln!("SKIPPED quick_reproduction: the Stanford bunny was not found (set PENUMBRA_BUNNY to bunny.ply)");
        return Ok(());
    };
    let dir = tempfile::tempdir()?;
    let opts = ReproduceOptions {
        bunny,
        out: dir.path().join("report"),
        quick: true,
        threads: None,
        study: None,
    };
    let started = Instant::now();
    let calls = std::cell::Cell::new(0usize);
    let report = reproduce(&opts, &|_, done, total| {
        assert!(done <= total, "progress {done}/{total}");
        calls.set(calls.get() + 1);
    })?
    .thesis()
    .ok_or("the thesis's evaluation did not run")?;
    eprintln!(
        "quick reproduction: {:.1} s",
        started.elapsed().as_secs_f64()
    );
    assert!(
        calls.get() >= report.renders,
        "progress reported for every render"
    );
    files_and_sections(&report)?;
    linear_growth(&report)?;
    mutual_reflection_grows_faster(&report)?;
    metrics_save_rays(&report)?;
    convergence_is_measured(&report)?;
    Ok(())
}

fn files_and_sections(r: &Report) -> Result<(), Box<dyn Error>> {
    for f in r.files() {
        let path = r.out.join(&f);
        assert!(path.is_file(), "missing {f}");
        if f.ends_with(".svg") {
            let svg = std::fs::read_to_string(&path)?;
            assert!(
                svg.contains("<svg") && svg.contains("<text"),
                "{f}: no labels"
            );
        }
    }
    assert_eq!(r.figures.len(), 10);
    // A figure embeds each panel's render under its label.
    for f in &r.figures {
        let svg = std::fs::read_to_string(r.out.join(&f.file))?;
        let images = svg.matches("<image ").count();
        assert_eq!(images, f.panels.len(), "{}", f.file);
        assert_eq!(svg.matches("data:image/png;base64,").count(), images);
        assert_eq!(svg.matches("</text>").count(), f.panels.len(), "{}", f.file);
    }
    // A plot is drawn with a line and markers per series.
    for p in &r.plots {
        let svg = std::fs::read_to_string(r.out.join(&p.file))?;
        assert!(p.file.ends_with(".svg"), "{}", p.file);
        assert!(svg.matches("<polyline").count() > 2, "{}", p.file);
        assert!(
            svg.contains(&format!(">\n{}\n</text>", p.title)),
            "{}",
            p.file
        );
    }
    let md = std::fs::read_to_string(r.markdown_path())?;
    let html = std::fs::read_to_string(r.html_path())?;
    for id in ["4.1", "4.2", "4.3", "4.4", "4.5", "4.6"] {
        assert!(
            md.contains(&format!("Table {id}:")),
            "report.md lacks Table {id}"
        );
        assert!(
            html.contains(&format!("Table {id}:")),
            "report.html lacks Table {id}"
        );
    }
    for f in &r.figures {
        assert!(
            md.contains(&format!("]({})", f.file)),
            "report.md does not show {}",
            f.file
        );
        assert!(
            html.contains(&format!("<img src=\"{}\"", f.file)),
            "report.html does not show {}",
            f.file
        );
    }
    for section in [
        "Summary of the measurements",
        "Plots",
        "convergence of the six distributions",
    ] {
        assert!(md.contains(section), "report.md lacks {section}");
    }
    assert!(md.contains("Quick run"), "the quick run says so");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(r.json_path())?)?;
    assert_eq!(json["quick"], serde_json::Value::Bool(true));
    Ok(())
}

/// n rays per pixel or shading point cost at most n times the rays of one,
/// and primary rays exactly n times.
fn linear_growth(r: &Report) -> Result<(), Box<dyn Error>> {
    for (id, mode, n) in [
        ("4.1", "depth of field", 16),
        ("S", "supersampling", 16),
        ("4.5", "standard", 32),
    ] {
        let t = table(r, id)?;
        let g = total(t, mode, n)? / total(t, mode, 1)?;
        assert!(
            g <= f64::from(n) * 1.02,
            "table {id}: {n} rays cost {g:.2}× one ray"
        );
        assert!(
            g >= 0.25 * f64::from(n),
            "table {id}: {n} rays cost only {g:.2}× one ray"
        );
    }
    let dof = table(r, "4.1")?;
    let g = total(dof, "depth of field", 16)? / total(dof, "depth of field", 1)?;
    assert!((14.0..=16.5).contains(&g), "depth of field 16 vs 1: {g:.2}");
    Ok(())
}

/// Between the reflective floor and the reflective bunny, sets of sets are
/// traced: doubling the budget more than doubles the count, and the growth
/// outpaces that of the floor alone.
fn mutual_reflection_grows_faster(r: &Report) -> Result<(), Box<dyn Error>> {
    let mirror = table(r, "4.3")?;
    let budgets: Vec<u32> = mirror
        .rows
        .iter()
        .filter(|x| x.mode == "standard")
        .map(|x| x.rays)
        .collect();
    let (mid, top) = (budgets[1], budgets[2]);
    let step = total(mirror, "standard", top)? / total(mirror, "standard", mid)?;
    let ratio = f64::from(top) / f64::from(mid);
    assert!(
        step > ratio,
        "mutual reflection {mid}→{top} rays: ×{step:.2}, not above ×{ratio}"
    );
    let floor = table(r, "4.2")?;
    let floor_step = total(floor, "standard", 32)? / total(floor, "standard", 4)?;
    let mirror_per_ray = step.ln() / ratio.ln();
    let floor_per_ray = floor_step.ln() / 8f64.ln();
    assert!(
        mirror_per_ray > 1.0 && mirror_per_ray > floor_per_ray,
        "growth exponents: mutual {mirror_per_ray:.2}, floor only {floor_per_ray:.2}"
    );
    Ok(())
}

fn metrics_save_rays(r: &Report) -> Result<(), Box<dyn Error>> {
    for t in &r.tables.metrics {
        for row in &t.rows {
            assert!(
                row.reduction_pct > 0.0,
                "table {} {}: no saving",
                t.id,
                row.setting
            );
            if let Some(without) = &row.without {
                assert!(row.with.total < without.total);
                assert!(
                    row.with.primary == without.primary,
                    "the metric never skips primary rays here"
                );
            }
        }
    }
    let shadow: Vec<f64> = r
        .sweep
        .iter()
        .filter(|p| p.metric == "shadow")
        .map(|p| p.reduction_pct)
        .collect();
    let (first, last) = (shadow.first().copied(), shadow.last().copied());
    assert!(
        first < last,
        "the shadow metric saves more with more rays: {shadow:?}"
    );
    Ok(())
}

fn convergence_is_measured(r: &Report) -> Result<(), Box<dyn Error>> {
    assert_eq!(r.convergence.len(), 4);
    for s in &r.convergence {
        assert_eq!(s.curves.len(), 6, "{}", s.effect);
        for c in &s.curves {
            assert!(
                c.points.iter().all(|p| p.1.is_finite() && p.1 > 0.0),
                "{} {}: {:?}",
                s.effect,
                c.distribution,
                c.points
            );
        }
        let random = s
            .curves
            .iter()
            .find(|c| c.distribution == "random")
            .map(|c| c.slope);
        assert!(
            random.is_some_and(|x| x < -0.2),
            "{}: random converges, slope {random:?}",
            s.effect
        );
    }
    Ok(())
}
