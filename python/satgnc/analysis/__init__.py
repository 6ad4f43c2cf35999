"""satgnc.analysis: see the room's C++ headers under satgnc/analysis."""
