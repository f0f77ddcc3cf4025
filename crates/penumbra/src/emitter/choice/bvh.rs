//! `bvh`: a binary tree over the bounded emitters, descended from the root
//! by choosing each child in proportion to its importance at the shading
//! point (pbrt-v4's `BVHLightSampler`, after Conty Estevez and Kulla,
//! *Importance sampling of many lights*, 2018). The emitters at infinity
//! (`constant`, `envmap`, `directional`) have no bounds: each is chosen
//! with probability `1 / (m + 1)` for `m` of them beside a tree, the tree
//! with the remaining `1 / (m + 1)`, as pbrt-v4 does.
//!
//! **One leaf per emitter.** An area light on a triangle mesh is one
//! emitter here (it samples its triangles by area), so its leaf bounds the
//! whole mesh: the box around its triangles and a cone around their
//! normals ([`Surface::normal_cone`](crate::geometry::Surface::normal_cone)).
//! pbrt-v4 makes every triangle a light of its own; doing so here would
//! change what an emitter index names (hits carry it, multiple importance
//! sampling looks its probability up by it) and the emitters' sampling, for
//! a gain only on large emitting meshes seen from nearby. Scenes of many
//! small lights, which the tree is for, are many emitters.
//!
//! **Building.** Top-down, in pbrt-v4's way: at each node the emitters'
//! box centres are cut into 12 buckets along each axis and the cut with
//! the least [`cost`](crate::emitter::bounds::LightBounds::cost) (power
//! times the measure of the emitted directions times the box's area, for
//! both halves) is taken; where no cut separates them (centres that
//! coincide), or past depth 40, the emitters are split at the median
//! along the longest axis, which bounds the depth by 40 + 24 for 2²⁴
//! emitters. Emitters of no power are left out of the tree (never chosen).
//!
//! **Probabilities.** The descent remaps its uniform number at every
//! level, so one number chooses the leaf; [`LightBvh::pmf`] follows the
//! emitter's path from the root (bits of its left and right turns, kept
//! per emitter) and multiplies the same ratios, in the same order, that
//! [`LightBvh::sample`] multiplied. Where both children of a node have
//! importance 0 at the point, nothing below can light it and the sample
//! gives no emitter. A tree of one emitter is a leaf at the root, chosen
//! at every point: pbrt-v4 asks a lone root's importance first, which can
//! only tell that the sample will bring nothing, at the cost of computing
//! it at every vertex of a scene with one light.

use crate::emitter::bounds::LightBounds;
use crate::emitter::Emitter;
use crate::math::{Aabb, Vec3};

/// Buckets per axis when a node's emitters are cut.
const BUCKETS: usize = 12;

/// The depth from which nodes are split at the median.
const MEDIAN_DEPTH: u32 = 40;

/// The largest `f32` below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// A node of the tree: a leaf holds one emitter; an interior node's first
/// child follows it, its second is at `index`.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: LightBounds,
    /// The emitter of a leaf, the second child of an interior node.
    index: u32,
    leaf: bool,
}

/// Where an emitter is.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Place {
    /// Not chosen (no power).
    Nowhere,
    /// Among the emitters at infinity.
    Infinite,
    /// In the tree, at the end of this path from the root: bit `d` set for
    /// a turn to the second child at depth `d`.
    Tree(u64),
}

/// The light BVH of a scene's emitters.
#[derive(Clone, Debug)]
pub struct LightBvh {
    nodes: Vec<Node>,
    infinite: Vec<u32>,
    place: Vec<Place>,
}

impl LightBvh {
    /// The tree over the bounded emitters of `emitters` that emit
    /// something, with the emitters at infinity beside it.
    pub fn new(emitters: &[Emitter]) -> LightBvh {
        let mut bvh = LightBvh {
            nodes: Vec::new(),
            infinite: Vec::new(),
            place: vec![Place::Nowhere; emitters.len()],
        };
        let mut items = Vec::new();
        for (k, e) in emitters.iter().enumerate() {
            match e.bounds() {
                None => {
                    bvh.infinite.push(k as u32);
                    bvh.place[k] = Place::Infinite;
                }
                Some(b) if b.phi > 0.0 && b.phi.is_finite() && !b.bounds.is_empty() => {
                    items.push((k as u32, b));
                }
                Some(_) => {}
            }
        }
        if !items.is_empty() {
            bvh.build(&mut items, 0, 0);
        }
        bvh
    }

    /// The emitters at infinity, and the probability that one of them is
    /// chosen rather than the tree.
    #[inline]
    fn p_infinite(&self) -> f32 {
        let m = self.infinite.len();
        let tree = usize::from(!self.nodes.is_empty());
        if m == 0 {
            0.0
        } else {
            m as f32 / (m + tree) as f32
        }
    }

    /// Builds the subtree of `items` at `depth`, reached by `path`; returns
    /// its bounds.
    fn build(&mut self, items: &mut [(u32, LightBounds)], path: u64, depth: u32) -> LightBounds {
        if let [(k, b)] = items {
            self.nodes.push(Node {
                bounds: *b,
                index: *k,
                leaf: true,
            });
            self.place[*k as usize] = Place::Tree(path);
            return *b;
        }
        let mid = split(items, depth);
        let at = self.nodes.len();
        // Filled in once both children are built.
        self.nodes.push(Node {
            bounds: items[0].1,
            index: 0,
            leaf: false,
        });
        let (left, right) = items.split_at_mut(mid);
        let a = self.build(left, path, depth + 1);
        let second = self.nodes.len() as u32;
        let b = self.build(right, path | 1 << depth, depth + 1);
        let bounds = a.union(&b);
        self.nodes[at] = Node {
            bounds,
            index: second,
            leaf: false,
        };
        bounds
    }

    /// The emitter chosen for the point `p` with normal `n` by `u` in
    /// [0, 1), and its probability (see the [module docs](self)).
    pub fn sample(&self, p: Vec3, n: Vec3, u: f32) -> Option<(u32, f32)> {
        let p_inf = self.p_infinite();
        if u < p_inf {
            let m = self.infinite.len();
            let k = ((u / p_inf * m as f32) as usize).min(m - 1);
            return Some((self.infinite[k], p_inf / m as f32));
        }
        if self.nodes.is_empty() {
            return None;
        }
        let mut u = ((u - p_inf) / (1.0 - p_inf)).min(ONE_MINUS_EPSILON);
        let mut pmf = 1.0 - p_inf;
        let mut i = 0;
        loop {
            let node = &self.nodes[i];
            if node.leaf {
                return Some((node.index, pmf));
            }
            let (a, b) = (i + 1, node.index as usize);
            let (ca, cb) = self.children(a, b, p, n)?;
            let pa = ca / (ca + cb);
            if u < pa {
                pmf *= pa;
                u = (u / pa).min(ONE_MINUS_EPSILON);
                i = a;
            } else {
                pmf *= cb / (ca + cb);
                u = ((u - pa) / (1.0 - pa)).min(ONE_MINUS_EPSILON);
                i = b;
            }
        }
    }

    /// The probability that [`sample`](Self::sample) chooses `emitter`
    /// for the point `p` with normal `n`.
    pub fn pmf(&self, p: Vec3, n: Vec3, emitter: u32) -> f32 {
        let Some(&place) = self.place.get(emitter as usize) else {
            return 0.0;
        };
        let p_inf = self.p_infinite();
        let path = match place {
            Place::Nowhere => return 0.0,
            Place::Infinite => return p_inf / self.infinite.len() as f32,
            Place::Tree(path) => path,
        };
        let mut pmf = 1.0 - p_inf;
        let (mut i, mut depth) = (0, 0);
        loop {
            let node = &self.nodes[i];
            if node.leaf {
                return pmf;
            }
            let (a, b) = (i + 1, node.index as usize);
            let Some((ca, cb)) = self.children(a, b, p, n) else {
                return 0.0;
            };
            if path >> depth & 1 == 0 {
                pmf *= ca / (ca + cb);
                i = a;
            } else {
                pmf *= cb / (ca + cb);
                i = b;
            }
            depth += 1;
        }
    }

    /// The importances of nodes `a` and `b` at `p`; `None` if both are 0.
    #[inline]
    fn children(&self, a: usize, b: usize, p: Vec3, n: Vec3) -> Option<(f32, f32)> {
        let ca = self.nodes[a].bounds.importance(p, n);
        let cb = self.nodes[b].bounds.importance(p, n);
        (ca > 0.0 || cb > 0.0).then_some((ca, cb))
    }

    /// The depth of the deepest leaf (0 for a tree of one leaf or none).
    pub fn depth(&self) -> u32 {
        fn walk(nodes: &[Node], i: usize) -> u32 {
            if nodes[i].leaf {
                0
            } else {
                1 + walk(nodes, i + 1).max(walk(nodes, nodes[i].index as usize))
            }
        }
        if self.nodes.is_empty() {
            0
        } else {
            walk(&self.nodes, 0)
        }
    }
}

/// Orders `items` (at least two) so that the first `mid` go to the first
/// child and the rest to the second, and returns `mid` (in `1..len`).
fn split(items: &mut [(u32, LightBounds)], depth: u32) -> usize {
    let bounds = items
        .iter()
        .fold(Aabb::EMPTY, |b, (_, l)| b.union(l.bounds));
    let centres = items
        .iter()
        .fold(Aabb::EMPTY, |b, (_, l)| b.grow(l.centroid()));
    let bucket = |c: Vec3, dim: usize| {
        let (lo, hi) = (centres.min[dim], centres.max[dim]);
        let t = (c[dim] - lo) / (hi - lo);
        ((t * BUCKETS as f32) as usize).min(BUCKETS - 1)
    };
    let mut best: Option<(f32, usize, usize)> = None;
    if depth < MEDIAN_DEPTH {
        for dim in 0..3 {
            if centres.max[dim] <= centres.min[dim] {
                continue;
            }
            let mut buckets: [Option<LightBounds>; BUCKETS] = [None; BUCKETS];
            for (_, l) in items.iter() {
                let k = bucket(l.centroid(), dim);
                buckets[k] = Some(match buckets[k] {
                    Some(b) => b.union(l),
                    None => *l,
                });
            }
            let gather = |range: std::ops::Range<usize>| {
                buckets[range]
                    .iter()
                    .flatten()
                    .fold(None, |acc: Option<LightBounds>, b| {
                        Some(acc.map_or(*b, |a| a.union(b)))
                    })
            };
            for cut in 1..BUCKETS {
                let (Some(a), Some(b)) = (gather(0..cut), gather(cut..BUCKETS)) else {
                    continue;
                };
                let cost = a.cost(bounds, dim) + b.cost(bounds, dim);
                if cost.is_finite() && best.is_none_or(|(c, ..)| cost < c) {
                    best = Some((cost, dim, cut));
                }
            }
        }
    }
    if let Some((_, dim, cut)) = best {
        let mut mid = 0;
        for i in 0..items.len() {
            if bucket(items[i].1.centroid(), dim) < cut {
                items.swap(i, mid);
                mid += 1;
            }
        }
        if mid > 0 && mid < items.len() {
            return mid;
        }
    }
    let dim = centres.longest_axis();
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| {
        a.1.centroid()[dim].total_cmp(&b.1.centroid()[dim])
    });
    mid
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::emitter::bounds::tests::random_unit;
    use crate::emitter::choice::tests::{area, many_emitters};
    use crate::emitter::Reference;
    use crate::geometry::quad::Quad;
    use crate::geometry::Shape;
    use crate::math::Frame;
    use crate::sampling::{Distribution, Rng};

    /// The tree never gives probability 0 to an emitter that can light the
    /// point: wherever a sample of a bounded emitter from the point brings
    /// light (a positive weight, at an angle to the surface's normal), the
    /// BVH's probability of that emitter is positive; every emitter at
    /// infinity is always possible.
    #[test]
    fn importance_is_conservative() {
        let emitters = many_emitters(true);
        let bvh = LightBvh::new(&emitters);
        let mut rng = Rng::new(19);
        let mut lit = 0;
        for _ in 0..3000 {
            let p = Vec3::new(
                rng.range(-6.0, 6.0),
                rng.range(-2.0, 5.0),
                rng.range(-6.0, 6.0),
            );
            let n = random_unit(&mut rng);
            for (k, e) in emitters.iter().enumerate() {
                if e.bounds().is_none() {
                    assert!(bvh.pmf(p, n, k as u32) > 0.0);
                    continue;
                }
                let can = (0..16).any(|_| {
                    let point = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
                    e.sample_one(Reference::new(p, 0.0), point, Distribution::Random)
                        .is_some_and(|s| s.weight.max_element() > 0.0 && s.dir.dot(n).abs() > 1e-3)
                });
                if can {
                    lit += 1;
                    assert!(
                        bvh.pmf(p, n, k as u32) > 0.0,
                        "emitter {k} lights {p:?} (normal {n:?}) but has probability 0"
                    );
                }
            }
        }
        assert!(lit > 20_000, "{lit} lit pairs");
    }

    /// Where an emitter's back faces the point, the tree does not choose
    /// it: a point below a one-sided square facing up, with a second
    /// square facing it, always gets the second.
    #[test]
    fn emitters_facing_away_are_not_chosen() {
        let up = Quad::new(Vec3::new(-0.5, 1.0, -0.5), Vec3::Z, Vec3::X);
        let down = Quad::new(Vec3::new(3.5, 1.0, -0.5), Vec3::X, Vec3::Z);
        assert!(up.normal.y > 0.0 && down.normal.y < 0.0);
        let emitters = [area(Shape::Quad(up), 1.0), area(Shape::Quad(down), 1.0)];
        let bvh = LightBvh::new(&emitters);
        let p = Vec3::new(0.0, 0.0, 0.0);
        assert_eq!(bvh.pmf(p, Vec3::Y, 0), 0.0);
        assert_eq!(bvh.pmf(p, Vec3::Y, 1), 1.0);
        for k in 0..100 {
            let u = (k as f32 + 0.5) / 100.0;
            assert_eq!(bvh.sample(p, Vec3::Y, u), Some((1, 1.0)));
        }
    }

    /// A thousand small lights in a grid make a tree of 1,999 nodes, a leaf
    /// each, no deeper than the median split allows; near one light of a
    /// grid of equal ones, that light is far likelier than under a uniform
    /// choice.
    #[test]
    fn a_grid_of_lights_is_a_shallow_tree() {
        let mut emitters = Vec::new();
        for i in 0..40 {
            for j in 0..25 {
                let at = Vec3::new(i as f32, 2.0, j as f32);
                let f = Frame::from_normal(-Vec3::Y);
                emitters.push(area(Shape::Quad(Quad::new(at, f.u * 0.1, f.v * 0.1)), 1.0));
            }
        }
        let bvh = LightBvh::new(&emitters);
        assert_eq!(bvh.nodes.len(), 1999);
        assert!(bvh.depth() <= 24, "depth {}", bvh.depth());
        let near = 17 * 25 + 11;
        let p = Vec3::new(17.05, 1.8, 11.05);
        let pmf = bvh.pmf(p, Vec3::Y, near);
        assert!(pmf > 50.0 / 1000.0, "{pmf}");
    }
}
