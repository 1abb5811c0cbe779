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

/// Writes a PNG preview: value × 2^exposure, Reinhard x/(1+x), sRGB-ish gamma 1/2.2.
/// Negative values show as 0 (the metrics report them).
pub fn write_png(path: &Path, grid: LatLong, px: &[[f64; 3]], exposure: f64) -> Result<(), String> {
    let scale = 2f64.powf(exposure);
    let img = image::RgbImage::from_fn(grid.width as u32, grid.height as u32, |x, y| {
        let p = px[y as usize * grid.width + x as usize];
        image::Rgb(p.map(|v| {
            let t = (v * scale).max(0.0);
            ((t / (1.0 + t)).powf(1.0 / 2.2) * 255.0).round().clamp(0.0, 255.0) as u8
        }))
    });
    img.save(path).map_err(|e| format!("writing {}: {e}", path.display()))
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

/// A log–log scatter plot with one labelled point per mode.
pub fn scatter(path: &Path, title: &str, xlabel: &str, ylabel: &str, points: &[(String, f64, f64)]) -> Result<(), String> {
    font();
    let (w, h) = (1000u32, 700u32);
    let pts: Vec<&(String, f64, f64)> = points.iter().filter(|p| p.1 > 0.0 && p.2 > 0.0 && p.1.is_finite() && p.2.is_finite()).collect();
    if pts.is_empty() {
        return Err(format!("{title}: nothing to plot"));
    }
    let (x0, x1) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let (y0, y1) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.2), b.max(p.2)));
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(20)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d((x0 / 1.5..x1 * 1.5).log_scale(), (y0 / 1.5..y1 * 1.5).log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(xlabel)
            .y_desc(ylabel)
            .x_label_formatter(&|v| format!("{v:.3e}"))
            .y_label_formatter(&|v| format!("{v:.3e}"))
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| e.to_string())?;
        chart
            .draw_series(pts.iter().map(|p| {
                EmptyElement::at((p.1, p.2)) + Circle::new((0, 0), 4, BLUE.filled()) + Text::new(p.0.clone(), (6, -6), ("sans-serif", 14))
            }))
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    image::RgbImage::from_raw(w, h, buf).ok_or("bitmap size")?.save(path).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// A log–log line plot, one labelled series per entry.
pub fn lines(path: &Path, title: &str, xlabel: &str, ylabel: &str, series: &[(String, Vec<(f64, f64)>)]) -> Result<(), String> {
    font();
    let (w, h) = (1000u32, 700u32);
    let ok = |p: &&(f64, f64)| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite();
    let all: Vec<(f64, f64)> = series.iter().flat_map(|s| s.1.iter().filter(ok).copied()).collect();
    if all.is_empty() {
        return Err(format!("{title}: nothing to plot"));
    }
    let (x0, x1) = all.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (y0, y1) = all.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(20)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d((x0 / 1.2..x1 * 1.2).log_scale(), (y0 / 1.2..y1 * 1.2).log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(xlabel)
            .y_desc(ylabel)
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.3e}"))
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| e.to_string())?;
        for (i, (name, pts)) in series.iter().enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            let pts: Vec<(f64, f64)> = pts.iter().filter(ok).copied().collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
                .map_err(|e| e.to_string())?
                .label(name.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
            chart.draw_series(pts.iter().map(|p| Circle::new(*p, 3, colour.filled()))).map_err(|e| e.to_string())?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    image::RgbImage::from_raw(w, h, buf).ok_or("bitmap size")?.save(path).map_err(|e| format!("writing {}: {e}", path.display()))
}
