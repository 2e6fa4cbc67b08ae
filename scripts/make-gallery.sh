#!/usr/bin/env bash
# Draws every picture of the modeling gallery into docs/gallery (and the trees each picture
# draws into docs/gallery/trees): builds the release preset's fuzzycsg_gallery and runs it.
#   scripts/make-gallery.sh [--only NAME ...]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release > /dev/null
cmake --build build/release -j "$(nproc)" --target fuzzycsg_gallery
build/release/gallery/fuzzycsg_gallery --out docs/gallery "$@"
