"""docs/tutorial.md runs as written.

The test takes the tutorial's fenced blocks in order and, in a temporary copy of
examples/tutorial/, runs every ```sh command (`contactdd` is the release binary, `python3` this
interpreter) and executes every ```python block in one namespace. The setup commands (cargo,
export, venv, source, pip) are skipped: the test brings the binary and the module itself. The Gmsh
script runs when `gmsh` can be imported; otherwise the shipped punch.msh is used.

Checks: every command exits 0; the first and last lines of the output the tutorial shows after a
command (mesh-independent: the headline and the results line) are in what it prints; the ```py
and ```toml excerpts are in the files they quote; punch_steps.toml is punch.toml with the lines the
tutorial says are added. Then the results against independent numbers: the contact forces and the
base's reaction equal the applied pressure times the width of the punch's top, measured on the
mesh; the punch's peak pressure and contact half-width agree with Hertz's formulas, computed
here from the materials of the file; each load step carries its share of the load, without
penetration.
"""

import csv
import json
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import contactdd
from conftest import REPO

DOC = REPO / "docs" / "tutorial.md"
TUTORIAL = REPO / "examples" / "tutorial"
FENCE = re.compile(r"^```(\w*)\n(.*?)^```\s*$", re.M | re.S)
SETUP = ("cargo ", "export ", "python3 -m venv", "source ", "pip ")
PRESSURE, WIDTH, RADIUS = 100.0, 2.0, 1.0  # punch.toml's load, the punch's top and radius


def blocks():
    """The tutorial's fenced blocks, in order: (language, text)."""
    if not DOC.is_file():
        pytest.skip(f"{DOC} does not exist (run the tests from a repository checkout)")
    return FENCE.findall(DOC.read_text(encoding="utf-8"))


def cli():
    """The release `contactdd` binary, built by cargo when cargo is there (a no-op when up to
    date); otherwise an existing one; otherwise the test is skipped."""
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    binary = target / "release" / "contactdd"
    if shutil.which("cargo"):
        build = subprocess.run(["cargo", "build", "--release", "-p", "contactdd-cli"], cwd=REPO,
                               capture_output=True, text=True)
        assert build.returncode == 0, f"cargo build --release -p contactdd-cli failed:\n{build.stderr}"
    if not binary.is_file():
        pytest.skip(f"{binary} is not built (cargo build --release -p contactdd-cli)")
    return binary


def gmsh_imports():
    """Whether `import gmsh` works (the wheel also needs system libraries such as libGLU)."""
    try:
        import gmsh  # noqa: F401
    except (ImportError, OSError):
        return False
    return True


def run_sh(text, cwd, env):
    """Runs the commands of an ```sh block; returns the output of the last one run."""
    out = None
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith("#") or line.startswith(SETUP):
            continue
        argv = shlex.split(line)
        if argv[0] == "python3":
            if not gmsh_imports():
                out = None  # the shipped .msh stands in for the script's
                continue
            argv[0] = sys.executable
        proc = subprocess.run(argv, cwd=cwd, env=env, capture_output=True, text=True)
        assert proc.returncode == 0, f"`{line}` exited {proc.returncode}:\n{proc.stdout}\n{proc.stderr}"
        out = proc.stdout
    return out


def assert_shown(shown, printed):
    """The first and last lines the tutorial shows are in what the command printed."""
    lines = [l for l in shown.splitlines() if l.strip()]
    for line in (lines[0], lines[-1]):
        assert line in printed.splitlines(), f"the tutorial shows {line!r}; the command printed:\n{printed}"


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """A folder where the tutorial has been run; yields it."""
    work = tmp_path_factory.mktemp("tutorial")
    shutil.copytree(TUTORIAL, work / "examples" / "tutorial",
                    ignore=shutil.ignore_patterns("*-out", "__pycache__"))
    env = dict(os.environ, PATH=f"{cli().parent}{os.pathsep}{os.environ.get('PATH', '')}")
    namespace, last, cwd = {"__name__": "__tutorial__"}, None, os.getcwd()
    try:
        os.chdir(work)
        for lang, text in blocks():
            if lang == "sh":
                last = run_sh(text, work, env)
            elif lang == "python":
                exec(compile(text, str(DOC), "exec"), namespace)
                last = None
            elif lang == "text" and last is not None:
                assert_shown(text, last)
                last = None
            else:
                last = None
    finally:
        os.chdir(cwd)
    return work


def test_excerpts_quote_the_files():
    files = {"py": [TUTORIAL / "punch.py"],
             "toml": [TUTORIAL / "punch.toml", TUTORIAL / "punch_steps.toml"]}
    excerpts = [(lang, text) for lang, text in blocks() if lang in files]
    assert len(excerpts) >= 10
    for lang, text in excerpts:
        assert any(text in f.read_text(encoding="utf-8") for f in files[lang]), \
            f"this {lang} excerpt of docs/tutorial.md is in none of {files[lang]}:\n{text}"


def test_steps_file_is_the_punch_plus_the_lines_shown():
    def body(name):
        lines = (TUTORIAL / name).read_text(encoding="utf-8").splitlines()
        return [l for l in lines if l and not l.startswith("#") and not l.startswith("name = ")]

    added = ['enforcement = "augmented"', "load-steps = 4",
             'monitor = { body = "punch", boundary = "punch-top" }']
    steps = body("punch_steps.toml")
    assert [l for l in steps if l not in added] == body("punch.toml")
    assert sum(l == added[0] for l in steps) == 2  # both contact pairs
    toml_blocks = "".join(text for lang, text in blocks() if lang == "toml")
    assert all(line in toml_blocks for line in added)


def test_solve_carries_the_load(workdir):
    summary = json.loads((workdir / "punch-out" / "summary.json").read_text())
    assert summary["converged"] and summary["stop"] == "converged"
    result = contactdd.load_results(workdir / "punch-out")
    punch = result.bodies[2]
    top = punch.nodes[np.isclose(punch.nodes[:, 1], punch.nodes[:, 1].max())]
    load = PRESSURE * (top[:, 0].max() - top[:, 0].min())
    assert load == pytest.approx(PRESSURE * WIDTH, rel=1e-12)
    seat, tip = result.contact
    assert seat.forces[1] == pytest.approx((0.0, load), abs=1e-8 * load)
    assert tip.forces[1] == pytest.approx((0.0, load), abs=1e-8 * load)
    base = summary["reactions"][0]
    assert base["body"] == "base" and base["total"] == pytest.approx([0.0, load], abs=1e-8 * load)


def test_hertz(workdir):
    result = contactdd.load_results(workdir / "punch-out")
    tip = result.contact[1]
    text = (TUTORIAL / "punch.toml").read_text(encoding="utf-8")
    materials = re.findall(r"^\[materials\.(\w+)\]\nyoung = (\S+)\npoisson = (\S+)$", text, re.M)
    assert [m[0] for m in materials] == ["steel", "aluminium"]  # the punch's and the block's
    inv_e = sum((1 - float(nu) ** 2) / float(e) for _, e, nu in materials)
    load = PRESSURE * WIDTH
    a = math.sqrt(4 * load * RADIUS * inv_e / math.pi)
    p0 = 2 * load / (math.pi * a)
    assert tip.pressure.max() == pytest.approx(p0, rel=0.02)
    on_punch = tip.closed & (tip.side == 1)
    h = 0.02  # the largest element along the contact zone (0.01 + 0.1 · distance)
    assert abs(tip.x[on_punch].max() - a) < h and abs(-tip.x[on_punch].min() - a) < h


def test_load_steps(workdir):
    with open(workdir / "punch_steps-out" / "steps.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [float(r["factor"]) for r in rows] == [0.25, 0.5, 0.75, 1.0]
    for r in rows:
        load = float(r["factor"]) * PRESSURE * WIDTH
        assert r["converged"] == "true"
        assert float(r["tip_force_y"]) == pytest.approx(-load, rel=1e-8)
        assert float(r["seat_force_y"]) == pytest.approx(-load, rel=1e-8)
    summary = json.loads((workdir / "punch_steps-out" / "summary.json").read_text())
    assert summary["converged"]
    for pair in summary["contact"]:
        assert pair["max_penetration"] <= summary["gap_tol"]
