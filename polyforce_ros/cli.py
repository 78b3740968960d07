"""``polyforce``: command-line tools of polyforce_ros.

    polyforce demo                               live: driver (sim) -> compensation -> errors
    polyforce simulate                           offline: simulate, compensate, print errors
    polyforce calibrate CREEP.mcap --output M.yaml [--sensor-serial SN]
    polyforce compensate IN.mcap OUT.mcap [--model M.yaml]
    polyforce replay BAG.mcap [--rate 2.0] [--loop] [--lossless]
    polyforce evaluate [--out DIR] [--bag BAG.mcap ...]
    polyforce diagnose BAG.mcap --base {elastic,maxwell,kelvin,zener,burgers,...} [--json OUT] [--report DIR] \
[--save-model M.yaml]
    polyforce make-bags [--out bags/]
    polyforce bringup [--backend sim|serial] [--port DEV] [--model M.yaml] [--with-bridge] [--record BAG.mcap]
    polyforce check-device --port DEV [--samples N]    bring-up checklist of a serial ADC device: PASS/FAIL per check
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Mapping, Optional, Sequence

import numpy as np

from .bags import BagError
from .model_file import default_model_path, load_model
from .physics.chain import ModelError
from .physics.metrics import error_summary
from .sim import profiles
from .sim.sensor import BridgeSimulator
from .runtime import CompensatorConfig
from .runtime.compensator import time_drifts, time_drifts_note
from .runtime.sources import SerialSourceConfig, SimSourceConfig
from .workflows import CalibrationConfig, compensate_record


def _print_row(profile: str, label: str, e: Mapping[str, float]) -> None:
    print(f"{profile:<18} {label:<12} {e['rmse_n']:9.4f} {e['max_abs_n']:11.4f} {e['r2']:7.4f}")


def _header() -> None:
    print(f"{'profile':<18} {'method':<12} {'RMSE [N]':>9} {'max|e| [N]':>11} {'R2':>7}")


def cmd_simulate(args: argparse.Namespace) -> int:
    model = load_model(args.model or default_model_path())
    if args.profile == "okamura" and profiles.okamura_csv_path() is None:
        print("Okamura data not found; using the synthetic needle-insertion profile", file=sys.stderr)
        args.profile = "needle_insertion"
    if model.chain.viscoelastic is None:
        raise ModelError("polyforce simulate needs a model with a viscoelastic core")
    # the sensor is the model itself (every element, the simulator's bridge offset), read with noise and an ADC
    sensor = model.chain.with_offset(BridgeSimulator.offset_v)
    truth = BridgeSimulator(chain=sensor, noise_std_v=args.noise_v, seed=args.seed)
    kinds = " -> ".join(e.kind for e in sensor.elements)
    print(f"sensor truth: {truth.model} ({kinds})  noise {args.noise_v * 1e3:.2f} mV, {truth.adc_bits}-bit ADC")
    print(f"compensation model: {args.model or default_model_path()}")
    note = time_drifts_note(time_drifts(model.chain))  # the sensor drifts as the model says; the runtime does not follow
    if note:
        print(f"note: {note}", file=sys.stderr)
    _header()
    names = [args.profile] if args.profile != "all" else ["needle_insertion", "step", "sawtooth", "creep"]
    ok = True
    for name in names:
        truth.reset()
        t, f = profiles.make_profile(name, rate_hz=args.rate, seed=args.seed)
        v = truth.simulate(t, f)
        out = compensate_record(model.chain, t, v)
        used = out.used
        _print_row(name, "static gain", error_summary(f[used], out.static_n[used]))
        _print_row(name, "compensated", error_summary(f[used], out.compensated_n[used]))
        ok &= bool(used.all())
    return 0 if ok else 1


def cmd_demo(args: argparse.Namespace) -> int:
    from .demo import plot, run_live_demo

    model_file = args.model or ""
    load_model(model_file or default_model_path())  # fail early with a clear message
    print(f"live pipeline: driver_node (sim, {args.profile}) -> compensation_node "
          f"({model_file or default_model_path()}) -> recorder; DDS on loopback")
    result = run_live_demo(profile=args.profile, model_file=model_file, seed=args.seed, progress=not args.quiet)
    print(f"wrench messages received: {result['received_wrench']} of {result['expected']} samples "
          f"(+{result['unanswered_wrench']} stamped with no recorded sample: the watchdog's zeros); "
          f"tare {'ok' if result['tare_ok'] else 'FAILED'} (offset {result['offset_v']:.4f} V)")
    _header()
    _print_row(args.profile, "static gain", result["static"])
    _print_row(args.profile, "compensated", result["compensated"])
    if args.plot:
        plot(result, args.plot, f"Live demo: {args.profile}, compensated vs static gain")
        print(f"plot written to {args.plot}")
    good = result["tare_ok"] and np.all(np.isfinite(result["compensated_n"]))
    return 0 if good else 1


def cmd_calibrate(args: argparse.Namespace) -> int:
    from .physics.fitting import check_model_types
    from .workflows import calibrate_bag

    check_model_types(args.candidates)  # before reading the bag
    result = calibrate_bag(args.bag, args.output, candidates=tuple(args.candidates), min_r2=args.min_r2,
                           progress=lambda name: print(f"fitting {name} ...", file=sys.stderr),
                           sensor_serial=args.sensor_serial)
    for warning in result.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    print(f"{'model':<9} {'R2':>8} {'RMSE [V]':>10} {'BIC':>12}  parameters (± standard error)")
    for fit in result.fits:
        params = ", ".join(f"{k}={v:.5g}±{fit['stderr'][k]:.2g}" for k, v in fit["parameters"].items())
        print(f"{fit['model']:<9} {fit['r2']:8.5f} {fit['rmse_v']:10.3e} {fit['bic']:12.1f}  {params}")
    print(result.reason)
    if args.json:
        Path(args.json).write_text(json.dumps(result.summary(), indent=2, default=float))
    return 0 if result.written else 3


def cmd_compensate(args: argparse.Namespace) -> int:
    from .runtime.compensator import check_noise_gain, runtime_chain
    from .workflows import compensate_bag

    model = load_model(args.model or default_model_path())
    config = CompensatorConfig(force_limit_n=args.force_limit, auto_tare=not args.no_auto_tare,
                               max_noise_gain=args.max_noise_gain, noise_gain_rate_hz=args.rate,
                               apply_time_drifts=args.apply_time_drifts)
    # the chain the runtime runs, as the compensator will judge it; exit 2 when refused
    gain = check_noise_gain(runtime_chain(model.chain, config.apply_time_drifts), config.noise_gain_rate_hz,
                            config.max_noise_gain)
    print(f"model noise gain {gain.gain_n_per_v:.3g} N/V rms at {gain.rate_hz:g} Hz (max_noise_gain "
          f"{config.max_noise_gain:g}; most from {gain.element}); latency {1e3 * model.chain.latency_s:.1f} ms",
          file=sys.stderr)
    n, warnings = compensate_bag(args.input, args.output, model, config, directory=args.directory)
    for warning in warnings:
        print(f"warning: {warning}", file=sys.stderr)
    print(f"{args.output}: copied {args.input} and added {n} /polyforce/wrench messages "
          f"(model {args.model or default_model_path()})")
    return 0


def cmd_replay(args: argparse.Namespace) -> int:
    from .nodes.replay_node import main as replay_main

    ros_args = ["polyforce-replay", "--ros-args", "-p", f"bag_path:={args.bag}", "-p", f"rate_factor:={args.rate}",
                "-p", f"loop:={'true' if args.loop else 'false'}",
                "-p", f"lossless:={'true' if args.lossless else 'false'}"]
    return replay_main(ros_args)


def cmd_evaluate(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from .evaluation.common import Settings
    from .evaluation.report import EXPERIMENTS, run_evaluation

    settings = Settings(seed=args.seed, noise_std_v=args.noise_v, quick=args.quick)
    bar = tqdm(total=len(EXPERIMENTS) + len(args.bag), desc="evaluate", unit="experiment")

    def progress(name: str) -> None:
        bar.set_postfix_str(name)
        bar.update(1)

    report, data = run_evaluation(args.out, settings, args.bag, args.model, progress=progress)
    bar.close()
    for section in data["sections"]:
        judged = [r for r in section["rows"] if r["passed"] is not None]
        print(f"{section['title']}: {sum(r['passed'] for r in judged)} of {len(judged)} judged rows meet the paper")
    print(f"report: {report}")
    return 0 if data["polymer_sensor_all_met"] else 4


def compensated_force_lines(newtons: Mapping[str, Any], max_noise_gain: float) -> list[str]:
    """The printout's lines on the left-out blocks' compensated force, for the base, the saved model and the saved
    model as the runtime runs it. A model whose noise gain at the record's rate is above ``max_noise_gain`` says so:
    its force figures (a stiff core's inverse passes the bridge noise on at that gain) are not a force the runtime's
    guard lets through at that rate. Whether the runtime accepts the saved model at its own rate is the
    ``runtime_guard`` line's."""
    lines = []
    for label, q in (("base model", newtons.get("base")), ("saved model", newtons.get("saved")),
                     ("saved model as the runtime runs it (time drifts left out)", newtons.get("saved_runtime"))):
        if q:
            gain = q["noise_gain_n_per_v"]
            lines.append(f"compensated force, left-out blocks, {label}: RMSE {q['rmse_n']:.4f} N "
                         f"({q['rmse_percent_full_scale']:.2f} % FS), largest error {q['max_error_n']:.4f} N "
                         f"({q['max_error_percent_full_scale']:.2f} % FS), R2 {q['r2']:.4f}; noise gain "
                         f"{gain:.3g} N/V at {q['noise_gain']['rate_hz']:g} Hz"
                         + ("" if gain <= max_noise_gain else
                            f", above the default max_noise_gain {max_noise_gain:g} N/V at this rate"))
    return lines


def cmd_diagnose(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from .discrepancy.report import run

    bar = tqdm(desc="diagnose", unit="step", disable=not sys.stderr.isatty() and not args.progress)

    def progress(step: str) -> None:
        bar.set_postfix_str(step)
        bar.update(1)

    diag, data = run(args.bag, args.base, args.json, args.report, args.save_model, progress, args.folds, args.effects,
                     args.sensor_serial)
    bar.close()
    print(f"missing effect: {diag.missing_effect}  (base {diag.base})")
    for name in diag.missing_effects:
        saved = diag.saved_text(name)
        print(f"  named {name} ({diag.variants.get(name) or 'as in the catalogue'}), confidence {diag.confidences[name]:.0%}"
              + (f"; saved as {saved}" if saved else ""))
    print(f"validation RMSE (out of sample): {diag.rmse_before:.3e} V -> {diag.rmse_after:.3e} V; "
          f"noise floor {diag.noise_floor_v:.3e} V")
    if diag.unexplained["present"]:
        print(f"unexplained: structured residual {diag.unexplained['rms_v']:.3e} V that no catalogue effect describes")
    runtime_view = diag.newtons.get("saved_runtime")
    for line in compensated_force_lines(diag.newtons, CompensatorConfig.max_noise_gain):
        print(line)
    if runtime_view:
        print(f"  this record's drift left in that force: {runtime_view['drift_in_force_rms_n']:.4f} N rms (live, the "
              "start-up zeroing and ~/tare set the zero, and drift_tracking follows it at rest)")
    if diag.newtons.get("lag_bandwidth"):
        bw = diag.newtons["lag_bandwidth"]
        print(f"sensor lag inverted with a bandwidth: filter {bw['filter_factor']:g} x tau, order {bw['filter_order']}, "
              f"added delay {1e3 * bw['added_delay_s']:.1f} ms")
    if diag.newtons.get("friction_inverse_share"):
        fr = diag.newtons["friction_inverse_share"]
        print(f"friction inverted with share {fr['chosen']:g} of the band (compensated RMSE by share: "
              + ", ".join(f"{k}: {v:.4f} N" for k, v in fr["force_rmse_n"].items()) + ")")
    guard = diag.newtons.get("runtime_guard")
    if guard and not guard["accepted"]:
        gain = guard["noise_gain_n_per_v"][f"{guard['noise_gain_rate_hz']:g}"]
        print(f"warning: the saved model's inverse turns white bridge noise into {gain:.3g} N/V at "
              f"{guard['noise_gain_rate_hz']:g} Hz, above the default max_noise_gain {guard['max_noise_gain']:g} N/V: "
              "compensate and compensation_node refuse it unless max_noise_gain is raised (a sensor this stiff "
              "passes its own bridge noise on at that gain)")
    if diag.newtons.get("rejected"):
        print(f"not saved: {', '.join(diag.newtons['rejected']['effects'])} compensate the force worse than the base")
    for line in diag.evidence:
        print(f"  - {line}")
    if args.save_model:
        print(f"augmented model written to {args.save_model}")
        note = time_drifts_note(time_drifts(diag.chain))
        if note:
            print(f"note: compensate and compensation_node: {note}")
    return 0


def cmd_make_bags(args: argparse.Namespace) -> int:
    from .sim.recording import make_sample_bags

    progress = lambda name: print(f"simulating {name} ...", file=sys.stderr)  # noqa: E731
    for path in make_sample_bags(args.out, progress=progress, directory=args.directory):
        size = sum(f.stat().st_size for f in path.rglob("*")) if path.is_dir() else path.stat().st_size
        print(f"{path}  {size / 1e6:.2f} MB")
    return 0


def cmd_bringup(args: argparse.Namespace) -> int:
    from .bringup import bringup

    return bringup(backend=args.backend, port=args.port, model=args.model, with_bridge=args.with_bridge, record=args.record,
                   namespace=args.namespace, stop_timeout_s=args.stop_timeout, dry_run=args.dry_run)


def cmd_check_device(args: argparse.Namespace) -> int:
    """The bring-up checklist of polyforce_ros.device_check: 0 when every check passes, 1 when one fails, 2 on bad
    input (no such port, a bad option)."""
    from .device_check import DeviceOpenError, Limits, evaluate, format_report, read_device

    if args.samples < 2:
        raise ValueError(f"--samples must be at least 2, got {args.samples}")
    limits = Limits(max_noise_uv=args.max_noise_uv, max_offset_fraction=args.max_offset_percent / 100.0)
    timeout_s = args.timeout if args.timeout is not None else 5.0 + 0.002 * args.samples
    try:
        reading = read_device(args.port, args.samples, baud=args.baud, timeout_s=timeout_s)
    except DeviceOpenError as exc:
        print(f"polyforce check-device: error: {exc}", file=sys.stderr)
        return 2
    results = evaluate(reading, args.samples, limits, volts_per_count=args.volts_per_count,
                       expected_rate_hz=args.expected_rate)
    print(f"{args.port}: {len(reading.frames)} samples, sensor unloaded")
    print(format_report(results))
    return 0 if all(r.passed for r in results) else 1


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="polyforce", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)

    demo = sub.add_parser("demo", help="live pipeline on the embedded simulator: errors with and without compensation")
    demo.add_argument("--profile", default=SimSourceConfig.profile, choices=list(profiles.PROFILE_NAMES) + ["okamura"])
    demo.add_argument("--model", help="model YAML for the compensation node (default: the shipped paper model)")
    demo.add_argument("--seed", type=int, default=SimSourceConfig.seed)
    demo.add_argument("--plot", help="write a PNG of the forces and errors")
    demo.add_argument("--quiet", action="store_true", help="no progress bar")
    demo.set_defaults(func=cmd_demo)

    sim = sub.add_parser("simulate", help="offline: simulate the sensor, compensate it, print errors")
    sim.add_argument("--profile", default="all", choices=list(profiles.PROFILE_NAMES) + ["okamura", "all"])
    sim.add_argument("--model", help="model YAML (default: the shipped paper model)")
    sim.add_argument("--rate", type=float, default=SimSourceConfig.rate_hz, help="sample rate in Hz")
    sim.add_argument("--noise-v", type=float, default=SimSourceConfig.noise_std_v, help="bridge noise, V (1 sigma)")
    sim.add_argument("--seed", type=int, default=SimSourceConfig.seed)
    sim.set_defaults(func=cmd_simulate)

    cal = sub.add_parser("calibrate", help="fit the model from a creep bag and write the model YAML")
    cal.add_argument("bag")
    cal.add_argument("--output", required=True, help="model YAML to write (kept if the new fit is worse)")
    cal.add_argument("--candidates", nargs="+", default=list(CalibrationConfig.candidates),
                     help="model types to fit; the lowest BIC wins (default: %(default)s)")
    cal.add_argument("--min-r2", type=float, default=CalibrationConfig.min_r2,
                     help="a best fit below this R^2 is not written (default %(default)s)")
    cal.add_argument("--json", help="also write the fit report as JSON")
    cal.add_argument("--sensor-serial", help="serial number of the sensor the bag was recorded on, written into the "
                     "model's provenance (compensation_node compares it with the live device's)")
    cal.set_defaults(func=cmd_calibrate)

    comp = sub.add_parser("compensate", help="copy a bag and add the compensated /polyforce/wrench topic")
    comp.add_argument("input")
    comp.add_argument("output")
    comp.add_argument("--model", help="model YAML (default: the shipped paper model)")
    comp.add_argument("--force-limit", type=float, default=CompensatorConfig.force_limit_n,
                      help="clamp |force| to this (N), like the node's force_limit_n (default %(default)s)")
    comp.add_argument("--directory", action="store_true",
                      help="write OUT as a rosbag2 bag directory (OUT/OUT_0.mcap + metadata.yaml)")
    comp.add_argument("--no-auto-tare", action="store_true",
                      help="do not zero the bridge offset at the first rest (like the node's auto_tare: false)")
    comp.add_argument("--apply-time-drifts", action="store_true",
                      help="apply the model's time drifts (like the node's apply_time_drifts; by default they are "
                           "left out, with a warning), from the first sample after the start-up zeroing, or from the "
                           "record's first with --no-auto-tare")
    comp.add_argument("--max-noise-gain", type=float, default=CompensatorConfig.max_noise_gain,
                      help="refuse (exit 2) a model whose inverse turns white bridge noise into more than this force, "
                           "N per V rms, like the node's max_noise_gain (default %(default)s)")
    comp.add_argument("--rate", type=float, default=CompensatorConfig.noise_gain_rate_hz,
                      help="sample rate that noise gain is judged at, Hz (the node's noise_gain_rate_hz; "
                           "default %(default)s)")
    comp.set_defaults(func=cmd_compensate)

    rep = sub.add_parser("replay", help="play a bag onto the topics with its original timing")
    rep.add_argument("bag")
    rep.add_argument("--rate", type=float, default=1.0, help="playback speed factor")
    rep.add_argument("--loop", action="store_true")
    rep.add_argument("--lossless", action="store_true",
                     help="pace by the compensation node's answers on wrench: never lose a sample, --rate is an upper bound")
    rep.set_defaults(func=cmd_replay)

    ev = sub.add_parser("evaluate", help="run the seed papers' experiments and write a report (Markdown + JSON + figures)")
    ev.add_argument("--out", default="out/evaluation", help="output folder")
    ev.add_argument("--bag", action="append", default=[], help="also evaluate a recorded bag with reference_force (repeatable)")
    ev.add_argument("--model", help="model YAML for the bags (default: the shipped paper model)")
    ev.add_argument("--seed", type=int, default=0)
    ev.add_argument("--noise-v", type=float, default=1e-3, help="simulated bridge noise, V (1 sigma)")
    ev.add_argument("--quick", action="store_true", help="shorter records (for tests)")
    ev.set_defaults(func=cmd_evaluate)

    from .discrepancy.effects import NAMES as EFFECT_NAMES
    from .physics.viscoelastic import MODEL_TYPES

    dg = sub.add_parser(
        "diagnose", help="find where simulation and measurement disagree and name every missing effect",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Fit the base core to a bench bag, then add effects of the catalogue by forward selection, each "
                    "kept only when it lowers the out-of-sample error of a time-blocked cross-validation.\n\n"
                    "JSON: missing_effects (ordered list, empty for none), missing_effect (the first, 'none', or "
                    "'unexplained' when no effect is justified but a structured residual remains), effects (each with "
                    "its variant, confidence = share of cross-validation folds it improves, and saved = the scalar parameters of "
                    "the element that holds it: a resonance's frequency_hz and damping_ratio, a friction's radius_n...), "
                    "rmse_before/rmse_after (out of "
                    "sample, V), noise_floor_v (estimated from the data), unexplained {present, rms_v, noise_floor_v, "
                    "where}, skipped (e.g. thermal_drift without a temperature topic), candidates, evidence, coefficients "
                    "(each with a block-jackknife standard_error over the folds), model, newtons {base, saved: the "
                    "compensated force of the left-out blocks against the reference (rmse_n, max_error_n, their % of "
                    "full scale, r2) and the inverse's white-noise gain (noise_gain_n_per_v, its frequency response); "
                    "lag_bandwidth: the filter time and added delay of a sensor lag's inverse; friction_inverse_share: "
                    "the share of a friction its inverse adds back, chosen by the compensated force; saved_runtime: "
                    "the same figures for the saved model as compensate and the node run it by default (time drifts "
                    "left out), when it holds one; runtime_guard: the "
                    "saved model's noise gain against the runtime's default max_noise_gain (accepted or not); "
                    "rejected: effects not "
                    "saved because they compensate the force worse than the base}. The saved model's provenance "
                    "carries the same figures.\n"
                    f"Effects of the catalogue: {', '.join(EFFECT_NAMES)}.")
    dg.add_argument("bag", help="bench bag: bridge_voltage, reference_force, optional temperature")
    dg.add_argument("--base", required=True, choices=list(MODEL_TYPES), help="the core model to start from")
    dg.add_argument("--json", help="write the diagnosis as JSON")
    dg.add_argument("--report", help="write report.md and figures into this folder")
    dg.add_argument("--save-model", help="write the model with every named effect (loads in compensation_node)")
    dg.add_argument("--sensor-serial", help="serial number of the sensor the bag was recorded on, written into the "
                    "saved model's provenance (compensation_node compares it with the live device's)")
    dg.add_argument("--effects", nargs="+", choices=list(EFFECT_NAMES), help="consider only these effects (default: all)")
    dg.add_argument("--folds", type=int, default=5,
                    help="folds of the cross-validation, each made of interleaved time blocks (default 5)")
    dg.add_argument("--progress", action="store_true", help="show the progress bar even when stderr is not a terminal")
    dg.set_defaults(func=cmd_diagnose)

    mk = sub.add_parser("make-bags", help="regenerate the sample bags with the simulator")
    mk.add_argument("--out", default="bags")
    mk.add_argument("--directory", action="store_true", help="write rosbag2 bag directories (NAME/NAME_0.mcap + metadata.yaml)")
    mk.set_defaults(func=cmd_make_bags)

    bu = sub.add_parser("bringup", help="start driver + compensation (+ haptic bridge, recorder) as processes; Ctrl-C stops them")
    bu.add_argument("--backend", choices=["sim", "serial"], help="driver data source (default: config/driver.yaml)")
    bu.add_argument("--port", help="serial device of the ADC (default: config/driver.yaml)")
    bu.add_argument("--model", help="model YAML for the compensation node (default: the shipped paper model)")
    bu.add_argument("--with-bridge", action="store_true", help="also start haptic_bridge_node (config/haptic_bridge.yaml)")
    bu.add_argument("--record", metavar="BAG", help="also record the topic contract to this .mcap file")
    bu.add_argument("--namespace", default=None, help="namespace of the nodes (default: the contract's)")
    bu.add_argument("--stop-timeout", type=float, default=10.0, help="seconds a node gets to stop after SIGINT before SIGKILL")
    bu.add_argument("--dry-run", action="store_true", help="print the node commands and parameter sources, start nothing")
    bu.set_defaults(func=cmd_bringup)

    cd = sub.add_parser("check-device", help="bring-up checklist of a serial ADC device, sensor unloaded: info, status, "
                        "link, rate, zero-load counts and noise floor, PASS/FAIL each (exit 0 pass, 1 fail, 2 bad input)")
    cd.add_argument("--port", required=True, help="serial device of the ADC, e.g. /dev/serial/by-id/usb-...")
    cd.add_argument("--samples", type=int, default=1000, help="samples judged (default 1000: 1 s at 1 kHz)")
    cd.add_argument("--baud", type=int, default=SerialSourceConfig.baud, help="serial baud rate (ignored by USB CDC devices)")
    cd.add_argument("--timeout", type=float, help="seconds to wait for the info, a status and the samples "
                    "(default 5 + 2 ms per sample)")
    cd.add_argument("--max-noise-uv", type=float, default=5.0, help="noise limit, uV rms input-referred (default 5)")
    cd.add_argument("--max-offset-percent", type=float, default=25.0,
                    help="zero-load mean limit, %% of full scale (default 25)")
    cd.add_argument("--volts-per-count", type=float,
                    help="the driver's volts_per_count: checked against the device's (and used without an info message)")
    cd.add_argument("--expected-rate", type=float, help="the driver's expected_rate_hz: checked against the device's")
    cd.set_defaults(func=cmd_check_device)
    return parser


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        code: int = args.func(args)
        return code
    except (ModelError, BagError, FileNotFoundError, ValueError) as exc:
        print(f"polyforce {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
