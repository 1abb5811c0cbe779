#!/usr/bin/env bash
# The inputs of docs/distributed.md's model, measured on one GPU: per atlas size (room-1m at
# the texel densities in SIZES), the single bake with the defaults and with checkpoints and
# dispatch batching off (the overheads apart), its 4 shards one after another (pass time,
# wall time, shard-file and checkpoint bytes per item; then again with both off: pass time
# and peak memory), and their merge (wall time, bytes read). One line per run.
#
#   tools/distributed-model.sh OUT        (BIN: folder of `baker`, default target/release;
#                                          SIZES, default "55 110"; PASSES, default 64)
set -euo pipefail
out=$1
bin=${BIN:-target/release}
passes=${PASSES:-64}
mkdir -p "$out"
# shellcheck disable=SC2054 # the commas are baker arguments
common=(--scene room-1m --bases sh2,ad9 --probes 0,0,0 --passes "$passes" --denoise off --device gpu --preview-width 64)
# Wall seconds of a command (its stderr to a log).
wall() {
  local log=$1
  shift
  local t0 t1
  t0=$(date +%s.%N)
  "$@" 2>"$log" >/dev/null
  t1=$(date +%s.%N)
  awk "BEGIN { printf \"%.2f\", $t1 - $t0 }"
}
# A value of bake.json: KEY (a jq-less grep for "key": number).
field() { grep -o "\"$2\": *[0-9.e+-]*" "$1" | head -1 | sed 's/.*: *//'; }
for s in ${SIZES:-55 110}; do
  d=$out/s$s
  rm -rf "$d" && mkdir -p "$d"
  w=$(wall "$d/single.log" "$bin/baker" "${common[@]}" --texels-per-unit "$s" --out "$d/single")
  items=$(grep -o '[0-9]* valid texels' "$d/single.log" | head -1 | cut -d' ' -f1)
  echo "size $s: single bake (defaults: checkpoint every 32, dispatches of 16 ms): wall $w s, passes $(field "$d/single/bake.json" lightmap_passes) s, bake $(field "$d/single/bake.json" seconds) s, $items texels; checkpoint $(stat -c %s "$d/single/lightmap.checkpoint") bytes"
  w=$(wall "$d/plain.log" "$bin/baker" "${common[@]}" --texels-per-unit "$s" --checkpoint-every 0 --batch-ms 0 --out "$d/plain")
  echo "size $s: single bake (no checkpoint, one dispatch per pass): wall $w s, passes $(field "$d/plain/bake.json" lightmap_passes) s, bake $(field "$d/plain/bake.json" seconds) s"
  for i in 0 1 2 3; do
    w=$(wall "$d/shard$i.log" "$bin/baker" "${common[@]}" --texels-per-unit "$s" --shard "$i/4" --checkpoint-every 32 --out "$d/shards")
    p=$(grep -o 'lightmap: [0-9]* passes in [0-9.]* s' "$d/shard$i.log" | tail -1 | awk '{print $5}')
    n=$(grep -o 'shard [0-9] of 4: [0-9]* of' "$d/shard$i.log" | head -1 | awk '{print $5}')
    echo "size $s: shard $i/4: $n items, wall $w s, passes $p s, shard file $(stat -c %s "$d/shards/shard-$i-of-4.sbfshard") bytes, checkpoint $(stat -c %s "$d/shards/lightmap.shard-$i-of-4.checkpoint") bytes"
  done
  # The shards' pass time and memory apart from checkpoints and batching (as the plain bake).
  for i in 0 1 2 3; do
    w=$(wall "$d/plain$i.log" "$bin/baker" "${common[@]}" --texels-per-unit "$s" --shard "$i/4" --checkpoint-every 0 --batch-ms 0 --out "$d/shards-plain")
    p=$(grep -o 'lightmap: [0-9]* passes in [0-9.]* s' "$d/plain$i.log" | tail -1 | awk '{print $5}')
    echo "size $s: shard $i/4 (no checkpoint, one dispatch per pass): wall $w s, passes $p s, peak memory $(field "$d/shards-plain/shard-$i-of-4.json" peak_memory_bytes) bytes (the single bake's: $(field "$d/plain/bake.json" peak_memory_bytes))"
  done
  rm -rf "$d/shards-plain"
  w=$(wall "$d/merge.log" "$bin/baker" merge "$d/merged" "$d"/shards/shard-*-of-4.sbfshard)
  echo "size $s: merge of 4 shards ($(cat "$d"/shards/shard-*-of-4.sbfshard | wc -c) bytes): wall $w s; equal to the single bake: $(cmp -s "$d/merged/sh2_00.exr" "$d/single/sh2_00.exr" && echo yes || echo no)"
done
