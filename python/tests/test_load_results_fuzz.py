"""load_results on damaged result folders: a real folder's summary.json, contact.csv,
history.csv and VTU files (zlib, binary and ASCII) mutated with a seeded generator (bytes
flipped, files cut short, numbers replaced by nan, 1e300 or -1). Every call returns a result or
raises ContactddError: never another exception type, never a crash, never a hang."""

import random
import re
import shutil
import time

import pytest

import contactdd

FILES = ["summary.json", "contact.csv", "history.csv", "lower.vtu"]
NUMBER = re.compile(rb"-?\d+(\.\d+)?([eE][-+]?\d+)?")
REPLACEMENTS = [b"nan", b"NaN", b"1e300", b"-1", b"-1e300", b"Infinity", b"0"]
CASES = 600


def flip(data, rng):
    out = bytearray(data)
    for _ in range(rng.randint(1, 8)):
        out[rng.randrange(len(out))] = rng.randrange(256)
    return bytes(out)


def cut(data, rng):
    return data[:rng.randrange(len(data))]


def numbers(data, rng):
    matches = list(NUMBER.finditer(data))
    chosen = sorted(rng.sample(matches, min(len(matches), rng.randint(1, 6))),
                    key=lambda m: m.start(), reverse=True)
    for m in chosen:
        data = data[:m.start()] + rng.choice(REPLACEMENTS) + data[m.end():]
    return data


MUTATIONS = [flip, cut, numbers]


@pytest.fixture(scope="module", params=["zlib", "binary", "ascii"])
def original(tmp_path_factory, request):
    folder = tmp_path_factory.mktemp("fuzz") / "original"
    contactdd.solve(contactdd.notch_benchmark(8, 4)).write_vtu(folder, format=request.param)
    return folder


def test_damaged_folders_load_or_raise_contactdd_error(original, tmp_path):
    rng = random.Random(36)
    pristine = {name: (original / name).read_bytes() for name in FILES}
    folder = tmp_path / "run"
    shutil.copytree(original, folder)
    outcomes = {"loaded": 0, "refused": 0}
    start = time.monotonic()
    for case in range(CASES):
        name = rng.choice(FILES)
        mutation = rng.choice(MUTATIONS)
        (folder / name).write_bytes(mutation(pristine[name], rng))
        try:
            result = contactdd.load_results(folder)
        except contactdd.ContactddError:
            outcomes["refused"] += 1
        except BaseException as e:  # noqa: BLE001 - any other type is the failure looked for
            pytest.fail(f"case {case}: {mutation.__name__} of {name}: {type(e).__name__}: {e}")
        else:
            outcomes["loaded"] += 1
            assert isinstance(result, (contactdd.Result, contactdd.MonolithicResult))
            repr(result)
        (folder / name).write_bytes(pristine[name])
    # Both outcomes occur: the mutations reach past the first check.
    assert outcomes["loaded"] > 0 and outcomes["refused"] > 0, outcomes
    assert time.monotonic() - start < 30.0
