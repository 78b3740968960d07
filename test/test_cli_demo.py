"""The README's demo command: the compensated sensor must beat static gain by far."""
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def run_demo(*args):
    out = subprocess.run(
        [sys.executable, "-m", "polyforce_ros.cli", "simulate", *args], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    rows = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) >= 5 and parts[-1].replace(".", "", 1).lstrip("-").isdigit() and parts[1] in ("static", "compensated"):
            rows[(parts[0], parts[1])] = float(parts[-3 if parts[1] == "compensated" else -3])
    return out, rows


def test_demo_compensation_beats_static_gain():
    out, rows = run_demo()
    for profile in ("needle_insertion", "step", "sawtooth", "creep"):
        static, compensated = rows[(profile, "static")], rows[(profile, "compensated")]
        assert compensated < static / 10, out
        assert compensated < 0.02, out  # ~ noise floor: 1 mV x 4.8 N/V


def test_demo_reports_bad_model_file(tmp_path):
    bad = tmp_path / "m.yaml"
    bad.write_text("format: polyforce_model/1\nelements: [{type: burgers}]\n")
    proc = subprocess.run(
        [sys.executable, "-m", "polyforce_ros.cli", "simulate", "--model", str(bad)], cwd=ROOT, capture_output=True, text=True
    )
    assert proc.returncode == 2
    assert "missing keys" in proc.stderr


def test_simulate_reads_the_sensor_as_the_whole_model_not_its_core_alone(tmp_path):
    """A model with hysteresis at the bridge: the simulated sensor has the plays too, so compensation is exact."""
    from polyforce_ros.model_file import SensorModel, save_model
    from polyforce_ros.physics.chain import BridgeHysteresisElement, OffsetElement, SensorChain, ViscoelasticElement
    from polyforce_ros.physics.viscoelastic import PAPER_BURGERS

    chain = SensorChain([BridgeHysteresisElement(ViscoelasticElement(PAPER_BURGERS), [0.2, 1.0], [0.02, 0.03]),
                         OffsetElement(0.0)])
    model = save_model(tmp_path / "m.yaml", SensorModel(chain, {"source": "test"}))
    out, rows = run_demo("--model", str(model), "--profile", "sawtooth", "--noise-v", "0")
    assert "bridge_hysteresis -> offset" in out
    assert rows[("sawtooth", "compensated")] < 0.01, out
