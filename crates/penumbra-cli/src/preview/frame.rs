//! One published state of the image, and the two forms the server sends of
//! it: the event text (numbers for the page's panel) and the binary image.

use serde_json::{json, Value};

/// The image after a pass, with the numbers the page shows beside it.
#[derive(Clone, Debug)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// Linear RGB, row-major, top row first, three values per pixel.
    pub rgb: Vec<f32>,
    /// Passes done (1-based), of `passes`.
    pub pass: u32,
    pub passes: u32,
    /// Seconds since the render started.
    pub elapsed_s: f64,
    /// Rays traced so far.
    pub rays: u64,
    /// The ray statistics to show: an object of counts (objects nest).
    pub stats: Value,
    /// Seconds left, when the driver can tell.
    pub eta_s: Option<f64>,
    /// Whatever else the page shows of this frame (the explorer's run and
    /// settings); `null` for none.
    pub info: Value,
}

/// The first four bytes of `/image`.
pub const IMAGE_MAGIC: [u8; 4] = *b"PNB1";
/// Bytes before the pixels: magic, width, height, pass (u32, little-endian).
pub const IMAGE_HEADER: usize = 16;

impl Frame {
    /// The `frame` event's JSON; `seq` counts publications, so that a page
    /// can tell a new image from one it has.
    pub(super) fn event_json(&self, seq: u64) -> String {
        let rays_per_s = if self.elapsed_s > 0.0 {
            self.rays as f64 / self.elapsed_s
        } else {
            0.0
        };
        json!({
            "seq": seq,
            "width": self.width,
            "height": self.height,
            "pass": self.pass,
            "passes": self.passes,
            "elapsed_s": self.elapsed_s,
            "rays": self.rays,
            "rays_per_s": rays_per_s,
            "eta_s": self.eta_s,
            "stats": self.stats,
            "info": self.info,
        })
        .to_string()
    }

    /// The `/image` body: the header, then the floats, little-endian.
    /// `None` when the pixel buffer does not hold width x height x 3 values.
    pub(super) fn encode_image(&self) -> Option<Vec<u8>> {
        let count = (self.width as usize)
            .checked_mul(self.height as usize)?
            .checked_mul(3)?;
        if self.rgb.len() != count {
            return None;
        }
        let mut out = Vec::with_capacity(IMAGE_HEADER + 4 * count);
        out.extend_from_slice(&IMAGE_MAGIC);
        out.extend_from_slice(&self.width.to_le_bytes());
        out.extend_from_slice(&self.height.to_le_bytes());
        out.extend_from_slice(&self.pass.to_le_bytes());
        // Written in place, four bytes a value: a loop the compiler turns
        // into wide stores (a pass's image is millions of values).
        out.resize(IMAGE_HEADER + 4 * count, 0);
        for (bytes, v) in out[IMAGE_HEADER..].chunks_exact_mut(4).zip(&self.rgb) {
            bytes.copy_from_slice(&v.to_le_bytes());
        }
        Some(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(width: u32, height: u32, rgb: Vec<f32>) -> Frame {
        Frame {
            width,
            height,
            rgb,
            pass: 2,
            passes: 8,
            elapsed_s: 4.0,
            rays: 1000,
            stats: json!({"primary": 10}),
            eta_s: Some(12.0),
            info: Value::Null,
        }
    }

    #[test]
    fn preview_image_bytes_are_header_then_little_endian_floats() {
        let bytes = frame(1, 1, vec![0.5, -1.0, 3.25]).encode_image().unwrap();
        assert_eq!(&bytes[..4], b"PNB1");
        assert_eq!(&bytes[4..16], &[1, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0]);
        assert_eq!(&bytes[16..20], &0.5f32.to_le_bytes());
        assert_eq!(&bytes[24..28], &3.25f32.to_le_bytes());
        assert_eq!(bytes.len(), 28);
    }

    #[test]
    fn preview_image_refuses_a_buffer_of_the_wrong_size() {
        assert!(frame(2, 1, vec![0.0; 3]).encode_image().is_none());
    }

    #[test]
    fn preview_event_carries_rays_per_second() {
        let v: Value = serde_json::from_str(&frame(1, 1, vec![0.0; 3]).event_json(7)).unwrap();
        assert_eq!(v["rays_per_s"], 250.0);
        assert_eq!(v["pass"], 2);
        assert_eq!(v["seq"], 7);
        assert_eq!(v["stats"]["primary"], 10);
    }
}
