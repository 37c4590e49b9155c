"""The γ sweep."""

import pytest

import contactdd

KEYS = {"method", "gamma", "iterations", "converged", "reason"}


def test_sweep_shape(notch):
    methods = ["active-set", "newton-chord", "newton-kurchatov"]
    gammas = [0.1, 0.5, 0.9]
    records = contactdd.sweep(notch, methods=methods, gammas=gammas)
    assert len(records) == len(methods) * len(gammas)
    assert all(set(r) == KEYS for r in records)
    assert [(r["gamma"], r["method"]) for r in records] == [(g, m) for g in gammas for m in methods]
    for r in records:
        assert r["converged"] == (r["reason"] == "")
    # A moderate γ converges for every method, a large one for none of them (the paper's finding).
    assert all(r["converged"] for r in records if r["gamma"] == 0.5)
    assert not any(r["converged"] for r in records if r["gamma"] == 0.9)


def test_sweep_matches_solve(notch):
    (rec,) = contactdd.sweep(notch, methods=["active-set"], gammas=[0.4])
    r = contactdd.solve(notch, method="active-set", gamma=0.4)
    assert rec["iterations"] == r.iterations and rec["converged"]


def test_sweep_defaults(notch):
    records = contactdd.sweep(notch, max_iter=50)
    assert len(records) == 3 * 18
    assert sorted({r["method"] for r in records}) == ["active-set", "newton-chord", "newton-kurchatov"]
    assert records[0]["gamma"] == 0.02 and records[-1]["gamma"] == 0.85


def test_sweep_auto(notch):
    (rec,) = contactdd.sweep(notch, methods=["robin"], gammas=["auto"])
    assert rec["gamma"] == "auto" and rec["method"] == "robin"


def test_progress_reports_every_run_once(notch):
    seen = []
    records = contactdd.sweep(notch, methods=["active-set", "robin"], gammas=[0.3, 0.5, "auto"],
                              progress=seen.append)
    assert len(seen) == len(records) == 6
    key = lambda r: (r["method"], str(r["gamma"]))  # noqa: E731
    assert sorted(seen, key=key) == sorted(records, key=key)
    assert records == contactdd.sweep(notch, methods=["active-set", "robin"],
                                      gammas=[0.3, 0.5, "auto"])


def test_progress_exception_stops_the_sweep(notch):
    class Stop(Exception):
        pass

    def stop(record):
        raise Stop(record["method"])

    with pytest.raises(Stop):
        contactdd.sweep(notch, gammas=[0.1, 0.3, 0.5], progress=stop)
