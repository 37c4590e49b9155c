"""Every Python example runs (style: every shipped example is a test)."""

import subprocess
import sys

import pytest

from conftest import REPO

pytest.importorskip("matplotlib")

STUDY = REPO / "examples" / "python" / "notch_study.py"


def test_notch_study(tmp_path):
    if not STUDY.is_file():
        pytest.skip(f"{STUDY} does not exist")
    out = subprocess.run(
        [sys.executable, str(STUDY), str(tmp_path / "study")],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert "gamma  active-set  newton-chord  newton-kurchatov" in lines
    assert sum(1 for line in lines if line[:1].isdigit()) == 18  # one row per γ
    assert any(line.startswith("newton-kurchatov: best gamma") for line in lines)
    for name in ["iterations_vs_gamma.png", "contact_pressure.png"]:
        png = tmp_path / "study" / name
        assert png.read_bytes()[:4] == b"\x89PNG"
