"""Shared fixtures: the CLI binary the bindings are compared with, and small settings.

The tests run in the venv `cargo xtask setup` makes (target/py-venv) with the wheel it
builds; `cargo xtask test` runs them after building the CLI (`cargo build --release`).
"""

import os
import pathlib
import subprocess

import pytest

try:
    import tooltouch  # noqa: F401
except ImportError as missing:
    raise pytest.UsageError(
        f"the tooltouch package is not installed in this Python ({missing}): run "
        "`cargo xtask setup` (builds the wheel into target/py-venv) and use "
        "target/py-venv/bin/python -m pytest python/tests, or `pip install ./python`"
    ) from missing

ROOT = pathlib.Path(__file__).resolve().parents[2]

# The quick lathe run of tests/cli_hdl_vectors.rs: 1 MHz clock, a fast spindle, one
# measurement (about 84 k clocks).
FAST_LATHE = """\
[lathe]
clock_hz = 1000000
rpm = 4800.0
[lathe.spindle_path]
loads = false    # a verification lathe: the measuring path is the machining path
[lathe.cycle]
repeats = 1
clearance_um = 3.0
z_dwell_ms = 0.2
retract_mm_per_s = 2.0
"""


def cli_binary() -> pathlib.Path:
    """The `tooltouch` CLI: $TOOLTOUCH_BIN, else target/release/tooltouch."""
    path = pathlib.Path(os.environ.get("TOOLTOUCH_BIN", ROOT / "target" / "release" / "tooltouch"))
    if not path.is_file():
        pytest.fail(
            f"the tooltouch CLI is not built at {path}: run `cargo xtask test` "
            "(it builds it with `cargo build --release` before pytest)"
        )
    return path


@pytest.fixture(scope="session")
def cli():
    """Runs the CLI with arguments; fails the test with its stderr on a non-zero exit."""
    binary = cli_binary()

    def run(*args):
        done = subprocess.run([str(binary), *map(str, args)], capture_output=True, text=True)
        if done.returncode != 0:
            pytest.fail(f"tooltouch {' '.join(map(str, args))} failed:\n{done.stderr}")
        return done.stdout

    return run


@pytest.fixture(scope="session")
def fast_run(tmp_path_factory, cli):
    """`tooltouch measure` on the fast lathe run, golden VCD of all of it: (settings
    file, output folder)."""
    work = tmp_path_factory.mktemp("fast_run")
    settings = work / "fast.toml"
    settings.write_text(FAST_LATHE)
    out = work / "out"
    cli("measure", "--config", settings, "--out", out, "--vcd", "all", "--no-progress")
    return settings, out
