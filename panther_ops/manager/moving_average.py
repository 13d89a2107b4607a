"""A moving average over a fixed window, like panther_utils::MovingAverage."""

from __future__ import annotations

from collections import deque


class MovingAverage:
    """Average of the last `window` values; `initial` until the first value arrives."""

    def __init__(self, window: int, initial: float = 0.0) -> None:
        if window < 1:
            raise ValueError(f"moving-average window must be at least 1, got {window}")
        self._values: deque[float] = deque(maxlen=window)
        self._sum = 0.0
        self._average = float(initial)

    @property
    def window(self) -> int:
        """The window length."""
        return self._values.maxlen or 1

    def roll(self, value: float) -> float:
        """Add a value and return the new average."""
        if len(self._values) == self._values.maxlen:
            self._sum -= self._values[0]
        self._values.append(float(value))
        self._sum += float(value)
        self._average = self._sum / len(self._values)
        return self._average

    @property
    def average(self) -> float:
        """The current average (the initial value before any sample)."""
        return self._average
