#!/usr/bin/env bash
# Peak memory of `crex run` against image size and samples (issue 13): plain crex and a stdlib
# pipeline, with the default --max-memory (1 GiB). Prints a markdown table. Slow (minutes per
# row on 2 cores); never in CI.
#   bash bench/memory_table.sh [path/to/crex]    (ROWS=crex, refining, pipelines or large: one group)
set -euo pipefail
cd "$(dirname "$0")/.."
CREX=${1:-build/release/apps/crex/crex}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
row() {  # label, then crex run arguments
    local label=$1; shift
    /usr/bin/time -v "$CREX" run -q -o "$out/img.exr" "$@" 2>"$out/time.txt" >/dev/null
    local kb secs
    kb=$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$out/time.txt")
    secs=$(awk '/Elapsed \(wall clock\)/ {print $NF}' "$out/time.txt")
    printf '| %s | %d MiB | %s |\n' "$label" "$((kb / 1024))" "$secs"
}
echo "| run | peak memory (max RSS) | wall time |"
echo "|---|---|---|"
rows=${ROWS:-all}
if [ "$rows" = all ] || [ "$rows" = crex ]; then
  for spp in 1 16 256 1024; do row "(TTMRSGD)* builtin:cornell 512x512, $spp spp" --size 512x512 --spp "$spp"; done
  row "(TTMRSGD)* builtin:cornell 1920x1080, 64 spp" --size 1920x1080 --spp 64
fi
if [ "$rows" = large ]; then  # issue 40: frames whose film alone used to pass the limit (an hour)
  for size in 2048x2048 3840x2160; do
    for spp in 1 64; do row "(TTMRSGD)* builtin:cornell $size, $spp spp" --size "$size" --spp "$spp"; done
  done
fi
if [ "$rows" = all ] || [ "$rows" = refining ]; then  # the preview's D answers made again, textured content
  room=build/release/examples/scenes/living_room/scene.gltf
  cat > "$out/ic_rays.pipe" <<'EOF'
pipeline ic_rays_by_saliency {
  preselective { crex "(TTMRSGD)*" spp 4 shadow_rays 4 }
  guidance { sal = threshold(saliency(preview), at 0.7) }
  selective { vary ic_rays 256 .. 1024 by sal }
}
EOF
  row "prog_all.pipe living room 960x540 (1 + up to 16 spp, irradiance cache refined)" stdlib/pipelines/prog_all.pipe --scene "$room" --size 960x540 --seed 1
  row "vary ic_rays 256 .. 1024 by saliency, living room 960x540, --ic --aa 0.3" "$out/ic_rays.pipe" --scene "$room" --size 960x540 --seed 1 --ic --aa 0.3
fi
if [ "$rows" = all ] || [ "$rows" = pipelines ]; then
  for spp in 1 16 256; do row "gold.pipe builtin:cornell 512x512, $spp spp" stdlib/pipelines/gold.pipe --size 512x512 --spp "$spp"; done
  row "prog_dis_all.pipe builtin:cornell 512x512 (1 + up to 16 spp, irradiance cache)" stdlib/pipelines/prog_dis_all.pipe --size 512x512
  row "sel_rp.pipe builtin:cornell 1920x1080 (preview 4 spp + up to 16)" stdlib/pipelines/sel_rp.pipe --size 1920x1080 --spp 4
fi
