"""The tooltouch golden model for Python, bit-identical to the Rust model and the CLI:
the measurement front end (cycle and event level), the force kernel, the lathe and drive
scenarios that make stimuli, and the CLI's files (.ttv streams, golden VCD, $readmemh
vectors).

Every value is computed by the Rust crates (``tooltouch-model`` and the ``tooltouch``
host crate's settings) through the native module ``tooltouch._tooltouch``; see its
stubs for units and fixed-point formats, and docs/python.md for a scoreboard.
"""

from ._tooltouch import (
    OUTPUT_NAMES,
    PIN_ARM,
    PIN_CONTACT,
    PIN_FES,
    PIN_INDEX,
    PIN_NAMES,
    PIN_SCALE_A,
    PIN_SCALE_B,
    Event,
    ForceEvent,
    ForceKernel,
    ForceOutputs,
    ForceSettings,
    FrontEnd,
    Measurement,
    Outputs,
    Record,
    Settings,
    Stimulus,
    TtvReader,
    TtvWriter,
    VcdReader,
    drive_scenario,
    lathe_stimulus,
    read_expect_hex,
    read_stimulus,
    ranges,
    tune_optimize,
    tune_sweep,
)

__all__ = [
    "OUTPUT_NAMES",
    "PIN_ARM",
    "PIN_CONTACT",
    "PIN_FES",
    "PIN_INDEX",
    "PIN_NAMES",
    "PIN_SCALE_A",
    "PIN_SCALE_B",
    "Event",
    "ForceEvent",
    "ForceKernel",
    "ForceOutputs",
    "ForceSettings",
    "FrontEnd",
    "Measurement",
    "Outputs",
    "Record",
    "Settings",
    "Stimulus",
    "TtvReader",
    "TtvWriter",
    "VcdReader",
    "drive_scenario",
    "lathe_stimulus",
    "read_expect_hex",
    "read_stimulus",
    "ranges",
    "tune_optimize",
    "tune_sweep",
]
