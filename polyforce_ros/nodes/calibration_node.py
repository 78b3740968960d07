"""calibration_node: fit the sensor model from creep bags or a live creep experiment.

Services (std_srvs/Trigger; the bag path is the ``bag_path`` parameter because
Trigger carries no arguments and this package defines no interfaces):
* ``~/calibrate``: fit the bag at ``bag_path``;
* ``~/start_recording``: buffer ``bridge_voltage`` and ``reference_force``;
* ``~/stop_and_fit``: stop recording and fit what was recorded.

The model goes to ``output_path`` atomically, and only when the fit is good
(R^2 >= ``min_r2``) and better than the model already there (see
:func:`polyforce_ros.workflows.calibrate_record`). Every outcome is logged,
published as JSON on ``~/result`` (std_msgs/String, transient local) and
reported on /diagnostics.

The model's provenance names the sensor it was calibrated on (``sensor_serial``):
the ``sensor_serial`` parameter when set, else, for a live recording, the serial
the driver announced on ``sensor_serial`` while recording (none when it changed
during the recording, with a warning). A bag names no sensor by itself, so a bag
fit carries the parameter's serial only.
"""
from __future__ import annotations

import json
from array import array
from pathlib import Path
from typing import Any, Callable, Optional

import numpy as np
from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import WrenchStamped
from rclpy.qos import DurabilityPolicy, QoSProfile
from sensor_msgs.msg import JointState
from std_msgs.msg import String
from std_srvs.srv import Trigger

from ..physics.fitting import check_model_types
from ..record import record_from_samples
from ..workflows import CalibrationConfig, CalibrationResult, calibrate_bag, calibrate_record
from .. import contract
from .common import (DEFAULT_NAMESPACE, ERROR, OK, WARN, Diagnostics, RosNode, data_qos, declare, declare_qos,
                     declare_settings, latched_qos, run, stamp_to_ns)

DEFAULT_OUTPUT = str(Path.home() / ".ros" / "polyforce_model.yaml")


class CalibrationNode(RosNode):
    """The calibration node (``ros2 run polyforce_ros calibration_node``); ``kwargs`` as for ``Node``."""

    def __init__(self, **kwargs: Any) -> None:
        kwargs.setdefault("namespace", DEFAULT_NAMESPACE)
        super().__init__("calibration_node", **kwargs)
        declare(self, "bag_path", "", "Creep bag (mcap) fitted by ~/calibrate (and at start if calibrate_on_start)")
        declare(self, "output_path", DEFAULT_OUTPUT, "Model YAML written by a successful calibration")
        declare_settings(self, CalibrationConfig)  # candidates, min_r2
        declare(self, "calibrate_on_start", False, "Fit bag_path once at start-up", read_only=True)
        declare(self, "sensor_serial", "",
                "Serial number of the calibrated sensor, written into the model's provenance; empty = for a live "
                "recording the serial the driver announces on sensor_serial, for a bag none")
        declare_qos(self)
        qos = data_qos(self)
        self.diag = Diagnostics(self, "polyforce_ros: calibration")
        latched = QoSProfile(  # type: ignore[no-untyped-call]  # rclpy leaves QoSProfile(**kwargs) unannotated
            depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.pub_result = self.create_publisher(String, "~/result", latched)
        self.create_service(Trigger, "~/calibrate", self._on_calibrate)
        self.create_service(Trigger, "~/start_recording", self._on_start)
        self.create_service(Trigger, "~/stop_and_fit", self._on_stop_and_fit)
        self.create_subscription(JointState, contract.Rel.BRIDGE_VOLTAGE, self._on_raw, qos)
        self.create_subscription(WrenchStamped, contract.Rel.REFERENCE_FORCE, self._on_ref, qos)
        self.live_serial: Optional[str] = None  # the driver's latest sensor serial
        self._recorded_serials: set[str] = set()  # the serials announced while recording
        self.create_subscription(String, contract.Rel.SENSOR_SERIAL, self._on_serial, latched_qos())
        check_model_types(self.get_parameter("candidates").value)  # a clear error at start, not at the first fit
        self.recording = False
        self._raw_t, self._raw_v = array("q"), array("d")
        self._ref_t, self._ref_f = array("q"), array("d")
        self.last: dict[str, Any] = {"state": "idle"}
        self.create_timer(1.0, self._publish_diagnostics)
        if self.get_parameter("calibrate_on_start").value:
            self._calibrate(lambda: calibrate_bag(self.get_parameter("bag_path").value, **self._options()))

    def _options(self) -> dict[str, Any]:
        return dict(output=self.get_parameter("output_path").value,
                    candidates=tuple(self.get_parameter("candidates").value),
                    min_r2=self.get_parameter("min_r2").value,
                    sensor_serial=self.get_parameter("sensor_serial").value.strip() or None)

    def _on_serial(self, msg: String) -> None:
        self.live_serial = msg.data
        if self.recording:
            self._recorded_serials.add(msg.data)

    def _recording_serial(self, warnings: list[str]) -> Optional[str]:
        """The sensor serial of a live recording: the parameter's, else the one the driver announced (or None)."""
        serial: str = self.get_parameter("sensor_serial").value.strip()
        if serial:
            return serial
        if len(self._recorded_serials) > 1:
            warnings.append(f"the sensor serial changed during the recording ({', '.join(sorted(self._recorded_serials))})"
                            ": the model names no sensor")
            return None
        return next(iter(self._recorded_serials), None)

    def _calibrate(self, job: Callable[[], CalibrationResult]) -> dict[str, Any]:
        try:
            result = job()
        except (ValueError, OSError) as exc:  # BagError and fit failures are ValueErrors
            self.last = {"state": "failed", "written": False, "reason": str(exc)}
            self.get_logger().error(f"calibration failed: {exc}")
        else:
            self.last = {"state": "done", **result.summary()}
            best = result.fits[0]
            line = (f"calibration: {result.reason}; best {best['model']} R^2 {best['r2']:.4f} "
                    f"RMSE {best['rmse_v']:.3e} V; params {best['parameters']}")
            # one call site per severity: rclpy refuses a call site whose severity changes
            if result.written:
                self.get_logger().info(line)
            else:
                self.get_logger().warn(line)
        self.pub_result.publish(String(data=json.dumps(self.last, default=float)))
        self._publish_diagnostics()
        return self.last

    def _respond(self, response: Trigger.Response, outcome: dict[str, Any]) -> Trigger.Response:
        response.success = bool(outcome.get("written"))
        response.message = outcome.get("reason", "")
        return response

    def _on_calibrate(self, request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        path = self.get_parameter("bag_path").value
        if not path:
            response.success, response.message = False, "set the bag_path parameter first"
            return response
        return self._respond(response, self._calibrate(lambda: calibrate_bag(path, **self._options())))

    def _on_start(self, request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        for buf in (self._raw_t, self._raw_v, self._ref_t, self._ref_f):
            del buf[:]
        self._recorded_serials = {self.live_serial} if self.live_serial is not None else set()
        self.recording = True
        response.success, response.message = True, "recording bridge_voltage and reference_force"
        self.get_logger().info(response.message)
        return response

    def _on_stop_and_fit(self, request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        if not self.recording:
            response.success, response.message = False, "not recording; call ~/start_recording first"
            return response
        self.recording = False
        raw_t, raw_v = np.frombuffer(self._raw_t, np.int64), np.frombuffer(self._raw_v)
        ref_t, ref_f = np.frombuffer(self._ref_t, np.int64), np.frombuffer(self._ref_f)

        def job() -> CalibrationResult:
            rec = record_from_samples(raw_t, raw_v, ref_t, ref_f, source="live recording")
            if rec.t_s.size < 10:
                raise ValueError(f"recorded {rec.t_s.size} usable raw samples: too few to fit")
            assert rec.force_n is not None  # a record made with reference samples has the reference force
            warnings = list(rec.warnings)
            options = dict(self._options(), sensor_serial=self._recording_serial(warnings))
            return calibrate_record(rec.t_s, rec.force_n, rec.voltage_v, source="live recording",
                                    warnings=warnings, **options)

        return self._respond(response, self._calibrate(job))

    def _on_raw(self, msg: JointState) -> None:
        if self.recording and msg.position:
            self._raw_t.append(stamp_to_ns(msg.header.stamp))
            self._raw_v.append(msg.position[0])

    def _on_ref(self, msg: WrenchStamped) -> None:
        if self.recording:
            self._ref_t.append(stamp_to_ns(msg.header.stamp))
            self._ref_f.append(msg.wrench.force.z)

    def _publish_diagnostics(self) -> DiagnosticStatus:
        state = self.last["state"]  # idle, failed or done
        level = {"failed": ERROR, "idle": OK}.get(state, OK if self.last.get("written") else WARN)
        message = "recording" if self.recording else self.last.get("reason", "idle")
        values = {"recording": self.recording, "raw_samples": len(self._raw_v), "output": self.get_parameter("output_path").value}
        if self.last.get("fits"):
            best = self.last["fits"][0]
            values.update(best_model=best["model"], r2=best["r2"], rmse_v=best["rmse_v"])
        if self.last.get("sensor_serial"):
            values["sensor_serial"] = self.last["sensor_serial"]
        return self.diag.publish(level, message, values)


def main(args: Optional[list[str]] = None) -> int:
    return run(CalibrationNode, args)


if __name__ == "__main__":
    raise SystemExit(main())
