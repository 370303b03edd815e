"""Random configurations and random per-clock stimuli for the cocotb bench of tt_frontend.

Everything is drawn from one ``random.Random`` so a seed reproduces a run. The
configurations favour what makes a short run interesting (few FES pulses per window,
small thresholds, short glitch filters, narrow registers that wrap and saturate) and
sometimes take a value from the whole valid range. The stimulus is a run of segments:
each lasts long enough to pass the glitch filter (``glitch_cycles + 1`` clocks) or, one
time in eight, is a glitch shorter than that; at each segment boundary several pins may
change together, so index and FES edges (and arm, contact, scale edges) reach the kernel
in the same clock. The MCU address is a new random word address (0..15, unmapped ones
included) every clock.
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from pathlib import Path
from typing import List

import numpy as np

import tooltouch

# Clocks whose period, 1e9 / clock_hz ns, is whole (the testbench's time unit is 1 ns),
# fast enough that the default [lathe] of the settings file is valid for every drawn
# configuration (at 1 MHz a long glitch filter makes its retract speed too fast).
CLOCKS_HZ = [100_000_000, 50_000_000, 40_000_000, 25_000_000, 10_000_000]

# Scale lines for positive motion, as pin bits (A leads B): 00 -> A -> AB -> B.
SCALE_PHASES = [
    0,
    tooltouch.PIN_SCALE_A,
    tooltouch.PIN_SCALE_A | tooltouch.PIN_SCALE_B,
    tooltouch.PIN_SCALE_B,
]

# Number of MCU word addresses (mcu_addr is 4 bits; 12..15 are unmapped and read 0).
MCU_ADDRESSES = 16


@dataclass
class Configuration:
    """A drawn configuration: the settings file's text and the generator's options."""

    toml: str
    """Settings TOML (``[measure]`` and ``[lathe] clock_hz``), as ``tooltouch hdl`` and
    ``tooltouch.Settings.from_toml`` read it."""
    mcu_diagnostics: bool
    """Generate with ``--mcu-diagnostics`` (REVOLUTIONS and PULSES readable)."""

    def write(self, path: Path) -> tooltouch.Settings:
        """Writes the settings file and returns it as the package reads it."""
        path.write_text(self.toml)
        return tooltouch.Settings.from_toml(path)


def draw_configuration(rng: random.Random) -> Configuration:
    """A random valid configuration (see the module documentation)."""
    ppr = rng.choice([16, 16, 24, 32, 48, 64, rng.randint(16, 16384)])
    window_revs = rng.choice([1, 1, 2, 3, rng.randint(1, 16)])
    window = ppr * window_revs
    i_def = rng.choice([rng.randint(0, min(window - 1, 12)), rng.randint(0, window - 1)])
    charge_bits = rng.choice([4, 5, 6, 8, 8, 10, 12, rng.randint(4, 24)])
    full = (1 << charge_bits) - 1
    if rng.random() < 0.6:
        small = max(1, full // 16)
        law = (
            f'{{ law = "linear", charge_step = {rng.randint(1, small)}, '
            f"discharge_step = {rng.randint(1, small)} }}"
        )
    else:
        shift = min(charge_bits, 6)
        law = (
            f'{{ law = "exponential", charge_shift = {rng.randint(0, shift)}, '
            f"discharge_shift = {rng.randint(0, shift)} }}"
        )
    fire = rng.choice([rng.randint(1, full), rng.randint(1, max(1, full // 4))])
    rearm = rng.randint(0, fire - 1)
    toml = "\n".join(
        [
            "[measure]",
            f"pulses_per_rev = {ppr}",
            f"i_def = {i_def}",
            f"window_revs = {window_revs}",
            f'contact_rule = "{rng.choice(["sampled", "sticky"])}"',
            f"charge_bits = {charge_bits}",
            f"charge_law = {law}",
            f"fire_threshold = {fire}",
            f"rearm_threshold = {rearm}",
            f"glitch_cycles = {rng.choice([0, 1, 1, 2, 2, 3, 4, rng.randint(0, 12)])}",
            f"scale_bits = {rng.choice([8, 9, 12, 16, 24, 32, rng.randint(8, 32)])}",
            f'method = "{rng.choice(["counter", "density"])}"',
            "",
            "[lathe]",
            f"clock_hz = {rng.choice(CLOCKS_HZ)}",
            "",
        ]
    )
    return Configuration(toml=toml, mcu_diagnostics=rng.random() < 0.5)


@dataclass
class Stimulus:
    """Per-clock inputs: ``pins[k]`` (a pin byte, ``tooltouch.PIN_*`` bits) and
    ``mcu_addr[k]`` are applied before rising edge ``k``."""

    pins: np.ndarray
    mcu_addr: np.ndarray


def draw_stimulus(rng: random.Random, settings: tooltouch.Settings, cycles: int) -> Stimulus:
    """A random stimulus of exactly ``cycles`` clocks for ``settings``."""
    passing = settings.glitch_cycles + 1
    levels: List[int] = []
    pins = 0
    phase = 0
    levels.extend([0] * rng.randint(1, 8))
    pins |= tooltouch.PIN_ARM  # arm early, often with other edges
    while len(levels) < cycles:
        if passing > 1 and rng.random() < 0.12:
            length = rng.randint(1, passing - 1)  # a glitch the filter must drop
        elif rng.random() < 0.02:
            length = rng.randint(passing, 40 * passing + 40)  # a pause
        else:
            length = passing + rng.randint(0, 2 * passing + 3)
        levels.extend([pins] * length)
        if rng.random() < 0.6:
            pins ^= tooltouch.PIN_FES
        if rng.random() < 0.2:
            pins ^= tooltouch.PIN_CONTACT
        if rng.random() < 0.06:
            pins ^= tooltouch.PIN_INDEX
        if rng.random() < 0.012:
            pins ^= tooltouch.PIN_ARM  # arm or retract
        if rng.random() < 0.3:
            if rng.random() < 0.03:
                phase = (phase + 2) % 4  # both lines at once: a scale error
            elif rng.random() < 0.6:
                phase = (phase + 1) % 4
            else:
                phase = (phase + 3) % 4
            scale = tooltouch.PIN_SCALE_A | tooltouch.PIN_SCALE_B
            pins = (pins & ~scale) | SCALE_PHASES[phase]
    pin_array = np.array(levels[:cycles], dtype=np.uint8)
    addresses = np.array(
        [rng.randrange(MCU_ADDRESSES) for _ in range(cycles)], dtype=np.uint8
    )
    return Stimulus(pins=pin_array, mcu_addr=addresses)


def stimulus_from_file(rng: random.Random, path: Path, settings: tooltouch.Settings) -> Stimulus:
    """The pins of a stimulus file (``tooltouch.read_stimulus``: a VCD or ``stim.hex``) at
    ``settings``' clock, every clock of it, with a random MCU address per clock."""
    pins = tooltouch.read_stimulus(path, settings.clock_hz).per_clock()
    addresses = np.array(
        [rng.randrange(MCU_ADDRESSES) for _ in range(len(pins))], dtype=np.uint8
    )
    return Stimulus(pins=np.asarray(pins, dtype=np.uint8), mcu_addr=addresses)
