//! Image outputs: float EXR per mode and signal (same lat-long parameterisation as the
//! input grid), tone-mapped PNG previews with a stated exposure, and the plots
//! (error against encode time and against reconstruction cost, one labelled point per
//! mode; error against sample count, one line per per-sample encoder) drawn with plotters and the DejaVu font from the `dejavu` crate.

use plotters::prelude::*;
use sbf::envmap::LatLong;
use std::path::Path;

/// Writes a float RGB image as OpenEXR.
pub fn write_exr(path: &Path, grid: LatLong, px: &[[f64; 3]]) -> Result<(), String> {
    let img = image::Rgb32FImage::from_fn(grid.width as u32, grid.height as u32, |x, y| {
        let p = px[y as usize * grid.width + x as usize];
        image::Rgb([p[0] as f32, p[1] as f32, p[2] as f32])
    });
    img.save(path).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// Saves an 8-bit RGB image as PNG with fast deflate and adaptive filtering (previews and
/// plots: lossless either way; the default deflate level costs more time than it saves
/// bytes here).
fn save_png(path: &Path, img: &image::RgbImage) -> Result<(), String> {
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    let file = std::fs::File::create(path).map_err(|e| format!("writing {}: {e}", path.display()))?;
    let enc = PngEncoder::new_with_quality(std::io::BufWriter::new(file), CompressionType::Fast, FilterType::Adaptive);
    img.write_with_encoder(enc).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// Box-filters a row-major image on `grid` by the smallest power of two that makes it at
/// most `max_width` wide (as far as the grid halves evenly); returns the new grid and texels.
pub fn box_shrink(grid: LatLong, px: &[[f64; 3]], max_width: usize) -> (LatLong, Vec<[f64; 3]>) {
    let mut f = 1;
    while grid.width / f > max_width && grid.width % (2 * f) == 0 && grid.height % (2 * f) == 0 {
        f *= 2;
    }
    let small = LatLong { width: grid.width / f, height: grid.height / f };
    let out = (0..small.width * small.height)
        .map(|k| {
            let (i, j) = (k % small.width, k / small.width);
            let mut s = [0.0; 3];
            for dj in 0..f {
                for di in 0..f {
                    let p = px[(j * f + dj) * grid.width + i * f + di];
                    for c in 0..3 {
                        s[c] += p[c];
                    }
                }
            }
            s.map(|x| x / (f * f) as f64)
        })
        .collect();
    (small, out)
}

/// Widest PNG preview; larger images are box-filtered down (the EXRs keep full size).
pub const PNG_MAX_WIDTH: usize = 256;

/// Writes a PNG preview (at most [`PNG_MAX_WIDTH`] wide): value × 2^exposure, Reinhard x/(1+x), sRGB-ish gamma 1/2.2.
/// Negative values show as 0 (the metrics report them).
pub fn write_png(path: &Path, grid: LatLong, px: &[[f64; 3]], exposure: f64) -> Result<(), String> {
    // Previews are thumbnails: grids wider than PNG_MAX_WIDTH are box-filtered by 2^k.
    if grid.width > PNG_MAX_WIDTH {
        let (small, shrunk) = box_shrink(grid, px, PNG_MAX_WIDTH);
        if small != grid {
            return write_png(path, small, &shrunk, exposure);
        }
    }
    let scale = 2f64.powf(exposure);
    let levels = gamma_thresholds();
    let img = image::RgbImage::from_fn(grid.width as u32, grid.height as u32, |x, y| {
        let p = px[y as usize * grid.width + x as usize];
        image::Rgb(p.map(|v| {
            let t = (v * scale).max(0.0);
            let r = t / (1.0 + t);
            // round(255·r^(1/2.2)) without a pow per channel: the byte whose interval holds r.
            levels.partition_point(|l| *l <= r) as u8
        }))
    });
    save_png(path, &img)
}

/// The 255 values of r at which round(255·r^(1/2.2)) steps up: ((b + ½)/255)^2.2, b = 0…254.
fn gamma_thresholds() -> &'static [f64; 255] {
    static T: std::sync::OnceLock<[f64; 255]> = std::sync::OnceLock::new();
    T.get_or_init(|| std::array::from_fn(|b| ((b as f64 + 0.5) / 255.0).powf(2.2)))
}

/// Exposure (EV) that maps the image's mean luminance to 0.18.
pub fn auto_exposure(px: &[[f64; 3]]) -> f64 {
    let mean = px.iter().map(|p| (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]).max(0.0)).sum::<f64>() / px.len().max(1) as f64;
    if mean > 0.0 {
        (0.18 / mean).log2()
    } else {
        0.0
    }
}

fn font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .unwrap_or_else(|_| panic!("DejaVu Sans is a valid font"));
    });
}

/// The chart type both plots draw on.
type LogLogChart<'a, 'b> = ChartContext<'a, BitMapBackend<'b>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

/// Draws a 1000×700 log–log chart over the bounding box of `xy` (padded by `pad`×), with
/// titled axes, lets `draw` add the data (and a legend of its labelled series if
/// `legend`), and saves it as PNG. Errors when `xy` is empty.
fn loglog_png(
    path: &Path,
    title: &str,
    labels: (&str, &str),
    x_digits: usize,
    pad: f64,
    xy: &[(f64, f64)],
    legend: bool,
    draw: impl FnOnce(&mut LogLogChart) -> Result<(), String>,
) -> Result<(), String> {
    font();
    if xy.is_empty() {
        return Err(format!("{title}: nothing to plot"));
    }
    let (w, h) = (1000u32, 700u32);
    let (x0, x1) = xy.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (y0, y1) = xy.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(20)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d((x0 / pad..x1 * pad).log_scale(), (y0 / pad..y1 * pad).log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(labels.0)
            .y_desc(labels.1)
            .x_label_formatter(&|v| if x_digits == 0 { format!("{v:.0}") } else { tick(*v) })
            .y_label_formatter(&|v| tick(*v))
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| e.to_string())?;
        draw(&mut chart)?;
        if legend {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .label_font(("sans-serif", 14))
                .draw()
                .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    save_png(path, &image::RgbImage::from_raw(w, h, buf).ok_or("bitmap size")?)
}

/// An axis label a reader can take in at a glance: plain decimals from 0.001 to 99 999
/// with three significant digits and no trailing zeros (`0.02`, `150`), otherwise
/// `2.5e-5`.
pub fn tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let e = v.abs().log10().floor() as i32;
    let trim = |s: String| if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s };
    if (-3..5).contains(&e) {
        let decimals = (2 - e).max(0) as usize;
        trim(format!("{v:.decimals$}"))
    } else {
        let m = v / 10f64.powi(e);
        format!("{}e{e}", trim(format!("{m:.2}")))
    }
}

/// The Pareto front of (cost, error) points: indices of the points no other point beats
/// on both, by increasing cost.
pub fn front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len()).collect();
    idx.sort_by(|a, b| points[*a].0.total_cmp(&points[*b].0).then(points[*a].1.total_cmp(&points[*b].1)));
    let mut out: Vec<usize> = Vec::new();
    for i in idx {
        if out.last().is_none_or(|j| points[i].1 < points[*j].1) {
            out.push(i);
        }
    }
    out
}

/// Label offsets (pixels from the point) tried in order; the first whose box overlaps no
/// placed label and no point wins.
const LABEL_OFFSETS: [(i32, i32); 10] = [(7, -16), (7, 2), (-7, -16), (-7, 2), (7, -30), (7, 16), (-7, -30), (-7, 16), (16, -7), (-16, -7)];

/// Places labels of ~7 px per character and 14 px height without overlaps; `None` where no
/// offset fits (the point is then labelled in the legend line below the plot).
pub fn place_labels(px: &[(i32, i32)], labels: &[String]) -> Vec<Option<(i32, i32)>> {
    let mut boxes: Vec<(i32, i32, i32, i32)> = px.iter().map(|p| (p.0 - 4, p.1 - 4, p.0 + 4, p.1 + 4)).collect();
    let overlaps = |a: &(i32, i32, i32, i32), b: &(i32, i32, i32, i32)| a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3;
    px.iter()
        .zip(labels)
        .map(|(p, l)| {
            let w = 7 * l.chars().count() as i32 + 2;
            LABEL_OFFSETS.iter().find_map(|&(dx, dy)| {
                let x0 = if dx < 0 { p.0 + dx - w } else { p.0 + dx };
                let b = (x0, p.1 + dy, x0 + w, p.1 + dy + 14);
                (!boxes.iter().any(|o| overlaps(o, &b))).then(|| {
                    boxes.push(b);
                    (x0 - p.0, p.1 + dy - p.1)
                })
            })
        })
        .collect()
}

fn plottable(x: f64, y: f64) -> bool {
    x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite()
}

/// A log–log scatter plot with one labelled point per mode and the Pareto front (lower
/// error at lower cost) drawn as a red staircase through its points; labels never overlap
/// (those that find no free place are listed in the caption's footnote).
pub fn scatter(path: &Path, title: &str, xlabel: &str, ylabel: &str, points: &[(String, f64, f64)]) -> Result<(), String> {
    let pts: Vec<&(String, f64, f64)> = points.iter().filter(|p| plottable(p.1, p.2)).collect();
    let xy: Vec<(f64, f64)> = pts.iter().map(|p| (p.1, p.2)).collect();
    let on_front = front(&xy);
    loglog_png(path, title, (xlabel, ylabel), 3, 1.5, &xy, false, |chart| {
        // The front as a staircase: from each front point right to the next one's cost, then down.
        let mut stair = Vec::new();
        for (k, &i) in on_front.iter().enumerate() {
            stair.push(xy[i]);
            if let Some(&j) = on_front.get(k + 1) {
                stair.push((xy[j].0, xy[i].1));
            }
        }
        chart.draw_series(LineSeries::new(stair, RED.stroke_width(2))).map_err(|e| e.to_string())?;
        let px: Vec<(i32, i32)> = xy.iter().map(|p| chart.backend_coord(p)).collect();
        let labels: Vec<String> = pts.iter().map(|p| p.0.clone()).collect();
        let placed = place_labels(&px, &labels);
        chart
            .draw_series(pts.iter().enumerate().map(|(i, p)| {
                let colour = if on_front.contains(&i) { RED } else { BLUE };
                let label = match placed[i] {
                    Some(off) => Text::new(p.0.clone(), off, ("sans-serif", 14)),
                    None => Text::new(String::new(), (0, 0), ("sans-serif", 14)),
                };
                EmptyElement::at((p.1, p.2)) + Circle::new((0, 0), 4, colour.filled()) + label
            }))
            .map_err(|e| e.to_string())?;
        let unplaced: Vec<&str> = placed.iter().zip(&labels).filter(|(p, _)| p.is_none()).map(|(_, l)| l.as_str()).collect();
        if !unplaced.is_empty() {
            let (x, y) = (chart.x_range().start, chart.y_range().start);
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at((x, y))
                        + Text::new(format!("unlabelled (crowded): {}", unplaced.join(", ")), (8, -20), ("sans-serif", 13)),
                ))
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    })
}

/// A log–log line plot, one labelled series per entry.
pub fn lines(path: &Path, title: &str, xlabel: &str, ylabel: &str, series: &[(String, Vec<(f64, f64)>)]) -> Result<(), String> {
    let clean: Vec<(&String, Vec<(f64, f64)>)> =
        series.iter().map(|(n, pts)| (n, pts.iter().copied().filter(|p| plottable(p.0, p.1)).collect())).collect();
    let xy: Vec<(f64, f64)> = clean.iter().flat_map(|s| s.1.iter().copied()).collect();
    loglog_png(path, title, (xlabel, ylabel), 0, 1.2, &xy, true, |chart| {
        for (i, (name, pts)) in clean.iter().enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            chart
                .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
                .map_err(|e| e.to_string())?
                .label(name.to_string())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
            chart.draw_series(pts.iter().map(|p| Circle::new(*p, 3, colour.filled()))).map_err(|e| e.to_string())?;
        }
        Ok(())
    })
}
