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


def held_notch(notch_toml, group, tail):
    """The notch example with the lower body held at its bottom (its support carries the load),
    the upper body's pressure in load group ``press`` if ``group``, and ``tail`` (the
    ``[solver]`` table and any ``[[steps]]``)."""
    body = notch_toml.read_text().split("[solver]")[0]
    lower = 'loads = [{ kind = "pressure", boundary = "bottom", value = 2100.0 }]'
    upper = '{ kind = "pressure", boundary = "top", value = 2100.0 }'
    support = 'supports = [{ boundary = "right", component = "x", value = 0.0 }]'
    assert lower in body and upper in body and support in body
    body = body.replace(lower, "").replace(
        support, support[:-1] + ', { boundary = "bottom", component = "y", value = 0.0 }]', 1)
    if group:
        body = body.replace(upper, upper[:-2] + ', group = "press" }')
    return contactdd.Problem.from_toml_str(body + "[solver]\ntol = 1e-8\n" + tail,
                                           source="held_notch.toml")


def imbalance(summary):
    """Per body, applied load + reactions + the pair's contact force on it: the largest, and the
    largest applied load."""
    pair = summary["contact"][0]
    worst = scale = 0.0
    for b, body in enumerate(summary["bodies"]):
        side = pair["bodies"].index(body["name"])
        for c in range(2):
            applied = body["applied_load"][c]
            total = applied + summary["reactions"][b]["total"][c] + pair["force"][side][c]
            worst, scale = max(worst, abs(total)), max(scale, abs(applied))
    return worst, scale


def test_every_step_balances_its_own_applied_loads(notch_toml):
    """Load steps and a load history that stop below the full load: every result's summary gives
    the applied loads of its own factors, which balance its reactions and contact forces."""
    history = ('[[steps]]\nname = "press"\nfactors = { press = 0.6 }\nincrements = 2\n'
               '[[steps]]\nname = "ease"\nfactors = { press = 0.4 }\n')
    cases = [(held_notch(notch_toml, False, ""), [0.25, 0.5], [0.25, 0.5]),
             (held_notch(notch_toml, True, history), None, [0.3, 0.6, 0.4])]
    for problem, load_steps, factors in cases:
        results = contactdd.solve_steps(problem, load_steps)
        assert len(results) == len(factors)
        for r, factor in zip(results, factors):
            s = r.summary()
            applied = s["bodies"][1]["applied_load"][1]
            assert abs(applied + 8400.0 * factor) <= 1e-9 * 8400.0, (factor, applied)
            worst, scale = imbalance(s)
            assert worst <= 1e-6 * scale, (factor, worst)
    with pytest.raises(contactdd.ContactddError, match="must increase"):
        contactdd.solve_steps(cases[0][0], [0.5, 0.5])
