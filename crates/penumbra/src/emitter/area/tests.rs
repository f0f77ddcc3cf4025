//! A textured area light against independent quadratures of its textured
//! radiance: what a point receives (drawn on the light, and found by rays
//! that hit it) and the power its rays carry; each drawn point's pdf and
//! weight against what the light says of that point when a ray hits it.

use super::{Area, PenumbraModel};
use crate::emitter::{EmitterModel, Reference};
use crate::geometry::quad::Quad;
use crate::geometry::sphere::intersect_sphere;
use crate::geometry::surface::tests::{still, triangles};
use crate::geometry::{Shape, ShapeHit, Sphere, Surface};
use crate::input::image::Image;
use crate::math::{Frame, Ray, Rgb, Vec2, Vec3};
use crate::sampling::warp::square_to_cosine_hemisphere;
use crate::sampling::{Distribution, Rng};
use crate::texture::bitmap::{Bitmap, Filter as BitmapFilter, Wrap};
use crate::texture::checkerboard::Checkerboard;
use crate::texture::{Texture, UvTransform};
use std::sync::Arc;

/// A 2 × 2 checker of two colours, moved and squeezed in `(u, v)` so that
/// no swap or mirror of `u` and `v` leaves it the same.
fn checker() -> Texture {
    Texture::Checkerboard(Checkerboard {
        color0: Box::new(Texture::Constant(Rgb::new(1.0, 2.0, 0.5))),
        color1: Box::new(Texture::Constant(Rgb::new(6.0, 0.5, 3.0))),
        to_uv: UvTransform {
            rows: [[0.7, 0.0, 0.1], [0.0, 0.9, 0.0]],
        },
    })
}

fn light(surface: Surface) -> Area {
    Area::new(surface, checker(), PenumbraModel::Surface)
}

/// An uneven bitmap of 8 × 4 texels, bilinear and repeated: dim texels,
/// a few black ones and one 40 times brighter, of another hue.
fn uneven() -> Texture {
    let mut pixels = Vec::new();
    for y in 0..4 {
        for x in 0..8 {
            let c = match (x, y) {
                (5, 1) => [40.0, 30.0, 20.0],
                (0, _) | (_, 3) => [0.0, 0.0, 0.0],
                _ => [0.5, 0.6, 0.8],
            };
            pixels.extend(c);
        }
    }
    let image = Image {
        width: 8,
        height: 4,
        channels: 3,
        pixels,
    };
    Texture::Bitmap(Bitmap::new(
        Arc::new(image),
        BitmapFilter::Bilinear,
        Wrap::Repeat,
        UvTransform::IDENTITY,
    ))
}

/// The mean and standard error of each channel of `n` draws of `f`.
fn estimate(n: usize, mut f: impl FnMut() -> Rgb) -> (Rgb, Rgb) {
    let (mut s, mut s2) = ([0f64; 3], [0f64; 3]);
    for _ in 0..n {
        let x = f().to_array();
        for k in 0..3 {
            s[k] += f64::from(x[k]);
            s2[k] += f64::from(x[k]) * f64::from(x[k]);
        }
    }
    let m = n as f64;
    let mean: [f64; 3] = std::array::from_fn(|k| s[k] / m);
    let se: [f64; 3] =
        std::array::from_fn(|k| ((s2[k] / m - mean[k] * mean[k]).max(0.0) / m).sqrt());
    let rgb = |a: [f64; 3]| Rgb::new(a[0] as f32, a[1] as f32, a[2] as f32);
    (rgb(mean), rgb(se))
}

/// `got` within 4.5 standard errors (and 0.5% for the quadrature's own
/// error at the checker's edges) of `want`, channel by channel.
fn agrees(what: &str, (got, se): (Rgb, Rgb), want: Rgb) {
    for k in 0..3 {
        let (g, s, w) = (got.to_array()[k], se.to_array()[k], want.to_array()[k]);
        assert!(
            (g - w).abs() <= 4.5 * s + 5e-3 * w,
            "{what}, channel {k}: {g} ± {s}, quadrature {w}"
        );
    }
}

/// Irradiance at `x` (normal `nx`) from points `p(u, v)` of the light with
/// normal `n(u, v)` and area element `da(u, v) du dv`, over the unit square
/// of `(u, v)` on an `nu × nv` midpoint grid, the light's radiance taken
/// from the texture at `(u, v)`; only the side each normal faces emits.
fn irradiance(
    tex: &Texture,
    x: Vec3,
    nx: Vec3,
    (nu, nv): (usize, usize),
    point: impl Fn(Vec2) -> (Vec3, Vec3, f32),
) -> Rgb {
    let mut sum = Rgb::ZERO;
    for j in 0..nv {
        for i in 0..nu {
            let uv = Vec2::new((i as f32 + 0.5) / nu as f32, (j as f32 + 0.5) / nv as f32);
            let (p, n, da) = point(uv);
            let to = p - x;
            let r2 = to.length_squared();
            let d = to / r2.sqrt();
            let (cos_x, cos_l) = (nx.dot(d), -n.dot(d));
            if cos_x > 0.0 && cos_l > 0.0 {
                sum += tex.eval_uv(uv) * (cos_x * cos_l / r2 * da);
            }
        }
    }
    sum * (1.0 / (nu * nv) as f32)
}

/// The estimate of the irradiance at `x` (normal +y) from the light's own
/// samples, each checked against the light at its target: the pdf it
/// carries is [`Area::pdf`] there, its weight the radiance a ray hitting
/// that point sees (found at the surface coordinates `hit_uv` gives of the
/// ray's hit) over that pdf.
fn sampled(a: &Area, x: Vec3, hit_uv: impl Fn(&Ray) -> Option<(Vec2, Vec3)>) -> (Rgb, Rgb) {
    let r = Reference::new(x, 0.0);
    let mut rng = Rng::new(5);
    let n = 200_000;
    let mut missed = 0;
    let got = estimate(n, || {
        let point = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
        let Some(s) = a.sample_one(r, point, Distribution::Jitter) else {
            return Rgb::ZERO;
        };
        let ray = Ray::new(x, s.dir, 0.0);
        // A ray toward a point at the very edge may miss by rounding.
        let Some((uv, n)) = hit_uv(&ray) else {
            missed += 1;
            return s.weight * s.dir.y.max(0.0);
        };
        // Toward a grazing point of a sphere the ray's hit (and its
        // normal) is ill-conditioned: checked elsewhere only.
        if -n.dot(s.dir) < 0.05 {
            return s.weight * s.dir.y.max(0.0);
        }
        let pdf = a.pdf(r, s.target, n);
        assert!((s.pdf - pdf).abs() <= 1e-3 * pdf, "pdf {} vs {pdf}", s.pdf);
        let le = a.eval(n, uv, s.dir);
        let want = le * (1.0 / pdf);
        assert!(
            (s.weight - want).abs().max_element() <= 1e-3 * want.max_element() + 1e-5,
            "weight {:?} vs L/pdf {want:?} at uv {uv}",
            s.weight
        );
        s.weight * s.dir.y.max(0.0)
    });
    assert!(
        missed * 1000 < n,
        "{missed} of {n} rays toward samples miss the light"
    );
    got
}

/// The estimate of the same irradiance from rays leaving `x` cosine-
/// distributed about +y, each seeing the light's radiance where it hits
/// it: `π · L`.
fn gathered(a: &Area, x: Vec3, hit_uv: impl Fn(&Ray) -> Option<(Vec2, Vec3)>) -> (Rgb, Rgb) {
    let frame = Frame::from_normal(Vec3::Y);
    let mut rng = Rng::new(9);
    estimate(400_000, || {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let dir = frame.to_world(square_to_cosine_hemisphere(u));
        let ray = Ray::new(x, dir, 0.0);
        match hit_uv(&ray) {
            Some((uv, n)) => a.eval(n, uv, dir) * std::f32::consts::PI,
            None => Rgb::ZERO,
        }
    })
}

/// A rectangle light with a checker texture, seen from a point below:
/// the irradiance from its samples and from rays that hit it both match
/// a quadrature of the texture over the rectangle's `(s, t)`, and every
/// sample's pdf and weight are what the light says of its point.
#[test]
fn a_textured_rectangle_lights_a_point_as_its_quadrature() {
    let q = Quad::new(Vec3::new(-0.5, 0.5, -0.5), Vec3::X, Vec3::Z);
    let a = light(still(Shape::Quad(q)));
    assert!(q.normal.y < 0.0, "the light faces the point");
    let x = Vec3::new(0.3, 0.0, -0.2);
    let want = irradiance(&checker(), x, Vec3::Y, (512, 512), |uv| {
        (q.point(uv.x, uv.y), q.normal, q.area())
    });
    let hit = |ray: &Ray| {
        q.intersect(ray, 1e-4, f32::INFINITY)
            .map(|(_, s, t)| (Vec2::new(s, t), q.normal))
    };
    agrees("rectangle, light samples", sampled(&a, x, hit), want);
    agrees("rectangle, rays that hit it", gathered(&a, x, hit), want);
    // The texture is seen: the light is not its mean colour.
    let plain = Area {
        radiance: Texture::Constant(a.mean_radiance()),
        ..a.clone()
    };
    let flat = sampled(&plain, x, hit).0;
    assert!((flat - want).abs().max_element() > 0.05 * want.max_element());
}

/// A sphere light with a checker texture in Mitsuba's `(u, v)` (the
/// azimuth about z over 2π, the polar angle from +z over π), drawn from
/// outside in the cone it subtends: as for the rectangle.
#[test]
fn a_textured_sphere_lights_a_point_as_its_quadrature() {
    let (c, radius) = (Vec3::new(0.2, 2.0, 0.4), 0.6);
    let ball = Sphere::new(c, radius);
    let a = light(still(Shape::Sphere(ball)));
    let x = Vec3::new(-0.3, 0.0, 0.1);
    let (tau, pi) = (std::f32::consts::TAU, std::f32::consts::PI);
    let want = irradiance(&checker(), x, Vec3::Y, (1024, 512), |uv| {
        let (phi, theta) = (tau * uv.x, pi * uv.y);
        let n = Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        );
        (c + radius * n, n, radius * radius * theta.sin() * tau * pi)
    });
    let shape = a.surface.shape().clone();
    let hit = |ray: &Ray| {
        let t = intersect_sphere(ray, c, radius, 1e-4, f32::INFINITY)?;
        let p = ray.at(t);
        let g = shape.geometry(&[], &ShapeHit::at(t), p);
        Some((g.uv, g.ng))
    };
    agrees("sphere, light samples", sampled(&a, x, hit), want);
    agrees("sphere, rays that hit it", gathered(&a, x, hit), want);
}

/// The rays a textured light draws for light tracing carry its power,
/// `π ∫ L dA` by a quadrature of the texture (a rectangle, a sphere); the
/// points drawn on it carry their own radiance (`sample_position`'s
/// surface coordinates are those of the point).
#[test]
fn a_textured_light_s_rays_carry_its_power() {
    let q = Quad::new(
        Vec3::new(-0.5, 2.0, -0.5),
        Vec3::new(1.5, 0.0, 0.0),
        Vec3::Z,
    );
    let ball = Sphere::new(Vec3::new(0.2, 2.0, 0.4), 0.6);
    let (tau, pi) = (std::f32::consts::TAU, std::f32::consts::PI);
    let tex = checker();
    let mean = |n: usize, da: &dyn Fn(Vec2) -> f32| {
        let mut sum = Rgb::ZERO;
        for j in 0..n {
            for i in 0..n {
                let uv = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                sum += tex.eval_uv(uv) * da(uv);
            }
        }
        sum * (pi / (n * n) as f32)
    };
    let cases: [(Area, Rgb); 2] = [
        (light(still(Shape::Quad(q))), mean(512, &|_| q.area())),
        (
            light(still(Shape::Sphere(ball))),
            mean(512, &|uv| 0.36 * (pi * uv.y).sin() * tau * pi),
        ),
    ];
    for (a, want) in cases {
        let mut rng = Rng::new(3);
        let mut u2 = || Vec2::new(rng.next_f32(), rng.next_f32());
        let got = estimate(200_000, || {
            let (up, ud) = (u2(), u2());
            a.sample_ray(up, ud, 0.0, (Vec3::ZERO, 10.0))
                .map_or(Rgb::ZERO, |r| r.weight)
        });
        agrees("power of the rays", got, want);
        let s = a.sample_position(u2(), 0.0).expect("a point");
        let shape = a.surface.shape();
        let uv = match shape.as_quad() {
            Some(q) => {
                let e = s.p - q.origin;
                Vec2::new(e.dot(q.edge_u) / q.edge_u.length_squared(), e.dot(q.edge_v))
            }
            None => shape.geometry(&[], &ShapeHit::default(), s.p).uv,
        };
        assert!((s.uv - uv).length() < 1e-4, "{} vs {uv}", s.uv);
    }
}

/// A point drawn on a mesh carries the surface coordinates a hit there
/// would: without texture coordinates, the barycentric weights of the
/// triangle's second and third corners.
#[test]
fn a_point_drawn_on_a_mesh_carries_its_barycentrics() {
    let corners = [
        [
            Vec3::new(-0.5, 2.0, -0.5),
            Vec3::new(0.5, 2.0, -0.5),
            Vec3::new(-0.5, 2.0, 0.5),
        ],
        [
            Vec3::new(0.5, 2.2, -0.5),
            Vec3::new(0.5, 2.2, 0.5),
            Vec3::new(-0.5, 2.4, 0.5),
        ],
    ];
    let a = light(triangles(&corners));
    let mut rng = Rng::new(11);
    for _ in 0..200 {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let s = a.sample_position(u, 0.0).expect("a point");
        let found = corners.iter().any(|[p0, p1, p2]| {
            let q = *p0 + s.uv.x * (*p1 - *p0) + s.uv.y * (*p2 - *p0);
            (q - s.p).length() < 1e-4
        });
        assert!(found, "{} at {}", s.p, s.uv);
    }
}

/// The rectangle and the sphere of the tests, each a light of `tex`, with
/// their maps from `(u, v)` to the point, its normal and `|∂p/∂u × ∂p/∂v|`
/// (written here again, independently of the light's own).
#[allow(clippy::type_complexity)]
fn charted(tex: &Texture) -> Vec<(&'static str, Area, Box<dyn Fn(Vec2) -> (Vec3, Vec3, f32)>)> {
    let q = Quad::new(
        Vec3::new(-0.5, 0.5, -0.5),
        Vec3::new(1.4, 0.0, 0.0),
        Vec3::new(0.0, 0.2, 0.9),
    );
    let (c, radius) = (Vec3::new(0.2, 2.0, 0.4), 0.6);
    let (tau, pi) = (std::f32::consts::TAU, std::f32::consts::PI);
    let sphere = move |uv: Vec2| {
        let (phi, theta) = (tau * uv.x, pi * uv.y);
        let n = Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        );
        (c + radius * n, n, radius * radius * theta.sin() * tau * pi)
    };
    vec![
        (
            "rectangle",
            Area::new(still(Shape::Quad(q)), tex.clone(), PenumbraModel::Surface),
            Box::new(move |uv: Vec2| (q.point(uv.x, uv.y), q.normal, q.area())),
        ),
        (
            "sphere",
            Area::new(
                still(Shape::Sphere(Sphere::new(c, radius))),
                tex.clone(),
                PenumbraModel::Surface,
            ),
            Box::new(sphere),
        ),
    ]
}

/// Points drawn by a bitmap's texels land where their density says: over
/// 16 × 16 cells of `(u, v)`, the counts of 200 000 draws against the
/// density of each cell's points (found from the points, through the
/// light's inverse map) times the area each cell stretches to, by
/// χ²; no draw lands where the density is 0. A sphere keeps its draw in
/// the cone it subtends.
#[test]
fn points_drawn_by_the_texture_follow_their_density() {
    let tex = uneven();
    for (what, a, chart) in charted(&tex) {
        let Some(by) = a.by_texture.clone() else {
            assert_eq!(what, "sphere");
            continue;
        };
        let (n, cells, sub) = (200_000usize, 16usize, 4usize);
        let mut counts = vec![0u32; cells * cells];
        let mut rng = Rng::new(17);
        for _ in 0..n {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let s = a.sample_position(u, 0.0).expect("a point");
            let (p, _, _) = chart(s.uv);
            assert!(
                (p - s.p).length() < 1e-4,
                "{what}: {} at {} is not {p}",
                s.p,
                s.uv
            );
            let (i, j) = (
                ((s.uv.x * cells as f32) as usize).min(cells - 1),
                ((s.uv.y * cells as f32) as usize).min(cells - 1),
            );
            counts[j * cells + i] += 1;
        }
        let mut chi2 = 0.0f64;
        let mut total = 0.0f64;
        let mut bins = 0usize;
        let step = 1.0 / (cells * sub) as f32;
        for j in 0..cells {
            for i in 0..cells {
                let mut prob = 0.0f64;
                for b in 0..sub {
                    for c in 0..sub {
                        let uv = Vec2::new(
                            ((i * sub + c) as f32 + 0.5) * step,
                            ((j * sub + b) as f32 + 0.5) * step,
                        );
                        let (p, _, da) = chart(uv);
                        prob += f64::from(by.pdf_area(p) * da * step * step);
                    }
                }
                total += prob;
                let observed = f64::from(counts[j * cells + i]);
                if prob == 0.0 {
                    assert_eq!(
                        observed, 0.0,
                        "{what}: draws in cell ({i}, {j}) of density 0"
                    );
                    continue;
                }
                let expected = prob * n as f64;
                chi2 += (observed - expected).powi(2) / expected;
                bins += 1;
            }
        }
        assert!(
            (total - 1.0).abs() < 2e-3,
            "{what}: the density integrates to {total}"
        );
        let dof = (bins - 1) as f64;
        assert!(
            chi2 < dof + 6.0 * (2.0 * dof).sqrt(),
            "{what}: χ² {chi2} over {dof} degrees of freedom"
        );
    }
}

/// A light drawn by its uneven texture lights a point as the quadrature
/// of the texture does, and as the same light drawn uniformly does, each
/// sample's pdf and weight checked against the light at its point; a
/// rectangle's estimate (drawn by the texture) has a smaller variance (the
/// ratio is printed); a sphere is drawn in its cone either way.
#[test]
fn a_light_drawn_by_its_texture_agrees_with_the_uniform_draw_with_less_noise() {
    let tex = uneven();
    for (what, a, chart) in charted(&tex) {
        let x = Vec3::new(0.3, 0.0, -0.2);
        let want = irradiance(&tex, x, Vec3::Y, (1024, 1024), &chart);
        let shape = a.surface.shape().clone();
        let hit = |ray: &Ray| {
            let h = shape.intersect(ray, 1e-4, f32::INFINITY)?;
            let g = shape.geometry(&[], &h, ray.at(h.t));
            Some((g.uv, g.ng))
        };
        let (by, by_se) = sampled(&a, x, hit);
        let uniform = a.clone().uniform();
        let (flat, flat_se) = sampled(&uniform, x, hit);
        agrees(&format!("{what}, drawn by the texture"), (by, by_se), want);
        agrees(&format!("{what}, drawn uniformly"), (flat, flat_se), want);
        if a.by_texture.is_none() {
            continue;
        }
        let ratio = (flat_se.to_array().iter().map(|s| s * s).sum::<f32>())
            / (by_se.to_array().iter().map(|s| s * s).sum::<f32>());
        println!("{what}: variance drawn uniformly over drawn by the texture: {ratio:.2}");
        assert!(ratio > 2.0, "{what}: variance ratio {ratio}");
    }
}
