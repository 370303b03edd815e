"""Type stubs of the native module ``tooltouch._tooltouch`` (built from python/src/).

Units and formats: times are ticks of a stream's ``tick_hz`` (FPGA clocks for cycle-level
streams); positions are scale counts, ``scale_bits`` two's complement (sign-extended to
int); the charge is UQ0.``charge_bits`` of full scale (LSBs); flags are bool.
"""

from os import PathLike
from typing import Any, Dict, Iterator, List, Optional, Sequence, Tuple, Union

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
"""The 17 output names, in the order of the VCD, the Verilog ports and ``Outputs.as_dict``."""
FAULT_NAMES: List[str]
"""The fault conditions' names by bit position of ``Outputs.faults`` (``contact_at_arm`` ...
``unconfirmed``), as in docs/measure.md and the firmware's decision line."""
FAULT_CONTACT_AT_ARM: int
"""Fault bit 0 (1): the contact was closed when the arm rose."""
FAULT_PULSES_LOST: int
"""Fault bit 1 (2): a revolution of fewer than ``pulses_per_rev - pulse_tolerance`` FES pulses."""
FAULT_INDEX_MISSING: int
"""Fault bit 2 (4): more than ``pulses_per_rev + pulse_tolerance`` FES pulses without an index."""
FAULT_SCALE_ERROR: int
"""Fault bit 3 (8): an illegal scale transition since arm."""
FAULT_NO_DECISION: int
"""Fault bit 4 (16): no decision within ``probe_revs`` revolutions of the arm."""
FAULT_FES_TIMEOUT: int
"""Fault bit 5 (32): no FES pulse for ``fes_timeout_cycles`` ticks while armed."""
FAULT_UNCONFIRMED: int
"""Fault bit 6 (64): the contact fell back in a confirmation window after the decision."""

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
    @property
    def confirmed(self) -> bool:
        """The decision was confirmed by the contact pattern after it."""
    @property
    def faults(self) -> int:
        """Fault conditions latched since arm, one bit each (``FAULT_*``, 7 bits). Accept a
        measurement only when ``confirmed`` and ``faults == 0``; alarm on any fault."""
    @property
    def fault_names(self) -> List[str]:
        """The latched faults' names in bit order (``FAULT_NAMES``); empty when none."""
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
    def run(
        self,
        pins: npt.NDArray[np.uint8],
        mcu_addr: Optional[npt.NDArray[np.uint8]] = None,
        mcu_diagnostics: bool = False,
    ) -> Dict[str, npt.NDArray[Any]]:
        """One clock per element of ``pins``; ``{name: array}`` with element ``k`` the
        output after clock ``k``. dtypes: flags bool, positions int32, scale_errors
        uint8, revolutions uint16, faults uint8, the others uint32. The loop runs in Rust.

        With ``mcu_addr`` (uint8, as long as ``pins``, addresses 0..=15) the dict also
        holds ``mcu_rdata`` (uint32): the MCU register map's word at ``mcu_addr[k]`` after
        clock ``k``, read from the registers clock ``k`` left, the diagnostic counters 0
        unless ``mcu_diagnostics``."""
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
    def run_segments(
        self, pins: npt.NDArray[np.uint8], cycles: npt.NDArray[np.uint32]
    ) -> Dict[str, npt.NDArray[Any]]:
        """Run-length clocking: ``pins[i]`` held for ``cycles[i]`` clocks (0 allowed),
        settled clocks skipped exactly (cost follows the pin changes). Returns the output
        change list: ``clock`` (uint64, clock index since reset) and every output (dtypes
        as ``run``), a row for the call's first clock and for every later clock after
        which an output changed; each row holds until the next — the outputs half of the
        golden VCD's change list."""
    @property
    def clocks(self) -> int:
        """Clocks since reset (``step``, ``run``, ``advance``, ``run_segments``)."""

class Measurement:
    """The event-level measurement kernel (firmware semantics) from reset."""

    def __init__(self, settings: Settings) -> None: ...
    def apply(self, event: Event, time: int) -> Outputs:
        """Applies one event at ``time`` (ticks of the stream's clock, a ``.ttv`` record's
        ``time``; the FES watchdog sees the time first); the outputs after it.
        ``ValueError`` if ``time`` is before the last event's or observed time."""
    def observe(self, now: int) -> Outputs:
        """The stream's clock reads ``now`` ticks with no event (the FES watchdog latches
        if it expired); the outputs then. ``ValueError`` if ``now`` goes backwards."""
    def outputs_at(self, now: int) -> Outputs:
        """The outputs at ``now`` (not before the last time), the watchdog evaluated then;
        changes nothing."""
    @property
    def outputs(self) -> Outputs:
        """The outputs at the last event's or observed time."""
    @property
    def time(self) -> int:
        """The last event's or observed time, ticks."""

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
    def value(
        self,
    ) -> Union[Event, Outputs, Settings, ForceEvent, ForceOutputs, Tuple[int, int, bytes], Dict[str, Any], None]:
        """The decoded payload: ``Event`` / ``Outputs`` / ``Settings`` (a measurement
        configuration record, ``[lathe]`` at its defaults); ``ForceEvent`` /
        ``ForceOutputs``; ``(total, offset, data)`` for a ``force_config_chunk`` (the
        reader's ``force_settings`` once the last one is read); a dict for a firmware
        record:

        - ``firmware_observe``: ``observe_fes`` (bool);
        - ``firmware_decision``: ``corrected_position``, ``offset`` (i32), the decision
          the firmware reported — those the payload holds (both required on writing);
        - ``firmware_profile``: ``arm``, ``contact``, ``index``, ``fes``, ``scale``, each
          ``(interrupts, systick_ticks)``;
        - ``firmware_force_profile``: ``sample``, ``tick``, ``command``, each
          ``(events, systick_ticks)``;
        - ``firmware_status``: ``events``, ``lost``, ``overflowed``, ``stack_bytes``,
          ``calibration_instructions``, ``calibration_ticks`` (u32), ``measure_hash``,
          ``force_hash`` (u64) — those the payload holds;
        - ``firmware_error``: ``code``, ``wire_error`` (u8), ``offset``, ``detail`` (u64),
          ``field`` (bytes), ``description`` (the CLI's explanation).

        ``None`` for an unknown kind."""

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
    @property
    def force_settings(self) -> Optional[ForceSettings]:
        """The force configuration reassembled from the ``force_config_chunk`` records
        read so far (hash checked against ``force_hash``); None before the last chunk."""
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
    def write_force_event(self, time: int, event: ForceEvent) -> None:
        """One force event (time in ADC samples for ``tooltouch control``'s streams)."""
    def write_force_outputs(self, time: int, outputs: ForceOutputs) -> None: ...
    def write_force_config(self, time: int, settings: ForceSettings) -> None:
        """The configuration as ``force_config_chunk`` records (at most 44 bytes each)."""
    def write_firmware(self, time: int, name: str, fields: Dict[str, Any]) -> None:
        """A firmware record from the dict ``Record.value`` gives for it."""
    def close(self) -> None: ...
    def __enter__(self) -> TtvWriter: ...
    def __exit__(self, *exc: object) -> bool: ...

class ForceSettings:
    """A validated force-path configuration (sampling, estimator, controller, wear
    monitor). ``ValueError`` names a bad field and its allowed range."""

    def __init__(self) -> None:
        """The model's defaults (what a firmware image without a ``[force]`` table runs)."""
    @staticmethod
    def design(
        controller: str = "pi", kp_percent: int = 100, ki_percent: int = 100, force_source: str = "estimated"
    ) -> ForceSettings:
        """A settings file's ``[force]`` table: ``pi``/``adaptive``/``fuzzy``, gains in %
        of the Ziegler–Nichols design (1..=1000), ``estimated``/``measured`` feedback."""
    @staticmethod
    def control_scenario(
        controller: str = "pi", force_source: str = "estimated", process: str = "kienzle"
    ) -> ForceSettings:
        """What ``tooltouch control --controller C --force S --process P`` runs
        (``kienzle``, the default, or ``linear``)."""
    @staticmethod
    def from_toml(path: StrPath) -> ForceSettings:
        """The ``[force]`` table of a settings file (model defaults without one)."""
    @staticmethod
    def from_canonical_bytes(data: bytes) -> ForceSettings: ...
    @property
    def canonical_bytes(self) -> bytes:
        """Canonical little-endian encoding (fixed-point values as raw bits)."""
    @property
    def force_hash(self) -> int:
        """64-bit FNV-1a of ``canonical_bytes``: the ``force_hash`` of .ttv headers."""
    @property
    def sample_hz(self) -> int:
        """ADC sample rate, Hz (the tick rate of force streams)."""
    @property
    def samples_per_period(self) -> int:
        """ADC samples per control period."""
    @property
    def period_s(self) -> float:
        """Control period, s (I32F32 as float)."""
    @property
    def reference_n(self) -> float:
        """Reference force, N."""
    @property
    def manual_override(self) -> int:
        """Feed override while control is off, %."""
    @property
    def lowpass_shift(self) -> int:
        """Low-pass coefficient 2**-k."""
    @property
    def force_source(self) -> str:
        """``estimated`` or ``measured``."""
    @property
    def controller(self) -> str:
        """``pi``, ``adaptive`` or ``fuzzy``."""

class ForceEvent:
    """One input event of the force path."""

    @staticmethod
    def sample(codes: Sequence[int]) -> ForceEvent:
        """One ADC sample: eight 12-bit codes (0..=4095, larger clamped) in wire order:
        speed, power (unipolar: code × scale), force, v_u, v_v, v_w, i_u, i_v (bipolar:
        (code − 2048) × scale)."""
    @staticmethod
    def tick() -> ForceEvent:
        """The control period's tick (estimate, control, wear)."""
    @staticmethod
    def identify(on: bool) -> ForceEvent:
        """CNC: no-load identification on (clears its sums) / off (solves B and T_fco)."""
    @staticmethod
    def control(on: bool) -> ForceEvent:
        """CNC: force control on / off (override back to ``manual_override``)."""
    @staticmethod
    def conditions(index: int) -> ForceEvent:
        """CNC: cutting conditions changed to condition set ``index`` (u8)."""
    @staticmethod
    def tool_changed() -> ForceEvent:
        """CNC: new tool; clears the wear alarm."""
    @property
    def kind(self) -> str:
        """``sample``, ``tick``, ``identify``, ``control``, ``conditions``, ``tool_changed``."""
    @property
    def codes(self) -> Optional[Tuple[int, int, int, int, int, int, int, int]]: ...
    @property
    def level(self) -> Optional[bool]: ...
    @property
    def index(self) -> Optional[int]: ...

class ForceOutputs:
    """Every output of the force path after one event. The I32F32 values (32 integer
    and 32 fraction bits) are given as float and exactly as ``<name>_bits`` (value ×
    2**32, int)."""

    @property
    def override_pct(self) -> int:
        """Feed override to the CNC, %, 0..=255."""
    @property
    def saturated(self) -> bool:
        """The controller's demand was outside 0..=255 in the last period."""
    @property
    def fast_estimate(self) -> bool:
        """The fast electrical estimate was selected in the last period."""
    @property
    def control_enabled(self) -> bool: ...
    @property
    def identifying(self) -> bool: ...
    @property
    def identified(self) -> bool:
        """B and T_fco come from an identification."""
    @property
    def wear_over(self) -> bool:
        """Spindle power at or above the wear threshold."""
    @property
    def wear_alarm(self) -> bool:
        """Wear alarm latched (change the tool)."""
    @property
    def wear_blind(self) -> bool:
        """The wear monitor cannot judge: its threshold is still above the conditions' own."""
    @property
    def bad_events(self) -> int:
        """Bad CNC commands (condition index out of range), saturating at 255."""
    @property
    def force_estimate(self) -> float:
        """Estimated cutting force, N."""
    @property
    def force_measured(self) -> float:
        """Dynamometer force (period average), N."""
    @property
    def wear_power(self) -> float:
        """Low-passed mean spindle power, W."""
    @property
    def wear_allowed(self) -> float:
        """Allowed power, W."""
    @property
    def coulomb(self) -> float:
        """Coulomb friction torque in use, N·m."""
    @property
    def force_estimate_bits(self) -> int: ...
    @property
    def force_measured_bits(self) -> int: ...
    @property
    def wear_power_bits(self) -> int: ...
    @property
    def wear_allowed_bits(self) -> int: ...
    @property
    def coulomb_bits(self) -> int: ...
    def as_dict(self) -> Dict[str, Union[int, bool, float]]:
        """Every output; each I32F32 value as float under its name and as bits under
        ``<name>_bits``."""

class ForceKernel:
    """The force path's event-level kernel (firmware semantics) from reset: sampling
    chain, estimator, controller, wear monitor."""

    def __init__(self, settings: ForceSettings) -> None: ...
    def apply(self, event: ForceEvent) -> ForceOutputs:
        """One event; the outputs after it (a sample counts toward ``samples``)."""
    def run(
        self, codes: npt.NDArray[np.uint16], commands: Optional[List[Tuple[int, ForceEvent]]] = None
    ) -> Dict[str, npt.NDArray[Any]]:
        """Feeds ADC samples (uint16, shape (n, 8), wire order) in Rust: sample ``k``
        (counted from the first sample of the kernel), then the tick when ``(k + 1) %
        samples_per_period == 0``, then the ``commands`` at ``k`` (CNC commands, in order).
        Returns one element per tick and command, the outputs after it: ``time`` (sample
        index, uint64), ``kind`` (wire kind, uint8), ``override_pct``, ``bad_events``
        (uint8), flags (bool), each I32F32 value as float64 and as int64 ``<name>_bits`` —
        the records of ``tooltouch control``'s ``.outputs.ttv``."""
    @property
    def outputs(self) -> ForceOutputs: ...
    @property
    def samples(self) -> int:
        """ADC samples applied so far."""

def drive_scenario(
    settings: ForceSettings, seed: int = 1, process: str = "kienzle"
) -> Tuple[npt.NDArray[np.uint16], List[Tuple[int, ForceEvent]]]:
    """``tooltouch control``'s depth-step scenario (13 s: identification, run-up, control
    on at 3 s, depth step at 8 s; ``process`` as ``control --process``) closed around the
    model: the ADC samples (uint16,
    (n, 8), one row per 1 kHz sample) and the CNC commands ``(sample index, event)``.
    ``ForceKernel(settings).run(codes, commands)`` replays it bit for bit."""

class Stimulus:
    """Run-length pins at a clock rate: segment ``i`` holds pin byte ``pins[i]`` for
    ``cycles[i]`` clocks."""

    def __init__(self, pins: npt.NDArray[np.uint8], cycles: npt.NDArray[np.uint32], clock_hz: int) -> None:
        """Segments from pin bytes and clock counts (each ≥ 1) at ``clock_hz`` Hz; equal
        neighbours are merged, as the CLI merges them reading a stimulus file."""
    @property
    def pins(self) -> npt.NDArray[np.uint8]: ...
    @property
    def cycles(self) -> npt.NDArray[np.uint32]: ...
    @property
    def clock_hz(self) -> int:
        """FPGA clock, Hz."""
    @property
    def total_cycles(self) -> int: ...
    def __len__(self) -> int: ...
    def per_clock(self) -> npt.NDArray[np.uint8]:
        """Every clock's pin byte (what ``FrontEnd.run`` takes)."""
    def events(self, settings: Settings) -> List[Tuple[int, Event]]:
        """The measurement events the cycle level acts on, ``(clock, event)``, canonical
        order: the events of ``tooltouch measure``'s ``events.ttv``."""
    def write_vcd(self, path: StrPath, settings: Settings, end: Optional[int] = None) -> int:
        """Writes the golden VCD of clocks ``[0, end)`` (byte for byte the CLI's);
        returns the clocks covered."""
    def hex_vectors(self, settings: Settings) -> Tuple[str, str]:
        """``(stim.hex, expect.hex)`` texts of the generated testbench (``$readmemh``),
        those of ``tooltouch hdl --vectors``."""

def lathe_stimulus(settings: Settings, seed: Optional[int] = None) -> Stimulus:
    """The pins of ``tooltouch measure``'s simulated lathe run for ``settings``
    (``[lathe]``), the model in the loop; ``seed`` replaces ``[lathe] seed``."""

def read_stimulus(path: StrPath, clock_hz: Optional[int] = None) -> Stimulus:
    """A pin stimulus from a VCD (golden, ``pin_*`` ports or bare names) or a
    ``stim.hex``, as ``tooltouch vectors --stimulus`` reads it."""

def read_expect_hex(path: StrPath, settings: Settings) -> Dict[str, npt.NDArray[np.uint64]]:
    """The generated testbench's ``expect.hex`` (``$readmemh``) as the output change
    list: ``clock`` and every output's register bits (uint64) at clock 0 and at each
    clock after which an output changed — ``FrontEnd.run_segments``' rows."""

class VcdReader:
    """Any tool's VCD: declarations at once, value changes in numpy chunks (constant
    memory). Errors name the file and line."""

    def __init__(self, path: StrPath) -> None: ...
    @property
    def signals(self) -> List[Tuple[str, str, int, int]]:
        """``(scope, name, width, code)`` of every ``$var``; scope dotted."""
    def code(self, name: str, scope: Optional[str] = None) -> int:
        """The code of ``name`` in a scope ending with ``scope`` (else the shallowest,
        outputs first); ``KeyError`` if none."""
    @property
    def timescale_fs(self) -> int: ...
    @property
    def golden_stamp(self) -> Optional[Tuple[int, int]]:
        """``(measure_hash, clock_hz)`` of a golden VCD."""
    @property
    def end_cycles(self) -> Optional[int]:
        """Clocks a golden VCD covers, once read to its end."""
    @property
    def time_fs(self) -> int:
        """Time of the last ``#`` read, fs."""
    def read(self, max_changes: int = 65536) -> Optional[Dict[str, npt.NDArray[Any]]]:
        """The next changes: ``time_fs`` (uint64), ``code`` (uint32), ``bits`` (uint64,
        x/z read 0), ``unknown`` (bool); None at the end."""
    def __iter__(self) -> Iterator[Dict[str, npt.NDArray[Any]]]: ...
    def __next__(self) -> Dict[str, npt.NDArray[Any]]: ...

def tune_sweep(spec_toml: str = "") -> Dict[str, Any]:
    """``tooltouch tune``'s sweep of a spec (TOML text, ``tune --spec``'s format; ``""``: the
    default sweep) on all cores: ``results.json`` as a dict (``rows``: each point's cost in
    flip-flops and iCE40 logic cells, its mean and largest |diameter error| vs the float
    reference in µm, revolution error, misses, ``pareto``; ``force``: each gain point's IAE
    in N·s)."""

def tune_optimize(spec_toml: str) -> Dict[str, Any]:
    """``tooltouch tune optimize`` on a spec (TOML text): ``evaluations`` (the JSON-lines
    log: ``family``, ``parameters``, ``cost``, ``metrics``, ``violated``), ``best`` (the
    answer's index, or None), ``stopped``, ``grid_points``, ``settings_toml`` (``tune
    point``'s format), ``unmet`` (``constraint``, ``tolerance``, ``best`` value reached),
    ``seconds``. A malformed spec is a ``ValueError`` naming the key."""

def ranges(
    settings: Optional[Settings] = None, force: Optional[ForceSettings] = None, scenarios: int = 8
) -> Dict[str, Any]:
    """``tooltouch ranges``: ``format`` (``tooltouch-ranges-2``), ``scenarios`` and
    ``registers``, each ``path``, ``kind`` (``output``, or ``internal``: a register inside a
    kernel, e.g. ``sampler.sums[power]``, ``estimator.no_load.sww``, ``pi.integral``),
    ``name``, ``format`` (``s24``, ``u16``, ``I32F32``, ``I56F8``, ``I32F32 clamp 0..255``
    …), ``bits`` (integer bits), ``signed``, ``overflow`` (``saturates`` / ``wraps``),
    ``limits`` (two numbers: the format's or the clamp's), observed ``min``/``max``,
    ``saturations`` (clocks or events at a limit), ``wraps``, ``headroom_bits``,
    ``samples``; over the tuning scenarios (seeds ``1..=scenarios``) and the force path's
    control scenario."""
