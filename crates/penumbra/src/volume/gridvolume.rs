//! `gridvolume`: values on a 3D grid read from a `.vol` file (Mitsuba 3's
//! `gridvolume`, see [`vol_file`](super::vol_file) for the format), 1 or 3
//! channels.
//!
//! The grid fills the unit cube of its own coordinates, which `transform`
//! places in the world; with `use_grid_bbox` the box the file names is
//! placed instead (the unit cube mapped onto it first). A world point is
//! looked up at its coordinates `p` in the unit cube:
//!
//! * `trilinear`: voxel `(i, j, k)` holds the value at the centre
//!   `((i + ½)/nx, (j + ½)/ny, (k + ½)/nz)`, and values in between are
//!   interpolated from the 8 voxels around `p · n − ½`;
//! * `nearest`: the value of the voxel `⌊p · n⌋`.
//!
//! Voxel indices outside the grid wrap by `wrap_mode`: `clamp` (the edge
//! voxel's), `repeat` (the grid tiled), `mirror` (tiled, flipped every other
//! time).
//!
//! `max_value` replaces the largest value a medium's single majorant is
//! made of (as Mitsuba's); a [`MajorantGrid`](super::MajorantGrid) bounds
//! the values themselves ([`VolumeModel::max_in`]).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `filename` | path | **required** | the `.vol` file |
//! | `filter_type` | `trilinear`, `nearest` | `trilinear` | interpolation between voxels |
//! | `wrap_mode` | `clamp`, `repeat`, `mirror` | `clamp` | voxel indices outside the grid |
//! | `raw` | boolean | `false` | Mitsuba's switch for spectral upsampling; without effect in RGB |
//! | `max_value` | number ≥ 0 | the largest value | the largest value the medium assumes (its majorant) |
//! | `use_grid_bbox` | boolean | `false` | place the file's box rather than the unit cube |
//! | `transform` | table | identity | the placement of the grid's unit cube (Mitsuba's `to_world`) |

use std::sync::Arc;

use super::vol_file::{read_vol, VolGrid};
use super::{world_box, VolumeModel, Volumes};
use crate::description::placement;
use crate::description::{Invalid, Param, Props, Range, Schema, Type};
use crate::description::{mitsuba::Mitsuba, Kind};
use crate::math::{Aabb, Mat4, Rgb, Vec3};
use crate::texture::bitmap::Wrap;

const FILTERS: &[&str] = &["trilinear", "nearest"];

/// Voxel coordinates are kept within ±2³⁰ (far outside any grid, where
/// every wrap mode still answers), so that a point at infinity neither
/// overflows an index nor reads out of range.
const LIMIT: Vec3 = Vec3::splat((1u32 << 30) as f32);
const WRAPS: &[&str] = &["clamp", "repeat", "mirror"];

/// Its parameters.
const SCHEMA: Schema = Schema {
    kind: Kind::Volume,
    plugin: "gridvolume",
    what: "grid volume",
    doc: "values on a 3D grid read from a `.vol` file, trilinear or nearest, clamped, repeated or mirrored",
    mitsuba: &["gridvolume"],
    params: &[
        Param::new("filename", Type::Path, "required", "the `.vol` file (Mitsuba's binary volume format, version 3, 1 or 3 channels)"),
        Param::new(
            "filter_type",
            Type::Choice("filter type", FILTERS),
            "trilinear",
            "interpolation between voxel centres, or the value of the voxel holding the point",
        ),
        Param::new(
            "wrap_mode",
            Type::Choice("wrap mode", WRAPS),
            "clamp",
            "voxel indices outside the grid: the edge's, tiled, or tiled mirrored",
        ),
        Param::new("raw", Type::Bool, "false", "Mitsuba's switch for spectral upsampling of 3 channels; without effect in RGB"),
        Param::new(
            "max_value",
            Type::Number,
            "the largest value",
            "the largest value a medium assumes (its single majorant), ≥ 0",
        )
        .range(Range::NonNegative),
        Param::new(
            "use_grid_bbox",
            Type::Bool,
            "false",
            "place the box the file names rather than the unit cube",
        ),
        Param::new(
            "transform",
            Type::Table(&placement::PARAMS),
            "identity",
            "placement of the grid's unit cube (or of its box, with `use_grid_bbox`)",
        )
        .mitsuba("to_world"),
    ],
};

/// How values between voxels are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    Trilinear,
    Nearest,
}

/// The grid volume (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct GridVolume {
    pub grid: Arc<VolGrid>,
    pub filter: Filter,
    pub wrap: Wrap,
    /// World points to the grid's unit cube.
    pub to_local: Mat4,
    /// The world box of the unit cube.
    pub bbox: Aabb,
    /// The largest value (of any channel), or `max_value`.
    pub max: f32,
}

impl GridVolume {
    /// A grid placed by `to_world` (its unit cube), filtered and wrapped so.
    pub fn new(grid: Arc<VolGrid>, filter: Filter, wrap: Wrap, to_world: Mat4) -> GridVolume {
        let max = grid.max();
        GridVolume {
            grid,
            filter,
            wrap,
            to_local: to_world.inverse(),
            bbox: world_box(&to_world),
            max,
        }
    }

    /// The values of voxel `(i, j, k)` (indices wrapped), 3 channels (one
    /// channel repeated).
    #[inline]
    fn voxel(&self, i: i64, j: i64, k: i64) -> [f32; 3] {
        let [nx, ny, nz] = self.grid.resolution;
        let (x, y, z) = (
            self.wrap.index(i, nx) as usize,
            self.wrap.index(j, ny) as usize,
            self.wrap.index(k, nz) as usize,
        );
        let v = (z * ny as usize + y) * nx as usize + x;
        let d = &self.grid.data;
        if self.grid.channels == 1 {
            [d[v]; 3]
        } else {
            [d[3 * v], d[3 * v + 1], d[3 * v + 2]]
        }
    }

    /// The values at `p` in the unit cube's coordinates.
    pub fn lookup_local(&self, p: Vec3) -> [f32; 3] {
        let n = Vec3::from_array(self.grid.resolution.map(|n| n as f32));
        match self.filter {
            Filter::Nearest => {
                let q = (p * n).floor().clamp(-LIMIT, LIMIT);
                self.voxel(q.x as i64, q.y as i64, q.z as i64)
            }
            Filter::Trilinear => {
                let q = p * n - 0.5;
                let f = q.floor();
                // At a point far away (or not a number) the weights of the
                // first corner: its fraction is lost to rounding anyway.
                let w1 = (q - f).clamp(Vec3::ZERO, Vec3::ONE);
                let f = f.clamp(-LIMIT, LIMIT);
                let w0 = Vec3::ONE - w1;
                let (i, j, k) = (f.x as i64, f.y as i64, f.z as i64);
                let mut out = [0.0f32; 3];
                for corner in 0..8 {
                    let (a, b, c) = (corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
                    let w = [w0.x, w1.x][a] * [w0.y, w1.y][b] * [w0.z, w1.z][c];
                    let v = self.voxel(i + a as i64, j + b as i64, k + c as i64);
                    for ch in 0..3 {
                        out[ch] += w * v[ch];
                    }
                }
                out
            }
        }
    }

    /// The voxel index range along one axis of `n` voxels whose values
    /// reach points with coordinates in `[lo, hi]`.
    fn span(&self, lo: f32, hi: f32, n: u32) -> (i64, i64) {
        let nf = n as f32;
        let (a, b) = match self.filter {
            Filter::Trilinear => ((lo * nf - 0.5).floor(), (hi * nf - 0.5).floor() + 1.0),
            Filter::Nearest => ((lo * nf).floor(), (hi * nf).floor()),
        };
        if !(a.is_finite() && b.is_finite()) || b - a >= nf {
            // Every voxel of the axis is reached (wrapped).
            return (0, i64::from(n) - 1);
        }
        (a as i64, b as i64)
    }
}

impl VolumeModel for GridVolume {
    const NAME: &'static str = "gridvolume";
    const SCHEMA: Schema = SCHEMA;
    const MITSUBA: Mitsuba = Mitsuba {
        differences: "1 or 3 channels (Mitsuba also reads 6, for the SGGX phase function); values must be finite and ≥ 0; `accel` is read with no effect (it asks for a GPU's texture units, which Mitsuba's CPU variants do not use either)",
        reads: &["accel"],
        adapt: None,
    };

    fn build(p: &Props, volumes: &Volumes) -> Result<GridVolume, Invalid> {
        let Some(file) = p.string("filename")? else {
            return Err(p.node_error("missing field `filename` (the `.vol` file)"));
        };
        let filter = match p.choice("filter_type", "filter type", FILTERS)? {
            Some("nearest") => Filter::Nearest,
            _ => Filter::Trilinear,
        };
        let wrap = match p.choice("wrap_mode", "wrap mode", WRAPS)? {
            Some("repeat") => Wrap::Repeat,
            Some("mirror") => Wrap::Mirror,
            _ => Wrap::Clamp,
        };
        let _raw = p.bool("raw")?.unwrap_or(false);
        let mut to_world = placement::read(p, "transform")?.unwrap_or(Mat4::IDENTITY);
        let grid = read_vol(&volumes.base_dir.join(file))
            .map_err(|e| p.error("filename", e.to_string()))?;
        if p.bool("use_grid_bbox")?.unwrap_or(false) {
            let b = grid.bbox;
            let extent = b.max - b.min;
            if extent.min_element() <= 0.0 {
                return Err(p.error(
                    "use_grid_bbox",
                    format!(
                        "the file's box {:?} to {:?} is empty along an axis",
                        b.min.to_array(),
                        b.max.to_array()
                    ),
                ));
            }
            to_world *= Mat4::from_translation(b.min) * Mat4::from_scale(extent);
        }
        let mut v = GridVolume::new(Arc::new(grid), filter, wrap, to_world);
        if let Some(m) = p.f32("max_value")? {
            if !(m.is_finite() && m >= 0.0) {
                return Err(p.error("max_value", format!("must be finite and ≥ 0, got {m}")));
            }
            v.max = m;
        }
        Ok(v)
    }

    fn eval(&self, p: Vec3) -> Rgb {
        Rgb::from_array(self.lookup_local(self.to_local.transform_point3(p)))
    }

    /// One value: the value of one channel, the luminance of three (as
    /// Mitsuba's `eval_1` in RGB).
    fn eval_1(&self, p: Vec3) -> f32 {
        let v = self.lookup_local(self.to_local.transform_point3(p));
        if self.grid.channels == 1 {
            v[0]
        } else {
            Rgb::from_array(v).luminance()
        }
    }

    fn max(&self) -> f32 {
        self.max
    }

    fn bbox(&self) -> Aabb {
        self.bbox
    }

    fn to_local(&self) -> Mat4 {
        self.to_local
    }

    /// The largest value of any channel of the voxels whose values reach
    /// a point of the box `[lo, hi]` (unit-cube coordinates): for
    /// trilinear, each voxel whose interpolation support (the box between
    /// the centres of its neighbours) meets the box.
    fn max_in(&self, lo: Vec3, hi: Vec3) -> f32 {
        let [nx, ny, nz] = self.grid.resolution;
        let (i0, i1) = self.span(lo.x, hi.x, nx);
        let (j0, j1) = self.span(lo.y, hi.y, ny);
        let (k0, k1) = self.span(lo.z, hi.z, nz);
        let mut m = 0.0f32;
        for k in k0..=k1 {
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let v = self.voxel(i, j, k);
                    m = m.max(v[0]).max(v[1]).max(v[2]);
                }
            }
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    fn volume(
        resolution: [u32; 3],
        channels: u32,
        f: impl Fn(usize, usize, usize, usize) -> f32,
        filter: Filter,
        wrap: Wrap,
        to_world: Mat4,
    ) -> GridVolume {
        let mut data = Vec::new();
        let [nx, ny, nz] = resolution.map(|n| n as usize);
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    for c in 0..channels as usize {
                        data.push(f(x, y, z, c));
                    }
                }
            }
        }
        let grid = VolGrid {
            resolution,
            channels,
            bbox: Aabb {
                min: Vec3::ZERO,
                max: Vec3::ONE,
            },
            data,
        };
        GridVolume::new(Arc::new(grid), filter, wrap, to_world)
    }

    /// A grid holding a linear function at its voxel centres gives that
    /// function exactly (to rounding) between the centres, through a
    /// placement: the trilinear interpolation and its half-voxel offset.
    #[test]
    fn trilinear_lookup_is_exact_on_a_linear_function() {
        let res = [5u32, 7, 4];
        let g = |x: f32, y: f32, z: f32| 1.0 + 2.0 * x - 0.5 * y + 3.0 * z;
        let centre = |i: usize, n: u32| (i as f32 + 0.5) / n as f32;
        let to_world = Mat4::from_translation(Vec3::new(1.0, -2.0, 0.5))
            * Mat4::from_scale(Vec3::new(2.0, 3.0, 0.5));
        let v = volume(
            res,
            3,
            |x, y, z, c| g(centre(x, res[0]), centre(y, res[1]), centre(z, res[2])) * (c + 1) as f32,
            Filter::Trilinear,
            Wrap::Clamp,
            to_world,
        );
        let mut rng = Rng::new(7);
        for _ in 0..2000 {
            // Between the outermost centres, where clamping plays no part.
            let lo = Vec3::from_array(res.map(|n| 0.5 / n as f32));
            let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let p = lo + u * (Vec3::ONE - 2.0 * lo);
            let want = g(p.x, p.y, p.z);
            let got = v.eval(to_world.transform_point3(p));
            for (c, x) in got.to_array().into_iter().enumerate() {
                let w = want * (c + 1) as f32;
                assert!((x - w).abs() < 1e-4 * w.abs().max(1.0), "{p}: {x} vs {w}");
            }
        }
        assert_eq!(v.max, g(centre(4, 5), centre(0, 7), centre(3, 4)) * 3.0);
    }

    /// Nearest lookups and the three wrap modes, by hand, on a 4-voxel row.
    #[test]
    fn nearest_and_wrap_modes_by_hand() {
        let row = [10.0, 20.0, 30.0, 40.0];
        let make = |filter, wrap| {
            volume([4, 1, 1], 1, |x, _, _, _| row[x], filter, wrap, Mat4::IDENTITY)
        };
        let at = |v: &GridVolume, x: f32| v.eval_1(Vec3::new(x, 0.5, 0.5));
        for (wrap, want) in [
            // x = −0.1, 0.1, 0.99, 1.1, 1.3, −0.3, 2.1
            (Wrap::Clamp, [10.0, 10.0, 40.0, 40.0, 40.0, 10.0, 40.0]),
            (Wrap::Repeat, [40.0, 10.0, 40.0, 10.0, 20.0, 30.0, 10.0]),
            (Wrap::Mirror, [10.0, 10.0, 40.0, 40.0, 30.0, 20.0, 10.0]),
        ] {
            let v = make(Filter::Nearest, wrap);
            for (x, w) in [-0.1, 0.1, 0.99, 1.1, 1.3, -0.3, 2.1].into_iter().zip(want) {
                assert_eq!(at(&v, x), w, "{wrap:?} at {x}");
            }
        }
        // Trilinear near the edges: at x = 0 the point is half a voxel
        // before the first centre, between voxels −1 and 0.
        for (wrap, want) in [
            (Wrap::Clamp, 10.0),
            (Wrap::Repeat, 25.0),
            (Wrap::Mirror, 10.0),
        ] {
            let v = make(Filter::Trilinear, wrap);
            assert!((at(&v, 0.0) - want).abs() < 1e-5, "{wrap:?}: {}", at(&v, 0.0));
            // Between the centres of voxels 1 and 2.
            assert!((at(&v, 0.5) - 25.0).abs() < 1e-5);
            // A quarter of the way from centre 2 to centre 3.
            assert!((at(&v, 0.6875) - 32.5).abs() < 1e-4, "{}", at(&v, 0.6875));
        }
        // Points far away, at infinity or not numbers: an answer, no panic.
        for wrap in [Wrap::Clamp, Wrap::Repeat, Wrap::Mirror] {
            for filter in [Filter::Nearest, Filter::Trilinear] {
                let v = make(filter, wrap);
                for x in [1e30, -1e30, f32::INFINITY, f32::NEG_INFINITY, f32::NAN] {
                    let y = at(&v, x);
                    assert!((10.0..=40.0).contains(&y), "{wrap:?} {filter:?} at {x}: {y}");
                }
            }
        }
        // Three channels read as one: their luminance.
        let c = volume([1, 1, 1], 3, |_, _, _, c| [1.0, 0.0, 0.0][c], Filter::Nearest, Wrap::Clamp, Mat4::IDENTITY);
        assert_eq!(c.eval_1(Vec3::splat(0.5)), Rgb::new(1.0, 0.0, 0.0).luminance());
    }

    /// The largest value over a box is at least every lookup inside it.
    #[test]
    fn max_in_a_box_bounds_every_lookup_in_it() {
        let mut rng = Rng::new(3);
        for filter in [Filter::Trilinear, Filter::Nearest] {
            for wrap in [Wrap::Clamp, Wrap::Repeat, Wrap::Mirror] {
                let v = volume([9, 6, 5], 1, |x, y, z, _| ((x * 7 + y * 13 + z * 29) % 11) as f32, filter, wrap, Mat4::IDENTITY);
                for _ in 0..300 {
                    let a = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 1.4 - 0.2;
                    let s = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.3;
                    let m = v.max_in(a, a + s);
                    for _ in 0..20 {
                        let p = a + s * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                        assert!(v.lookup_local(p)[0] <= m + 1e-5, "{filter:?} {wrap:?} {p}");
                    }
                }
            }
        }
    }
}
