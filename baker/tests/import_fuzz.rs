//! A seeded mutation test of the glTF importer: glTF JSON (values swapped for edge cases,
//! keys deleted, indices redirected, text truncated or bit-flipped) and GLB bytes
//! (bit flips, truncation, chunk-length edits), each loaded, and when it imports, its BVH
//! and lightmap layout built. Zero panics allowed; every failure must be an error value.
//!
//! Cases: `SBF_FUZZ_CASES` (default 1000 for CI, about a second; the benchmark-sized run is
//! `SBF_FUZZ_CASES=10000 cargo test --release -p baker --test import_fuzz -- --nocapture`).
//! Seeds are fixed, so a failing case is reproducible from its number.

use baker::layout::lightmap::Lightmap;
use baker::scene::bvh::Bvh;
use baker::scene::import;
use sbf::sampling::Pcg32;
use serde_json::{json, Value};
use std::path::Path;

/// A small valid asset: a floor with TEXCOORD_1, a wall, an emitter, two lights, a node
/// tree; buffer as a data URI (JSON) or a GLB blob.
fn asset() -> (Value, Vec<u8>) {
    let mut bin = Vec::new();
    let mut f32s = |v: &[f32]| {
        let off = bin.len();
        for x in v {
            bin.extend_from_slice(&x.to_le_bytes());
        }
        off
    };
    let pos = f32s(&[-1., 0., 1., 1., 0., 1., 1., 0., -1., -1., 0., -1.]);
    let nrm = f32s(&[0., 1., 0., 0., 1., 0., 0., 1., 0., 0., 1., 0.]);
    let uv = f32s(&[0., 0., 1., 0., 1., 1., 0., 1.]);
    let wall = f32s(&[-1., 0., -1., 1., 0., -1., 1., 2., -1., -1., 2., -1.]);
    let idx = bin.len();
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let view = |off: usize, len: usize| json!({"buffer": 0, "byteOffset": off, "byteLength": len});
    let acc = |v: usize, ct: u32, n: usize, ty: &str| json!({"bufferView": v, "componentType": ct, "count": n, "type": ty});
    let mut pa = acc(0, 5126, 4, "VEC3");
    pa["min"] = json!([-1, 0, -1]);
    pa["max"] = json!([1, 0, 1]);
    let mut wa = acc(3, 5126, 4, "VEC3");
    wa["min"] = json!([-1, 0, -1]);
    wa["max"] = json!([1, 2, -1]);
    let doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "intensity": 3.0},
            {"type": "spot", "intensity": 20.0, "range": 5.0, "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.6}}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 3]}],
        "nodes": [
            {"mesh": 0, "children": [1, 2]},
            {"mesh": 1, "translation": [0, 0, 0.5]},
            {"extensions": {"KHR_lights_punctual": {"light": 0}}, "rotation": [-0.38, 0, 0, 0.92]},
            {"extensions": {"KHR_lights_punctual": {"light": 1}}, "translation": [0, 1.5, 0]}
        ],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_1": 2}, "indices": 4, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 3}, "indices": 4, "material": 1}]}
        ],
        "materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1], "roughnessFactor": 0.5}, "doubleSided": true},
            {"emissiveFactor": [1, 0.5, 0.2], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}}
        ],
        "accessors": [pa, acc(1, 5126, 4, "VEC3"), acc(2, 5126, 4, "VEC2"), wa, acc(4, 5123, 6, "SCALAR")],
        "bufferViews": [view(pos, 48), view(nrm, 48), view(uv, 32), view(wall, 48), view(idx, 12)],
        "buffers": [{"byteLength": bin.len()}]
    });
    (doc, bin)
}

fn data_uri(doc: &Value, bin: &[u8]) -> Value {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::from("data:application/octet-stream;base64,");
    for c in bin.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            s.push(if k <= c.len() { T[(n >> (18 - 6 * k) & 63) as usize] as char } else { '=' });
        }
    }
    let mut d = doc.clone();
    d["buffers"][0]["uri"] = Value::String(s);
    d
}

/// GLB 2.0: header, JSON chunk (space-padded), BIN chunk (zero-padded).
fn glb(doc: &Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(doc).unwrap();
    while j.len() % 4 != 0 {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while b.len() % 4 != 0 {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    out.extend_from_slice(&(b.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&b);
    out
}

/// Every path (object keys, array indices) in a JSON tree.
fn paths(v: &Value, at: &mut Vec<Value>, out: &mut Vec<Vec<Value>>) {
    out.push(at.clone());
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                at.push(Value::String(k.clone()));
                paths(x, at, out);
                at.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                at.push(json!(i));
                paths(x, at, out);
                at.pop();
            }
        }
        _ => {}
    }
}

fn get_mut<'a>(v: &'a mut Value, path: &[Value]) -> Option<&'a mut Value> {
    let mut cur = v;
    for p in path {
        cur = match p {
            Value::String(k) => cur.get_mut(k.as_str())?,
            Value::Number(i) => cur.get_mut(i.as_u64()? as usize)?,
            _ => return None,
        };
    }
    Some(cur)
}

const EDGE: [f64; 14] = [0.0, -1.0, 1.0, 2.0, 3.0, 255.0, 65535.0, 4294967295.0, 1e38, -1e38, 1e-38, 0.5, 1e300, 5126.0];

/// One to three JSON-level mutations.
fn mutate_json(doc: &Value, r: &mut Pcg32) -> Value {
    let mut d = doc.clone();
    let n = 1 + (r.next_f64() * 3.0) as usize;
    for _ in 0..n {
        let mut all = Vec::new();
        paths(&d, &mut Vec::new(), &mut all);
        // Mostly numbers (counts, offsets, indices, component types, factors): the
        // mutations that pass schema validation and reach the importer's own checks.
        let numbers: Vec<Vec<Value>> = all.iter().filter(|p| get_mut(&mut d.clone(), p).is_some_and(|x| x.is_number())).cloned().collect();
        let pool = if r.next_f64() < 0.8 && !numbers.is_empty() { &numbers } else { &all };
        let path = pool[(r.next_f64() * pool.len() as f64) as usize % pool.len()].clone();
        let pick = (r.next_f64() * 8.0) as usize;
        let other = all[(r.next_f64() * all.len() as f64) as usize % all.len()].clone();
        let other_value = get_mut(&mut d, &other).map(|x| x.clone());
        let Some(slot) = get_mut(&mut d, &path) else { continue };
        match pick {
            0..=2 => {
                let x = EDGE[(r.next_f64() * EDGE.len() as f64) as usize % EDGE.len()];
                // Integers stay integers (the schema wants u32 for counts and indices).
                *slot = if slot.is_u64() && x >= 0.0 && x.fract() == 0.0 && x < 1e10 { json!(x as u64) } else { json!(x) };
            }
            3 => *slot = json!((r.next_f64() * 8.0) as u64),
            4 => *slot = Value::Null,
            5 => {
                if let Value::Object(m) = slot {
                    if let Some(k) = m.keys().nth((r.next_f64() * m.len().max(1) as f64) as usize).cloned() {
                        m.remove(&k);
                    }
                } else if let Value::Array(a) = slot {
                    if !a.is_empty() {
                        let x = a[0].clone();
                        a.push(x);
                    }
                }
            }
            6 => {
                if let Some(o) = other_value {
                    *slot = o;
                }
            }
            _ => *slot = json!([0, 0, 0]),
        }
    }
    d
}

/// One to three byte-level mutations: bit flips, truncation, a 32-bit field overwritten.
fn mutate_bytes(b: &[u8], r: &mut Pcg32) -> Vec<u8> {
    let mut v = b.to_vec();
    let n = 1 + (r.next_f64() * 3.0) as usize;
    for _ in 0..n {
        if v.is_empty() {
            break;
        }
        let at = (r.next_f64() * v.len() as f64) as usize % v.len();
        match (r.next_f64() * 4.0) as usize {
            0 => v[at] ^= 1 << ((r.next_f64() * 8.0) as u32 % 8),
            1 => v.truncate(at),
            2 => {
                let x = [0u32, 1, 0xffff_ffff, 0x7fff_ffff, 12, 0x8000_0000][(r.next_f64() * 6.0) as usize % 6];
                for (k, byte) in x.to_le_bytes().iter().enumerate() {
                    if let Some(s) = v.get_mut(at + k) {
                        *s = *byte;
                    }
                }
            }
            _ => v[at] = (r.next_f64() * 256.0) as u8,
        }
    }
    v
}

/// Loads a file; if it imports, builds its BVH and a lightmap layout (bounded: the
/// layout refuses atlases over 8192², the importer bounds every accessor).
fn exercise(path: &Path) -> Result<(), String> {
    let (scene, _) = import::load(path).map_err(|e| e.to_string())?;
    let bvh = Bvh::build(&scene);
    assert!(bvh.depth() <= baker::scene::bvh::MAX_DEPTH + 1);
    Lightmap::build(&scene, 4.0, 1).map_err(|e| e.to_string())?;
    Ok(())
}

#[test]
fn mutated_gltf_and_glb_never_panic() {
    let cases: usize = std::env::var("SBF_FUZZ_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(1000);
    let dir = std::env::temp_dir().join(format!("baker-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (doc, bin) = asset();
    // The seeds import cleanly.
    let json_seed = data_uri(&doc, &bin);
    std::fs::write(dir.join("seed.gltf"), serde_json::to_vec(&json_seed).unwrap()).unwrap();
    exercise(&dir.join("seed.gltf")).expect("the JSON seed imports");
    let glb_seed = glb(&doc, &bin);
    std::fs::write(dir.join("seed.glb"), &glb_seed).unwrap();
    exercise(&dir.join("seed.glb")).expect("the GLB seed imports");
    let (mut imported, mut errors, mut panics) = (0, 0, Vec::new());
    let mut kinds = std::collections::BTreeMap::new();
    for case in 0..cases {
        let mut r = Pcg32::new(0x5eed, case as u64);
        let (name, bytes) = match case % 4 {
            0 => ("json.gltf", serde_json::to_vec(&mutate_json(&json_seed, &mut r)).unwrap()),
            1 => ("text.gltf", mutate_bytes(&serde_json::to_vec(&json_seed).unwrap(), &mut r)),
            2 => ("json.glb", glb(&mutate_json(&doc, &mut r), &bin)),
            _ => ("bytes.glb", mutate_bytes(&glb_seed, &mut r)),
        };
        let p = dir.join(format!("case-{name}"));
        std::fs::write(&p, &bytes).unwrap();
        match std::panic::catch_unwind(|| exercise(&p)) {
            Ok(Ok(())) => imported += 1,
            Ok(Err(e)) => {
                errors += 1;
                let e = e.replace(&*p.to_string_lossy(), "FILE");
                let key: String = e.chars().take(60).collect();
                *kinds.entry(key).or_insert(0) += 1;
            }
            Err(_) => {
                let keep = dir.join(format!("panic-{case}-{name}"));
                std::fs::write(&keep, &bytes).unwrap();
                panics.push(format!("case {case} ({name}) kept at {}", keep.display()));
            }
        }
    }
    println!("{cases} mutated assets: {imported} imported and laid out, {errors} clear errors, {} panics", panics.len());
    for (k, n) in kinds.iter().rev().take(12) {
        println!("  {n:>5} × {k}…");
    }
    assert!(panics.is_empty(), "panics: {panics:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
