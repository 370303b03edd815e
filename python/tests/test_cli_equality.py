"""The bindings against the CLI on the same settings: the batched FrontEnd against
`tooltouch vectors`' expect.hex (cycle level, every output bit of every clock), and the
event-level Measurement against `tooltouch measure`'s expected_outputs.ttv."""

import itertools

import numpy as np

import tooltouch

SMALL = {
    "measure": {
        "pulses_per_rev": 16,
        "i_def": 6,
        "window_revs": 2,
        "charge_bits": 6,
        "charge_law": {"law": "linear", "charge_step": 5, "discharge_step": 3},
        "fire_threshold": 40,
        "rearm_threshold": 10,
        "glitch_cycles": 1,
        "scale_bits": 10,
        "method": "density",
    }
}


def random_segments(seed, count):
    """Run-length pins: (pins, clocks) segments with bursts, glitches and scale moves."""
    rng = np.random.default_rng(seed)
    pins = rng.integers(0, 64, size=count, dtype=np.uint8)
    # Arm mostly high so the kernel counts; short segments make glitches and same-clock edges.
    pins = pins | np.where(rng.random(count) < 0.9, tooltouch.PIN_ARM, 0).astype(np.uint8)
    clocks = np.where(rng.random(count) < 0.5, rng.integers(1, 4, size=count), rng.integers(4, 40, size=count))
    return pins, clocks.astype(np.int64)


def write_stim_hex(path, pins, clocks):
    words = [f"{len(pins):010x}"] + [f"{p:02x}{c:08x}" for p, c in zip(pins, clocks)]
    path.write_text("\n".join(words) + "\n")


def read_expect_hex(path, widths, cycles):
    """expect.hex as one array per output over `cycles` clocks (register bits)."""
    words = path.read_text().split()
    entries = [int(w, 16) for w in words[1:]]
    total = sum(w for _, w in widths)
    out = {name: np.zeros(cycles, dtype=np.uint64) for name, _ in widths}
    starts = [e >> total for e in entries] + [cycles]
    for i, entry in enumerate(entries):
        shift = total
        for name, width in widths:
            shift -= width
            out[name][starts[i] : starts[i + 1]] = (entry >> shift) & ((1 << width) - 1)
    return out


def test_batched_front_end_equals_the_clis_vectors_bit_for_bit(tmp_path, cli):
    settings = tooltouch.Settings(SMALL)
    config = tmp_path / "small.toml"
    config.write_text(settings.to_toml())
    pins, clocks = random_segments(seed=15, count=3000)
    write_stim_hex(tmp_path / "stim.hex", pins, clocks)
    cli("vectors", "--stimulus", tmp_path / "stim.hex", "--config", config, "--out", tmp_path / "golden")

    per_clock = np.repeat(pins, clocks)
    got = tooltouch.FrontEnd(settings).run(per_clock)
    widths = settings.output_widths
    expected = read_expect_hex(tmp_path / "golden" / "expect.hex", widths, len(per_clock))
    assert expected["register_now"].any(), "the stimulus never decided: a weak test"
    for name, width in widths:
        bits = got[name].astype(np.int64).astype(np.uint64) & np.uint64((1 << width) - 1)
        mismatch = np.flatnonzero(bits != expected[name])
        assert mismatch.size == 0, (
            f"clock {mismatch[0]}: {name} expected {expected[name][mismatch[0]]:#x} got {bits[mismatch[0]]:#x}"
        )


def test_step_and_advance_equal_the_batched_run():
    settings = tooltouch.Settings(SMALL)
    pins, clocks = random_segments(seed=7, count=400)
    per_clock = np.repeat(pins, clocks)
    batched = tooltouch.FrontEnd(settings).run(per_clock)
    one_by_one = tooltouch.FrontEnd(settings)
    for k, p in enumerate(per_clock):
        o = one_by_one.step(int(p))
        assert o.as_dict() == {name: int(batched[name][k]) for name in tooltouch.OUTPUT_NAMES}, k
    fast = tooltouch.FrontEnd(settings)
    for p, c in zip(pins, clocks):
        fast.advance(int(p), int(c))
    assert fast.outputs == one_by_one.outputs


def test_pins_above_bit_5_are_refused():
    fe = tooltouch.FrontEnd(tooltouch.Settings())
    try:
        fe.run(np.array([0, 64], dtype=np.uint8))
    except ValueError as e:
        assert "pins[1]" in str(e)
    else:
        raise AssertionError("pin bit 6 accepted")


def test_event_level_measurement_equals_the_clis_expected_outputs(fast_run):
    settings_file, out = fast_run
    events = tooltouch.TtvReader(out / "events.ttv")
    first = next(events)
    assert first.name == "measure_config"
    settings = tooltouch.Settings.from_toml(settings_file)
    assert first.value.config_hash == settings.config_hash
    measurement = tooltouch.Measurement(settings)
    expected = tooltouch.TtvReader(out / "expected_outputs.ttv")
    assert expected.stream == "outputs"
    compared = 0
    for event, outputs in itertools.zip_longest(events, expected):
        assert event is not None and outputs is not None, "not one outputs record per event"
        assert event.time == outputs.time
        got = measurement.apply(event.value, event.time)
        assert got == outputs.value, f"event {compared} at {event.time}"
        compared += 1
    assert compared > 1000
    assert measurement.outputs.register_now


def test_mcu_rdata_is_the_word_the_register_map_documents():
    """``run(pins, mcu_addr=…)``'s ``mcu_rdata`` against the map as docs/CONTRACT.md writes
    it, computed here from the output columns."""
    settings = tooltouch.Settings(SMALL)
    pins, clocks = random_segments(seed=15, count=3000)
    per_clock = np.repeat(pins, clocks)
    rng = np.random.default_rng(3)
    addr = rng.integers(0, 16, size=len(per_clock), dtype=np.uint8)
    got = tooltouch.FrontEnd(settings).run(per_clock, mcu_addr=addr)
    diagnostic = tooltouch.FrontEnd(settings).run(per_clock, mcu_addr=addr, mcu_diagnostics=True)
    assert got["register_now"].any(), "the stimulus never decided: a weak test"
    c = {name: got[name].astype(np.int64) for name in tooltouch.OUTPUT_NAMES}
    flags = ["armed", "contact", "register_now", "first_contact", "density_armed", "density_fired", "confirmed"]
    status = sum(c[name] << bit for bit, name in enumerate(flags)) | (c["faults"] << 8)
    by_addr = {
        0: status,
        1: c["position"] & 0xFFFF_FFFF,
        2: c["decision_position"] & 0xFFFF_FFFF,
        3: c["first_contact_position"] & 0xFFFF_FFFF,
        4: c["count"],
        5: c["last_window_count"],
        6: c["charge"],
        9: c["scale_errors"],
        10: np.full(len(addr), settings.config_hash & 0xFFFF_FFFF),
        11: np.full(len(addr), settings.config_hash >> 32),
    }
    want = np.zeros(len(addr), dtype=np.int64)
    for a, words in by_addr.items():
        want[addr == a] = words[addr == a]
    assert (got["mcu_rdata"].astype(np.int64) == want).all()
    want[addr == 7] = c["revolutions"][addr == 7]
    want[addr == 8] = c["pulses"][addr == 8]
    assert (diagnostic["mcu_rdata"].astype(np.int64) == want).all()
    assert "mcu_rdata" not in tooltouch.FrontEnd(settings).run(per_clock[:10])


def test_bad_mcu_addresses_are_refused_naming_the_element():
    fe = tooltouch.FrontEnd(tooltouch.Settings())
    pins = np.zeros(3, dtype=np.uint8)
    for addr, named in [(np.array([0, 1, 16], dtype=np.uint8), "mcu_addr[2] = 16"), (np.zeros(2, dtype=np.uint8), "mcu_addr has 2 elements")]:
        try:
            fe.run(pins, mcu_addr=addr)
        except ValueError as e:
            assert named in str(e), str(e)
        else:
            raise AssertionError(f"{addr} accepted")
