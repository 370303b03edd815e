"""Stimuli and their files against the CLI: the lathe scenario equals `tooltouch
measure`'s run (events, golden VCD byte for byte), the `$readmemh` vectors and golden VCD
of a stimulus equal `tooltouch vectors`' and `tooltouch hdl --vectors`', stimulus files
read back to the same pins, and the VCD reader's change lists equal the model's."""

import numpy as np
import pytest

import tooltouch
from test_cli_equality import SMALL, random_segments


@pytest.fixture(scope="session")
def small_vectors(tmp_path_factory, cli):
    """A random stimulus under SMALL and the CLI's golden set for it: (settings, stimulus, folder)."""
    work = tmp_path_factory.mktemp("small_vectors")
    settings = tooltouch.Settings(SMALL)
    (work / "small.toml").write_text(settings.to_toml())
    pins, clocks = random_segments(seed=21, count=2000)
    stimulus = tooltouch.Stimulus(pins, clocks.astype(np.uint32), settings.clock_hz)
    assert len(stimulus) < 2000, "equal neighbours are merged"
    stim_hex, _ = stimulus.hex_vectors(settings)
    (work / "stim.hex").write_text(stim_hex)
    cli("vectors", "--stimulus", work / "stim.hex", "--config", work / "small.toml", "--out", work / "golden")
    return settings, stimulus, work


def test_the_lathe_scenario_is_the_clis_run(fast_run):
    settings_file, out = fast_run
    settings = tooltouch.Settings.from_toml(settings_file)
    stimulus = tooltouch.lathe_stimulus(settings)
    assert stimulus.clock_hz == settings.clock_hz == 1_000_000
    events = stimulus.events(settings)
    records = list(tooltouch.TtvReader(out / "events.ttv"))[1:]
    assert len(events) == len(records) > 1000
    assert events == [(r.time, r.value) for r in records]
    assert stimulus.write_vcd(out.parent / "lathe.vcd", settings) == stimulus.total_cycles
    assert (out.parent / "lathe.vcd").read_bytes() == (out / "measure.vcd").read_bytes()


def test_a_seed_given_to_the_lathe_scenario_is_the_clis_seed_flag(fast_run, tmp_path, cli):
    settings_file, _ = fast_run
    settings = tooltouch.Settings.from_toml(settings_file)
    cli("measure", "--config", settings_file, "--seed", 99, "--out", tmp_path / "out", "--vcd", "all", "--no-progress")
    stimulus = tooltouch.lathe_stimulus(settings, seed=99)
    assert stimulus != tooltouch.lathe_stimulus(settings), "the seed changes the surface and the noise"
    stimulus.write_vcd(tmp_path / "seed.vcd", settings)
    assert (tmp_path / "seed.vcd").read_bytes() == (tmp_path / "out" / "measure.vcd").read_bytes()


def test_hex_vectors_and_golden_vcd_equal_the_clis(small_vectors, tmp_path, cli):
    settings, stimulus, work = small_vectors
    golden = work / "golden"
    stim_hex, expect_hex = stimulus.hex_vectors(settings)
    assert stim_hex == (golden / "stim.hex").read_text()
    assert expect_hex == (golden / "expect.hex").read_text()
    stimulus.write_vcd(tmp_path / "golden.vcd", settings)
    assert (tmp_path / "golden.vcd").read_bytes() == (golden / "golden.vcd").read_bytes()
    cli("hdl", "--config", work / "small.toml", "--out", tmp_path / "hdl", "--vectors", work / "stim.hex")
    assert (tmp_path / "hdl" / "stim.hex").read_text() == stim_hex
    assert (tmp_path / "hdl" / "expect.hex").read_text() == expect_hex


def test_stimulus_files_read_back_to_the_same_pins(small_vectors, fast_run):
    settings, stimulus, work = small_vectors
    from_hex = tooltouch.read_stimulus(work / "stim.hex", clock_hz=settings.clock_hz)
    assert from_hex == stimulus, "both merge equal neighbours"
    from_vcd = tooltouch.read_stimulus(work / "golden" / "golden.vcd")
    assert from_vcd.clock_hz == settings.clock_hz
    assert np.array_equal(from_vcd.per_clock(), stimulus.per_clock())
    _, out = fast_run
    lathe = tooltouch.read_stimulus(out / "measure.vcd")
    assert lathe.events(settings_of(fast_run)) == tooltouch.lathe_stimulus(settings_of(fast_run)).events(settings_of(fast_run))
    with pytest.raises(ValueError, match="says 1000000 Hz"):
        tooltouch.read_stimulus(out / "measure.vcd", clock_hz=2_000_000)
    with pytest.raises(ValueError, match="TtvReader"):
        tooltouch.read_stimulus(out / "events.ttv")
    with pytest.raises(ValueError, match="cycles\\[1\\] = 0"):
        tooltouch.Stimulus(np.array([1, 2], dtype=np.uint8), np.array([1, 0], dtype=np.uint32), 1000)


def settings_of(fast_run):
    return tooltouch.Settings.from_toml(fast_run[0])


def vcd_outputs_per_clock(path, settings, clocks, max_changes):
    """Every output of a golden VCD, clock by clock, from its change list in chunks."""
    reader = tooltouch.VcdReader(path)
    hash_, clock_hz = reader.golden_stamp
    assert hash_ == settings.config_hash and clock_hz == settings.clock_hz
    period_fs = reader.timescale_fs * (10**9 // clock_hz)
    codes = {name: reader.code(name, "outputs") for name in tooltouch.OUTPUT_NAMES}
    changes = {name: ([], []) for name in codes}
    chunks = 0
    for chunk in iter(lambda: reader.read(max_changes), None):
        chunks += 1
        assert len(chunk["code"]) <= max_changes and not chunk["unknown"].any()
        for name, code in codes.items():
            mine = chunk["code"] == code
            changes[name][0].append((chunk["time_fs"][mine] // np.uint64(period_fs)).astype(np.int64))
            changes[name][1].append(chunk["bits"][mine])
    assert reader.end_cycles == clocks
    out = {}
    for name, (at, bits) in changes.items():
        at, bits = np.concatenate(at), np.concatenate(bits)
        out[name] = np.repeat(bits, np.diff(np.append(at, np.int64(clocks))))
    return out, chunks


def test_the_vcd_reader_gives_the_models_outputs_in_chunks(small_vectors):
    settings, stimulus, work = small_vectors
    clocks = stimulus.total_cycles
    got, chunks = vcd_outputs_per_clock(work / "golden" / "golden.vcd", settings, clocks, max_changes=1000)
    assert chunks > 3
    expected = tooltouch.FrontEnd(settings).run(stimulus.per_clock())
    for name, width in settings.output_widths:
        want = expected[name].astype(np.int64).astype(np.uint64) & np.uint64((1 << width) - 1)
        assert np.array_equal(got[name], want), name


def test_run_segments_is_the_change_list_of_the_clock_by_clock_run_and_of_expect_hex(small_vectors):
    settings, stimulus, work = small_vectors
    per_clock = tooltouch.FrontEnd(settings).run(stimulus.per_clock())
    fe = tooltouch.FrontEnd(settings)
    changes = fe.run_segments(stimulus.pins, stimulus.cycles)
    assert fe.clocks == stimulus.total_cycles
    expect = tooltouch.read_expect_hex(work / "golden" / "expect.hex", settings)
    assert np.array_equal(expect["clock"], changes["clock"])
    for name, width in settings.output_widths:
        bits = changes[name].astype(np.int64).astype(np.uint64) & np.uint64((1 << width) - 1)
        assert np.array_equal(expect[name], bits), name
    at = changes["clock"].astype(np.int64)
    assert at[0] == 0 and len(at) < stimulus.total_cycles // 4
    held = np.diff(np.append(at, np.int64(stimulus.total_cycles)))
    for name in tooltouch.OUTPUT_NAMES:
        assert np.array_equal(np.repeat(changes[name], held), per_clock[name]), name
    # In two calls, with zero-length segments: the same change list after the first row.
    split = tooltouch.FrontEnd(settings)
    cut = len(stimulus) // 2
    first = split.run_segments(stimulus.pins[:cut], stimulus.cycles[:cut])
    zero = split.run_segments(np.array([1], dtype=np.uint8), np.array([0], dtype=np.uint32))
    assert len(zero["clock"]) == 0
    second = split.run_segments(stimulus.pins[cut:], stimulus.cycles[cut:])
    joined = np.concatenate([first["position"], second["position"]])
    joined_at = np.concatenate([first["clock"], second["clock"]]).astype(np.int64)
    held = np.diff(np.append(joined_at, np.int64(stimulus.total_cycles)))
    assert np.array_equal(np.repeat(joined, held), per_clock["position"])
    assert split.outputs == fe.outputs
