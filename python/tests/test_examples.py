"""The examples run (shortened where they take options) and write what they say."""

import os
import pathlib
import subprocess
import sys

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def run(tmp_path, name, *args):
    result = subprocess.run([sys.executable, str(EXAMPLES / name), *args], cwd=tmp_path, env=dict(os.environ),
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    return result.stdout


def test_hello(tmp_path):
    assert "after 1000 steps" in run(tmp_path, "hello.py")


def test_stiffness_study_writes_a_png(tmp_path):
    out = run(tmp_path, "stiffness_study.py", "--steps", "200", "--output", "study.png")
    assert out.count("bond_k") == 5
    assert (tmp_path / "study.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_haptic_probe(tmp_path):
    out = run(tmp_path, "haptic_probe.py", "--duration", "2.5")
    assert "peak force" in out
    peak = float(out.split("peak force ")[1].split()[0])
    assert peak > 0.01  # the probe pressed into the sheet


def test_paraview(tmp_path):
    out = run(tmp_path, "paraview.py", "--frames", "3", "--output", "frames")
    assert (tmp_path / "frames" / "frames.pvd").exists()
    assert len(list((tmp_path / "frames").glob("frame_*.vtu"))) == 4
    assert "768 tetrahedra" in out
