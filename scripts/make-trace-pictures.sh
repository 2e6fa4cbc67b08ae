#!/usr/bin/env bash
# Traces the paper's letters P, E, b, i (DejaVu Sans Bold, 128x128) with Table 2's defaults
# into docs/trace/GLYPH/, and morphs P -> E and b -> i (the paper's Fig. 14 and 13) into
# docs/trace/morph_A_B/ (nine frames and the animated GIF). Builds the release preset first.
#   scripts/make-trace-pictures.sh
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/data-dir.sh
glyphs=$(fuzzycsg_data_dir glyphs) || exit 2
cmake --preset release > /dev/null
cmake --build build/release -j "$(nproc)" --target fuzzycsg
fuzzycsg=build/release/apps/fuzzycsg/fuzzycsg
for g in U0050_P U0045_E U0062_b U0069_i; do
  "$fuzzycsg" trace "$glyphs/DejaVuSans-Bold_$g.png" -o "docs/trace/${g#*_}" --seed 1
done
"$fuzzycsg" morph "$glyphs/DejaVuSans-Bold_U0050_P.png" "$glyphs/DejaVuSans-Bold_U0045_E.png" \
  -o docs/trace/morph_P_E --frames 9 --delay 150 --seed 1
"$fuzzycsg" morph "$glyphs/DejaVuSans-Bold_U0062_b.png" "$glyphs/DejaVuSans-Bold_U0069_i.png" \
  -o docs/trace/morph_b_i --frames 9 --delay 150 --seed 1
# The frames side by side, for pages that do not animate GIFs (python3-pil).
for m in morph_P_E morph_b_i; do
  /usr/bin/python3 - "docs/trace/$m" <<'PY'
import sys
from PIL import Image
d = sys.argv[1]
frames = [Image.open(f"{d}/frames/frame_{i:03d}.png").convert("L") for i in range(9)]
w, h = frames[0].size
strip = Image.new("L", (9 * w // 2, h // 2), 255)
for i, f in enumerate(frames):
    strip.paste(f.resize((w // 2, h // 2)), (i * w // 2, 0))
strip.save(f"{d}/strip.png")
PY
done
