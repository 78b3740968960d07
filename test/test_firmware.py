"""Reference firmware (firmware/): the other end of the serial cable, tested on the host.

* the whole firmware (core, host programs, the sketch on stubs) builds and passes its C
  self-checks with gcc and with clang, under -Werror and ASan + UBSan, wherever each exists;
* the core cross-compiles for the claimed cores (Cortex-M0+, Cortex-M4, RV32IMAC, AVR) with
  whatever cross compiler exists, and needs no library function where the README says so;
* the portable C core builds under strict flags and links no library; its frames equal
  serial_protocol.encode_frame byte for byte (edge cases and random samples); the ring
  buffer, the device clock and the pacer against exact references (ASan + UBSan builds);
  the device clock refuses counters it could not serve in constant time;
* the ADS1220 board sketch, compiled for the PC against stub Arduino headers and run with a
  scripted ADC: register bytes, SPI reads, frames, overflow and the DRDY watchdog; the
  temperature conversion once a second (register writes, decoding, never a sample); the
  50/60 Hz rejection build (20 SPS, register bytes, the info);
* the virtual device (same core) streaming into a pty read by a running DriverNode (serial
  backend): values and stamps match what the device sent, 1 kHz without loss through
  sequence and clock wraps, a 100 ppm fast device clock is followed, and the faults
  (unplug/replug, line noise, a dropped byte, a device reset, a device or link too slow) are
  each counted while no sample of a corrupt frame is ever published.
"""
import bisect
import math
import os
import queue
import random
import shutil
import signal
import subprocess
import sys
import threading
import time
from contextlib import contextmanager

import numpy as np
import pytest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.node import Node
from rclpy.parameter import Parameter
from sensor_msgs.msg import Temperature

from conftest import REPO
from polyforce_ros import contract
from polyforce_ros.nodes.common import stamp_to_ns
from polyforce_ros.nodes.driver_node import DriverNode
from polyforce_ros.serial_protocol import (FRAME_SIZE, DeviceInfo, DeviceStatus, DeviceTemperature, FrameParser,
                                           MessageDemux, encode_frame, encode_info, encode_message, encode_status)
from ros_harness import ros
from test_serial_protocol import GOLDEN_INFO, GOLDEN_INFO_STUFFED, GOLDEN_STATUS, GOLDEN_TEMPERATURE

FIRMWARE = REPO / "firmware"
#: the host compilers the firmware is built with: C and C++ driver of each, where installed
COMPILERS = {"gcc": (shutil.which("gcc"), shutil.which("g++")), "clang": (shutil.which("clang"), shutil.which("clang++"))}
# the programs the other tests run are built with gcc, or clang where gcc is missing
CC, CXX = COMPILERS["gcc"] if COMPILERS["gcc"][0] else COMPILERS["clang"]
pytestmark = pytest.mark.skipif(CC is None or shutil.which("make") is None,
                                reason="gcc or clang, and make, are needed to build the firmware")
SAN_ENV = dict(os.environ, ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:abort_on_error=0",
               UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1")
SCALE, OFFSET = 2.0**-20, 0.25  # exact in binary: published volts map back to counts exactly


def make(build_dir, *targets, timeout=300, cc=None, cxx=None, variables=()):
    cc, cxx = (cc, cxx) if cc else (CC, CXX)
    args = ["make", "-C", str(FIRMWARE), f"BUILD={build_dir}", f"CC={cc}", *variables]
    if cxx:
        args.append(f"CXX={cxx}")
    proc = subprocess.run([*args, *targets], capture_output=True, text=True, timeout=timeout)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-6000:]
    return proc


@pytest.fixture(scope="module")
def build(tmp_path_factory):
    out = tmp_path_factory.mktemp("firmware")
    make(out, "all", "sanitize", *(["sim"] if CXX else []))
    return out


def run(build, program, *args, stdin=None, timeout=120):  # a hang fails the test by its timeout
    proc = subprocess.run([str(build / program), *map(str, args)], input=stdin, capture_output=True, text=True,
                          timeout=timeout, env=SAN_ENV)
    assert proc.returncode == 0 and "FAIL" not in proc.stdout, proc.stdout[-3000:] + proc.stderr[-6000:]
    return proc.stdout


# ---------------------------------------------------------------------------------------- builds
@pytest.mark.parametrize("compiler", sorted(COMPILERS))
def test_everything_builds_and_self_checks_with_each_compiler(tmp_path, compiler):
    cc, cxx = COMPILERS[compiler]
    if cc is None or cxx is None:
        pytest.skip(f"{compiler} (C and C++) is not installed")
    # `make check`: strict core objects, the core as C++, the host programs, the ASan + UBSan builds,
    # the sketch on stubs, then the C self-checks (ring, threads, soft division, sketch smoke run)
    proc = make(tmp_path, "check", cc=cc, cxx=cxx)
    assert f"{cc} -std=c99 -Wall -Wextra -Werror" in proc.stdout and "-fsanitize=address,undefined" in proc.stdout
    assert "ok threads" in proc.stdout and "4294967295 4294967295 1 0" in proc.stdout
    for program in ("virtual_device", "fw_test", "fw_test_san", "fw_test_softdiv_san", "arduino_sim"):
        assert (tmp_path / program).is_file(), program


def _first_tool(*candidates):
    """The first of (command..., nm) whose program exists, or None."""
    for command, nm in candidates:
        if shutil.which(command[0]):
            return command, next((t for t in (nm, "llvm-nm", "nm") if shutil.which(t)), None)
    return None


_CLANG = shutil.which("clang")
#: claimed core -> (make target, make variable, [(compiler command, its nm)], library helpers it may need)
CROSS = {
    # ARMv6-M has no divide instruction: the core divides by itself (PFW_SOFT_DIVIDE), so nothing is needed
    "cortex-m0plus": ("cross-m0plus", "ARM_CC", [(["arm-none-eabi-gcc"], "arm-none-eabi-nm"),
                                                 ([_CLANG or "clang", "--target=arm-none-eabi", "-ffreestanding"],
                                                  "llvm-nm")], set()),
    "cortex-m4": ("cross-m4", "ARM_CC", [(["arm-none-eabi-gcc"], "arm-none-eabi-nm"),
                                         ([_CLANG or "clang", "--target=arm-none-eabi", "-ffreestanding"], "llvm-nm")],
                  set()),
    "rv32imac": ("cross-rv32", "RV_CC", [([_CLANG or "clang", "--target=riscv32-unknown-elf", "-ffreestanding"],
                                          "llvm-nm")], set()),
    # 8-bit AVR: 32-bit multiply and divide are libgcc helpers that avr-gcc always links (README)
    "avr": ("cross-avr", "AVR_CC", [(["avr-gcc"], "avr-nm")], {"__mulsi3", "__udivmodsi4"}),
}


@pytest.mark.parametrize("core", sorted(CROSS))
def test_core_cross_compiles_for_each_claimed_core(tmp_path, core):
    target, variable, candidates, allowed = CROSS[core]
    tool = _first_tool(*candidates)
    if tool is None:
        pytest.skip(f"no cross compiler for {core}: install one of " + ", ".join(c[0][0] for c in candidates))
    command, nm = tool
    proc = subprocess.run(["make", "-C", str(FIRMWARE), f"BUILD={tmp_path}", f"{variable}={' '.join(command)}", target],
                          capture_output=True, text=True, timeout=300)
    if proc.returncode != 0 and command[0] == _CLANG and "unknown target" in proc.stderr.lower():
        pytest.skip(f"this clang has no {core} backend: {proc.stderr.strip()[-300:]}")
    # the default configuration builds: on AVR that is 8-bit ring indices and a ring of 64
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    objects = list(tmp_path.glob("cross_*.o"))
    assert len(objects) == 1
    if nm is None:
        pytest.skip("no nm to list the object's undefined symbols")
    undefined = set(subprocess.run([nm, "-u", str(objects[0])], capture_output=True, text=True,
                                   check=True).stdout.split()) - {"U"}
    assert undefined <= allowed, (core, sorted(undefined - allowed))


# ---------------------------------------------------------------------------------------- the core
def test_core_builds_with_strict_flags_and_links_no_library(tmp_path):
    proc = make(tmp_path, "strict", *(["strict-cxx"] if CXX else []))
    assert "-std=c99 -Wall -Wextra -Werror -pedantic" in proc.stdout
    objects = sorted(tmp_path.glob("core_*.o"))
    # -O0, -O2, -Os with 8-bit ring indices, -O2 with the core's own division (, and as C++)
    assert len(objects) == (5 if CXX else 4)
    if shutil.which("nm"):
        for obj in objects:
            undefined = subprocess.run(["nm", "-u", str(obj)], capture_output=True, text=True, check=True).stdout.split()
            assert undefined == [], (obj.name, undefined)  # no libc, no heap, no OS: nothing to link
    includes = [line for line in (FIRMWARE / "polyforce_fw.c").read_text().splitlines() + (
        FIRMWARE / "polyforce_fw.h").read_text().splitlines() if line.startswith("#include")]
    assert sorted(set(includes)) == ['#include "polyforce_fw.h"', "#include <stdbool.h>", "#include <stddef.h>",
                                     "#include <stdint.h>"]


def _check_frame_lines(lines):
    decoded = []
    for line in lines:
        seq, t_us, counts, hexframe = line.split()
        frame = bytes.fromhex(hexframe)
        assert frame == encode_frame(int(seq), int(t_us), int(counts)), line
        # one parser per frame: these frames repeat and reorder sequence numbers, which a stream drops
        decoded += FrameParser().feed(frame)
    assert [(f.seq, f.t_us, f.counts) for f in decoded] == [tuple(map(int, line.split()[:3])) for line in lines]
    return len(lines)


def test_golden_frames_equal_serial_protocol_byte_for_byte(build):
    edge = run(build, "fw_test_san", "edge", 7, 3000).splitlines()
    assert _check_frame_lines(edge) == 6 * 7 * 10 + 3000
    extremes = [-(2**31), 2**31 - 1, -1, 0, 1, 2**23 - 1, -(2**23), 0x5AA5, -0x5AA5A5A5]
    rnd = random.Random(20240601)
    samples = [(rnd.choice([0, 1, 0xFFFE, 0xFFFF, rnd.randrange(2**16)]),
                rnd.choice([0, 2**31 - 1, 2**31, 2**32 - 1, rnd.randrange(2**32)]),
                rnd.choice(extremes + [rnd.randrange(-(2**31), 2**31)] * 4)) for _ in range(3000)]
    out = run(build, "fw_test_san", "encode", stdin="".join(f"{s} {t} {c}\n" for s, t, c in samples)).splitlines()
    assert len(out) == len(samples) and _check_frame_lines(out) == len(samples)


def test_golden_messages_equal_serial_protocol_byte_for_byte(build):
    assert run(build, "fw_test_san", "golden").split() == [
        m.hex() for m in (GOLDEN_INFO, GOLDEN_INFO_STUFFED, GOLDEN_STATUS, GOLDEN_TEMPERATURE)]
    rnd = random.Random(27)
    # any payload (0xA5 bytes to stuff), empty ones, the largest, and one too large
    payloads = [bytes(rnd.choice([0xA5, 0x5A, 0xC3, 0, rnd.randrange(256)]) for _ in range(rnd.randrange(65)))
                for _ in range(400)] + [b"", bytes([0xA5]) * 64, bytes(65)]
    lines = [f"{rnd.randrange(256)} {rnd.randrange(256)} {p.hex() or '-'}\n" for p in payloads]
    out = run(build, "fw_test_san", "message", stdin="".join(lines)).split()
    expected = [encode_message(int(t), bytes.fromhex(p) if p != "-" else b"", int(v)).hex()
                for t, v, p in (line.split() for line in lines[:-1])] + ["refused"]
    assert out == expected
    text = [rnd.choice(["-", "A", "ADS1220", "PF-0001", "0123456789abcdefXYZ"]) for _ in range(3 * 300)]
    infos = [DeviceInfo(rnd.randrange(2**32), rnd.randrange(2**32), rnd.randrange(2**16), rnd.randrange(256),
                        rnd.randrange(4), *(("" if t == "-" else t)[:n] for t, n in zip(text[3 * i:3 * i + 3], (8, 16, 16))))
             for i in range(300)]
    stdin = "".join(f"{i.rate_hz} {i.vref_uv} {i.gain} {i.adc_bits} {i.mains_filter} {' '.join(text[3 * k:3 * k + 3])}\n"
                    for k, i in enumerate(infos))
    assert run(build, "fw_test_san", "info", stdin=stdin).split() == [encode_info(i).hex() for i in infos]
    statuses = [DeviceStatus(rnd.randrange(2**32), rnd.randrange(6), rnd.randrange(2**16), rnd.randrange(2**32),
                             rnd.randrange(2**32), rnd.randrange(2**32)) for _ in range(300)]
    stdin = "".join(f"{s.t_us} {s.reset_reason} {s.watchdog_resets} {s.overflows} {s.adc_reconfigs} {s.uptime_s}\n"
                    for s in statuses)
    assert run(build, "fw_test_san", "status", stdin=stdin).split() == [encode_status(s).hex() for s in statuses]


def test_ads1220_temperature_words(build):
    # datasheet SBAS501 table 12: 14-bit left-justified, 0.03125 degC per code
    words = {0x0C80: 25.0, 0x0000: 0.0, 0xFFFC: -0.03125, 0xF380: -25.0, 0x1900: 50.0, 0x7FFC: 255.96875,
             0x8000: -256.0, 0x0004: 0.03125, 0x0C83: 25.0}  # the low two bits are not data
    out = run(build, "fw_test_san", "tempword", stdin="".join(f"{w:04x}\n" for w in words)).splitlines()
    assert [int(line.split()[1]) / 32 for line in out] == list(words.values())


def test_sequence_and_device_time_wrap(build):
    assert run(build, "fw_test_san", "seqwrap").split() == ["65533", "65534", "65535", "0", "1"]
    pairs = [(0, 0), (0, 1), (1, 0), (0, 2**32 - 1), (2**32 - 1, 0), (5, 2**32 - 5), (2**31 - 1, 0), (0, 2**31 - 1),
             (2**31, 0), (0, 2**31), (123456, 4000000000)]
    rnd = random.Random(3)
    pairs += [(rnd.randrange(2**32), rnd.randrange(2**32)) for _ in range(500)]
    out = run(build, "fw_test_san", "timediff", stdin="".join(f"{a} {b}\n" for a, b in pairs)).splitlines()
    for (a, b), line in zip(pairs, out, strict=True):
        assert int(line.split()[2]) == ((a - b + 2**31) % 2**32) - 2**31, line


def test_ads1220_words_are_sign_extended(build):
    words = [0x000000, 0x000001, 0x7FFFFF, 0x800000, 0x800001, 0xFFFFFF, 0xA55A00] + random.Random(5).sample(
        range(2**24), 500)
    out = run(build, "fw_test_san", "be24", stdin="".join(f"{w:06x}\n" for w in words)).splitlines()
    for word, line in zip(words, out, strict=True):
        assert int(line.split()[1]) == int.from_bytes(word.to_bytes(3, "big"), "big", signed=True)


@pytest.mark.parametrize("program", ["fw_test_san", "fw_test_u8_san"])
def test_ring_fill_overflow_and_wrap(build, program):
    out = run(build, program, "ring")
    capacity, width = (256, 4) if program == "fw_test_san" else (64, 1)
    assert f"ok fill capacity={capacity} overflows=2" in out  # full ring refuses and counts, never overwrites
    assert f"index_bytes={width}" in out  # 8-bit indices wrap hundreds of times in the interleaving check


def test_ring_between_two_threads(build):
    out = run(build, "fw_test_san", "threads", 200000)
    received, overflows = (int(x.split("=")[1]) for x in out.split()[2:4])
    assert received + overflows == 200000 and received >= 100000  # lossless half, then overflowing half


def test_soft_division_is_exact(build):
    rnd = random.Random(17)
    pairs = [(n, d) for n in (0, 1, 2**31 - 1, 2**31, 2**32 - 1) for d in (1, 2, 3, 2**31 - 1, 2**31, 2**31 + 1, 2**32 - 1)]
    pairs += [(rnd.randrange(2**32), rnd.choice([rnd.randrange(1, 2**32), rnd.randrange(1, 1 << rnd.randrange(1, 33))]))
              for _ in range(3000)]
    out = run(build, "fw_test_softdiv_san", "divmod", stdin="".join(f"{n} {d}\n" for n, d in pairs)).splitlines()
    assert [tuple(map(int, line.split())) for line in out] == [(n, d, n // d, n % d) for n, d in pairs]


def _clock_accepts(tick_hz):
    """The documented rule: 1e6 / tick_hz reduced to num / den with (den - 1) * (num + 1) < 2^32."""
    g = math.gcd(1_000_000, tick_hz)
    return (tick_hz // g - 1) * (1_000_000 // g + 1) < 2**32


@pytest.mark.parametrize("tick_hz", [4_294_967_291, 999_999, 14_318_180, 4_294_967_000])
def test_device_clock_refuses_a_counter_it_cannot_serve(build, tick_hz):
    # 4294967291 Hz used to be accepted with a zero step, and the update then never returned
    assert not _clock_accepts(tick_hz)
    for program in ("fw_test_san", "fw_test_softdiv_san"):
        assert run(build, program, "clock", tick_hz, 32, 0, stdin="0\n1\n", timeout=20).split() == ["invalid"]


def test_device_clock_accepts_what_its_header_promises(build):
    promised = [1_000_000, 1, 3, 125, 32_768, 11_059_200, 14_745_600, 16_000_000, 133_000_000, 3_999_999_000]
    rnd = random.Random(8)
    promised += [1000 * rnd.randrange(1, 4_000_000) for _ in range(40)]
    promised += [d for d in range(1, 1_000_001) if 1_000_000 % d == 0]
    for tick_hz in promised:
        assert _clock_accepts(tick_hz), tick_hz
    others = [rnd.randrange(1, 2**32) for _ in range(60)]
    stdin = "".join(f"{t}\n" for t in (0, 2**32 - 1, 5))
    for tick_hz in promised[:12] + others:
        out = run(build, "fw_test_san", "clock", tick_hz, 32, 0, stdin=stdin, timeout=20).split()
        if _clock_accepts(tick_hz):
            total = 2**32 - 1 + 6  # two updates: 2^32 - 1 ticks, then one wrap to 5
            assert out == [str((2**32 - 1) * 1_000_000 // tick_hz % 2**32), str(total * 1_000_000 // tick_hz % 2**32)]
        else:
            assert out == ["invalid"], tick_hz


@pytest.mark.parametrize("program", ["fw_test_san", "fw_test_softdiv_san"])
@pytest.mark.parametrize("tick_hz,bits", [(1_000_000, 32), (32_768, 16), (250_000, 8), (48_000_000, 24),
                                          (600_000_000, 32), (1_000_000_000, 32), (3, 2), (32_768, 24),
                                          (11_059_200, 32), (14_745_600, 16)])
def test_device_clock_is_exact_for_any_counter(build, tick_hz, bits, program):
    rnd = random.Random(tick_hz + bits)
    us0 = 2**32 - 1_000_000  # the microsecond clock wraps during the run
    total, readings = rnd.randrange(2**bits), []
    first = total
    for _ in range(4000):
        total += rnd.choice([0, 1, 2**bits - 1, rnd.randrange(2**bits)])  # at most one counter wrap per update
        readings.append(total)
    mask = 2**bits - 1
    stdin = "".join(f"{t & mask}\n" for t in [first, *readings])
    out = [int(x) for x in run(build, program, "clock", tick_hz, bits, us0, stdin=stdin).split()]
    expected = [(us0 + (t - first) * 1_000_000 // tick_hz) % 2**32 for t in readings]
    assert out == expected  # floor of the exact elapsed time: no drift, however long it runs
    assert (readings[-1] - first) * 1_000_000 // tick_hz > 1_000_000  # and it did wrap


@pytest.mark.parametrize("program", ["fw_test_san", "fw_test_softdiv_san"])
@pytest.mark.parametrize("rate_hz", [1000, 2000, 3000, 7, 999_983, 1_000_000])
def test_pacer_is_drift_free(build, rate_hz, program):
    first, n = 2**32 - 5000, 5000
    out = run(build, program, "pacer", rate_hz, first, n).split("\n")
    assert out[0] == f"period {1_000_000 // rate_hz}"
    assert [int(x) for x in out[1:] if x] == [(first + k * 1_000_000 // rate_hz) % 2**32 for k in range(n)]
    for bad in (0, 1_000_001):
        assert run(build, "fw_test_san", "pacer", bad, 0, 1).strip() == "invalid 0"


@pytest.mark.skipif(shutil.which("valgrind") is None, reason="valgrind not installed")
def test_core_under_valgrind(build):
    for args in (["ring"], ["edge", "1", "200"]):
        proc = subprocess.run(["valgrind", "-q", "--error-exitcode=99", str(build / "fw_test"), *args],
                              capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, proc.stderr[-4000:]


# ---------------------------------------------------------------------------------------- the sketch
@pytest.mark.skipif(CXX is None, reason="g++ is needed to compile the Arduino sketch for the PC")
def test_arduino_sketch_on_host_stubs(build):
    rnd = random.Random(11)
    words = [0x7FFFFF, 0x800000, 0xFFFFFF, 0x000000, 0x000001] + [rnd.randrange(2**24) for _ in range(20)]
    burst = [rnd.randrange(2**24) for _ in range(256 + 5)]  # the ring holds 256: five conversions are refused
    script = [f"conv {w:06x}\nloop\n" for w in words] + [f"conv {w:06x}\n" for w in burst] + ["loop\n"]
    script += ["advance 200000\n", "loop\n", "conv 123456\n", "loop\n"]  # DRDY silent for 200 periods: watchdog
    script += ["host 49 53 00\n", "loop\n"]  # the host asks for info and status (and sends a byte it ignores)
    micros0 = 2**32 - 20_000  # micros() wraps during setup
    out = run(build, "arduino_sim", micros0, stdin="".join(script)).splitlines()
    assert not [line for line in out if line.startswith("error")], out
    config = ["spi 06", "spi 43 3e c4 40 00", "spi 08"]  # RESET; WREG regs 0-3; START/SYNC
    assert out[:6] == ["baud 921600", *config, "attach 2 falling", "watchdog 1000"]
    assert "watchdog expired" not in out  # loop() stalled for 261 ms at most (the burst): less than the watchdog
    spi = [line for line in out if line.startswith("spi")]
    reads = [line for line in spi if line == "spi 00 00 00"]
    assert len(reads) == len(words) + len(burst) + 1  # every DRDY read 24 bits
    restart = spi.index("spi 06", 3)
    assert spi[restart:restart + 3] == config and spi[restart + 3] == "spi 00 00 00"
    isr = [int(line.split()[1]) for line in out if line.startswith("isr")]
    stream, messages = MessageDemux().feed(bytes.fromhex(out[-1].split()[1]))
    parser = FrameParser()
    frames = parser.feed(stream)
    assert len(stream) % FRAME_SIZE == 0 and parser.crc_errors == 0
    # at start: who it is and why it started; on request: the same, with the ADC reconfiguration and overflows
    info = DeviceInfo(rate_hz=1000, vref_uv=5_000_000, gain=128, adc_bits=24, mains_filter=0, adc="ADS1220",
                      board="arduino", sensor_serial="unset")
    assert [type(m) for m in messages] == [DeviceInfo, DeviceStatus, DeviceInfo, DeviceStatus]
    assert messages[0] == messages[2] == info and info.volts_per_count == 5 / 2**30
    assert (messages[1].reset_reason_name, messages[1].overflows, messages[1].adc_reconfigs) == ("power_on", 0, 0)
    assert (messages[3].overflows, messages[3].adc_reconfigs, messages[3].watchdog_resets) == (5, 1, 0)
    sent = words + burst[:256] + [0x123456]
    assert [f.counts for f in frames] == [int.from_bytes(w.to_bytes(3, "big"), "big", signed=True) for w in sent]
    assert [f.seq for f in frames] == list(range(len(words) + 256)) + [len(words) + 256 + 5]
    assert parser.lost_frames == 5  # the refused conversions are a sequence gap at the host
    stamped = isr[:len(words) + 256] + isr[-1:]
    assert [f.t_us for f in frames] == [(m - stamped[0] + frames[0].t_us) % 2**32 for m in stamped]
    assert frames[0].t_us < 20_000  # the device clock started at 0 in setup()


@pytest.mark.skipif(CXX is None, reason="g++ is needed to compile the Arduino sketch for the PC")
def test_arduino_sketch_watchdog_and_reset_reason(build):
    script = ["conv 000001\n", "loop\n", "advance 200000\n", "loop\n",  # fed while healthy
              "advance 1200000\n",  # loop() hangs (a stuck link write): not fed for 1.2 s
              "reboot 4\n", "conv 000002\n", "loop\n",  # the watchdog reset: counted, survives the reset
              "reboot 4\n", "loop\n", "reboot 2\n", "loop\n", "reboot 1\n", "loop\n"]  # again; reset pin; power-on
    out = run(build, "arduino_sim", 0, stdin="".join(script)).splitlines()
    assert not [line for line in out if line.startswith("error")], out
    assert out.count("watchdog expired") == 1 and out.index("watchdog expired") > out.index("spi 00 00 00")
    stream, messages = MessageDemux().feed(bytes.fromhex(out[-1].split()[1]))
    statuses = [(m.reset_reason_name, m.watchdog_resets) for m in messages if isinstance(m, DeviceStatus)]
    assert statuses == [("power_on", 0), ("watchdog", 1), ("watchdog", 2), ("external", 2), ("power_on", 0)]
    # one frame per boot, each numbered 0 by its boot
    assert [FrameParser().feed(stream[i:i + FRAME_SIZE])[0].counts for i in range(0, len(stream), FRAME_SIZE)] == [1, 2]


def _ads1220_temp_c(word):
    """The ADS1220 temperature word (24 bits, 14-bit two's complement left-justified) in degC."""
    raw = word >> 10
    return (raw - (1 << 14) if raw & (1 << 13) else raw) * 0.03125


def _sim_isr(out):
    """(micros, is_temperature) of each DRDY, in order."""
    return [(int(line.split()[1]), line.endswith(" ts")) for line in out if line.startswith("isr")]


@pytest.mark.skipif(CXX is None, reason="g++ is needed to compile the Arduino sketch for the PC")
def test_arduino_sketch_reads_the_adc_temperature_once_a_second(build):
    rnd = random.Random(31)
    # the temperature sensor's words: 25, -25.03125 (low bits are no data), 127.96875, -0.03125 degC
    temp_words = [0x0C8000, 0xF37FFF, 0x3FFC00, 0xFFFC00]
    words = [rnd.randrange(2**24) for _ in range(4300)]  # the bridge's words (unused by a temperature conversion)
    script = []
    for i, w in enumerate(words):
        if i % 1000 == 500:  # the sensor's word changes between two temperature conversions
            script.append(f"tempword {temp_words[i // 1000]:06x}\n")
        script.append(f"conv {w:06x}\nloop\n")
    out = run(build, "arduino_sim", 2**32 - 500_000, stdin="".join(script)).splitlines()
    assert not [line for line in out if line.startswith("error")], out
    isr = _sim_isr(out)
    ts_at = [k for k, (_, ts) in enumerate(isr) if ts]
    # once a second of device time (the first a second after start), 4.3 s of conversions: 4 of them
    assert len(ts_at) == 4 and all(1000 <= b - a <= 1002 for a, b in zip(ts_at, ts_at[1:])), ts_at
    assert isr[ts_at[0]][0] - isr[0][0] >= 1000_000 - 15_000
    # the register writes: right after a bridge read, register 1 with TS = 1 (C4 | 02) and START/SYNC;
    # after the temperature read, register 1 as configured (C4) and START/SYNC; nothing else
    spi = [line for line in out if line.startswith(("spi", "isr"))]
    for k in ts_at:
        at = [j for j, line in enumerate(spi) if line.startswith("isr")][k]
        assert spi[at - 4:at] == ["isr " + str(isr[k - 1][0]), "spi 00 00 00", "spi 44 c6", "spi 08"], spi[at - 4:at + 4]
        assert spi[at:at + 5] == [f"isr {isr[k][0]} ts", "spi 00 00 00", "spi 44 c4", "spi 08", f"isr {isr[k + 1][0]}"]
    assert len([line for line in spi if line.startswith("spi 44")]) == 2 * len(ts_at)
    stream, messages = MessageDemux().feed(bytes.fromhex(out[-1].split()[1]))
    temps = [m for m in messages if isinstance(m, DeviceTemperature)]
    # the temperature conversion, decoded (0.03125 degC per 14-bit LSB), stamped at its DRDY on the device clock
    assert [t.celsius for t in temps] == [_ads1220_temp_c(w) for w in temp_words] == [25.0, -25.03125, 127.96875,
                                                                                     -0.03125]
    parser = FrameParser()
    frames = parser.feed(stream)
    assert parser.crc_errors == 0 and parser.lost_frames == 0
    t0 = frames[0].t_us - isr[0][0]
    assert [t.t_us for t in temps] == [(isr[k][0] + t0) % 2**32 for k in ts_at]
    # no sample is published from a temperature conversion; every bridge conversion is, numbered without a gap
    bridge = [k for k in range(len(words)) if k not in ts_at]
    assert [f.counts for f in frames] == [int.from_bytes(words[k].to_bytes(3, "big"), "big", signed=True) for k in bridge]
    assert [f.seq for f in frames] == list(range(len(bridge)))
    assert [f.t_us for f in frames] == [(isr[k][0] + t0) % 2**32 for k in bridge]


@pytest.mark.skipif(CXX is None, reason="g++ is needed to compile the Arduino sketch for the PC")
def test_arduino_sketch_temperature_survives_a_silent_adc(build):
    # DRDY falls silent right after the switch to the temperature sensor: the ADC is configured again
    # (register 1 without TS), the next conversion is a bridge sample, then the lost temperature is taken
    script = [f"conv {i:06x}\nloop\n" for i in range(1, 1002)]  # setup() ends at 11 ms: TS after the last
    script += ["advance 150000\n", "loop\n"]  # silent for 150 periods
    script += [f"conv {i:06x}\nloop\n" for i in range(0x1000, 0x1010)] + ["host 53\n", "loop\n"]  # a status
    out = run(build, "arduino_sim", 0, stdin="".join(script)).splitlines()
    assert not [line for line in out if line.startswith("error")], out
    spi = [line for line in out if line.startswith(("spi", "isr"))]
    switch = spi.index("spi 44 c6")
    assert spi[switch - 2:switch + 10] == [
        "isr 1012000", "spi 00 00 00", "spi 44 c6", "spi 08",  # the bridge sample 1001, then TS on
        "spi 06", "spi 43 3e c4 40 00", "spi 08",  # silent: configured again, TS off
        "isr 1164000", "spi 00 00 00", "spi 44 c6", "spi 08",  # a bridge sample, then TS on again
        "isr 1165000 ts"]
    assert [line for line in spi if line.startswith("isr") and line.endswith("ts")] == ["isr 1165000 ts"]
    stream, messages = MessageDemux().feed(bytes.fromhex(out[-1].split()[1]))
    frames = FrameParser().feed(stream)
    assert [f.counts for f in frames] == list(range(1, 1002)) + [0x1000] + list(range(0x1002, 0x1010))
    assert [m.celsius for m in messages if isinstance(m, DeviceTemperature)] == [25.0]
    assert [m.adc_reconfigs for m in messages if isinstance(m, DeviceStatus)][-1:] == [1]


@pytest.mark.skipif(CXX is None, reason="g++ is needed to compile the Arduino sketch for the PC")
def test_arduino_sketch_with_mains_rejection(build):
    # PFW_MAINS_REJECTION=1: 20 SPS normal mode with simultaneous 50/60 Hz rejection, announced in the info
    rnd = random.Random(41)
    words = [rnd.randrange(2**23) for _ in range(230)]  # 11.5 s at 20 SPS
    script = [f"advance 49000\nconv {w:06x}\nloop\n" for w in words] + ["host 49\n", "loop\n"]
    out = run(build, "arduino_sim_mains", 0, stdin="".join(script)).splitlines()
    # the scripted ADC refuses the 50/60 Hz bits at any other rate ("error ...")
    assert not [line for line in out if line.startswith("error")], out
    # register 1 = 04: DR 000 (20 SPS), normal mode, continuous; register 2 = 50: REFP0/REFN0, 50/60 = 01
    assert out[1:4] == ["spi 06", "spi 43 3e 04 50 00", "spi 08"]
    spi = [line for line in out if line.startswith("spi 44")]
    assert spi == ["spi 44 06", "spi 44 04"]  # one temperature in 11.5 s: every 10 s at this rate
    stream, messages = MessageDemux().feed(bytes.fromhex(out[-1].split()[1]))
    infos = [m for m in messages if isinstance(m, DeviceInfo)]
    assert len(infos) == 2 and all(i.rate_hz == 20 and i.mains_filter == 1 for i in infos)
    assert infos[0].volts_per_count == 5 / 2**30
    assert [m.celsius for m in messages if isinstance(m, DeviceTemperature)] == [25.0]
    frames = FrameParser().feed(stream)
    assert len(frames) == len(words) - 1
    assert "watchdog expired" not in out  # fed at 20 SPS: conversions 50 ms apart keep the loop healthy


@pytest.mark.skipif(CXX is None, reason="g++ is needed to compile the Arduino sketch for the PC")
def test_sketch_mains_rejection_differs_from_the_default_build(build):
    # the default build must not set the 50/60 Hz bits (the datasheet allows them only at 20 SPS)
    out = run(build, "arduino_sim", 0, stdin="").splitlines()
    assert out[1:4] == ["spi 06", "spi 43 3e c4 40 00", "spi 08"]
    info = MessageDemux().feed(bytes.fromhex(out[-1].split()[1]))[1][0]
    assert (info.rate_hz, info.mains_filter) == (1000, 0)


# ---------------------------------------------------------------------------------------- live
class Listener(Node):
    """The driver's diagnostics over DDS; its samples as handed to its publisher (``raw``).

    The samples are recorded at the publish call, not through a subscription: at 1 kHz on a loaded
    two-core machine this single-threaded test executor may fall behind and the writer's KEEP_LAST
    history would then drop samples before a subscriber takes them (DDS delivery of bridge_voltage
    is tested in test_driver_node.py and test_two_namespaces.py). Here the question is what the
    driver publishes.
    """

    def __init__(self, context, driver):
        super().__init__("fw_listener", namespace="/polyforce", context=context)
        self.raw, self.diags, self.temps = [], [], []
        self.create_subscription(DiagnosticArray, "/diagnostics", self._diag, 100)
        self.create_subscription(Temperature, contract.TEMPERATURE, self.temps.append, 100)
        publish = driver.pub_raw.publish

        def record(msg):
            self.raw.append(msg)
            publish(msg)

        driver.pub_raw.publish = record

    def _diag(self, msg):
        for status in msg.status:
            if status.hardware_id == "driver_node":
                self.diags.append((status.level, status.message, {kv.key: kv.value for kv in status.values}))


class VirtualDevice:
    """firmware/host/virtual_device (ASan + UBSan build) on a pty behind a stable link."""

    def __init__(self, exe, tmp_path, *args):
        self.link, self.log = tmp_path / "ttyPOLYFORCE", tmp_path / "device.log"
        self.err_path = tmp_path / "device.err"
        self._err = open(self.err_path, "w")
        self.proc = subprocess.Popen([str(exe), "--link", str(self.link), "--log", str(self.log), *map(str, args)],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self._err, text=True,
                                     bufsize=1, env=SAN_ENV)
        self.lines = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for line in self.proc.stdout:
            self.lines.put(line.rstrip("\n"))

    def expect(self, h, prefix, timeout=20.0):
        """Spins ROS until the device prints a line starting with ``prefix``; returns it."""
        found = []

        def seen():
            while not found:
                try:
                    line = self.lines.get_nowait()
                except queue.Empty:
                    return False
                if line.startswith(prefix):
                    found.append(line)
            return True

        if not h.spin_until(seen, timeout):
            self._err.flush()
            raise AssertionError(f"virtual device never said {prefix!r} (exit status {self.proc.poll()}): "
                                 + self.err_path.read_text()[-3000:])
        return found[0]

    def command(self, h, cmd):
        self.proc.stdin.write(cmd + "\n")
        self.proc.stdin.flush()
        return self.expect(h, f"ok {cmd}")

    def stop(self):
        """SIGINT, then SIGKILL; returns the exit status."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(5)
        if not self.proc.stdin.closed:
            try:
                self.proc.stdin.close()
            except BrokenPipeError:
                pass
        self._err.close()
        return self.proc.returncode

    def assert_clean_exit(self):
        code = self.stop()
        err = self.err_path.read_text()
        assert code == 0 and "Sanitizer" not in err and "runtime error" not in err, err[-4000:]

    def status(self, h):
        self.proc.stdin.write("status\n")
        self.proc.stdin.flush()
        line = self.expect(h, "status ")
        return {k: int(v) for k, v in (item.split("=") for item in line.split()[1:])}

    def records(self):
        """Valid frames (seq, t_us, counts, acq_ns, write_ns), corrupt frames, and events with the
        number of valid frames written before them."""
        text = self.log.read_text()
        valid, corrupt, events = [], [], []
        for line in text[: text.rfind("\n") + 1].splitlines():
            kind, *rest = line.split()
            if kind == "F":
                valid.append(tuple(int(x) for x in rest))
            elif kind == "X":
                corrupt.append(tuple(int(x) for x in rest))
            else:
                events.append((kind if kind == "N" else rest[0], len(valid)))
        return valid, corrupt, events


def published_counts(raw):
    counts = []
    for msg in raw:
        volts = msg.position[0]
        c = round((volts - OFFSET) / SCALE)
        assert c * SCALE + OFFSET == volts, volts  # exactly a scaled integer count
        counts.append(c)
    return counts


def match_sent(counts, valid):
    """Indices into the device's valid frames of each published sample: the published samples must be
    the valid frames, in order, with none added (greedy in-order matching by value)."""
    positions = {}
    for i, frame in enumerate(valid):
        positions.setdefault(frame[2], []).append(i)
    out, j = [], -1
    for n, c in enumerate(counts):
        lst = positions.get(c, [])
        k = bisect.bisect_right(lst, j)
        assert k < len(lst), f"published sample {n} ({c} counts) is no valid frame sent after frame {j}"
        j = lst[k]
        out.append(j)
    return np.array(out)


def last_diag(lis):
    """(level, message, values) of the driver's latest diagnostics, or (None, "", {})."""
    return lis.diags[-1] if lis.diags else (None, "", {})


def received_rate(lis):
    value = last_diag(lis)[2].get("received_rate_hz", "n/a")
    return None if value == "n/a" else float(value)


@contextmanager
def live(tmp_path, build, device_args=(), **driver_params):
    """A DriverNode (serial backend) on the link of a virtual device; yields once samples flow."""
    dev = None
    try:
        with ros() as h:
            params = dict(backend="serial", port=str(tmp_path / "ttyPOLYFORCE"), volts_per_count=SCALE,
                          volts_offset=OFFSET, reconnect_period_s=0.05, diagnostics_period_s=0.2)
            params.update(driver_params)
            node = h.add(DriverNode(context=h.context,
                                    parameter_overrides=[Parameter(k, value=v) for k, v in params.items()]))
            lis = h.add(Listener(h.context, node))
            # the device's own volts_per_count (8 V / 2^23 = 2^-20) and rate agree with the driver's parameters
            dev = VirtualDevice(build / "virtual_device_san", tmp_path, "--vref-uv", 8_000_000, "--gain", 1, *device_args)
            dev.expect(h, "pty ")
            assert h.spin_until(lambda: len(lis.raw) >= 200, 60.0), "no samples from the virtual device"
            yield h, node, lis, dev
    finally:
        if dev is not None:
            dev.stop()


def test_live_stream_matches_device_through_wraps_and_follows_fast_clock(build, tmp_path):
    # sequence wraps ~1.5 s and the device clock ~2.5 s after the device starts; its crystal is 100 ppm fast
    args = ["--rate", 1000, "--ppm", 100, "--seq0", 65536 - 1500, "--t0-us", 2**32 - 2_500_000]
    with live(tmp_path, build, args, expected_rate_hz=1000.0, rate_window_s=1.0) as (h, node, lis, dev):
        arrival_ns = {}  # device time -> host instant the driver read its frame (the clock's only evidence)
        stamp_batch = node.clock.stamp_batch

        def spy(t_us_seq, arrival):
            arrival_ns.update(dict.fromkeys(t_us_seq, arrival))
            return stamp_batch(t_us_seq, arrival)

        node.clock.stamp_batch = spy
        n0, crc0, lost0 = len(lis.raw), node.parser.crc_errors, node.parser.lost_frames
        assert h.spin_until(lambda: len(lis.raw) >= n0 + 8000, 120.0)
        assert h.spin_until(lambda: received_rate(lis) is not None, 20.0)
        level, message, values = last_diag(lis)
        raw = list(lis.raw)
        crc, lost, implausible = node.parser.crc_errors - crc0, node.parser.lost_frames - lost0, node.clock.implausible
    dev.assert_clean_exit()
    valid, corrupt, _ = dev.records()
    idx = match_sent(published_counts(raw), valid)
    assert not corrupt
    # 1 kHz without loss: every valid frame from the first published one on was published
    assert np.all(np.diff(idx) == 1), np.flatnonzero(np.diff(idx) != 1)[:10]
    assert crc == 0 and lost == 0 and implausible == 0
    assert level == DiagnosticStatus.OK, message
    assert float(values["received_rate_hz"]) == pytest.approx(1000.0, rel=0.1)  # one window: host stalls shift it
    sent = np.array([valid[i] for i in idx], dtype=np.int64)
    seq, t_us, acq = sent[:, 0], sent[:, 1], sent[:, 3]
    assert np.any(np.diff(seq) < 0) and np.any(np.diff(t_us) < 0)  # both wrapped inside the measured stream
    # stamps: the host instant of each conversion (acq, from the device's simulated crystal), to within
    # the transport latency; the mapping anchors on the least-delayed frames of the first second
    stamps = np.array([stamp_to_ns(m.header.stamp) for m in raw], dtype=np.int64)
    err = (stamps - acq) / 1e3  # us
    settled = err[1000:]
    profile = [(round(c.min()), round(np.median(c)), round(c.max())) for c in np.array_split(err, 8)]
    assert settled.min() > -300, profile  # never earlier than the conversion (beyond clock-read rounding)
    assert np.median(settled) < 3000 and settled.max() < 20000, profile
    # 100 ppm fast: 1000 us of device time are 1 ms / (1 + 1e-4) = 999.9 us of host time. A mapping that
    # kept its first offset would be late by 100 us per second of run on top of the first frame's
    # latency. The driver's offset steps down as newer frames show a smaller delay, so at the end the
    # error is the latency of the best recent frame plus the drift since it. That latency is this
    # machine's (a loaded host reads late), so the bound is taken from the arrivals the driver saw.
    run_s = (acq[-1] - acq[1000]) / 1e9
    assert run_s > 6.5
    seen = np.array([t in arrival_ns for t in t_us])
    assert seen[-2000:].all()
    latency_us = np.array([arrival_ns[t] - a for t, a in zip(t_us[-2000:], acq[-2000:])]) / 1e3
    since_s = (acq[-1] - acq[-2000:]) / 1e9
    best_recent_us = np.min(latency_us + 100e-6 * since_s * 1e6)  # best evidence of the last 2 s, drift included
    first_us = err[np.flatnonzero(seen)[0]]
    assert err[-1000:].min() <= best_recent_us + 50, (best_recent_us, first_us, run_s, profile)

def test_live_faults_are_counted_and_never_publish_a_corrupt_sample(build, tmp_path):
    with live(tmp_path, build, ["--rate", 1000, "--ppm", 30], expected_rate_hz=1000.0,
              rate_window_s=1.0) as (h, node, lis, dev):
        p = node.parser

        def flowing(extra=200):
            n = len(lis.raw)
            assert h.spin_until(lambda: len(lis.raw) >= n + extra, 30.0), "samples stopped"

        # line noise: costs CRC rejections, not one frame
        crc, lost = p.crc_errors, p.lost_frames
        dev.command(h, "noise 64")
        assert h.spin_until(lambda: p.crc_errors > crc, 20.0)
        flowing()
        assert p.lost_frames == lost
        # a dropped byte: that frame fails its CRC and is a sequence gap of one
        crc, lost = p.crc_errors, p.lost_frames
        dev.command(h, "dropbyte")
        assert h.spin_until(lambda: p.lost_frames > lost, 20.0)
        flowing()
        assert p.crc_errors > crc and p.lost_frames == lost + 1
        # unplug and replug: ERROR while away, reconnected by the driver itself
        dev.command(h, "unplug")
        assert h.spin_until(lambda: not node.connected, 20.0)
        assert h.spin_until(lambda: last_diag(lis)[0] == DiagnosticStatus.ERROR, 20.0)
        h.spin_for(0.3)  # the cable stays out for a few reconnect attempts
        assert node.outages == 1 and not node.connected
        dev.command(h, "plug")
        assert h.spin_until(lambda: node.connected, 20.0)
        flowing()
        # device reset: sequence and clock restart at 0; the stamps re-anchor after 0.2 s of agreement
        implausible, reanchored, lost, jumps = node.clock.implausible, node.clock.reanchored, p.lost_frames, p.seq_jumps
        resets = node.sensor_resets
        dev.command(h, "reset")
        assert h.spin_until(lambda: node.clock.reanchored == reanchored + 1, 20.0)
        assert node.sensor_resets == resets + 1  # sensor_reset sent: the compensation clears its history and re-zeroes
        flowing(500)
        assert node.clock.implausible > implausible
        assert h.spin_until(lambda: last_diag(lis)[2].get("reanchored") == "1", 10.0)
        level, message, values = last_diag(lis)
        raw = list(lis.raw)
        lost_at_reset, jumps_at_reset = p.lost_frames - lost, p.seq_jumps - jumps
        info_after_replug_and_reset = node.source.info
    dev.assert_clean_exit()
    valid, corrupt, events = dev.records()
    assert len(corrupt) == 1 and [e for e, _ in events if e in ("N", "unplug", "plug", "reset")] == [
        "N", "unplug", "plug", "reset"]
    # diagnostics count every fault
    assert level == DiagnosticStatus.WARN and "corrupt or lost" in message
    assert int(values["crc_errors"]) >= 2 and values["outages"] == "1" and values["connected"] == "True"
    assert int(values["implausible_stamp"]) > 0 and values["reanchored"] == "1"
    # a reset restarts the sequence at 0: modulo 2**16 that is a jump back (a sequence jump, nothing lost) or,
    # after 32768 frames or more, ahead (counted as lost frames: the parser cannot tell)
    last_seq_before_reset = valid[dict((e, n) for e, n in events)["reset"] - 1][0]
    ahead = (0 - last_seq_before_reset) % 2**16
    if ahead < 2**15:
        assert (lost_at_reset, jumps_at_reset) == (ahead - 1, 0)
    else:
        assert (lost_at_reset, jumps_at_reset) == (0, 1)
    # the device said who it is again after the replug and after the reset (asked for at each connection)
    assert info_after_replug_and_reset is not None and info_after_replug_and_reset.sensor_serial == "VIRTUAL-0001"
    assert [e for e, _ in events].count("info") >= 3
    # never a corrupt sample: the published samples are the device's valid frames, in order
    idx = match_sent(published_counts(raw), valid)
    # and frames go missing only where the cable was out or while the reset re-anchored the stamps
    breaks = {n for e, n in events if e in ("unplug", "reset")}
    for a, b in zip(idx, idx[1:]):
        if b != a + 1:
            assert any(a < n <= b for n in breaks), (a, b, events)
    stamps = np.array([stamp_to_ns(m.header.stamp) for m in raw], dtype=np.int64)
    assert np.all(np.diff(stamps) >= 0)  # acquisition order, also across the replug and the reset
    acq = np.array([valid[i][3] for i in idx], dtype=np.int64)
    after_reset = idx >= dict((e, n) for e, n in events)["reset"]
    err = (stamps - acq)[after_reset][50:] / 1e3
    assert err.min() > -300 and np.median(err) < 3000, (err.min(), np.median(err))  # re-anchored on host time


def test_live_too_slow_device_or_link_warns(build, tmp_path):
    def rate(lis):
        return received_rate(lis)

    with live(tmp_path, build, ["--rate", 1000], expected_rate_hz=1000.0, rate_window_s=1.0) as (h, node, lis, dev):
        assert h.spin_until(lambda: rate(lis) is not None and rate(lis) > 950, 30.0)
        assert last_diag(lis)[0] == DiagnosticStatus.OK
        # the ADC set to half the rate: nothing lost, but the rate budget is missed
        dev.command(h, "rate 500")
        assert h.spin_until(lambda: "frames/s, expected 1000" in last_diag(lis)[1], 30.0)
        assert last_diag(lis)[0] == DiagnosticStatus.WARN  # two consecutive windows below 950/s
        # and the device itself says so: its info follows the rate change
        assert "device converts at 500 Hz, expected_rate_hz is 1000" in last_diag(lis)[1]
        assert last_diag(lis)[2]["device_rate_hz"] == "500"
        assert 400 < rate(lis) < 600 and node.parser.lost_frames == 0
        dev.command(h, "rate 1000")
        assert h.spin_until(lambda: last_diag(lis)[0] == DiagnosticStatus.OK, 30.0)
        # a 115200-baud link: 11520 bytes/s carry 822 frames/s; the device's ring overflows
        dev.command(h, "baud 115200")
        assert h.spin_until(lambda: "frames/s, expected 1000" in last_diag(lis)[1], 30.0)
        assert last_diag(lis)[0] == DiagnosticStatus.WARN and 600 < rate(lis) < 900, last_diag(lis)
        assert h.spin_until(lambda: node.parser.lost_frames > 0, 20.0)  # once the device's ring has filled
        assert dev.status(h)["overflows"] > 0  # the device's ring refused what the link could not carry
        raw = list(lis.raw)
    dev.assert_clean_exit()
    valid, corrupt, _ = dev.records()
    match_sent(published_counts(raw), valid)  # still nothing but valid frames
    assert not corrupt


def test_live_device_identity_status_and_temperature(build, tmp_path):
    args = ["--serial", "PF-SN-77", "--board", "bench-1", "--temperature", 31.5, "--status-period", 0.3,
            "--temp-period", 0.2]
    with live(tmp_path, build, args, expected_rate_hz=1000.0) as (h, node, lis, dev):
        assert h.spin_until(lambda: "sensor_serial" in last_diag(lis)[2] and "device_reset_reason" in last_diag(lis)[2],
                            20.0)
        level, message, values = last_diag(lis)
        assert level == DiagnosticStatus.OK, message
        assert values["sensor_serial"] == "PF-SN-77" and values["device_board"] == "bench-1"
        assert values["device_firmware"] == "1.1.0" and values["device_protocol"] == "1"
        assert values["device_adc"] == "virtual" and values["device_rate_hz"] == "1000"
        assert values["device_gain"] == "1" and float(values["device_volts_per_count"]) == SCALE
        assert values["device_reset_reason"] == "power_on" and values["device_watchdog_resets"] == "0"
        assert dev.status(h)["requests"] >= 2  # the driver asked for info and status when it opened the port
        # the ADC's temperature on `temperature`
        assert h.spin_until(lambda: len(lis.temps) >= 2, 20.0)
        assert {m.temperature for m in lis.temps} == {31.5} and lis.temps[-1].header.frame_id == node._frame
        dev.command(h, "temp -12.25")
        assert h.spin_until(lambda: lis.temps[-1].temperature == -12.25, 20.0)
        # the firmware hangs and its watchdog resets it: reported, and a warning
        dev.command(h, "watchdog")
        assert h.spin_until(lambda: last_diag(lis)[2].get("device_reset_reason") == "watchdog", 20.0)
        assert h.spin_until(lambda: "restarted by its watchdog" in last_diag(lis)[1], 20.0)
        level, message, values = last_diag(lis)
        assert level == DiagnosticStatus.WARN and values["device_watchdog_resets"] == "1"
        n = len(lis.raw)
        assert h.spin_until(lambda: len(lis.raw) >= n + 300, 20.0)  # samples flow again after the restart
        crc_errors, raw = node.parser.crc_errors, list(lis.raw)
    dev.assert_clean_exit()
    valid, corrupt, events = dev.records()
    names = [e for e, _ in events]
    assert names.count("temperature") >= 5 and names.count("status") >= 5 and "watchdog" in names
    # messages cost no sample and no CRC error: the published samples are the device's frames
    assert crc_errors == 0 and not corrupt
    match_sent(published_counts(raw), valid)


def test_live_device_disagreeing_with_the_driver_parameters_warns(build, tmp_path):
    # the device converts with 5 V / (128 2^23) per count; the driver is told 2^-20
    with live(tmp_path, build, ["--vref-uv", 5_000_000, "--gain", 128], expected_rate_hz=1000.0) as (h, node, lis, dev):
        assert h.spin_until(lambda: "device reports volts_per_count" in last_diag(lis)[1], 20.0)
        level, message, values = last_diag(lis)
        assert level == DiagnosticStatus.WARN and f"parameter is {SCALE!r}" in message
        assert float(values["device_volts_per_count"]) == 5 / 2**30
    dev.assert_clean_exit()


def test_live_sensor_serial_reaches_the_compensation_node(build, tmp_path):
    """The device's sensor serial, through the driver's latched sensor_serial, against the model's provenance:
    another sensor gets zero force and ERROR while require_matching_sensor, a WARN without."""
    from polyforce_ros.model_file import SensorModel, save_model
    from polyforce_ros.nodes.compensation_node import CompensationNode
    from polyforce_ros.physics.chain import SensorChain
    from polyforce_ros.physics.viscoelastic import PAPER_BURGERS

    model = tmp_path / "other_sensor.yaml"
    save_model(model, SensorModel(SensorChain.from_model(PAPER_BURGERS), {"sensor_serial": "PF-OTHER"}))
    # at rest (0 V) for 1 s, then 200000 counts (0.19 V, about 0.9 N on the paper model) for 1 s, and so on
    args = ["--serial", "PF-LIVE-1", "--signal", "step", "--offset", 0, "--amplitude", 200_000, "--freq", 1.0]
    with live(tmp_path, build, args, volts_offset=0.0) as (h, node, lis, dev):
        comp = h.add(CompensationNode(context=h.context, parameter_overrides=[
            Parameter("model_file", value=str(model)), Parameter("require_matching_sensor", value=True),
            Parameter("auto_tare", value=False), Parameter("stale_timeout_s", value=5.0)]))
        forces, volts = [], []
        publish = comp.pub.publish

        def record(msg):
            forces.append(msg.wrench.force.z)
            publish(msg)

        comp.pub.publish = record
        assert h.spin_until(lambda: comp.live_serial == "PF-LIVE-1", 20.0)  # latched: the driver sent it earlier
        n_raw = len(lis.raw)
        assert h.spin_until(lambda: len(forces) >= 2500, 60.0)
        volts = [m.position[0] for m in lis.raw[n_raw:]]
        refused = list(forces)
        status = comp._publish_diagnostics()
        assert comp.set_parameters([Parameter("require_matching_sensor", value=False)])[0].successful
        n = len(forces)
        assert h.spin_until(lambda: any(f > 0.3 for f in forces[n:]), 30.0), "no force once allowed"
        warned = comp._publish_diagnostics()
        comp.pub.publish = publish
    dev.assert_clean_exit()
    assert max(volts) > 0.15 and set(refused) == {0.0}  # the sensor was loaded while its force was refused
    assert status.level == DiagnosticStatus.ERROR and "'PF-LIVE-1' is not the one the model was calibrated on " \
        "('PF-OTHER'): zero force" in status.message
    assert warned.level == DiagnosticStatus.WARN and "not the one the model was calibrated on" in warned.message


class _Waiter:
    """Stands in for the ROS harness where VirtualDevice waits for its output without ROS."""

    @staticmethod
    def spin_until(predicate, timeout=5.0):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if predicate():
                return True
            time.sleep(0.01)
        return predicate()


def check_device(*args):
    return subprocess.run([sys.executable, "-m", "polyforce_ros.cli", "check-device", *map(str, args)], cwd=REPO,
                          capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("device_args,failed", [
    ([], []),
    # a bridge far off zero with 50 Hz pickup, flashed without a serial
    (["--offset", 3_000_000, "--amplitude", 20_000, "--freq", 50, "--serial", "unset"],
     ["sensor serial", "zero offset", "noise"]),
    (["--offset", 2**23 - 1, "--amplitude", 0], ["not railed", "zero offset"]),  # an input at full scale
])
def test_check_device_against_the_virtual_device(build, tmp_path, device_args, failed):
    dev = VirtualDevice(build / "virtual_device_san", tmp_path, "--amplitude", 0, "--offset", 41_000, *device_args)
    try:
        dev.expect(_Waiter, "pty ")
        proc = check_device("--port", dev.link, "--samples", 500, "--volts-per-count", 5 / 2**30,
                            "--expected-rate", 1000)
    finally:
        dev.stop()
    lines = proc.stdout.splitlines()
    verdicts = {line[6:].split("  ")[0].strip(): line[:4] for line in lines if line[:4] in ("PASS", "FAIL")
                and line[4:6] == "  "}
    assert set(verdicts) == {"info", "sensor serial", "status", "link", "volts_per_count", "expected rate", "rate",
                             "counts in range", "not railed", "zero offset", "noise"}, proc.stdout + proc.stderr
    assert sorted(name for name, v in verdicts.items() if v == "FAIL") == sorted(failed), proc.stdout
    assert proc.returncode == (1 if failed else 0), proc.stdout + proc.stderr
    assert lines[-1].startswith("FAIL: " if failed else "PASS: all 11 checks")


def test_check_device_refuses_bad_input(tmp_path):
    proc = check_device("--port", tmp_path / "no-such-tty")
    assert proc.returncode == 2 and "cannot open" in proc.stderr and not proc.stdout
    proc = check_device("--port", tmp_path / "no-such-tty", "--samples", 1)
    assert proc.returncode == 2 and "--samples must be at least 2" in proc.stderr
