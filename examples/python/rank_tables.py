"""
Controllability, observability and loss tables
==============================================

Decide the controllability and observability of the Clohessy-Wiltshire model (Hill frame: x radial,
y along-track, z orbit normal; state m, m/s; inputs m/s^2) with the staircase form, which reports
its rounding margin, and tabulate what is lost when thrusters or sensors fail.
"""

import numpy as np
from satgnc import analysis

n = 0.0011  # rad/s: mean motion of a ~500 km LEO
A, B, C = analysis.cw_model(n)
ctrb = analysis.controllability(A, B)
print(f"CW with 3 thrust axes: rank {ctrb.rank}/6, {ctrb.verdict_text}, margin {ctrb.margin:.3g}")
# Along-track (y) thrust alone controls the in-plane motion only.
only_y = analysis.controllability(A, B[:, [1]])
print(f"along-track thrust only: rank {only_y.rank}/6, {only_y.verdict_text}")
print(analysis.format_loss_table(analysis.loss_table(A, B=B), ["ax", "ay", "az"], 6,
                                 title="Thruster loss table (CW)"))

# Sensors: measuring the relative position components.
A, B, C = analysis.cw_model(n, measured=(0, 1, 2))
print(analysis.format_loss_table(analysis.loss_table(A, C=C), ["x", "y", "z"], 6,
                                 title="Sensor loss table (CW)"))
print("numpy matrix_rank of the Kalman matrix:", int(np.linalg.matrix_rank(analysis.kalman_matrix(A, B=B))))
