"""cocotb test module: tt_frontend against the tooltouch Python package, clock by clock.

Run by test_tt_frontend.py through cocotb's runner, which passes the run in environment
variables: ``TT_BENCH_SETTINGS`` (the settings TOML the design was generated from),
``TT_BENCH_SEED``, ``TT_BENCH_CYCLES``, ``TT_BENCH_MCU_DIAGNOSTICS`` (``1`` when generated
with ``--mcu-diagnostics``) and ``TT_BENCH_REPORT`` (a JSON file this writes: the cycles
run, the wall and CPU time and the first mismatch, if any). With ``TT_BENCH_STIMULUS`` (a
pin stimulus file as ``tooltouch vectors --stimulus`` reads it, e.g. the golden VCD of
``tooltouch vectors --stress``) the pins are that file's, every clock of it, in place of
the random ones; the MCU addresses stay random (seeded).

Clocking: the bench drives ``clk`` itself, two timer waits per clock (a ``Clock``
coroutine plus an edge trigger costs more), and writes immediately
(``cocotb_compat.immediate_writer``: a ``.value =`` write costs a ReadWrite trigger per
time step, half of the bench's CPU time under cocotb 1.8). The pins and ``mcu_addr`` of
clock ``k`` are applied at the falling edge before rising edge ``k``, as tt_testbench.v
does (applying them at the rising edge itself races the flip-flops); nothing in the
design reacts to them before that rising edge, so the immediate writes are race-free.
Every output, ``irq`` and ``mcu_rdata`` are read at the end of the high phase, before the
next falling edge. Reset (``rst``, active high, synchronous) is held for three clocks
with every pin low.
"""

from __future__ import annotations

import json
import os
import random
import time
from pathlib import Path

import cocotb
from cocotb.triggers import Timer

import tooltouch
from cocotb_compat import binary_reader, immediate_writer
from scoreboard import Reference, first_mismatch
from stimuli import draw_stimulus, stimulus_from_file

RESET_CLOCKS = 3
# Clocks of model output computed at a time (bounds the memory of long runs).
CHUNK = 65536


@cocotb.test()
async def tt_frontend_matches_the_model(dut):
    """Random stimulus; every port compared with the model after every clock."""
    settings = tooltouch.Settings.from_toml(os.environ["TT_BENCH_SETTINGS"])
    seed = int(os.environ["TT_BENCH_SEED"])
    cycles = int(os.environ["TT_BENCH_CYCLES"])
    diagnostics = os.environ.get("TT_BENCH_MCU_DIAGNOSTICS") == "1"
    report_path = Path(os.environ["TT_BENCH_REPORT"])

    stimulus_file = os.environ.get("TT_BENCH_STIMULUS")
    if stimulus_file:
        stimulus = stimulus_from_file(random.Random(seed), Path(stimulus_file), settings)
        cycles = len(stimulus.pins)
    else:
        stimulus = draw_stimulus(random.Random(seed), settings, cycles)
    reference = Reference(settings, diagnostics)

    period_ns = 1_000_000_000 // settings.clock_hz
    high = Timer(period_ns // 2, "ns")
    low = Timer(period_ns - period_ns // 2, "ns")
    pin_ports = [getattr(dut, f"pin_{name}") for name in tooltouch.PIN_NAMES]
    readers = [binary_reader(getattr(dut, name)) for name in reference.signals]

    dut.clk.value = 0
    dut.rst.value = 1
    dut.mcu_addr.value = 0
    for port in pin_ports:
        port.value = 0
    for _ in range(RESET_CLOCKS):
        await low
        dut.clk.value = 1
        await high
        dut.clk.value = 0
    dut.rst.value = 0
    write_clk, write_mcu_addr = immediate_writer(dut.clk), immediate_writer(dut.mcu_addr)
    write_pins = [immediate_writer(port) for port in pin_ports]

    mismatch = None
    applied = 0
    run = 0
    started = time.perf_counter()
    cpu_started = time.process_time()
    for first in range(0, cycles, CHUNK):
        pins_chunk = stimulus.pins[first : first + CHUNK]
        addr_chunk = stimulus.mcu_addr[first : first + CHUNK]
        expected = reference.expect(pins_chunk, addr_chunk)
        columns = [expected[name] for name in reference.signals]
        for i, (pins, address) in enumerate(zip(pins_chunk.tolist(), addr_chunk.tolist())):
            # The falling edge before rising edge k: the inputs of clock k.
            write_clk(0)
            changed = pins ^ applied
            if changed:
                for bit, write_pin in enumerate(write_pins):
                    if changed >> bit & 1:
                        write_pin(pins >> bit & 1)
                applied = pins
            write_mcu_addr(address)
            await low
            write_clk(1)
            await high
            # End of the high phase: the registers of rising edge k.
            run += 1
            for reader, column in zip(readers, columns):
                bits = reader()
                try:
                    same = int(bits, 2) == column[i]
                except ValueError:  # X or Z
                    same = False
                if not same:
                    mismatch = first_mismatch(
                        first + i,
                        {name: expected[name][i] for name in reference.signals},
                        {
                            name: read()
                            for name, read in zip(reference.signals, readers)
                        },
                    )
                    break
            if mismatch is not None:
                break
        if mismatch is not None:
            break
    seconds = time.perf_counter() - started
    cpu_seconds = time.process_time() - cpu_started

    report = {
        "cycles": run,
        "seconds": seconds,
        "cycles_per_s": run / seconds if seconds > 0 else None,
        # The simulator and Python share this process: its CPU time is the bench's cost
        # without the other processes of a busy machine.
        "cpu_seconds": cpu_seconds,
        "cycles_per_cpu_s": run / cpu_seconds if cpu_seconds > 0 else None,
        "mismatch": None
        if mismatch is None
        else {
            "cycle": mismatch.cycle,
            "signal": mismatch.signal,
            "expected": mismatch.expected,
            "actual": mismatch.actual,
            "message": str(mismatch),
        },
    }
    report_path.write_text(json.dumps(report, indent=1))
    if mismatch is not None:
        dut._log.error(str(mismatch))
        raise AssertionError(str(mismatch))
    dut._log.info(
        "%d clocks match the model (%.0f clocks/s)", run, report["cycles_per_s"] or 0
    )
