"""Shared helpers of the Python package's tests (pytest, from the venv that
python-tests/run.sh makes, the wheel installed in it).

Independent numbers come from pytransform3d and numpy, computed here from
the files themselves (xml.etree, tomllib), never from the package. Real
third-party files are found by tools/testdata.py, the same lookup as the
Rust tests' helper, and their tests skip when the test-data folder is absent.
"""

import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import pytransform3d.rotations as pr

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import testdata  # noqa: E402

FIXTURES = os.path.join(ROOT, "tests", "fixtures")
CALIBRATIONS = os.path.join(ROOT, "calibrations")
ANYMAL_C_LIDAR = os.path.join(FIXTURES, "urdf", "anymal_c_lidar.urdf")


def real(name):
    """The verified path of a third-party file, or skip the test."""
    path = testdata.find(name)
    if path is None:
        pytest.skip(f"test data not found: {name} (docs/test-data.md)")
    return path


def audit_command():
    """The `audit` console script the wheel installed beside this Python."""
    exe = os.path.join(os.path.dirname(sys.executable), "audit")
    if not os.path.exists(exe):
        exe = shutil.which("audit")
    assert exe, "the wheel's `audit` console script is not installed"
    return exe


def cli_json(*args, cwd=ROOT):
    """`audit ARGS --format json` run from `cwd`: (its JSON, exit code)."""
    p = subprocess.run([audit_command(), *args, "--format", "json"], cwd=cwd,
                       capture_output=True, text=True, check=False)
    assert p.returncode in (0, 1), p.stderr
    return json.loads(p.stdout), p.returncode


def urdf_pose(xyz, rpy):
    """A URDF joint origin as a 4x4 pose: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    m = np.eye(4)
    m[:3, :3] = pr.matrix_from_euler(rpy, 0, 1, 2, extrinsic=True)
    m[:3, 3] = xyz
    return m


def urdf_links(path):
    """Every link of a URDF, by xml.etree."""
    return sorted(link.get("name") for link in ET.parse(path).getroot().iter("link"))


@pytest.fixture(autouse=True)
def _in_root(monkeypatch):
    """Every test runs from the checkout (relative paths as the CLI's)."""
    monkeypatch.chdir(ROOT)
