"""Status enums: every _satgnc status enum is the C++ table of satgnc/core/status.hpp (names, values,
messages, `unsolved` first), and the strings users read are the ones they read before the table."""

from __future__ import annotations

import pytest
from satgnc import _satgnc, guidance
from satgnc.guidance import planning as nl  # the library module that reads the C++ tables

TABLES = _satgnc.status_tables()
BOUND = ["AdmmStatus", "IlqrAdmmStatus", "ScpStatus", "OdStatus", "ObservationStatus"]
# old Python member names kept as aliases of the same value (not table rows)
ALIASES = {"IlqrAdmmStatus": {"not_run": "unsolved"}, "ScpStatus": {"not_run": "unsolved"}}


def test_tables_unsolved_first_unique_snake_case():
    assert sorted(TABLES) == sorted(["AdmmStatus", "RiccatiStatus", "IlqrAdmmStatus", "ScpStatus", "OdStatus",
                                     "PropagationStatus", "Dop853Status", "KeplerStatus", "Verdict",
                                     "ObservationStatus"])
    for name, rows in TABLES.items():
        names = [r[1] for r in rows]
        values = [r[0] for r in rows]
        assert len(set(names)) == len(names), name
        assert sorted(values) == list(range(len(values))), name
        assert all(n == n.lower() and " " not in n for n in names), name
        assert all(len(r[2]) > 3 for r in rows), name
        assert (names[0] == "unsolved") == (name != "Verdict"), name


@pytest.mark.parametrize("enum_name", BOUND)
def test_bound_enum_is_the_cpp_table(enum_name):
    enum = getattr(_satgnc, enum_name)
    rows = TABLES[enum_name]
    members = {k: int(v) for k, v in enum.__members__.items()}
    expected = {n: v for v, n, _ in rows}
    for old, new in ALIASES.get(enum_name, {}).items():
        expected[old] = expected[new]
    assert members == expected
    for value, name, message in rows:
        member = getattr(enum, name)
        assert int(member) == value
        assert member.name == name  # the table name, also for values that have an old alias
        assert member.message == message


def test_strings_users_read_are_unchanged():
    assert guidance.STATUS_NAMES == {0: "solved", 1: "solved_paper_rule", 2: "max_iterations",
                                     3: "terminal_unreachable", 4: "numerical_error", 5: "unsolved",
                                     6: "solved_inaccurate", 7: "primal_infeasible", 8: "time_limit"}
    assert nl.SCP_STATUS_NAMES == {0: "solved", 1: "max_outer", 2: "propagation_failed", 3: "inner_failed",
                                   4: "line_search_failed", 5: "not_run", 6: "solved_inaccurate",
                                   7: "inner_infeasible", 8: "time_limit"}
    assert nl.ILQR_ADMM_STATUS_NAMES == {0: "solved", 1: "max_iterations", 2: "propagation_failed",
                                         3: "ilqr_failed", 4: "not_run", 5: "solved_inaccurate",
                                         6: "time_limit"}
    assert _satgnc.OdStatus.converged.name == "converged"
    assert int(_satgnc.OdStatus.stalled) == 7
    assert _satgnc.od_status_message(_satgnc.OdStatus.converged) == "converged"
    assert _satgnc.admm_status_message(5) == "not solved yet"
    assert _satgnc.status_message("success") == "success"
    assert "surface" in _satgnc.status_message("impact")
    with pytest.raises(ValueError, match="status: unknown status 'nope'"):
        _satgnc.status_message("nope")
    assert _satgnc.IlqrAdmmStatus.not_run == _satgnc.IlqrAdmmStatus.unsolved
    assert _satgnc.ScpStatus.not_run == _satgnc.ScpStatus.unsolved
    # the orbit filter's step statuses by value (read from filter/status.hpp's table since session 8)
    assert list(_satgnc.FILTER_STEP_STATUS) == ["updated", "rejected", "propagation_failed",
                                                "measurement_failed", "not_positive_definite", "not_run"]


def test_earth_constants_are_the_extension_s():
    """Issue 12 (I5): the Earth constants are defined once in C++ (core/constants.hpp); the Python
    modules re-export the extension's values, they do not re-type them."""
    from satgnc import analysis, od

    assert od.EARTH_MU is _satgnc.EARTH_MU
    assert od.EARTH_OMEGA is _satgnc.EARTH_OMEGA
    assert od.EARTH_RADIUS is _satgnc.EARTH_RADIUS
    assert analysis.MU_EARTH is _satgnc.EARTH_MU
    want = (398600.4418, 6378.1363, 7.292115e-5)  # km^3/s^2, km, rad/s
    assert (_satgnc.EARTH_MU, _satgnc.EARTH_RADIUS, _satgnc.EARTH_OMEGA) == want
