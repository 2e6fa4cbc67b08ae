#!/usr/bin/env bash
# `cmake --install BUILD --component python --prefix PREFIX` puts an importable package under
# PREFIX: Python finds it there (site-packages given by PYTHONPATH, as a prefix on sys.path is),
# not in the build tree, and it evaluates a tree.
# Usage: install_test.sh CMAKE BUILD_DIR WORK_DIR PYTHON SITE (relative to the prefix)
set -euo pipefail
cmake=$1 build=$2 work=$3 python=$4 site=$5
rm -rf "$work"
"$cmake" --install "$build" --component python --prefix "$work/prefix" >/dev/null
cd "$work"
PYTHONPATH="$work/prefix/$site" "$python" - "$work/prefix/$site" <<'PY'
import os, sys
import numpy as np
import fuzzycsg
assert os.path.dirname(fuzzycsg.__file__) == os.path.join(sys.argv[1], "fuzzycsg"), fuzzycsg.__file__
tree = fuzzycsg.full_binary_tree(leaves=4, seed=1)
occ = fuzzycsg.eval(tree, np.zeros((3, 3), np.float32))
assert occ.shape == (3,) and np.all((0 <= occ) & (occ <= 1)), occ
for module in ("torch", "reference", "dataset", "generative"):
    assert os.path.exists(os.path.join(sys.argv[1], "fuzzycsg", module + ".py")), module
print("installed fuzzycsg", fuzzycsg.__version__)
PY
