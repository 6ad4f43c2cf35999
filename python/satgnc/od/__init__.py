"""satgnc.od: see the room's C++ headers under satgnc/od."""
