"""ROS-free runtime: what the nodes and the offline tools do with each sample."""
from .compensator import Compensator, CompensatorConfig, SampleGate

__all__ = ["Compensator", "CompensatorConfig", "SampleGate"]
