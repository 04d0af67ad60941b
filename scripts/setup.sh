#!/usr/bin/env bash
# Installs the Debian packages pleat needs (only those missing) and builds pleat in Release under build/
# (`cmake --preset release && cmake --build --preset release`).
# Usage: scripts/setup.sh            (as root, or with sudo available)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake ninja-build lld make g++ pkg-config  # the build: CMakePresets.json (Ninja); lld links
          libopenmesh-dev libglm-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev
          libtinygltf-dev nlohmann-json3-dev libtbb-dev libembree-dev libstb-dev libcli11-dev
          zlib1g-dev libgtest-dev libgmock-dev librapidcheck-dev libbenchmark-dev python3-matplotlib
          clang libfuzzer-14-dev clang-format clang-tidy  # scripts/check_sanitized.sh, the format and function-size checks
          openmpi-bin libopenmpi-dev  # mpirun -np N pleat visibility|shade (cli/world.hpp; PLEAT_MPI)
          pybind11-dev python3-dev python3-numpy python3-pytest python3-tqdm  # the Python module (python/), its tests
          python3-setuptools python3-pip python3-venv  # pip install --no-build-isolation . (pyproject.toml)
          libjs-three chromium  # pleat view's three.js, and the browser its test runs headless
          blender)  # the add-on's test (tests/blender/bake_test.py) runs Blender headless
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "pleat setup: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Node.js and npm (the glTF validator in the tests): Debian's, unless a node with npm is already installed
# (a NodeSource node bundles npm, and Debian's npm would conflict with it).
if ! command -v npm >/dev/null || ! command -v node >/dev/null; then
  echo "pleat setup: installing nodejs npm" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
fi
# The Khronos glTF-Validator from the npm registry, pinned, under build/npm (tests/tools/validate_gltf.mjs).
if [ ! -f build/npm/node_modules/gltf-validator/package.json ]; then
  echo "pleat setup: installing gltf-validator from npm" >&2
  npm install --no-save --silent --prefix build/npm gltf-validator@2.0.0-dev.3.10 >/dev/null
fi

scripts/build_preset.sh release
