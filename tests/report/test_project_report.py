"""The report of a project run (flexgvt.report.project)."""


def test_report_says_how_far_the_objective_still_moved_at_the_evaluation_limit():
    from types import SimpleNamespace

    from flexgvt.report.project import _stop_note
    rows = [{"objective": v} for v in (1.0, 0.5, 0.30, 0.29, 0.288)]
    limit = SimpleNamespace(message="The maximum number of function evaluations is exceeded.", history=rows)
    note = _stop_note(limit)
    assert "evaluation limit" in note and "fell 71 %" in note and "last 4 iterations" in note and "raise" in note
    flat = SimpleNamespace(message=limit.message, history=[{"objective": v} for v in (0.5, 0.5, 0.5, 0.4995)])
    assert "raise" not in _stop_note(flat) and "fell 0.1 %" in _stop_note(flat)
    done = SimpleNamespace(message="`xtol` termination condition is satisfied.", history=rows)
    assert _stop_note(done) == done.message


def test_the_summary_counts_the_iterations_of_every_solve():
    """After identifiability holds the update is solved again; the summary counts each solve's
    iterations, not only the last one's (whose history the report plots)."""
    from types import SimpleNamespace

    from flexgvt.report.project import _iterations
    one = SimpleNamespace(stages=[{"iterations": 12, "variables": ["a", "b"]}], history=[{}] * 13)
    assert _iterations(one) == "12 iterations"
    two = SimpleNamespace(stages=[{"iterations": 54, "variables": list("abcd")}, {"iterations": 0, "variables": ["a"]}],
                          history=[{}])
    assert _iterations(two) == "54 + 0 iterations (4, then 1 variables)"
