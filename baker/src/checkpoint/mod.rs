//! Checkpoints of the progressive state, written atomically (a temporary file in the
//! same directory, synced, then renamed over the old one), so a bake killed at any
//! moment leaves either the previous or the new checkpoint, never a torn one.
//!
//! The shards of a bake spread over machines and their merge: [`shard`].
//!
//! Uses: [`crate::scene`], [`crate::accumulate`].
//!
//! Format (little endian): magic `SBFBAKE6`; u64 fingerprint of the bake's identity
//! (scene, layout, seed, bounces, bases, solver and each basis' update rule, sample sequence, adaptive sampling: a resumed bake must be the same bake);
//! u64 passes; u32 items (of the whole set); u32 bases; per basis u32 lobes; the part the
//! file holds — u32 count, u32 index, u64 block (count 1: every item; a shard's checkpoint
//! holds only its items, [`crate::accumulate::Partition`], as its state does); per held
//! item the six f64 moments
//! and the u64 counts of accepted, back-face and non-finite samples;
//! per basis and held item the f32 encoder state (RGB amplitude and mean B² per lobe, total
//! weight) and the u64 update count; u32 count n and the f32 ray-guiding sums, then the n
//! sums of the current stage's basis (n = 0 without guiding); u32 count m of filtered
//! gather targets (0 without a filter), per target the eight f64 weighted moments (Σw, Σw²,
//! mean, M2) and the u64 sample count, the u64 count of negative-weight samples, and per
//! basis and target the encoder state as above; last, the u64 FNV-1a hash of every byte
//! before it, checked before anything is read (a torn or bit-flipped checkpoint is refused
//! with a message, not resumed). Checkpoints of earlier bakers (`SBFBAKE4`, `SBFBAKE5`:
//! their fingerprint hashed the points themselves) are refused with a message. f32 state
//! round-trips exactly, so a resumed bake continues bit for bit.
//!
//! [`write_atomic`] writes through a temporary name unique to the writer (process id and a
//! counter), so two processes writing one checkpoint — a retried task beside an orphaned
//! one — cannot rename each other's file away.

pub mod shard;

use crate::accumulate::{BakeConfig, BakeState, Moments, Partition, Targets};
use crate::scene::{Environment, Light, Scene};
use sbf::solve::ProgressiveEncoder;
use std::io::Write;
use std::path::Path;

const MAGIC: &[u8; 8] = b"SBFBAKE6";
/// Earlier formats (before the trailing hash; before [`Targets::identity`]).
const MAGIC_EARLIER: [&[u8; 8]; 2] = [b"SBFBAKE4", b"SBFBAKE5"];

pub use crate::layout::digest::Fnv;

/// The materials' maps, their textures and the meshes' TEXCOORD_0 — nothing for an
/// untextured scene, whose identity stays what it was before maps existed.
fn hash_maps(h: &mut Fnv, scene: &Scene) {
    if !scene.has_textures() {
        return;
    }
    for m in &scene.materials {
        for r in [m.maps.base_color, m.maps.metallic_roughness, m.maps.emissive] {
            match r {
                None => h.u64(u64::MAX),
                Some(r) => {
                    h.u64(r.texture as u64);
                    h.u64(r.texcoord as u64);
                    r.transform.iter().for_each(|row| h.f32s(row));
                }
            }
        }
        if let Some(mask) = m.maps.mask {
            h.f32s(&[mask.factor, mask.cutoff]);
        }
    }
    for t in &scene.textures {
        h.u64(((t.width as u64) << 32) | t.height as u64);
        h.bytes(t.texels.as_flattened());
        h.bytes(format!("{:?}{:?}", t.wrap, t.filter).as_bytes());
    }
    for m in &scene.meshes {
        m.uv.iter().flatten().for_each(|v| h.f32s(&v.to_array()));
    }
}

/// The identity of a bake: a hash of the scene content (geometry, normals, lightmap UVs,
/// materials, lights, environment texels), the targets ([`Targets::identity`]: every
/// sample point and item of the whole set — so the layout and the probe positions), and the settings that change the result: the
/// bake spec's `config` in its canonical serialisation and each basis' encoder rule.
pub fn content_fingerprint(scene: &Scene, targets: &Targets, config: &BakeConfig, what: &str) -> u64 {
    let mut h = Fnv::default();
    h.bytes(what.as_bytes());
    for m in &scene.meshes {
        h.u64(m.positions.len() as u64);
        m.positions.iter().chain(&m.normals).for_each(|v| h.vec3(*v));
        m.indices.iter().flatten().for_each(|i| h.u64(*i as u64));
        if let Some(uv) = &m.lightmap_uv {
            uv.iter().for_each(|v| h.f32s(&v.to_array()));
        }
        h.u64(m.material as u64);
        h.u64(m.lightmapped as u64);
    }
    for m in &scene.materials {
        h.vec3(m.base_color);
        h.vec3(m.emissive);
        h.f32s(&[m.metallic, m.roughness, m.specular]);
        h.u64(m.double_sided as u64);
    }
    hash_maps(&mut h, scene);
    for l in &scene.lights {
        match *l {
            Light::Directional { direction, irradiance } => {
                h.u64(0);
                h.vec3(direction);
                h.vec3(irradiance);
            }
            Light::Point { position, intensity, range } => {
                h.u64(1);
                h.vec3(position);
                h.vec3(intensity);
                h.f32s(&[range]);
            }
            Light::Spot { position, direction, intensity, cos_inner, cos_outer, range } => {
                h.u64(2);
                h.vec3(position);
                h.vec3(direction);
                h.vec3(intensity);
                h.f32s(&[cos_inner, cos_outer, range]);
            }
        }
    }
    match &scene.environment {
        Environment::Black => h.u64(10),
        Environment::Constant(c) => {
            h.u64(11);
            h.vec3(*c);
        }
        Environment::Sky { zenith, horizon, ground } => {
            h.u64(12);
            [zenith, horizon, ground].iter().for_each(|c| h.vec3(**c));
        }
        Environment::Map(m) => {
            h.u64(13);
            h.u64(m.geometry.width as u64);
            m.texels.iter().for_each(|t| h.f32s(t));
        }
    }
    // Every sample point of the whole set, through its identity: a part of the set (a
    // shard's targets) has the whole set's.
    h.u64(targets.identity);
    // The settings: the bake spec's `config` part in its canonical serialisation (the
    // pipeline, how a GPU runs the passes, is not part of it: both give the same state).
    h.bytes(serde_json::to_string(config).expect("a bake config serialises").as_bytes());
    // Each basis' update rule (a state saved under another rule — e.g. SH's residual update
    // before the projection — is not this bake's running estimate).
    config.bases.iter().for_each(|b| h.bytes(format!("{:?}", config.encoder_options(*b, targets.sphere)).as_bytes()));
    h.finish()
}

/// Serialises a state of whole targets (at least one item).
pub fn to_bytes(state: &BakeState, fingerprint: u64) -> Vec<u8> {
    let lobes: Vec<usize> = state.encoders.iter().map(|e| e.first().map_or(0, |x| x.coefficients().nrows())).collect();
    write_state(state, fingerprint, None, &lobes)
}

/// Serialises the state of a bake of `config` on `targets` — whole, or a part
/// ([`Targets::part`]: the state holds the part's items, in order; a part may hold none).
pub fn to_bytes_for(state: &BakeState, fingerprint: u64, config: &BakeConfig, targets: &Targets) -> Vec<u8> {
    let lobes: Vec<usize> = config.bases.iter().map(|b| b.lobes()).collect();
    write_state(state, fingerprint, targets.part, &lobes)
}

/// The checkpoint bytes of `state`: of a part (the part and the whole set's item count)
/// or of whole targets (None), with `lobes` per basis.
fn write_state(state: &BakeState, fingerprint: u64, part: Option<(Partition, usize)>, lobes: &[usize]) -> Vec<u8> {
    // Reserved whole (the state's items; the filtered gather's, if any, grow it once).
    let per_item = 72 + lobes.iter().map(|l| 16 * l + 12).sum::<usize>();
    let mut v = Vec::with_capacity(64 + 4 * lobes.len() + state.moments.len() * per_item + 8 * state.guide_sums.len());
    v.extend_from_slice(MAGIC);
    v.extend_from_slice(&fingerprint.to_le_bytes());
    v.extend_from_slice(&state.passes.to_le_bytes());
    v.extend_from_slice(&(part.map_or(state.moments.len(), |p| p.1) as u32).to_le_bytes());
    v.extend_from_slice(&(state.encoders.len() as u32).to_le_bytes());
    for l in lobes {
        v.extend_from_slice(&(*l as u32).to_le_bytes());
    }
    let p = part.map(|p| p.0).filter(|p| p.count > 1);
    v.extend_from_slice(&(p.map_or(1, |p| p.count) as u32).to_le_bytes());
    v.extend_from_slice(&(p.map_or(0, |p| p.index) as u32).to_le_bytes());
    v.extend_from_slice(&(p.map_or(0, |p| p.block) as u64).to_le_bytes());
    state.moments.iter().for_each(|m| write_moments(&mut v, m));
    for encs in &state.encoders {
        encs.iter().for_each(|e| write_encoder(&mut v, e));
    }
    v.extend_from_slice(&(state.guide_sums.len() as u32).to_le_bytes());
    for x in state.guide_sums.iter().chain(&state.guide_basis) {
        v.extend_from_slice(&x.to_le_bytes());
    }
    match &state.filtered {
        None => v.extend_from_slice(&0u32.to_le_bytes()),
        Some(f) => {
            v.extend_from_slice(&(f.moments.len() as u32).to_le_bytes());
            for m in &f.moments {
                for x in [m.weight, m.weight_sq].iter().chain(&m.mean).chain(&m.m2) {
                    v.extend_from_slice(&x.to_le_bytes());
                }
                v.extend_from_slice(&m.samples.to_le_bytes());
            }
            v.extend_from_slice(&f.negative_weights.to_le_bytes());
            write_encoders(&mut v, &f.encoders);
        }
    }
    let mut h = Fnv::default();
    h.bytes(&v);
    v.extend_from_slice(&h.finish().to_le_bytes());
    v
}

fn write_encoders(v: &mut Vec<u8>, encoders: &[Vec<ProgressiveEncoder<f32>>]) {
    encoders.iter().flatten().for_each(|e| write_encoder(v, e));
}

/// One encoder's state: per lobe the RGB amplitude and mean B² (f32), the total weight
/// (f32) and the u64 update count.
fn write_encoder(v: &mut Vec<u8>, e: &ProgressiveEncoder<f32>) {
    for (a, g) in e.amplitudes().iter().zip(e.lobe_integrals()) {
        for x in [a[0], a[1], a[2], *g] {
            v.extend_from_slice(&x.to_le_bytes());
        }
    }
    v.extend_from_slice(&(e.total_weight() as f32).to_le_bytes());
    v.extend_from_slice(&e.sample_count().to_le_bytes());
}

fn read_encoder(r: &mut Reader, opts: &sbf::solve::ProgressiveOptions, lobes: usize) -> Result<ProgressiveEncoder<f32>, String> {
    let mut amp = vec![[0.0; 3]; lobes];
    let mut integ = vec![0.0; lobes];
    for i in 0..lobes {
        amp[i] = [r.f32()? as f64, r.f32()? as f64, r.f32()? as f64];
        integ[i] = r.f32()? as f64;
    }
    let w = r.f32()? as f64;
    let n = r.u64()?;
    ProgressiveEncoder::from_state(opts.clone(), &amp, &integ, w, n).map_err(|e| format!("checkpoint: {e}"))
}

/// One item's moments: the six f64 sums, then the accepted, back-face and non-finite counts.
fn write_moments(v: &mut Vec<u8>, m: &Moments) {
    for x in m.sum.iter().chain(&m.sum_sq) {
        v.extend_from_slice(&x.to_le_bytes());
    }
    for n in [m.accepted, m.back_faces, m.non_finite] {
        v.extend_from_slice(&n.to_le_bytes());
    }
}

fn read_moments(r: &mut Reader) -> Result<Moments, String> {
    let mut x = [0.0; 6];
    for v in x.iter_mut() {
        *v = r.f64()?;
    }
    let (accepted, back_faces, non_finite) = (r.u64()?, r.u64()?, r.u64()?);
    Ok(Moments { sum: [x[0], x[1], x[2]], sum_sq: [x[3], x[4], x[5]], accepted, back_faces, non_finite })
}

fn read_encoders(
    r: &mut Reader,
    config: &BakeConfig,
    targets: &Targets,
    lobes: &[usize],
    encoders: &mut [Vec<ProgressiveEncoder<f32>>],
) -> Result<(), String> {
    for (b, encs) in encoders.iter_mut().enumerate() {
        let opts = config.encoder_options(config.bases[b], targets.sphere);
        for e in encs.iter_mut() {
            *e = read_encoder(r, &opts, lobes[b])?;
        }
    }
    Ok(())
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let s = self.b.get(self.at..self.at + n).ok_or_else(|| format!("checkpoint truncated at byte {}", self.at))?;
        self.at += n;
        Ok(s)
    }
    fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().expect("4 bytes")))
    }
    fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().expect("8 bytes")))
    }
    fn f32(&mut self) -> Result<f32, String> {
        Ok(f32::from_le_bytes(self.take(4)?.try_into().expect("4 bytes")))
    }
    fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.take(8)?.try_into().expect("8 bytes")))
    }
}

/// Reads a state saved for the bake with this fingerprint, config and targets (a part's
/// targets, [`Targets::part`], read a checkpoint of that part: the state of its items).
pub fn from_bytes(bytes: &[u8], fingerprint: u64, config: &BakeConfig, targets: &Targets) -> Result<BakeState, String> {
    let bytes = match bytes.get(..8) {
        Some(m) if m == MAGIC => {
            let (data, sum) = bytes.split_at(bytes.len().saturating_sub(8).max(8));
            let mut h = Fnv::default();
            h.bytes(data);
            if sum.len() != 8 || h.finish().to_le_bytes() != sum {
                return Err("checksum mismatch: the checkpoint is truncated or corrupt (delete it to bake from the start)".into());
            }
            data
        }
        Some(m) if MAGIC_EARLIER.iter().any(|e| m == e.as_slice()) => {
            return Err("a checkpoint of an earlier baker, whose bake identity was computed otherwise: delete it to bake from the start (or resume with that baker)".into());
        }
        _ => return Err("not a baker checkpoint (bad magic)".into()),
    };
    let mut r = Reader { b: bytes, at: 0 };
    r.take(8)?;
    let fp = r.u64()?;
    if fp != fingerprint {
        return Err(format!("checkpoint belongs to a different bake (fingerprint {fp:016x}, this bake {fingerprint:016x}): the scene content, layout or probe positions, seed, bounces, bases, solver, sample sequence, adaptive sampling, ray guiding or the filter changed"));
    }
    let passes = r.u64()?;
    let (items, nb) = (r.u32()? as usize, r.u32()? as usize);
    let mut state = BakeState::new(config, targets);
    let whole = targets.part.map_or(targets.items.len(), |p| p.1);
    if items != whole || nb != state.encoders.len() {
        return Err(format!("checkpoint has {items} items × {nb} bases, this bake {whole} × {}", state.encoders.len()));
    }
    let mut lobes = Vec::with_capacity(nb);
    for b in 0..nb {
        let l = r.u32()? as usize;
        let want = config.bases[b].lobes();
        if l != want {
            return Err(format!("checkpoint basis {b} has {l} lobes, {} has {want}", config.bases[b].name()));
        }
        lobes.push(l);
    }
    let want = targets.part.map(|p| p.0).filter(|p| p.count > 1);
    let (count, index, block) = (r.u32()? as usize, r.u32()? as usize, r.u64()? as usize);
    let have = (count > 1).then_some((count, index, block));
    if have != want.map(|p| (p.count, p.index, p.block)) {
        let show =
            |x: Option<(usize, usize, usize)>| x.map_or("every item".to_string(), |(c, i, b)| format!("part {i} of {c} in blocks of {b}"));
        return Err(format!("checkpoint holds {}, this bake needs {}", show(have), show(want.map(|p| (p.count, p.index, p.block)))));
    }
    for m in state.moments.iter_mut() {
        *m = read_moments(&mut r)?;
    }
    read_encoders(&mut r, config, targets, &lobes, &mut state.encoders)?;
    let sums = r.u32()? as usize;
    if sums != state.guide_sums.len() {
        return Err(format!("checkpoint has {sums} ray-guiding sums, this bake {}", state.guide_sums.len()));
    }
    for x in state.guide_sums.iter_mut().chain(state.guide_basis.iter_mut()) {
        *x = r.f32()?;
    }
    let gathered = r.u32()? as usize;
    let want = state.filtered.as_ref().map_or(0, |f| f.moments.len());
    if gathered != want {
        return Err(format!("checkpoint has {gathered} filtered gather targets, this bake {want}"));
    }
    if let Some(f) = &mut state.filtered {
        for m in f.moments.iter_mut() {
            let mut x = [0.0; 8];
            for v in x.iter_mut() {
                *v = r.f64()?;
            }
            let samples = r.u64()?;
            *m = crate::accumulate::filter::WeightedMoments {
                weight: x[0],
                weight_sq: x[1],
                mean: [x[2], x[3], x[4]],
                m2: [x[5], x[6], x[7]],
                samples,
            };
        }
        f.negative_weights = r.u64()?;
        read_encoders(&mut r, config, targets, &lobes, &mut f.encoders)?;
    }
    if r.at != bytes.len() {
        return Err(format!("checkpoint has {} trailing bytes", bytes.len() - r.at));
    }
    state.passes = passes;
    Ok(state)
}

/// Writes `bytes` to `path` atomically (temporary file + fsync + rename); the temporary
/// name is unique to this process and call.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let k = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let name = path.file_name().map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    let tmp = path.with_file_name(format!(".{name}.{}.{k}.tmp", std::process::id()));
    let mut f = std::fs::File::create(&tmp).map_err(|e| format!("creating {}: {e}", tmp.display()))?;
    f.write_all(bytes).map_err(|e| format!("writing {}: {e}", tmp.display()))?;
    f.sync_all().map_err(|e| format!("syncing {}: {e}", tmp.display()))?;
    drop(f);
    if let Err(e) = std::fs::rename(&tmp, path) {
        let _ = std::fs::remove_file(&tmp);
        return Err(format!("renaming {} to {}: {e}", tmp.display(), path.display()));
    }
    // The rename is durable only once the directory entry is (POSIX): sync the folder.
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    #[cfg(unix)]
    std::fs::File::open(dir).and_then(|d| d.sync_all()).map_err(|e| format!("syncing {}: {e}", dir.display()))?;
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}
