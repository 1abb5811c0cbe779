//! The interactive view in report.html: per map, a rotatable sphere of
//! the reference and of a chosen mode side by side, for every signal (radiance,
//! irradiance, GGX specular per α) and the error against the reference — offline, no
//! network, no WebGL (a canvas 2D renderer, so it works in any browser and headless).
//!
//! Data: every image box-filtered to at most [`VIEW_WIDTH`] × [`VIEW_WIDTH`]/2 and stored
//! as RGBE (shared exponent, 4 bytes per texel; relative precision 2⁻⁸) in base64, inline in
//! the page (a page opened from disk cannot fetch files). The sphere shows f(n) at each
//! visible normal n, rotated by the drag; lat-long lookup and tone mapping (Reinhard,
//! gamma 2.2, exposure from the reference per signal) as in the PNG previews.

use crate::outcome::MapReport;
use sbf::envmap::LatLong;
use std::fmt::Write;

/// Largest width of the embedded images.
pub const VIEW_WIDTH: usize = 64;

/// RGBE (Ward 1991): mantissas m_c = ⌊v_c·256/2^e⌋ with 2^(e−1) ≤ max_c v_c < 2^e, byte 4 = e + 128;
/// negative and non-finite values stored as 0.
fn rgbe(px: &[[f64; 3]]) -> Vec<u8> {
    let mut out = Vec::with_capacity(4 * px.len());
    for p in px {
        let p = p.map(|v| if v.is_finite() && v > 0.0 { v } else { 0.0 });
        let m = p[0].max(p[1]).max(p[2]);
        if m < 1e-32 {
            out.extend([0, 0, 0, 0]);
            continue;
        }
        let e = m.log2().floor() as i32 + 1;
        let s = 256.0 / 2f64.powi(e);
        out.extend([(p[0] * s).min(255.0) as u8, (p[1] * s).min(255.0) as u8, (p[2] * s).min(255.0) as u8, (e + 128).clamp(0, 255) as u8]);
    }
    out
}

fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

fn image_js(grid: LatLong, px: &[[f64; 3]]) -> String {
    let (g, small) = crate::images::box_shrink(grid, px, VIEW_WIDTH);
    let (w, h) = (g.width, g.height);
    format!("{{\"w\":{w},\"h\":{h},\"d\":\"{}\"}}", base64(&rgbe(&small)))
}

fn js_str(s: &str) -> String {
    serde_json::to_string(s).expect("a string serialises")
}

/// The mode each signal of one map opens on (the decision's recommendation): irradiance
/// (also used for radiance) and per specular α.
#[derive(Debug, Clone, Default)]
pub struct Recommended {
    pub irradiance: Option<String>,
    pub specular: Vec<(f64, String)>,
}

/// The data of one map: signals, each with its exposure, the reference, every mode and the
/// mode it opens on.
fn map_js(m: &MapReport, index: usize, rec: &Recommended) -> String {
    let mut signals: Vec<String> = Vec::new();
    let mut push = |name: String, rec: Option<&String>, reference: &[[f64; 3]], modes: Vec<(&str, &[[f64; 3]])>| {
        let ev = crate::images::auto_exposure(reference);
        let rec = rec.map_or("null".to_string(), |id| js_str(id));
        let mut s = format!("{{\"name\":{},\"rec\":{rec},\"ev\":{ev},\"ref\":{},\"modes\":{{", js_str(&name), image_js(m.grid, reference));
        for (k, (id, img)) in modes.iter().enumerate() {
            let _ = write!(s, "{}{}:{}", if k > 0 { "," } else { "" }, js_str(id), image_js(m.grid, img));
        }
        s.push_str("}}");
        signals.push(s);
    };
    push(
        "radiance".into(),
        rec.irradiance.as_ref(),
        &m.radiance,
        m.rows.iter().filter_map(|r| Some((r.result.id, r.result.radiance.as_deref()?))).collect(),
    );
    push(
        "irradiance (E/π)".into(),
        rec.irradiance.as_ref(),
        &m.reference,
        m.rows.iter().map(|r| (r.result.id, r.result.irradiance.as_slice())).collect(),
    );
    for sr in &m.specular_reference {
        let modes = m
            .rows
            .iter()
            .filter_map(|r| {
                let i = r.specular.iter().position(|(a, _)| *a == sr.alpha)?;
                Some((r.result.id, r.specular_images[i].as_slice()))
            })
            .collect();
        let r = rec.specular.iter().find(|(a, _)| *a == sr.alpha).map(|(_, id)| id);
        push(format!("GGX specular α = {}", sr.alpha), r, &sr.image, modes);
    }
    format!("{{\"index\":{index},\"name\":{},\"signals\":[{}]}}", js_str(&m.path), signals.join(","))
}

/// The `<section>` of one map (two canvases and the controls).
pub fn section(index: usize) -> String {
    format!(
        "<section class=\"viewer\" data-map=\"{index}\"><h3>Interactive view</h3><p>Drag to rotate. Left: reference; right: the mode (or its error against the reference, at 4 EV more).</p>\
<p><label>signal <select class=\"sig\"></select></label> <label>mode <select class=\"mode\"></select></label> <label><input type=\"checkbox\" class=\"err\"> error</label></p>\
<canvas class=\"ref\" width=\"240\" height=\"240\"></canvas> <canvas class=\"cmp\" width=\"240\" height=\"240\"></canvas></section>"
    )
}

/// The script with every map's data and the renderer; `recommended[i]` is map i's (missing:
/// the first mode).
pub fn script(maps: &[MapReport], recommended: &[Recommended]) -> String {
    let none = Recommended::default();
    let data: Vec<String> = maps.iter().enumerate().map(|(i, m)| map_js(m, i, recommended.get(i).unwrap_or(&none))).collect();
    format!("<script>\nconst PROBES_DATA = [{}];\n{}</script>", data.join(",\n"), RENDERER)
}

/// Decoding, lookup, tone mapping and the controls; reports problems in the page itself
/// (`data-errors`) and how many lit pixels it drew (`data-nonblank`), which the browser
/// test reads.
const RENDERER: &str = r#"
(function () {
  const errors = [];
  const note = () => { document.body.dataset.errors = String(errors.length); if (errors.length) document.body.dataset.errorText = errors.join(' | '); };
  window.addEventListener('error', e => { errors.push(String(e.message)); note(); });
  const origError = console.error;
  console.error = function (...a) { errors.push(a.join(' ')); note(); origError.apply(console, a); };
  function decode(img) {
    if (img.f) return img.f;
    const b = atob(img.d), n = img.w * img.h, f = new Float32Array(3 * n);
    for (let k = 0; k < n; k++) {
      const e = b.charCodeAt(4 * k + 3);
      if (e === 0) continue;
      const s = Math.pow(2, e - 128) / 256;
      for (let c = 0; c < 3; c++) f[3 * k + c] = (b.charCodeAt(4 * k + c) + 0.5) * s;
    }
    img.f = f;
    return f;
  }
  function sample(f, w, h, d) {
    // sbf::envmap::LatLong::direction_to_uv, then bilinear with wrap in u, clamp in v.
    let u = 0.5 * (1 + Math.atan2(d[0], -d[2]) / Math.PI);
    const v = Math.acos(Math.max(-1, Math.min(1, d[1]))) / Math.PI;
    const x = u * w - 0.5, y = Math.max(0, Math.min(h - 1, v * h - 0.5));
    const x0 = Math.floor(x), y0 = Math.floor(y), fx = x - x0, fy = y - y0;
    const y1 = Math.min(h - 1, y0 + 1);
    const out = [0, 0, 0];
    for (const [xx, wx] of [[x0, 1 - fx], [x0 + 1, fx]]) {
      const i = ((xx % w) + w) % w;
      for (const [yy, wy] of [[y0, 1 - fy], [y1, fy]]) {
        const k = 3 * (yy * w + i);
        for (let c = 0; c < 3; c++) out[c] += wx * wy * f[k + c];
      }
    }
    return out;
  }
  function draw(canvas, img, ref, ev, rot) {
    const ctx = canvas.getContext('2d'), W = canvas.width, H = canvas.height;
    const id = ctx.createImageData(W, H), p = id.data;
    const f = decode(img), g = ref ? decode(ref) : null, scale = Math.pow(2, ev);
    let lit = 0;
    const [cy, sy, cp, sp] = [Math.cos(rot.yaw), Math.sin(rot.yaw), Math.cos(rot.pitch), Math.sin(rot.pitch)];
    for (let py = 0; py < H; py++) for (let px = 0; px < W; px++) {
      const x = (2 * (px + 0.5) / W - 1), y = -(2 * (py + 0.5) / H - 1), r2 = x * x + y * y;
      const o = 4 * (py * W + px);
      if (r2 > 1) { p[o] = p[o + 1] = p[o + 2] = 255; p[o + 3] = 255; continue; }
      const z = Math.sqrt(1 - r2);
      // Pitch about x, then yaw about the world's up (+Y).
      const y1 = cp * y - sp * z, z1 = sp * y + cp * z;
      const d = [cy * x + sy * z1, y1, -sy * x + cy * z1];
      let c = sample(f, img.w, img.h, d);
      if (g) { const q = sample(g, ref.w, ref.h, d); c = c.map((v, i) => Math.abs(v - q[i])); }
      for (let i = 0; i < 3; i++) {
        const t = Math.max(0, c[i] * scale), b = Math.round(255 * Math.pow(t / (1 + t), 1 / 2.2));
        p[o + i] = Math.max(0, Math.min(255, b));
        if (p[o + i] > 0) lit++;
      }
      p[o + 3] = 255;
    }
    ctx.putImageData(id, 0, 0);
    return lit;
  }
  let total = 0;
  for (const sec of document.querySelectorAll('section.viewer')) {
    const m = PROBES_DATA[Number(sec.dataset.map)];
    const sig = sec.querySelector('select.sig'), mode = sec.querySelector('select.mode'), err = sec.querySelector('input.err');
    const cref = sec.querySelector('canvas.ref'), ccmp = sec.querySelector('canvas.cmp');
    const rot = { yaw: 0.6, pitch: 0.35 };
    m.signals.forEach((s, i) => sig.add(new Option(s.name, i)));
    function fillModes() {
      const keep = mode.value;
      mode.innerHTML = '';
      for (const id of Object.keys(m.signals[sig.value].modes)) mode.add(new Option(id, id));
      const rec = m.signals[sig.value].rec;
      if ([...mode.options].some(o => o.value === keep)) mode.value = keep;
      else if (rec !== null && [...mode.options].some(o => o.value === rec)) mode.value = rec;
    }
    function render() {
      const s = m.signals[sig.value], img = s.modes[mode.value];
      let lit = draw(cref, s.ref, null, s.ev, rot);
      if (img) lit += err.checked ? draw(ccmp, img, s.ref, s.ev + 4, rot) : draw(ccmp, img, null, s.ev, rot);
      return lit;
    }
    sig.addEventListener('change', () => { fillModes(); render(); });
    mode.addEventListener('change', render);
    err.addEventListener('change', render);
    let drag = null;
    for (const c of [cref, ccmp]) {
      c.addEventListener('pointerdown', e => { drag = [e.clientX, e.clientY]; c.setPointerCapture(e.pointerId); });
      c.addEventListener('pointermove', e => {
        if (!drag) return;
        rot.yaw += 0.01 * (e.clientX - drag[0]);
        rot.pitch = Math.max(-1.5, Math.min(1.5, rot.pitch + 0.01 * (e.clientY - drag[1])));
        drag = [e.clientX, e.clientY];
        render();
      });
      c.addEventListener('pointerup', () => { drag = null; });
    }
    sig.value = m.signals.length > 1 ? 1 : 0;
    fillModes();
    total += render();
  }
  document.body.dataset.nonblank = String(total);
  // What the browser test checks: the page's width and the mode the first view opened on.
  document.body.dataset.scrollWidth = String(document.documentElement.scrollWidth);
  const first = document.querySelector('section.viewer select.mode');
  if (first) document.body.dataset.openMode = first.value;
  // #selftest: render every signal × mode × (value, error) once and count the renders
  // that drew nothing although the image holds light (the browser test reads this).
  if (location.hash === '#selftest') {
    let renders = 0, blank = 0;
    for (const sec of document.querySelectorAll('section.viewer')) {
      const m = PROBES_DATA[Number(sec.dataset.map)];
      const sig = sec.querySelector('select.sig'), mode = sec.querySelector('select.mode'), err = sec.querySelector('input.err');
      for (let i = 0; i < m.signals.length; i++) {
        sig.value = i; sig.dispatchEvent(new Event('change'));
        for (const id of Object.keys(m.signals[i].modes)) {
          for (const e of [false, true]) {
            mode.value = id; err.checked = e; mode.dispatchEvent(new Event('change'));
            const c = sec.querySelector('canvas.cmp'), d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
            let lit = 0;
            for (let k = 0; k < d.length; k += 4) if ((d[k] || d[k + 1] || d[k + 2]) && !(d[k] === 255 && d[k + 1] === 255 && d[k + 2] === 255)) lit++;
            renders++;
            if (!e && lit === 0 && decode(m.signals[i].modes[id]).some(v => v > 0)) blank++;
          }
        }
      }
    }
    document.body.dataset.selftestRenders = String(renders);
    document.body.dataset.selftestBlank = String(blank);
  }
  note();
})();
"#;
