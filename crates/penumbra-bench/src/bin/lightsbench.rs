//! Many lights: a floor under a grid of 1,000 small one-sided area lights
//! of powers over two orders of magnitude (and a few spheres casting
//! shadows), rendered by `path` with each light sampler at equal samples.
//! Prints, per sampler, the render time, the relative MSE against a
//! high-sample reference (rendered with `bvh`) and their product, the
//! work needed for a given error (lower is better), as JSON.
//!
//! ```text
//! lightsbench [--width 160] [--height 100] [--spp 16] [--reference-spp 1024]
//!             [--threads 2] [--repeat 3] [--write-scene lights.toml]
//! ```

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use penumbra::emitter::choice::LightChoice;
use penumbra::render::{render, Image, RenderOptions};
use penumbra::scene::{LoadOptions, Overrides, SceneSource};
use penumbra_bench::median;
use serde_json::json;

#[derive(Parser)]
#[command(name = "lightsbench")]
struct Args {
    #[arg(long, default_value_t = 160)]
    width: u32,
    #[arg(long, default_value_t = 100)]
    height: u32,
    #[arg(long, default_value_t = 16)]
    spp: u32,
    #[arg(long, default_value_t = 1024)]
    reference_spp: u32,
    #[arg(long)]
    threads: Option<usize>,
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    repeat: u32,
    /// Also write the scene file here.
    #[arg(long)]
    write_scene: Option<PathBuf>,
}

/// The lights' grid: columns along x, rows along z.
const COLUMNS: u32 = 40;
const ROWS: u32 = 25;

/// A number in [0, 1) from `k`, the same on every machine.
fn hash(k: u32) -> f32 {
    let mut x = u64::from(k).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ 0x5851_f42d_4c95_7f2d;
    x ^= x >> 33;
    x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
    x ^= x >> 33;
    (x >> 40) as f32 / (1u64 << 24) as f32
}

/// The scene: a 20 × 12.5 floor, three spheres on it, and 40 × 25 squares
/// of side 0.1 facing down at heights 1–1.5, each of radiance 10^(2h) for
/// a number h in [0, 1) and a hue of its own.
fn scene_text() -> String {
    let mut s = String::from(
        "# A floor under 1,000 small area lights of powers over two orders of\n\
         # magnitude: the many-lights benchmark (penumbra-bench's lightsbench).\n\
         [render]\nintegrator = \"path\"\nmax_depth = 3\n\n\
         [camera]\nposition = [0.0, 6.0, 9.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 60\n\n\
         [materials.floor]\ntype = \"diffuse\"\nreflectance = [0.6, 0.6, 0.6]\n\n\
         [materials.ball]\ntype = \"diffuse\"\nreflectance = [0.3, 0.5, 0.7]\n\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-10.0, 0.0, 6.25]\n\
         edge_u = [20.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, -12.5]\n",
    );
    for (x, z, r) in [(-3.0, 0.5, 0.8), (1.5, -1.5, 0.6), (4.0, 2.0, 0.5)] {
        s += &format!(
            "\n[[objects]]\ntype = \"sphere\"\nmaterial = \"ball\"\ncenter = [{x:?}, {r:?}, {z:?}]\n\
             radius = {r:?}\n"
        );
    }
    for i in 0..COLUMNS {
        for j in 0..ROWS {
            let k = i * ROWS + j;
            let x = -9.75 + 0.5 * i as f32;
            let z = -6.0 + 0.5 * j as f32;
            let y = 1.0 + 0.5 * hash(3 * k);
            let level = 10f32.powf(2.0 * hash(3 * k + 1));
            let hue = hash(3 * k + 2);
            let c = [
                level * (0.5 + 0.5 * hue),
                level * 0.75,
                level * (1.0 - 0.5 * hue),
            ];
            // Edges x then z: the normal (x × z = −y) faces the floor.
            s += &format!(
                "\n[[lights]]\ntype = \"rect\"\norigin = [{:?}, {:?}, {:?}]\n\
                 edge_u = [0.1, 0.0, 0.0]\nedge_v = [0.0, 0.0, 0.1]\n\
                 radiance = [{:.4}, {:.4}, {:.4}]\n",
                x - 0.05,
                y,
                z - 0.05,
                c[0],
                c[1],
                c[2]
            );
        }
    }
    s
}

/// The relative MSE of `img` against `reference`, as the harness measures
/// it (`(x − r)² / (r² + 0.01)`, averaged over pixels and channels).
fn rel_mse(img: &Image, reference: &Image) -> f64 {
    let mut sum = 0.0f64;
    for (a, b) in img.pixels.iter().zip(&reference.pixels) {
        for (a, b) in a.to_array().into_iter().zip(b.to_array()) {
            let (a, b) = (f64::from(a), f64::from(b));
            sum += (a - b).powi(2) / (b * b + 0.01);
        }
    }
    sum / (3 * img.pixels.len()) as f64
}

fn run(args: Args) -> Result<serde_json::Value, String> {
    let text = scene_text();
    if let Some(path) = &args.write_scene {
        std::fs::write(path, &text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let opts = RenderOptions {
        threads: args.threads,
        region: None,
    };
    let frame = |spp: u32, choice: LightChoice, repeat: u32| -> Result<(Image, f64), String> {
        let mut src = SceneSource::from_toml(
            &text,
            Path::new("lights.toml"),
            Path::new("."),
            &LoadOptions::default(),
        )
        .map_err(|e| e.to_string())?;
        Overrides {
            width: Some(args.width),
            height: Some(args.height),
            spp: Some(spp),
            light_sampler: Some(choice),
            ..Overrides::default()
        }
        .apply(&mut src);
        let scene = src.build().map_err(|e| e.to_string())?;
        let mut times = Vec::new();
        let mut image = None;
        for _ in 0..repeat {
            let t0 = Instant::now();
            let (img, _) = render(&scene, &opts, &|_, _| {}, None).map_err(|e| e.to_string())?;
            times.push(t0.elapsed().as_secs_f64());
            image = Some(img);
        }
        Ok((image.expect("repeat ≥ 1"), median(times)))
    };
    let (reference, reference_s) = frame(args.reference_spp, LightChoice::Bvh, 1)?;
    let mut rows = Vec::new();
    let mut uniform_work = None;
    for choice in LightChoice::ALL {
        let (img, s) = frame(args.spp, choice, args.repeat)?;
        let err = rel_mse(&img, &reference);
        let work = err * s;
        let base = *uniform_work.get_or_insert(work);
        rows.push(json!({
            "sampler": choice.name(),
            "render_s": s,
            "relmse": err,
            "relmse_x_s": work,
            "work_vs_uniform": work / base,
        }));
    }
    Ok(json!({
        "lights": COLUMNS * ROWS,
        "width": args.width,
        "height": args.height,
        "spp": args.spp,
        "reference_spp": args.reference_spp,
        "reference_s": reference_s,
        "samplers": rows,
    }))
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(doc) => {
            println!("{doc}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("lightsbench: {e}");
            ExitCode::from(2)
        }
    }
}
