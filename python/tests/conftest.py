"""Shared fixtures: the source tree (examples, tests/data) and the fuzzycsg program, whose error
messages the module's exceptions must repeat."""

import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("FUZZYCSG_SOURCE_DIR",
                                     pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture
def source() -> pathlib.Path:
    return SOURCE


@pytest.fixture
def program_error():
    """The program's one-line error for a command line (without 'fuzzycsg: error: ')."""
    program = os.environ.get("FUZZYCSG_PROGRAM")
    if not program:
        pytest.fail("FUZZYCSG_PROGRAM is not set (the tests run through ctest)")

    def run(*args) -> str:
        r = subprocess.run([program, *map(str, args)], capture_output=True, text=True)
        assert r.returncode == 2, (r.returncode, r.stderr)
        line = r.stderr.strip().splitlines()[-1]
        prefix = "fuzzycsg: error: "
        assert line.startswith(prefix), line
        return line[len(prefix):]

    return run
