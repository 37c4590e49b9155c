"""The type stubs (contactdd/_contactdd.pyi) describe the extension module as it is: the same
public names at the top level and in every class, and the same parameters (names, kinds,
defaults) wherever Python can introspect the compiled function."""

import ast
import inspect
from pathlib import Path

import pytest

import contactdd
from contactdd import _contactdd

STUBS = Path(contactdd.__file__).with_name("_contactdd.pyi")


def public(names):
    return {n for n in names if not n.startswith("_") or n == "__version__"}


@pytest.fixture(scope="module")
def stub():
    return ast.parse(STUBS.read_text())


def stub_names(body):
    """The names a stub body defines: classes, functions and annotated or assigned names."""
    names = {}
    for node in body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            names[node.name] = node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names[node.target.id] = node
        elif isinstance(node, ast.Assign):
            for t in node.targets:
                if isinstance(t, ast.Name):
                    names[t.id] = node
    return names


def test_top_level_names(stub):
    names = stub_names(stub.body)
    exported = public(dir(_contactdd))
    assert public(names) - {"TypedDict"} == exported
    declared = ast.literal_eval(names["__all__"].value)
    assert sorted(declared) == sorted(exported)


def stub_signature(fn):
    """(name, kind, default) per parameter of a stub function, without ``self``/``cls``."""
    a = fn.args
    out = []
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + list(a.defaults)
    for i, (arg, default) in enumerate(zip(positional, defaults)):
        kind = "positional_only" if i < len(a.posonlyargs) else "positional_or_keyword"
        out.append((arg.arg, kind, None if default is None else ast.literal_eval(default)))
    for arg, default in zip(a.kwonlyargs, a.kw_defaults):
        out.append((arg.arg, "keyword_only", None if default is None else ast.literal_eval(default)))
    if out and out[0][0] in ("self", "cls"):
        out = out[1:]
    return out


def runtime_signature(obj):
    """(name, kind, default) per parameter, or None where Python cannot introspect it."""
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return None
    out = []
    for p in sig.parameters.values():
        if p.name in ("self", "cls", "$self", "$cls"):
            continue
        kind = p.kind.name.lower()
        if kind == "positional_only":
            kind = "positional_or_keyword"
        default = None if p.default is inspect.Parameter.empty else p.default
        out.append((p.name, kind, default))
    return out


def normalised(sig):
    return [(n, "positional_or_keyword" if k == "positional_only" else k, d) for n, k, d in sig]


def test_functions_match(stub):
    names = stub_names(stub.body)
    for name in public(dir(_contactdd)):
        obj = getattr(_contactdd, name)
        if inspect.isroutine(obj):
            expected = runtime_signature(obj)
            assert expected is not None, name
            assert normalised(stub_signature(names[name])) == expected, name


def test_classes_match(stub):
    names = stub_names(stub.body)
    for name in public(dir(_contactdd)):
        cls = getattr(_contactdd, name)
        if not isinstance(cls, type) or issubclass(cls, BaseException):
            continue
        members = stub_names(names[name].body)
        runtime = public(vars(cls))
        assert public(members) - {"__new__"} == runtime, name
        for member in runtime:
            obj = getattr(cls, member)
            if inspect.isroutine(obj):
                expected = runtime_signature(obj)
                if expected is not None:
                    got = normalised(stub_signature(members[member]))
                    assert got == expected, f"{name}.{member}"
        if "__new__" in members:
            assert normalised(stub_signature(members["__new__"])) == runtime_signature(cls), name
