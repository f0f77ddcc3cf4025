use glam::{Vec3A, Vec4};

use crate::accel::{Hit, PacketScratch, ShaftSet};
use crate::bsdf::{Dielectric, Phong, Surface};
use crate::emitter::{Emitter, LightSamples4};
use crate::math::Rgb;
use crate::math::{offset_origin, reach, Aabb, Ray, Vec3};
use crate::sampling::points::end_point;
use crate::sampling::{BranchKey, Distribution, Rng};
use crate::scene::Scene;

use crate::integrator::metric::RunningMean;
use crate::integrator::stats::RayStats;

const SHADOW: u64 = 1 << 32;
const REFLECT_SET: u64 = 1;
const REFLECT_RAY: u64 = 2;
const REFRACT_SET: u64 = 3;
const REFRACT_RAY: u64 = 4;
const FRESNEL_SET: u64 = 5;
const FRESNEL_RAY: u64 = 6;

/// Shadow rays stop this fraction short of their target, so that the surface
/// they aim at (or a surface touching it) does not count as a blocker.
const SHADOW_END: f32 = 1.0 - 1e-4;

/// Shadow sets of at least this many rays are traced through their shaft
/// (see [`crate::accel::Shaft`]). Building and gathering a shaft costs a few
/// rays' worth of work; on the bunny scene (instruction counts) it saved 16%
/// of a 64-ray render, 4% at 16 rays, and cost 28% at 4.
const SHAFT_MIN_RAYS: u32 = 16;

/// A shaft reaching more BVH leaves than this is not used: past it, testing
/// every ray against every leaf costs more than traversing the tree (16 and
/// 32 measured alike; 64 and more were slower).
const SHAFT_MAX_LEAVES: usize = 16;

/// One worker's tracer: reads the scene, counts its own rays, and keeps a pool
/// of point buffers so that distributing rays allocates nothing once warm.
pub struct Tracer<'a> {
    scene: &'a Scene,
    pub stats: RayStats,
    pool: Vec<Vec<Vec3>>,
    /// The shadow set being traced (shadow rays do not recurse: one suffices).
    shadow_set: Vec<Option<ShadowRay>>,
    /// What the current shadow set's shaft may cross.
    shaft: ShaftSet,
    /// The hits of the current pixel's camera rays, found together.
    primary: Vec<Option<Hit>>,
    packet: PacketScratch,
    /// Boxed, so that taking it out for a group moves a pointer.
    batch: Option<Box<Batch>>,
    /// The models of each of the scene's materials.
    surfaces: Vec<Surface>,
    /// The scene's lights, ready to be sampled.
    emitters: Vec<Emitter>,
    /// The branch of light `j`'s shadow sets, `SHADOW + j`, hashed once.
    shadow_keys: Vec<BranchKey>,
}

/// The direct light of a pixel's camera rays, found together (see
/// [`Tracer::radiance_primaries`]).
#[derive(Default)]
struct Batch {
    /// The hits that receive direct light: camera ray, material, frame.
    lit: Vec<(usize, u32, Local)>,
    /// The shadow sets of all lit hits toward one light, one after another.
    rays: Vec<Option<ShadowRay>>,
    /// Where each lit hit's set starts in `rays`, and where the last ends
    /// (not filled for sets of one ray: set `k` is `rays[k]`).
    starts: Vec<usize>,
    /// Direct light at lit hit `k` from light `j`, at `j * lit.len() + k`.
    direct: Vec<Rgb>,
}

/// Which secondary set is being traced: selects the ray kind and the streams.
#[derive(Clone, Copy)]
enum Branch {
    Reflect,
    Refract,
    Fresnel,
}

impl Branch {
    fn tags(self) -> (u64, u64) {
        match self {
            Branch::Reflect => (REFLECT_SET, REFLECT_RAY),
            Branch::Refract => (REFRACT_SET, REFRACT_RAY),
            Branch::Fresnel => (FRESNEL_SET, FRESNEL_RAY),
        }
    }
}

/// The local frame of a hit, oriented toward the viewer.
struct Local {
    p: Vec3,
    /// The magnitude that rays leaving `p` are offset in proportion to ([`reach`]).
    reach: f32,
    wo: Vec3,
    /// Shading normal on the viewer's side.
    n: Vec3,
    /// Geometric normal on the viewer's side.
    ng: Vec3,
    /// True if the ray arrived on the side the geometric normal points to.
    front: bool,
    /// The path's time: every secondary ray inherits its primary ray's time.
    time: f32,
}

impl Local {
    /// The frame of `hit`, seen along `ray`: normals flipped to the viewer's side.
    fn new(ray: &Ray, hit: &Hit) -> Local {
        let wo = -ray.dir.normalize();
        let front = hit.ng.dot(wo) >= 0.0;
        let flip = if front { 1.0 } else { -1.0 };
        Local {
            p: hit.point,
            reach: reach(hit.point, ray.origin),
            wo,
            n: hit.ns * flip,
            ng: hit.ng * flip,
            front,
            time: ray.time,
        }
    }
}

impl<'a> Tracer<'a> {
    pub fn new(scene: &'a Scene) -> Self {
        Tracer {
            scene,
            stats: RayStats::default(),
            pool: Vec::new(),
            shadow_set: Vec::new(),
            shaft: ShaftSet::default(),
            primary: Vec::new(),
            packet: PacketScratch::default(),
            batch: Some(Box::default()),
            surfaces: scene.materials.iter().map(Surface::new).collect(),
            emitters: scene.lights.iter().map(Emitter::new).collect(),
            shadow_keys: (0..scene.lights.len() as u64)
                .map(|j| BranchKey::new(SHADOW + j))
                .collect(),
        }
    }

    /// Radiance arriving along `ray`; `depth` counts reflection/refraction levels so far.
    pub fn radiance(&mut self, ray: &Ray, depth: u32, rng: Rng) -> Rgb {
        let hit = self.scene.world.intersect(ray, 0.0, f32::INFINITY);
        self.radiance_from(ray, hit.as_ref(), depth, rng)
    }

    /// Finds where each of a pixel's camera rays hits, all together (see
    /// [`World::intersect_all`](crate::accel::World::intersect_all)),
    /// for [`radiance_primaries`](Self::radiance_primaries) to shade.
    pub fn intersect_primary(&mut self, rays: &[Ray]) {
        let world = &self.scene.world;
        world.intersect_all(rays, 0.0, &mut self.packet, &mut self.primary);
    }

    /// [`radiance`](Self::radiance) along each of the rays last given to
    /// [`intersect_primary`](Self::intersect_primary), at depth 0, into
    /// `out`; `rng(i)` is the `i`-th ray's stream. Direct light is found for
    /// the whole pixel first, light by light, so that sets of few shadow rays
    /// (one per camera ray, say) can share one shaft, as a set of many rays
    /// does. The values are those of `radiance`, bit for bit.
    pub fn radiance_primaries(
        &mut self,
        rays: &[Ray],
        rng: impl Fn(usize) -> Rng,
        out: &mut Vec<Rgb>,
    ) {
        let scene = self.scene;
        let mut batch = self.batch.take().unwrap_or_default();
        batch.lit.clear();
        for (i, ray) in rays.iter().enumerate() {
            let Some(hit) = &self.primary[i] else {
                continue;
            };
            if hit.light.is_none() && self.surfaces[hit.material as usize].lit {
                batch.lit.push((i, hit.material, Local::new(ray, hit)));
            }
        }
        batch.direct.clear();
        let emitters = std::mem::take(&mut self.emitters);
        for (j, light) in emitters.iter().enumerate() {
            let key = self.shadow_keys[j];
            self.direct_batch(light, |i| rng(i).derive_key(key), &mut batch);
        }
        self.emitters = emitters;
        out.clear();
        let lit = batch.lit.len();
        let mut k = 0;
        for (i, ray) in rays.iter().enumerate() {
            let Some(hit) = self.primary[i] else {
                out.push(scene.settings.background);
                continue;
            };
            // A lit hit's frame and direct light were found above.
            let found = match batch.lit.get(k) {
                Some((at, _, s)) if *at == i => {
                    k += 1;
                    Some((s, k - 1))
                }
                _ => None,
            };
            let frame = found.map(|(s, _)| s);
            let direct = |_: &mut Self, _: &Local, j: usize| match found {
                Some((_, k)) => batch.direct[j * lit + k],
                None => Rgb::ZERO,
            };
            out.push(self.shade_with(ray, &hit, frame, 0, rng(i), direct));
        }
        self.batch = Some(batch);
    }

    /// Direct light from `light` at every lit hit of `batch`, appended to
    /// `batch.direct`: [`direct`](Self::direct) for each, except that sets
    /// too small for a shaft of their own share one if the pixel's sets
    /// together are large enough.
    fn direct_batch(&mut self, light: &Emitter, rng: impl Fn(usize) -> Rng, batch: &mut Batch) {
        let Batch {
            lit,
            rays,
            starts,
            direct,
        } = batch;
        rays.clear();
        starts.clear();
        let single = self.single_rays(lit, light, &rng, rays);
        if !single {
            for (i, _, s) in lit.iter() {
                starts.push(rays.len());
                self.shadow_set(s, light, rng(*i), rays);
            }
            starts.push(rays.len());
        }
        let own = light.shadow_rays() >= SHAFT_MIN_RAYS;
        let traced = rays.iter().flatten().count();
        let shared = !own && traced >= SHAFT_MIN_RAYS as usize && self.gather_shaft(rays);
        if single {
            // Sets of one ray: what `trace_set` gives each, with the shared
            // shaft's emptiness checked once for all.
            let clear = shared && self.scene.world.shaft_is_clear(&self.shaft);
            for ((_, material, s), r) in lit.iter().zip(rays.iter()) {
                let m = self.surfaces[*material as usize].local;
                direct.push(self.single_term(s, &m, r.as_ref(), shared, clear));
            }
            return;
        }
        for (k, (_, material, s)) in lit.iter().enumerate() {
            let m = self.surfaces[*material as usize].local;
            let set = &rays[starts[k]..starts[k + 1]];
            let shaft = shared || (own && self.gather_shaft(set));
            direct.push(self.trace_set(s, &m, light, set, shaft));
        }
    }

    fn radiance_from(&mut self, ray: &Ray, hit: Option<&Hit>, depth: u32, rng: Rng) -> Rgb {
        match hit {
            None => self.scene.settings.background,
            Some(hit) => self.shade(ray, hit, depth, rng),
        }
    }

    /// [`shade_with`](Self::shade_with), the direct light of each light
    /// found here for this hit alone.
    fn shade(&mut self, ray: &Ray, hit: &Hit, depth: u32, rng: Rng) -> Rgb {
        let direct = |this: &mut Self, s: &Local, j: usize| {
            let local = this.surfaces[hit.material as usize].local;
            let emitters = std::mem::take(&mut this.emitters);
            let key = this.shadow_keys[j];
            let l = this.direct(s, &local, &emitters[j], rng.derive_key(key));
            this.emitters = emitters;
            l
        };
        self.shade_with(ray, hit, None, depth, rng, direct)
    }

    /// The radiance leaving `hit` along `ray`: the light's own radiance if
    /// it is a light's surface; else emission (on the front side), the
    /// direct light `direct(self, frame, j)` of each light `j` if the
    /// material is lit, then reflection and refraction (see
    /// [`indirect`](Self::indirect)), summed in this order on every path.
    /// `frame` is the hit's frame if the caller has it.
    #[inline]
    fn shade_with(
        &mut self,
        ray: &Ray,
        hit: &Hit,
        frame: Option<&Local>,
        depth: u32,
        rng: Rng,
        mut direct: impl FnMut(&mut Self, &Local, usize) -> Rgb,
    ) -> Rgb {
        if let Some(l) = hit.light {
            return self.emitters[l as usize].emitted(hit.ng, ray.dir);
        }
        let fresh;
        let s = match frame {
            Some(s) => s,
            None => {
                fresh = Local::new(ray, hit);
                &fresh
            }
        };
        let sh = &self.surfaces[hit.material as usize];
        let (lit, scatters) = (sh.lit, sh.scatters);
        let mut l = if s.front { sh.emission } else { Rgb::ZERO };
        if lit {
            for j in 0..self.emitters.len() {
                l += direct(self, s, j);
            }
        }
        if scatters {
            self.indirect(s, ray, hit.material, depth, rng, &mut l);
        }
        l
    }

    /// Adds the light reflected and refracted at `s` to `l` (in this order,
    /// which the pixel-wide path keeps, so that both sum alike).
    fn indirect(&mut self, s: &Local, ray: &Ray, material: u32, depth: u32, rng: Rng, l: &mut Rgb) {
        let m = &self.surfaces[material as usize];
        if depth < self.scene.settings.max_depth && m.scatters {
            let (mirror, dielectric) = (m.mirror, m.dielectric);
            if let Some(mirror) = mirror {
                let dir = mirror.direction(ray.dir.normalize(), s.n);
                let e = mirror.effect;
                let spec = (e.rays, e.distribution, mirror.glossiness);
                *l += mirror.reflectivity * self.scatter(s, dir, spec, Branch::Reflect, depth, rng);
            }
            if let Some(glass) = dielectric {
                *l += glass.transparency * self.dielectric(s, ray, &glass, depth, rng);
            }
        }
    }

    /// Direct light from one light: the average over its shadow set of
    /// `brdf · weight · cos θ · transmittance`. The whole set is prepared
    /// first, so that a set of several rays can gather once the BVH leaves
    /// its shaft reaches and test every ray against those only.
    fn direct(&mut self, s: &Local, m: &Phong, light: &Emitter, rng: Rng) -> Rgb {
        let mut set = std::mem::take(&mut self.shadow_set);
        set.clear();
        self.shadow_set(s, light, rng, &mut set);
        let shaft = light.shadow_rays() >= SHAFT_MIN_RAYS && self.gather_shaft(&set);
        let l = self.trace_set(s, m, light, &set, shaft);
        self.shadow_set = set;
        l
    }

    /// The average over a prepared shadow set of `brdf · weight · cos θ ·
    /// transmittance`, its rays traced one by one, within the shaft last
    /// gathered if `shaft`, and stopped early by the shadow metric.
    fn trace_set(
        &mut self,
        s: &Local,
        m: &Phong,
        light: &Emitter,
        set: &[Option<ShadowRay>],
        shaft: bool,
    ) -> Rgb {
        let world = &self.scene.world;
        let clear = shaft && world.shaft_is_clear(&self.shaft);
        if let [one] = set {
            return self.single_term(s, m, one.as_ref(), shaft, clear);
        }
        let n = light.shadow_rays();
        let k = (self.scene.settings.metric)
            .filter(|m| m.shadows)
            .map_or(u32::MAX, |m| m.shadow_rays);
        let (mut sum, mut reached, mut blocked, mut done) = (Rgb::ZERO, 0u32, 0u32, 0u32);
        for r in set {
            done += 1;
            if let Some(r) = r {
                match self.shadow_term(s, m, r, shaft, clear) {
                    Some(term) => {
                        sum += term;
                        reached += 1;
                    }
                    None => blocked += 1,
                }
            }
            // The shadow metric: after k rays, all reached or all blocked.
            if done == k && done < n && (reached == 0 || blocked == 0) && reached + blocked > 0 {
                self.stats.saved.shadow += u64::from(n - done);
                break;
            }
        }
        sum / done.max(1) as f32
    }

    /// [`trace_set`](Self::trace_set) of a set of one ray (`None`: a point
    /// that gives no ray). No metric acts on one ray, and the average of one
    /// is its value (`0 + x` as the loop sums, so even a -0 comes out alike).
    #[inline(always)]
    fn single_term(
        &mut self,
        s: &Local,
        m: &Phong,
        one: Option<&ShadowRay>,
        shaft: bool,
        clear: bool,
    ) -> Rgb {
        let term = one.and_then(|r| self.shadow_term(s, m, r, shaft, clear));
        Rgb::ZERO + term.unwrap_or(Rgb::ZERO)
    }

    /// Traces one shadow ray (within the shaft last gathered if `shaft`; not
    /// at all if that shaft is `clear`): `brdf · weight · cos θ ·
    /// transmittance`, or `None` if it is blocked.
    #[inline(always)]
    fn shadow_term(
        &mut self,
        s: &Local,
        m: &Phong,
        r: &ShadowRay,
        shaft: bool,
        clear: bool,
    ) -> Option<Rgb> {
        self.stats.shadow += 1;
        let t = if clear {
            1.0
        } else {
            let (world, transparency) = (&self.scene.world, &self.scene.transparency);
            let within = shaft.then_some(&self.shaft);
            world.transmittance(&r.ray, (0.0, SHADOW_END), transparency, within)?
        };
        Some(m.eval(s.n, s.wo, r.wi) * r.weight * (r.cos * t))
    }

    /// Appends the rays of the shadow set toward `light` to `set` (`None`
    /// for points that give no ray).
    fn shadow_set(
        &mut self,
        s: &Local,
        light: &Emitter,
        mut rng: Rng,
        set: &mut Vec<Option<ShadowRay>>,
    ) {
        let d = light.shadow().distribution;
        // Every ray of the set leaves on the side the geometric normal points
        // to (others are not traced), so all start at the same offset point.
        let origin = offset_origin(s.p, s.reach, s.ng, s.ng);
        if light.shadow_rays() == 1 {
            // A point light, or a Whitted shadow ray: no buffer needed.
            let one = [d.one(1.0, &mut rng)];
            shadow_rays(|_| (s, origin), &one, light, set);
            return;
        }
        let mut points = self.pool.pop().unwrap_or_default();
        self.set_points(light, &mut rng, &mut points);
        shadow_rays(|_| (s, origin), &points, light, set);
        self.pool.push(points);
    }

    /// The distribution points of a shadow set toward `light`, into `points`.
    fn set_points(&self, light: &Emitter, rng: &mut Rng, points: &mut Vec<Vec3>) {
        let (n, d) = (light.shadow_rays() as usize, light.shadow().distribution);
        // The rays are summed: their order matters only to the shadow
        // metric, which may stop the set early.
        if self.scene.settings.metric.is_some_and(|m| m.shadows) {
            d.generate(n, 1.0, rng, points);
        } else {
            d.generate_unordered(n, 1.0, rng, points);
        }
    }

    /// The one-ray shadow sets toward `light` of all `lit` hits, appended to
    /// `set`: the rays [`shadow_set`](Self::shadow_set) gives each, prepared
    /// together. False, and nothing appended, if the light's sets are larger.
    fn single_rays(
        &mut self,
        lit: &[(usize, u32, Local)],
        light: &Emitter,
        rng: &impl Fn(usize) -> Rng,
        set: &mut Vec<Option<ShadowRay>>,
    ) -> bool {
        let d = light.shadow().distribution;
        if light.shadow_rays() != 1 {
            return false;
        }
        let mut points = self.pool.pop().unwrap_or_default();
        points.clear();
        points.extend(lit.iter().map(|&(i, _, _)| d.one(1.0, &mut rng(i))));
        let frame = |k: usize| {
            let s = &lit[k].2;
            (s, offset_origin(s.p, s.reach, s.ng, s.ng))
        };
        shadow_rays(frame, &points, light, set);
        self.pool.push(points);
        true
    }

    /// Gathers the static-triangle leaves of the shaft holding every ray of
    /// the set; false if the shaft reaches too many to be worth it.
    fn gather_shaft(&mut self, set: &[Option<ShadowRay>]) -> bool {
        // Four-wide min and max (glam's `Vec3A`): the same values as
        // `Aabb::grow`, without a compare and select per coordinate.
        let (mut lo, mut hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
        let (mut o_lo, mut o_hi) = (lo, hi);
        for r in set.iter().flatten() {
            let (o, t) = (Vec3A::from(r.ray.origin), Vec3A::from(r.ray.at(1.0)));
            (o_lo, o_hi) = (o_lo.min(o), o_hi.max(o));
            (lo, hi) = (lo.min(t), hi.max(t));
        }
        let aabb = |lo: Vec3A, hi: Vec3A| Aabb {
            min: lo.into(),
            max: hi.into(),
        };
        let (origins, targets) = (aabb(o_lo, o_hi), aabb(lo, hi));
        let world = &self.scene.world;
        world.gather_shaft(origins, targets, SHAFT_MAX_LEAVES, &mut self.shaft)
    }

    /// A dielectric interface: Fresnel-weighted reflection and refraction.
    fn dielectric(&mut self, s: &Local, ray: &Ray, m: &Dielectric, depth: u32, rng: Rng) -> Rgb {
        let split = m.split(ray.dir.normalize(), s.n, s.front);
        let spec = (m.effect.rays, m.effect.distribution, m.translucency);
        let f = split.fresnel;
        let mut l = Rgb::ZERO;
        if let (Some(t), true) = (split.refracted, f < 1.0) {
            l += (1.0 - f) * self.scatter(s, t, spec, Branch::Refract, depth, rng);
        }
        if f > 0.0 {
            l += f * self.scatter(s, split.reflected, spec, Branch::Fresnel, depth, rng);
        }
        l
    }

    /// Traces a distributed set around the perfect direction `dir` (reflected
    /// or refracted) and averages it. Radius 0 means the single perfect ray.
    fn scatter(
        &mut self,
        s: &Local,
        dir: Vec3,
        (rays, d, radius): (u32, Distribution, f32),
        branch: Branch,
        depth: u32,
        rng: Rng,
    ) -> Rgb {
        let n = if radius > 0.0 { rays } else { 1 };
        let (set_tag, ray_tag) = branch.tags();
        let points = self.points(d, n, rng.derive(set_tag));
        let transmit = matches!(branch, Branch::Refract);
        // Rays must leave on the viewer's side for reflection, the other side for refraction.
        let side = if transmit { -s.ng } else { s.ng };
        let children = rng.derive(ray_tag);
        let metric = self.scene.settings.metric.filter(|m| m.reflections);
        let mut mean = RunningMean::default();
        for (k, point) in points.iter().enumerate() {
            let mut w = if radius > 0.0 {
                end_point(dir, dir, *point, radius, d)
            } else {
                dir
            };
            let below = w.dot(side);
            if below < 0.0 {
                w -= 2.0 * below * side;
            }
            let w = w.normalize();
            if transmit {
                self.stats.refraction += 1;
            } else {
                self.stats.reflection += 1;
            }
            let child = Ray::new(offset_origin(s.p, s.reach, s.ng, w), w, s.time);
            let l = self.radiance(&child, depth + 1, children.derive(k as u64));
            if mean.push(l, metric.as_ref(), n) {
                let saved = u64::from(n) - (k as u64 + 1);
                if transmit {
                    self.stats.saved.refraction += saved;
                } else {
                    self.stats.saved.reflection += saved;
                }
                break;
            }
        }
        self.pool.push(points);
        mean.mean()
    }

    /// The points of a distribution set, in trace order, from the buffer pool.
    fn points(&mut self, d: Distribution, n: u32, mut rng: Rng) -> Vec<Vec3> {
        let mut buf = self.pool.pop().unwrap_or_default();
        d.generate(n as usize, 1.0, &mut rng, &mut buf);
        buf
    }
}

/// A shadow ray of a set, prepared before any ray of the set is traced.
#[derive(Clone, Copy)]
struct ShadowRay {
    /// From the offset shading point to the light sample (at parameter 1).
    ray: Ray,
    wi: Vec3,
    cos: f32,
    /// What the light brings along the ray if it is not blocked.
    weight: Rgb,
}

/// Four shading points as lanes: what [`shadow_rays4`] needs of them.
struct Lanes {
    n: [Vec4; 3],
    ng: [Vec4; 3],
    origin: [Vec4; 3],
    time: [f32; 4],
}

impl Lanes {
    /// Lane `l` from frame `s[l]`, its rays leaving from `origin[l]`.
    fn new(s: [&Local; 4], origin: &[Vec3; 4]) -> Lanes {
        let soa = |v: [Vec3; 4]| std::array::from_fn(|k| Vec4::from_array(v.map(|v| v[k])));
        Lanes {
            n: soa(s.map(|s| s.n)),
            ng: soa(s.map(|s| s.ng)),
            origin: soa(*origin),
            time: s.map(|s| s.time),
        }
    }
}

/// Appends to `set` the shadow rays toward `light` for the distribution
/// points `points`, point `k` seen from the frame and ray origin `frame(k)`
/// (`None` for a point that gives no ray: below the horizon, or on the back
/// of the light). Groups of four go through the light's four-wide kernel
/// ([`Emitter::sample4`]) where it has one; the rest, and every point of a
/// light without one, through the portable form ([`shadow_ray`]), which the
/// kernel matches bit for bit.
fn shadow_rays<'a>(
    frame: impl Fn(usize) -> (&'a Local, Vec3),
    points: &[Vec3],
    light: &Emitter,
    set: &mut Vec<Option<ShadowRay>>,
) {
    let d = light.shadow().distribution;
    let wide = if light.four_wide(d) {
        points.len() / 4 * 4
    } else {
        0
    };
    for (g, four) in points[..wide].chunks_exact(4).enumerate() {
        let lanes: [(&Local, Vec3); 4] = std::array::from_fn(|l| frame(4 * g + l));
        let (s, origin) = (lanes.map(|f| f.0), lanes.map(|f| f.1));
        let four: &[Vec3; 4] = four.try_into().expect("chunks of four");
        let ls = light
            .sample4(&s.map(|s| s.p), four, d)
            .expect("a light with a kernel");
        shadow_rays4(&Lanes::new(s, &origin), &ls, set);
    }
    set.extend((wide..points.len()).map(|k| {
        let (s, origin) = frame(k);
        shadow_ray(s, origin, light, points[k], d)
    }));
}

/// The shadow ray from `origin` (the shading point lifted off its surface)
/// toward one distribution point of the light; `None` if there is none to
/// trace (the sample is below the horizon or on the back of the light). The
/// portable form of [`shadow_rays4`].
fn shadow_ray(
    s: &Local,
    origin: Vec3,
    light: &Emitter,
    point: Vec3,
    d: Distribution,
) -> Option<ShadowRay> {
    let ls = light.sample(s.p, point, d)?;
    let wi = ls.dir;
    let cos = s.n.dot(wi);
    if cos <= 0.0 || s.ng.dot(wi) <= 0.0 {
        return None;
    }
    Some(ShadowRay {
        ray: Ray::new(origin, ls.target - origin, s.time),
        wi,
        cos,
        weight: ls.weight,
    })
}

/// [`shadow_ray`] for the four light samples of `ls`, lane `l` from the
/// shading point of lane `l` of `s`, appended to `set`: lane by lane the
/// same rays. A lane gives no ray where its sample is invalid or a cosine
/// at the receiver is at most 0 (a NaN cosine too, as in `shadow_ray`).
fn shadow_rays4(s: &Lanes, ls: &LightSamples4, set: &mut Vec<Option<ShadowRay>>) {
    let dot = |n: &[Vec4; 3], d: &[Vec4; 3]| n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
    let (cos, cos_g) = (dot(&s.n, &ls.dir), dot(&s.ng, &ls.dir));
    let rejected = cos.cmple(Vec4::ZERO) | cos_g.cmple(Vec4::ZERO);
    let valid = ls.valid & !rejected.bitmask();
    let to = std::array::from_fn::<_, 3, _>(|k| (ls.target[k] - s.origin[k]).to_array());
    let origin = s.origin.map(|c| c.to_array());
    let dir = ls.dir.map(|c| c.to_array());
    let (cos, weight) = (cos.to_array(), ls.weight.map(|c| c.to_array()));
    set.extend((0..4).map(|i| {
        (valid >> i & 1 != 0).then(|| ShadowRay {
            ray: Ray::new(
                Vec3::new(origin[0][i], origin[1][i], origin[2][i]),
                Vec3::new(to[0][i], to[1][i], to[2][i]),
                s.time[i],
            ),
            wi: Vec3::new(dir[0][i], dir[1][i], dir[2][i]),
            cos: cos[i],
            weight: Rgb::new(weight[0][i], weight[1][i], weight[2][i]),
        })
    }));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::quad::Quad;
    use crate::scene::{EffectSpec, Light, LightShape, PenumbraModel};

    fn unit(r: &mut Rng) -> Vec3 {
        let v = Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0));
        v.normalize_or(Vec3::Y)
    }

    fn bits(r: &Option<ShadowRay>) -> Option<[u32; 14]> {
        r.map(|r| {
            let mut b = [0; 14];
            let v = [r.ray.origin, r.ray.dir, r.wi].map(|v| v.to_array());
            for (k, c) in v.iter().chain([&r.weight.to_array()]).flatten().enumerate() {
                b[k] = c.to_bits();
            }
            b[12] = r.cos.to_bits();
            b[13] = r.ray.time.to_bits();
            b
        })
    }

    /// Shadow rays prepared in groups (a set of 16 from one frame, and sets
    /// of one from 13 frames: a last group of one) are, ray by ray, bit for
    /// bit the portable form's, through the rectangle's kernel (every square
    /// distribution) and without it (the thesis model, random points):
    /// points on both sides of the light and in its plane, points past the
    /// square's edge, surfaces facing away.
    #[test]
    fn prepared_shadow_rays_are_the_one_by_one_rays() {
        let mut r = Rng::new(47);
        let quad = Quad::new(Vec3::new(-0.5, 4.0, -0.5), Vec3::X, Vec3::Z);
        let mut light = Light {
            shape: LightShape::Rect(quad),
            power: Rgb::new(40.0, 30.0, 20.0),
            model: PenumbraModel::Surface,
            shadow: EffectSpec {
                rays: 16,
                distribution: Distribution::Grid,
            },
        };
        let (mut points, mut set) = (Vec::new(), Vec::new());
        let (mut traced, mut wide) = (0, 0);
        let frame = |r: &mut Rng, k: usize| {
            let p = Vec3::new(r.range(-3.0, 3.0), r.range(0.0, 5.0), r.range(-3.0, 3.0));
            let p = if k.is_multiple_of(50) {
                Vec3::new(p.x, 4.0, p.z)
            } else {
                p
            };
            Local {
                p,
                reach: reach(p, Vec3::new(0.0, 1.3, 4.2)),
                wo: Vec3::Y,
                n: unit(r),
                ng: unit(r),
                front: true,
                time: r.next_f32(),
            }
        };
        for k in 0..2000 {
            light.shadow.distribution = Distribution::ALL[k % 6];
            light.model = [PenumbraModel::Surface, PenumbraModel::Thesis][usize::from(k % 7 == 0)];
            let emitter = Emitter::new(&light);
            wide += usize::from(emitter.four_wide(light.shadow.distribution));
            let frames: Vec<Local> = (0..13).map(|j| frame(&mut r, k + j)).collect();
            let origin = |s: &Local| offset_origin(s.p, s.reach, s.ng, s.ng);
            // One frame, a set of 16.
            light
                .shadow
                .distribution
                .generate(16, 1.0, &mut r, &mut points);
            points[0] = Vec3::new(1.5, -1.5, 0.0);
            set.clear();
            let s = &frames[0];
            shadow_rays(|_| (s, origin(s)), &points, &emitter, &mut set);
            for (q, got) in points.iter().zip(&set) {
                let want = shadow_ray(s, origin(s), &emitter, *q, light.shadow.distribution);
                assert_eq!(bits(got), bits(&want), "{light:?} {q:?}");
                traced += usize::from(got.is_some());
            }
            // Thirteen frames, one point each.
            points.truncate(13);
            set.clear();
            shadow_rays(
                |j| (&frames[j], origin(&frames[j])),
                &points,
                &emitter,
                &mut set,
            );
            assert_eq!(set.len(), 13);
            for ((s, q), got) in frames.iter().zip(&points).zip(&set) {
                assert_eq!(
                    bits(got),
                    bits(&shadow_ray(
                        s,
                        origin(s),
                        &emitter,
                        *q,
                        light.shadow.distribution
                    ))
                );
            }
        }
        assert!(
            wide > 1000 && traced > 5000,
            "{wide} kernel sets, {traced} rays"
        );
    }

    /// Shadow rays from the ground near the world's origin, seen from a
    /// camera four units away, reach the light above: the hit points there
    /// are off by an ulp of the camera's coordinates (1e-7, often below the
    /// ground), so an offset scaled by the points' own tiny coordinates would
    /// leave them under the ground, which would then shadow them (a few dark
    /// samples in the bunny scene's ground).
    #[test]
    fn points_near_the_origin_are_not_shadowed_by_their_own_surface() {
        use crate::scene::{LoadOptions, SceneSource};
        let toml = "[[objects]]\ntype = \"quad\"\norigin = [-5.0, 0.0, -5.0]\n\
                    edge_u = [0.0, 0.0, 10.0]\nedge_v = [10.0, 0.0, 0.0]\n";
        let here = std::path::Path::new(".");
        let src = SceneSource::from_toml(toml, here, here, &LoadOptions::default());
        let scene = src
            .and_then(|s| s.build())
            .unwrap_or_else(|e| panic!("{e}"));
        let (world, eye, light) = (
            &scene.world,
            Vec3::new(0.0, 1.3, 4.2),
            Vec3::new(0.0, 4.0, 0.0),
        );
        let (mut r, mut below) = (Rng::new(5), 0);
        for _ in 0..20_000 {
            let aim = Vec3::new(r.range(-1e-3, 1e-3), 0.0, r.range(-1e-3, 1e-3));
            let ray = Ray::new(eye, (aim - eye).normalize(), 0.0);
            let hit = world
                .intersect(&ray, 0.0, f32::INFINITY)
                .expect("the ground");
            below += usize::from(hit.point.y < 0.0);
            let s = Local::new(&ray, &hit);
            let origin = offset_origin(s.p, s.reach, s.ng, s.ng);
            let shadow = Ray::new(origin, light - origin, 0.0);
            let t = world.transmittance(&shadow, (0.0, SHADOW_END), &scene.transparency, None);
            assert_eq!(t, Some(1.0), "from {:?} (hit at {:?})", origin, hit.point);
        }
        // Not vacuous: many hit points are computed below the ground.
        assert!(below > 1_000, "{below} hit points below the ground");
    }

    /// A closed mesh (an octahedron split into 128 triangles) as OBJ text,
    /// centred at `c` with radius `r`.
    fn blob_obj(c: Vec3, r: f32) -> String {
        let mut obj = String::new();
        let (n, mut verts) = (4usize, 0);
        let corners = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
        let faces = [(0, 1, 2), (1, 3, 2), (3, 4, 2), (4, 0, 2)];
        for (a, b, e) in faces
            .iter()
            .flat_map(|&(a, b, e)| [(a, b, e), (b, a, e + 3)])
        {
            let (a, b, e) = (corners[a], corners[b], corners[e]);
            for i in 0..n {
                for j in 0..n - i {
                    let p = |i: usize, j: usize| {
                        let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                        let q = (a * u + b * v + e * (1.0 - u - v)).normalize();
                        c + q * r * (1.0 + 0.2 * (5.0 * q.x).sin())
                    };
                    let mut tri = |x: Vec3, y: Vec3, z: Vec3| {
                        for v in [x, y, z] {
                            obj += &format!("v {} {} {}\n", v.x, v.y, v.z);
                        }
                        obj += &format!("f {} {} {}\n", verts + 1, verts + 2, verts + 3);
                        verts += 3;
                    };
                    tri(p(i, j), p(i + 1, j), p(i, j + 1));
                    if i + j + 1 < n {
                        tri(p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
                    }
                }
            }
        }
        obj
    }

    /// The pixel-wide path (direct light of all camera rays first, sets of
    /// one ray four hits at a time, shared shafts) gives every camera ray
    /// the radiance and the ray counts the one-by-one path gives, bit for
    /// bit: for one-ray sets on both penumbra models, sets too small for a
    /// shaft of their own, sets with one, a point light, a transparent
    /// caster, a mirror and packets hitting ground, mesh, lights and sky.
    #[test]
    fn pixel_wide_direct_light_matches_one_by_one() {
        use crate::scene::{LoadOptions, SceneSource};
        let dir = tempfile::tempdir().unwrap();
        let obj = dir.path().join("blob.obj");
        std::fs::write(&obj, blob_obj(Vec3::new(0.0, 0.6, 0.0), 0.6)).unwrap();
        let lights = [
            ("surface", 1, "jitter"),
            ("thesis", 1, "grid"),
            ("surface", 1, "random"),
            ("surface", 4, "poisson"),
            ("surface", 16, "semi-jitter"),
        ];
        let mut compared = 0;
        for (k, (model, rays, dist)) in lights.into_iter().enumerate() {
            let toml = format!(
                "[render]\nmax_depth = 2\n\
                 [materials.m]\nalbedo = [0.6, 0.5, 0.4]\nspecular = 0.2\nshininess = 20\n\
                 [materials.mirror]\nreflectivity = 0.8\n\
                 [materials.clear]\ntransparency = 0.5\n\
                 [[objects]]\ntype = \"quad\"\nmaterial = \"m\"\norigin = [-5.0, 0.0, -5.0]\n\
                 edge_u = [0.0, 0.0, 10.0]\nedge_v = [10.0, 0.0, 0.0]\n\
                 [[objects]]\ntype = \"mesh\"\nmaterial = \"m\"\npath = {obj:?}\n\
                 [[objects]]\ntype = \"sphere\"\nmaterial = \"clear\"\ncenter = [1.2, 0.5, 0.3]\nradius = 0.4\n\
                 [[objects]]\ntype = \"sphere\"\nmaterial = \"mirror\"\ncenter = [-1.3, 0.5, 0.2]\nradius = 0.4\n\
                 [[lights]]\ntype = \"rect\"\norigin = [-0.5, 3.0, -0.5]\nedge_u = [1.0, 0.0, 0.0]\n\
                 edge_v = [0.0, 0.0, 1.0]\nradiance = [30.0, 30.0, 30.0]\nmodel = \"{model}\"\n\
                 shadow_rays = {rays}\nshadow_distribution = \"{dist}\"\n\
                 [[lights]]\ntype = \"point\"\nposition = [2.0, 2.5, 2.0]\nintensity = [3.0, 3.0, 3.0]\n"
            );
            let src = SceneSource::from_toml(
                &toml,
                std::path::Path::new("test.toml"),
                dir.path(),
                &LoadOptions::default(),
            );
            let scene = src
                .and_then(|s| s.build())
                .unwrap_or_else(|e| panic!("{e}"));
            let mut r = Rng::new(k as u64);
            let (mut wide, mut one) = (Tracer::new(&scene), Tracer::new(&scene));
            let mut out = Vec::new();
            for _ in 0..300 {
                // A pixel's rays: one origin, directions in a narrow cone
                // toward a point of the scene (or past the light, at the sky).
                let origin = Vec3::new(r.range(-3.0, 3.0), r.range(0.5, 4.0), 5.0);
                let aim = Vec3::new(r.range(-2.0, 2.0), r.range(-0.5, 3.5), r.range(-2.0, 2.0));
                let rays: Vec<Ray> = (0..16)
                    .map(|_| {
                        let jitter = Vec3::new(r.range(-0.05, 0.05), r.range(-0.05, 0.05), 0.0);
                        Ray::new(origin, (aim - origin).normalize() + jitter, 0.0)
                    })
                    .collect();
                let stream = |i: usize| Rng::new(99).derive(i as u64);
                wide.intersect_primary(&rays);
                wide.radiance_primaries(&rays, stream, &mut out);
                for (i, ray) in rays.iter().enumerate() {
                    let l = one.radiance(ray, 0, stream(i));
                    let bits = |c: Rgb| c.to_array().map(f32::to_bits);
                    assert_eq!(bits(out[i]), bits(l), "light {k}, ray {ray:?}");
                    compared += usize::from(l != Rgb::ZERO);
                }
            }
            assert_eq!(wide.stats, one.stats, "light {k}");
            assert!(wide.stats.shadow > 2_000, "light {k}: {:?}", wide.stats);
        }
        assert!(compared > 8_000, "{compared} lit rays compared");
    }
}
