#!/usr/bin/env bash
# Installs the Debian 12 packages Lancer builds against, only those missing.
# Runs as root, or through sudo when available.
set -euo pipefail
packages=(
  g++ cmake make git pkg-config
  libglm-dev libtbb-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libopenexr-dev
  libtinyobjloader-dev libcli11-dev libgtest-dev libbenchmark-dev libembree-dev libdraco-dev
  libmeshoptimizer-dev libwebp-dev  # EXT_meshopt_compression, EXT_texture_webp
  libopenmpi-dev openmpi-bin  # optional at build time: mpirun -np N lancer render (one render, many processes)
  clang-14 libclang-rt-14-dev  # `make fuzz`: libFuzzer and the sanitizer runtimes for clang
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then sudo=(); elif command -v sudo >/dev/null; then sudo=(sudo); else
  echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -q
"${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
