//! # Penumbra
//!
//! A CPU stochastic (distributed) ray tracer: Cook-style distributed ray
//! tracing on top of Whitted recursion, as described in the thesis
//! *Stochastic Ray Tracing* (Pfeuti, Bern 2007), with the thesis's six ray
//! distributions selectable per effect, penumbra, blurry reflection and
//! refraction, supersampling, depth of field and motion blur.
//!
//! The library is a stack of layers, each a folder that uses only the ones
//! before it: [`math`] (with the colour type [`math::Rgb`]) and [`input`]
//! (every input file read bounded, every quoted value cut) → [`sampling`] →
//! [`geometry`], [`accel`] and [`camera`] → [`scene`] → [`bsdf`] and
//! [`emitter`] → [`integrator`] → [`render`] → [`io`]. A render goes:
//!
//! * [`scene`] parses a TOML scene (or a built-in one) into a plain
//!   [`scene::SceneDesc`], validates it with errors at `file:line:column`, and
//!   builds an immutable [`scene::Scene`] (meshes read by
//!   [`geometry::mesh_file`], the world's BVHs from [`accel`]).
//! * [`render::render`] cuts the image into tiles and renders them in
//!   parallel, each with a worker of an [`integrator::Integrator`] (the
//!   thesis's [`integrator::Whitted`]), and returns an [`render::Image`] plus
//!   [`render::RenderStats`] (rays by kind, time).
//! * [`io::output`] writes PNG or EXR atomically.
//!
//! ```no_run
//! use penumbra::scene::{LoadOptions, SceneSource};
//! use penumbra::render::{render, RenderOptions};
//!
//! let scene = SceneSource::open("showcase", &LoadOptions::default())?.build()?;
//! let (image, stats) = render(&scene, &RenderOptions::default(), &|_, _| {}, None)?;
//! penumbra::io::output::write_image("showcase.png".as_ref(), &image)?;
//! println!("{} rays", stats.rays.total());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod accel;
pub mod bsdf;
pub mod camera;
pub mod description;
pub mod emitter;
pub mod geometry;
pub mod input;
pub mod integrator;
pub mod io;
pub mod math;
pub mod render;
pub mod sampling;
pub mod scene;
