#!/usr/bin/env bash
# Installs what Veach needs to build, test and benchmark, from Debian 12 packages only.
# Does nothing when everything is already there. Run as root (or with sudo available).
#   scripts/install-deps.sh          build + test dependencies
#   scripts/install-deps.sh --bench  also what `make bench` uses (Blender for Cycles timings)
#   scripts/install-deps.sh --fuzz   also what `make fuzz` uses (clang 14 with libFuzzer)
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libembree-dev libtbb-dev libopenimageio-dev libopencolorio-dev
  libtinygltf-dev libstb-dev nlohmann-json3-dev libgtest-dev
  libcli11-dev  # the `veach` command's parser (plugins/cli)
  libmeshoptimizer-dev  # EXT_meshopt_compression (the glTF importer)
  gltfpack  # the importer tests compress the reference scenes with it (-c, -cc)
  libdraco-dev  # KHR_draco_mesh_compression (the glTF importer); tests encode streams with it too
  openimageio-tools opencolorio-tools
  python3 python3-numpy python3-openimageio
  blender  # the add-on's headless test (tests/api/check_blender.py); ~23 MB download, with its
           # glTF exporter (which needs python3-numpy, above)
  assimp-testmodels
  fonts-dejavu-core  # the titles of `make gallery`'s contact sheet
  slurm-wlm munge  # tests/farm/check_slurm_cluster.py starts a single-node cluster (as root)
  zlib1g-dev       # part files (.vpart) are zlib streams
  nodejs           # the Flamenco job type's test (tests/farm/test_flamenco_job.js, node:test)
)
if [[ "${1:-}" == "--bench" ]]; then
  packages+=(blender gnuplot-nox valgrind)  # valgrind: instruction counts of the farm parts
fi
if [[ "${1:-}" == "--fuzz" ]]; then
  packages+=(clang-14 libclang-rt-14-dev)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: run as root (or install sudo): ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
