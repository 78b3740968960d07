"""`polyforce evaluate`: the report has every experiment, the papers' numbers beside ours, and seed 000 is met."""
import json
import subprocess
import sys

from conftest import REPO


def test_evaluate_writes_report_with_all_rows(tmp_path):
    out = tmp_path / "eval"
    proc = subprocess.run([sys.executable, "-m", "polyforce_ros.cli", "evaluate", "--quick", "--out", str(out),
                           "--bag", str(REPO / "bags" / "step_5n.mcap")], cwd=REPO, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    data = json.loads((out / "report.json").read_text())
    titles = [s["title"] for s in data["sections"]]
    assert [t.split(":")[0] for t in titles[:3]] == ["Design and Modeling of a Polymer Force Sensor",
                                                     "Hysteresis in force sensing resistors",
                                                     "Thin-film force sensor on pneumatic artificial muscles"]
    assert "step_5n" in titles[3]
    metrics = {r["metric"] for s in data["sections"] for r in s["rows"]}
    for needed in ("R² of the creep fit", "minimum of the 4th cycle", "normalised hysteresis", "mean detected change",
                   "10-90 % rise time", "-3 dB bandwidth (re. the applied force)", "R² reading vs applied",
                   "bandwidth >= 3 Hz", "MSE reduction of CMA vs linear, whole data", "hysterons for n_h = 40",
                   "R² of the voltage fit", "slope of F vs p", "-3 dB bandwidth of the force reading"):
        assert needed in metrics, needed
    sensor_rows = data["sections"][0]["rows"]
    assert data["polymer_sensor_all_met"] and all(r["passed"] for r in sensor_rows if r["passed"] is not None)
    assert all(r["paper_ours_method"] is not None for r in sensor_rows if r["target"])  # the paper's number is beside ours
    report = (out / "report.md").read_text()
    for s in data["sections"]:
        for fig in s["figures"]:
            assert (out / fig).is_file() and fig in report
    bag_rows = {r["metric"]: r for r in data["sections"][3]["rows"]}
    assert bag_rows["rmse_n"]["ours_method"] < bag_rows["rmse_n"]["ours_baseline"] / 10
