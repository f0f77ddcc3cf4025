//! Writing and reading images: the library's atomic PNG/EXR writer, and an
//! EXR reader so that Python can compare its renders with the CLI's files.

use std::path::PathBuf;

use numpy::{PyArray3, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;

use penumbra::io::output::{write_image, Format, OutputError};
use penumbra::math::Rgb;
use penumbra::render::Image;

use crate::convert::image_to_numpy;

/// Largest image side, as for rendering (`width`, `height` ≤ 32768).
const MAX_SIDE: usize = 32768;

/// Writes an image (float array of shape (height, width, 3), linear RGB) to
/// `path`: `.png` is 8-bit sRGB, `.exr` 32-bit float linear. The file is
/// written atomically, as the CLI writes its output: a failure never leaves a
/// partial file and never destroys an existing one.
#[pyfunction]
pub fn save_image(py: Python<'_>, path: PathBuf, image: &Bound<'_, PyAny>) -> PyResult<()> {
    Format::of(&path).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let np = py.import("numpy")?;
    let array = np.call_method1("ascontiguousarray", (image, "float32"))?;
    let array = array
        .cast_into::<PyArray3<f32>>()
        .map_err(|_| PyValueError::new_err("image must have shape (height, width, 3)"))?;
    let shape = array.shape().to_vec();
    if shape[2] != 3 || shape[0] == 0 || shape[1] == 0 || shape[0] > MAX_SIDE || shape[1] > MAX_SIDE
    {
        return Err(PyValueError::new_err(format!(
            "image must have shape (height, width, 3) with 1 <= height, width <= {MAX_SIDE}, got {shape:?}"
        )));
    }
    let (h, w) = (shape[0], shape[1]);
    let data = array.readonly();
    let flat = data
        .as_slice()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let pixels: Vec<Rgb> = flat
        .chunks_exact(3)
        .map(|c| Rgb::new(c[0], c[1], c[2]))
        .collect();
    let img = Image {
        width: w as u32,
        height: h as u32,
        pixels,
        extra: None,
    };
    py.detach(|| write_image(&path, &img)).map_err(|e| match e {
        OutputError::Format(_) => PyValueError::new_err(e.to_string()),
        OutputError::Write { .. } => PyOSError::new_err(e.to_string()),
        OutputError::Channels { .. } => PyValueError::new_err(e.to_string()),
    })
}

/// Reads an OpenEXR image (as written by `save_image` or `penumbra render -o
/// out.exr`) into a float32 array of shape (height, width, 3). Only EXR:
/// a PNG holds 8-bit sRGB, not the rendered values.
#[pyfunction]
pub fn load_image<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyArray3<f32>>> {
    if Format::of(&path).ok() != Some(Format::Exr) {
        return Err(PyValueError::new_err(format!(
            "{}: load_image reads .exr files only",
            path.display()
        )));
    }
    let read = py.detach(|| {
        exr::prelude::read_first_rgba_layer_from_file(
            &path,
            // An oversized header gets an empty image (refused below) rather
            // than an allocation of whatever size the file claims.
            |size, _| {
                if size.0 <= MAX_SIDE && size.1 <= MAX_SIDE {
                    Image::new(size.0 as u32, size.1 as u32)
                } else {
                    Image::new(0, 0)
                }
            },
            |img: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                let i = pos.1 * img.width as usize + pos.0;
                if let Some(p) = img.pixels.get_mut(i) {
                    *p = Rgb::new(r, g, b);
                }
            },
        )
    });
    let image = read.map_err(|e| match e {
        exr::error::Error::Io(io) => PyOSError::new_err(format!("{}: {io}", path.display())),
        other => PyValueError::new_err(format!("{}: {other}", path.display())),
    })?;
    let pixels = &image.layer_data.channel_data.pixels;
    if pixels.width == 0 || pixels.height == 0 {
        return Err(PyValueError::new_err(format!(
            "{}: the image is empty or larger than {MAX_SIDE} pixels on a side",
            path.display()
        )));
    }
    image_to_numpy(py, pixels)
}
