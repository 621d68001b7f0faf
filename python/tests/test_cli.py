"""The `audit` console script the wheel installs: the binary's command line."""

import json
import subprocess

import extrinsic_audit as ea
from conftest import ROOT, audit_command


def run(*args):
    return subprocess.run([audit_command(), *args], cwd=ROOT, capture_output=True, text=True,
                          check=False)


def test_version():
    p = run("--version")
    assert p.returncode == 0
    assert p.stdout.strip() == f"audit {ea.__version__}"


def test_a_report_and_exit_codes():
    p = run("tests/fixtures/urdf/anymal_c_lidar.urdf", "--from", "base", "--to", "lidar",
            "--format", "json")
    assert p.returncode == 0
    assert json.loads(p.stdout)["lever_arm_m"] == ea.load(
        "tests/fixtures/urdf/anymal_c_lidar.urdf").report("base", "lidar").lever_arm_m
    bad = run("no/such/file.urdf", "--from", "a", "--to", "b")
    assert bad.returncode == 2 and "no/such/file.urdf: cannot read" in bad.stderr
    usage = run("--no-such-flag")
    assert usage.returncode == 2


def test_text_output_reaches_a_pipe():
    p = run("survey", "calibrations/")
    assert p.returncode == 0 and "anymal-d-lidar-imu" in p.stdout
