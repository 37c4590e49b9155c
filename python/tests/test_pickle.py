"""Problems, results and errors pickle (multiprocessing, Jupyter): a round trip in this process
and through a spawned worker process gives identical attributes, and a problem solves to the
same result after it."""

import multiprocessing
import pickle

import pytest

import contactdd
from compare import assert_same_result, same_value


def round_trip(obj):
    return pickle.loads(pickle.dumps(obj))


def solve_in_worker(problem):
    """Runs in a spawned process: the problem arrives pickled, the result goes back pickled."""
    return contactdd.solve(problem)


def fail_in_worker(problem):
    """Runs in a spawned process: raises ConvergenceError (two iterations are not enough)."""
    return contactdd.solve(problem, max_iter=2)


def test_problem_round_trip_solves_the_same(notch):
    again = round_trip(notch)
    assert isinstance(again, contactdd.Problem)
    for name in ["name", "plane", "materials", "bodies", "contacts", "settings"]:
        same_value(getattr(notch, name), getattr(again, name), name)
    assert_same_result(contactdd.solve(notch), contactdd.solve(again), timing=False)


def test_result_round_trip(notch):
    result = contactdd.solve(notch)
    again = round_trip(result)
    assert_same_result(result, again)
    assert again.summary() == result.summary()
    assert repr(again) == repr(result)


def test_unpickled_result_writes_no_files(notch, tmp_path):
    again = round_trip(contactdd.solve(notch))
    with pytest.raises(contactdd.ContactddError, match="unpickled or read from a result folder"):
        again.write_vtu(tmp_path)


def test_monolithic_steps_and_sweep_round_trip(notch):
    mono = contactdd.monolithic(notch)
    assert_same_result(mono, round_trip(mono))
    assert round_trip(mono).summary() == mono.summary()
    steps = contactdd.solve_steps(notch, 2)
    for a, b in zip(steps, round_trip(steps)):
        assert_same_result(a, b)
    records = contactdd.sweep(notch, methods=["active-set"], gammas=[0.5, "auto"])
    assert round_trip(records) == records


def test_convergence_error_keeps_class_message_and_result(notch):
    with pytest.raises(contactdd.ConvergenceError) as info:
        contactdd.solve(notch, max_iter=2)
    again = round_trip(info.value)
    assert type(again) is contactdd.ConvergenceError
    assert str(again) == str(info.value)
    assert_same_result(info.value.result, again.result)


def test_io_error_keeps_class_message_and_errno(tmp_path):
    with pytest.raises(contactdd.ContactddIOError) as info:
        contactdd.Problem.from_toml(tmp_path / "missing.toml")
    again = round_trip(info.value)
    assert type(again) is contactdd.ContactddIOError
    assert str(again) == str(info.value)
    assert again.errno == info.value.errno is not None


def test_through_a_spawned_worker_process(notch):
    context = multiprocessing.get_context("spawn")
    with context.Pool(1) as pool:
        remote = pool.apply(solve_in_worker, (notch,))
        with pytest.raises(contactdd.ConvergenceError) as info:
            pool.apply(fail_in_worker, (notch,))
    assert_same_result(contactdd.solve(notch), remote, timing=False)
    assert remote.summary()["iterations"] == remote.iterations
    with pytest.raises(contactdd.ConvergenceError) as here:
        contactdd.solve(notch, max_iter=2)
    assert str(info.value) == str(here.value)
    assert_same_result(here.value.result, info.value.result, timing=False)
