"""Set-ups and reproductions of the papers satgnc was checked against (paper code, kept apart from the
library packages ``od``, ``analysis`` and ``guidance``, which never import it).

* :mod:`satgnc.papers.od_newton_raphson` -- Gao & Luo, Newton-Raphson orbit determination (Tables 1-11);
* :mod:`satgnc.papers.od_newton_raphson_mc` -- its formal covariance against Monte Carlo scatter;
* :mod:`satgnc.papers.polar_linearization_rank` -- the polar linearization's printed matrices and ranks;
* :mod:`satgnc.papers.l1_admm_rendezvous_linear` -- L1 ADMM rendezvous, Table 1 linear columns, Figs. 1-3;
* :mod:`satgnc.papers.l1_admm_rendezvous` -- the same paper's nonlinear cases (Table 1, Figs. 4-5), read
  from the scenario file ``scenarios/l1_rendezvous.toml``.

The report (``satgnc reproduce``) calls these modules. The old paths (``satgnc.od.paper``,
``satgnc.od.montecarlo``, ``satgnc.analysis.paper``, ``satgnc.guidance.rendezvous``,
``satgnc.guidance.nonlinear``) still import, with a DeprecationWarning naming the new module.
"""
