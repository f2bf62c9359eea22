"""Shared fixtures of the Python module's tests: the real recordings, the `pushpred` program, a few pushes.

The tests run on real pushes from PUSHPRED_DATA (set by ctest to the configured data folder) and compare the
module's numbers with the C++ library's as the `pushpred` program (PUSHPRED_EXECUTABLE) writes them."""
import json
import os
import subprocess
from pathlib import Path

import pytest

import pushpred


def pytest_sessionstart(session):
    """A test file that reads the real recordings is registered with PUSHPRED_REQUIRED_DATA naming their folder
    (tests/CMakeLists.txt): without that folder it is skipped (exit 77, which ctest counts as skipped)."""
    required = os.environ.get("PUSHPRED_REQUIRED_DATA")
    if required and not Path(required).is_dir():
        pytest.exit(f"SKIPPED: this test reads the real recordings, and their folder {required} does not exist",
                    returncode=77)


@pytest.fixture(scope="session")
def data_dir():
    return Path(pushpred.data_folder())


@pytest.fixture(scope="session")
def executable():
    path = os.environ.get("PUSHPRED_EXECUTABLE")
    if not path:
        pytest.fail("PUSHPRED_EXECUTABLE is not set: run these tests through ctest")
    return path


@pytest.fixture(scope="session")
def hex_file(data_dir):
    """A real ABS push of the hexagon at 50 mm/s: an ordinary push with a live force sensor."""
    return str(data_dir / "abs" / "motion_surface=abs_shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000.h5")


@pytest.fixture(scope="session")
def ellip_file(data_dir):
    return str(sorted((data_dir / "abs").glob("*shape=ellip1_a=0_v=20*.h5"))[0])


def run_cli(executable, *args, expect=0):
    """Runs `pushpred ARGS...`; returns the completed process after checking its exit code."""
    proc = subprocess.run([executable, *map(str, args)], capture_output=True, text=True)
    assert proc.returncode == expect, f"pushpred {' '.join(map(str, args))}: exit {proc.returncode}\n{proc.stderr}"
    return proc


def read_json(path):
    with open(path) as f:
        return json.load(f)
