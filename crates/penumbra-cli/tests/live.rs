//! `--display-server`: the render streams its passes to a fake tev that
//! reads tev's packets (parsed here, independently of the client), and
//! the last image it holds is the film written to the EXR, bit for bit.

use std::collections::HashMap;
use std::io::Read;
use std::net::TcpListener;
use std::process::Command;

/// What the fake tev saw: the images created (name → width, height,
/// channel names), their pixels per channel, and the updates received.
#[derive(Default)]
struct Tev {
    images: HashMap<String, (usize, usize, Vec<String>)>,
    pixels: HashMap<(String, String), Vec<f32>>,
    updates: usize,
}

struct Packet<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Packet<'_> {
    fn take(&mut self, n: usize) -> &[u8] {
        let part = &self.bytes[self.at..self.at + n];
        self.at += n;
        part
    }
    fn i32(&mut self) -> i32 {
        i32::from_le_bytes(self.take(4).try_into().unwrap())
    }
    fn i64(&mut self) -> i64 {
        i64::from_le_bytes(self.take(8).try_into().unwrap())
    }
    fn f32(&mut self) -> f32 {
        f32::from_le_bytes(self.take(4).try_into().unwrap())
    }
    fn string(&mut self) -> String {
        let end = self.bytes[self.at..].iter().position(|&b| b == 0).unwrap();
        let s = String::from_utf8(self.bytes[self.at..self.at + end].to_vec()).unwrap();
        self.at += end + 1;
        s
    }
}

impl Tev {
    /// Reads one packet: CreateImage (4) or UpdateImage version 3 (6).
    fn packet(&mut self, bytes: &[u8]) {
        let mut p = Packet { bytes, at: 0 };
        let kind = p.take(1)[0];
        let _grab_focus = p.take(1)[0];
        let name = p.string();
        match kind {
            4 => {
                let (w, h, n) = (p.i32() as usize, p.i32() as usize, p.i32() as usize);
                let channels: Vec<String> = (0..n).map(|_| p.string()).collect();
                for c in &channels {
                    self.pixels
                        .insert((name.clone(), c.clone()), vec![0.0; w * h]);
                }
                self.images.insert(name, (w, h, channels));
            }
            6 => {
                let n = p.i32() as usize;
                let channels: Vec<String> = (0..n).map(|_| p.string()).collect();
                let (x, y, w, h) = (
                    p.i32() as usize,
                    p.i32() as usize,
                    p.i32() as usize,
                    p.i32() as usize,
                );
                let offsets: Vec<i64> = (0..n).map(|_| p.i64()).collect();
                let strides: Vec<i64> = (0..n).map(|_| p.i64()).collect();
                let count = (bytes.len() - p.at) / 4;
                let values: Vec<f32> = (0..count).map(|_| p.f32()).collect();
                let width = self.images[&name].0;
                for (c, channel) in channels.iter().enumerate() {
                    let plane = self
                        .pixels
                        .get_mut(&(name.clone(), channel.clone()))
                        .unwrap();
                    for j in 0..h {
                        for i in 0..w {
                            let k = offsets[c] + strides[c] * (j * w + i) as i64;
                            plane[(y + j) * width + x + i] = values[k as usize];
                        }
                    }
                }
                self.updates += 1;
            }
            other => panic!("unexpected packet type {other}"),
        }
        assert_eq!(p.at, bytes.len(), "bytes left in the packet");
    }
}

#[test]
fn passes_stream_to_tev_and_its_last_image_is_the_film() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    let server = std::thread::spawn(move || {
        let (mut stream, _) = listener.accept().unwrap();
        let mut bytes = Vec::new();
        stream.read_to_end(&mut bytes).unwrap();
        let mut tev = Tev::default();
        let mut at = 0;
        while at < bytes.len() {
            let len = u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
            tev.packet(&bytes[at + 4..at + len]);
            at += len;
        }
        tev
    });
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(dir.path())
        .args(["render", "showcase", "--width", "48", "--height", "32"])
        .args(["--spp", "8", "--passes", "4", "-o", "out.exr", "--quiet"])
        .args(["--display-server", &addr])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let tev = server.join().unwrap();
    assert_eq!(tev.images.len(), 1);
    let (name, (w, h, channels)) = tev.images.iter().next().unwrap();
    assert_eq!((*w, *h), (48, 32));
    assert_eq!(channels, &["R", "G", "B"]);
    // A pass after each of the first three, and the final image.
    assert!(tev.updates >= 4, "{} updates", tev.updates);
    let exr = exr::prelude::read_all_flat_layers_from_file(dir.path().join("out.exr")).unwrap();
    let layer = &exr.layer_data[0];
    for channel in &layer.channel_data.list {
        let c = channel.name.to_string();
        let film: Vec<u32> = channel
            .sample_data
            .values_as_f32()
            .map(f32::to_bits)
            .collect();
        let shown: Vec<u32> = tev.pixels[&(name.clone(), c.clone())]
            .iter()
            .map(|v| v.to_bits())
            .collect();
        assert!(film == shown, "channel {c}");
    }
}

#[test]
fn an_absent_tev_is_an_input_error() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    drop(listener);
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(dir.path())
        .args([
            "render", "showcase", "--width", "8", "--height", "8", "-o", "o.png",
        ])
        .args(["--display-server", &addr])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains(&addr));
    assert!(!dir.path().join("o.png").exists());
}
