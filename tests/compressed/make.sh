#!/usr/bin/env bash
# Remakes the compressed test files of this folder (README.md says what each
# is). Needs Node.js and npm (the npm registry) and cargo; run from anywhere:
#   bash tests/compressed/make.sh
# Tools, pinned: @gltf-transform/cli 4.5.1 (Draco through Google's draco3dgltf
# encoder, meshopt through meshoptimizer's), gltfpack 1.3 (meshoptimizer's own
# packer).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$here/../.."
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm init -y >/dev/null &&
  npm install --silent @gltf-transform/cli@4.5.1 @gltf-transform/core@4.5.1 \
    @gltf-transform/extensions@4.5.1 @gltf-transform/functions@4.5.1 gltfpack@1.3.0 >/dev/null)
gt="$work/node_modules/.bin/gltf-transform"
gp="$work/node_modules/.bin/gltfpack"

# Sources: CesiumMan without its texture, and the generated museum room.
cp "$here/strip_textures.mjs" "$work/"
node "$work/strip_textures.mjs" "$repo/assets/CesiumMan.glb" "$work/cesium.glb"
(cd "$repo" && cargo run --quiet --example export_room -- museum "$work/room.glb")

for name in cesium room; do
  # KHR_draco_mesh_compression, edgebreaker (reorders vertices and triangles),
  # positions quantized to 14 bits (the tool's default).
  "$gt" draco "$work/$name.glb" "$here/${name}_draco.glb"
  # EXT_meshopt_compression with KHR_mesh_quantization (gltf-transform's
  # "high" level: octahedral, quaternion and exponential filters).
  "$gt" meshopt "$work/$name.glb" "$here/${name}_meshopt.glb"
  # gltfpack -cc: meshopt with the packer's own layout, quantization and filters.
  "$gp" -i "$work/$name.glb" -o "$here/${name}_gltfpack.glb" -cc
done
# The character only: Draco's sequential method (vertex and triangle order
# kept, another decoder path) and KHR_mesh_quantization alone.
"$gt" draco --method sequential "$work/cesium.glb" "$here/cesium_draco_sequential.glb"
"$gt" quantize "$work/cesium.glb" "$here/cesium_quantized.glb"
ls -l "$here"/*.glb
