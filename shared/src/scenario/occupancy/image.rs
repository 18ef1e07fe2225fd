//! The map's image, decoded and read as map_server reads it: every pixel
//! free, occupied or unknown. PGM (binary P5 and plain P2, 8 or 16 bits)
//! by hand, PNG (any colour type and depth) with the `png` crate. Sizes
//! come from the header and are checked against [`MAX_IMAGE_PIXELS`]
//! before any pixel is stored.

use super::yaml::{Meta, Mode};

/// The most pixels an image may have (4096 x 4096): every pass of the
/// conversion is linear in them, and a SLAM map of a large building at
/// 5 cm a pixel is about 2000 x 2000.
pub const MAX_IMAGE_PIXELS: usize = 4096 * 4096;

/// What map_server makes of a pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Class {
    Free,
    Occupied,
    Unknown,
}

/// The pixels, row 0 at the top of the image (the map's far side in y).
#[derive(Clone, Debug, PartialEq)]
pub struct Raster {
    pub width: usize,
    pub height: usize,
    pub cells: Vec<Class>,
}

/// One pixel's channels on a scale of `max`: gray or RGB, and alpha.
struct Pixel {
    rgb_sum: f64,
    alpha: Option<f64>,
    max: f64,
}

/// map_server's reading (nav2 map_io): the shade is the mean of R, G, B
/// (and, in trinary mode, alpha), occupancy `1 - shade` (or the shade
/// itself when `negate`), then the thresholds.
fn classify(meta: &Meta, p: &Pixel) -> Class {
    let rgb = p.rgb_sum / (3.0 * p.max);
    let shade = match (meta.mode, p.alpha) {
        (Mode::Trinary, Some(a)) => (p.rgb_sum + a) / (4.0 * p.max),
        (Mode::Scale, Some(a)) if a < p.max => return Class::Unknown,
        _ => rgb,
    };
    let occ = match meta.mode {
        Mode::Raw => {
            let percent = (rgb * 255.0).round();
            if percent > 100.0 {
                return Class::Unknown;
            }
            percent / 100.0
        }
        _ if meta.negate => shade,
        _ => 1.0 - shade,
    };
    if occ > meta.occupied_thresh {
        Class::Occupied
    } else if occ < meta.free_thresh {
        Class::Free
    } else {
        Class::Unknown
    }
}

/// Decodes `bytes` (PGM or PNG, told apart by their first bytes).
pub fn decode(bytes: &[u8], meta: &Meta) -> Result<Raster, String> {
    match bytes {
        [b'P', b'5', ..] | [b'P', b'2', ..] => pgm(bytes, meta),
        [0x89, b'P', b'N', b'G', ..] => png(bytes, meta),
        _ => Err("is neither a PGM (P5 or P2) nor a PNG image: only those are read".into()),
    }
}

fn check_size(width: usize, height: usize) -> Result<usize, String> {
    if width == 0 || height == 0 {
        return Err(format!("has no pixels ({width} x {height})"));
    }
    match width.checked_mul(height) {
        Some(n) if n <= MAX_IMAGE_PIXELS => Ok(n),
        _ => Err(format!(
            "is {width} x {height} pixels, above the limit MAX_IMAGE_PIXELS = {MAX_IMAGE_PIXELS} (4096 x 4096): \
             crop it, or scale it down and raise `resolution`"
        )),
    }
}

/// The PGM header's tokens and where the data starts: whitespace and `#`
/// comments between tokens, one whitespace byte after the last.
struct Tokens<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Tokens<'_> {
    fn next(&mut self, what: &str) -> Result<&str, String> {
        loop {
            match self.bytes.get(self.at) {
                Some(b'#') => {
                    while self.bytes.get(self.at).is_some_and(|&b| b != b'\n') {
                        self.at += 1;
                    }
                }
                Some(b) if b.is_ascii_whitespace() => self.at += 1,
                Some(_) => break,
                None => return Err(format!("ends before its {what}")),
            }
        }
        let start = self.at;
        while self.bytes.get(self.at).is_some_and(|b| !b.is_ascii_whitespace() && *b != b'#') {
            self.at += 1;
        }
        std::str::from_utf8(&self.bytes[start..self.at]).map_err(|_| format!("has a {what} that is not a number"))
    }

    fn number(&mut self, what: &str, max: usize) -> Result<usize, String> {
        let t = self.next(what)?;
        match t.parse::<usize>() {
            Ok(v) if v <= max => Ok(v),
            Ok(v) => Err(format!("has a {what} of {v}, above {max}")),
            Err(_) => Err(format!("has a {what} `{}` that is not a whole number", t.escape_default())),
        }
    }
}

fn pgm(bytes: &[u8], meta: &Meta) -> Result<Raster, String> {
    let plain = bytes[1] == b'2';
    let mut t = Tokens { bytes, at: 2 };
    let width = t.number("width (PGM header)", usize::MAX)?;
    let height = t.number("height (PGM header)", usize::MAX)?;
    let n = check_size(width, height)?;
    let maxval = t.number("maxval (PGM header)", 65535)?;
    if maxval == 0 {
        return Err("has a maxval (PGM header) of 0".into());
    }
    let max = maxval as f64;
    let gray = |v: usize| Pixel { rgb_sum: 3.0 * v as f64, alpha: None, max };
    let mut cells = Vec::with_capacity(n);
    if plain {
        for k in 0..n {
            // The message is built only for a pixel that is wrong.
            let v = match t.next("pixels").map(str::parse::<usize>) {
                Ok(Ok(v)) if v <= maxval => v,
                Ok(_) => return Err(format!("has a pixel {k} that is not a whole number up to its maxval {maxval}")),
                Err(_) => return Err(format!("ends before its pixel {k} (its header's {width} x {height} needs {n})")),
            };
            cells.push(classify(meta, &gray(v)));
        }
    } else {
        let wide = maxval > 255;
        let data = &bytes[(t.at + 1).min(bytes.len())..];
        let need = n * if wide { 2 } else { 1 };
        if data.len() < need {
            return Err(format!(
                "holds {} bytes of pixels, but its header's {width} x {height} at maxval {maxval} needs {need}",
                data.len()
            ));
        }
        for k in 0..n {
            let v = if wide { u16::from_be_bytes([data[2 * k], data[2 * k + 1]]) as usize } else { data[k] as usize };
            if v > maxval {
                return Err(format!("has pixel {k} = {v}, above its maxval {maxval}"));
            }
            cells.push(classify(meta, &gray(v)));
        }
    }
    Ok(Raster { width, height, cells })
}

fn png(bytes: &[u8], meta: &Meta) -> Result<Raster, String> {
    let bad = |e: png::DecodingError| format!("is not a readable PNG: {e}");
    // The decoder's own buffers, beyond the one we allocate for the pixels.
    let limits = png::Limits { bytes: 4 * MAX_IMAGE_PIXELS };
    let mut decoder = png::Decoder::new_with_limits(std::io::Cursor::new(bytes), limits);
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let header = decoder.read_header_info().map_err(bad)?;
    let (width, height) = (header.width as usize, header.height as usize);
    let n = check_size(width, height)?;
    let mut reader = decoder.read_info().map_err(bad)?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let frame = reader.next_frame(&mut buf).map_err(bad)?;
    let channels = frame.color_type.samples();
    let stride = frame.line_size;
    let mut cells = Vec::with_capacity(n);
    for y in 0..height {
        let row = &buf[y * stride..];
        for x in 0..width {
            let c = &row[x * channels..(x + 1) * channels];
            let f = |k: usize| c[k] as f64;
            let (rgb_sum, alpha) = match channels {
                1 => (3.0 * f(0), None),
                2 => (3.0 * f(0), Some(f(1))),
                3 => (f(0) + f(1) + f(2), None),
                _ => (f(0) + f(1) + f(2), Some(f(3))),
            };
            cells.push(classify(meta, &Pixel { rgb_sum, alpha, max: 255.0 }));
        }
    }
    Ok(Raster { width, height, cells })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meta(mode: Mode, negate: bool) -> Meta {
        Meta {
            image: "m.pgm".into(),
            resolution: 0.1,
            origin: (0.0, 0.0),
            negate,
            occupied_thresh: 0.65,
            free_thresh: 0.196,
            mode,
        }
    }

    #[test]
    fn map_saver_shades_read_back_as_written() {
        use Class::*;
        let m = meta(Mode::Trinary, false);
        // map_saver writes free 254, occupied 0, unknown 205.
        let p5 = [b"P5\n# saved\n3 1\n255\n".as_slice(), &[254, 0, 205]].concat();
        assert_eq!(decode(&p5, &m).unwrap().cells, [Free, Occupied, Unknown]);
        let p2 = b"P2 3 1 255\n254 0\n205";
        assert_eq!(decode(p2, &m).unwrap().cells, [Free, Occupied, Unknown]);
        let wide = [b"P5 2 1 65535\n".as_slice(), &[0xff, 0xff, 0, 0]].concat();
        assert_eq!(decode(&wide, &m).unwrap().cells, [Free, Occupied]);
        // Negated, white is occupied, and map_saver's unknown grey too.
        assert_eq!(decode(&p5, &meta(Mode::Trinary, true)).unwrap().cells, [Occupied, Free, Occupied]);
        // Raw: the value is the occupancy in percent.
        let raw = [b"P5 3 1 255\n".as_slice(), &[0, 100, 255]].concat();
        assert_eq!(decode(&raw, &meta(Mode::Raw, false)).unwrap().cells, [Free, Occupied, Unknown]);
    }

    #[test]
    fn pngs_of_every_colour_type_read_like_pgm() {
        use Class::*;
        let m = meta(Mode::Trinary, false);
        let encode = |color: png::ColorType, data: &[u8]| {
            let mut out = Vec::new();
            let mut e = png::Encoder::new(&mut out, 3, 1);
            e.set_color(color);
            e.write_header().unwrap().write_image_data(data).unwrap();
            out
        };
        let gray = encode(png::ColorType::Grayscale, &[254, 0, 205]);
        assert_eq!(decode(&gray, &m).unwrap().cells, [Free, Occupied, Unknown]);
        let rgb = encode(png::ColorType::Rgb, &[254, 254, 254, 0, 0, 0, 205, 205, 205]);
        assert_eq!(decode(&rgb, &m).unwrap().cells, [Free, Occupied, Unknown]);
        // A transparent pixel is unknown in scale mode.
        let rgba = encode(png::ColorType::Rgba, &[254, 254, 254, 255, 0, 0, 0, 255, 254, 254, 254, 0]);
        assert_eq!(decode(&rgba, &meta(Mode::Scale, false)).unwrap().cells, [Free, Occupied, Unknown]);
    }

    #[test]
    fn broken_images_are_named_errors() {
        let m = meta(Mode::Trinary, false);
        let cases: [(&[u8], &str); 8] = [
            (b"P5 3 1 255\n\x00", "holds 1 bytes of pixels, but its header's 3 x 1 at maxval 255 needs 3"),
            (b"P5 3", "ends before its height"),
            (b"P5 x 1 255\n", "width (PGM header) `x` that is not a whole number"),
            (b"P5 5000 5000 255\n", "above the limit MAX_IMAGE_PIXELS = 16777216"),
            (b"P5 0 3 255\n", "has no pixels"),
            (b"P2 2 1 255 1\n", "ends before its pixel 1 (its header's 2 x 1 needs 2)"),
            (b"P2 1 1 15 16\n", "pixel 0 that is not a whole number up to its maxval 15"),
            (b"GIF89a", "neither a PGM"),
        ];
        for (bytes, want) in cases {
            let e = decode(bytes, &m).unwrap_err();
            assert!(e.contains(want), "{}: {e}", String::from_utf8_lossy(bytes));
        }
        let e = decode(b"\x89PNG\r\n\x1a\n", &m).unwrap_err();
        assert!(e.contains("is not a readable PNG"), "{e}");
    }
}
