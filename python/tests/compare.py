"""Attribute-by-attribute comparison of contactdd result objects, for the tests that rebuild a
result another way (pickle, a problem written out and read back, a result folder read back)."""

import numpy as np

import contactdd

BODY = ["name", "order", "nodes", "triangles", "displacement", "stress", "von_mises",
        "contact_pressure"]
CONTACT = ["name", "bodies", "side", "node", "x", "y", "gap", "pressure", "nodal_traction", "closed", "status",
           "weight", "normal", "forces", "max_penetration", "complementarity"]
RESULT = ["converged", "stop", "iterations", "message", "method", "gamma", "theta", "history",
          "bodies", "contact", "updates", "gap_tol", "load_factor"]
MONOLITHIC = ["newton_steps", "rigid_modes", "bodies", "contact"]


def same_value(a, b, where):
    """Asserts that two attribute values are identical: arrays bit for bit (NaN equal to NaN,
    same dtype and shape), containers item by item, result objects attribute by attribute."""
    if isinstance(a, (contactdd.Body, contactdd.Contact)):
        assert type(a) is type(b), where
        names = BODY if isinstance(a, contactdd.Body) else CONTACT
        for name in names:
            same_value(getattr(a, name), getattr(b, name), f"{where}.{name}")
    elif isinstance(a, np.ndarray):
        assert isinstance(b, np.ndarray), where
        assert a.dtype == b.dtype and a.shape == b.shape, (where, a.dtype, b.dtype, a.shape, b.shape)
        assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), where
    elif isinstance(a, dict):
        assert isinstance(b, dict) and sorted(a) == sorted(b), (where, sorted(a), sorted(b))
        for k in a:
            same_value(a[k], b[k], f"{where}[{k!r}]")
    elif isinstance(a, (list, tuple)):
        assert type(a) is type(b) and len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            same_value(x, y, f"{where}[{i}]")
    elif isinstance(a, float) and np.isnan(a):
        assert isinstance(b, float) and np.isnan(b), where
    else:
        assert type(a) is type(b) and a == b, (where, a, b)


def assert_same_result(a, b, timing=True):
    """Asserts that two results (Result or MonolithicResult) have identical attributes; the wall
    times only when ``timing`` (two solves never take the same time)."""
    assert type(a) is type(b)
    names = RESULT if isinstance(a, contactdd.Result) else MONOLITHIC
    if timing:
        names = names + (["timing"] if isinstance(a, contactdd.Result) else ["seconds"])
    for name in names:
        same_value(getattr(a, name), getattr(b, name), name)
