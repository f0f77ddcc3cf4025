//! The render session: one thread that holds the scene and its settings,
//! renders in passes and publishes a frame after each, and, when a change
//! arrives, cancels the render, applies it, builds the scene again (reusing
//! the world) and starts over.
//!
//! A request counts its change in `sent` before sending it; the thread
//! counts the changes it takes. A render is interrupted as soon as more
//! were sent than taken, and the thread then waits for every change
//! counted: none is missed, and none interrupts the render it started.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::Receiver;
use std::sync::Arc;

use penumbra::description::Node;
use penumbra::integrator::Config;
use penumbra::render::{
    render_progressive, Ended, Image, PassView, Progressive, RenderOptions, RenderStats,
};
use penumbra::scene::{Choices, LoadOptions, RenderOption, Scene, SceneSource, WorldCache};
use serde_json::{json, Value as Json};
use tokio::sync::oneshot;

use super::camera::{Placement, DOLLY_RANGE};
use super::catalogue::Catalogue;
use super::controls::value_json;
use crate::preview::server::Shared;
use crate::preview::Frame;

/// Passes a render is made in when no one chose: enough for the image to
/// refine visibly, at most one per sample.
const DEFAULT_PASSES: u32 = 16;

/// How requests and the owner reach a running session.
#[derive(Default)]
pub struct Signals {
    /// Changes sent (counted before they are).
    pub sent: AtomicU64,
    /// Ends the session, cancelling its render.
    pub close: AtomicBool,
}

/// What a request asks the session to change.
pub enum Change {
    /// A control, its value checked.
    Set(&'static RenderOption, penumbra::scene::options::Value),
    /// Orbit (yaw, pitch, degrees) then dolly (distance factor).
    Camera { yaw: f32, pitch: f32, dolly: f32 },
    /// The scene of the catalogue at this index.
    Scene(usize),
}

/// A change and where to answer: the new run's settings, or why not.
pub struct Command {
    pub change: Change,
    pub reply: oneshot::Sender<Result<Json, String>>,
}

/// Everything a render is made from.
#[derive(Clone)]
struct State {
    scene: usize,
    /// The scene's description as read, before any change.
    root: Node,
    base_dir: PathBuf,
    choices: Choices,
    /// The controls set, by name, in the order first set.
    chosen: Vec<(&'static str, penumbra::scene::options::Value)>,
    camera: Option<Placement>,
}

pub struct Session {
    catalogue: Arc<Catalogue>,
    load: LoadOptions,
    worlds: WorldCache,
    state: State,
    /// Renders started, the first 1: a frame names its run.
    run: u64,
}

impl Session {
    /// A session on the catalogue's scene `scene` with `choices`.
    pub fn open(
        catalogue: Arc<Catalogue>,
        load: LoadOptions,
        scene: usize,
        choices: Choices,
    ) -> Result<Session, String> {
        let (root, base_dir) = catalogue.open(scene, &load)?;
        let camera = Placement::of(&root);
        let mut session = Session {
            catalogue,
            load,
            worlds: WorldCache::new(2),
            state: State {
                scene,
                root,
                base_dir,
                choices,
                chosen: Vec::new(),
                camera,
            },
            run: 0,
        };
        // Refuse at start what could not render.
        session.build(&session.state.clone())?;
        Ok(session)
    }

    /// Renders, and answers changes, until the channel closes or `close`
    /// is raised.
    pub fn run(mut self, commands: Receiver<Command>, signals: &Signals, server: &Shared) {
        let mut scene = self.build(&self.state.clone()).ok();
        let mut taken = 0u64;
        loop {
            let mut completed = true;
            if let Some(s) = scene.take() {
                self.run += 1;
                let changed = || signals.sent.load(Ordering::SeqCst) > taken;
                completed = self.render(&s, &changed, &signals.close, server);
            }
            if signals.close.load(Ordering::SeqCst) {
                return;
            }
            let mut batch = Vec::new();
            // Every change counted, and at least one: idle until asked.
            while batch.is_empty() || signals.sent.load(Ordering::SeqCst) > taken {
                match commands.recv() {
                    Ok(c) => {
                        batch.push(c);
                        taken += 1;
                    }
                    Err(_) => return,
                }
            }
            while let Ok(c) = commands.try_recv() {
                batch.push(c);
                taken += 1;
            }
            let mut changed = false;
            for c in batch {
                let answer = self.apply(c.change).map(|built| {
                    changed = true;
                    let echo = self.echo(&built, self.run + 1);
                    scene = Some(built);
                    echo
                });
                let _ = c.reply.send(answer);
            }
            if !changed && !completed {
                // Every change refused: the interrupted render starts over.
                scene = self.build(&self.state.clone()).ok();
            }
        }
    }

    /// The state with `change`, built; kept only if it builds.
    fn apply(&mut self, change: Change) -> Result<Scene, String> {
        let mut next = self.state.clone();
        match change {
            Change::Set(o, v) => {
                o.store(&mut next.choices, v);
                match next.chosen.iter_mut().find(|(name, _)| *name == o.name) {
                    Some(entry) => entry.1 = v,
                    None => next.chosen.push((o.name, v)),
                }
            }
            Change::Camera { yaw, pitch, dolly } => {
                let Some(camera) = &mut next.camera else {
                    return Err("the scene has no camera to move".into());
                };
                if !(DOLLY_RANGE.0..=DOLLY_RANGE.1).contains(&dolly) {
                    return Err(format!(
                        "dolly must be from {} to {}",
                        DOLLY_RANGE.0, DOLLY_RANGE.1
                    ));
                }
                camera.orbit(yaw, pitch);
                camera.dolly(dolly);
            }
            Change::Scene(index) => {
                let (root, base_dir) = self.catalogue.open(index, &self.load)?;
                next.camera = Placement::of(&root);
                next.scene = index;
                next.root = root;
                next.base_dir = base_dir;
            }
        }
        let scene = self.build(&next)?;
        self.state = next;
        Ok(scene)
    }

    /// The scene `state` describes: the choices and the camera applied to
    /// its description, the passes made `DEFAULT_PASSES` (at most the
    /// samples) unless chosen.
    fn build(&mut self, state: &State) -> Result<Scene, String> {
        let source = |choices: &Choices| {
            let mut src = SceneSource::from_tree(state.root.clone(), &state.base_dir, &self.load);
            choices.overrides.apply(&mut src);
            if let Some(camera) = &state.camera {
                camera.apply(&mut src.root);
            }
            src
        };
        let scene = source(&state.choices)
            .build_reusing(&mut self.worlds)
            .map_err(|e| e.to_string())?;
        if state.choices.overrides.passes.is_some() || scene.settings.spp <= 1 {
            return Ok(scene);
        }
        let mut choices = state.choices.clone();
        choices.overrides.passes = Some(scene.settings.spp.min(DEFAULT_PASSES));
        source(&choices)
            .build_reusing(&mut self.worlds)
            .map_err(|e| e.to_string())
    }

    /// Renders `scene`, publishing each pass and the end; false if
    /// cancelled.
    fn render(
        &self,
        scene: &Scene,
        changed: &(dyn Fn() -> bool + Sync),
        close: &AtomicBool,
        server: &Shared,
    ) -> bool {
        let info = self.echo(scene, self.run);
        let publish = |image: &Image, stats: &RenderStats, (pass, passes)| {
            server.publish(&Frame {
                width: image.width,
                height: image.height,
                rgb: image.pixels.iter().flat_map(|p| p.to_array()).collect(),
                pass,
                passes,
                elapsed_s: stats.render_time.as_secs_f64(),
                rays: stats.rays.total(),
                stats: serde_json::to_value(stats.rays).unwrap_or_default(),
                eta_s: None,
                info: info.clone(),
            });
        };
        let on_pass =
            |view: &PassView<'_>| publish(view.image, view.stats, (view.pass, view.passes));
        let opts = RenderOptions {
            threads: self.state.choices.threads.map(|t| t as usize),
            region: None,
        };
        let run = Progressive {
            time_limit: None,
            interrupt: Some(changed),
            on_pass: Some(&on_pass),
            checkpoint: None,
        };
        match render_progressive(scene, &opts, &|_, _| {}, Some(close), &run) {
            Ok((image, stats)) if stats.ended == Ended::Complete => {
                let passes = Config::of(scene).map(|c| c.passes()).unwrap_or(1);
                publish(&image, &stats, (passes, passes));
                true
            }
            _ => false,
        }
    }

    /// What a frame of run `run` of `scene` says of it: the scene, the
    /// settings it was built with, the values chosen, the camera.
    fn echo(&self, scene: &Scene, run: u64) -> Json {
        let s = &scene.settings;
        let effect = |e: penumbra::scene::EffectSpec| json!({ "rays": e.rays, "distribution": e.distribution.name() });
        let passes = Config::of(scene).map(|c| c.passes()).unwrap_or(1);
        let chosen: serde_json::Map<String, Json> = self
            .state
            .chosen
            .iter()
            .map(|(name, v)| (name.to_string(), value_json(*v)))
            .collect();
        let camera =
            self.state.camera.as_ref().map(
                |c| json!({ "position": c.position.to_array(), "look_at": c.look_at.to_array() }),
            );
        json!({
            "run": run,
            "scene": self.state.scene,
            "scene_name": self.catalogue.name(self.state.scene),
            "settings": {
                "integrator": scene.integrator.plugin,
                "width": s.width,
                "height": s.height,
                "spp": s.spp,
                "passes": passes,
                "pixel_distribution": s.pixel.name(),
                "lens_distribution": s.lens.name(),
                "shadow": effect(s.shadow),
                "reflection": effect(s.reflection),
                "refraction": effect(s.refraction),
            },
            "chosen": chosen,
            "camera": camera,
        })
    }
}
