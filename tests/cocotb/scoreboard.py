"""The bench's reference: every port of tt_frontend after every clock, from the tooltouch
Python package.

The model runs once over the whole stimulus (``FrontEnd.run``, the loop in Rust), so the
simulation loop only looks values up. The expected values are the unsigned register bits
the Verilog ports carry: positions are ``scale_bits`` two's complement; ``irq`` is
``register_now``; ``mcu_rdata`` is the word of the MCU register map at the address driven
for that clock (the model's map, from ``FrontEnd.run(pins, mcu_addr=…)``), read
combinationally from the registers just clocked (tt_frontend's read has no latency; the
chip top tt_fpga registers it, one clock later).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence

import numpy as np

import tooltouch


@dataclass
class Mismatch:
    """The first port that differs from the model."""

    cycle: int
    """Clock index from the end of reset (rising edge 0 is the first without reset)."""
    signal: str
    expected: int
    actual: str
    """The port's value as read (an integer, or its bits when some are X or Z)."""

    def __str__(self) -> str:
        return (
            f"MISMATCH at cycle {self.cycle}: {self.signal} expected {self.expected} "
            f"(0x{self.expected:x}), got {self.actual}"
        )


class Reference:
    """Expected port values, clock by clock, in chunks: ``expect`` continues the model
    from where the previous chunk left it, so a long run needs memory for one chunk."""

    def __init__(self, settings: tooltouch.Settings, mcu_diagnostics: bool) -> None:
        self.settings = settings
        self.diagnostics = mcu_diagnostics
        self.widths = dict(settings.output_widths)
        self.model = tooltouch.FrontEnd(settings)
        self.signals: Sequence[str] = list(tooltouch.OUTPUT_NAMES) + ["irq", "mcu_rdata"]

    def expect(self, pins: np.ndarray, mcu_addr: np.ndarray) -> Dict[str, List[int]]:
        """``{port: [value after each clock]}`` for the next ``len(pins)`` clocks."""
        columns = self.model.run(
            pins, mcu_addr=mcu_addr, mcu_diagnostics=self.diagnostics
        )
        expected: Dict[str, List[int]] = {}
        for name in tooltouch.OUTPUT_NAMES:
            values = columns[name].astype(np.int64) & ((1 << self.widths[name]) - 1)
            expected[name] = values.tolist()
        expected["irq"] = expected["register_now"]
        expected["mcu_rdata"] = columns["mcu_rdata"].astype(np.int64).tolist()
        return expected


def first_mismatch(
    cycle: int, expected: Dict[str, int], bits: Dict[str, str]
) -> Optional[Mismatch]:
    """The first port (in ``expected``'s order) whose ``bits`` as read (a binary string,
    X and Z as letters) differ from its expected value."""
    for name, want in expected.items():
        got = bits[name]
        if not set(got) <= {"0", "1"}:
            return Mismatch(cycle, name, want, f"{got} (not 0/1)")
        if int(got, 2) != want:
            value = int(got, 2)
            return Mismatch(cycle, name, want, f"{value} (0x{value:x})")
    return None
