#!/bin/sh
# Why a near-converged rpict render and a converged path-traced reference differ (issue 40,
# docs/peer.md, "Why the two earlier references differed"). Four rpict renders of the diffuse
# box at 128x128 with the same near-converged ambient settings, each changing one more thing
# from rpict's defaults toward what crex's reference does, each scored against the committed
# 256x256 reference averaged 2x2 (crex's pixel is a box, so that is the 128x128 reference).
# Never in CI: about 30 minutes on one core.
#   sh bench/peer/reference_gap.sh [RADIANCE_BIN] [OUT]
set -eu
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-$here/.radiance/bin}
out=${2:-$here/../../out/reference_gap}
crex=${CREX:-$here/../../build/release/apps/crex/crex}
mkdir -p "$out"
out=$(cd "$out" && pwd)
export PATH="$bin:$PATH"
(cd "$here" && oconv -f cornell_diffuse.rad) > "$out/diffuse.oct"
oiiotool "$here/refs/cornell_diffuse_256.exr" --resize:filter=box 128x128 --eraseattrib "crex:.*" -o "$out/ref128.exr"
ambient="-ab 8 -aa .1 -ad 1024 -as 512 -ar 32 -lw 1e-4 -lr -10"
view="-vf $here/cornell_diffuse.vf"
render() {  # NAME SIZE RPICT_OPTIONS...
    name=$1 size=$2
    shift 2
    # shellcheck disable=SC2086
    rpict $view -x "$size" -y "$size" "$@" $ambient "$out/diffuse.oct" > "$out/$name.hdr"
}
# 1. rpict's own pixel and source sampling: pixels every 4th, interpolated where contrast is low
#    (-ps 4 -pt .05 -pj .67), sources neither jittered nor subdivided finely (-dj 0 -ds .2).
render e1_defaults 128
# 2. Every pixel its own jittered ray.
render e2_every_pixel 128 -ps 1 -pj .9
# 3. Sources jittered and subdivided (penumbrae sampled, not stepped); its ambient values kept.
render e3_jittered_sources 128 -ps 1 -pj .9 -dj .7 -ds .15 -af "$out/e3.amb"
# 4. 2x2 rays a pixel averaged (crex's box filter), from the same ambient values: only the
#    pixel filter differs from 3.
cp "$out/e3.amb" "$out/e4.amb"
render e4_box_filter_x2 256 -ps 1 -pj .9 -dj .7 -ds .15 -af "$out/e4.amb"
pfilt -1 -e 1 -x /2 -y /2 "$out/e4_box_filter_x2.hdr" > "$out/e4_box_filter.hdr"
for name in e1_defaults e2_every_pixel e3_jittered_sources e4_box_filter; do
    printf '%s: ' "$name"
    "$crex" compare "$out/$name.hdr" "$out/ref128.exr" --metric flip,relmse,rmse
done
