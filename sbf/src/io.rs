//! Loading lat-long HDR maps (Radiance `.hdr`, RLE or flat, and OpenEXR) with
//! validation: 2:1 aspect, and texels that are NaN, ±Inf or negative are an error
//! naming the file, the problem, the first texel and the count — or, with
//! `sanitize`, replaced by 0 and counted.
//!
//! Behind the `io` cargo feature (off by default: the core does no file I/O). The one
//! place where both tools — `probes` (comparison) and `baker` (environment lighting) —
//! read maps, so the baker does not depend on the comparison tool.

use crate::envmap::LatLongImage;
use std::fmt;
use std::path::Path;

/// Why a map could not be used.
#[derive(Debug, Clone, PartialEq)]
pub enum InputError {
    /// Nothing at the path.
    NotFound {
        /// The path as given.
        path: String,
    },
    /// The path is a directory.
    IsDirectory {
        /// The path as given.
        path: String,
    },
    /// Extension other than .hdr/.exr.
    UnsupportedFormat {
        /// The path as given.
        path: String,
        /// Its extension (empty: none).
        extension: String,
    },
    /// The extension says one format, the first bytes say otherwise.
    NotFormat {
        /// The path as given.
        path: String,
        /// The format the extension names ("a Radiance HDR", "an OpenEXR").
        format: &'static str,
        /// The signature that format starts with.
        expected: &'static str,
    },
    /// The decoder rejected the file (truncated, corrupt, unreadable).
    Decode {
        /// The path as given.
        path: String,
        /// The decoder's message.
        message: String,
    },
    /// Not a 2:1 lat-long map.
    Aspect {
        /// The path as given.
        path: String,
        /// Its width in texels.
        width: u32,
        /// Its height in texels.
        height: u32,
    },
    /// Non-finite or negative texels (without --sanitize).
    BadTexels {
        /// The path as given.
        path: String,
        /// "NaN", "infinite" or "negative".
        kind: &'static str,
        /// Texel channels of that kind.
        count: usize,
        /// The first such texel (column, row).
        first: (u32, u32),
        /// Its value.
        value: f32,
    },
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InputError::NotFound { path } => write!(f, "{path}: not found"),
            InputError::IsDirectory { path } => write!(f, "{path}: is a directory (expected a lat-long .hdr or .exr file)"),
            InputError::UnsupportedFormat { path, extension } if extension.is_empty() => {
                write!(f, "{path}: not a Radiance HDR or OpenEXR file (no extension; expected a lat-long .hdr or .exr)")
            }
            InputError::UnsupportedFormat { path, extension } => {
                write!(f, "{path}: not a Radiance HDR or OpenEXR file (extension '.{extension}'; expected a lat-long .hdr or .exr)")
            }
            InputError::NotFormat { path, format, expected } => {
                write!(f, "{path}: not {format} file (it does not start with {expected})")
            }
            InputError::Decode { path, message } => write!(f, "{path}: cannot decode: {message}"),
            InputError::Aspect { path, width, height } => write!(f, "{path}: {width}×{height} is not a 2:1 lat-long map"),
            InputError::BadTexels { path, kind, count, first, value } => write!(
                f,
                "{path}: {count} texel channel(s) are {kind}; first at texel ({}, {}) = {value} (use --sanitize to replace them with 0)",
                first.0, first.1
            ),
        }
    }
}

impl std::error::Error for InputError {}

/// What `sanitize` replaced.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SanitizeReport {
    /// NaN texel channels replaced by 0.
    pub nan: usize,
    /// Infinite texel channels replaced by 0.
    pub infinite: usize,
    /// Negative texel channels replaced by 0.
    pub negative: usize,
}

impl SanitizeReport {
    /// Texel channels replaced in all.
    pub fn total(&self) -> usize {
        self.nan + self.infinite + self.negative
    }
}

/// Decodes, validates and (optionally) sanitises a lat-long map.
pub fn load_map(path: &Path, sanitize: bool) -> Result<(LatLongImage, SanitizeReport), InputError> {
    let p = path.display().to_string();
    let format = check_path(path)?;
    let bytes = std::fs::read(path).map_err(|e| InputError::Decode { path: p.clone(), message: e.to_string() })?;
    check_magic(&p, format, &bytes)?;
    if format == image::ImageFormat::Hdr {
        check_hdr(&bytes).map_err(|message| InputError::Decode { path: p.clone(), message })?;
    }
    let img = image::load_from_memory_with_format(&bytes, format)
        .map_err(|e| InputError::Decode { path: p.clone(), message: e.to_string() })?
        .to_rgb32f();
    let (w, h) = img.dimensions();
    if w != 2 * h || h == 0 {
        return Err(InputError::Aspect { path: p, width: w, height: h });
    }
    let mut texels: Vec<[f32; 3]> = img.pixels().map(|px| px.0).collect();
    let report = validate(&p, w, &mut texels, sanitize)?;
    let map = LatLongImage::new(w as usize, h as usize, texels).map_err(|e| InputError::Decode { path: p, message: e.to_string() })?;
    Ok((map, report))
}

/// What can be known of a map without decoding it: that the path exists, is a file, and
/// has a map's extension (its format). Tools call it for every input before any work.
pub fn check_path(path: &Path) -> Result<image::ImageFormat, InputError> {
    let p = path.display().to_string();
    match std::fs::metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(InputError::NotFound { path: p }),
        Err(e) => return Err(InputError::Decode { path: p, message: e.to_string() }),
        Ok(m) if m.is_dir() => return Err(InputError::IsDirectory { path: p }),
        Ok(_) => {}
    }
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    match ext.as_str() {
        "hdr" => Ok(image::ImageFormat::Hdr),
        "exr" => Ok(image::ImageFormat::OpenExr),
        _ => Err(InputError::UnsupportedFormat { path: p, extension: ext }),
    }
}

/// The format's signature: Radiance files start with `#?` (Ward, "Real Pixels", Graphics
/// Gems II; the `#?RADIANCE` line), OpenEXR files with the magic number 20000630
/// (0x76 0x2f 0x31 0x01, OpenEXR file layout).
fn check_magic(path: &str, format: image::ImageFormat, bytes: &[u8]) -> Result<(), InputError> {
    let (name, magic, expected): (&str, &[u8], &str) = match format {
        image::ImageFormat::Hdr => ("a Radiance HDR", b"#?", "'#?'"),
        _ => ("an OpenEXR", &[0x76, 0x2f, 0x31, 0x01], "the OpenEXR magic number"),
    };
    if bytes.starts_with(magic) {
        Ok(())
    } else {
        Err(InputError::NotFormat { path: path.to_string(), format: name, expected })
    }
}

/// Scans for NaN, ±Inf and negative values; errors on the first kind found (NaN, then
/// Inf, then negative), or replaces all of them with 0 when `sanitize`.
pub fn validate(path: &str, width: u32, texels: &mut [[f32; 3]], sanitize: bool) -> Result<SanitizeReport, InputError> {
    let mut r = SanitizeReport::default();
    let mut first: [Option<((u32, u32), f32)>; 3] = [None; 3];
    for (k, t) in texels.iter_mut().enumerate() {
        for v in t.iter_mut() {
            let kind = if v.is_nan() {
                0
            } else if v.is_infinite() {
                1
            } else if *v < 0.0 {
                2
            } else {
                continue;
            };
            match kind {
                0 => r.nan += 1,
                1 => r.infinite += 1,
                _ => r.negative += 1,
            }
            first[kind].get_or_insert(((k as u32 % width, k as u32 / width), *v));
            if sanitize {
                *v = 0.0;
            }
        }
    }
    if !sanitize {
        for (kind, name, count) in [(0, "NaN", r.nan), (1, "infinite", r.infinite), (2, "negative", r.negative)] {
            if let Some((pos, value)) = first[kind] {
                return Err(InputError::BadTexels { path: path.to_string(), kind: name, count, first: pos, value });
            }
        }
    }
    Ok(r)
}

/// Checks a Radiance `.hdr` file where the `image` decoder is lenient, before it decodes:
/// every `EXPOSURE=` header value must be finite and positive (it scales the radiance),
/// and in a new-style RLE file every scanline's width field must equal the image width
/// and its runs must fill the scanline exactly (walked, not decoded). Flat and old-style
/// files are left to the decoder.
pub fn check_hdr(bytes: &[u8]) -> Result<(), String> {
    let mut pos = 0;
    let mut line = || -> Option<&[u8]> {
        let start = pos;
        let end = start + bytes.get(start..)?.iter().position(|b| *b == b'\n')?;
        pos = end + 1;
        Some(&bytes[start..end])
    };
    loop {
        let Some(l) = line() else { return Ok(()) }; // truncated header: the decoder says so
        if l.is_empty() {
            break;
        }
        if let Some(v) = l.strip_prefix(b"EXPOSURE=") {
            let text = String::from_utf8_lossy(v);
            let e: f64 = text.trim().parse().map_err(|_| format!("header EXPOSURE={text} is not a number"))?;
            if !(e.is_finite() && e > 0.0) {
                return Err(format!("header EXPOSURE={text} must be finite and positive"));
            }
        }
    }
    let Some(res) = line() else { return Ok(()) };
    let res = String::from_utf8_lossy(res).to_string();
    let f: Vec<&str> = res.split_whitespace().collect();
    let (Some(h), Some(w)) = (f.get(1).and_then(|x| x.parse::<usize>().ok()), f.get(3).and_then(|x| x.parse::<usize>().ok())) else {
        return Ok(());
    };
    if !(8..=0x7fff).contains(&w) {
        return Ok(());
    }
    for y in 0..h {
        let Some(head) = bytes.get(pos..pos + 4) else { return Ok(()) };
        if head[0] != 2 || head[1] != 2 || head[2] & 0x80 != 0 {
            // Not new-style RLE (flat or old-style): only the first scanline can tell.
            return Ok(());
        }
        let field = ((head[2] as usize) << 8) | head[3] as usize;
        if field != w {
            return Err(format!("RLE scanline {y} says it is {field} pixels wide, the image is {w}"));
        }
        pos += 4;
        for c in 0..4 {
            let mut x = 0;
            while x < w {
                let Some(&n) = bytes.get(pos) else { return Ok(()) };
                let (count, skip) = if n > 128 { (n as usize - 128, 2) } else { (n as usize, 1 + n as usize) };
                if count == 0 || x + count > w {
                    return Err(format!("RLE scanline {y}, channel {c}: a run of {count} at pixel {x} does not fit the width {w}"));
                }
                x += count;
                pos += skip;
            }
        }
    }
    Ok(())
}
