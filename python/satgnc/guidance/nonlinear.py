"""Deprecated: the nonlinear rendezvous module was split (issue 12).

* the library part: :func:`satgnc.guidance.plan` (``plan``, ``make_map``), :func:`satgnc.guidance.fly`
  and :func:`satgnc.guidance.mpc` (time-major results), :class:`satgnc.guidance.RendezvousProblem`;
* the paper part (``MU``, ``R_TARGET``, ``MASS``, ``TF``, ``N``, ``U_MAX``, ``Case``, ``paper_case``,
  ``release_state``, ``drift_state``, ``solve_paper``, ``solve_scp``, ``summarize``, ``miss``,
  ``model_params``, ``run_cli``, and ``fly``, ``mpc``, ``linear_cw_plan`` on a ``Case`` in the old
  3 x N / 12 x (N+1) orientation): :mod:`satgnc.papers.l1_admm_rendezvous`, its values read from
  ``scenarios/l1_rendezvous.toml``.

Every old name still resolves here with a DeprecationWarning naming its new place, and behaves as
before (old orientation, old return types).
"""

from satgnc.papers._moved import forward as _forward

_TIME_MAJOR = {
    "fly": " (same behaviour); the library's time-major form is satgnc.guidance.fly -> Flight",
    "mpc": " (same behaviour); the library's time-major form is satgnc.guidance.mpc -> MpcRun",
    "linear_cw_plan": " (same behaviour); the library's form is "
    "satgnc.guidance.plan(problem, model='linear')",
    "solve_scp": " (same behaviour); the library's form is satgnc.guidance.plan(problem, 'nonlinear', 'scp')",
    "solve_paper": " (same behaviour); the library's form is satgnc.guidance.plan(problem, 'nonlinear', "
    "'ilqr_admm')",
}

__getattr__, __dir__ = _forward(
    "satgnc.guidance.nonlinear",
    "satgnc.papers.l1_admm_rendezvous",
    renamed={"make_map": "satgnc.guidance.planning:make_map"},
    hints=_TIME_MAJOR,
)
