"""Deprecated: moved to :mod:`satgnc.papers.l1_admm_rendezvous_linear`
(paper code, kept apart from the library).

Every attribute still resolves, to the new module's object, with a DeprecationWarning naming it."""

from satgnc.papers._moved import forward as _forward

__getattr__, __dir__ = _forward("satgnc.guidance.rendezvous", "satgnc.papers.l1_admm_rendezvous_linear")
