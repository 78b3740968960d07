"""``polyforce``: command-line tools of polyforce_ros.

    polyforce demo        simulate the sensor, compensate it, print the errors
"""
from __future__ import annotations

import argparse
import sys

import numpy as np

from .model_file import default_model_path, load_model
from .physics.chain import ModelError
from .physics.metrics import error_summary
from .sim import profiles
from .sim.sensor import BridgeSimulator

#: Seconds at the start of a record over which the unloaded bridge output is averaged (tare).
TARE_WINDOW_S = 0.5


def tare_offset_v(t_s, voltage_v, window_s=TARE_WINDOW_S) -> float:
    """Bridge offset estimated as the mean output over the first ``window_s`` (sensor unloaded)."""
    t = np.asarray(t_s)
    return float(np.mean(np.asarray(voltage_v)[t - t[0] <= window_s]))


def compare_static_and_compensated(chain, t_s, force_n, voltage_v):
    """Force estimates by static gain and by the chain's inverse, both tared alike.

    Returns ``(static_n, compensated_n)``.
    """
    offset = tare_offset_v(t_s, voltage_v)
    chain.offset.voltage_v = offset
    static = (np.asarray(voltage_v) - offset) / chain.static_gain_v_per_n()
    return static, chain.backward(t_s, voltage_v)


def cmd_demo(args) -> int:
    model = load_model(args.model or default_model_path())
    if args.profile == "okamura" and profiles.okamura_csv_path() is None:
        print("Okamura data not found; using the synthetic needle-insertion profile", file=sys.stderr)
        args.profile = "needle_insertion"
    truth = BridgeSimulator(model=model.chain.viscoelastic, noise_std_v=args.noise_v, seed=args.seed)
    print(f"sensor truth: {truth.model}  noise {args.noise_v * 1e3:.2f} mV, {truth.adc_bits}-bit ADC")
    print(f"compensation model: {args.model or default_model_path()}")
    print(f"{'profile':<18} {'method':<12} {'RMSE [N]':>9} {'max|e| [N]':>11} {'R2':>7}")
    names = [args.profile] if args.profile != "all" else ["needle_insertion", "step", "sawtooth", "creep"]
    ok = True
    for name in names:
        truth.reset()
        t, f = profiles.make_profile(name, rate_hz=args.rate, seed=args.seed)
        v = truth.simulate(t, f)
        static, compensated = compare_static_and_compensated(model.chain, t, f, v)
        for label, est in (("static gain", static), ("compensated", compensated)):
            e = error_summary(f, est)
            print(f"{name:<18} {label:<12} {e['rmse_n']:9.4f} {e['max_abs_n']:11.4f} {e['r2']:7.4f}")
        ok &= bool(np.all(np.isfinite(compensated)))
    return 0 if ok else 1


def build_parser():
    parser = argparse.ArgumentParser(prog="polyforce", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="simulate the sensor, compensate it, print errors")
    demo.add_argument("--profile", default="all", choices=list(profiles.PROFILE_NAMES) + ["okamura", "all"])
    demo.add_argument("--model", help="model YAML (default: the shipped paper model)")
    demo.add_argument("--rate", type=float, default=1000.0, help="sample rate in Hz")
    demo.add_argument("--noise-v", type=float, default=1e-3, help="bridge noise, V (1 sigma)")
    demo.add_argument("--seed", type=int, default=0)
    demo.set_defaults(func=cmd_demo)
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (ModelError, FileNotFoundError, ValueError) as exc:
        print(f"polyforce {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
