"""satgnc.mission: the main job as one path (docs/mission.md).

simulated tracking of the target -> OD estimate and covariance -> relative state -> L1 plan -> flight
on the J2 + drag truth -> controllability and observability checks of the models that were used.

``run(scenario, quick=False, closed_loop=None) -> MissionRun`` runs the stages on a mission scenario TOML
(:mod:`satgnc.scenarios.mission`); each stage is also a function of its own taking the previous
stages' read-only results (:func:`track`, :func:`estimate`, :func:`relative_state`, :func:`plan`,
:func:`fly`, :func:`check`). ``satgnc mission --scenario X.toml --out DIR`` is the command line.

:func:`failure_table` (issue 16): the thruster-loss table of a rendezvous (controllability verdict and
margin of the survivors, certified L1 replan, fuel, miss on the truth); ``satgnc rendezvous --failures``.
"""

from __future__ import annotations

from ..scenarios.mission import MissionScenario, load
from .failures import FailureRow, FailureTable, failure_table
from .pipeline import (
    Checks,
    ClosedLoop,
    Flight,
    HandOff,
    MissionError,
    MissionRun,
    OrbitEstimate,
    Plan,
    RelativeState,
    Tracking,
    check,
    estimate,
    flight_truth,
    fly,
    fly_closed_loop,
    od_force_model,
    plan,
    problem,
    relative_state,
    run,
    track,
    truth_force_model,
    truth_params,
)

__all__ = [
    "Checks",
    "ClosedLoop",
    "FailureRow",
    "FailureTable",
    "Flight",
    "HandOff",
    "MissionError",
    "MissionRun",
    "MissionScenario",
    "OrbitEstimate",
    "Plan",
    "RelativeState",
    "Tracking",
    "check",
    "estimate",
    "failure_table",
    "fly",
    "fly_closed_loop",
    "flight_truth",
    "load",
    "od_force_model",
    "plan",
    "problem",
    "relative_state",
    "run",
    "track",
    "truth_force_model",
    "truth_params",
]
