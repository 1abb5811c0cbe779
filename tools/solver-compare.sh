#!/usr/bin/env bash
# The lightmap solvers side by side at scene level (docs/render.md, "Directional lightmaps
# that keep the measured light"): per scene and solver, `baker` then `render --bake` against
# the path-traced reference; one line per scene × solver × configuration with the mean ratio
# to the reference and the RMSEs of diffuse, specular and total. Bakes take the materials'
# factors (`--material-maps factors`): `render` shades factors and refuses a textured bake.
#
#   tools/solver-compare.sh OUT SCENE… (SCENE: a built-in name or a .gltf path)
#   SOLVERS (default "nnls ls nnls-rescaled nnls-irradiance"), PASSES (256), BASES
#   (sh2,ad9,sg9), SIZE (480x270), SPP (1024), DEVICE (auto), BIN (target/release),
#   BAKE_ARGS (more `baker` arguments, e.g. "--texels-per-unit 32"; default none), TAG (a
#   suffix for the output names).
set -euo pipefail
out=$1; shift
bin=${BIN:-target/release}
mkdir -p "$out"
for scene in "$@"; do
  tag=$(basename "$scene" | sed 's/\.gl[tb]f\?$//')${TAG:-}
  for solver in ${SOLVERS:-nnls ls nnls-rescaled nnls-irradiance}; do
    d=$out/$tag-$solver
    "$bin/baker" --scene "$scene" --device "${DEVICE:-auto}" --passes "${PASSES:-256}" --bases "${BASES:-sh2,ad9,sg9}" \
      --solver "$solver" --material-maps factors ${BAKE_ARGS:-} --out "$d/bake" >"$d.bake.log" 2>&1 || { echo "bake failed: $d.bake.log"; tail -3 "$d.bake.log"; exit 1; }
    "$bin/render" --scene "$scene" --bake "$d/bake" --bases "${BASES:-sh2,ad9,sg9}" --specular both --size "${SIZE:-480x270}" \
      --reference-samples "${SPP:-1024}" --reference-noise 0.005 --frames 0 --device "${DEVICE:-auto}" --out "$d/render" >"$d.render.log" 2>&1 \
      || { echo "render failed: $d.render.log"; tail -3 "$d.render.log"; exit 1; }
    python3 - "$d/render/results.json" "$tag" "$solver" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
f = lambda x, spec: "—" if x is None else format(x, spec)
for c in r["configurations"]:
    t, d, s = c["total"], c["diffuse"], c["specular"]
    print(f'{sys.argv[2]:22s} {sys.argv[3]:16s} {c["name"]:11s} mean ×{f(t["mean_ratio"], ".4f")}  diffuse {f(d["rmse"], ".4e")} (×{f(d["mean_ratio"], ".4f")})  '
          f'specular {f(s["rmse"], ".4e")} (×{f(s["mean_ratio"], ".4f")})  total {f(t["rmse"], ".4e")}')
PY
  done
done
