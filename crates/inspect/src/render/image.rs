//! The rendered image and its PNG encoding.

use std::path::Path;

use crate::InspectError;

/// An 8-bit RGBA image (straight, not premultiplied, alpha), rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `4 * width * height` bytes, RGBA per pixel, row-major from the top-left corner.
    pub rgba: Vec<u8>,
    /// The value range of the colour map in the curvature mode (the legend's labels), as
    /// `[low, high]`; `None` in the other modes.
    pub legend_range: Option<[f64; 2]>,
}

impl Image {
    /// The RGBA bytes of pixel (x, y).
    ///
    /// # Panics
    /// When (x, y) is outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = 4 * (y as usize * self.width as usize + x as usize);
        [
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ]
    }

    /// The PNG file's bytes (RGBA, 8 bits per channel, fixed compression settings: the same
    /// image always gives the same bytes).
    ///
    /// # Errors
    /// [`InspectError::Write`] if the encoder fails (it does not for a consistent image).
    pub fn encode_png(&self) -> Result<Vec<u8>, InspectError> {
        let err = |e: png::EncodingError| InspectError::Write {
            path: "<memory>".into(),
            message: e.to_string(),
        };
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, self.width, self.height);
            enc.set_color(png::ColorType::Rgba);
            enc.set_depth(png::BitDepth::Eight);
            enc.set_compression(png::Compression::Balanced);
            let mut w = enc.write_header().map_err(err)?;
            w.write_image_data(&self.rgba).map_err(err)?;
            w.finish().map_err(err)?;
        }
        Ok(out)
    }

    /// Writes the PNG to `path` atomically (temporary file in the same directory + rename).
    ///
    /// # Errors
    /// [`InspectError::Write`] naming the file.
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<(), InspectError> {
        let path = path.as_ref();
        let bytes = self.encode_png()?;
        algesurf_io::write_atomic(path, &bytes).map_err(|e| InspectError::Write {
            path: path.display().to_string(),
            message: e.to_string(),
        })
    }
}
