"""What every benchmark that starts ROS processes needs: DDS kept on this machine, and children stopped by PID."""
import os
import signal
import subprocess
import sys

STOP_TIMEOUT_S = 10.0


def isolate_dds():
    """DDS on loopback only, in a domain of this process's own (100..199), with the venv's ament index."""
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    os.environ["ROS_DOMAIN_ID"] = str(100 + os.getpid() % 100)
    os.environ.setdefault("AMENT_PREFIX_PATH", sys.prefix)


def stop_pid(proc, timeout=STOP_TIMEOUT_S):
    """SIGINT to the process's PID, SIGKILL after ``timeout`` s; returns (exit status, killed)."""
    if proc.poll() is not None:
        return proc.returncode, False
    proc.send_signal(signal.SIGINT)
    try:
        proc.wait(timeout)
        return proc.returncode, False
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        return proc.returncode, True
