"""Exact contact (augmented Lagrangian) and load steps from Python: the same answers as the
command line's, checked against the Signorini conditions, force balance and linearity."""

import pytest

import contactdd


def peak(result):
    return max(abs(p) for p in result.contact[0].pressure)


def test_exact_contact_does_not_depend_on_the_penalty(notch):
    soft = contactdd.solve(notch, enforcement="augmented", accelerator="newton")
    stiff_problem = contactdd.notch_benchmark()
    assert soft.updates > 1 and soft.gap_tol > 0
    pair = soft.contact[0]
    assert pair.max_penetration <= soft.gap_tol
    assert pair.complementarity <= soft.gap_tol
    penalty = contactdd.solve(stiff_problem, accelerator="newton")
    assert penalty.updates == 0 and penalty.gap_tol is None
    # The penalty's penetration θ·p is far above the exact mode's tolerance.
    assert penalty.contact[0].max_penetration > 1e3 * soft.gap_tol
    # The exact mode presses harder at the notch edge (no spring layer softens it).
    assert peak(soft) > 1.05 * peak(penalty)


def test_enforcement_per_pair_and_bad_names():
    problem = contactdd.notch_benchmark()
    with pytest.raises(contactdd.ContactddError, match="enforcement"):
        contactdd.solve(problem, enforcement="lagrange")


def test_load_steps_carry_their_share_of_the_load(notch):
    results = contactdd.solve_steps(notch, 4, accelerator="newton")
    assert [r.load_factor for r in results] == [0.25, 0.5, 0.75, 1.0]
    for r in results:
        assert r.converged
        fy = abs(r.contact[0].forces[0][1])
        assert abs(fy - 8400.0 * r.load_factor) <= 1e-6 * 8400.0
    with pytest.raises(contactdd.ContactddError, match="load_steps"):
        contactdd.solve_steps(notch, [0.5, -1.0])


def test_progress_sees_every_iteration(notch):
    seen = []
    result = contactdd.solve(notch, progress=seen.append)
    assert [r["k"] for r in seen] == list(range(1, result.iterations + 1))
    assert len(seen[-1]["rel_change"]) == 2 and len(seen[-1]["normal_force"]) == 2


def test_an_exception_in_progress_stops_the_solve(notch):
    class Stop(Exception):
        pass

    def stop(record):
        if record["k"] == 2:
            raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        contactdd.solve(notch, progress=stop)
