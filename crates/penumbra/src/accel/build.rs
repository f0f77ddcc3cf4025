//! The binned-SAH builder of the four-wide BVH ([`Bvh4`](super::Bvh4)): it
//! produces a binary tree of [`Node`]s over primitive boxes and the
//! primitive order of its leaves, which the four-wide tree then collapses
//! into its own layout.
//!
//! Primitive references (box and index, 32 bytes) are partitioned in place,
//! so each level is one linear pass and the build is O(n log n). Large ranges
//! build their two subtrees in parallel (rayon).

use crate::math::Aabb;
use glam::{BVec4A, Vec4, Vec4Swizzles};

/// Number of bins per axis. 16 bins on each of the three axes gave trees within
/// a percent or two of 32 bins (measured on tessellated meshes) at half the
/// sweep cost; binning all three axes instead of only the longest is worth a
/// few percent of traversal speed for little build time.
const BINS: usize = 16;

/// Ranges smaller than this are binned into `BINS / 2` bins.
const SMALL_RANGE: usize = 64;

/// SAH cost of one traversal step (a node's box tests) relative to one
/// primitive intersection.
const TRAVERSAL_COST: f32 = 1.0;
const INTERSECT_COST: f32 = 1.0;

/// Maximum depth of a leaf (the root has depth 0). The build falls back to
/// median splits when the remaining budget gets tight, which guarantees the
/// bound, and with it that the traversal stack (one entry per level) cannot
/// overflow.
pub(crate) const MAX_DEPTH: usize = 64;

/// Ranges at least this large build their two subtrees in parallel. Below it,
/// the cost of a task and of grafting its nodes exceeds the work.
const PARALLEL_MIN: usize = 16 * 1024;

/// What a BVH wants from the builder.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Config {
    /// Ranges of at most this many primitives always become leaves.
    pub max_leaf: usize,
    /// Ranges larger than this are split even when the SAH prefers a leaf.
    pub max_sah_leaf: usize,
    /// Primitives are intersected in blocks of `1 << block_shift` (SIMD
    /// packets): the SAH charges a leaf per started block, as a packet of
    /// four costs about what one primitive does.
    pub block_shift: u32,
}

impl Config {
    /// Cost units of `n` primitives: the number of blocks they occupy.
    #[inline(always)]
    fn blocks(&self, n: usize) -> f32 {
        ((n + (1 << self.block_shift) - 1) >> self.block_shift) as f32
    }
}

/// Builds the binary tree over `prim_bounds` (finite boxes; at most
/// `u32::MAX - 1` of them). Returns the nodes (node 0 the root, node 1 an
/// unused [`EMPTY_NODE`], siblings at `2k, 2k + 1`; leaves refer to ranges of
/// the returned primitive order). Empty input gives two empty vectors.
pub(crate) fn build_binary(prim_bounds: &[Aabb], cfg: &Config) -> (Vec<Node>, Vec<u32>) {
    let n = prim_bounds.len();
    assert!(
        n < u32::MAX as usize,
        "too many primitives for 32-bit indices"
    );
    if n == 0 {
        return (Vec::new(), Vec::new());
    }
    let mut refs: Vec<PrimRef> = prim_bounds
        .iter()
        .enumerate()
        .map(|(i, b)| PrimRef::new(b, i as u32))
        .collect();
    let (bounds, cbounds) = range_bounds(&refs);
    let nodes = build_subtree(&mut refs, 0, bounds, cbounds, 0, cfg);
    let prims = refs.iter().map(PrimRef::prim).collect();
    (nodes, prims)
}

/// A node during the build: box plus either (first child node, 0) or (first
/// primitive slot, count). Node 0 is the root, node 1 unused (the empty
/// sibling of the root), and siblings are at `2k, 2k + 1`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node {
    pub bounds: Aabb,
    pub first: u32,
    pub count: u32,
}

impl Node {
    /// The node with its child index moved by `base` if it is interior.
    fn rebased(&self, base: u32) -> Node {
        if self.count == 0 {
            Node {
                first: self.first + base,
                ..*self
            }
        } else {
            *self
        }
    }
}

pub(crate) const EMPTY_NODE: Node = Node {
    bounds: Aabb::EMPTY,
    first: 0,
    count: 0,
};

/// Lanes x, y, z set: clears the w lane with a bitwise and.
const XYZ: BVec4A = BVec4A::new(true, true, true, false);

/// A primitive reference: its box and index in 32 bytes, so that
/// partitioning moves whole cache-line halves and binning reads memory
/// sequentially (gathering boxes through an index array would miss the cache
/// on large inputs). The boxes are 4-lane vectors so that growing a bin is one
/// SIMD min and max; `max.w` carries the primitive index as bits and `min.w`
/// is zero.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
struct PrimRef {
    min: Vec4,
    max: Vec4,
}

impl PrimRef {
    fn new(b: &Aabb, prim: u32) -> Self {
        PrimRef {
            min: b.min.extend(0.0),
            max: b.max.extend(f32::from_bits(prim)),
        }
    }

    fn prim(&self) -> u32 {
        self.max.w.to_bits()
    }

    /// The upper corner with w lane zero. The index bits must not enter
    /// arithmetic: as a float they are usually subnormal, and arithmetic on
    /// subnormals is very slow (it tripled the build time when bin boxes
    /// carried them into the SAH sweep).
    #[inline(always)]
    fn hi(&self) -> Vec4 {
        Vec4::select(XYZ, self.max, Vec4::ZERO)
    }

    /// Twice the centroid, w lane zero: binning only needs a consistent
    /// measure, and this saves a multiplication.
    #[inline(always)]
    fn centroid2(&self) -> Vec4 {
        self.min + self.hi()
    }
}

/// A box of 4-lane vectors with zero w lanes.
#[derive(Clone, Copy, Debug)]
struct Box4 {
    min: Vec4,
    max: Vec4,
}

impl Box4 {
    const EMPTY: Box4 = Box4 {
        min: Vec4::INFINITY,
        max: Vec4::NEG_INFINITY,
    };

    #[inline(always)]
    fn grow(&mut self, min: Vec4, max: Vec4) {
        self.min = self.min.min(min);
        self.max = self.max.max(max);
    }

    fn aabb(&self) -> Aabb {
        Aabb {
            min: self.min.truncate(),
            max: self.max.truncate(),
        }
    }
}

/// Box and (doubled) centroid box of a range.
fn range_bounds(refs: &[PrimRef]) -> (Box4, Box4) {
    let mut b = Box4::EMPTY;
    let mut cb = Box4::EMPTY;
    for r in refs {
        b.grow(r.min, r.hi());
        let c = r.centroid2();
        cb.grow(c, c);
    }
    (b, cb)
}

/// The outcome of splitting a range: the first `mid` references form the left
/// child. Boxes and centroid boxes of both sides come along so that children
/// never rescan their range for them.
struct Split {
    mid: usize,
    left: Box4,
    left_c: Box4,
    right: Box4,
    right_c: Box4,
}

/// Bin indices (lanes x, y, z) of a doubled centroid, given
/// `(c - cmin) * scale` and the last bin index (splat).
///
/// A float-to-integer cast (saturating in Rust) takes several instructions per
/// lane and dominated the build; instead the value is clamped to
/// `[0, last]` and rounded by adding 2^23, after which the low mantissa bits
/// are the integer. Subtracting 0.5 first makes the rounding a floor except at
/// exact bin boundaries, where either side is fine: all that matters is that
/// binning and partitioning call this same function. Any input (even NaN)
/// gives valid indices thanks to the final mask.
#[inline(always)]
fn bins_of(scaled: Vec4, last: Vec4) -> [usize; 3] {
    const ROUND: f32 = (1 << 23) as f32;
    let s = (scaled - Vec4::splat(0.5)).max(Vec4::ZERO).min(last) + Vec4::splat(ROUND);
    let bits = |v: f32| v.to_bits() as usize & (BINS - 1);
    [bits(s.x), bits(s.y), bits(s.z)]
}

const _: () = assert!(BINS.is_power_of_two());

/// Half the surface area of a box with w lanes zero (the SAH only compares
/// ratios). Only called on non-empty boxes.
#[inline(always)]
fn half_area(min: Vec4, max: Vec4) -> f32 {
    let e = max - min;
    let p = e * e.yzxw();
    p.x + p.y + p.z
}

/// `ceil(log2(n))` for n >= 1: the depth a median-split subtree of n
/// primitives needs to reach single-primitive leaves.
fn ceil_log2(n: usize) -> usize {
    (usize::BITS - (n.max(1) - 1).leading_zeros()) as usize
}

/// Decides how to split `refs` (and partitions it), or returns `None` for a leaf.
fn split_range(
    refs: &mut [PrimRef],
    bounds: &Box4,
    cbounds: &Box4,
    depth: usize,
    cfg: &Config,
) -> Option<Split> {
    let n = refs.len();
    if n <= cfg.max_leaf {
        return None;
    }
    let ext = cbounds.aabb().extent();
    if ext.max_element() <= 0.0 {
        // All centroids coincide: no spatial split separates anything.
        return Some(split_at(refs, n / 2));
    }
    let area = bounds.aabb().surface_area();
    if depth + ceil_log2(n) >= MAX_DEPTH - 1 || area.is_nan() || area <= 0.0 {
        return Some(median_split(refs, cbounds));
    }

    // Small ranges use half the bins: the sweep, not the binning, dominates
    // their cost, and the coarser choice of plane hardly matters there.
    let nbins = if n < SMALL_RANGE { BINS / 2 } else { BINS };
    let last = Vec4::splat((nbins - 1) as f32);
    let cmin = cbounds.min;
    let scale = ext
        .to_array()
        .map(|e| if e > 0.0 { nbins as f32 / e } else { 0.0 });
    let scale4 = Vec4::new(scale[0], scale[1], scale[2], 0.0);
    // Bin boxes (w lanes zero) and counts, per axis.
    let mut bmin = [[Vec4::INFINITY; BINS]; 3];
    let mut bmax = [[Vec4::NEG_INFINITY; BINS]; 3];
    let mut bcount = [[0u32; BINS]; 3];
    for r in refs.iter() {
        let hi = r.hi();
        let b = bins_of((r.min + hi - cmin) * scale4, last);
        for axis in 0..3 {
            let i = b[axis];
            bmin[axis][i] = bmin[axis][i].min(r.min);
            bmax[axis][i] = bmax[axis][i].max(hi);
            bcount[axis][i] += 1;
        }
    }

    // Sweep each axis: right-to-left to accumulate the right sides, then
    // left-to-right evaluating A_L N_L + A_R N_R at each of the BINS-1 planes.
    let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, first right bin)
    for axis in 0..3 {
        if scale[axis] <= 0.0 {
            continue;
        }
        let (bmin, bmax, bcount) = (&bmin[axis], &bmax[axis], &bcount[axis]);
        let mut right_cost = [0.0f32; BINS];
        let mut right_count = [0u32; BINS];
        let (mut lo, mut hi, mut cnt) = (Vec4::INFINITY, Vec4::NEG_INFINITY, 0);
        for i in (1..nbins).rev() {
            lo = lo.min(bmin[i]);
            hi = hi.max(bmax[i]);
            cnt += bcount[i];
            right_count[i] = cnt;
            right_cost[i] = half_area(lo, hi) * cfg.blocks(cnt as usize);
        }
        let (mut lo, mut hi, mut cnt) = (Vec4::INFINITY, Vec4::NEG_INFINITY, 0);
        for i in 1..nbins {
            lo = lo.min(bmin[i - 1]);
            hi = hi.max(bmax[i - 1]);
            cnt += bcount[i - 1];
            if cnt == 0 || right_count[i] == 0 {
                continue;
            }
            let cost = half_area(lo, hi) * cfg.blocks(cnt as usize) + right_cost[i];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, i));
            }
        }
    }
    let Some((cost, axis, split_bin)) = best else {
        return Some(median_split(refs, cbounds));
    };
    let split_cost = TRAVERSAL_COST + INTERSECT_COST * cost / half_area(bounds.min, bounds.max);
    let leaf_cost = INTERSECT_COST * cfg.blocks(n);
    if split_cost >= leaf_cost && n <= cfg.max_sah_leaf {
        return None;
    }

    // Child boxes are the unions of their bins (exact: bins are unions of
    // primitive boxes); centroid boxes are gathered during the partition.
    let union = |r: std::ops::Range<usize>| Box4 {
        min: bmin[axis][r.clone()]
            .iter()
            .fold(Vec4::INFINITY, |a, &b| a.min(b)),
        max: bmax[axis][r]
            .iter()
            .fold(Vec4::NEG_INFINITY, |a, &b| a.max(b)),
    };
    let left = union(0..split_bin);
    let right = union(split_bin..nbins);
    let goes_left = |c: Vec4| bins_of((c - cmin) * scale4, last)[axis] < split_bin;
    let mut left_c = Box4::EMPTY;
    let mut right_c = Box4::EMPTY;
    // Two-cursor in-place partition; each reference is classified once.
    let (mut i, mut j) = (0, n);
    loop {
        while i < j {
            let c = refs[i].centroid2();
            if !goes_left(c) {
                break;
            }
            left_c.grow(c, c);
            i += 1;
        }
        while i < j {
            let c = refs[j - 1].centroid2();
            if goes_left(c) {
                break;
            }
            right_c.grow(c, c);
            j -= 1;
        }
        if i >= j {
            break;
        }
        refs.swap(i, j - 1);
        let (cl, cr) = (refs[i].centroid2(), refs[j - 1].centroid2());
        left_c.grow(cl, cl);
        right_c.grow(cr, cr);
        i += 1;
        j -= 1;
    }
    if i == 0 || i == n {
        // Cannot happen (the sweep only picks planes with primitives on both
        // sides, and the partition bins exactly as the binning did), but an
        // empty child would be a leaf of count 0, i.e. a bogus interior node.
        return Some(median_split(refs, cbounds));
    }
    Some(Split {
        mid: i,
        left,
        left_c,
        right,
        right_c,
    })
}

/// Splits at `mid` as the references are ordered.
fn split_at(refs: &[PrimRef], mid: usize) -> Split {
    let (l, r) = refs.split_at(mid);
    let (left, left_c) = range_bounds(l);
    let (right, right_c) = range_bounds(r);
    Split {
        mid,
        left,
        left_c,
        right,
        right_c,
    }
}

/// Object median along the longest centroid axis: always balanced, so it
/// guarantees the depth bound, and it separates primitives that the SAH
/// cannot rank (zero-area boxes).
fn median_split(refs: &mut [PrimRef], cbounds: &Box4) -> Split {
    let axis = cbounds.aabb().longest_axis();
    let mid = refs.len() / 2;
    refs.select_nth_unstable_by(mid, |a, b| {
        a.centroid2()[axis].total_cmp(&b.centroid2()[axis])
    });
    split_at(refs, mid)
}

/// Builds the subtree of `refs` into `nodes`, writing its root to node `index`
/// (already allocated). `offset` is the position of `refs` in the whole
/// reference array, which is what leaves store.
#[allow(clippy::too_many_arguments)] // the recursion state, passed down as is
fn build_node(
    refs: &mut [PrimRef],
    offset: usize,
    nodes: &mut Vec<Node>,
    index: usize,
    bounds: Box4,
    cbounds: Box4,
    depth: usize,
    cfg: &Config,
) {
    let Some(s) = split_range(refs, &bounds, &cbounds, depth, cfg) else {
        nodes[index] = Node {
            bounds: bounds.aabb(),
            first: offset as u32,
            count: refs.len() as u32,
        };
        return;
    };
    let first = nodes.len();
    nodes.extend([EMPTY_NODE; 2]);
    nodes[index] = Node {
        bounds: bounds.aabb(),
        first: first as u32,
        count: 0,
    };
    let parallel = refs.len() >= PARALLEL_MIN;
    let (l, r) = refs.split_at_mut(s.mid);
    let r_offset = offset + s.mid;
    if parallel {
        let (lt, rt) = rayon::join(
            || build_subtree(l, offset, s.left, s.left_c, depth + 1, cfg),
            || build_subtree(r, r_offset, s.right, s.right_c, depth + 1, cfg),
        );
        graft(nodes, first, &lt);
        graft(nodes, first + 1, &rt);
    } else {
        build_node(l, offset, nodes, first, s.left, s.left_c, depth + 1, cfg);
        build_node(
            r,
            r_offset,
            nodes,
            first + 1,
            s.right,
            s.right_c,
            depth + 1,
            cfg,
        );
    }
}

/// Builds a subtree into a fresh node array whose node 0 is the subtree root
/// (node 1 unused, as for the whole tree).
fn build_subtree(
    refs: &mut [PrimRef],
    offset: usize,
    bounds: Box4,
    cbounds: Box4,
    depth: usize,
    cfg: &Config,
) -> Vec<Node> {
    // A subtree of n primitives has at most 2n - 1 nodes.
    let mut nodes = Vec::with_capacity(2 * refs.len());
    nodes.extend([EMPTY_NODE; 2]);
    build_node(refs, offset, &mut nodes, 0, bounds, cbounds, depth, cfg);
    nodes
}

/// Appends a subtree built by [`build_subtree`] to `nodes`, its root going to
/// node `slot`. Interior nodes' child indices are rebased; leaf ranges are
/// already global.
fn graft(nodes: &mut Vec<Node>, slot: usize, sub: &[Node]) {
    // Local node i >= 2 lands at base + i - 2.
    let base = nodes.len() as u32 - 2;
    nodes[slot] = sub[0].rebased(base);
    nodes.extend(sub[2..].iter().map(|n| n.rebased(base)));
}
