"""Deprecated: moved to :mod:`satgnc.papers.polar_linearization_rank`
(paper code, kept apart from the library).

Every attribute still resolves, to the new module's object, with a DeprecationWarning naming it."""

from satgnc.papers._moved import forward as _forward

__getattr__, __dir__ = _forward("satgnc.analysis.paper", "satgnc.papers.polar_linearization_rank")
