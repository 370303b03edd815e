"""The force path against `tooltouch control`: the drive scenario's stimuli, the
ForceKernel's outputs and the typed force records equal the CLI's `.events.ttv` /
`.outputs.ttv` on the same settings and seed, bit for bit."""

import numpy as np
import pytest

import tooltouch

# Every controller with each feedback: `control --controller all --force both`.
RUNS = [(c, s) for c in ("pi", "adaptive", "fuzzy") for s in ("estimated", "measured")]
SEED = 3


@pytest.fixture(scope="session")
def control_run(tmp_path_factory, cli):
    """The CLI's vectors of every controller and feedback at seed SEED: the folder."""
    out = tmp_path_factory.mktemp("control")
    cli("control", "--controller", "all", "--force", "both", "--seed", SEED, "--out", out)
    return out


def cli_streams(out, controller, source):
    stem = out / f"{controller}_{source}"
    return stem.with_suffix(".events.ttv"), stem.with_suffix(".outputs.ttv")


def read_events(path):
    """(force settings, sample codes (n, 8), commands [(sample, ForceEvent)]) of an events.ttv."""
    reader = tooltouch.TtvReader(path)
    rows, commands, ticks = [], [], []
    for record in reader:
        if record.name == "force_config_chunk":
            continue
        event = record.value
        assert isinstance(event, tooltouch.ForceEvent), record
        if event.kind == "sample":
            assert record.time == len(rows), "samples are timed by their index"
            rows.append(event.codes)
        elif event.kind == "tick":
            ticks.append(record.time)
        else:
            commands.append((record.time, event))
    assert reader.force_settings is not None
    return reader.force_settings, np.array(rows, dtype=np.uint16), commands, ticks


@pytest.mark.parametrize("controller,source", RUNS)
def test_the_drive_scenario_and_the_kernel_equal_the_clis_vectors(control_run, controller, source):
    settings = tooltouch.ForceSettings.control_scenario(controller, source)
    events_bin, outputs_bin = cli_streams(control_run, controller, source)
    stream_settings, codes, commands, ticks = read_events(events_bin)
    assert stream_settings == settings
    assert tooltouch.TtvReader(events_bin).force_hash == settings.force_hash

    got_codes, got_commands = tooltouch.drive_scenario(settings, seed=SEED)
    assert got_codes.dtype == np.uint16 and got_codes.shape == codes.shape
    assert np.array_equal(got_codes, codes)
    assert got_commands == commands

    kernel = tooltouch.ForceKernel(settings)
    got = kernel.run(got_codes, got_commands)
    assert kernel.samples == len(codes)
    expected = [(r.time, r.value) for r in tooltouch.TtvReader(outputs_bin)]
    assert len(got["time"]) == len(expected) == len(ticks) + len(commands)
    assert got["override_pct"].max() != got["override_pct"].min(), "the controller never acted: a weak test"
    for i, (time, outputs) in enumerate(expected):
        assert got["time"][i] == time
        for name, value in outputs.as_dict().items():
            assert got[name][i] == value, f"output {i} at sample {time}: {name}"


def test_one_event_at_a_time_equals_the_batched_run():
    settings = tooltouch.ForceSettings.control_scenario("fuzzy", "estimated")
    codes, commands = tooltouch.drive_scenario(settings, seed=5)
    batched = tooltouch.ForceKernel(settings).run(codes, commands)
    kernel = tooltouch.ForceKernel(settings)
    rows = []
    pending = list(commands)
    for k, row in enumerate(codes):
        kernel.apply(tooltouch.ForceEvent.sample(row.tolist()))
        if (k + 1) % settings.samples_per_period == 0:
            rows.append(kernel.apply(tooltouch.ForceEvent.tick()))
        while pending and pending[0][0] == k:
            rows.append(kernel.apply(pending.pop(0)[1]))
    assert len(rows) == len(batched["time"])
    for i, o in enumerate(rows):
        for name, value in o.as_dict().items():
            assert batched[name][i] == value, (i, name)
    # Split in two calls: the sample index and the period carry over.
    split = tooltouch.ForceKernel(settings)
    cut = 4321
    first = split.run(codes[:cut], [c for c in commands if c[0] < cut])
    second = split.run(codes[cut:], [c for c in commands if c[0] >= cut])
    assert np.array_equal(np.concatenate([first["wear_power_bits"], second["wear_power_bits"]]), batched["wear_power_bits"])
    assert split.outputs == kernel.outputs


def test_force_streams_write_back_byte_for_byte(control_run, tmp_path):
    events_bin, outputs_bin = cli_streams(control_run, "pi", "estimated")
    settings = tooltouch.ForceSettings.control_scenario("pi", "estimated")
    codes, commands = tooltouch.drive_scenario(settings, seed=SEED)
    outputs = tooltouch.ForceKernel(settings)
    pending = list(commands)
    ev = tmp_path / "events.bin"
    out = tmp_path / "outputs.bin"
    with tooltouch.TtvWriter(ev, "events", settings.sample_hz, measure_hash=0, force_hash=settings.force_hash) as we, \
            tooltouch.TtvWriter(out, "outputs", settings.sample_hz, measure_hash=0, force_hash=settings.force_hash) as wo:
        we.write_force_config(0, settings)
        for k, row in enumerate(codes):
            sample = tooltouch.ForceEvent.sample(row.tolist())
            we.write_force_event(k, sample)
            outputs.apply(sample)
            events = [tooltouch.ForceEvent.tick()] if (k + 1) % settings.samples_per_period == 0 else []
            while pending and pending[0][0] == k:
                events.append(pending.pop(0)[1])
            for e in events:
                we.write_force_event(k, e)
                wo.write_force_outputs(k, outputs.apply(e))
    assert ev.read_bytes() == events_bin.read_bytes()
    assert out.read_bytes() == outputs_bin.read_bytes()


def test_force_settings_errors_and_sources(tmp_path):
    with pytest.raises(ValueError, match="kp_percent.*1..=1000"):
        tooltouch.ForceSettings.design(kp_percent=0)
    with pytest.raises(ValueError, match="bang-bang"):
        tooltouch.ForceSettings.design(controller="bang-bang")
    with pytest.raises(ValueError, match="controller"):
        tooltouch.ForceSettings.control_scenario("pid")
    default = tooltouch.ForceSettings()
    assert default.sample_hz == 1000 and default.samples_per_period == 50
    assert default.period_s == pytest.approx(0.05) and default.reference_n == 500.0
    assert tooltouch.ForceSettings.from_canonical_bytes(default.canonical_bytes) == default
    with pytest.raises(ValueError, match="do not decode"):
        tooltouch.ForceSettings.from_canonical_bytes(default.canonical_bytes[:-1])
    path = tmp_path / "s.toml"
    path.write_text('[force]\ncontroller = "fuzzy"\nkp_percent = 50\n')
    from_file = tooltouch.ForceSettings.from_toml(path)
    assert from_file == tooltouch.ForceSettings.design("fuzzy", kp_percent=50)
    assert from_file.controller == "fuzzy" and from_file.force_hash != default.force_hash
    path.write_text("[measure]\ni_def = 300\n")
    assert tooltouch.ForceSettings.from_toml(path) == default
    kernel = tooltouch.ForceKernel(default)
    with pytest.raises(ValueError, match="8 codes"):
        kernel.run(np.zeros((4, 7), dtype=np.uint16))
    with pytest.raises(ValueError, match="commands\\[0\\] at sample 9"):
        kernel.run(np.zeros((4, 8), dtype=np.uint16), [(9, tooltouch.ForceEvent.control(True))])
    with pytest.raises(ValueError, match="tick"):
        kernel.run(np.zeros((4, 8), dtype=np.uint16), [(1, tooltouch.ForceEvent.tick())])
    bad = kernel.apply(tooltouch.ForceEvent.conditions(200))
    assert bad.bad_events == 1
    assert bad.wear_allowed_bits == round(bad.wear_allowed * 2**32)
