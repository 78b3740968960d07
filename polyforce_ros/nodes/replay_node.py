"""replay_node: play an mcap log onto the contract topics with its original timing.

Publishes the recorded ``bridge_voltage``, ``reference_force`` and
``temperature`` messages (whichever the bag holds) with their recorded header
stamps (the acquisition times), spaced as recorded (by log time) divided by
``rate_factor``. A compensation node downstream therefore runs on logged data
exactly as it would live. ``wrench`` is not replayed (it is what the
compensation node produces).

Loss is never silent. A reliable KEEP_LAST queue overflows without telling
anyone when its reader cannot keep up (a fast replay into a busy executor), and
a DDS acknowledgement only says a sample reached the reader's queue, not that
it was processed. The replay therefore listens to ``pace_topic`` (by default
the compensation node's ``wrench``, stamped like the raw sample it comes from)
and matches each answer to a published ``bridge_voltage`` stamp:

* timed mode (default): samples left unanswered for ``pace_timeout_s`` are
  counted (``unanswered``) and diagnostics WARN, as does falling behind schedule;
* ``lossless: true``: at most ``max_in_flight`` samples are published ahead of
  the last answer, so no queue of depth > ``max_in_flight`` can overflow
  whatever the speed of the machine; ``rate_factor`` is then an upper bound.
  Replay starts once every publisher has a subscriber, and the first sample is
  re-sent until it is answered (a reliable writer drops what it publishes
  before the reader has matched; the compensation node drops the re-sent
  duplicates by their stamp).
"""
from __future__ import annotations

import time
from collections import deque
from typing import Any, Optional

import numpy as np
from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import WrenchStamped

from .. import bags, contract
from .common import (DEFAULT_NAMESPACE, OK, WARN, Diagnostics, RosNode, data_qos, declare, declare_qos, message_class,
                     run, stamp_to_ns)

#: Replayed topics: full name in the bag -> relative name (wrench is what the compensation node makes).
_RELATIVE = {contract.full_name(rel): rel for rel in contract.RECORDED if rel != contract.Rel.WRENCH}
#: Lag behind schedule (s) above which the timed replay reports that it cannot keep its pace.
BEHIND_WARN_S = 0.1
#: Period (s) of re-sending the first sample until it is answered (lossless start).
HANDSHAKE_PERIOD_S = 0.2


class AnswerTracker:
    """Published sample stamps waiting for their answer on the pace topic (ROS-free).

    ``published`` registers a stamp; ``answered`` settles it and every stamp
    published before it (those were dropped downstream, e.g. duplicates, and
    are counted as unanswered); ``expire`` settles stamps older than a
    timeout. ``capacity`` bounds the memory: beyond it the oldest is settled as
    unanswered.
    """

    def __init__(self, capacity: int) -> None:
        self.capacity = int(capacity)
        self._pending: deque[tuple[int, float]] = deque()  # (stamp_ns, publish time s), in publish order
        self._seq: dict[int, int] = {}  # stamp_ns -> publish ordinal, pending only
        self._next = 0
        self._first = 0                 # ordinal of _pending[0]
        self.answered_count = 0
        self.unanswered = 0
        self.foreign = 0                # answers to stamps we did not publish (or already settled)

    def __len__(self) -> int:
        return len(self._pending)

    def published(self, stamp_ns: int, now_s: float) -> None:
        if stamp_ns in self._seq:  # a re-sent sample: one entry is enough
            return
        if len(self._pending) >= self.capacity:
            self._pop(unanswered=True)
        self._pending.append((stamp_ns, now_s))
        self._seq[stamp_ns] = self._next
        self._next += 1

    def answered(self, stamp_ns: int) -> bool:
        seq = self._seq.get(stamp_ns)
        if seq is None:
            self.foreign += 1
            return False
        while self._first < seq:
            self._pop(unanswered=True)
        self._pop(unanswered=False)
        self.answered_count += 1
        return True

    def expire(self, now_s: float, timeout_s: float) -> None:
        while self._pending and now_s - self._pending[0][1] > timeout_s:
            self._pop(unanswered=True)

    def oldest_age_s(self, now_s: float) -> float:
        return now_s - self._pending[0][1] if self._pending else 0.0

    def _pop(self, unanswered: bool) -> None:
        stamp, _ = self._pending.popleft()
        del self._seq[stamp]
        self._first += 1
        self.unanswered += int(unanswered)


class ReplayNode(RosNode):
    """The replay (``ros2 run polyforce_ros replay_node``); ``kwargs`` as for ``Node``."""

    def __init__(self, **kwargs: Any) -> None:
        kwargs.setdefault("namespace", DEFAULT_NAMESPACE)
        super().__init__("replay_node", **kwargs)
        path = declare(self, "bag_path", "", "The mcap log to play", read_only=True)
        declare(self, "rate_factor", 1.0,
                "Playback speed (2.0 = twice as fast); an upper bound when lossless", 0.01, 1000.0, read_only=True)
        declare(self, "loop", False, "Start again at the end", read_only=True)
        declare(self, "start_delay_s", 0.5,
                "Wait before the first message, for subscribers to connect (s)", 0.0, 60.0, read_only=True)
        declare(self, "joint_name", contract.JOINT_NAME, "JointState name used for replayed samples", read_only=True)
        declare(self, "frame_id", contract.FRAME_ID, "Frame of replayed messages", read_only=True)
        declare(self, "lossless", False,
                "Pace by answers on pace_topic: never more than max_in_flight samples ahead (no queue can overflow)",
                read_only=True)
        declare(self, "pace_topic", contract.Rel.WRENCH,
                "WrenchStamped topic stamped like the replayed bridge_voltage (the compensation output); empty = none",
                read_only=True)
        declare(self, "max_in_flight", 100,
                "Lossless mode: samples published ahead of the last answer", 1, 100000, read_only=True)
        declare(self, "pace_timeout_s", 2.0,
                "A sample not answered for this long is counted unanswered (s)", 0.01, 600.0, read_only=True)
        declare_qos(self)
        if not path:
            raise ValueError("replay_node needs the bag_path parameter")
        bag = bags.read_bag(path)
        for warning in bag.warnings:
            self.get_logger().warn(f"{path}: {warning}")
        qos = data_qos(self)
        streams = []
        for topic, data in bag.topics.items():
            if topic not in _RELATIVE or len(data) == 0:
                continue
            pub = self.create_publisher(message_class(data.type_name), _RELATIVE[topic], qos)
            streams.append((data.log_time_ns, data.stamp_ns, data.fields[bags.SCALAR_FIELD[data.type_name]], data.type_name, pub,
                            topic == bags.BRIDGE_VOLTAGE))
        if not streams:
            raise ValueError(f"{path}: no contract topic to replay")
        # One merged timeline ordered by log time.
        log = np.concatenate([s[0] for s in streams])
        order = np.argsort(log, kind="stable")
        self._log = log[order]
        self._stamp = np.concatenate([s[1] for s in streams])[order]
        self._value = np.concatenate([s[2] for s in streams])[order]
        self._stream = np.concatenate([np.full(len(s[0]), i) for i, s in enumerate(streams)])[order]
        self._kinds = [(s[3], s[4], s[5]) for s in streams]
        self._frame, self._joint = self.get_parameter("frame_id").value, self.get_parameter("joint_name").value
        self._rate = float(self.get_parameter("rate_factor").value)
        self._lossless = bool(self.get_parameter("lossless").value)
        self._window = int(self.get_parameter("max_in_flight").value)
        self._pace_timeout_s = float(self.get_parameter("pace_timeout_s").value)
        if self._lossless and self._window >= int(self.get_parameter("qos_depth").value):
            raise ValueError("max_in_flight must be smaller than qos_depth, or a queue can still overflow")
        pace_topic = self.get_parameter("pace_topic").value
        if self._lossless and not pace_topic:
            raise ValueError("lossless replay needs a pace_topic to pace by")
        self._answers = AnswerTracker(capacity=max(self._window, int(self.get_parameter("qos_depth").value)))
        if pace_topic:
            self.create_subscription(WrenchStamped, pace_topic, self._on_answer, qos)
        # timed mode tracks answers only while someone publishes the pace topic: a replay into a
        # recorder or a plot, with no compensation node, has nothing to answer and loses nothing
        self._tracking = self._lossless
        self._first_answer = False
        self._handshake_index: Optional[int] = None  # timeline index of the first bridge sample, while unanswered
        self._handshake_resends = 0
        self._last_handshake = 0.0
        self.behind_s = 0.0        # how far the last publication was behind schedule
        self.max_behind_s = 0.0
        self.diag = Diagnostics(self, "polyforce_ros: replay")
        self.index = 0
        self.loops = 0
        self.done = False
        self._started = False
        self._t_start = time.monotonic() + self.get_parameter("start_delay_s").value
        self.create_timer(0.001, self._tick)
        self.create_timer(1.0, self._refresh_tracking)
        self.create_timer(1.0, self._publish_diagnostics)
        mode = f"lossless, at most {self._window} in flight" if self._lossless else "timed"
        self.get_logger().info(f"replaying {path}: {self._log.size} messages over "
                               f"{(self._log[-1] - self._log[0]) * 1e-9:.1f} s at x{self._rate} ({mode})")

    # ------------------------------------------------------------------ pacing
    @property
    def answered(self) -> int:
        return self._answers.answered_count

    @property
    def unanswered(self) -> int:
        return self._answers.unanswered

    def _on_answer(self, msg: WrenchStamped) -> None:
        if self._answers.answered(stamp_to_ns(msg.header.stamp)):
            self._first_answer = True

    def _ready(self) -> bool:
        """Lossless mode starts once bridge_voltage has a subscriber and the pace topic a publisher."""
        if not self._lossless:
            return True
        pace = self.get_parameter("pace_topic").value
        raw = [pub for _, pub, is_raw in self._kinds if is_raw]
        return all(p.get_subscription_count() > 0 for p in raw) and self.count_publishers(
            self.resolve_topic_name(pace)) > 0

    def _tick(self) -> None:
        if self.done:
            return
        now = time.monotonic()
        if not self._started:
            if now < self._t_start or not self._ready():
                return
            self._started, self._t_start = True, now
            self._tracking = self._lossless or self._answerer_present()
        self._answers.expire(now, self._pace_timeout_s)
        elapsed = now - self._t_start
        due_log = self._log[0] + int(elapsed * self._rate * 1e9)
        end = int(np.searchsorted(self._log, due_log, side="right"))
        if self._lossless and not self._first_answer and self._handshake_index is not None:
            if now - self._last_handshake >= HANDSHAKE_PERIOD_S:  # re-send the first sample until answered
                self._publish(self._handshake_index, now)
                self._handshake_resends += 1
                self._last_handshake = now
            return
        i = self.index
        while i < end:
            kind, pub, is_raw = self._kinds[self._stream[i]]
            if is_raw and self._lossless and len(self._answers) >= self._window:
                break
            self._publish(i, now)
            i += 1
            if is_raw and self._lossless and not self._first_answer:
                self._handshake_index, self._last_handshake = i - 1, now
                break
        if i > self.index:
            self.behind_s = max(0.0, (due_log - self._log[i - 1]) * 1e-9 / self._rate)
            self.max_behind_s = max(self.max_behind_s, self.behind_s)
        self.index = i
        if self.index >= self._log.size:
            if self.get_parameter("loop").value:
                self.index, self.loops = 0, self.loops + 1
                self._t_start = time.monotonic()
            else:
                self.done = True
                self.get_logger().info(f"replay finished: {self.answered} samples answered, {self.unanswered} unanswered")

    def _publish(self, i: int, now: float) -> None:
        kind, pub, is_raw = self._kinds[self._stream[i]]
        stamp = int(self._stamp[i])
        pub.publish(bags.make_message(kind, stamp, self._value[i], self._frame, self._joint))
        if is_raw and self._tracking:
            self._answers.published(stamp, now)

    def _answerer_present(self) -> bool:
        pace = self.get_parameter("pace_topic").value
        return bool(pace) and self.count_publishers(self.resolve_topic_name(pace)) > 0

    def _refresh_tracking(self) -> None:
        """Timed mode: track answers while something publishes the pace topic (it may come and go)."""
        if not self._lossless:
            self._tracking = self._answerer_present()

    def _publish_diagnostics(self) -> DiagnosticStatus:
        values = {"published": self.index, "total": int(self._log.size), "loops": self.loops,
                  "answered": self.answered, "unanswered": self.unanswered, "in_flight": len(self._answers),
                  "behind_schedule_s": round(self.behind_s, 4), "max_behind_schedule_s": round(self.max_behind_s, 4),
                  "handshake_resends": self._handshake_resends, "lossless": self._lossless}
        if self.unanswered:
            level, message = WARN, f"{self.unanswered} samples not answered on the pace topic: subscribers lose messages"
        elif not self._tracking and self.index and not self.done:
            level, message = OK, "replaying; answers not tracked (nobody publishes the pace topic)"
        elif not self._lossless and self.behind_s > BEHIND_WARN_S:
            level, message = WARN, f"{self.behind_s:.2f} s behind schedule"
        elif self.done:
            level, message = WARN, "finished"
        else:
            level, message = OK, "replaying"
        return self.diag.publish(level, message, values)


def main(args: Optional[list[str]] = None) -> int:
    return run(ReplayNode, args)


if __name__ == "__main__":
    raise SystemExit(main())
