//! glTF assets written by the tests: a square with texture coordinates, its material and
//! images given as JSON.

/// Standard base64 (RFC 4648), for data URIs.
pub fn b64(bytes: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            s.push(if k <= c.len() { T[(n >> (18 - 6 * k) & 63) as usize] as char } else { '=' });
        }
    }
    s
}

/// `dir/floor.gltf`: the square [−a, a]² at height `y` facing +Y, TEXCOORD_0 = ((x + a)/2a,
/// (z + a)/2a), one texture (image `image`, NEAREST magnification, REPEAT) and the
/// material `material` (JSON); returns its path.
pub fn plane(dir: &std::path::Path, a: f32, y: f32, material: &str, image: &str) -> std::path::PathBuf {
    let bin = square_buffer(a, y);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":["KHR_texture_transform","KHR_materials_emissive_strength"],
        "scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"name":"floor","primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}},"indices":3,"material":0}}]}}],
        "materials":[{material}],
        "textures":[{{"source":0,"sampler":0}}],"samplers":[{{"magFilter":9728,"wrapS":10497,"wrapT":10497}}],
        "images":[{image}],
        "buffers":[{{"byteLength":{len},"uri":"data:application/octet-stream;base64,{data}"}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":48}},
                       {{"buffer":0,"byteOffset":96,"byteLength":32}},{{"buffer":0,"byteOffset":128,"byteLength":12}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[-{a},{y},-{a}],"max":[{a},{y},{a}]}},
                     {{"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"}},
                     {{"bufferView":2,"componentType":5126,"count":4,"type":"VEC2"}},
                     {{"bufferView":3,"componentType":5123,"count":6,"type":"SCALAR"}}]}}"#,
        len = bin.len(),
        data = b64(&bin),
    );
    let path = dir.join("floor.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

/// The buffer of the square [−a, a]² at height `y` facing +Y: 4 positions (VEC3 f32, bytes
/// 0..48), 4 normals +Y (48..96), 4 texture coordinates ((x + a)/2a, (z + a)/2a) (VEC2 f32,
/// 96..128) and 6 u16 indices (128..140), counter-clockwise seen from +Y.
pub fn square_buffer(a: f32, y: f32) -> Vec<u8> {
    let pos = [[-a, y, -a], [a, y, -a], [a, y, a], [-a, y, a]];
    let mut bin: Vec<u8> = Vec::new();
    for p in pos {
        bin.extend(p.iter().flat_map(|x| x.to_le_bytes()));
    }
    for _ in pos {
        bin.extend([0.0f32, 1.0, 0.0].iter().flat_map(|x| x.to_le_bytes()));
    }
    for p in pos {
        bin.extend([(p[0] + a) / (2.0 * a), (p[2] + a) / (2.0 * a)].iter().flat_map(|x| x.to_le_bytes()));
    }
    // Counter-clockwise seen from +Y: the floor faces up (and emits upwards).
    for i in [0u16, 3, 2, 0, 2, 1] {
        bin.extend(i.to_le_bytes());
    }
    bin
}
