#!/usr/bin/env bash
# Every GPU test binary of the workspace, run whole on a machine with a real GPU (the
# device: an NVIDIA H100/H200 with no Rust toolchain), one summary line per binary.
#
#   tools/device-tests.sh list     the GPU test binaries, one "<package>/<test>" a line
#   tools/device-tests.sh pack     here: builds the release test binaries and the
#                                  workspace's binaries, strips them and packs them with
#                                  ../shared's data and the Debian packages the device
#                                  lacks (Vulkan/EGL loaders, glslang) into target/device/
#   tools/device-tests.sh run      there (repo root, target/device carried): unpacks, puts
#                                  the checkout where the binaries' compiled-in paths point,
#                                  runs each binary with SBF_REQUIRE_GPU=1 SBF_REQUIRE_PROBES=1
#                                  from its package's folder (as cargo does), and prints
#                                  "PASS|FAIL <binary> <passed> passed <failed> failed <s> s"
#                                  per binary and the adapter; logs in target/device/logs (and
#                                  $OUT/device-test-logs.tar.gz where $OUT is set)
#   DEVICE_PACK: the pack's folder (default target/device); DEVICE_TESTS: which binaries
#   (`pack`: only those are packed, a smaller and quicker pack; `run`: in that order);
#   DEVICE_TEST_TIMEOUT: seconds per binary (default 600).
#
# Test binaries find their data and the binaries they invoke through absolute paths fixed at
# build time (CARGO_MANIFEST_DIR, CARGO_BIN_EXE_*), so `run` links this checkout to the path
# it was packed at, and the data beside it as ../shared. Extra arguments after `run` go to
# every test binary (a filter, --test-threads).
set -euo pipefail
cd "$(dirname "$0")/.."
pack=${DEVICE_PACK:-target/device}

# The test binaries that reach a GPU (their sources lease the device, make one, or run a
# command on it): <package folder>/<test>.
gpu_tests() {
  grep -l -E 'common::gpu|shaders::gpu::|Gpu::(new|hardware|logical)|"--device", "gpu"|gpu-cost|fn gpu\(' \
    baker/tests/*.rs shaders/tests/*.rs probes/tests/*.rs tests/tests/*.rs | sed -E 's#^([a-z]+)/tests/#\1/#; s#\.rs$##'
}

case "${1:-}" in
list)
  gpu_tests
  ;;
pack)
  rm -rf "$pack" && mkdir -p "$pack/bin" "$pack/deb"
  # (The binaries the tests run are those `cargo test` builds: `cargo build --bins` unifies
  # other features and would build others.)
  # Test executables and their packages, from cargo's own report.
  cargo test --workspace --release --no-run --message-format=json 2>/dev/null \
    | python3 -c '
import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["kind"] == ["test"]:
        pkg = m["manifest_path"].split("/")[-2]
        print(pkg + "/" + m["target"]["name"], m["executable"], m["manifest_path"])
' >"$pack/all-tests.txt"
  wanted=$(gpu_tests)
  if [ -n "${DEVICE_TESTS:-}" ]; then
    for t in $DEVICE_TESTS; do grep -qx "$t" <<<"$wanted" || { echo "no GPU test binary $t" >&2; exit 2; }; done
    wanted=$(tr ' ' '\n' <<<"$DEVICE_TESTS")
  fi
  : >"$pack/tests.txt"
  while read -r name exe manifest; do
    grep -qx "$name" <<<"$wanted" || continue
    strip -o "$pack/bin/${name//\//__}" "$exe"
    echo "$name ${name//\//__} $(dirname "$manifest")" >>"$pack/tests.txt"
  done <"$pack/all-tests.txt"
  # The workspace binaries those tests run (CARGO_BIN_EXE_*).
  for b in $(cd "$pack" && grep -ohE 'CARGO_BIN_EXE_[a-z_]+' $(sed -E 's#^([a-z]+)/(.*)#../../\1/tests/\2.rs#' <<<"$wanted") ../../*/tests/common/*.rs | sort -u | sed 's/CARGO_BIN_EXE_//'); do
    strip -o "$pack/bin/$b" "target/release/$b"
  done
  echo "$PWD" >"$pack/root.txt"
  # One solid stream with a 64 MiB window: the binaries share most of their code (≈ 230 MB
  # stripped → ≈ 22 MB; the device call carries at most 64 MiB).
  (cd "$pack/bin" && tar cf - --sort=name . | xz -9e -T1 >../bin.tar.xz) && rm -rf "$pack/bin"
  mkdir -p "$pack/shared" && cp -r ../shared/probes ../shared/hdri ../shared/scenes "$pack/shared/"
  # The loaders (libvulkan, EGL/GL dispatch) and glslang for the HLSL/GLSL parity runs.
  mkdir -p /tmp/amd64/partial
  o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
  # shellcheck disable=SC2086
  apt-get $o update -qq && (cd "$pack/deb" && apt-get $o download libvulkan1 libglvnd0 libegl1 libopengl0 libgl1 libglx0 libgles2 glslang-tools spirv-tools >/dev/null)
  du -sh "$pack"
  echo "packed $(wc -l <"$pack/tests.txt") GPU test binaries: carry target/device"
  ;;
run)
  shift
  [ -f "$pack/tests.txt" ] || { echo "no $pack/tests.txt: run '$0 pack' where the toolchain is, and carry $pack" >&2; exit 2; }
  for f in "$pack"/deb/*.deb; do dpkg -x "$f" /; done
  ldconfig
  if [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
    export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
    export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
  fi
  root=$(cat "$pack/root.txt")
  if [ "$root" != "$PWD" ]; then
    [ -e "$root" ] && [ ! -L "$root" ] && { echo "$root exists here and is not this checkout" >&2; exit 2; }
    mkdir -p "$(dirname "$root")" && ln -sfn "$PWD" "$root"
  fi
  [ -e "$(dirname "$root")/shared" ] || ln -sfn "$PWD/$pack/shared" "$(dirname "$root")/shared"
  mkdir -p target/release "$pack/run"
  [ "$pack/run/.unpacked" -nt "$pack/bin.tar.xz" ] || { tar xJf "$pack/bin.tar.xz" -C "$pack/run" && touch "$pack/run/.unpacked"; }
  for b in baker render slc probes; do [ -f "$pack/run/$b" ] && cp "$pack/run/$b" target/release/; done
  logs=$pack/logs
  mkdir -p "$logs"
  export SBF_REQUIRE_GPU=1 SBF_REQUIRE_PROBES=1
  status=0
  # DEVICE_TESTS: only these binaries ("<package>/<test> …"), in that order.
  order=$pack/tests.txt
  if [ -n "${DEVICE_TESTS:-}" ]; then
    order=$pack/tests-chosen.txt
    for t in $DEVICE_TESTS; do grep "^$t " "$pack/tests.txt" || echo "no GPU test binary $t" >&2; done >"$order"
  fi
  while read -r name file dir; do
    start=$(date +%s.%N)
    set +e
    exe="$PWD/$pack/run/$file"
    # Each binary within DEVICE_TEST_TIMEOUT seconds (default 600): one that hangs is
    # reported, not waited for.
    (cd "$dir" && timeout "${DEVICE_TEST_TIMEOUT:-600}" "$exe" "$@") >"$logs/${file}.log" 2>&1
    rc=$?
    set -e
    secs=$(python3 -c "import time; print(f'{time.time() - $start:.1f}')")
    passed=$(grep -oE '[0-9]+ passed' "$logs/${file}.log" | awk '{s += $1} END {print s + 0}')
    failed=$(grep -oE '[0-9]+ failed' "$logs/${file}.log" | awk '{s += $1} END {print s + 0}')
    if [ "$rc" = 0 ]; then verdict=PASS; else verdict=FAIL; status=1; fi
    printf '%s %-26s %4s passed %3s failed %7s s\n' "$verdict" "$name" "$passed" "$failed" "$secs"
    [ "$rc" = 0 ] || grep -E "panicked|^test .* FAILED|error" "$logs/${file}.log" | head -5 | sed 's/^/    /'
  done <"$order"
  grep -h -oE "[^:]*\((Vulkan|Gl), [^)]*\)" "$logs"/*.log | sed 's/.* on //; s/^adapter: //' | sort | uniq -c | sort -rn | head -3
  # The logs, one file ($OUT brings back few files).
  [ -z "${OUT:-}" ] || tar czf "$OUT/device-test-logs.tar.gz" -C "$pack" logs
  exit $status
  ;;
*)
  sed -n '2,20p' "$0"
  exit 2
  ;;
esac
