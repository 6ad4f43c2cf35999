"""satgnc.mission: the main job as one path (docs/mission.md).

simulated tracking of the target -> OD estimate and covariance -> relative state -> L1 plan -> flight
on the J2 + drag truth -> controllability and observability checks of the models that were used.

``run(scenario) -> MissionRun`` runs every stage on a mission scenario TOML
(:mod:`satgnc.scenarios.mission`); each stage is also a function of its own taking the previous
stages' read-only results (:func:`track`, :func:`estimate`, :func:`relative_state`, :func:`plan`,
:func:`fly`, :func:`check`). ``satgnc mission --scenario X.toml --out DIR`` is the command line.
"""

from __future__ import annotations

from ..scenarios.mission import MissionScenario, load
from .pipeline import (
    Checks,
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
    fly,
    plan,
    relative_state,
    run,
    track,
    truth_params,
)

__all__ = [
    "Checks",
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
    "fly",
    "load",
    "plan",
    "relative_state",
    "run",
    "track",
    "truth_params",
]
