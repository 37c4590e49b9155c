"""Arguments of the wrong type or out of range raise :class:`ContactddError`.

The extension's functions convert their arguments before they run: an argument that does not
convert (a string for ``tol``, ``-1`` or ``2**64`` for ``max_iter``, a number for ``bodies``)
makes Python's ``TypeError``, ``OverflowError`` or ``ValueError``, with a note naming the
argument. :func:`checked` wraps every public function of the extension and :func:`install_methods` the
methods of :class:`Problem` so that such an error becomes a
:class:`ContactddError` with a short message naming the argument, what it must be and the value (shown compactly: ``-1``, ``'abc'``,
``1.000e+300``, ``<301-digit number>``)::

    max_iter: expected a whole number ≥ 0, got -1

Errors of a callback (``progress``) carry no such note and are raised as they are.
"""

from __future__ import annotations

import functools
import inspect
import re
from typing import Any, Callable

from ._contactdd import ContactddError

#: What an argument must be, from the message of the failed conversion.
_EXPECTED = [
    (re.compile(r"GammaArg"), 'a positive number or "auto"'),
    (re.compile(r"must be real number"), "a number"),
    (re.compile(r"cannot be interpreted as an integer|'float' object"), "a whole number ≥ 0"),
    (re.compile(r"instance of 'str'|PyString"), "a string"),
    (re.compile(r"instance of 'bool'|PyBool"), "True or False"),
    (re.compile(r"instance of 'tuple'|PyTuple"), "a pair"),
    (re.compile(r"instance of 'Problem'"), "a contactdd.Problem"),
    (re.compile(r"instance of 'dict'|PyDict"), "a dict"),
    (re.compile(r"Sequence|to `Vec`"), "a list"),
    (re.compile(r"os\.PathLike"), "a path"),
]

_NOTE = re.compile(r"^while processing '([A-Za-z_0-9]+)'$")


def shown(value: Any) -> str:
    """A value as an error message shows it: short, never hundreds of digits."""
    if isinstance(value, bool) or value is None:
        return repr(value)
    if isinstance(value, int):
        if abs(value) < 10**20:
            return str(value)
        digits = int(value.bit_length() * 0.30103) + 1
        return f"{'-' if value < 0 else ''}<{digits}-digit number>"
    if isinstance(value, float):
        text = repr(value)
        return text if len(text) <= 12 else f"{value:.3e}"
    if isinstance(value, str):
        return repr(value) if len(value) <= 40 else repr(value[:37]) + "…"
    return f"a value of type {type(value).__name__}"


def _argument(error: BaseException) -> str | None:
    """The argument whose conversion failed, from the note Python's binding adds."""
    for note in getattr(error, "__notes__", ()):
        m = _NOTE.match(note)
        if m:
            return m.group(1)
    return None


def _message(error: BaseException, name: str, value: Any) -> str:
    if isinstance(error, OverflowError):
        if isinstance(value, int) and value < 0:
            return f"{name}: expected a whole number ≥ 0, got {shown(value)}"
        return f"{name}: {shown(value)} is too large"
    text = str(error)
    expected = next((what for pattern, what in _EXPECTED if pattern.search(text)), None)
    if expected is None:
        first = text.splitlines()[0] if text else type(error).__name__
        return f"{name}: cannot use {shown(value)}: {first}"
    return f"{name}: expected {expected}, got {shown(value)}"


def checked(function: Callable[..., Any]) -> Callable[..., Any]:
    """`function` with its argument conversion errors raised as :class:`ContactddError`."""
    try:
        signature: inspect.Signature | None = inspect.signature(function)
    except (TypeError, ValueError):
        signature = None

    @functools.wraps(function)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return function(*args, **kwargs)
        except (TypeError, OverflowError, ValueError) as e:
            name = _argument(e)
            if name is None or isinstance(e, ContactddError):
                raise
            value: Any = None
            if signature is not None:
                try:
                    value = signature.bind_partial(*args, **kwargs).arguments.get(name)
                except TypeError:
                    pass
            raise ContactddError(_message(e, name, value)) from None

    return wrapper


def install_methods(cls: type) -> None:
    """Wraps the public methods of `cls` with :func:`checked` (the constructor checks its own
    arguments)."""
    for name, attribute in list(vars(cls).items()):
        if name.startswith("_"):
            continue
        if isinstance(attribute, staticmethod):
            setattr(cls, name, staticmethod(checked(attribute.__func__)))
        elif inspect.ismethoddescriptor(attribute) and callable(attribute):
            setattr(cls, name, checked(attribute))
