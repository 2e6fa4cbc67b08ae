#!/usr/bin/env bash
# Installs the Debian packages fuzzycsg needs to build, test and benchmark.
# Idempotent: packages already present are not touched, and apt is not called at all
# when nothing is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  clang clang-format libclang-rt-14-dev
  libeigen3-dev libtbb-dev nlohmann-json3-dev libcli11-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev libhwy-dev
  libassimp-dev libembree-dev libstb-dev libnanoflann-dev libgraphviz-dev libgif-dev
  libcairo2-dev fonts-dejavu-core libcgal-dev
  openscad
  libopencsg-dev libglew-dev libgl-dev libegl-dev libegl-mesa0 libgl1-mesa-dri
  # The Python module (built by pybind11 for Debian's python3) and its tests; OpenBLAS so that
  # PyTorch's matrix products do not run on the reference BLAS.
  # matplotlib draws the generative model's pictures (and bench/fig12_pareto.py's).
  python3 python3-dev pybind11-dev python3-numpy python3-pytest python3-torch libopenblas0-pthread
  python3-matplotlib
  # Slurm and munge: the batch verb's test starts a single-node cluster on localhost
  # (tests/apps/slurm_cluster.sh); no service is enabled or configured in /etc.
  slurm-wlm munge
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=()
if [[ $(id -u) -ne 0 ]]; then
  sudo=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
