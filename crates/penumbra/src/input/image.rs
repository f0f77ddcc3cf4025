//! Image files read into linear RGB(A) pixels: PNG, JPEG, OpenEXR and
//! Radiance HDR, through the `image` crate, for environment maps and
//! bitmap textures.
//!
//! The format is judged by the file's first bytes, not by its name. The
//! file is opened through [`InputFile`] (regular files only, within the
//! size limit of the other inputs); its header is read and its dimensions
//! judged before a pixel is decoded: more than [`MAX_IMAGE_PIXELS`]
//! pixels is refused, so that a header claiming 65535 × 65535 pixels
//! cannot make the reader allocate for them. A file shorter than its
//! header says, or whose data does not decode, is an error naming the file.
//!
//! | stored as | read as |
//! |---|---|
//! | 8 or 16 bits per channel (PNG, JPEG) | [`Encoding::Srgb`]: decoded from sRGB to linear; [`Encoding::Raw`]: the stored value over 255 or 65535 |
//! | floats (OpenEXR, Radiance HDR) | the stored values, always linear |
//! | grey | grey in each of red, green and blue |
//! | alpha | kept as stored (never sRGB-decoded), as a fourth channel |

use std::fmt;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use image::{DynamicImage, ImageDecoder, ImageReader, Limits};

use super::{size_limit, InputError, InputFile, DEFAULT_MAX_FILE_SIZE};

/// The most pixels an image file may have: 2²⁷, a 16384 × 8192
/// environment map. Its pixels take 2 GiB as four 32-bit floats.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 27;

/// How stored 8- and 16-bit values become linear ones (float files are
/// always read as they are).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// The values are sRGB-encoded (the usual case of a colour picture).
    Srgb,
    /// The values are linear already (Mitsuba's `raw`: normal maps,
    /// roughness maps).
    Raw,
}

/// An image's pixels as linear 32-bit floats, row by row from the top
/// row, each pixel `channels` values: red, green, blue, and alpha if the
/// file has it.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    /// 3 (RGB) or 4 (RGBA).
    pub channels: usize,
    pub pixels: Vec<f32>,
}

impl Image {
    /// The red, green and blue of the pixel at column `x`, row `y` (row 0
    /// at the top).
    #[inline]
    pub fn rgb(&self, x: u32, y: u32) -> [f32; 3] {
        let i = (y as usize * self.width as usize + x as usize) * self.channels;
        [self.pixels[i], self.pixels[i + 1], self.pixels[i + 2]]
    }

    /// The alpha of the pixel at column `x`, row `y`: 1 for a file without one.
    #[inline]
    pub fn alpha(&self, x: u32, y: u32) -> f32 {
        if self.channels < 4 {
            return 1.0;
        }
        self.pixels[(y as usize * self.width as usize + x as usize) * 4 + 3]
    }
}

/// Why an image file was not read. Every message starts with the file's path.
#[derive(Debug)]
pub enum ImageError {
    /// Opening or reading the file failed, or it is not a regular file
    /// within the size limit.
    Input(InputError),
    /// Its first bytes are not those of a PNG, JPEG, OpenEXR or Radiance
    /// HDR file.
    Format { path: PathBuf },
    /// Its header claims more pixels than [`MAX_IMAGE_PIXELS`].
    TooManyPixels {
        path: PathBuf,
        width: u32,
        height: u32,
    },
    /// The header or the data does not decode (a truncated or damaged file).
    Decode { path: PathBuf, message: String },
}

impl ImageError {
    /// The file the error is about, if any.
    pub fn path(&self) -> Option<&Path> {
        match self {
            ImageError::Input(e) => e.path(),
            ImageError::Format { path }
            | ImageError::TooManyPixels { path, .. }
            | ImageError::Decode { path, .. } => Some(path),
        }
    }
}

impl fmt::Display for ImageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ImageError::Input(e) => e.fmt(f),
            ImageError::Format { path } => write!(
                f,
                "{}: not an image file that can be read (PNG, JPEG, BMP, OpenEXR or Radiance HDR)",
                path.display()
            ),
            ImageError::TooManyPixels {
                path,
                width,
                height,
            } => write!(
                f,
                "{}: the header claims {width} × {height} pixels, more than the limit of \
                 {MAX_IMAGE_PIXELS} pixels",
                path.display()
            ),
            ImageError::Decode { path, message } => write!(
                f,
                "{}: damaged or truncated image: {}",
                path.display(),
                super::quote::clip(message, super::quote::MAX_QUOTED_CHARS)
            ),
        }
    }
}

impl std::error::Error for ImageError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ImageError::Input(e) => Some(e),
            _ => None,
        }
    }
}

impl From<InputError> for ImageError {
    fn from(e: InputError) -> Self {
        ImageError::Input(e)
    }
}

/// Reads the image file at `path` into linear pixels, 8- and 16-bit values
/// decoded as `encoding` says.
pub fn read_image(path: &Path, encoding: Encoding) -> Result<Image, ImageError> {
    let file = InputFile::open(path, size_limit(DEFAULT_MAX_FILE_SIZE)?)?;
    let bytes = file.read_rest(Vec::new())?;
    decode(path, bytes, encoding)
}

/// The pixels of the bytes of an image file (`path` names it in messages).
fn decode(path: &Path, bytes: Vec<u8>, encoding: Encoding) -> Result<Image, ImageError> {
    let damaged = |e: image::ImageError| ImageError::Decode {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let reader = ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| ImageError::Decode {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
    use image::ImageFormat as F;
    if !matches!(
        reader.format(),
        Some(F::Png | F::Jpeg | F::Bmp | F::OpenExr | F::Hdr)
    ) {
        return Err(ImageError::Format {
            path: path.to_path_buf(),
        });
    }
    let mut limits = Limits::default();
    // Room for the decoded image at its widest (four 32-bit floats a pixel).
    limits.max_alloc = Some(MAX_IMAGE_PIXELS * 16);
    let mut reader = reader;
    reader.limits(limits);
    // Only the header has been read here.
    let decoder = reader.into_decoder().map_err(|e| match e {
        image::ImageError::Limits(_) => too_many(path, None),
        e => damaged(e),
    })?;
    let (width, height) = decoder.dimensions();
    if u64::from(width) * u64::from(height) > MAX_IMAGE_PIXELS {
        return Err(too_many(path, Some((width, height))));
    }
    if width == 0 || height == 0 {
        return Err(ImageError::Decode {
            path: path.to_path_buf(),
            message: format!("{width} × {height} pixels: the image is empty"),
        });
    }
    let image = DynamicImage::from_decoder(decoder).map_err(damaged)?;
    Ok(linear(image, encoding))
}

fn too_many(path: &Path, size: Option<(u32, u32)>) -> ImageError {
    let (width, height) = size.unwrap_or((u32::MAX, u32::MAX));
    ImageError::TooManyPixels {
        path: path.to_path_buf(),
        width,
        height,
    }
}

/// The linear value of an sRGB-encoded one in [0, 1].
#[inline]
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Pixels as linear floats: colour channels through `colour`, alpha through
/// `alpha`, grey spread over red, green and blue.
fn convert<T: Copy>(
    samples: &[T],
    from: usize,
    has_alpha: bool,
    colour: impl Fn(T) -> f32,
    alpha: impl Fn(T) -> f32,
) -> (usize, Vec<f32>) {
    let to = if has_alpha { 4 } else { 3 };
    let colours = if has_alpha { from - 1 } else { from };
    let mut out = Vec::with_capacity(samples.len() / from * to);
    for px in samples.chunks_exact(from) {
        if colours == 1 {
            let g = colour(px[0]);
            out.extend([g, g, g]);
        } else {
            out.extend(px[..3].iter().map(|&v| colour(v)));
        }
        if has_alpha {
            out.push(alpha(px[from - 1]));
        }
    }
    (to, out)
}

fn linear(image: DynamicImage, encoding: Encoding) -> Image {
    let (width, height) = (image.width(), image.height());
    let srgb = encoding == Encoding::Srgb;
    // A table for 8 bits; 16 bits through the formula.
    let table8: [f32; 256] = std::array::from_fn(|i| {
        let v = i as f32 / 255.0;
        if srgb {
            srgb_to_linear(v)
        } else {
            v
        }
    });
    let c8 = |v: u8| table8[usize::from(v)];
    let a8 = |v: u8| f32::from(v) / 255.0;
    let c16 = |v: u16| {
        let v = f32::from(v) / 65535.0;
        if srgb {
            srgb_to_linear(v)
        } else {
            v
        }
    };
    let a16 = |v: u16| f32::from(v) / 65535.0;
    let (channels, pixels) = match image {
        DynamicImage::ImageLuma8(b) => convert(b.as_raw(), 1, false, c8, a8),
        DynamicImage::ImageLumaA8(b) => convert(b.as_raw(), 2, true, c8, a8),
        DynamicImage::ImageRgb8(b) => convert(b.as_raw(), 3, false, c8, a8),
        DynamicImage::ImageRgba8(b) => convert(b.as_raw(), 4, true, c8, a8),
        DynamicImage::ImageLuma16(b) => convert(b.as_raw(), 1, false, c16, a16),
        DynamicImage::ImageLumaA16(b) => convert(b.as_raw(), 2, true, c16, a16),
        DynamicImage::ImageRgb16(b) => convert(b.as_raw(), 3, false, c16, a16),
        DynamicImage::ImageRgba16(b) => convert(b.as_raw(), 4, true, c16, a16),
        DynamicImage::ImageRgb32F(b) => (3, b.into_raw()),
        DynamicImage::ImageRgba32F(b) => (4, b.into_raw()),
        // Any other layout a decoder may give: through 32-bit floats.
        other => {
            let has_alpha = other.color().has_alpha();
            if has_alpha {
                (4, other.into_rgba32f().into_raw())
            } else {
                (3, other.into_rgb32f().into_raw())
            }
        }
    };
    Image {
        width,
        height,
        channels,
        pixels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{ImageFormat, Rgb32FImage, RgbImage, Rgba32FImage};

    fn write(dir: &Path, name: &str, image: &DynamicImage, format: ImageFormat) -> PathBuf {
        let path = dir.join(name);
        image.save_with_format(&path, format).unwrap();
        path
    }

    fn rgb8() -> DynamicImage {
        DynamicImage::ImageRgb8(RgbImage::from_fn(4, 3, |x, y| {
            image::Rgb([(x * 60) as u8, (y * 100) as u8, 255])
        }))
    }

    /// The CRC of PNG chunks (ISO 3309), to forge headers that pass it.
    fn crc32(bytes: &[u8]) -> u32 {
        let mut c = !0u32;
        for &b in bytes {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 != 0 {
                    0xEDB8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }

    /// The bytes of a PNG file whose header claims `w` × `h` pixels.
    fn png_claiming(w: u32, h: u32) -> Vec<u8> {
        let mut bytes = Vec::new();
        rgb8()
            .write_to(&mut Cursor::new(&mut bytes), ImageFormat::Png)
            .unwrap();
        // Signature (8), IHDR length (4), "IHDR" (4), width, height.
        bytes[16..20].copy_from_slice(&w.to_be_bytes());
        bytes[20..24].copy_from_slice(&h.to_be_bytes());
        let crc = crc32(&bytes[12..29]);
        bytes[29..33].copy_from_slice(&crc.to_be_bytes());
        bytes
    }

    #[test]
    fn png_is_decoded_from_srgb_unless_raw() {
        let dir = tempfile::tempdir().unwrap();
        let path = write(dir.path(), "a.png", &rgb8(), ImageFormat::Png);
        let img = read_image(&path, Encoding::Srgb).unwrap();
        assert_eq!((img.width, img.height, img.channels), (4, 3, 3));
        let [r, g, b] = img.rgb(2, 1);
        assert!((r - srgb_to_linear(120.0 / 255.0)).abs() < 1e-6, "{r}");
        assert!((g - srgb_to_linear(100.0 / 255.0)).abs() < 1e-6, "{g}");
        assert_eq!(b, 1.0);
        // sRGB 0.5 is linear 0.214.
        assert!((srgb_to_linear(0.5) - 0.21404).abs() < 1e-4);
        let raw = read_image(&path, Encoding::Raw).unwrap();
        assert_eq!(raw.rgb(2, 1), [120.0 / 255.0, 100.0 / 255.0, 1.0]);
        assert_eq!(raw.alpha(2, 1), 1.0);
    }

    #[test]
    fn sixteen_bits_grey_and_alpha_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let img = DynamicImage::ImageLumaA16(image::ImageBuffer::from_fn(2, 2, |x, _| {
            image::LumaA([if x == 0 { 0 } else { 65535 / 2 }, 65535 / 4])
        }));
        let path = write(dir.path(), "g.png", &img, ImageFormat::Png);
        let got = read_image(&path, Encoding::Srgb).unwrap();
        assert_eq!(got.channels, 4);
        let want = srgb_to_linear(32767.0 / 65535.0);
        assert_eq!(got.rgb(1, 0), [want; 3]);
        assert_eq!(got.rgb(0, 1), [0.0; 3]);
        assert!(
            (got.alpha(1, 1) - 0.25).abs() < 1e-4,
            "alpha is not decoded"
        );
    }

    #[test]
    fn float_files_are_linear_whatever_the_encoding() {
        let dir = tempfile::tempdir().unwrap();
        let hdr = DynamicImage::ImageRgb32F(Rgb32FImage::from_fn(5, 2, |x, y| {
            image::Rgb([x as f32 * 10.0, 0.25, y as f32 + 0.5])
        }));
        let exr = DynamicImage::ImageRgba32F(Rgba32FImage::from_fn(5, 2, |x, y| {
            image::Rgba([x as f32 * 10.0, 0.25, y as f32 + 0.5, 0.75])
        }));
        let h = write(dir.path(), "a.hdr", &hdr, ImageFormat::Hdr);
        let e = write(dir.path(), "a.exr", &exr, ImageFormat::OpenExr);
        for enc in [Encoding::Srgb, Encoding::Raw] {
            let got = read_image(&h, enc).unwrap();
            assert_eq!((got.width, got.height, got.channels), (5, 2, 3));
            // RGBE keeps 8 bits of mantissa.
            let [r, g, b] = got.rgb(4, 1);
            assert!((r - 40.0).abs() < 0.2 && (g - 0.25).abs() < 2e-3 && (b - 1.5).abs() < 0.01);
            let got = read_image(&e, enc).unwrap();
            assert_eq!(got.channels, 4);
            assert_eq!(got.rgb(4, 1), [40.0, 0.25, 1.5]);
            assert_eq!(got.alpha(4, 1), 0.75);
        }
    }

    #[test]
    fn jpeg_is_read_by_its_bytes_not_its_name() {
        let dir = tempfile::tempdir().unwrap();
        let grey = DynamicImage::ImageRgb8(RgbImage::from_pixel(16, 8, image::Rgb([128; 3])));
        let path = write(dir.path(), "photo.png", &grey, ImageFormat::Jpeg);
        let got = read_image(&path, Encoding::Srgb).unwrap();
        assert_eq!((got.width, got.height), (16, 8));
        let [r, ..] = got.rgb(7, 3);
        assert!((r - srgb_to_linear(128.0 / 255.0)).abs() < 0.01, "{r}");
    }

    #[test]
    fn a_header_claiming_65535_squared_pixels_is_refused_before_decoding() {
        let dir = tempfile::tempdir().unwrap();
        let png = dir.path().join("huge.png");
        std::fs::write(&png, png_claiming(65535, 65535)).unwrap();
        let hdr = dir.path().join("huge.hdr");
        let mut bytes = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 65535 +X 65535\n".to_vec();
        bytes.extend([0x80; 64]);
        std::fs::write(&hdr, bytes).unwrap();
        let jpg = dir.path().join("huge.jpg");
        let mut bytes = Vec::new();
        rgb8()
            .write_to(&mut Cursor::new(&mut bytes), ImageFormat::Jpeg)
            .unwrap();
        // The start-of-frame marker: length (2), precision (1), height, width.
        let sof = bytes
            .windows(2)
            .position(|w| w == [0xFF, 0xC0])
            .expect("a baseline frame");
        bytes[sof + 5..sof + 9].copy_from_slice(&[0xFF, 0xFF, 0xFF, 0xFF]);
        std::fs::write(&jpg, bytes).unwrap();
        for path in [&png, &hdr, &jpg] {
            let e = read_image(path, Encoding::Srgb).unwrap_err();
            assert!(
                matches!(e, ImageError::TooManyPixels { .. }),
                "{}: {e:?}",
                path.display()
            );
            let m = e.to_string();
            assert!(m.starts_with(&path.display().to_string()), "{m}");
            assert!(m.contains("65535 × 65535"), "{m}");
        }
    }

    #[test]
    fn truncated_and_lying_files_are_errors_naming_them() {
        let dir = tempfile::tempdir().unwrap();
        let big = DynamicImage::ImageRgb8(RgbImage::from_fn(64, 64, |x, y| {
            image::Rgb([(x * 4) as u8, (y * 4) as u8, (x ^ y) as u8])
        }));
        let float = DynamicImage::ImageRgb32F(Rgb32FImage::from_fn(64, 64, |x, y| {
            image::Rgb([x as f32, y as f32, 1.0])
        }));
        let mut cases = Vec::new();
        for (name, img, format) in [
            ("t.png", &big, ImageFormat::Png),
            ("t.jpg", &big, ImageFormat::Jpeg),
            ("t.hdr", &float, ImageFormat::Hdr),
            ("t.exr", &float, ImageFormat::OpenExr),
        ] {
            let path = write(dir.path(), name, img, format);
            let bytes = std::fs::read(&path).unwrap();
            for keep in [bytes.len() / 2, 40, 12] {
                let cut = dir.path().join(format!("{keep}-{name}"));
                std::fs::write(&cut, &bytes[..keep]).unwrap();
                cases.push(cut);
            }
        }
        // A header claiming 4000 × 4000 pixels (within the limit) over the
        // data of 4 × 3.
        let lying = dir.path().join("lying.png");
        std::fs::write(&lying, png_claiming(4000, 4000)).unwrap();
        cases.push(lying);
        let empty = dir.path().join("empty.png");
        std::fs::write(&empty, b"").unwrap();
        cases.push(empty);
        for path in &cases {
            let e = read_image(path, Encoding::Srgb).unwrap_err();
            let m = e.to_string();
            assert!(m.starts_with(&path.display().to_string()), "{m}");
            assert_eq!(e.path(), Some(path.as_path()));
        }
    }

    #[test]
    fn other_files_are_refused_by_their_bytes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sky.exr");
        std::fs::write(&path, b"not an image at all").unwrap();
        let e = read_image(&path, Encoding::Srgb).unwrap_err();
        assert!(matches!(e, ImageError::Format { .. }), "{e:?}");
        let e = read_image(dir.path(), Encoding::Srgb).unwrap_err();
        assert!(matches!(e, ImageError::Input(_)), "{e:?}");
        let gif = dir.path().join("a.gif");
        std::fs::write(&gif, b"GIF89a\x01\x00\x01\x00\x00\x00\x00").unwrap();
        let e = read_image(&gif, Encoding::Srgb).unwrap_err();
        assert!(matches!(e, ImageError::Format { .. }), "{e:?}");
    }

    /// A BMP (Mitsuba's test textures are) is read, its 8-bit values
    /// decoded from sRGB: a 1 × 1 file of a red pixel.
    #[test]
    fn bmp_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let mut bytes = b"BM".to_vec();
        for v in [58u32, 0, 54, 40, 1, 1] {
            bytes.extend(v.to_le_bytes());
        }
        bytes.extend(1u16.to_le_bytes());
        bytes.extend(24u16.to_le_bytes());
        for v in [0u32, 4, 2835, 2835, 0, 0] {
            bytes.extend(v.to_le_bytes());
        }
        // Blue, green, red, and the row's padding.
        bytes.extend([0u8, 0, 255, 0]);
        let path = dir.path().join("red.bmp");
        std::fs::write(&path, &bytes).unwrap();
        let img = read_image(&path, Encoding::Srgb).unwrap();
        assert_eq!((img.width, img.height), (1, 1));
        assert_eq!(img.rgb(0, 0), [1.0, 0.0, 0.0]);
    }
}
