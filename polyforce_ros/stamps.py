"""Stamp healing, the one rule shared by the compensation gate and the serial device clock.

A stamp (or a device time) that disagrees with the history is rejected. Rejected ones
that agree among themselves (increasing times, a steady skew between their time and
their arrival) for :data:`REANCHOR_AFTER_S` of arrival time are a clock that really
jumped (a device reset, a host clock step): the history re-anchors on them. ROS-free.
"""
from __future__ import annotations

from typing import Optional

__all__ = ["STAMP_TOLERANCE_S", "REANCHOR_AFTER_S", "ConsistentRun"]

#: The skew (stamp - arrival) may change by this much before a stamp is implausible, s.
STAMP_TOLERANCE_S = 1.0
#: Rejected but self-consistent stamps this long (arrival time) re-anchor the history, s.
REANCHOR_AFTER_S = 0.2


class ConsistentRun:
    """The run of rejected stamps that agree among themselves.

    Parameters
    ----------
    tolerance_ns : float
        How far the skew of consecutive members may differ [ns]; 0 or less: no limit.
    after_ns : float
        Arrival time the run must last to be believed [ns].
    """

    __slots__ = ("tolerance_ns", "after_ns", "_run")

    def __init__(self, tolerance_ns: float, after_ns: float) -> None:
        self.tolerance_ns, self.after_ns = tolerance_ns, after_ns
        self._run: Optional[list[int]] = None  # [first arrival, last time, last skew]

    def reset(self) -> None:
        """Forget the run (a stamp was accepted, or the history restarted)."""
        self._run = None

    def add(self, time: int, skew: int, arrival_ns: int) -> bool:
        """Take a rejected stamp; True once the run it belongs to has lasted ``after_ns`` of arrival time.

        A stamp that does not follow the run (not later, or its skew off by more than the tolerance)
        starts a new run.
        """
        run = self._run
        if run is None or time <= run[1] or (self.tolerance_ns > 0 and abs(skew - run[2]) > self.tolerance_ns):
            self._run = [arrival_ns, time, skew]
            return False
        run[1], run[2] = time, skew
        return arrival_ns - run[0] >= self.after_ns
