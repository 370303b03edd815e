"""Type stubs of the native module ``tooltouch._tooltouch`` (built from python/src/).

Units and formats: times are ticks of a stream's ``tick_hz`` (FPGA clocks for cycle-level
streams); positions are scale counts, ``scale_bits`` two's complement (sign-extended to
int); the charge is UQ0.``charge_bits`` of full scale (LSBs); flags are bool.
"""

from os import PathLike
from typing import Any, Dict, Iterator, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

StrPath = Union[str, PathLike[str]]

PIN_ARM: int
"""Bit 0 of a pin byte: the CNC's arm line (measurement-cycle start; low = abort / end)."""
PIN_CONTACT: int
"""Bit 1: tool-workpiece contact."""
PIN_INDEX: int
"""Bit 2: spindle index pulse."""
PIN_FES: int
"""Bit 3: spindle FES encoder pulse."""
PIN_SCALE_A: int
"""Bit 4: linear scale line A."""
PIN_SCALE_B: int
"""Bit 5: linear scale line B."""
PIN_NAMES: List[str]
"""Pin names by bit position, as the VCD signals (the Verilog ports are ``pin_<name>``)."""
OUTPUT_NAMES: List[str]
"""The 15 output names, in the order of the VCD, the Verilog ports and ``Outputs.as_dict``."""

class Settings:
    """Validated settings: the CLI's settings file, ``[measure]`` (the model) and
    ``[lathe]`` (the simulated lathe), validated by the CLI's own code.

    Raises ``ValueError`` naming the field, its value and the allowed range (e.g.
    ``[measure] configuration field `i_def` = 5000 is out of range: allowed 0..=1023``),
    or an unknown field; ``OSError`` for a file that cannot be read.
    """

    def __init__(self, table: Optional[Dict[str, Any]] = None) -> None:
        """Settings from a dict shaped like the TOML file; ``None`` gives the defaults."""
    @staticmethod
    def from_toml(path: StrPath) -> Settings:
        """Reads a settings file, as ``tooltouch measure --config PATH`` does."""
    @staticmethod
    def from_toml_str(text: str) -> Settings:
        """Parses settings from TOML text."""
    def to_toml(self) -> str:
        """Every field as TOML text (a file the CLI reads back)."""
    @property
    def config_hash(self) -> int:
        """64-bit FNV-1a hash of the model configuration (stamped in .ttv, VCD, Verilog)."""
    @property
    def clock_hz(self) -> int:
        """FPGA clock, Hz."""
    @property
    def glitch_cycles(self) -> int:
        """Glitch filter: a level passes once seen on ``glitch_cycles + 1`` clocks."""
    @property
    def latency_cycles(self) -> int:
        """Clocks from a pin change to the outputs reacting to it: ``3 + glitch_cycles``."""
    @property
    def output_widths(self) -> List[Tuple[str, int]]:
        """``(name, register width in bits)`` of every output, in ``OUTPUT_NAMES`` order."""

class Outputs:
    """Every output after one clock or event (immutable, comparable with ``==``)."""

    @property
    def armed(self) -> bool:
        """A measurement cycle is running (arm is high)."""
    @property
    def contact(self) -> bool:
        """Filtered contact level."""
    @property
    def register_now(self) -> bool:
        """"Position reached, register now" to the CNC; held until the next arm."""
    @property
    def decision_position(self) -> int:
        """Scale position latched at the decision, counts (0 until decided)."""
    @property
    def first_contact(self) -> bool:
        """A contact edge has been seen since arm."""
    @property
    def first_contact_position(self) -> int:
        """Scale position latched at the first contact edge, counts (0 until then)."""
    @property
    def position(self) -> int:
        """Live scale position, counts, ``scale_bits`` two's complement."""
    @property
    def scale_errors(self) -> int:
        """Illegal scale transitions since power-on, saturating at 255."""
    @property
    def count(self) -> int:
        """Contact pulses in the current window (``count_bits`` wide)."""
    @property
    def last_window_count(self) -> int:
        """Contact pulses in the previous window."""
    @property
    def charge(self) -> int:
        """Capacitor charge, LSBs (UQ0.``charge_bits`` of full scale)."""
    @property
    def density_armed(self) -> bool:
        """The density detector is armed (hysteresis state)."""
    @property
    def density_fired(self) -> bool:
        """The density detector has fired since arm."""
    @property
    def revolutions(self) -> int:
        """Index pulses since arm, saturating at 65535."""
    @property
    def pulses(self) -> int:
        """FES pulses since arm, wrapping at 2**32."""
    def as_dict(self) -> Dict[str, int]:
        """``{name: value}`` in ``OUTPUT_NAMES`` order; flags 0/1, positions signed."""
    def register_bits(self, settings: Settings) -> List[int]:
        """Unsigned register bits of every output (positions truncated to ``scale_bits``),
        as the Verilog ports carry them."""

class Event:
    """One measurement input event (event level, firmware semantics)."""

    @staticmethod
    def arm(level: bool) -> Event: ...
    @staticmethod
    def contact(level: bool) -> Event: ...
    @staticmethod
    def index() -> Event:
        """Rising edge of the index pulse."""
    @staticmethod
    def fes() -> Event:
        """Rising edge of an FES pulse."""
    @staticmethod
    def scale(a: bool, b: bool) -> Event:
        """Scale lines changed to these levels."""
    @staticmethod
    def preset_pulses(pulses: int) -> Event:
        """Test event: sets the FES pulse count since arm (u32)."""
    @property
    def kind(self) -> str:
        """``arm``, ``contact``, ``index``, ``fes``, ``scale`` or ``preset_pulses``."""
    @property
    def level(self) -> Optional[bool]: ...
    @property
    def lines(self) -> Optional[Tuple[bool, bool]]: ...
    @property
    def pulses(self) -> Optional[int]: ...

class FrontEnd:
    """The cycle-level front end (RTL semantics) from reset: per pin a 2-flip-flop
    synchronizer, a glitch filter and edge detection, then the measurement kernel. A pin
    level applied at clock ``k`` shows in the outputs after clock ``k + latency_cycles``.

    Pin bytes: bit 0 arm, 1 contact, 2 index, 3 fes, 4 scale_a, 5 scale_b (``PIN_*``);
    other bits are a ``ValueError``.
    """

    def __init__(self, settings: Settings) -> None: ...
    def step(self, pins: int) -> Outputs:
        """One rising clock edge with ``pins``; the outputs registered by it."""
    def run(self, pins: npt.NDArray[np.uint8]) -> Dict[str, npt.NDArray[Any]]:
        """One clock per element of ``pins``; ``{name: array}`` with element ``k`` the
        output after clock ``k``. dtypes: flags bool, positions int32, scale_errors
        uint8, revolutions uint16, the others uint32. The loop runs in Rust."""
    def advance(self, pins: int, cycles: int) -> int:
        """``cycles`` clocks with ``pins`` held, exactly skipping those after the front
        end settled; returns the clocks simulated one by one."""
    def is_settled(self, pins: int) -> bool:
        """Whether clocking with ``pins`` held would change no register."""
    @property
    def outputs(self) -> Outputs:
        """The outputs after the last clock."""
    @property
    def filtered_pins(self) -> int:
        """Glitch-filtered pin levels, a pin byte."""

class Measurement:
    """The event-level measurement kernel (firmware semantics) from reset."""

    def __init__(self, settings: Settings) -> None: ...
    def apply(self, event: Event) -> Outputs:
        """Applies one event; the outputs after it."""
    @property
    def outputs(self) -> Outputs: ...

class Record:
    """One record of a ``.ttv`` stream."""

    @property
    def kind(self) -> int:
        """Kind byte."""
    @property
    def name(self) -> str:
        """Kind name: ``measure_config``, ``arm`` ... ``measure_outputs``, a force or
        firmware kind, or ``unknown``."""
    @property
    def time(self) -> int:
        """Time, ticks of the header's ``tick_hz``."""
    @property
    def payload(self) -> bytes: ...
    @property
    def value(self) -> Union[Event, Outputs, Settings, None]:
        """The decoded payload (a configuration record gives ``Settings`` with
        ``[lathe]`` at its defaults); ``None`` for kinds not decoded here."""

class TtvReader:
    """Reads a ``.ttv`` stream record by record (constant memory); stops at its END
    record. A malformed stream is a ``ValueError`` naming the file and byte offset."""

    def __init__(self, path: StrPath) -> None: ...
    @property
    def stream(self) -> str:
        """``events`` or ``outputs``."""
    @property
    def tick_hz(self) -> int:
        """Ticks per second of the record times, Hz."""
    @property
    def measure_hash(self) -> int: ...
    @property
    def force_hash(self) -> int: ...
    def __iter__(self) -> Iterator[Record]: ...
    def __next__(self) -> Record: ...

class TtvWriter:
    """Writes a ``.ttv`` stream: header now, records in time order, END on ``close()``."""

    def __init__(
        self,
        path: StrPath,
        stream: str,
        tick_hz: int,
        settings: Optional[Settings] = None,
        measure_hash: Optional[int] = None,
        force_hash: int = 0,
    ) -> None: ...
    def write_record(self, kind: int, time: int, payload: bytes) -> None: ...
    def write_config(self, time: int, settings: Settings) -> None: ...
    def write_event(self, time: int, event: Event) -> None: ...
    def write_outputs(self, time: int, outputs: Outputs) -> None: ...
    def close(self) -> None: ...
    def __enter__(self) -> TtvWriter: ...
    def __exit__(self, *exc: object) -> bool: ...
