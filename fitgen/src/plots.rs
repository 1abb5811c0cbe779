//! `--plots DIR`: PNG plots of each fit against its ground truth, and error heat maps
//! of the LUT approximations (plotters on a bitmap, DejaVu Sans from the `dejavu`
//! crate; saved with `image`). Not part of `luts/` and not checked.

use plotters::prelude::*;
use rayon::prelude::*;
use sbf::glam::DVec3;
use sbf::recon::ambient_dice as ad;
use std::path::Path;

const W: u32 = 900;
const H: u32 = 600;

fn font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .unwrap_or_else(|_| panic!("DejaVu Sans from the dejavu crate is a valid font"));
    });
}

fn save(buf: Vec<u8>, path: &Path) -> Result<(), String> {
    image::RgbImage::from_raw(W, H, buf).ok_or("bitmap size")?.save(path).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// A line chart of named series.
pub fn lines(path: &Path, title: &str, xlabel: &str, series: &[(&str, Vec<(f64, f64)>)]) -> Result<(), String> {
    font();
    let mut buf = vec![0u8; (W * H * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (W, H)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let pts = series.iter().flat_map(|s| s.1.iter());
        let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for (x, y) in pts {
            x0 = x0.min(*x);
            x1 = x1.max(*x);
            y0 = y0.min(*y);
            y1 = y1.max(*y);
        }
        let pad = 0.05 * (y1 - y0).max(1e-12);
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))
            .map_err(|e| e.to_string())?;
        chart.configure_mesh().x_desc(xlabel).label_style(("sans-serif", 14)).draw().map_err(|e| e.to_string())?;
        for (k, (name, s)) in series.iter().enumerate() {
            let color = Palette99::pick(k).to_rgba();
            chart
                .draw_series(LineSeries::new(s.iter().copied(), color.stroke_width(2)))
                .map_err(|e| e.to_string())?
                .label(*name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
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
    save(buf, path)
}

/// A heat map of `values[j * w + i]` over [0, 1]² with a max-normalised colour scale.
pub fn heatmap(path: &Path, title: &str, xlabel: &str, ylabel: &str, w: usize, h: usize, values: &[f64]) -> Result<(), String> {
    font();
    let vmax = values.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-30);
    let mut buf = vec![0u8; (W * H * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (W, H)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(format!("{title} (max {vmax:.2e})"), ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..1.0, 0.0..1.0)
            .map_err(|e| e.to_string())?;
        chart.configure_mesh().x_desc(xlabel).y_desc(ylabel).label_style(("sans-serif", 14)).draw().map_err(|e| e.to_string())?;
        chart
            .draw_series((0..h).flat_map(|j| (0..w).map(move |i| (i, j))).map(|(i, j)| {
                let t = values[j * w + i].abs() / vmax;
                let c = HSLColor(0.66 * (1.0 - t), 0.9, 0.5);
                Rectangle::new(
                    [(i as f64 / w as f64, j as f64 / h as f64), ((i + 1) as f64 / w as f64, (j + 1) as f64 / h as f64)],
                    c.filled(),
                )
            }))
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    save(buf, path)
}

/// Writes every plot into `dir`, returning the files written.
pub fn write_all(dir: &Path, fits: &crate::outputs::fits::Fits) -> Result<Vec<String>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("creating {}: {e}", dir.display()))?;
    let mut written = Vec::new();
    let grid: Vec<f64> = (0..=400).map(|k| -1.0 + 2.0 * k as f64 / 400.0).collect();
    // AD diffuse: exact quartic, [Roughton19 eq. 8.14], re-derived quadratic; and their errors.
    let q: [f64; 3] = fits.ad_diffuse[0].1[..3].try_into().unwrap();
    let curve = |f: &dyn Fn(f64) -> f64| grid.iter().map(|c| (*c, f(*c))).collect::<Vec<_>>();
    let p = dir.join("ad_diffuse_fit.png");
    lines(
        &p,
        "AD lobe irradiance E/π vs cos θ",
        "cos θ",
        &[
            ("exact quartic", curve(&ad::lobe_irradiance_cos)),
            ("[Roughton19 eq. 8.14]", curve(&|c| ad::lobe_irradiance_fit(&ad::DIFFUSE_FIT_EQ_8_14, c))),
            ("re-derived quadratic", curve(&|c| ad::lobe_irradiance_fit(&q, c))),
        ],
    )?;
    written.push(p.display().to_string());
    let p = dir.join("ad_diffuse_fit_error.png");
    lines(
        &p,
        "AD lobe irradiance fit error (E/π)",
        "cos θ",
        &[
            ("[Roughton19 eq. 8.14]", curve(&|c| ad::lobe_irradiance_fit(&ad::DIFFUSE_FIT_EQ_8_14, c) - ad::lobe_irradiance_cos(c))),
            ("re-derived quadratic", curve(&|c| ad::lobe_irradiance_fit(&q, c) - ad::lobe_irradiance_cos(c))),
        ],
    )?;
    written.push(p.display().to_string());
    // DFG error heat map: |1024-sample entry − 16384-sample entry|, 32×32.
    let cells: Vec<(usize, usize)> = (0..32).flat_map(|j| (0..32).map(move |i| (i, j))).collect();
    let dfg_err: Vec<f64> = cells
        .par_iter()
        .map(|&(i, j)| {
            let (nv, a) = ((i as f64 + 0.5) / 32.0, (j as f64 + 0.5) / 32.0);
            let (x, y) = (sbf::ggx::dfg_entry(nv, a, 1024), sbf::ggx::dfg_entry(nv, a, 16384));
            ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2)).sqrt()
        })
        .collect();
    let p = dir.join("dfg_error.png");
    heatmap(&p, "DFG Monte-Carlo error (1024 vs 16384 samples)", "n·v", "α", 32, 32, &dfg_err)?;
    written.push(p.display().to_string());
    // AD specular 2D LUT error: RMS over 48 lobe axes of fit·LUT − ground truth, 16×16.
    let lut = sbf::recon::tables::ad_specular_2d();
    let lobes: Vec<DVec3> = (0..48).map(|i| sbf::sampling::spherical_fibonacci(i, 48)).collect();
    let cells: Vec<(usize, usize)> = (0..16).flat_map(|j| (0..16).map(move |i| (i, j))).collect();
    let ad_err: Vec<f64> = cells
        .par_iter()
        .map(|&(i, j)| {
            let (nv, a) = ((i as f64 + 0.5) / 16.0, (j as f64 + 0.5) / 16.0);
            let v = DVec3::new(0.0, (1.0 - nv * nv).sqrt(), nv);
            let l = lut.sample2(nv as f32, a as f32);
            let fit = ad::SpecularFit::new(&ad::SPECULAR_FIT_LISTING_8_1, &ad::DIFFUSE_FIT_LISTING_8_1, DVec3::Z, v, a);
            let ss: f64 = lobes
                .iter()
                .map(|lobe| {
                    let gt = ad::lobe_specular_reference(*lobe, nv, a, 1024);
                    let f = fit.lobe(*lobe);
                    (f * l[0] as f64 - gt[0]).powi(2) + (f * l[1] as f64 - gt[1]).powi(2)
                })
                .sum();
            (ss / 96.0).sqrt()
        })
        .collect();
    let p = dir.join("ad_specular_2d_error.png");
    heatmap(&p, "AD specular fit × 2D LUT, RMS error over lobes", "n·v", "α", 16, 16, &ad_err)?;
    written.push(p.display().to_string());
    Ok(written)
}
