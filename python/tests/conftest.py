"""Shared fixtures of the contactdd Python tests."""

from pathlib import Path

import pytest

import contactdd

#: The repository root (python/tests/ is two levels below it).
REPO = Path(__file__).resolve().parents[2]
NOTCH_TOML = REPO / "examples" / "notch.toml"


@pytest.fixture
def notch_toml() -> Path:
    """Path of examples/notch.toml; skips the test when the example is not there."""
    if not NOTCH_TOML.is_file():
        pytest.skip(f"{NOTCH_TOML} does not exist (run the tests from a repository checkout)")
    return NOTCH_TOML


@pytest.fixture
def notch() -> contactdd.Problem:
    """The paper's notch benchmark built in Rust (32 × 16 cells per body)."""
    return contactdd.notch_benchmark()
