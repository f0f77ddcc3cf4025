//! A client for the display protocol of the [tev](https://github.com/Tom94/tev)
//! HDR image viewer: a render can be shown in tev while it is running.
//!
//! tev listens on a TCP port (14158 by default) for packets; each packet is
//! a little-endian `u32` holding the packet's whole length (those four bytes
//! included), a `u8` packet type, then the type's fields. Integers are
//! little-endian `i32` or `i64`, booleans one byte (0 or 1), strings UTF-8
//! ended by a NUL byte, pixel values `f32`. This client sends three types:
//!
//! | type | name | fields after the type byte |
//! |---|---|---|
//! | 4 | CreateImage | grab focus, image name, width, height, channel count *n*, *n* channel names |
//! | 6 | UpdateImage, version 3 | grab focus, image name, *n*, *n* channel names, x, y, width, height, *n* offsets (`i64`), *n* strides (`i64`), the values |
//! | 2 | CloseImage | image name |
//!
//! An UpdateImage packet carries a rectangle of several channels at once:
//! value `p` (counted row by row inside the rectangle) of channel `c` is
//! the float at index `offset[c] + p * stride[c]` of the values. This client
//! sends the channels interleaved, pixel after pixel (offset `c`, stride
//! *n*), which is how an [`Image`] already holds its RGB. Version 3 of
//! UpdateImage (type 6) is the newest form of the packet; tev reads it since
//! version 1.18, and CreateImage since 1.16. The older forms (type 3, one
//! channel per packet, which pbrt-v4 sends in 128x128 tiles, and type 5,
//! channels one after the other) carry nothing more.
//!
//! tev reads a packet only once all of it has arrived, so large updates
//! are split into rectangles of whole rows (or pieces of a row, for
//! very wide images) of at most [`MAX_PACKET_BYTES`] each.
//!
//! A failed write may leave half a packet in the stream, after which tev
//! could not make sense of anything more: the client then refuses every
//! later call with [`TevError::Closed`], so a caller can report the first
//! error as one warning and carry on rendering.

use std::collections::HashMap;
use std::io::Write;
use std::net::{TcpStream, ToSocketAddrs};
use std::time::Duration;

use crate::render::Image;

/// The port tev listens on unless told otherwise; used when the address
/// given to [`TevClient::connect`] has none.
pub const DEFAULT_PORT: u16 = 14158;

/// The largest packet sent; pixel updates are split to stay below it.
pub const MAX_PACKET_BYTES: usize = 4 << 20;

/// Packet types, as tev numbers them.
const CLOSE_IMAGE: u8 = 2;
const CREATE_IMAGE: u8 = 4;
const UPDATE_IMAGE_V3: u8 = 6;

/// Why tev could not be reached or sent to; each names tev's address.
#[derive(Debug, thiserror::Error)]
pub enum TevError {
    #[error("tev at {addr}: cannot resolve the address: {source}")]
    Resolve {
        addr: String,
        source: std::io::Error,
    },
    #[error("tev at {addr}: cannot connect: {source}")]
    Connect {
        addr: String,
        source: std::io::Error,
    },
    #[error("tev at {addr}: sending failed: {source}")]
    Send {
        addr: String,
        source: std::io::Error,
    },
    /// An earlier send failed; nothing more is sent on this connection.
    #[error("tev at {addr}: the connection was lost earlier")]
    Closed { addr: String },
    /// The call cannot be put into a packet (a NUL in a name, a size beyond
    /// tev's 32-bit integers, pixel values that do not match the rectangle).
    #[error("tev at {addr}: {message}")]
    Invalid { addr: String, message: String },
}

/// A rectangle of pixels, in pixels from the image's top-left corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

/// The layout of an image this client created in tev: size and channels.
#[derive(Debug, PartialEq)]
struct Layout {
    width: u32,
    height: u32,
    channels: Vec<String>,
}

/// A connection to a running tev.
pub struct TevClient {
    addr: String,
    stream: TcpStream,
    broken: bool,
    max_packet_bytes: usize,
    /// Images created through this connection, by name.
    created: HashMap<String, Layout>,
    /// The packet being built, kept to reuse its allocation.
    packet: Vec<u8>,
}

impl TevClient {
    /// Connects to tev at `addr` (`HOST:PORT`, or `HOST` for tev's default
    /// port), trying each address the host resolves to for at most
    /// `timeout`. Writes that block longer than `timeout` (tev stopped
    /// reading) fail too.
    pub fn connect(addr: &str, timeout: Duration) -> Result<TevClient, TevError> {
        let target = if addr.contains(':') {
            addr.to_string()
        } else {
            format!("{addr}:{DEFAULT_PORT}")
        };
        let resolve = |source| TevError::Resolve {
            addr: target.clone(),
            source,
        };
        let candidates: Vec<_> = target.to_socket_addrs().map_err(resolve)?.collect();
        if candidates.is_empty() {
            return Err(resolve(std::io::Error::new(
                std::io::ErrorKind::NotFound,
                "the host has no address",
            )));
        }
        let mut last = None;
        for socket in candidates {
            match TcpStream::connect_timeout(&socket, timeout) {
                Ok(stream) => {
                    let setup = stream
                        .set_write_timeout(Some(timeout))
                        .and_then(|()| stream.set_nodelay(true));
                    if let Err(source) = setup {
                        return Err(TevError::Connect {
                            addr: target,
                            source,
                        });
                    }
                    return Ok(TevClient {
                        addr: target,
                        stream,
                        broken: false,
                        max_packet_bytes: MAX_PACKET_BYTES,
                        created: HashMap::new(),
                        packet: Vec::new(),
                    });
                }
                Err(e) => last = Some(e),
            }
        }
        Err(TevError::Connect {
            addr: target,
            source: last.unwrap_or_else(|| std::io::Error::other("no address tried")),
        })
    }

    /// The address connected to, as `HOST:PORT`.
    pub fn addr(&self) -> &str {
        &self.addr
    }

    /// Creates (or replaces) image `name` in tev, `width` x `height` pixels
    /// of the given channels, all zero. tev groups channels by their names
    /// (`R`, `G`, `B`, `A`; `albedo.R`, ...).
    pub fn create_image(
        &mut self,
        name: &str,
        width: u32,
        height: u32,
        channels: &[&str],
        grab_focus: bool,
    ) -> Result<(), TevError> {
        self.check_open()?;
        self.check_name(name)?;
        for c in channels {
            self.check_name(c)?;
        }
        let width_i = self.to_i32(width as u64, "width")?;
        let height_i = self.to_i32(height as u64, "height")?;
        let count = self.to_i32(channels.len() as u64, "channel count")?;

        let mut p = Packet::begin(&mut self.packet, CREATE_IMAGE);
        p.bool(grab_focus);
        p.str(name);
        p.i32(width_i);
        p.i32(height_i);
        p.i32(count);
        for c in channels {
            p.str(c);
        }
        self.send()?;
        self.created.insert(
            name.to_string(),
            Layout {
                width,
                height,
                channels: channels.iter().map(|c| c.to_string()).collect(),
            },
        );
        Ok(())
    }

    /// Sets the pixels of `rect` in channels `channels` of image `name`.
    /// `values` holds them interleaved, pixel after pixel, row by row:
    /// value `c` of the rectangle's pixel `p` is `values[p * channels.len() + c]`
    /// (one channel is simply `&["R"]` and its values). Sent as UpdateImage
    /// (version 3) packets of at most [`MAX_PACKET_BYTES`].
    pub fn update_image(
        &mut self,
        name: &str,
        grab_focus: bool,
        rect: Rect,
        channels: &[&str],
        values: &[f32],
    ) -> Result<(), TevError> {
        self.check_open()?;
        self.check_name(name)?;
        for c in channels {
            self.check_name(c)?;
        }
        let n = channels.len();
        if n == 0 {
            return Err(self.invalid(format!("update of image '{name}' names no channel")));
        }
        self.to_i32(n as u64, "channel count")?;
        self.to_i32(rect.x as u64 + rect.width as u64, "rectangle's right edge")?;
        self.to_i32(
            rect.y as u64 + rect.height as u64,
            "rectangle's bottom edge",
        )?;
        let (w, h) = (rect.width as usize, rect.height as usize);
        if values.len() != w * h * n {
            return Err(self.invalid(format!(
                "update of image '{name}': {} values for {w}x{h} pixels of {n} channels",
                values.len()
            )));
        }
        if let Some(layout) = self.created.get(name) {
            let inside = rect.x as u64 + rect.width as u64 <= layout.width as u64
                && rect.y as u64 + rect.height as u64 <= layout.height as u64;
            if !inside {
                return Err(self.invalid(format!(
                    "update of image '{name}': rectangle {}x{} at ({}, {}) exceeds its {}x{} pixels",
                    rect.width, rect.height, rect.x, rect.y, layout.width, layout.height
                )));
            }
        }
        self.send_pixels(name, grab_focus, rect, channels, |p, start, count| {
            p.f32s(&values[start * n..(start + count) * n]);
        })
    }

    /// Sends the pixels of `rect` in UpdateImage packets of at most
    /// `max_packet_bytes`. `put(packet, start, count)` appends the values
    /// of the rectangle's pixels `start..start + count` (counted row by row),
    /// every channel of a pixel together. The arguments are checked.
    fn send_pixels(
        &mut self,
        name: &str,
        grab_focus: bool,
        rect: Rect,
        channels: &[&str],
        put: impl Fn(&mut Packet, usize, usize),
    ) -> Result<(), TevError> {
        let (w, h, n) = (rect.width as usize, rect.height as usize, channels.len());
        if w == 0 || h == 0 {
            return Ok(());
        }
        // Everything of a packet but its values.
        let header = 4
            + 1
            + 1
            + (name.len() + 1)
            + 4
            + channels.iter().map(|c| c.len() + 1).sum::<usize>()
            + 4 * 4
            + 2 * 8 * n;
        let pixels_per_packet = (self.max_packet_bytes.saturating_sub(header) / (4 * n)).max(1);
        let (tile_w, tile_h) = if pixels_per_packet >= w {
            (w, (pixels_per_packet / w).min(h))
        } else {
            (pixels_per_packet, 1)
        };

        // In range of i32: the callers checked the rectangle and count.
        for ty in (0..h).step_by(tile_h) {
            let th = tile_h.min(h - ty);
            for tx in (0..w).step_by(tile_w) {
                let tw = tile_w.min(w - tx);
                let mut p = Packet::begin(&mut self.packet, UPDATE_IMAGE_V3);
                p.bool(grab_focus);
                p.str(name);
                p.i32(n as i32);
                for c in channels {
                    p.str(c);
                }
                p.i32((rect.x as usize + tx) as i32);
                p.i32((rect.y as usize + ty) as i32);
                p.i32(tw as i32);
                p.i32(th as i32);
                for c in 0..n {
                    p.i64(c as i64);
                }
                for _ in 0..n {
                    p.i64(n as i64);
                }
                for row in ty..ty + th {
                    put(&mut p, row * w + tx, tw);
                }
                self.send()?;
            }
        }
        Ok(())
    }

    /// Closes image `name` in tev.
    pub fn close_image(&mut self, name: &str) -> Result<(), TevError> {
        self.check_open()?;
        self.check_name(name)?;
        let mut p = Packet::begin(&mut self.packet, CLOSE_IMAGE);
        p.str(name);
        self.send()?;
        self.created.remove(name);
        Ok(())
    }

    /// Shows `image` in tev as image `name`: its channels `R`, `G`, `B`,
    /// then its extra channels under their own names. The image is created
    /// (taking the focus) on the first call for `name`, or when its size or
    /// channels changed; later calls update its pixels.
    pub fn show(&mut self, name: &str, image: &Image) -> Result<(), TevError> {
        self.check_open()?;
        let pixels = image.width as usize * image.height as usize;
        if image.pixels.len() != pixels {
            return Err(self.invalid(format!(
                "image '{name}' has {} pixels for {}x{}",
                image.pixels.len(),
                image.width,
                image.height
            )));
        }
        let extra_names: &[String] = image.extra.as_ref().map_or(&[], |e| &e.names);
        let extra_values: &[f32] = image.extra.as_ref().map_or(&[], |e| &e.values);
        let ne = extra_names.len();
        if extra_values.len() != pixels * ne {
            return Err(self.invalid(format!(
                "image '{name}' has {} values for {pixels} pixels of {ne} extra channels",
                extra_values.len()
            )));
        }
        let mut channels: Vec<&str> = vec!["R", "G", "B"];
        channels.extend(extra_names.iter().map(String::as_str));

        let layout = Layout {
            width: image.width,
            height: image.height,
            channels: channels.iter().map(|c| c.to_string()).collect(),
        };
        if self.created.get(name) != Some(&layout) {
            self.create_image(name, image.width, image.height, &channels, true)?;
        }

        let rect = Rect {
            x: 0,
            y: 0,
            width: image.width,
            height: image.height,
        };
        self.send_pixels(name, false, rect, &channels, |p, start, count| {
            for i in start..start + count {
                p.f32s(&image.pixels[i].to_array());
                p.f32s(&extra_values[i * ne..(i + 1) * ne]);
            }
        })
    }

    /// Writes the packet built in `self.packet`; after a failure the
    /// connection is given up.
    fn send(&mut self) -> Result<(), TevError> {
        let Ok(length) = u32::try_from(self.packet.len()) else {
            return Err(self.invalid(format!("a packet of {} bytes", self.packet.len())));
        };
        self.packet[..4].copy_from_slice(&length.to_le_bytes());
        if let Err(source) = self.stream.write_all(&self.packet) {
            self.broken = true;
            return Err(TevError::Send {
                addr: self.addr.clone(),
                source,
            });
        }
        Ok(())
    }

    fn check_open(&self) -> Result<(), TevError> {
        if self.broken {
            return Err(TevError::Closed {
                addr: self.addr.clone(),
            });
        }
        Ok(())
    }

    /// tev's strings end at a NUL: a name holding one cannot be sent.
    fn check_name(&self, name: &str) -> Result<(), TevError> {
        if name.contains('\0') {
            return Err(self.invalid(format!("name {name:?} holds a NUL character")));
        }
        Ok(())
    }

    fn to_i32(&self, value: u64, what: &str) -> Result<i32, TevError> {
        i32::try_from(value).map_err(|_| self.invalid(format!("{what} {value} exceeds 2^31 - 1")))
    }

    fn invalid(&self, message: String) -> TevError {
        TevError::Invalid {
            addr: self.addr.clone(),
            message,
        }
    }
}

/// Appends a packet's fields to a buffer; the length is filled in by
/// [`TevClient::send`].
struct Packet<'a>(&'a mut Vec<u8>);

impl<'a> Packet<'a> {
    fn begin(buf: &'a mut Vec<u8>, kind: u8) -> Packet<'a> {
        buf.clear();
        buf.extend_from_slice(&[0; 4]);
        buf.push(kind);
        Packet(buf)
    }

    fn bool(&mut self, v: bool) {
        self.0.push(u8::from(v));
    }

    fn str(&mut self, s: &str) {
        self.0.extend_from_slice(s.as_bytes());
        self.0.push(0);
    }

    fn i32(&mut self, v: i32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }

    fn i64(&mut self, v: i64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }

    fn f32s(&mut self, values: &[f32]) {
        self.0.reserve(4 * values.len());
        for v in values {
            self.0.extend_from_slice(&v.to_le_bytes());
        }
    }
}

#[cfg(test)]
mod tests {
    //! A fake tev: a listener that keeps every byte it receives, and a
    //! parser of the packets written from tev's description of them, apart
    //! from the client's encoder.

    use super::*;
    use crate::math::Rgb;
    use crate::render::ExtraChannels;
    use std::io::Read;
    use std::net::TcpListener;
    use std::thread::{self, JoinHandle};

    const TIMEOUT: Duration = Duration::from_secs(10);

    /// A packet as the fake tev understood it.
    #[derive(Debug)]
    enum Received {
        Create {
            focus: bool,
            name: String,
            width: i32,
            height: i32,
            channels: Vec<String>,
        },
        Update {
            name: String,
            channels: Vec<String>,
            rect: [i32; 4],
            offsets: Vec<i64>,
            strides: Vec<i64>,
            data: Vec<f32>,
        },
        Close {
            name: String,
        },
    }

    struct Fields<'a> {
        bytes: &'a [u8],
        at: usize,
    }

    impl Fields<'_> {
        fn take<const N: usize>(&mut self) -> Result<[u8; N], String> {
            let end = self.at + N;
            let got = self
                .bytes
                .get(self.at..end)
                .ok_or("field past the packet's end")?;
            self.at = end;
            Ok(got.try_into().unwrap())
        }
        fn flag(&mut self) -> Result<bool, String> {
            match self.take::<1>()? {
                [0] => Ok(false),
                [1] => Ok(true),
                [b] => Err(format!("boolean byte {b}")),
            }
        }
        fn int(&mut self) -> Result<i32, String> {
            Ok(i32::from_le_bytes(self.take()?))
        }
        fn long(&mut self) -> Result<i64, String> {
            Ok(i64::from_le_bytes(self.take()?))
        }
        fn text(&mut self) -> Result<String, String> {
            let rest = &self.bytes[self.at..];
            let nul = rest
                .iter()
                .position(|&b| b == 0)
                .ok_or("string without NUL")?;
            let s = String::from_utf8(rest[..nul].to_vec()).map_err(|e| e.to_string())?;
            self.at += nul + 1;
            Ok(s)
        }
        fn texts(&mut self, count: i32) -> Result<Vec<String>, String> {
            (0..count).map(|_| self.text()).collect()
        }
    }

    /// Splits a byte stream into packets, parses each, and returns them
    /// with their lengths.
    fn parse_stream(bytes: &[u8]) -> Result<Vec<(usize, Received)>, String> {
        let mut packets = Vec::new();
        let mut at = 0;
        while at < bytes.len() {
            let head = bytes.get(at..at + 4).ok_or("truncated length")?;
            let length = u32::from_le_bytes(head.try_into().unwrap()) as usize;
            if length < 5 || at + length > bytes.len() {
                return Err(format!("packet length {length} at byte {at}"));
            }
            packets.push((length, parse_packet(&bytes[at..at + length])?));
            at += length;
        }
        Ok(packets)
    }

    fn parse_packet(packet: &[u8]) -> Result<Received, String> {
        let mut f = Fields {
            bytes: packet,
            at: 4,
        };
        let [kind] = f.take::<1>()?;
        let received = match kind {
            4 => {
                let focus = f.flag()?;
                let name = f.text()?;
                let width = f.int()?;
                let height = f.int()?;
                let count = f.int()?;
                let channels = f.texts(count)?;
                Received::Create {
                    focus,
                    name,
                    width,
                    height,
                    channels,
                }
            }
            6 => {
                f.flag()?;
                let name = f.text()?;
                let count = f.int()?;
                let channels = f.texts(count)?;
                let rect = [f.int()?, f.int()?, f.int()?, f.int()?];
                let offsets = (0..count)
                    .map(|_| f.long())
                    .collect::<Result<Vec<_>, _>>()?;
                let strides = (0..count)
                    .map(|_| f.long())
                    .collect::<Result<Vec<_>, _>>()?;
                let pixels = rect[2] as i64 * rect[3] as i64;
                let needed = (0..count as usize)
                    .map(|c| offsets[c] + (pixels - 1) * strides[c] + 1)
                    .max()
                    .unwrap_or(0) as usize;
                let rest = packet.len() - f.at;
                if rest != 4 * needed {
                    return Err(format!("{rest} value bytes for {needed} floats"));
                }
                let data = packet[f.at..]
                    .chunks_exact(4)
                    .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
                    .collect();
                f.at = packet.len();
                Received::Update {
                    name,
                    channels,
                    rect,
                    offsets,
                    strides,
                    data,
                }
            }
            2 => Received::Close { name: f.text()? },
            other => return Err(format!("packet type {other}")),
        };
        if f.at != packet.len() {
            return Err(format!("{} bytes left in a packet", packet.len() - f.at));
        }
        Ok(received)
    }

    /// A fake tev accepting one connection; the thread returns every byte
    /// received until the client hangs up.
    fn fake_tev() -> (String, JoinHandle<Vec<u8>>) {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        let server = thread::spawn(move || {
            let (mut conn, _) = listener.accept().unwrap();
            let mut bytes = Vec::new();
            conn.read_to_end(&mut bytes).unwrap();
            bytes
        });
        (addr, server)
    }

    /// A channel's name and the bits of its values, `None` where nothing
    /// was sent.
    type Plane = (String, Vec<Option<u32>>);

    /// The channels of image `name` as tev would hold them after the
    /// packets: its last creation, then every update after it. `None`
    /// marks a value never sent.
    fn reassemble(packets: &[(usize, Received)], name: &str) -> (i32, i32, Vec<Plane>) {
        let mut image = None;
        for (_, p) in packets {
            match p {
                Received::Create {
                    name: n,
                    width,
                    height,
                    channels,
                    ..
                } if n == name => {
                    let planes: Vec<_> = channels
                        .iter()
                        .map(|c| (c.clone(), vec![None; (*width * *height) as usize]))
                        .collect();
                    image = Some((*width, *height, planes));
                }
                Received::Update {
                    name: n,
                    channels,
                    rect: [x, y, w, h],
                    offsets,
                    strides,
                    data,
                } if n == name => {
                    let (width, height, planes) = image.as_mut().expect("update before create");
                    assert!(
                        x + w <= *width && y + h <= *height,
                        "update outside the image"
                    );
                    for (c, channel) in channels.iter().enumerate() {
                        let plane = &mut planes
                            .iter_mut()
                            .find(|(n, _)| n == channel)
                            .expect("update of a channel not created")
                            .1;
                        for p in 0..(w * h) as i64 {
                            let (px, py) = (x + (p % *w as i64) as i32, y + (p / *w as i64) as i32);
                            let v = data[(offsets[c] + p * strides[c]) as usize];
                            plane[(py * *width + px) as usize] = Some(v.to_bits());
                        }
                    }
                }
                _ => {}
            }
        }
        image.expect("image never created")
    }

    /// A `width` x `height` image with the given extra channels, whose
    /// values are all different and include the awkward ones (signed zero,
    /// infinity, NaN with a payload, subnormals).
    fn test_image(width: u32, height: u32, extra: &[&str], seed: u32) -> Image {
        let n = (width * height) as usize;
        let special = [
            -0.0,
            f32::INFINITY,
            f32::from_bits(0x7fc0_1234),
            f32::from_bits(1),
            -f32::MIN_POSITIVE,
        ];
        let value = |i: usize| {
            if i % 97 < special.len() {
                special[i % 97]
            } else {
                (i as f32 * 0.37 + seed as f32).sin() * 1e3
            }
        };
        let pixels = (0..n)
            .map(|p| Rgb::new(value(3 * p), value(3 * p + 1), value(3 * p + 2)))
            .collect();
        let extra = (!extra.is_empty()).then(|| ExtraChannels {
            names: extra.iter().map(|s| s.to_string()).collect(),
            values: (0..n * extra.len()).map(|i| value(i + 7 * n)).collect(),
        });
        Image {
            width,
            height,
            pixels,
            extra,
        }
    }

    /// Checks the channels tev holds against `image`, bit for bit.
    fn assert_shows(packets: &[(usize, Received)], name: &str, image: &Image) {
        let (width, height, planes) = reassemble(packets, name);
        assert_eq!((width as u32, height as u32), (image.width, image.height));
        let extra_names = image.extra.as_ref().map_or(vec![], |e| e.names.clone());
        let mut want_names = vec!["R".to_string(), "G".into(), "B".into()];
        want_names.extend(extra_names.iter().cloned());
        let names: Vec<String> = planes.iter().map(|(n, _)| n.clone()).collect();
        assert_eq!(names, want_names);
        for (c, (channel, plane)) in planes.iter().enumerate() {
            for (p, got) in plane.iter().enumerate() {
                let want = if c < 3 {
                    image.pixels[p].to_array()[c]
                } else {
                    image.extra.as_ref().unwrap().values[p * extra_names.len() + c - 3]
                };
                assert_eq!(*got, Some(want.to_bits()), "channel {channel}, pixel {p}");
            }
        }
    }

    fn creates(packets: &[(usize, Received)]) -> usize {
        packets
            .iter()
            .filter(|(_, p)| matches!(p, Received::Create { .. }))
            .count()
    }

    #[test]
    fn tev_shows_rgb_and_extra_channels_bit_for_bit() {
        let (addr, server) = fake_tev();
        let mut client = TevClient::connect(&addr, TIMEOUT).unwrap();
        let extra = ["albedo.R", "albedo.G", "albedo.B", "nn.X", "A"];
        let first = test_image(37, 23, &extra, 1);
        let second = test_image(37, 23, &extra, 2);
        client.show("pass", &first).unwrap();
        // The second pass in pieces of rows of 9 pixels.
        client.max_packet_bytes = 500;
        client.show("pass", &second).unwrap();
        drop(client);
        let packets = parse_stream(&server.join().unwrap()).unwrap();

        assert_eq!(creates(&packets), 1, "created once, updated after");
        let Received::Create {
            focus,
            name,
            width,
            height,
            channels,
        } = &packets[0].1
        else {
            panic!("first packet {:?}", packets[0].1);
        };
        assert!(focus);
        assert_eq!((name.as_str(), *width, *height), ("pass", 37, 23));
        assert_eq!(channels.len(), 3 + extra.len());
        assert_shows(&packets[..2], "pass", &first);
        assert!(packets.len() > 2 + 23 * 4, "{} packets", packets.len());
        assert!(packets[2..].iter().all(|(len, _)| *len <= 500));
        assert_shows(&packets, "pass", &second);
    }

    #[test]
    fn tev_splits_a_large_image_into_packets_below_the_limit() {
        let (addr, server) = fake_tev();
        let mut client = TevClient::connect(&addr, TIMEOUT).unwrap();
        // 13 MB of values: four packets or more.
        let image = test_image(1201, 901, &[], 3);
        client.show("large", &image).unwrap();
        drop(client);
        let packets = parse_stream(&server.join().unwrap()).unwrap();

        let updates = packets.len() - creates(&packets);
        assert!(updates >= 4, "{updates} updates");
        assert!(packets.iter().all(|(len, _)| *len <= MAX_PACKET_BYTES));
        assert_shows(&packets, "large", &image);
    }

    #[test]
    fn tev_updates_a_rectangle_in_pieces_of_rows() {
        let rect = Rect {
            x: 5,
            y: 11,
            width: 19,
            height: 7,
        };
        let values: Vec<f32> = (0..19 * 7 * 2).map(|i| i as f32 - 100.5).collect();
        let single: Vec<f32> = (0..19 * 7).map(|i| i as f32 * 0.25).collect();
        // The whole rectangle in one packet, several rows, pieces of a row
        // (the widest piece of the two channels at 150 bytes: 68 bytes of
        // header leave room for 10 pixels).
        for (limit, widest) in [(MAX_PACKET_BYTES, 19), (400, 19), (150, 10)] {
            let (addr, server) = fake_tev();
            let mut client = TevClient::connect(&addr, TIMEOUT).unwrap();
            client.max_packet_bytes = limit;
            client
                .create_image("tiles", 40, 30, &["Y", "Z", "W"], false)
                .unwrap();
            client
                .update_image("tiles", false, rect, &["Z", "Y"], &values)
                .unwrap();
            client
                .update_image("tiles", false, rect, &["W"], &single)
                .unwrap();
            drop(client);
            let packets = parse_stream(&server.join().unwrap()).unwrap();

            assert!(packets.iter().all(|(len, _)| *len <= limit));
            let widths = packets.iter().filter_map(|(_, p)| match p {
                Received::Update { rect, channels, .. } if channels.len() == 2 => Some(rect[2]),
                _ => None,
            });
            assert_eq!(widths.max(), Some(widest), "limit {limit}");
            if limit == MAX_PACKET_BYTES {
                assert_eq!(packets.len(), 3);
            }

            let (_, _, planes) = reassemble(&packets, "tiles");
            for (name, plane) in &planes {
                for (i, got) in plane.iter().enumerate() {
                    let (x, y) = (i as u32 % 40, i as u32 / 40);
                    let inside = (5..24).contains(&x) && (11..18).contains(&y);
                    let p = (y.wrapping_sub(11).wrapping_mul(19)).wrapping_add(x.wrapping_sub(5))
                        as usize;
                    let want = match (inside, name.as_str()) {
                        (false, _) => None,
                        (true, "Z") => Some(values[2 * p]),
                        (true, "Y") => Some(values[2 * p + 1]),
                        (true, _) => Some(single[p]),
                    };
                    assert_eq!(
                        *got,
                        want.map(f32::to_bits),
                        "channel {name}, pixel ({x}, {y})"
                    );
                }
            }
        }
    }

    #[test]
    fn tev_close_forgets_the_image() {
        let (addr, server) = fake_tev();
        let mut client = TevClient::connect(&addr, TIMEOUT).unwrap();
        let image = test_image(4, 3, &[], 4);
        client.show("a", &image).unwrap();
        client.close_image("a").unwrap();
        client.show("a", &image).unwrap();
        // A new size is a new image.
        client.show("a", &test_image(3, 4, &[], 4)).unwrap();
        drop(client);
        let packets = parse_stream(&server.join().unwrap()).unwrap();
        assert!(matches!(&packets[2].1, Received::Close { name } if name == "a"));
        assert_eq!(creates(&packets), 3);
    }

    #[test]
    fn tev_refuses_bad_calls_and_keeps_the_connection() {
        let (addr, server) = fake_tev();
        let mut client = TevClient::connect(&addr, TIMEOUT).unwrap();
        let bad = client
            .create_image("a\0b", 2, 2, &["R"], false)
            .unwrap_err();
        assert!(matches!(bad, TevError::Invalid { .. }), "{bad}");
        client.create_image("ok", 2, 2, &["R"], false).unwrap();
        let rect = Rect {
            x: 0,
            y: 0,
            width: 2,
            height: 2,
        };
        let short = client
            .update_image("ok", false, rect, &["R"], &[1.0; 3])
            .unwrap_err();
        assert!(
            short.to_string().contains("3 values for 2x2 pixels"),
            "{short}"
        );
        let outside = Rect { x: 1, ..rect };
        let err = client
            .update_image("ok", false, outside, &["R"], &[1.0; 4])
            .unwrap_err();
        assert!(err.to_string().contains("exceeds"), "{err}");
        client
            .update_image("ok", false, rect, &["R"], &[2.0; 4])
            .unwrap();
        drop(client);
        let packets = parse_stream(&server.join().unwrap()).unwrap();
        assert_eq!(packets.len(), 2);
    }

    #[test]
    fn tev_connect_to_a_closed_port_names_the_address() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        drop(listener);
        let err = TevClient::connect(&addr, TIMEOUT).err().unwrap();
        assert!(matches!(err, TevError::Connect { .. }), "{err}");
        assert!(err.to_string().contains(&addr), "{err}");

        let err = TevClient::connect("localhost:notaport", TIMEOUT)
            .err()
            .unwrap();
        assert!(matches!(err, TevError::Resolve { .. }), "{err}");
        assert!(err.to_string().contains("localhost:notaport"), "{err}");
    }

    #[test]
    fn tev_going_away_mid_stream_is_an_error_then_closed() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        // Reads the start of the stream, then hangs up with data unread.
        let server = thread::spawn(move || {
            let (mut conn, _) = listener.accept().unwrap();
            let mut start = [0; 1000];
            conn.read_exact(&mut start).unwrap();
        });
        let mut client = TevClient::connect(&addr, TIMEOUT).unwrap();
        let image = test_image(1201, 901, &[], 5);
        // The kernel's buffers may take a pass or two before the hang-up
        // is seen; once it is, every write fails.
        let mut result = Ok(());
        for _ in 0..20 {
            result = client.show("gone", &image);
            if result.is_err() {
                break;
            }
        }
        server.join().unwrap();
        let err = result.unwrap_err();
        assert!(matches!(err, TevError::Send { .. }), "{err}");
        assert!(err.to_string().contains(&addr), "{err}");
        let again = client.show("gone", &image).unwrap_err();
        assert!(matches!(again, TevError::Closed { .. }), "{again}");
    }
}
