#!/usr/bin/env bash
# One entry point for building crex on a fresh Debian machine (as root, or with sudo).
#
#   tools/dev.sh demo     install what is missing, build the tool (Release), run the main job
#   tools/dev.sh test     install what is missing, build (Release), run every test, then
#                         rebuild with ASan+UBSan at -O1 and rerun the fast labels
#   tools/dev.sh build    install what is missing and build (Release) only
#   tools/dev.sh fuzz [S] [TARGET...]  build the libFuzzer targets with clang; run each (or the
#                         TARGETs named, e.g. gltf_fuzzer) for S seconds (120)
#
# Build trees: build/release, build/asan, build/fuzz. Safe to rerun: installs only what is
# missing and rebuilds incrementally. JOBS=n limits the build's parallel jobs (all cores).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
JOBS=${JOBS:-$(nproc)}

log() { printf '\n== %s\n' "$*" >&2; }

install_packages() {
  local wanted=() missing=()
  mapfile -t wanted < <(grep -v '^\s*#' "$ROOT/tools/debian-packages.txt" | sed '/^\s*$/d')
  wanted+=("$@")
  for p in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    log "installing: ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo=sudo
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
}

# build_release [TARGET...]: everything, or only the targets named (the demo needs the tool
# and its image plugin, not the tests and benchmarks).
build_release() {
  log "configure + build (Release${*:+: $*})"
  cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build/release -j "$JOBS" ${*:+--target "$@"}
}

run_tests() {
  log "tests (Release, all labels)"
  (cd build/release && ctest --output-on-failure -j "$JOBS")
  log "configure + build (ASan+UBSan, -O1)"
  # -g1: line tables are all the sanitizers' stack traces need (full debug info only makes the
  # compiles and links slower); and only the targets the fast labels run.
  cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS=-O1 -DCMAKE_CXX_FLAGS_DEBUG=-g1 \
        -DCREX_SANITIZE=ON -DCREX_BENCH=OFF >/dev/null
  cmake --build build/asan -j "$JOBS" --target crex_fast_tests
  log "tests (ASan+UBSan, fast labels)"
  # Left to the Release stage: the six slowest tests under the sanitizers (about 5 of their 18 CPU
  # minutes), each a sweep whose code paths the faster tests already put through them: every
  # command of the docs, 100 random crex strings through the tool (crex_check_fuzzer does that
  # under the sanitizers, `tools/dev.sh fuzz`), two convergence curves of the irradiance cache,
  # and two comparisons of the cache's glossy light with 2048- and 256-spp path-traced gold (43 and
  # 50 s under the sanitizers against 3.4 and 3.8 s in Release; the cache's glossy light runs
  # under them in TexturedSceneCli.RunReportsTheTextureCache, the living room cached). And Ctrl-C
  # during a reference, which renders twice what runs before the signal (the signal's handler
  # runs under them in the other CrexProgressCli tests).
  local sanitizer_skips='^(Docs\.EveryCommandInTheDocsRuns|CrexProgressCli\.CtrlCKeepsAReferencesSamplesSoFar|CrexCheckCli\.RandomArgumentsExitZeroOrOne|IrradianceCache\.ConvergesToPathTracingWithTheSameBouncesAsAaFalls|IrradianceCache\.OnTheCornellBoxItApproachesPathTracedGoldAsAaFalls|IrradianceCache\.AGlossyLobeAsWideAsADiffuseOneAsksTheCacheToo|IrradianceCache\.ARecordsRaysTakeTheGlossyLightOfWhatTheyMeetToo)$'
  # intercept_tls_get_addr=0: the leak check at exit walks the dynamic TLS of the dlopen'd
  # image plugin (libcrex_oiio.so) and LSan's tracer crashed there in about one run in five
  # ("Tracer caught signal 11", as in google/sanitizers#1353); without the interception,
  # 0 of 60 runs failed.
  # new_delete_type_mismatch=0: OpenImageIO 2.4's TextureSystem::destroy deletes its
  # implementation through the base class, so ASan sees a sized delete of 1 byte for an object of
  # 184 (inside libOpenImageIO, not crex; the leak check still finds nothing left behind).
  (cd build/asan && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0:new_delete_type_mismatch=0 \
      LSAN_OPTIONS=suppressions="$ROOT/tools/lsan.supp" \
      UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      ctest --output-on-failure -j "$JOBS" -L '^(unit|diag|cli|numerics)$' -E "$sanitizer_skips")
}

run_demo() {
  local crex=build/release/apps/crex/crex
  log "check the thesis's crex expressions and the normative pipeline"
  "$crex" check stdlib/crex/thesis.crex
  "$crex" check examples/pipelines/cornell_prog.pipe
  log "its execution plan, pruned for the corridor (out/cornell_prog.plan.svg)"
  mkdir -p out
  "$crex" plan examples/pipelines/cornell_prog.pipe -o out/cornell_prog.plan.svg
  # Without its 10 s budget: on a slow or busy machine the budget went to the preview's rays and
  # no pixel got more than the 4 samples of the preview, so the demo showed nothing selective.
  log "main job: the normative pipeline - preview, guidance maps, then selective rendering: 4 to 25 samples a pixel by importance"
  "$crex" run examples/pipelines/cornell_prog.pipe --no-budget -o out/cornell_prog.exr -o out/cornell_prog.png
  log "look at: out/cornell_prog.png, out/maps/samples_per_pixel.png (where the samples went), the report out/report/index.html"
}

run_fuzz() {
  local seconds=${1:-120}
  shift || true
  local only=("$@")
  install_packages clang-14 libclang-rt-14-dev
  log "configure + build (libFuzzer, clang-14)"
  cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_CXX_COMPILER=clang++-14 -DCREX_FUZZ=ON -DCREX_BENCH=OFF >/dev/null
  local targets=(crex_check_fuzzer scene_load_fuzzer pipeline_fuzzer plan_read_fuzzer ic_file_fuzzer view_fuzzer obj_fuzzer profile_fuzzer
                 profile_numbers_fuzzer ic_records_fuzzer gltf_fuzzer mtl_fuzzer camera_path_fuzzer exr_read_fuzzer
                 png_read_fuzzer)
  cmake --build build/fuzz -j "$JOBS" --target "${targets[@]}"
  rm -rf build/fuzz/corpus && mkdir -p build/fuzz/corpus/{crex,scene,pipeline,plan,ic,view,obj,profile,profile_numbers,ic_records,gltf,mtl,camera_path,exr,png}
  grep -v '^#' stdlib/crex/thesis.crex | sed '/^$/d' | split -l 1 - build/fuzz/corpus/crex/seed_
  # Seeds keep their directory in their name: three scene.json files are three seeds.
  for f in examples/scenes/*/scene.json examples/scenes/*/scene.rad tests/fuzz/radiance_seed.rad tests/fuzz/radiance_patterns_seed.rad; do
    [ -f "$f" ] && cp "$f" "build/fuzz/corpus/scene/$(echo "$f" | tr '/' '_')"
  done
  printf 'materials = basic.mat\nscene = room.rad "!xform -n a -a 3 -t 1 0 0 chair.rad"\nview = def -vf inside.vf -vh 60\n' \
    > build/fuzz/corpus/scene/seed_project.rif
  for f in stdlib/pipelines/*.pipe examples/pipelines/*.pipe; do cp "$f" "build/fuzz/corpus/pipeline/$(echo "$f" | tr '/' '_')"; done
  for f in tests/golden/plans/*.plan.json; do cp "$f" build/fuzz/corpus/plan/; done
  # Irradiance cache seeds with the fuzzer's settings (--ad 16 --ab 1, no caustic map), when a
  # crex is built.
  if [ -x build/release/apps/crex/crex ]; then
    for size in 2x2 4x4; do
      build/release/apps/crex/crex run --size "$size" --spp 1 --ad 16 --ab 1 --caustic-photons 0 -q -o build/fuzz/corpus/seed.exr \
          --ic-file "build/fuzz/corpus/ic/seed_$size"
    done
    # One whose records carry rays of their own (`vary ic_rays`: the file's optional byte string).
    printf 'pipeline q {\n preselective { crex "(TTMRSGD)*" spp 1 }\n guidance { c = constant(1) }\n selective { vary ic_rays 16 .. 32 by c }\n}\n' \
      > build/fuzz/corpus/seed.pipe
    build/release/apps/crex/crex run build/fuzz/corpus/seed.pipe --size 4x4 --ab 1 --caustic-photons 0 -q -o build/fuzz/corpus/seed.exr \
        --ic-file build/fuzz/corpus/ic/seed_rays
    rm -f build/fuzz/corpus/seed.pipe
    # The records of a cache with ic_records_fuzzer's settings (--ad 16 --ab 2), behind its
    # one leading byte: the CBOR byte string after "records".
    build/release/apps/crex/crex run --size 4x4 --spp 1 --ad 16 --ab 2 --caustic-photons 0 -q -o build/fuzz/corpus/seed.exr \
        --ic-file build/fuzz/corpus/seed.ic
    python3 - build/fuzz/corpus/seed.ic build/fuzz/corpus/ic_records/seed_4x4 <<'PY'
import struct, sys
d = open(sys.argv[1], 'rb').read()
i = d.find(b'records') + 7
n, start = (struct.unpack('>H', d[i+1:i+3])[0], i + 3) if d[i] == 0x59 else (struct.unpack('>I', d[i+1:i+5])[0], i + 5)
open(sys.argv[2], 'wb').write(b'\0' + d[start:start + min(n, 120 * 8)])
PY
    rm -f build/fuzz/corpus/seed.exr build/fuzz/corpus/seed.ic
    # EXR files as crex writes them: the composite alone, with component layers, a one-channel map.
    build/release/apps/crex/crex run --size 4x3 --spp 1 --caustic-photons 0 -q -o build/fuzz/corpus/exr/seed_rgb.exr
    build/release/apps/crex/crex run --size 3x2 --spp 1 --caustic-photons 0 -q --components -o build/fuzz/corpus/exr/seed_layers.exr \
        --maps build/fuzz/corpus/maps
    cp build/fuzz/corpus/maps/samples_per_pixel.exr build/fuzz/corpus/exr/seed_map.exr
    # PNG files as crex writes them (RGB, a grey map) and small textures of other colour types.
    build/release/apps/crex/crex run --size 4x3 --spp 1 --caustic-photons 0 -q -o build/fuzz/corpus/png/seed_rgb.png
    cp build/fuzz/corpus/maps/samples_per_pixel.png build/fuzz/corpus/png/seed_map.png && rm -rf build/fuzz/corpus/maps
    find build/release/examples -name '*.png' -size -16k | head -4 | while read -r f; do cp "$f" "build/fuzz/corpus/png/$(echo "$f" | tr '/' '_')"; done
  fi
  cp examples/scenes/cornell/scene.vf build/fuzz/corpus/view/
  printf 'rpict -vtv -vp 1 2 3 -vd 0 0 -1 -vu 0 1 0 -vh 60 -vv 45 -vs 0 -vl 0\n' > build/fuzz/corpus/view/seed_options
  printf 'mtllib fuzz.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\nvn 0 0 1\nusemtl lamp\nf 1//1 2//1 3//1\nusemtl glass\nf 2 4 3\n#mtl\nnewmtl lamp\nKe 5 5 5\nnewmtl glass\nKd 0.9 0.9 0.9\nd 0.5\nNi 1.5\nillum 7\n' \
    > build/fuzz/corpus/obj/seed_triangles
  # glTF seeds: Debian's assimp-testmodels (valid and broken files), when installed.
  find /usr/share/assimp/models/glTF2 \( -name '*.gltf' -o -name '*.glb' \) -size -64k 2>/dev/null |
    while read -r f; do cp "$f" "build/fuzz/corpus/gltf/$(echo "$f" | tr '/' '_')"; done
  # One of crex's own: vertex colours and an image in a data URI of a type tinygltf does not list.
  cp tests/fuzz/gltf_seed.gltf build/fuzz/corpus/gltf/
  printf 'newmtl a\nKd 0.8 0.6 0.4\nKs 0.2 0.2 0.2\nNs 100\nmap_Kd -s 2 3 1 -o 0.5 0 0 -clamp on tex/wood.png\nmap_Ks tex/wood.png\nmap_Ns tex/wood.png\nbump -bm 2 tex/wood.png\nnorm tex/wood.png\nnewmtl b\nKd 0.3 0.6 0.2\nmap_d -imfchan m tex/leaf.png\nnewmtl c\nKe 1 1 1\nmap_Ke -colorspace sRGB tex/screen.png\nnewmtl d\nd 0.5\nNi 1.5\nillum 7\n' \
    > build/fuzz/corpus/mtl/seed_textures
  printf '{"format": "crex-profile", "version": 1, "full_render_seconds": 1.33, "seconds_per_ray": {"D": 3.5e-06, "T": 2.7e-06, "camera": 4.1e-07}}\n' \
    > build/fuzz/corpus/profile/seed_profile
  head -c 96 /dev/urandom > build/fuzz/corpus/profile_numbers/seed_random
  cp examples/paths/*.json build/fuzz/corpus/camera_path/
  printf 'rpict -vtv -vp 0 1.5 3 -vd 0 0 -1 -vu 0 1 0 -vh 60 -vv 45\n-vp 0 1.5 2.9 -vd 0.1 0 -1 -vu 0 1 0\n' > build/fuzz/corpus/camera_path/seed_views
  local -A corpus=([crex_check_fuzzer]=crex [scene_load_fuzzer]=scene [pipeline_fuzzer]=pipeline [plan_read_fuzzer]=plan
                   [ic_file_fuzzer]=ic [view_fuzzer]=view [obj_fuzzer]=obj [profile_fuzzer]=profile
                   [profile_numbers_fuzzer]=profile_numbers [ic_records_fuzzer]=ic_records [gltf_fuzzer]=gltf [mtl_fuzzer]=mtl
                   [camera_path_fuzzer]=camera_path [exr_read_fuzzer]=exr [png_read_fuzzer]=png)
  local -A max_len=([crex_check_fuzzer]=512 [scene_load_fuzzer]=8192 [pipeline_fuzzer]=4096 [plan_read_fuzzer]=16384
                    [ic_file_fuzzer]=65536 [view_fuzzer]=512 [obj_fuzzer]=4096 [profile_fuzzer]=2048
                    [profile_numbers_fuzzer]=256 [ic_records_fuzzer]=4096 [gltf_fuzzer]=65536 [mtl_fuzzer]=4096
                    [camera_path_fuzzer]=4096 [exr_read_fuzzer]=16384 [png_read_fuzzer]=16384)
  # Every target runs even when one finds a crash (its input is written as crash-*); the
  # script fails at the end if any did.
  local failed=()
  mkdir -p build/fuzz/artifacts
  for t in "${targets[@]}"; do
    if ((${#only[@]})) && [[ ! " ${only[*]} " == *" $t "* ]]; then continue; fi
    log "fuzzing ${t} for ${seconds}s"
    local dict=()
    [ "$t" = scene_load_fuzzer ] && dict=(-dict=tests/fuzz/radiance.dict)
    build/fuzz/tests/fuzz/"$t" "${dict[@]}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len="${max_len[$t]}" \
        -artifact_prefix="build/fuzz/artifacts/${t}-" -print_final_stats=1 "build/fuzz/corpus/${corpus[$t]}" || failed+=("$t")
  done
  if ((${#failed[@]})); then
    log "found inputs that fail: ${failed[*]} (build/fuzz/artifacts/)"
    return 1
  fi
}

case "${1:-}" in
  demo) install_packages; build_release crex; run_demo ;;
  test) install_packages; build_release; run_tests ;;
  build) install_packages; build_release ;;
  fuzz) shift; run_fuzz "$@" ;;
  *) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
