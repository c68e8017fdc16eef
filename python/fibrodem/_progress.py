"""A text progress bar for fibrodem.run(progress=True)."""

import sys
import time


class TextBar:
    """Draws ``[#####.....]  t / duration ms`` on one line of a stream.

    Works in a terminal and in a Jupyter notebook (both honour ``\\r``).
    Called with the simulated time [ms]; ``close()`` ends the line.
    """

    def __init__(self, duration_ms, stream=None, width=30):
        self.duration_ms = float(duration_ms)
        self.stream = stream if stream is not None else sys.stderr
        self.width = width
        self.started = time.monotonic()

    def __call__(self, t_ms):
        done = min(1.0, t_ms / self.duration_ms) if self.duration_ms > 0 else 1.0
        filled = int(round(done * self.width))
        elapsed = time.monotonic() - self.started
        left = elapsed / done - elapsed if done > 0 else float("nan")
        self.stream.write("\r[%s%s] %7.1f / %.1f ms  about %.0f s left " %
                          ("#" * filled, "." * (self.width - filled), t_ms, self.duration_ms, left))
        self.stream.flush()

    def close(self):
        self.stream.write("\n")
        self.stream.flush()
