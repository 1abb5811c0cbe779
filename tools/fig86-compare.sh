#!/usr/bin/env bash
# The thesis' scene-level comparison (seed 004 Fig. 8.6 and the per-basis table of
# docs/render.md) with the current solvers: NNLS SG 12 at λ 8 (the thesis' comparator) and SG 9
# λ 8 and AD 9, each baked with plain `nnls` and the default `nnls-rescaled` (all light, and
# for the room indirect light only), then `render --bake` of their fit paths; then the
# per-basis table (`render`'s own bake with the default solver: SH L1/L2, SG 9/12, AD 9/12,
# both specular paths, frame times). One summary line per configuration.
#
#   tools/fig86-compare.sh ROOM_GLTF [WORK]   BIN (default target/release)
set -u
B=${BIN:-$PWD/target/release}; S=$1
W=${2:-/tmp/fig86}; rm -rf $W; mkdir -p $W
summ() { python3 - "$1" "$2" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
for c in r["configurations"]:
    t, d, s, f = c["total"], c["diffuse"], c["specular"], c.get("frame") or {}
    fm = c.get("frame")
    print(f'{sys.argv[2]:28s} {c["name"]:12s} mean ×{t["mean_ratio"]:.4f} rel {t["relative_rmse"]:.4f} diff {d["rmse"]:.4e} spec {s["rmse"]:.4e} (×{(s["mean_ratio"] or 0):.3f}) frame {fm} overhead {c.get("overhead_ms")}')
PY
}
for sc in cornell $S; do
  n=$(basename $sc .gltf)
  for ind in "" "--indirect-only"; do
    [ "$n" = cornell ] && [ -n "$ind" ] && continue
    for solver in nnls nnls-rescaled; do
      d=$W/l8-$n-$solver${ind:+-ind}
      $B/baker --scene $sc --device gpu --passes 512 --texels-per-unit 32 --bases sg12,sg9,ad9 --sg-sharpness 8 --solver $solver \
        --material-maps factors $ind --out $d/bake > $d.bake.log 2>&1 || tail -3 $d.bake.log
      $B/render --scene $sc --bake $d/bake --bases sg12,sg9,ad9 --specular fit --size 480x270 --reference-samples 1024 \
        --reference-noise 0.005 --frames 0 --device gpu --out $d/render > $d.render.log 2>&1 || tail -3 $d.render.log
      summ $d/render/results.json "l8 $n $solver${ind:+ ind}"
    done
  done
done
for sc in cornell $S; do
  n=$(basename $sc .gltf)
  $B/render --scene $sc --passes 512 --texels-per-unit 32 --bases sh1,sh2,sg9,sg12,ad9,ad12 --specular both --size 480x270 \
    --reference-samples 1024 --reference-noise 0.005 --frames 30 --device gpu --out $W/t-$n > $W/t-$n.log 2>&1 || tail -3 $W/t-$n.log
  summ $W/t-$n/results.json "table $n"
done
