//! Pictures: tone-mapped tiles, ꟻLIP error maps in the magma colour map (ꟻLIP's own
//! convention, 0 → black, 1 → white-yellow), a colour bar, and grids of tiles written
//! as PNG. Tiles are centre crops, never downsampled: downsampling would average away
//! the aliasing the figures show.

use super::measure::tone;
use crate::error::{Error, Result};
use std::path::Path;

/// An RGB8 image.
#[derive(Clone, Debug)]
pub struct Rgb {
    pub w: usize,
    pub h: usize,
    pub px: Vec<[u8; 3]>,
}

impl Rgb {
    pub fn new(w: usize, h: usize, fill: [u8; 3]) -> Rgb {
        Rgb {
            w,
            h,
            px: vec![fill; w * h],
        }
    }
    /// A linear image, tone-mapped.
    pub fn from_linear(img: &[f64], w: usize, h: usize, exposure: f64) -> Rgb {
        Rgb {
            w,
            h,
            px: img
                .iter()
                .map(|&x| {
                    let v = (tone(x, exposure) * 255.0).round().clamp(0.0, 255.0) as u8;
                    [v, v, v]
                })
                .collect(),
        }
    }
    /// Values in [0, 1] through the magma colour map.
    pub fn magma(vals: &[f32], w: usize, h: usize) -> Rgb {
        let lut = nv_flip::magma_lut().to_vec();
        Rgb {
            w,
            h,
            px: vals
                .iter()
                .map(|&v| {
                    let i = ((v.clamp(0.0, 1.0) * 255.0).round() as usize).min(255);
                    [lut[3 * i], lut[3 * i + 1], lut[3 * i + 2]]
                })
                .collect(),
        }
    }
    /// The centre crop of side ≤ (cw, ch).
    pub fn crop(&self, cw: usize, ch: usize) -> Rgb {
        let (cw, ch) = (cw.min(self.w), ch.min(self.h));
        let (x0, y0) = ((self.w - cw) / 2, (self.h - ch) / 2);
        Rgb {
            w: cw,
            h: ch,
            px: (0..cw * ch)
                .map(|k| self.px[(y0 + k / cw) * self.w + x0 + k % cw])
                .collect(),
        }
    }
    fn blit(&mut self, t: &Rgb, x0: usize, y0: usize) {
        for y in 0..t.h.min(self.h.saturating_sub(y0)) {
            for x in 0..t.w.min(self.w.saturating_sub(x0)) {
                self.px[(y0 + y) * self.w + x0 + x] = t.px[y * t.w + x];
            }
        }
    }
    /// PNG bytes.
    pub fn png(&self) -> Result<Vec<u8>> {
        let raw: Vec<u8> = self.px.iter().flatten().copied().collect();
        let img = image::RgbImage::from_raw(self.w as u32, self.h as u32, raw)
            .ok_or_else(|| Error::InvalidArgument("picture: buffer size".into()))?;
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png)
            .map_err(|e| Error::InvalidArgument(format!("PNG encoding: {e}")))?;
        Ok(out.into_inner())
    }
    pub fn write(&self, path: &Path) -> Result<()> {
        crate::io::write_atomic(path, &self.png()?)
    }
}

/// Tiles laid out in rows (each row may be shorter), `gap` pixels apart on a grey
/// background.
pub fn grid(rows: &[Vec<Rgb>], gap: usize) -> Rgb {
    let tw = rows.iter().flatten().map(|t| t.w).max().unwrap_or(1);
    let th = rows.iter().flatten().map(|t| t.h).max().unwrap_or(1);
    let cols = rows.iter().map(|r| r.len()).max().unwrap_or(1);
    let mut g = Rgb::new(
        cols * (tw + gap) + gap,
        rows.len() * (th + gap) + gap,
        [96, 96, 96],
    );
    for (r, row) in rows.iter().enumerate() {
        for (c, t) in row.iter().enumerate() {
            g.blit(t, gap + c * (tw + gap), gap + r * (th + gap));
        }
    }
    g
}

/// A horizontal colour bar of the magma map from 0 (left) to 1 (right), with tick
/// marks at 0, 0.25, 0.5, 0.75 and 1.
pub fn colour_bar(w: usize, h: usize) -> Rgb {
    let vals: Vec<f32> = (0..w * h)
        .map(|k| (k % w) as f32 / (w - 1).max(1) as f32)
        .collect();
    let mut bar = Rgb::magma(&vals, w, h);
    for q in 0..5 {
        let x = (q * (w - 1)) / 4;
        for y in h.saturating_sub(h / 4)..h {
            bar.px[y * w + x] = [255, 255, 255];
        }
    }
    bar
}
