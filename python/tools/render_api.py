#!/usr/bin/env python3
"""Renders docs/python-api.md, the reference of the contactdd Python module, from its docstrings.

Usage: python python/tools/render_api.py [OUTPUT]   (default: docs/python-api.md of the checkout)

The page lists, in the order of ``contactdd.__all__``: the functions, the classes with their
methods and attributes, the exceptions, the constants, the ``contactdd.plot`` functions and the
functions and classes of ``contactdd.space`` (problems in space), each
with its signature (where Python can introspect it) and its docstring. Docstrings are Google style
with reST markup; :func:`markdown` turns their sections into lists and their ``::`` blocks into
code. python/tests/test_api_docs.py checks that the committed page is what this script renders.
"""

from __future__ import annotations

import inspect
import re
import sys
from pathlib import Path
from typing import Any

SECTIONS = re.compile(r"^(Args|Arguments|Returns|Raises|Yields|Example|Examples|Note):\s*$")
ROLE = re.compile(r":(?:class|func|meth|attr|mod|data|exc):`~?([^`]+)`")
HEADER = """# The Python API

The reference of the `contactdd` Python module, rendered from its docstrings by
`python/tools/render_api.py` (`python/tests/test_api_docs.py` checks that this page is up to
date; after changing a docstring, run `python python/tools/render_api.py`). `python/README.md`
shows the module at work; the type stubs are `python/src/contactdd/_contactdd.pyi`.
"""


def inline(text: str) -> str:
    """reST inline markup as Markdown: roles and double backquotes become code spans."""
    text = ROLE.sub(lambda m: f"`{m.group(1)}`", text)
    return text.replace("``", "`")


def markdown(doc: str) -> str:
    """A cleaned docstring as Markdown: paragraphs as they are, the entries of a section (Args:,
    Returns:, ...) as a list, a block after ``::`` as a Python code block."""
    out: list[str] = []
    lines = doc.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if SECTIONS.match(line):
            out += ["", f"**{line.strip()[:-1]}:**", ""]
            i += 1
            while i < len(lines) and (not lines[i].strip() or lines[i].startswith(" ")):
                entry = lines[i].strip()
                if entry and len(lines[i]) - len(lines[i].lstrip()) <= 4:
                    out.append(f"- {inline(entry)}")
                elif entry:
                    out[-1] += f" {inline(entry)}"
                i += 1
            out.append("")
        elif line.rstrip().endswith("::"):
            out.append(inline(line.rstrip()[:-1]))
            block, i = [], i + 1
            while i < len(lines) and (not lines[i].strip() or lines[i].startswith(" ")):
                block.append(lines[i])
                i += 1
            out += ["", "```python", inspect.cleandoc("\n".join(block)), "```", ""]
        else:
            out.append(inline(line))
            i += 1
    return re.sub(r"\n{3,}", "\n\n", "\n".join(out)).strip()


def signature(name: str, obj: Any) -> str:
    """``name(parameters)`` without annotations (the stubs have the types) or ``self``."""
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return f"{name}(...)"
    params = [p.replace(annotation=inspect.Parameter.empty) for p in sig.parameters.values()
              if p.name not in ("self", "cls")]
    plain = sig.replace(parameters=params, return_annotation=inspect.Signature.empty)
    return f"{name}{plain}"


def first_paragraph(doc: str) -> str:
    return " ".join(inline(doc).split("\n\n")[0].split())


def routine(title: str, obj: Any, level: str) -> list[str]:
    return [f"{level} `{signature(title, obj)}`", "", markdown(inspect.getdoc(obj) or ""), ""]


def class_section(name: str, cls: type) -> list[str]:
    out = [f"## `{signature(name, cls)}`", "", markdown(inspect.getdoc(cls) or ""), ""]
    members = sorted(n for n in vars(cls) if not n.startswith("_"))
    attributes = [n for n in members if not inspect.isroutine(getattr(cls, n))]
    if attributes:
        out += ["| attribute | |", "|-----------|-|"]
        for n in attributes:
            doc = first_paragraph(inspect.getdoc(vars(cls)[n]) or "").replace("|", "\\|")
            out.append(f"| `{n}` | {doc} |")
        out.append("")
    for n in members:
        if inspect.isroutine(getattr(cls, n)):
            out += routine(f"{name}.{n}", getattr(cls, n), "###")
    return out


def render() -> str:
    import contactdd

    groups: dict[str, list[str]] = {"functions": [], "classes": [], "errors": [], "data": []}
    for name in contactdd.__all__:
        obj = getattr(contactdd, name)
        if inspect.ismodule(obj):
            continue
        if inspect.isroutine(obj):
            groups["functions"] += routine(name, obj, "##")
        elif isinstance(obj, type) and issubclass(obj, BaseException):
            bases = ", ".join(b.__name__ for b in obj.__bases__)
            groups["errors"] += [f"## `{name}({bases})`", "", markdown(inspect.getdoc(obj)), ""]
        elif isinstance(obj, type):
            groups["classes"] += class_section(name, obj)
        elif name == "__version__":  # not its value: the page would change with every release
            groups["data"] += ["- `__version__`: the version of the package, a string"]
        else:
            groups["data"] += [f"- `{name}` = `{obj!r}`"]
    plot = ["# `contactdd.plot`", "", markdown(inspect.getdoc(contactdd.plot)), ""]
    for name in contactdd.plot.__all__:
        plot += routine(f"plot.{name}", getattr(contactdd.plot, name), "##")
    space = ["# `contactdd.space`", "", markdown(inspect.getdoc(contactdd.space)), ""]
    for name in contactdd.space.__all__:
        obj = getattr(contactdd.space, name)
        if inspect.isroutine(obj):
            space += routine(f"space.{name}", obj, "##")
    for name in contactdd.space.__all__:
        obj = getattr(contactdd.space, name)
        if isinstance(obj, type):
            space += class_section(f"space.{name}", obj)
    parts = [HEADER, "# Functions", "", *groups["functions"], "# Classes", "",
             *groups["classes"], "# Exceptions", "", *groups["errors"], "# Constants", "",
             *groups["data"], "", *plot, *space]
    return re.sub(r"\n{3,}", "\n\n", "\n".join(parts)).strip() + "\n"


def main() -> None:
    default = Path(__file__).resolve().parents[2] / "docs" / "python-api.md"
    target = Path(sys.argv[1]) if len(sys.argv) > 1 else default
    target.write_text(render(), encoding="utf-8")


if __name__ == "__main__":
    main()
