use super::pixel::{render_pixel, render_span};
use super::region::{BadSample, Region};
use crate::integrator::{RayStats, Tracer};
use crate::math::Rgb;
use crate::scene::Scene;

/// A linear-RGB float image, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Rgb>,
}

impl Image {
    pub fn new(width: u32, height: u32) -> Self {
        Image {
            width,
            height,
            pixels: vec![Rgb::ZERO; width as usize * height as usize],
        }
    }

    pub fn get(&self, x: u32, y: u32) -> Rgb {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// Mean of all pixels (handy in tests and reports).
    pub fn mean(&self) -> Rgb {
        self.pixels.iter().copied().sum::<Rgb>() / self.pixels.len().max(1) as f32
    }
}

/// One rendered tile with what it counted.
pub(super) struct Tile {
    pub region: Region,
    pub pixels: Vec<Rgb>,
    pub rays: RayStats,
    pub bad: Vec<BadSample>,
}

impl Tile {
    /// Copies the tile into `rows`, the band of the image of `frame` (the
    /// rendered region, in frame coordinates) that holds the tile's rows,
    /// starting with its first.
    pub(super) fn copy_into(&self, rows: &mut [Rgb], frame: Region) {
        let (w, stride) = (self.region.width() as usize, frame.width() as usize);
        let x = (self.region.x0 - frame.x0) as usize;
        for (src, dst) in self
            .pixels
            .chunks_exact(w)
            .zip(rows.chunks_exact_mut(stride))
        {
            dst[x..x + w].copy_from_slice(src);
        }
    }
}

/// How many pixels of a row are rendered together in a frame of one
/// camera ray per pixel (see [`render_span`]): about 2% of the image's
/// width, from 2 to 16. Wider spans hold less coherent rays than a lone
/// ray is worth: on the bunny's Whitted frame (instruction counts) 16 was
/// best at 800 pixels across (8 and 32 cost 5% more) and 4 at 200 (16
/// cost 3% more than tracing pixel by pixel).
fn span_width(width: u32) -> u32 {
    (width / 50).clamp(2, 16)
}

/// Renders one tile; `None` if `cancelled` becomes true, which is checked
/// before every row so that a cancel takes effect within a row of pixels,
/// not a whole tile (a tile of a costly scene can take seconds).
pub(super) fn render_tile(
    scene: &Scene,
    region: Region,
    cancelled: &dyn Fn() -> bool,
) -> Option<Tile> {
    let mut tracer = Tracer::new(scene);
    let mut pixels = Vec::with_capacity((region.width() * region.height()) as usize);
    let mut bad = Vec::new();
    for y in region.y0..region.y1 {
        if cancelled() {
            return None;
        }
        if scene.settings.spp == 1 {
            let span = span_width(scene.settings.width);
            for x0 in (region.x0..region.x1).step_by(span as usize) {
                let xs = x0..(x0 + span).min(region.x1);
                render_span(scene, &mut tracer, xs, y, &mut bad, &mut pixels);
            }
            continue;
        }
        for x in region.x0..region.x1 {
            pixels.push(render_pixel(scene, &mut tracer, x, y, &mut bad));
        }
    }
    Some(Tile {
        region,
        pixels,
        rays: tracer.stats,
        bad,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{LoadOptions, SceneSource};
    use std::cell::Cell;

    /// A frame of one camera ray per pixel is rendered in spans of a row;
    /// every pixel is what rendering it alone gives (the showcase at one
    /// sample: lens, motion, mirror, glass and an area light), and the rays
    /// are counted alike.
    #[test]
    fn spans_give_what_single_pixels_give() {
        let mut src = SceneSource::open("showcase", &LoadOptions::default()).expect("built-in");
        src.desc.render.spp = 1;
        let scene = src.build().expect("showcase builds");
        assert_eq!(scene.settings.spp, 1);
        let region = Region {
            x0: 3,
            y0: 5,
            x1: 3 + span_width(scene.settings.width) * 2 + 5,
            y1: 12,
        };
        let tile = render_tile(&scene, region, &|| false).expect("not cancelled");
        let mut tracer = Tracer::new(&scene);
        let (mut bad, mut lit) = (Vec::new(), 0);
        let pixels =
            (region.y0..region.y1).flat_map(|y| (region.x0..region.x1).map(move |x| (x, y)));
        for (k, (x, y)) in pixels.enumerate() {
            let alone = render_pixel(&scene, &mut tracer, x, y, &mut bad);
            let bits = |c: Rgb| c.to_array().map(f32::to_bits);
            assert_eq!(bits(tile.pixels[k]), bits(alone), "pixel ({x}, {y})");
            lit += usize::from(alone != Rgb::ZERO);
        }
        assert_eq!(tile.rays, tracer.stats);
        assert!(lit > 100, "{lit} pixels not black");
    }

    /// The cancel flag is read before every row: a tile stops within a row.
    #[test]
    fn a_tile_checks_for_cancel_before_every_row() {
        let src = SceneSource::open("showcase", &LoadOptions::default()).expect("built-in");
        let scene = src.build().expect("showcase builds");
        let region = Region {
            x0: 0,
            y0: 0,
            x1: 8,
            y1: 8,
        };
        let checks = Cell::new(0);
        let after_three_rows = || {
            checks.set(checks.get() + 1);
            checks.get() > 3
        };
        assert!(render_tile(&scene, region, &after_three_rows).is_none());
        assert_eq!(checks.get(), 4);
        let never = || false;
        let tile = render_tile(&scene, region, &never).expect("not cancelled");
        assert_eq!(tile.pixels.len(), 64);
    }
}
