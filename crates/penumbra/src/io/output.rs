//! Image and JSON output, written atomically.
//!
//! Everything is written to a temporary file in the destination's directory
//! and renamed over the destination only once complete: an error or a kill
//! never leaves a half-written file and never destroys an existing one.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::render::Image;

#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("{}: unsupported output format; use .png (8-bit sRGB) or .exr (32-bit float linear)", .0.display())]
    Format(PathBuf),
    #[error("{}: {message}", path.display())]
    Write { path: PathBuf, message: String },
    /// The image has channels beside its RGB that the format cannot hold.
    #[error(
        "{}: the integrator writes {count} channels beside the image ({names}), which only \
         EXR holds; write to a .exr file",
        path.display()
    )]
    Channels {
        path: PathBuf,
        count: usize,
        names: String,
    },
}

/// Output formats, chosen by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    Exr,
}

impl Format {
    /// The format a path's extension asks for; checked before rendering.
    pub fn of(path: &Path) -> Result<Format, OutputError> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("png") => Ok(Format::Png),
            Some("exr") => Ok(Format::Exr),
            _ => Err(OutputError::Format(path.to_path_buf())),
        }
    }
}

/// Writes an image in the format its extension names. An image with
/// channels beside its RGB (an `aov` or `moment` integrator's) is written
/// to EXR only: a PNG is refused ([`check_channels`]) rather than written
/// without them. The film's alpha channel `A` alone is written to PNG as
/// 8-bit RGBA with straight alpha ([`to_srgba8`]), and to EXR as a
/// channel `A` beside the premultiplied RGB, as OpenEXR holds it.
pub fn write_image(path: &Path, image: &Image) -> Result<(), OutputError> {
    match Format::of(path)? {
        Format::Png => {
            if let Some(extra) = &image.extra {
                check_channels(path, &extra.names)?;
            }
            match alpha_of(image) {
                Some(alpha) => write_atomic(path, |file| write_png_alpha(file, image, &alpha)),
                None => write_atomic(path, |file| write_png(file, image)),
            }
        }
        Format::Exr => write_atomic(path, |file| write_exr(file, image)),
    }
}

/// Refuses to write channels `names` beside the image to `path` unless
/// its format holds them (EXR; PNG holds the alpha channel `A` alone):
/// what a caller checks before it renders.
pub fn check_channels(path: &Path, names: &[String]) -> Result<(), OutputError> {
    if names.is_empty() || names == [ALPHA] || Format::of(path)? == Format::Exr {
        return Ok(());
    }
    let mut shown: Vec<&str> = names.iter().take(6).map(String::as_str).collect();
    if names.len() > shown.len() {
        shown.push("…");
    }
    Err(OutputError::Channels {
        path: path.to_path_buf(),
        count: names.len(),
        names: shown.join(", "),
    })
}

/// Writes bytes (e.g. a JSON document) atomically.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    write_atomic(path, |file| {
        file.write_all(bytes).map_err(|e| e.to_string())
    })
}

fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut std::fs::File) -> Result<(), String>,
) -> Result<(), OutputError> {
    let err = |message: String| OutputError::Write {
        path: path.to_path_buf(),
        message,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".penumbra-").suffix(".partial");
    // Temporary files are private (0600); an output is an ordinary file,
    // made with the mode any new file gets (0666 less the umask).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder.tempfile_in(&dir).map_err(|e| {
        err(format!(
            "cannot create a temporary file in {}: {e}",
            dir.display()
        ))
    })?;
    write(tmp.as_file_mut()).map_err(err)?;
    tmp.as_file().sync_all().map_err(|e| err(e.to_string()))?;
    tmp.persist(path).map_err(|e| err(e.error.to_string()))?;
    Ok(())
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
pub fn srgb_encode(v: f32) -> f32 {
    let v = if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.0
    };
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// 8-bit sRGB bytes of an image, row-major RGB.
pub fn to_srgb8(image: &Image) -> Vec<u8> {
    image
        .pixels
        .iter()
        .flat_map(|p| p.to_array())
        .map(|v| (srgb_encode(v) * 255.0 + 0.5) as u8)
        .collect()
}

/// The name of the film's alpha channel.
const ALPHA: &str = "A";

/// The alpha channel of an image whose one channel beside its RGB is the
/// film's alpha `A`.
fn alpha_of(image: &Image) -> Option<Vec<f32>> {
    let extra = image.extra.as_ref()?;
    (extra.names == [ALPHA]).then(|| extra.channel(0).collect())
}

/// 8-bit sRGB bytes with straight alpha, row-major RGBA, of an image
/// whose colour is premultiplied by `alpha` (as a film develops it: a
/// pixel half covered holds half its surface's colour): the colour is
/// divided by the alpha (where it is not 0) before it is encoded, as PNG
/// readers expect.
pub fn to_srgba8(image: &Image, alpha: &[f32]) -> Vec<u8> {
    let byte = |v: f32| (v * 255.0 + 0.5) as u8;
    image
        .pixels
        .iter()
        .zip(alpha)
        .flat_map(|(p, &a)| {
            let a = if a.is_finite() {
                a.clamp(0.0, 1.0)
            } else {
                0.0
            };
            let c = p.to_array().map(|v| if a > 0.0 { v / a } else { v });
            [
                byte(srgb_encode(c[0])),
                byte(srgb_encode(c[1])),
                byte(srgb_encode(c[2])),
                byte(a),
            ]
        })
        .collect()
}

fn write_png_alpha(file: &mut std::fs::File, image: &Image, alpha: &[f32]) -> Result<(), String> {
    use image::ImageEncoder;
    let bytes = to_srgba8(image, alpha);
    let w = std::io::BufWriter::new(file);
    image::codecs::png::PngEncoder::new(w)
        .write_image(
            &bytes,
            image.width,
            image.height,
            image::ExtendedColorType::Rgba8,
        )
        .map_err(|e| e.to_string())
}

fn write_png(file: &mut std::fs::File, image: &Image) -> Result<(), String> {
    use image::ImageEncoder;
    let bytes = to_srgb8(image);
    let w = std::io::BufWriter::new(file);
    image::codecs::png::PngEncoder::new(w)
        .write_image(
            &bytes,
            image.width,
            image.height,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| e.to_string())
}

/// An image with channels beside its RGB: `R`, `G`, `B` and each channel
/// under its name (Mitsuba's), 32-bit float. OpenEXR lists a file's
/// channels sorted by name, so readers see them in that order.
fn write_exr_channels(
    file: &mut std::fs::File,
    image: &Image,
    extra: &crate::render::ExtraChannels,
) -> Result<(), String> {
    use exr::prelude::*;
    let (w, h) = (image.width as usize, image.height as usize);
    let mut list: Vec<AnyChannel<FlatSamples>> = Vec::new();
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        let v = image.pixels.iter().map(|p| p.to_array()[c]).collect();
        list.push(AnyChannel::new(*name, FlatSamples::F32(v)));
    }
    for (c, name) in extra.names.iter().enumerate() {
        let v = extra.channel(c).collect();
        list.push(AnyChannel::new(name.as_str(), FlatSamples::F32(v)));
    }
    let layer = Layer::new(
        (w, h),
        LayerAttributes::default(),
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(list.into()),
    );
    exr::image::Image::from_layer(layer)
        .write()
        .to_buffered(std::io::BufWriter::new(file))
        .map_err(|e| e.to_string())
}

fn write_exr(file: &mut std::fs::File, image: &Image) -> Result<(), String> {
    use exr::prelude::*;
    if let Some(extra) = &image.extra {
        return write_exr_channels(file, image, extra);
    }
    let (w, h) = (image.width as usize, image.height as usize);
    let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
        let c = image.pixels[p.1 * w + p.0];
        (c.r, c.g, c.b)
    });
    let layer = Layer::new(
        (w, h),
        LayerAttributes::default(),
        Encoding::SMALL_LOSSLESS,
        channels,
    );
    let out = exr::image::Image::from_layer(layer);
    out.write()
        .to_buffered(std::io::BufWriter::new(file))
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;

    #[test]
    fn srgb_known_values() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_encode(0.18) - 0.4614).abs() < 1e-3);
        assert_eq!(srgb_encode(f32::NAN), 0.0);
    }

    #[test]
    fn failed_write_keeps_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.png");
        std::fs::write(&path, b"precious").unwrap();
        let r = write_atomic(&path, |_| Err("disk on fire".into()));
        assert!(r.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"precious");
        let leftovers: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(leftovers.len(), 1, "the temporary file must be removed");
    }

    #[test]
    fn png_and_exr_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let mut img = Image::new(3, 2);
        img.pixels[4] = Rgb::new(0.25, 0.5, 2.0);
        write_image(&dir.path().join("a.png"), &img).unwrap();
        // The mode of any new file (the umask's).
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = |name: &str| {
                std::fs::metadata(dir.path().join(name))
                    .unwrap()
                    .permissions()
                    .mode()
                    & 0o777
            };
            std::fs::write(dir.path().join("plain"), b"").unwrap();
            assert_eq!(mode("a.png"), mode("plain"));
        }
        let png = image::open(dir.path().join("a.png")).unwrap().to_rgb8();
        assert_eq!(png.dimensions(), (3, 2));
        assert_eq!(png.get_pixel(1, 1).0, [137, 188, 255]);
        write_image(&dir.path().join("a.exr"), &img).unwrap();
        let exr = exr::prelude::read_first_rgba_layer_from_file(
            dir.path().join("a.exr"),
            |res, _| vec![[0f32; 3]; res.0 * res.1],
            |px: &mut Vec<[f32; 3]>, p, (r, g, b, _a): (f32, f32, f32, f32)| {
                px[p.1 * 3 + p.0] = [r, g, b]
            },
        )
        .unwrap();
        assert_eq!(exr.layer_data.channel_data.pixels[4], [0.25, 0.5, 2.0]);
        assert!(matches!(
            write_image(&dir.path().join("a.jpg"), &img),
            Err(OutputError::Format(_))
        ));
    }

    /// The film's alpha alone goes to PNG as straight 8-bit alpha, and to
    /// EXR as the channel `A`.
    #[test]
    fn alpha_goes_to_png_and_exr() {
        use crate::render::ExtraChannels;
        let dir = tempfile::tempdir().unwrap();
        let mut img = Image::new(2, 1);
        img.pixels[0] = Rgb::new(0.5, 0.25, 0.0);
        img.pixels[1] = Rgb::new(0.3, 0.3, 0.3);
        img.extra = Some(ExtraChannels {
            names: vec!["A".into()],
            values: vec![0.5, 0.0],
        });
        let png = dir.path().join("a.png");
        write_image(&png, &img).unwrap();
        let read = image::open(&png).unwrap().to_rgba8();
        // The colour unpremultiplied: 0.5 / 0.5 = 1, 0.25 / 0.5 = 0.5.
        assert_eq!(read.get_pixel(0, 0).0, [255, 188, 0, 128]);
        assert_eq!(read.get_pixel(1, 0).0[3], 0);
        let exr = dir.path().join("a.exr");
        write_image(&exr, &img).unwrap();
        let layers = exr::prelude::read_all_flat_layers_from_file(&exr).unwrap();
        let a = layers.layer_data[0]
            .channel_data
            .list
            .iter()
            .find(|c| c.name == *"A")
            .expect("an A channel");
        assert!(matches!(&a.sample_data, exr::prelude::FlatSamples::F32(v) if v == &[0.5, 0.0]));
        assert!(check_channels(&png, &["A".to_string()]).is_ok());
        assert!(check_channels(&png, &["A".to_string(), "B2".to_string()]).is_err());
    }

    /// An image with channels beside its RGB is written to EXR with every
    /// channel under its name, and read back the same; a PNG is refused.
    #[test]
    fn channels_round_trip_through_exr_by_name() {
        use crate::render::ExtraChannels;
        use exr::prelude::{read_all_flat_layers_from_file, FlatSamples};
        let dir = tempfile::tempdir().unwrap();
        let mut img = Image::new(3, 2);
        img.pixels[4] = Rgb::new(0.25, 0.5, 2.0);
        let names: Vec<String> = ["dd.T", "nn.X", "nn.Y", "nn.Z", "m2_img.Y"]
            .map(String::from)
            .into();
        let values: Vec<f32> = (0..6 * names.len()).map(|i| i as f32 * 0.5 - 3.0).collect();
        img.extra = Some(ExtraChannels {
            names: names.clone(),
            values: values.clone(),
        });
        let path = dir.path().join("aov.exr");
        write_image(&path, &img).unwrap();
        let read = read_all_flat_layers_from_file(&path).unwrap();
        let layer = &read.layer_data[0];
        let channel = |name: &str| -> Vec<f32> {
            let c = layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name == *name)
                .unwrap_or_else(|| panic!("no channel {name}"));
            match &c.sample_data {
                FlatSamples::F32(v) => v.clone(),
                other => panic!("{name}: {other:?}"),
            }
        };
        let mut got: Vec<String> = layer
            .channel_data
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        got.sort();
        let mut want = names.clone();
        want.extend(["R", "G", "B"].map(String::from));
        want.sort();
        assert_eq!(got, want);
        assert_eq!(channel("R")[4], 0.25);
        assert_eq!(channel("B")[4], 2.0);
        for (c, name) in names.iter().enumerate() {
            let want: Vec<f32> = values
                .iter()
                .skip(c)
                .step_by(names.len())
                .copied()
                .collect();
            assert_eq!(channel(name), want, "{name}");
        }
        let png = dir.path().join("aov.png");
        let e = write_image(&png, &img).unwrap_err();
        assert!(matches!(e, OutputError::Channels { count: 5, .. }), "{e}");
        assert!(e.to_string().contains("dd.T, nn.X"), "{e}");
        assert!(!png.exists());
    }
}
