"""docs/python-api.md is what python/tools/render_api.py renders from the module's docstrings
now, and it documents every exported name."""

import importlib.util

import pytest

import contactdd
from conftest import REPO

PAGE = REPO / "docs" / "python-api.md"
SCRIPT = REPO / "python" / "tools" / "render_api.py"


@pytest.fixture(scope="module")
def rendered():
    if not SCRIPT.is_file():
        pytest.skip(f"{SCRIPT} does not exist (run the tests from a repository checkout)")
    spec = importlib.util.spec_from_file_location("render_api", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.render()


def test_committed_page_is_up_to_date(rendered):
    assert PAGE.read_text(encoding="utf-8") == rendered, (
        "docs/python-api.md is out of date: run python python/tools/render_api.py"
    )


def test_every_exported_name_is_documented(rendered):
    headings = [line for line in rendered.splitlines() if line.startswith(("#", "- `"))]
    for name in contactdd.__all__:
        if name in ("plot", "space"):
            name = f"contactdd.{name}"
        assert any(f"`{name}" in h for h in headings), name
    for name in contactdd.plot.__all__:
        assert any(f"`plot.{name}(" in h for h in headings), name
    for name in contactdd.space.__all__:
        assert any(f"`space.{name}" in h for h in headings), name
