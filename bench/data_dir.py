"""The larger data collection that benchmarks and studies read (CAD meshes, glyphs, OpenSCAD
models, the reference cases of Liu et al.).

It is not part of the repository: its folder is $FUZZYCSG_DATA, or ../shared/data beside the
repository root when that is unset. The test suite never reads it.
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def data_dir():
    return os.environ.get("FUZZYCSG_DATA") or os.path.normpath(os.path.join(ROOT, "..", "shared", "data"))


def data_path(*parts):
    """A path in the collection (not checked: for defaults of command-line options)."""
    return os.path.join(data_dir(), *parts)


def require(path):
    """Exits with status 2 and one line when `path` (a file or folder) is missing."""
    if not os.path.exists(path):
        print(f"{path}: missing; this script reads the data collection at {data_dir()} "
              "(set FUZZYCSG_DATA to its folder)", file=sys.stderr)
        sys.exit(2)
    return path
