#!/bin/sh
# Builds RADIANCE's rpict, oconv, pfilt and mkpmap from a checkout of NREL/Radiance (the peer of issue 40,
# docs/peer.md), without its GUI tools. Never run in CI: the peer is built by hand.
#   sh bench/peer/build_rpict.sh RADIANCE_SOURCE [PREFIX]
# PREFIX (default bench/peer/.radiance) gets bin/rpict, bin/oconv, bin/xform (oconv runs it for
# !xform), bin/pfilt (filters rpict's oversampled images down), bin/mkpmap (photon maps) and lib/ (RADIANCE's function
# files, which rpict finds through RAYPATH=PREFIX/lib).
set -eu
src=${1:?usage: build_rpict.sh RADIANCE_SOURCE [PREFIX]}
prefix=${2:-$(dirname "$0")/.radiance}
mkdir -p "$prefix"
prefix=$(cd "$prefix" && pwd)
build="$prefix/build"
# RADIANCE's CMakeLists copies test/ into the build; a source exported without its test scenes
# (large files a snapshot may lack) gets an empty one.
[ -d "$src/test" ] || mkdir "$src/test"
cmake -S "$src" -B "$build" -DCMAKE_BUILD_TYPE=Release -DBUILD_HEADLESS=ON -DBUILD_SHARED_LIBS=OFF >/dev/null
cmake --build "$build" --target rpict oconv xform pfilt mkpmap -j "$(nproc)"
mkdir -p "$prefix/bin" "$prefix/lib"
for tool in rpict oconv xform pfilt mkpmap; do cp "$(find "$build" -name "$tool" -type f -perm -u+x | head -n 1)" "$prefix/bin/"; done
cp "$src"/src/cal/cal/*.cal "$prefix/lib/"
echo "built rpict, oconv, xform, pfilt and mkpmap in $prefix/bin: put it first on PATH; set RAYPATH=.:$prefix/lib"
