//! Pictures: tone-mapped tiles, ꟻLIP error maps in the magma colour map (ꟻLIP's own
//! convention, 0 → black, 1 → white-yellow), a colour bar, and grids of tiles written
//! as PNG. Tiles are centre crops, never downsampled: downsampling would average away
//! the aliasing the figures show.

use super::measure::tone;
use crate::error::{Error, Result};

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

/// The ASCII spelling of a label's other characters (font8x8's basic set is ASCII).
fn ascii(s: &str) -> String {
    let mut out = String::new();
    for c in s.chars() {
        match c {
            'α' => out.push_str("alpha"),
            'κ' => out.push_str("kappa"),
            'σ' => out.push_str("sigma"),
            'δ' => out.push_str("delta"),
            'ρ' => out.push_str("rho"),
            'ψ' => out.push_str("psi"),
            'ε' => out.push_str("eps"),
            'ꟻ' => out.push('F'),
            '²' => out.push_str("^2"),
            // after a caret already: "A)^¼" reads "A)^(1/4)"
            '¼' => out.push_str(if out.ends_with('^') {
                "(1/4)"
            } else {
                "^(1/4)"
            }),
            '→' => out.push_str("to"),
            '⁻' => out.push_str("^-"),
            '¹' => out.push('1'),
            '×' => out.push('x'),
            '–' | '—' => out.push('-'),
            '≥' => out.push_str(">="),
            '≤' => out.push_str("<="),
            '·' => out.push('.'),
            '‖' => out.push('|'),
            c if c.is_ascii() => out.push(c),
            _ => out.push('?'),
        }
    }
    out
}

/// Wrap `s` at spaces into lines of at most `cols` characters (a longer word is cut).
fn wrap(s: &str, cols: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in s.split_whitespace() {
        let mut word = word.to_string();
        while word.len() > cols {
            let rest = word.split_off(cols);
            lines.push(std::mem::replace(&mut word, rest));
        }
        match lines.last_mut() {
            Some(l) if !l.is_empty() && l.len() + 1 + word.len() <= cols => {
                l.push(' ');
                l.push_str(&word);
            }
            _ => lines.push(word),
        }
    }
    lines
}

/// Pixels per text line (an 8×8 glyph and a 2-pixel lead).
pub const LINE: usize = 10;

/// A label: `s` in font8x8's 8×8 glyphs, white on the grids' grey, wrapped into a box
/// `w` pixels wide and `lines` text lines high (text beyond them is cut; Greek letters and
/// other marks are spelled in ASCII).
pub fn label(s: &str, w: usize, lines: usize) -> Rgb {
    let mut img = Rgb::new(w, lines * LINE, [96, 96, 96]);
    let cols = (w / 8).max(1);
    for (l, line) in wrap(&ascii(s), cols).iter().take(lines).enumerate() {
        for (k, ch) in line.bytes().enumerate() {
            let glyph = font8x8::legacy::BASIC_LEGACY[(ch as usize).min(127)];
            for (gy, bits) in glyph.iter().enumerate() {
                for gx in 0..8 {
                    if bits >> gx & 1 == 1 {
                        let (x, y) = (k * 8 + gx, l * LINE + 1 + gy);
                        if x < w {
                            img.px[y * w + x] = [255, 255, 255];
                        }
                    }
                }
            }
        }
    }
    img
}

/// A grid ([`grid`]) with its columns named above it and its rows named to its left, in
/// the picture itself: `cols[c]` heads column c, `rows[r]` names row r (an empty name
/// leaves the row unnamed). The names must match the tiles' layout.
pub fn labelled_grid(
    tiles: &[Vec<Rgb>],
    gap: usize,
    cols: &[String],
    rows: &[String],
    head_lines: usize,
    side: usize,
) -> Result<Rgb> {
    let ncols = tiles.iter().map(|r| r.len()).max().unwrap_or(0);
    if cols.len() != ncols || rows.len() != tiles.len() {
        return Err(Error::InvalidArgument(format!(
            "a labelled grid of {} rows × {ncols} columns given {} row and {} column names",
            tiles.len(),
            rows.len(),
            cols.len()
        )));
    }
    let body = grid(tiles, gap);
    let tw = tiles.iter().flatten().map(|t| t.w).max().unwrap_or(1);
    let th = tiles.iter().flatten().map(|t| t.h).max().unwrap_or(1);
    let head = head_lines * LINE + gap;
    let mut g = Rgb::new(side + body.w, head + body.h, [96, 96, 96]);
    g.blit(&body, side, head);
    for (c, name) in cols.iter().enumerate() {
        g.blit(
            &label(name, tw, head_lines),
            side + gap + c * (tw + gap),
            gap,
        );
    }
    let side_lines = (th / LINE).max(1);
    for (r, name) in rows.iter().enumerate() {
        let l = label(name, side.saturating_sub(gap).max(8), side_lines);
        g.blit(&l, gap, head + gap + r * (th + gap));
    }
    Ok(g)
}
