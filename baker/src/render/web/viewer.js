// viewer.js — the bake viewer (written by `render --web DIR`; no dependencies). Loads the
// folder's scene.json and binaries, shades the scene with the exported runtime library —
// WebGL 2: sbf.es.glsl + viewer.es.glsl; WebGPU: viewer.wgsl (the library's WGSL export +
// render.wgsl) + display.wgsl — and shows it with the reference beside it.
//
// Test mode (`?test=1&apis=webgl2,webgpu&configs=sh2,ad9,sh2:bicubic`): at the reference camera, the
// total term, exposure ±0 EV, no split, bilinear filter, each API × configuration is drawn
// and its canvas (RGBA8, rows from the top) POSTed to /__capture?api=…&config=…; then a JSON
// report (errors, the APIs' adapters, the first frame's time) to /__report. Only the test's
// local server answers these; the viewer itself makes no request outside its folder.

const errors = [];
window.addEventListener('error', (e) => errors.push(`error: ${e.message} (${e.filename}:${e.lineno})`));
window.addEventListener('unhandledrejection', (e) => errors.push(`unhandled rejection: ${e.reason}`));
const consoleError = console.error.bind(console);
console.error = (...a) => {
  errors.push(`console.error: ${a.join(' ')}`);
  consoleError(...a);
};

const params = new URLSearchParams(location.search);
const $ = (id) => document.getElementById(id);

async function fetchOk(url, kind) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${url}: HTTP ${r.status}`);
  return kind === 'json' ? r.json() : kind === 'text' ? r.text() : r.arrayBuffer();
}

// ---- camera: the renderer's ViewCamera (right-handed look-at, depth in [0, 1]) ----
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const mul = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm = (a) => mul(a, 1 / Math.hypot(a[0], a[1], a[2]));

// World → clip, column-major (baker::scene::camera::ViewCamera::view_proj without jitter).
function viewProj(cam, aspect) {
  const f = norm(sub(cam.target, cam.eye));
  const r = norm(cross(f, cam.up));
  const u = cross(r, f);
  const h = 1 / Math.tan(0.5 * cam.fov);
  const depth = cam.far / (cam.near - cam.far);
  const view = [r[0], u[0], -f[0], 0, r[1], u[1], -f[1], 0, r[2], u[2], -f[2], 0, -dot(r, cam.eye), -dot(u, cam.eye), dot(f, cam.eye), 1];
  const proj = [h / aspect, 0, 0, 0, 0, h, 0, 0, 0, 0, depth, -1, 0, 0, depth * cam.near, 0];
  const out = new Array(16).fill(0);
  for (let c = 0; c < 4; c++) for (let rr = 0; rr < 4; rr++) for (let k = 0; k < 4; k++) out[c * 4 + rr] += proj[k * 4 + rr] * view[c * 4 + k];
  return out;
}

function halfToFloat(h) {
  const s = h & 0x8000 ? -1 : 1;
  const e = (h >> 10) & 0x1f;
  const m = h & 0x3ff;
  if (e === 0) return s * m * 2 ** -24;
  if (e === 31) return m ? NaN : s * Infinity;
  return s * (1 + m / 1024) * 2 ** (e - 15);
}

// RGB f16 → RGBA f16 (WebGPU has no rgb16float).
function rgbToRgbaHalf(u16) {
  const n = u16.length / 3;
  const out = new Uint16Array(n * 4);
  for (let i = 0; i < n; i++) {
    out[4 * i] = u16[3 * i];
    out[4 * i + 1] = u16[3 * i + 1];
    out[4 * i + 2] = u16[3 * i + 2];
    out[4 * i + 3] = 0x3c00;
  }
  return out;
}

// ---- WebGL 2 ----
function sections(src) {
  const out = {};
  let name = null;
  for (const line of src.split('\n')) {
    const m = line.match(/^\/\/--- (\S+)/);
    if (m) {
      name = m[1];
      out[name] = '';
    } else if (name) out[name] += line + '\n';
  }
  return out;
}

class WebGl2 {
  constructor(canvas, data) {
    const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true, alpha: false });
    if (!gl) throw new Error('no WebGL 2 context');
    if (!gl.getExtension('EXT_color_buffer_float')) throw new Error('WebGL 2 without EXT_color_buffer_float (float render targets)');
    this.gl = gl;
    this.data = data;
    const dbg = gl.getExtension('WEBGL_debug_renderer_info');
    this.adapter = dbg ? gl.getParameter(dbg.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
    const [aw, ah] = data.scene.atlas;
    const most = gl.getParameter(gl.MAX_TEXTURE_SIZE);
    if (aw > most || ah > most) throw new Error(`the atlas (${aw}×${ah}) exceeds this WebGL 2's ${most} texels a side: write the viewer with render --web-max-texture ${most}`);
    this.src = sections(data.glsl);
    this.programs = new Map();
    const { width: w, height: h } = data.scene.camera;
    this.width = w;
    this.height = h;
    this.vao = gl.createVertexArray();
    gl.bindVertexArray(this.vao);
    const vb = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, vb);
    gl.bufferData(gl.ARRAY_BUFFER, data.mesh, gl.STATIC_DRAW);
    const f = (loc, n, off) => {
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, n, gl.FLOAT, false, 48, off);
    };
    f(0, 3, 0);
    f(1, 3, 12);
    f(2, 2, 24);
    gl.enableVertexAttribArray(3);
    gl.vertexAttribIPointer(3, 1, gl.UNSIGNED_INT, 48, 32);
    f(4, 3, 36);
    gl.bindVertexArray(null);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    const tex2d = (internal, format, type, tw, th, pixels, filter) => {
      const t = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D, t);
      gl.texImage2D(gl.TEXTURE_2D, 0, internal, tw, th, 0, format, type, pixels);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, filter);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, filter);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
      return t;
    };
    const s = data.scene;
    this.luts = {
      dfg: tex2d(gl.RG32F, gl.RG, gl.FLOAT, s.luts.dfg[0], s.luts.dfg[1], new Float32Array(data.luts.dfg), gl.NEAREST),
      ad: tex2d(gl.RG32F, gl.RG, gl.FLOAT, s.luts.ad[0], s.luts.ad[1], new Float32Array(data.luts.ad), gl.NEAREST),
    };
    this.materials = tex2d(gl.RGBA32F, gl.RGBA, gl.FLOAT, 2 * s.materials, 1, new Float32Array(data.materials), gl.NEAREST);
    // The probes: nine RGBA32F texels each, `perRow` probes a row (a grid of more probes than
    // the texture's height fits stays within its limits).
    const count = Math.max(1, Math.floor(data.probes.byteLength / 144));
    this.probesPerRow = Math.max(1, Math.min(count, Math.floor(most / 9)));
    const rows = Math.ceil(count / this.probesPerRow);
    if (rows > most) throw new Error(`${count} probes exceed this WebGL 2's textures (${most} texels a side)`);
    const probeTexels = new Float32Array(this.probesPerRow * 9 * rows * 4);
    probeTexels.set(new Float32Array(data.probes).subarray(0, Math.min(data.probes.byteLength / 4, probeTexels.length)));
    this.probes = tex2d(gl.RGBA32F, gl.RGBA, gl.FLOAT, this.probesPerRow * 9, rows, probeTexels, gl.NEAREST);
    this.reference = data.reference
      ? tex2d(gl.RGB16F, gl.RGB, gl.HALF_FLOAT, w, 2 * h, new Uint16Array(data.reference), gl.NEAREST)
      : tex2d(gl.RGB16F, gl.RGB, gl.HALF_FLOAT, 1, 1, new Uint16Array(3), gl.NEAREST);
    this.lightmaps = new Map();
    // The shaded targets: diffuse and specular (f32), depth.
    this.fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.fb);
    this.targets = [0, 1].map((k) => {
      const t = tex2d(gl.RGBA32F, gl.RGBA, gl.FLOAT, w, h, null, gl.NEAREST);
      gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0 + k, gl.TEXTURE_2D, t, 0);
      return t;
    });
    const depth = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT32F, w, h);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
    gl.drawBuffers([gl.COLOR_ATTACHMENT0, gl.COLOR_ATTACHMENT1]);
    const status = gl.checkFramebufferStatus(gl.FRAMEBUFFER);
    if (status !== gl.FRAMEBUFFER_COMPLETE) throw new Error(`float framebuffer incomplete (0x${status.toString(16)})`);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    this.display = this.program('display', '#version 300 es\nprecision highp float;\nprecision highp int;\nvoid main() { vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)); gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0); }\n', this.header() + this.src.display);
  }

  header(defines = '') {
    return `#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2DArray;\n${defines}`;
  }

  program(key, vs, fs) {
    const gl = this.gl;
    const compile = (type, text, what) => {
      const sh = gl.createShader(type);
      gl.shaderSource(sh, text);
      gl.compileShader(sh);
      if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) throw new Error(`${key} ${what} shader: ${gl.getShaderInfoLog(sh)}`);
      return sh;
    };
    const p = gl.createProgram();
    gl.attachShader(p, compile(gl.VERTEX_SHADER, vs, 'vertex'));
    gl.attachShader(p, compile(gl.FRAGMENT_SHADER, fs, 'fragment'));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(`${key}: link: ${gl.getProgramInfoLog(p)}`);
    return p;
  }

  shading(conf, bicubic) {
    const key = `${conf.name}/${bicubic}`;
    if (!this.programs.has(key)) {
      const defines = `#define ENCODING ${conf.encoding}\n#define LOBES ${conf.lobes}\n#define BICUBIC ${bicubic ? 1 : 0}\n`;
      this.programs.set(key, this.program(key, this.header() + this.src.vertex, this.header(defines) + this.data.library + this.src.fragment));
    }
    return this.programs.get(key);
  }

  lightmap(conf) {
    const gl = this.gl;
    if (!this.lightmaps.has(conf.name)) {
      const [w, h] = this.data.scene.atlas;
      const t = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, t);
      gl.texImage3D(gl.TEXTURE_2D_ARRAY, 0, gl.RGB16F, w, h, conf.lobes, 0, gl.RGB, gl.HALF_FLOAT, new Uint16Array(this.data.lightmaps[conf.name]));
      gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
      gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
      gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
      gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
      this.lightmaps.set(conf.name, t);
    }
    return this.lightmaps.get(conf.name);
  }

  draw(view) {
    const gl = this.gl;
    const s = this.data.scene;
    const conf = view.conf;
    const p = this.shading(conf, view.bicubic);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.fb);
    gl.viewport(0, 0, this.width, this.height);
    gl.clearBufferfv(gl.COLOR, 0, [0, 0, 0, -1]);
    gl.clearBufferfv(gl.COLOR, 1, [0, 0, 0, 0]);
    gl.clearBufferfv(gl.DEPTH, 0, [1]);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LESS);
    gl.useProgram(p);
    const u = (n) => gl.getUniformLocation(p, n);
    gl.uniformMatrix4fv(u('view_proj'), false, view.viewProj);
    gl.uniform4f(u('eye'), view.eye[0], view.eye[1], view.eye[2], conf.sg_sharpness);
    gl.uniform2ui(u('atlas'), s.atlas[0], s.atlas[1]);
    const axes = new Float32Array(48);
    conf.axes.forEach((a, k) => axes.set([a[0], a[1], a[2], 0], 4 * k));
    gl.uniform4fv(u('axes'), axes);
    gl.uniform4ui(u('grid_dims'), ...s.probes.dims);
    gl.uniform4fv(u('grid_first'), s.probes.first);
    gl.uniform4fv(u('grid_last'), s.probes.last);
    gl.uniform1i(u('probes_per_row'), this.probesPerRow);
    const bind = (unit, target, tex, name) => {
      gl.activeTexture(gl.TEXTURE0 + unit);
      gl.bindTexture(target, tex);
      gl.uniform1i(u(name), unit);
    };
    bind(0, gl.TEXTURE_2D_ARRAY, this.lightmap(conf), 'lightmap');
    bind(1, gl.TEXTURE_2D, conf.lut === 'ad' ? this.luts.ad : this.luts.dfg, 'lut');
    bind(2, gl.TEXTURE_2D, this.luts.dfg, 'dfg');
    bind(3, gl.TEXTURE_2D, this.materials, 'materials');
    bind(4, gl.TEXTURE_2D, this.probes, 'probes');
    gl.bindVertexArray(this.vao);
    gl.drawArrays(gl.TRIANGLES, 0, s.vertices);
    gl.bindVertexArray(null);
    gl.disable(gl.DEPTH_TEST);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, this.width, this.height);
    gl.useProgram(this.display);
    const d = (n) => gl.getUniformLocation(this.display, n);
    [this.targets[0], this.targets[1], this.reference].forEach((t, k) => {
      gl.activeTexture(gl.TEXTURE0 + k);
      gl.bindTexture(gl.TEXTURE_2D, t);
    });
    gl.uniform1i(d('shaded_diffuse'), 0);
    gl.uniform1i(d('shaded_specular'), 1);
    gl.uniform1i(d('reference'), 2);
    gl.uniform1f(d('exposure'), view.exposure);
    gl.uniform1i(d('term'), view.term);
    gl.uniform1f(d('split'), view.split);
    gl.uniform1i(d('has_reference'), this.data.reference ? 1 : 0);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }

  // `view` drawn, the canvas as RGBA8, rows from the top.
  async capture(view) {
    this.draw(view);
    const gl = this.gl;
    const { width: w, height: h } = this;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    const out = new Uint8Array(w * h * 4);
    for (let y = 0; y < h; y++) out.set(px.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
    return out;
  }
}

// ---- WebGPU ----
class WebGpu {
  static async create(canvas, data) {
    if (!navigator.gpu) throw new Error('this browser has no WebGPU (navigator.gpu)');
    const adapter = await navigator.gpu.requestAdapter();
    if (!adapter) throw new Error('WebGPU: no adapter');
    const device = await adapter.requestDevice();
    const g = new WebGpu();
    await g.init(canvas, data, adapter, device);
    return g;
  }

  async init(canvas, data, adapter, device) {
    this.device = device;
    this.data = data;
    const [aw, ah] = data.scene.atlas;
    const most = device.limits.maxTextureDimension2D;
    if (aw > most || ah > most) throw new Error(`the atlas (${aw}×${ah}) exceeds this WebGPU device's ${most} texels a side: write the viewer with render --web-max-texture ${most}`);
    const info = adapter.info || {};
    this.adapter = `${info.vendor || '?'} ${info.architecture || ''} ${info.description || ''}`.trim();
    device.addEventListener('uncapturederror', (e) => errors.push(`WebGPU: ${e.error.message}`));
    const s = data.scene;
    const { width: w, height: h } = s.camera;
    this.width = w;
    this.height = h;
    this.ctx = canvas.getContext('webgpu');
    this.format = navigator.gpu.getPreferredCanvasFormat();
    this.ctx.configure({ device, format: this.format, alphaMode: 'opaque' });
    const module = async (code, label) => {
      const m = device.createShaderModule({ code, label });
      const ci = await m.getCompilationInfo();
      const bad = ci.messages.filter((x) => x.type === 'error');
      if (bad.length) throw new Error(`${label}: ${bad.map((x) => `${x.lineNum}:${x.linePos} ${x.message}`).join('; ')}`);
      return m;
    };
    this.render = await module(data.wgsl, 'viewer.wgsl');
    this.displayModule = await module(data.displayWgsl, 'display.wgsl');
    const buffer = (bytes, usage) => {
      const b = device.createBuffer({ size: Math.max(16, Math.ceil(bytes.byteLength / 4) * 4), usage: usage | GPUBufferUsage.COPY_DST });
      device.queue.writeBuffer(b, 0, bytes);
      return b;
    };
    this.vertices = buffer(data.mesh, GPUBufferUsage.VERTEX);
    this.materials = buffer(data.materials, GPUBufferUsage.STORAGE);
    this.probes = buffer(data.probes, GPUBufferUsage.STORAGE);
    this.frame = device.createBuffer({ size: 336, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
    this.displayUniform = device.createBuffer({ size: 16, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
    const texture = (format, size, bytes, bpr, dim = '2d', usage = GPUTextureUsage.TEXTURE_BINDING) => {
      const t = device.createTexture({ format, size, dimension: dim, usage: usage | GPUTextureUsage.COPY_DST });
      if (bytes) device.queue.writeTexture({ texture: t }, bytes, { bytesPerRow: bpr, rowsPerImage: size[1] }, size);
      return t;
    };
    this.luts = {
      dfg: texture('rg32float', [s.luts.dfg[0], s.luts.dfg[1]], data.luts.dfg, s.luts.dfg[0] * 8),
      ad: texture('rg32float', [s.luts.ad[0], s.luts.ad[1]], data.luts.ad, s.luts.ad[0] * 8),
    };
    this.lobeTable = texture('rgba16float', [1, 1, 1], new Uint16Array(4), 8, '3d');
    this.reference = data.reference
      ? texture('rgba16float', [w, 2 * h], rgbToRgbaHalf(new Uint16Array(data.reference)), w * 8)
      : texture('rgba16float', [1, 1], new Uint16Array(4), 8);
    const att = GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.TEXTURE_BINDING;
    this.targets = [0, 1].map(() => texture('rgba32uint', [w, h], null, 0, '2d', att));
    this.depth = device.createTexture({ format: 'depth32float', size: [w, h], usage: GPUTextureUsage.RENDER_ATTACHMENT });
    this.sampler = device.createSampler({ magFilter: 'linear', minFilter: 'linear', addressModeU: 'clamp-to-edge', addressModeV: 'clamp-to-edge' });
    const V = GPUShaderStage.VERTEX | GPUShaderStage.FRAGMENT;
    // render.wgsl's bindings (baker::render::bindings::layouts, the lightmap sampled).
    this.layout = device.createBindGroupLayout({
      entries: [
        { binding: 0, visibility: V, buffer: { type: 'uniform' } },
        { binding: 1, visibility: V, buffer: { type: 'read-only-storage' } },
        { binding: 2, visibility: V, texture: { sampleType: 'float', viewDimension: '2d-array' } },
        { binding: 3, visibility: V, texture: { sampleType: 'unfilterable-float' } },
        { binding: 4, visibility: V, texture: { sampleType: 'float', viewDimension: '3d' } },
        { binding: 5, visibility: V, buffer: { type: 'read-only-storage' } },
        { binding: 6, visibility: V, texture: { sampleType: 'unfilterable-float' } },
        { binding: 7, visibility: V, sampler: { type: 'filtering' } },
        { binding: 8, visibility: V, sampler: { type: 'filtering' } },
      ],
    });
    // The display pass to the canvas' format, and to rgba8unorm for a capture (a canvas'
    // texture cannot be read back on every browser: headless Chromium's never maps).
    const display = (format) =>
      device.createRenderPipeline({
        layout: 'auto',
        vertex: { module: this.displayModule, entryPoint: 'vs_display' },
        fragment: { module: this.displayModule, entryPoint: 'fs_display', targets: [{ format }] },
        primitive: { topology: 'triangle-list' },
      });
    this.displayPipelines = { canvas: display(this.format), capture: display('rgba8unorm') };
    this.displayGroups = {};
    for (const [k, p] of Object.entries(this.displayPipelines)) {
      this.displayGroups[k] = device.createBindGroup({
        layout: p.getBindGroupLayout(0),
        entries: [
          { binding: 0, resource: { buffer: this.displayUniform } },
          { binding: 1, resource: this.targets[0].createView() },
          { binding: 2, resource: this.targets[1].createView() },
          { binding: 3, resource: this.reference.createView() },
        ],
      });
    }
    this.captureTarget = texture('rgba8unorm', [w, h], null, 0, '2d', GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_SRC);
    this.pipelines = new Map();
    this.lightmaps = new Map();
  }

  pipeline(conf, bicubic) {
    const key = `${conf.name}/${bicubic}`;
    if (!this.pipelines.has(key)) {
      const constants = { ENCODING: conf.encoding, TABLES: 0, LOBES: conf.lobes, HW_FILTER: 0, BICUBIC: bicubic ? 1 : 0, FETCH_ONLY: 0 };
      const f = (format, offset, shaderLocation) => ({ format, offset, shaderLocation });
      this.pipelines.set(
        key,
        this.device.createRenderPipeline({
          layout: this.device.createPipelineLayout({ bindGroupLayouts: [this.layout] }),
          vertex: {
            module: this.render,
            entryPoint: 'vs_main',
            buffers: [{ arrayStride: 48, attributes: [f('float32x3', 0, 0), f('float32x3', 12, 1), f('float32x2', 24, 2), f('uint32', 32, 3), f('float32x3', 36, 4)] }],
          },
          fragment: { module: this.render, entryPoint: 'fs_terms', constants, targets: [{ format: 'rgba32uint' }, { format: 'rgba32uint' }] },
          primitive: { topology: 'triangle-list' },
          depthStencil: { format: 'depth32float', depthWriteEnabled: true, depthCompare: 'less' },
        }),
      );
    }
    return this.pipelines.get(key);
  }

  lightmap(conf) {
    if (!this.lightmaps.has(conf.name)) {
      const [w, h] = this.data.scene.atlas;
      const t = this.device.createTexture({ format: 'rgba16float', size: [w, h, conf.lobes], usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST });
      this.device.queue.writeTexture({ texture: t }, rgbToRgbaHalf(new Uint16Array(this.data.lightmaps[conf.name])), { bytesPerRow: w * 8, rowsPerImage: h }, [w, h, conf.lobes]);
      this.lightmaps.set(conf.name, t);
    }
    return this.lightmaps.get(conf.name);
  }

  // `readback`: draw the display pass into the capture target instead of the canvas and
  // copy it into this buffer.
  draw(view, readback = null) {
    const d = this.device;
    const s = this.data.scene;
    const conf = view.conf;
    // WGSL Frame: view_proj, eye (w: λ), atlas (u32), axes[12], grid dims (u32), first, last.
    const frame = new ArrayBuffer(336);
    const fv = new Float32Array(frame);
    const uv = new Uint32Array(frame);
    fv.set(view.viewProj, 0);
    fv.set([view.eye[0], view.eye[1], view.eye[2], conf.sg_sharpness], 16);
    uv.set([s.atlas[0], s.atlas[1], 0, 0], 20);
    conf.axes.forEach((a, k) => fv.set([a[0], a[1], a[2], 0], 24 + 4 * k));
    uv.set(s.probes.dims, 72);
    fv.set(s.probes.first, 76);
    fv.set(s.probes.last, 80);
    d.queue.writeBuffer(this.frame, 0, frame);
    const dv = new ArrayBuffer(16);
    new Float32Array(dv).set([view.exposure], 0);
    new Uint32Array(dv).set([view.term], 1);
    new Float32Array(dv).set([view.split], 2);
    new Uint32Array(dv).set([this.data.reference ? 1 : 0], 3);
    d.queue.writeBuffer(this.displayUniform, 0, dv);
    const group = d.createBindGroup({
      layout: this.layout,
      entries: [
        { binding: 0, resource: { buffer: this.frame } },
        { binding: 1, resource: { buffer: this.materials } },
        { binding: 2, resource: this.lightmap(conf).createView({ dimension: '2d-array' }) },
        { binding: 3, resource: (conf.lut === 'ad' ? this.luts.ad : this.luts.dfg).createView() },
        { binding: 4, resource: this.lobeTable.createView() },
        { binding: 5, resource: { buffer: this.probes } },
        { binding: 6, resource: this.luts.dfg.createView() },
        { binding: 7, resource: this.sampler },
        { binding: 8, resource: this.sampler },
      ],
    });
    const enc = d.createCommandEncoder();
    const pass = enc.beginRenderPass({
      colorAttachments: this.targets.map((t) => ({ view: t.createView(), loadOp: 'clear', storeOp: 'store', clearValue: [0, 0, 0, 0] })),
      depthStencilAttachment: { view: this.depth.createView(), depthClearValue: 1, depthLoadOp: 'clear', depthStoreOp: 'store' },
    });
    pass.setPipeline(this.pipeline(conf, view.bicubic));
    pass.setBindGroup(0, group);
    pass.setVertexBuffer(0, this.vertices);
    pass.draw(s.vertices);
    pass.end();
    const k = readback ? 'capture' : 'canvas';
    const target = readback ? this.captureTarget : this.ctx.getCurrentTexture();
    const show = enc.beginRenderPass({ colorAttachments: [{ view: target.createView(), loadOp: 'clear', storeOp: 'store', clearValue: [0, 0, 0, 1] }] });
    show.setPipeline(this.displayPipelines[k]);
    show.setBindGroup(0, this.displayGroups[k]);
    show.draw(3);
    show.end();
    if (readback) enc.copyTextureToBuffer({ texture: target }, { buffer: readback, bytesPerRow: Math.ceil((this.width * 4) / 256) * 256 }, [this.width, this.height]);
    d.queue.submit([enc.finish()]);
  }

  // `view` drawn, the canvas as RGBA8, rows from the top.
  async capture(view) {
    const { width: w, height: h } = this;
    const bpr = Math.ceil((w * 4) / 256) * 256;
    const buf = this.device.createBuffer({ size: bpr * h, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
    this.draw(view, buf);
    await buf.mapAsync(GPUMapMode.READ);
    const src = new Uint8Array(buf.getMappedRange());
    const out = new Uint8Array(w * h * 4);
    for (let y = 0; y < h; y++) out.set(src.subarray(y * bpr, y * bpr + w * 4), y * w * 4);
    buf.unmap();
    return out;
  }
}

// ---- the page ----
async function load() {
  const scene = await fetchOk('scene.json', 'json');
  const results = await fetchOk('results.json', 'json').catch(() => null);
  const [mesh, materials, probes, dfg, ad, reference, library, glsl, wgsl, displayWgsl] = await Promise.all([
    fetchOk('mesh.bin'),
    fetchOk('materials.bin'),
    fetchOk('probes.bin'),
    fetchOk('lut-dfg.bin'),
    fetchOk('lut-ad.bin'),
    fetchOk('reference.bin').catch(() => null),
    fetchOk('sbf.es.glsl', 'text'),
    fetchOk('viewer.es.glsl', 'text'),
    fetchOk('viewer.wgsl', 'text'),
    fetchOk('display.wgsl', 'text'),
  ]);
  const lightmaps = {};
  await Promise.all(scene.configurations.map(async (c) => (lightmaps[c.name] = await fetchOk(c.file))));
  return { scene, results, mesh, materials, probes, luts: { dfg, ad }, reference, library, glsl, wgsl, displayWgsl, lightmaps };
}

function referenceView(scene) {
  const c = scene.camera;
  return { eye: c.eye.slice(), target: c.target.slice(), up: c.up.slice(), fov: (c.fov_y_degrees * Math.PI) / 180, near: c.near, far: c.far, exact: true };
}

function table(data) {
  const rows = data.results ? data.results.configurations : [];
  const fmt = (x, d = 4) => (x === null || x === undefined ? '—' : Number(x).toPrecision(d));
  const body = rows
    .map((c) => `<tr><td>${c.name}</td><td>${fmt(c.total && c.total.rmse)}</td><td>${fmt(c.total && c.total.relative_rmse, 3)}</td><td>×${fmt(c.total && c.total.mean_ratio)}</td><td>${c.bytes_per_texel}</td></tr>`)
    .join('');
  const f16 = data.scene.configurations.map((c) => `${c.name} ${fmt(c.f16_relative_rms, 2)}`).join(', ');
  return `<table><tr><th>configuration</th><th>RMSE (total)</th><th>relative</th><th>mean</th><th>bytes/texel (RGBA, as rendered)</th></tr>${body}</table>
<p>Errors against the path-traced reference, from results.json (the render run's storage and filter). This viewer stores the lightmaps as RGB f16: the image's relative RMS change from f32 storage — ${f16}.${data.scene.downsampled.factor > 1 ? ` The atlas is downsampled ${data.scene.downsampled.factor}× to fit the browser's texture limit (E/π relative RMS ${fmt(data.scene.downsampled.irradiance_relative_rms, 3)}).` : ''}</p>`;
}

async function main() {
  const t0 = performance.now();
  if (location.protocol === 'file:') {
    throw new Error('this page loads its data by fetch, which browsers refuse for files opened from disk: serve this folder (e.g. `python3 -m http.server` in it) and open the address it prints');
  }
  const data = await load();
  const s = data.scene;
  const canvas = $('view');
  canvas.width = s.camera.width;
  canvas.height = s.camera.height;
  $('errors').innerHTML = table(data);
  const pick = $('config');
  s.configurations.forEach((c) => pick.add(new Option(`${c.label} (${c.name})`, c.name)));
  const byName = (n) => s.configurations.find((c) => c.name === n);
  const asked = params.get('config');
  if (asked && !byName(asked)) $('status').textContent = `no configuration '${asked}' in this bake (${s.configurations.map((c) => c.name).join(', ')})`;
  const state = {
    cam: referenceView(s),
    conf: byName(asked) || byName('sh2') || s.configurations[0],
    term: 2,
    ev: 0,
    bicubic: false,
    split: false,
    splitAt: 0.5,
    mode: 'orbit',
  };
  pick.value = state.conf.name;
  const evLabel = () => ($('ev-value').textContent = `${state.ev >= 0 ? '+' : ''}${state.ev.toFixed(1)} EV`);
  // A view to link to: ?config=ad9&term=1&ev=1&split=0.5&filter=bicubic&api=webgpu.
  if (params.has('term')) $('term').value = String((state.term = Number(params.get('term'))));
  if (params.has('ev')) $('ev').value = String((state.ev = Number(params.get('ev'))));
  evLabel();
  if (params.has('filter')) $('filter').value = (state.bicubic = params.get('filter') === 'bicubic') ? 'bicubic' : 'bilinear';
  if (params.has('split')) {
    state.split = $('split').checked = true;
    $('split-at').value = String((state.splitAt = Number(params.get('split'))));
  }
  // One renderer per API, each on its own canvas (a canvas holds one kind of context),
  // made once; a canvas is shown only once its renderer exists.
  const renderers = {};
  let renderer = null;
  async function make(api) {
    if (!renderers[api]) {
      const c = api === 'webgl2' ? canvas : document.createElement('canvas');
      c.width = s.camera.width;
      c.height = s.camera.height;
      renderers[api] = api === 'webgpu' ? await WebGpu.create(c, data) : new WebGl2(c, data);
      renderers[api].canvas = c;
    }
    const r = renderers[api];
    const shown = document.querySelector('#view-box canvas');
    if (shown !== r.canvas) shown.replaceWith(r.canvas);
    return r;
  }
  // The scene's bounds: moved views put the far plane past them and the near plane at half
  // the distance to them (inside: a fraction of their size), for f32 depth.
  const [lo, hi] = s.bounds;
  const size = Math.hypot(...sub(hi, lo));
  const centre = mul(add(lo, hi), 0.5);
  function planes(eye) {
    const outside = Math.hypot(...[0, 1, 2].map((k) => Math.max(lo[k] - eye[k], 0, eye[k] - hi[k])));
    const far = 2 * (size + Math.hypot(...sub(eye, centre)));
    return { near: Math.max(far * 1e-4, outside > 0 ? 0.5 * outside : 0.002 * size), far };
  }
  function view() {
    const c = state.cam;
    const aspect = s.camera.width / s.camera.height;
    return {
      conf: state.conf,
      viewProj: c.exact ? s.camera.view_proj : viewProj({ ...c, ...planes(c.eye) }, aspect),
      eye: c.eye,
      exposure: s.exposure * 2 ** state.ev,
      term: state.term,
      bicubic: state.bicubic,
      split: state.split ? state.splitAt * s.camera.width : s.camera.width + 1,
    };
  }
  let pending = false;
  const redraw = () => {
    if (pending || !renderer) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      try {
        renderer.draw(view());
      } catch (e) {
        errors.push(String(e));
        $('status').textContent = String(e);
      }
    });
  };
  const lost = (what) => {
    $('status').textContent = `${what} was lost (the browser reset the GPU): reload the page`;
    renderer = null;
  };
  canvas.addEventListener('webglcontextlost', () => lost('the WebGL 2 context'));

  if (params.get('test') === '1') {
    await runTest(data, make, view, state, t0);
    return;
  }
  // The API asked for (WebGL 2 by default), else the other one.
  const want = params.get('api') === 'webgpu' ? 'webgpu' : 'webgl2';
  for (const api of [want, want === 'webgpu' ? 'webgl2' : 'webgpu']) {
    try {
      renderer = await make(api);
      break;
    } catch (e) {
      $('status').textContent += `${api}: ${e.message}. `;
    }
  }
  if (!renderer) throw new Error('neither WebGL 2 nor WebGPU could draw this bake here');
  if (renderer.device) renderer.device.lost.then((i) => lost(`the WebGPU device (${i.message})`));
  $('api').value = renderer instanceof WebGpu ? 'webgpu' : 'webgl2';
  $('adapter').textContent = renderer.adapter;
  renderer.draw(view());
  $('first-frame').textContent = `first frame after ${(performance.now() - t0).toFixed(0)} ms`;

  // ---- controls ----
  pick.onchange = () => {
    state.conf = byName(pick.value);
    redraw();
  };
  $('term').onchange = () => {
    state.term = Number($('term').value);
    redraw();
  };
  $('filter').onchange = () => {
    state.bicubic = $('filter').value === 'bicubic';
    redraw();
  };
  $('ev').oninput = () => {
    state.ev = Number($('ev').value);
    evLabel();
    redraw();
  };
  $('split').onchange = () => {
    state.split = $('split').checked;
    if (state.split) state.cam = referenceView(s);
    redraw();
  };
  $('split-at').oninput = () => {
    state.splitAt = Number($('split-at').value);
    redraw();
  };
  $('mode').onchange = () => (state.mode = $('mode').value);
  $('reset').onclick = () => {
    state.cam = referenceView(s);
    redraw();
  };
  $('api').onchange = async () => {
    const api = $('api').value;
    try {
      renderer = await make(api);
      if (renderer.device) renderer.device.lost.then((i) => lost(`the WebGPU device (${i.message})`));
      $('adapter').textContent = renderer.adapter;
      $('status').textContent = '';
    } catch (e) {
      // The renderer and canvas shown stay as they were.
      $('status').textContent = `${api}: ${e.message}`;
      $('api').value = renderer instanceof WebGpu ? 'webgpu' : 'webgl2';
    }
    redraw();
  };
  // The split view compares at the reference camera: moving the camera ends it.
  const unsplit = () => {
    state.split = false;
    $('split').checked = false;
  };
  // Orbit: drag turns about the target, the wheel moves in; fly: drag looks, WASD/QE move.
  let drag = null;
  document.addEventListener('pointerup', () => (drag = null));
  document.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const dx = (e.clientX - drag[0]) * 0.005;
    const dy = (e.clientY - drag[1]) * 0.005;
    drag = [e.clientX, e.clientY];
    const c = state.cam;
    c.exact = false;
    const centre = state.mode === 'orbit' ? c.target : c.eye;
    let d = sub(state.mode === 'orbit' ? c.eye : c.target, centre);
    const r = Math.hypot(...d);
    let yaw = Math.atan2(d[0], d[2]);
    let pitch = Math.asin(Math.max(-1, Math.min(1, d[1] / r)));
    const sgn = state.mode === 'orbit' ? -1 : 1;
    yaw += sgn * dx;
    pitch = Math.max(-1.5, Math.min(1.5, pitch - sgn * dy));
    d = [r * Math.cos(pitch) * Math.sin(yaw), r * Math.sin(pitch), r * Math.cos(pitch) * Math.cos(yaw)];
    if (state.mode === 'orbit') c.eye = add(c.target, d);
    else c.target = add(c.eye, d);
    unsplit();
    redraw();
  });
  document.addEventListener('pointerdown', (e) => {
    if (e.target.tagName === 'CANVAS') drag = [e.clientX, e.clientY];
  });
  document.addEventListener(
    'wheel',
    (e) => {
      if (e.target.tagName !== 'CANVAS') return;
      e.preventDefault();
      const c = state.cam;
      c.exact = false;
      const d = sub(c.eye, c.target);
      c.eye = add(c.target, mul(d, Math.exp(e.deltaY * 0.001)));
      unsplit();
      redraw();
    },
    { passive: false },
  );
  document.addEventListener('keydown', (e) => {
    if (state.mode !== 'fly') return;
    const c = state.cam;
    const f = norm(sub(c.target, c.eye));
    const r = norm(cross(f, c.up));
    const step = size * 0.02;
    const m = { w: f, s: mul(f, -1), d: r, a: mul(r, -1), e: c.up, q: mul(c.up, -1) }[e.key];
    if (!m) return;
    c.exact = false;
    c.eye = add(c.eye, mul(m, step));
    c.target = add(c.target, mul(m, step));
    unsplit();
    redraw();
  });
}

async function runTest(data, make, view, state, t0) {
  const report = { errors, apis: {}, first_frame_ms: null, captures: 0 };
  const apis = (params.get('apis') || 'webgl2').split(',');
  const confs = (params.get('configs') || data.scene.configurations.map((c) => c.name).join(',')).split(',');
  for (const api of apis) {
    let r;
    try {
      r = await make(api);
      report.apis[api] = r.adapter;
    } catch (e) {
      report.apis[api] = `unavailable: ${e.message}`;
      continue;
    }
    for (const item of confs) {
      // NAME or NAME:bicubic.
      const [name, filter] = item.split(':');
      state.conf = data.scene.configurations.find((c) => c.name === name);
      state.bicubic = filter === 'bicubic';
      if (!state.conf) {
        errors.push(`no configuration ${name}`);
        continue;
      }
      const px = await r.capture(view());
      if (report.first_frame_ms === null) {
        report.first_frame_ms = performance.now() - t0;
        await fetch('/__first_frame', { method: 'POST', body: String(report.first_frame_ms) });
      }
      await fetch(`/__capture?api=${api}&config=${item}&width=${r.width}&height=${r.height}`, { method: 'POST', body: px });
      report.captures += 1;
    }
  }
  await fetch('/__report', { method: 'POST', body: JSON.stringify(report) });
}

main().catch((e) => {
  errors.push(`viewer: ${e.message}`);
  const st = document.getElementById('status');
  if (st) st.textContent = `viewer: ${e.message}`;
  if (params.get('test') === '1') fetch('/__report', { method: 'POST', body: JSON.stringify({ errors, apis: {}, captures: 0 }) });
});
