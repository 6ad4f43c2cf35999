"""satgnc's plotting style for your own figures (matplotlib; install with ``pip install "satgnc[plot]"``).

The report and the example gallery use the same rules: the Okabe-Ito colour-blind-safe palette, one
colour per axis (x / u1, y / u2, z / u3) across figures, titles, axis labels with units, legends
outside the data, and the start and the target marked on tracks.
"""

from __future__ import annotations

from typing import Any

from ._plot import AXIS_COLORS, PALETTE, SERIES_COLORS, legend_outside, mark_start_target

__all__ = ["AXIS_COLORS", "PALETTE", "SERIES_COLORS", "legend_outside", "mark_start_target", "pyplot"]


def pyplot() -> Any:
    """``matplotlib.pyplot`` on the Agg backend with satgnc's colour cycle and grid set."""
    from ._plot import _pyplot

    return _pyplot()
