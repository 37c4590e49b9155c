"""Every option of the problem file's [solver] table and of `contactdd solve` / `contactdd
monolithic` has its Python keyword, under the same name (snake_case of the kebab-case key), and a
file's settings are honoured: its load steps and monitor run by solve_steps, refused by solve.

The [solver] keys are read from the schema itself (the fields of `SolverSpec` in
crates/io/src/problem.rs, checked against the module's message for an unknown [solver] key,
which lists the keys the schema accepts), and the command-line options from
crates/cli/src/args.rs (and from `contactdd solve --help` when the binary is built), so a key
or option added there fails this test until Python has it."""

import inspect
import json
import os
import pickle
import re
import shutil
import subprocess

import numpy as np
import pytest

import contactdd
from conftest import REPO

ARGS_RS = REPO / "crates" / "cli" / "src" / "args.rs"
PROBLEM_RS = REPO / "crates" / "io" / "src" / "problem.rs"
RECESS = REPO / "examples" / "recess_steps.toml"

#: Command-line options that have no keyword, and why.
CLI_ONLY = {
    "file": "the problem file: Python's `problem` argument (Problem.from_toml reads one)",
    "quiet": "Python prints nothing; progress= reports every iteration",
    "vtu-format": "the .vtu encoding: write_vtu(format=...); out= follows the problem's [output] vtu",
    "vtu-layout": "the .vtu layout: write_vtu(layout=...); out= follows the problem's [output] "
                  "vtu-layout",
}

#: [solver] keys that a function does not take, and why.
NOT_ON = {
    "solve": {"load-steps": "solve runs one solve at the full load; solve_steps runs the steps"},
}

MINIMAL = """
plane = "strain"
[materials.steel]
young = 1.0
poisson = 0.3
[[bodies]]
name = "block"
material = "steel"
mesh = { kind = "rectangle", x = [0.0, 1.0], y = [0.0, 1.0], nx = 1, ny = 1 }
supports = [{ boundary = "bottom", component = "both" }]
[solver]
"""


def snake(key):
    return key.replace("-", "_")


def keywords(fn):
    return set(inspect.signature(fn).parameters)


@pytest.fixture(scope="module")
def solver_keys():
    """The keys of the [solver] table: the fields of the schema's `SolverSpec` (kebab-case),
    checked against the module's own unknown-key message, which lists the keys the schema it
    was built from accepts (the message echoes a long line cut short, so it is a prefix)."""
    if not PROBLEM_RS.is_file():
        pytest.skip(f"{PROBLEM_RS} does not exist (run the tests from a repository checkout)")
    body = re.search(r"pub struct SolverSpec \{(.*?)\n\}", PROBLEM_RS.read_text(), re.S)
    assert body, "no SolverSpec in problem.rs"
    keys = [snake(f).replace("_", "-") for f in re.findall(r"^\s*pub (\w+):", body.group(1), re.M)]
    with pytest.raises(contactdd.ContactddError) as e:
        contactdd.Problem.from_toml_str(MINIMAL + "no-such-key = 1\n")
    message = str(e.value)
    assert "unknown field `no-such-key`" in message, message
    listed = re.findall(r"`([a-z0-9-]+)`", message.split("expected one of", 1)[1])
    assert len(listed) >= 5 and listed == keys[: len(listed)], (listed, keys)
    assert {"method", "gamma", "tol", "max-iter", "load-steps", "monitor", "threads"} <= set(keys)
    return keys


def struct_options(text, name):
    """The long options of the clap struct `name` of args.rs (flattened structs included)."""
    body = re.search(rf"pub struct {name} \{{(.*?)\n\}}", text, re.S)
    assert body, name
    options, flatten = [], False
    for line in body.group(1).splitlines():
        line = line.strip()
        if "#[command(flatten)]" in line:
            flatten = True
        field = re.match(r"pub (\w+): (\w+)", line)
        if field:
            if flatten:
                options += struct_options(text, field.group(2))
            else:
                options.append(field.group(1).replace("_", "-"))
            flatten = False
    return options


def binary():
    """The built `contactdd` binary, if any."""
    candidates = [os.environ.get("CONTACTDD_BIN"), shutil.which("contactdd")]
    target = os.environ.get("CARGO_TARGET_DIR", str(REPO / "target"))
    candidates += [os.path.join(target, kind, "contactdd") for kind in ("release", "debug")]
    return next((c for c in candidates if c and os.access(c, os.X_OK)), None)


def help_options(command):
    exe = binary()
    if exe is None:
        return []
    out = subprocess.run([exe, command, "--help"], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    return [o for o in re.findall(r"--([a-z][a-z0-9-]*)", out.stdout) if o not in ("help",)]


@pytest.fixture(scope="module")
def cli_options():
    if not ARGS_RS.is_file():
        pytest.skip(f"{ARGS_RS} does not exist (run the tests from a repository checkout)")
    text = ARGS_RS.read_text()
    options = {}
    for command, struct in [("solve", "SolveArgs"), ("monolithic", "MonolithicArgs")]:
        found = struct_options(text, struct) + help_options(command)
        assert "tol" in found or command == "monolithic", found
        options[command] = sorted(set(found))
    return options


def test_every_solver_key_is_a_keyword(solver_keys):
    """Problem.solver takes every [solver] key, solve and solve_steps every one that applies,
    Problem.settings reports each, and each function's docstring documents its keywords."""
    targets = {
        "Problem.solver": contactdd.Problem.solver,
        "solve": contactdd.solve,
        "solve_steps": contactdd.solve_steps,
    }
    missing = []
    for name, fn in targets.items():
        params, doc = keywords(fn), inspect.getdoc(fn) or ""
        for key in solver_keys:
            if key in NOT_ON.get(name, {}):
                continue
            if snake(key) not in params:
                missing.append(f"{name} has no keyword {snake(key)} ([solver] {key})")
            elif not re.search(rf"\b{snake(key)}\b", doc):
                missing.append(f"{name}'s docstring does not document {snake(key)}")
    settings = contactdd.notch_benchmark().settings
    missing += [f"Problem.settings has no {snake(k)}" for k in solver_keys if snake(k) not in settings]
    assert not missing, "\n".join(missing)


def test_every_cli_option_is_a_keyword(cli_options):
    """`contactdd solve` options on solve and solve_steps, `contactdd monolithic` options on
    monolithic, under the same names."""
    targets = {
        "solve": [contactdd.solve, contactdd.solve_steps],
        "monolithic": [contactdd.monolithic],
    }
    missing = []
    for command, functions in targets.items():
        for option in cli_options[command]:
            if option in CLI_ONLY:
                continue
            for fn in functions:
                if snake(option) not in keywords(fn):
                    missing.append(f"{fn.__name__} has no keyword {snake(option)} "
                                   f"(contactdd {command} --{option})")
    assert not missing, "\n".join(missing)


def test_the_parsers_see_the_options(cli_options, solver_keys):
    """The sources are read, not empty: known options and keys are found."""
    assert {"method", "gamma", "enforcement", "gap-tol", "max-iter", "threads", "out"} <= set(
        cli_options["solve"])
    assert {"max-steps", "enforcement", "gap-tol", "threads", "out"} <= set(
        cli_options["monolithic"])
    assert len(solver_keys) == len(set(solver_keys)) >= 15


@pytest.fixture(scope="module")
def recess():
    if not RECESS.is_file():
        pytest.skip(f"{RECESS} does not exist")
    return contactdd.Problem.from_toml(RECESS)


def test_solve_refuses_a_file_with_load_steps(recess):
    with pytest.raises(contactdd.ContactddError, match=r"4 load steps.*solve_steps\(problem\)"):
        contactdd.solve(recess)


def top_mean(result, body):
    """Mean displacement of the nodes of `body` at its largest y (a rectangle's top)."""
    b = next(b for b in result.bodies if b.name == body)
    top = np.isclose(b.nodes[:, 1], b.nodes[:, 1].max())
    return b.displacement[top].mean(axis=0)


def test_solve_steps_runs_the_files_steps_and_monitor(recess, tmp_path):
    results = contactdd.solve_steps(recess, out=tmp_path / "out")
    assert [r.load_factor for r in results] == [0.25, 0.5, 0.75, 1.0]
    for r in results:
        assert r.converged
        # The lower block carries its share of the pressure 100 on a top 10 long.
        fy = r.contact[0].forces[0][1]
        assert abs(abs(fy) - 1000.0 * r.load_factor) <= 1e-6 * 1000.0
        ux, uy = r.monitor
        assert np.allclose([ux, uy], top_mean(r, "upper"), rtol=1e-12, atol=0.0)
    # The monitored displacement grows with the load (downwards).
    uys = [r.monitor[1] for r in results]
    assert all(a > b for a, b in zip(uys, uys[1:])) and uys[0] < 0
    steps_csv = (tmp_path / "out" / "steps.csv").read_text().splitlines()
    assert "monitor_uy" in steps_csv[0].split(",") and len(steps_csv) == 5
    # The monitored value pickles with the result.
    assert pickle.loads(pickle.dumps(results[0])).monitor == results[0].monitor
    # The same as the load factors and monitor given as arguments.
    again = contactdd.solve_steps(recess, [0.25, 0.5, 0.75, 1.0],
                                  monitor={"body": "upper", "boundary": "top"})
    assert [r.monitor for r in again] == [r.monitor for r in results]


def test_problem_solver_sets_load_steps_and_monitor(notch, tmp_path):
    notch.solver(load_steps=2, monitor=("upper", "top"), max_updates=7, equilibrium_tol=0.02,
                 condensation="dense", gap_tol=1e-7)
    s = notch.settings
    assert s["load_steps"] == 2 and s["monitor"] == {"body": "upper", "boundary": "top"}
    assert (s["max_updates"], s["equilibrium_tol"], s["condensation"], s["gap_tol"]) == (
        7, 0.02, "dense", 1e-7)
    text = notch.to_toml()
    assert "load-steps = 2" in text and "max-updates = 7" in text
    again = contactdd.Problem.from_toml_str(text)
    assert again.settings == s
    with pytest.raises(contactdd.ContactddError, match="solve_steps"):
        contactdd.solve(notch)
    results = contactdd.solve_steps(notch)
    assert [r.load_factor for r in results] == [0.5, 1.0]
    assert all(r.monitor is not None for r in results)
    # One step at factor 1 is a plain solve, which reports the monitor too.
    notch.solver(load_steps=1)
    one = contactdd.solve(notch)
    assert one.monitor == contactdd.solve_steps(notch)[0].monitor
    assert one.monitor == pytest.approx(tuple(top_mean(one, "upper")), rel=1e-12)


def test_bad_load_steps_and_monitor_are_refused(notch):
    for bad, match in [(0, "load_steps: must be at least 1"), ([0.5, -1.0], "load_steps"),
                       ("x", "load_steps")]:
        with pytest.raises(contactdd.ContactddError, match=match):
            notch.solver(load_steps=bad)
    with pytest.raises(contactdd.ContactddError, match="monitor: no body named 'nope'"):
        notch.solver(monitor=("nope", "top"))
    with pytest.raises(contactdd.ContactddError, match="monitor: body 'upper'"):
        notch.solver(monitor={"body": "upper", "boundary": "nope"})
    with pytest.raises(contactdd.ContactddError, match="condensation"):
        notch.solver(condensation="fast")
    with pytest.raises(contactdd.ContactddError, match="no load steps"):
        contactdd.solve_steps(notch)
    # Nothing was kept from the refused calls.
    assert notch.settings["load_steps"] is None and notch.settings["monitor"] is None


def test_monolithic_takes_the_cli_options(notch, tmp_path):
    penalty = contactdd.monolithic(notch)
    exact = contactdd.monolithic(notch, enforcement="augmented", threads=1,
                                 out=tmp_path / "mono")
    summary = json.loads((tmp_path / "mono" / "summary.json").read_text())
    assert summary["converged"] is True and summary["updates"] == exact.summary()["updates"] > 1
    assert penalty.summary()["updates"] == 0
    assert exact.contact[0].max_penetration < 1e-3 * penalty.contact[0].max_penetration
    short = contactdd.monolithic(notch, max_steps=1)
    assert short.newton_steps == 1 and short.summary()["converged"] is False
    with pytest.raises(contactdd.ContactddError, match="enforcement"):
        contactdd.monolithic(notch, enforcement="lagrange")


def test_solve_writes_its_folder_and_takes_every_setting(notch, tmp_path):
    base = contactdd.solve(notch)
    same = contactdd.solve(notch, equilibrium_tol=1e-2, max_updates=100, condensation="auto",
                           out=tmp_path / "out")
    assert same.iterations == base.iterations
    assert np.array_equal(same.bodies[0].displacement, base.bodies[0].displacement)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["converged"] is True
    assert (tmp_path / "out" / "contact.csv").is_file()
