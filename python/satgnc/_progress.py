"""A dependency-free progress bar for long jobs (report, sweeps); writes to stderr only on a TTY."""

from __future__ import annotations

import sys
import time


class Progress:
    """Count ``total`` steps and show ``label [#####.....] k/total elapsed``.

    On a non-TTY stream (CI logs) it prints one line per step instead of redrawing.
    """

    def __init__(self, total: int, label: str = "", stream=None, enabled: bool = True):
        if total < 0:
            raise ValueError(f"total: must be >= 0, got {total}")
        self.total = total
        self.label = label
        self.count = 0
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = enabled
        self._t0 = time.perf_counter()
        self._tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def step(self, what: str = "") -> None:
        self.count += 1
        if not self.enabled:
            return
        elapsed = time.perf_counter() - self._t0
        width = 30
        filled = int(width * self.count / max(self.total, 1))
        bar = "#" * filled + "." * (width - filled)
        line = f"{self.label} [{bar}] {self.count}/{self.total} {elapsed:6.1f}s {what}"
        if self._tty:
            self.stream.write("\r" + line[:120].ljust(120))
            if self.count >= self.total:
                self.stream.write("\n")
        else:
            self.stream.write(line + "\n")
        self.stream.flush()
