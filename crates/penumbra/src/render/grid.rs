//! How a frame is cut into tiles, and the worker pools that render them.

use std::sync::{Arc, Mutex};

use super::outcome::RenderError;
use super::region::Region;

/// The whole frame of `s`, crop window or not.
pub(super) fn frame_of(s: &crate::scene::Settings) -> Region {
    Region {
        x0: 0,
        y0: 0,
        x1: s.width,
        y1: s.height,
    }
}

/// The part of the frame a render makes unless told otherwise: the
/// film's crop window, or the whole frame.
pub fn frame(s: &crate::scene::Settings) -> Region {
    match s.crop {
        Some(c) => Region {
            x0: c.x,
            y0: c.y,
            x1: c.x + c.width,
            y1: c.y + c.height,
        },
        None => Region {
            x0: 0,
            y0: 0,
            x1: s.width,
            y1: s.height,
        },
    }
}

/// Copies the values of tile `at` (row by row) within `region` into `out`,
/// the values of `region` row by row (a tile of the grown region of a
/// splatting film may reach beyond it).
pub(super) fn place<T: Copy>(out: &mut [T], region: Region, at: Region, values: &[T]) {
    let (w, stride) = (at.width() as usize, region.width() as usize);
    let (x0, x1) = (at.x0.max(region.x0), at.x1.min(region.x1));
    if x0 >= x1 {
        return;
    }
    let n = (x1 - x0) as usize;
    for y in at.y0.max(region.y0)..at.y1.min(region.y1) {
        let src = (y - at.y0) as usize * w + (x0 - at.x0) as usize;
        let dst = (y - region.y0) as usize * stride + (x0 - region.x0) as usize;
        out[dst..dst + n].copy_from_slice(&values[src..src + n]);
    }
}

/// The worker pool of `threads` threads, made on first use and kept: starting
/// threads costs about half a millisecond per render, which small renders
/// (a distributed tile, an interactive preview) and the first tiles of every
/// render would otherwise pay, and kept workers keep their warm buffers.
pub(super) fn pool(threads: usize) -> Result<Arc<rayon::ThreadPool>, RenderError> {
    static POOLS: Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>> = Mutex::new(Vec::new());
    let mut pools = POOLS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, p)) = pools.iter().find(|(n, _)| *n == threads) {
        return Ok(Arc::clone(p));
    }
    let p = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("penumbra-worker-{i}"))
        .build()
        .map_err(|e| RenderError::Threads {
            threads,
            message: e.to_string(),
        })?;
    let p = Arc::new(p);
    pools.push((threads, Arc::clone(&p)));
    Ok(p)
}

/// The region cut into tiles, row by row: its parts in each tile of the
/// frame's grid of `tile × tile` tiles.
pub(super) fn tiles(r: Region, tile: u32) -> Vec<Region> {
    let (xs, ys) = (cuts(r.x0, r.x1, tile), cuts(r.y0, r.y1, tile));
    let mut out = Vec::new();
    for y in ys.windows(2) {
        for x in xs.windows(2) {
            out.push(Region {
                x0: x[0],
                y0: y[0],
                x1: x[1],
                y1: y[1],
            });
        }
    }
    out
}

/// `lo`, the multiples of `tile` between, and `hi`: where `[lo, hi)` is cut.
pub(super) fn cuts(lo: u32, hi: u32, tile: u32) -> Vec<u32> {
    let mut at = vec![lo];
    at.extend((lo / tile + 1..).map(|k| k * tile).take_while(|&c| c < hi));
    at.push(hi);
    at
}

/// The tile of the frame's grid (a `width × height` frame cut into tiles
/// of side `tile`) that holds `t`.
pub(super) fn aligned(t: Region, (width, height): (u32, u32), tile: u32) -> Region {
    let (x0, y0) = (t.x0 / tile * tile, t.y0 / tile * tile);
    Region {
        x0,
        y0,
        x1: (x0 + tile).min(width),
        y1: (y0 + tile).min(height),
    }
}
