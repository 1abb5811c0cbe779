#!/usr/bin/env python3
"""A flat grid of 2·K² triangles as glTF 2.0 (positions, normals, TEXCOORD_1, u32 indices in
one .bin), lit by a directional light: a large scene file for measuring what a worker pays
to read and import a scene (docs/distributed.md's model). Standard library only.

    tools/grid-gltf.py K OUT.gltf
"""
import json
import struct
import sys
from array import array

k = int(sys.argv[1])
out = sys.argv[2]
n = k + 1
pos, nrm, uv, idx = array("f"), array("f"), array("f"), array("I")
for j in range(n):
    for i in range(n):
        pos.extend((i / k * 100.0, 0.0, j / k * 100.0))
        nrm.extend((0.0, 1.0, 0.0))
        uv.extend((i / k, j / k))
for j in range(k):
    for i in range(k):
        a = j * n + i
        idx.extend((a, a + n, a + 1, a + 1, a + n, a + n + 1))
blobs = [pos.tobytes(), nrm.tobytes(), uv.tobytes(), idx.tobytes()]
views, offset = [], 0
for b in blobs:
    views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(b)})
    offset += len(b)
bin_name = out.rsplit("/", 1)[-1].replace(".gltf", ".bin")
doc = {
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}}, "rotation": [-0.5, 0.0, 0.0, 0.8660254]}],
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 3.0}]}},
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_1": 2}, "indices": 3, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": n * n, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [100.0, 0.0, 100.0]},
        {"bufferView": 1, "componentType": 5126, "count": n * n, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": n * n, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5125, "count": 6 * k * k, "type": "SCALAR"},
    ],
    "bufferViews": views,
    "buffers": [{"uri": bin_name, "byteLength": offset}],
}
with open(out.replace(".gltf", ".bin"), "wb") as f:
    for b in blobs:
        f.write(b)
with open(out, "w") as f:
    json.dump(doc, f)
print(f"{out}: {2 * k * k} triangles, {offset} bytes of buffers")
