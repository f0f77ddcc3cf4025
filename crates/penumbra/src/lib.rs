//! # Penumbra
//!
//! A CPU stochastic (distributed) ray tracer: Cook-style distributed ray
//! tracing on top of Whitted recursion, as described in the thesis
//! *Stochastic Ray Tracing* (Pfeuti, Bern 2007), with the thesis's six ray
//! distributions selectable per effect, penumbra, blurry reflection and
//! refraction, supersampling, depth of field and motion blur.
//!
//! The library is a stack of layers, each a folder that uses only the ones
//! before it: [`math`] (with the colour type [`math::Rgb`]), [`simd`] (the
//! kernel sets the hot loops are compiled for) and [`input`]
//! (every input file read bounded, every quoted value cut) → [`sampling`] →
//! [`geometry`], [`accel`] and [`camera`] → [`description`] → [`texture`]
//! → [`bsdf`], [`emitter`] and [`medium`] → [`scene`] → [`integrator`] → [`render`] → [`io`]. A render
//! goes:
//!
//! * [`description`] reads a TOML scene (or a Python dict) into a tree of
//!   plugins whose every value knows its `file:line:column`;
//!   [`scene`] checks it against the plugins' schemas and builds an
//!   immutable [`scene::Scene`]: camera, the world (meshes read by
//!   [`geometry::mesh_file`], BVHs from [`accel`]), the BSDFs and emitters.
//! * [`render::render`] cuts the image into tiles and renders them in
//!   parallel and in passes, each asking a worker of the scene's
//!   [`integrator::Integrator`] (the thesis's [`integrator::Whitted`]) to add
//!   a range of every pixel's samples to the tile's film, and returns an
//!   [`render::Image`] plus [`render::RenderStats`] (rays by kind, time).
//! * [`io::output`] writes PNG or EXR atomically; [`io::tev`] streams the
//!   image to the tev viewer while passes come in.
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
pub mod medium;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod simd;
pub mod texture;
pub mod volume;
