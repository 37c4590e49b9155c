#!/usr/bin/env python3
"""Checks the shape of the Rust sources (docs/architecture.md, "Rules of the house").

- No file-level import circle inside a crate: a file's module uses another through `crate::` or
  `super::` paths; the modules of each crate must form a graph without cycles.
- No source file over 700 lines and no function over 80 lines, outside tests.

Usage: python3 scripts/structure.py        (exit 1 and a list when a rule is broken)
"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CRATES = ["crates/core", "crates/ddm", "crates/io", "crates/cli", "python"]
MAX_FILE, MAX_FN = 700, 80


def sources(crate):
    src = ROOT / crate / ("rust" if crate == "python" else "src")
    return src, sorted(src.rglob("*.rs"))


def module_path(src, f):
    parts = list(f.relative_to(src).with_suffix("").parts)
    if parts[-1] in ("lib", "main", "mod"):
        parts = parts[:-1]
    return tuple(parts)


def code_part(text):
    """The file without its unit-test module."""
    m = re.search(r"\n#\[cfg\(test\)\]\s*\n\s*mod\s+\w+\s*\{", text)
    return text[: m.start()] if m else text


def without_comments(text):
    return re.sub(r"//.*", "", text)


def resolve(parts, mods):
    for k in range(len(parts), -1, -1):
        if tuple(parts[:k]) in mods:
            return tuple(parts[:k])
    return None


def references(text, me, mods):
    out = set()
    for m in re.finditer(r"\bcrate((?:::\w+)+)", text):
        out.add(resolve(tuple(m.group(1).strip(":").split("::")), mods))
    for m in re.finditer(r"\bcrate::\{([^;]*?)\}", text, re.S):
        for item in m.group(1).split(","):
            head = item.strip().split("::")[0].strip("{} \n")
            if head:
                out.add(resolve((head,), mods))
    for m in re.finditer(r"\b(super(?:::super)*)((?:::\w+)*)", text):
        ups = m.group(1).count("super")
        base = me[: len(me) - ups]
        rest = tuple(p for p in m.group(2).split("::") if p)
        out.add(resolve(base + rest, mods))
    out.discard(None)
    out.discard(me)
    return out


def cycles(graph):
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(100000)

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))

    for v in graph:
        if v not in index:
            visit(v)
    return found


def long_functions(text):
    lines = text.split("\n")
    head = re.compile(r"\s*(pub(\([^)]*\))?\s+)?(const\s+)?(unsafe\s+)?fn\s+(\w+)")
    for i, line in enumerate(lines):
        m = head.match(line)
        if not m:
            continue
        depth, started, j = 0, False, i
        while j < len(lines):
            s = without_comments(lines[j])
            s = re.sub(r'"(\\.|[^"\\])*"', '""', s)
            s = re.sub(r"'(\\.|[^'\\])'", "''", s)
            depth += s.count("{") - s.count("}")
            started = started or "{" in s
            if (not started and s.rstrip().endswith(";")) or (started and depth <= 0):
                break
            j += 1
        if started and j - i + 1 > MAX_FN:
            yield m.group(5), i + 1, j - i + 1


def main():
    problems = []
    for crate in CRATES:
        src, files = sources(crate)
        mods = {module_path(src, f): f for f in files}
        graph = {}
        for me, f in mods.items():
            code = code_part(f.read_text())
            graph[me] = references(without_comments(code), me, mods)
            rel = f.relative_to(ROOT)
            if code.count("\n") > MAX_FILE:
                problems.append(f"{rel}: {code.count(chr(10))} lines (at most {MAX_FILE})")
            for name, line, n in long_functions(code):
                problems.append(f"{rel}:{line}: fn {name} has {n} lines (at most {MAX_FN})")
        for comp in cycles(graph):
            names = " ".join("::".join(c) or "lib" for c in comp)
            problems.append(f"{crate}: import circle between {names}")
    for p in problems:
        print(p)
    print(f"structure: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
