//! `penumbra samples`: the points of a distribution, as JSON or an SVG
//! picture.

use std::path::PathBuf;

use clap::Args;
use penumbra::io::output::write_bytes;
use penumbra::math::Vec3;
use penumbra::sampling::{Distribution, PointTable, Rng};
use penumbra::scene::read_points;
use penumbra_eval::samples;
use serde_json::json;

use crate::error::{input, other, CliError};
use crate::flags::parse_positive;

/// Options of `penumbra samples`.
#[derive(Args)]
pub struct SamplesArgs {
    /// grid, jitter, semi-jitter, poisson, random, fast-random, sobol, zsobol,
    /// pmj02, pmj02bn, halton, r2, custom (with --points), or `all` (SVG only).
    #[arg(long, short)]
    pub distribution: String,
    /// Number of points.
    #[arg(long, short, value_parser = clap::value_parser!(u32).range(1..=100000))]
    pub count: u32,
    #[arg(long, short, default_value_t = 1.0, value_parser = parse_positive)]
    pub radius: f32,
    #[arg(long, short, default_value_t = 0)]
    pub seed: u64,
    #[arg(long, short, value_enum, default_value = "json")]
    pub format: SampleFormat,
    /// Output file (default: standard output for JSON, samples.svg for SVG).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// The custom distribution's point sets: a JSON or .npy file (see the
    /// scene format's `points` key).
    #[arg(long, value_name = "FILE")]
    pub points: Option<PathBuf>,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum SampleFormat {
    Json,
    Svg,
}

pub fn run(a: &SamplesArgs) -> Result<(), CliError> {
    let all = a.distribution == "all";
    let dist = if all {
        None
    } else {
        Some(Distribution::from_name(&a.distribution).ok_or_else(|| {
            let names: Vec<&str> = Distribution::SELECTABLE.iter().map(|d| d.name()).collect();
            input(format!(
                "unknown distribution `{}`; valid choices are: {}, all",
                a.distribution,
                names.join(", ")
            ))
        })?)
    };
    let table =
        match (&a.points, dist) {
            (Some(path), _) => read_points(path).map_err(input)?,
            (None, Some(d)) if d.needs_table() => return Err(input(
                "the custom distribution draws from your point sets: give them with --points FILE \
                 (a JSON or .npy file)",
            )),
            (None, _) => PointTable::NONE,
        };
    match (a.format, dist) {
        (SampleFormat::Json, None) => Err(input(
            "`--distribution all` draws a picture: use --format svg",
        )),
        (SampleFormat::Json, Some(d)) => {
            let points = points(d, &table, a);
            let coords: Vec<Vec<f32>> = points
                .iter()
                .map(|p| {
                    if d.is_3d() {
                        vec![p.x, p.y, p.z]
                    } else {
                        vec![p.x, p.y]
                    }
                })
                .collect();
            let doc = json!({"distribution": d.name(), "count": a.count, "radius": a.radius, "points": coords});
            let text = serde_json::to_string_pretty(&doc).map_err(other)? + "\n";
            match &a.output {
                Some(path) => write_bytes(path, text.as_bytes()).map_err(other),
                None => {
                    print!("{text}");
                    Ok(())
                }
            }
        }
        (SampleFormat::Svg, d) => {
            let svg = match d {
                Some(d) => samples::draw_points(&points(d, &table, a), a.radius, d.name()),
                None => samples::draw_all(a.count as usize, a.radius, a.seed),
            }
            .map_err(other)?;
            let path = a
                .output
                .clone()
                .unwrap_or_else(|| PathBuf::from("samples.svg"));
            write_bytes(&path, svg.as_bytes()).map_err(other)
        }
    }
}

fn points(d: Distribution, table: &PointTable, a: &SamplesArgs) -> Vec<Vec3> {
    if let Some(w) = d.non_square_warning(a.count as usize) {
        eprintln!("warning: {w}");
    }
    let mut out = Vec::new();
    d.generate_in(
        table,
        a.count as usize,
        a.radius,
        &mut Rng::new(a.seed),
        &mut out,
    );
    out
}
