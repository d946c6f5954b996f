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
