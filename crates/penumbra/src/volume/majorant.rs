//! The majorant grid: a coarse grid of cells over a volume's world box,
//! each holding a bound on the (scaled) density anywhere in the cell, and
//! the walk of a ray through its cells (a 3D DDA, Amanatides and Woo) that
//! yields the ray's stretches inside the box with their majorants, in order.
//!
//! Tracking with the majorant of each cell rather than one for the whole
//! medium ([`tracking`](super::tracking)) takes long steps through thin or
//! empty regions: fewer null collisions, the same estimates.
//!
//! A cell's bound is the largest value of the voxels whose values reach a
//! point of the cell ([`VolumeModel::max_in`](super::VolumeModel::max_in)):
//! the cell's corners are taken into the volume's unit cube, and for
//! trilinear filtering every voxel whose interpolation support meets that
//! box counts. Interpolation weights are not negative, so no value inside
//! exceeds it.

use crate::math::{Aabb, Mat4, Vec3};

/// The cells along each axis unless a caller asks for others: the grid
/// pbrt-v4 uses, 16³.
pub const DEFAULT_RESOLUTION: [u32; 3] = [16, 16, 16];

/// A stretch `[t0, t1]` of a ray and a bound on the density along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub t0: f32,
    pub t1: f32,
    pub majorant: f32,
}

/// The majorant grid (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct MajorantGrid {
    /// The world box the cells divide.
    pub bounds: Aabb,
    /// Cells along x, y, z.
    pub resolution: [u32; 3],
    /// `(z · ny + y) · nx + x`.
    pub cells: Vec<f32>,
}

impl MajorantGrid {
    /// The grid of `scale` times a volume's values over the world box
    /// `bounds`, `resolution` cells along each axis (each at least 1):
    /// `to_local` maps world points to the volume's unit cube, `max_in`
    /// bounds its values over a box of unit-cube coordinates
    /// ([`Volume::majorant_grid`](super::Volume::majorant_grid) gives them).
    pub fn new(
        bounds: Aabb,
        to_local: &Mat4,
        max_in: impl Fn(Vec3, Vec3) -> f32,
        scale: f32,
        resolution: [u32; 3],
    ) -> MajorantGrid {
        let resolution = resolution.map(|n| n.max(1));
        let [nx, ny, nz] = resolution;
        let n = Vec3::new(nx as f32, ny as f32, nz as f32);
        let extent = bounds.max - bounds.min;
        let mut cells = Vec::with_capacity(nx as usize * ny as usize * nz as usize);
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let c = Vec3::new(x as f32, y as f32, z as f32);
                    let lo = bounds.min + extent * c / n;
                    let hi = bounds.min + extent * (c + 1.0) / n;
                    let local = Aabb::from_points((0..8).map(|k| {
                        let corner = Vec3::new(
                            if k & 1 == 0 { lo.x } else { hi.x },
                            if k & 2 == 0 { lo.y } else { hi.y },
                            if k & 4 == 0 { lo.z } else { hi.z },
                        );
                        to_local.transform_point3(corner)
                    }));
                    cells.push(scale * max_in(local.min, local.max));
                }
            }
        }
        MajorantGrid {
            bounds,
            resolution,
            cells,
        }
    }

    /// The largest majorant of any cell.
    pub fn max(&self) -> f32 {
        self.cells.iter().fold(0.0, |a: f32, &b| a.max(b))
    }

    /// The majorant of cell `(x, y, z)`.
    pub fn cell(&self, x: u32, y: u32, z: u32) -> f32 {
        let [nx, ny, _] = self.resolution;
        self.cells[((z * ny + y) * nx + x) as usize]
    }

    /// The stretches of the ray `origin + t · direction`, `t` in
    /// `[tmin, tmax]`, inside the grid's box, cell by cell in order: each
    /// starts where the one before ends, the first at the larger of `tmin`
    /// and the entry into the box, the last ends at the smaller of `tmax`
    /// and the exit. None when the ray misses the box.
    pub fn segments(&self, origin: Vec3, direction: Vec3, tmin: f32, tmax: f32) -> Segments<'_> {
        Segments::new(self, origin, direction, tmin, tmax)
    }
}

/// The stretch `[t0, t1]` of `origin + t · direction` inside `bounds` and
/// within `[tmin, tmax]`; `None` when there is none (or it is empty), and
/// for a direction of length 0.
pub fn clip_to_box(
    bounds: &Aabb,
    origin: Vec3,
    direction: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<(f32, f32)> {
    if direction == Vec3::ZERO {
        // Not a ray: it would stay in the box for ever.
        return None;
    }
    let (mut t0, mut t1) = (tmin, tmax);
    for a in 0..3 {
        let (o, d) = (origin[a], direction[a]);
        let (lo, hi) = (bounds.min[a], bounds.max[a]);
        if d == 0.0 {
            if o < lo || o > hi {
                return None;
            }
            continue;
        }
        let (mut near, mut far) = ((lo - o) / d, (hi - o) / d);
        if near > far {
            std::mem::swap(&mut near, &mut far);
        }
        t0 = t0.max(near);
        t1 = t1.min(far);
    }
    (t0 < t1).then_some((t0, t1))
}

/// The walk of a ray through a [`MajorantGrid`]'s cells, yielding
/// [`Segment`]s (see [`MajorantGrid::segments`]).
pub struct Segments<'a> {
    grid: &'a MajorantGrid,
    /// The ray in cell units: cell `(i, j, k)` spans `[i, i + 1]` × ….
    origin: Vec3,
    direction: Vec3,
    cell: [i64; 3],
    step: [i64; 3],
    /// The `t` at which the ray leaves the current cell along each axis.
    next: [f32; 3],
    t: f32,
    end: f32,
    done: bool,
}

impl<'a> Segments<'a> {
    fn new(
        grid: &'a MajorantGrid,
        origin: Vec3,
        direction: Vec3,
        tmin: f32,
        tmax: f32,
    ) -> Segments<'a> {
        let n = Vec3::from_array(grid.resolution.map(|n| n as f32));
        let extent = grid.bounds.max - grid.bounds.min;
        let o = (origin - grid.bounds.min) * n / extent;
        let d = direction * n / extent;
        let clipped = if extent.min_element() > 0.0 && o.is_finite() && d.is_finite() {
            clip_to_box(&grid.bounds, origin, direction, tmin, tmax)
        } else {
            None
        };
        let mut s = Segments {
            grid,
            origin: o,
            direction: d,
            cell: [0; 3],
            step: [0; 3],
            next: [f32::INFINITY; 3],
            t: 0.0,
            end: 0.0,
            done: true,
        };
        let Some((t0, t1)) = clipped else {
            return s;
        };
        let p = o + d * t0;
        for a in 0..3 {
            let last = i64::from(grid.resolution[a]) - 1;
            s.cell[a] = (p[a].floor() as i64).clamp(0, last);
            s.step[a] = if d[a] > 0.0 {
                1
            } else if d[a] < 0.0 {
                -1
            } else {
                0
            };
            s.next[a] = s.crossing(a);
        }
        s.t = t0;
        s.end = t1;
        s.done = false;
        s
    }

    /// Where the ray crosses the current cell's far wall along axis `a`
    /// (from the ray's origin, so no error accumulates from cell to cell).
    fn crossing(&self, a: usize) -> f32 {
        match self.step[a] {
            0 => f32::INFINITY,
            s => {
                let wall = (self.cell[a] + i64::from(s > 0)) as f32;
                (wall - self.origin[a]) / self.direction[a]
            }
        }
    }
}

impl Iterator for Segments<'_> {
    type Item = Segment;

    fn next(&mut self) -> Option<Segment> {
        while !self.done {
            let a = if self.next[0] <= self.next[1] && self.next[0] <= self.next[2] {
                0
            } else if self.next[1] <= self.next[2] {
                1
            } else {
                2
            };
            let t1 = self.next[a].min(self.end).max(self.t);
            let [x, y, z] = self.cell.map(|c| c as u32);
            let segment = Segment {
                t0: self.t,
                t1,
                majorant: self.grid.cell(x, y, z),
            };
            if self.next[a] >= self.end {
                self.done = true;
            } else {
                self.cell[a] += self.step[a];
                if self.cell[a] < 0 || self.cell[a] >= i64::from(self.grid.resolution[a]) {
                    self.done = true;
                }
                self.next[a] = self.crossing(a);
            }
            self.t = t1;
            if t1 > segment.t0 {
                if self.done {
                    // The last stretch ends where the ray leaves the box.
                    return Some(Segment {
                        t1: self.end,
                        ..segment
                    });
                }
                return Some(segment);
            } else if self.done && self.end > segment.t0 {
                return Some(Segment {
                    t1: self.end,
                    ..segment
                });
            }
        }
        None
    }
}
