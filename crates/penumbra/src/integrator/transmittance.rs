//! Transparent shadows (the thesis's §2.4: a shadow ray passes a
//! transparent surface, dimmed by its transparency, without bending): the
//! core's loop over the surfaces a shadow segment crosses, which the world
//! finds ([`World::crossings`]) and the integrators weigh here.
//!
//! A material's transparency is a number of the table `transparency` (0:
//! opaque), or NaN where it varies over its surfaces (a textured opacity),
//! read then at each point crossed by `varying`.

use crate::accel::{Hit, ShaftSet, World};
use crate::math::Ray;

/// The fraction of light passing along `ray` within `range`: `None` when
/// an opaque surface blocks it. Each crossing of a surface multiplies it by
/// its material's transparency (a closed shape crossed twice, twice); a
/// material of NaN transparency lets through `varying` of each point
/// crossed. With `shaft`, only what the shaft holds is looked at (the same
/// bits).
#[inline]
pub fn transmittance(
    world: &World,
    ray: &Ray,
    range: (f32, f32),
    transparency: &[f32],
    shaft: Option<&ShaftSet>,
    varying: &dyn Fn(&Hit) -> f32,
) -> Option<f32> {
    let mut trans = 1.0f32;
    let blocked = world.crossings(ray, range, shaft, |c| {
        let kt = transparency[c.material() as usize];
        if kt.is_nan() {
            return c.each_hit(|h| {
                trans *= varying(h);
                trans <= 0.0
            });
        }
        let n = c.count();
        trans *= if n == 1 { kt } else { kt.powi(n) };
        trans <= 0.0
    });
    (!blocked).then_some(trans)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::world::tests::soup_ground_and_sphere;
    use crate::geometry::{Shape, Sphere};
    use crate::math::{Aabb, Vec3};
    use crate::sampling::Rng;

    /// A material whose transparency varies (NaN in the table) is read at
    /// each point crossed: along a segment the light kept is the product of
    /// its value over the hits met one after another by closest-hit
    /// queries (a second way), for the static triangles, the ground quad and
    /// a sphere crossed twice, traced alone or through a shaft; read as
    /// opaque, such a material blocks.
    #[test]
    fn varying_transparency_is_read_where_crossed() {
        let world =
            soup_ground_and_sphere(Shape::Sphere(Sphere::new(Vec3::new(0.5, 1.0, 0.0), 0.4)));
        let transparency = [f32::NAN, f32::NAN];
        let varying = |h: &Hit| 0.3 + 0.6 * h.uv.x.rem_euclid(1.0);
        let (mut set, mut r) = (ShaftSet::default(), Rng::new(43));
        let (mut crossings, mut twice) = (0, 0);
        for _ in 0..200 {
            let p = Vec3::new(r.range(-3.0, 3.0), -1.0, r.range(-3.0, 3.0));
            let light = Aabb::new(Vec3::new(-0.5, 4.0, -0.5), Vec3::new(0.5, 4.0, 0.5));
            assert!(world.gather_shaft(Aabb::new(p, p), light, usize::MAX, &mut set));
            for _ in 0..8 {
                let t = Vec3::new(r.range(-0.5, 0.5), 4.0, r.range(-0.5, 0.5));
                let ray = Ray::new(p, t - p, 0.0);
                let range = (0.0, 1.0 - 1e-4);
                let (mut want, mut from, mut n, mut on_sphere) = (1.0f32, range.0, 0, 0);
                while let Some(h) = world.intersect(&ray, from, range.1) {
                    want *= varying(&h);
                    (from, n) = (h.t, n + 1);
                    on_sphere += usize::from(h.object == 2);
                }
                crossings += n;
                twice += usize::from(on_sphere == 2);
                for shaft in [None, Some(&set)] {
                    let got = transmittance(&world, &ray, range, &transparency, shaft, &varying);
                    let got = got.expect("nothing is opaque");
                    assert!(
                        (got - want).abs() <= 1e-5 * want,
                        "{ray:?}: {got} vs {want}"
                    );
                    let opaque = |_: &Hit| 0.0;
                    let blocked = transmittance(&world, &ray, range, &transparency, shaft, &opaque);
                    assert_eq!(blocked, None, "{ray:?}: crosses the ground");
                }
            }
        }
        assert!(
            crossings > 2000 && twice > 50,
            "{crossings} crossings, {twice} through the sphere"
        );
    }

    /// Fixed transparencies multiply, a closed shape's twice: the soup's
    /// see-through triangles and sphere (material 1, 0.5) dim a segment by
    /// 0.5 per crossing found by closest-hit queries, and an opaque one
    /// (material 0) blocks it.
    #[test]
    fn fixed_transparencies_multiply_per_crossing() {
        let world =
            soup_ground_and_sphere(Shape::Sphere(Sphere::new(Vec3::new(0.5, 1.0, 0.0), 0.4)));
        let transparency = [0.0, 0.5];
        let mut r = Rng::new(5);
        let (mut dimmed, mut blocked) = (0, 0);
        let none = |_: &Hit| 0.0;
        for _ in 0..2000 {
            let p = Vec3::new(r.range(-3.0, 3.0), 0.01, r.range(-3.0, 3.0));
            let t = Vec3::new(r.range(-0.5, 0.5), 4.0, r.range(-0.5, 0.5));
            let ray = Ray::new(p, t - p, 0.0);
            let range = (0.0, 1.0 - 1e-4);
            let (mut want, mut from) = (Some(1.0f32), range.0);
            while let Some(h) = world.intersect(&ray, from, range.1) {
                want = want
                    .map(|w| w * transparency[h.material as usize])
                    .filter(|w| *w > 0.0);
                from = h.t;
            }
            let got = transmittance(&world, &ray, range, &transparency, None, &none);
            assert_eq!(got, want, "{ray:?}");
            dimmed += usize::from(got.is_some_and(|t| t < 1.0));
            blocked += usize::from(got.is_none());
        }
        assert!(
            dimmed > 20 && blocked > 50,
            "{dimmed} dimmed, {blocked} blocked"
        );
    }
}
