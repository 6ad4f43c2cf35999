"""satgnc.guidance: see the room's C++ headers under satgnc/guidance."""
