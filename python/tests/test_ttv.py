"""`.ttv` streams: the CLI's files read and written back byte for byte; malformed streams
are errors naming the file and the byte."""

import pytest

import tooltouch


def copy_stream(source, target):
    reader = tooltouch.TtvReader(source)
    with tooltouch.TtvWriter(
        target, reader.stream, reader.tick_hz, measure_hash=reader.measure_hash, force_hash=reader.force_hash
    ) as writer:
        for record in reader:
            writer.write_record(record.kind, record.time, record.payload)


@pytest.mark.parametrize("name", ["events.ttv", "expected_outputs.ttv"])
def test_the_clis_streams_read_and_write_back_byte_for_byte(fast_run, tmp_path, name):
    _, out = fast_run
    copy_stream(out / name, tmp_path / name)
    assert (tmp_path / name).read_bytes() == (out / name).read_bytes()


def test_typed_records_write_the_same_bytes(fast_run, tmp_path):
    _, out = fast_run
    reader = tooltouch.TtvReader(out / "events.ttv")
    settings = None
    with tooltouch.TtvWriter(tmp_path / "e.ttv", "events", reader.tick_hz, measure_hash=reader.measure_hash) as w:
        for record in reader:
            if record.name == "measure_config":
                settings = record.value
                w.write_config(record.time, settings)
            else:
                w.write_event(record.time, record.value)
    assert settings is not None
    assert (tmp_path / "e.ttv").read_bytes() == (out / "events.ttv").read_bytes()


def test_malformed_streams_name_the_file_and_the_byte(fast_run, tmp_path):
    _, out = fast_run
    data = (out / "events.ttv").read_bytes()
    cut = tmp_path / "cut.ttv"
    cut.write_bytes(data[:-5])
    with pytest.raises(ValueError, match="cut.ttv: truncated at byte"):
        list(tooltouch.TtvReader(cut))
    glued = tmp_path / "glued.ttv"
    glued.write_bytes(data + data)
    with pytest.raises(ValueError, match="glued.ttv: bytes after the END record"):
        list(tooltouch.TtvReader(glued))
    magic = tmp_path / "magic.ttv"
    magic.write_bytes(b"XXXX" + data[4:])
    with pytest.raises(ValueError, match="magic.ttv: wrong magic"):
        tooltouch.TtvReader(magic)


def test_the_writer_refuses_time_going_backwards(tmp_path):
    with tooltouch.TtvWriter(tmp_path / "t.ttv", "events", 1000, settings=tooltouch.Settings()) as w:
        w.write_event(10, tooltouch.Event.arm(True))
        with pytest.raises(ValueError, match="before the previous"):
            w.write_event(9, tooltouch.Event.fes())
    records = list(tooltouch.TtvReader(tmp_path / "t.ttv"))
    assert [r.value for r in records] == [tooltouch.Event.arm(True)]


FIRMWARE_RECORDS = [
    ("firmware_observe", {"observe_fes": False}),
    ("firmware_decision", {"corrected_position": -90, "offset": -13}),
    ("firmware_profile", {"arm": (3, 120), "contact": (5, 300), "index": (2, 80), "fes": (9, 40), "scale": (7, 210)}),
    ("firmware_force_profile", {"sample": (650, 91000), "tick": (13, 52000), "command": (3, 900)}),
    (
        "firmware_status",
        {
            "events": 1234,
            "lost": 0,
            "overflowed": 1,
            "stack_bytes": 1800,
            "calibration_instructions": 100,
            "calibration_ticks": 104,
            "measure_hash": 0x0123456789ABCDEF,
            "force_hash": 0xFEDCBA9876543210,
        },
    ),
    ("firmware_error", {"code": 8, "wire_error": 1, "offset": 28, "detail": 50, "field": b""}),
]


def test_every_record_kind_is_typed_and_written_back_byte_for_byte(tmp_path):
    """Measurement, force and firmware records, each typed on reading and written back
    from its typed value to the same bytes."""
    settings = tooltouch.Settings()
    force = tooltouch.ForceSettings.design("adaptive")
    measure_outputs = tooltouch.Measurement(settings).apply(tooltouch.Event.arm(True), 0)
    force_outputs = tooltouch.ForceKernel(force).apply(tooltouch.ForceEvent.control(True))
    typed = tmp_path / "typed.ttv"
    with tooltouch.TtvWriter(typed, "events", 1000, settings=settings, force_hash=force.force_hash) as w:
        w.write_config(0, settings)
        w.write_force_config(0, force)
        for t, event in enumerate(
            [tooltouch.Event.arm(True), tooltouch.Event.contact(False), tooltouch.Event.index(), tooltouch.Event.fes(),
             tooltouch.Event.scale(True, False), tooltouch.Event.preset_pulses(77)]
        ):
            w.write_event(t, event)
        for event in [tooltouch.ForceEvent.sample([1, 2, 3, 4095, 2048, 7, 8, 9]), tooltouch.ForceEvent.tick(),
                      tooltouch.ForceEvent.identify(True), tooltouch.ForceEvent.control(False),
                      tooltouch.ForceEvent.conditions(3), tooltouch.ForceEvent.tool_changed()]:
            w.write_force_event(10, event)
        w.write_outputs(11, measure_outputs)
        w.write_force_outputs(11, force_outputs)
        for name, fields in FIRMWARE_RECORDS:
            w.write_firmware(12, name, fields)
    reader = tooltouch.TtvReader(typed)
    records = list(reader)
    assert reader.force_settings == force
    names = [r.name for r in records]
    assert names.count("force_config_chunk") == (len(force.canonical_bytes) + 43) // 44
    assert all(r.value is not None for r in records), [r.name for r in records if r.value is None]
    assert [r.value for r in records if r.name == "measure_outputs"] == [measure_outputs]
    assert [r.value for r in records if r.name == "force_outputs"] == [force_outputs]
    firmware = {r.name: r.value for r in records if r.name.startswith("firmware_")}
    for name, fields in FIRMWARE_RECORDS:
        assert {k: v for k, v in firmware[name].items() if k != "description"} == fields
    assert "chunk of 50 bytes" in firmware["firmware_error"]["description"]

    again = tmp_path / "again.ttv"
    with tooltouch.TtvWriter(again, reader.stream, reader.tick_hz, measure_hash=reader.measure_hash,
                             force_hash=reader.force_hash) as w:
        chunks_written = False
        for r in records:
            v = r.value
            if r.name == "measure_config":
                w.write_config(r.time, v)
            elif r.name == "force_config_chunk":
                if not chunks_written:
                    w.write_force_config(r.time, reader.force_settings)
                    chunks_written = True
            elif isinstance(v, tooltouch.Event):
                w.write_event(r.time, v)
            elif isinstance(v, tooltouch.ForceEvent):
                w.write_force_event(r.time, v)
            elif isinstance(v, tooltouch.Outputs):
                w.write_outputs(r.time, v)
            elif isinstance(v, tooltouch.ForceOutputs):
                w.write_force_outputs(r.time, v)
            else:
                w.write_firmware(r.time, r.name, v)
    assert again.read_bytes() == typed.read_bytes()


def test_a_firmware_decision_out_of_range_or_incomplete_is_refused(tmp_path):
    with tooltouch.TtvWriter(tmp_path / "d.ttv", "outputs", 1000, measure_hash=0) as w:
        with pytest.raises(ValueError, match="offset"):
            w.write_firmware(0, "firmware_decision", {"corrected_position": 5, "offset": 2**31})
        with pytest.raises(ValueError, match="corrected_position"):
            w.write_firmware(0, "firmware_decision", {"corrected_position": -(2**31) - 1, "offset": 0})
        with pytest.raises(ValueError, match="corrected_position"):
            w.write_firmware(0, "firmware_decision", {"offset": 0})
        with pytest.raises(ValueError, match="offset"):
            w.write_firmware(0, "firmware_decision", {"corrected_position": 0})
        w.write_firmware(1, "firmware_decision", {"corrected_position": 2**31 - 1, "offset": -(2**31)})
        # A short payload reads as the fields it holds.
        w.write_record(0x5A, 2, (-7).to_bytes(4, "little", signed=True) + b"\x01")
        w.write_record(0x5A, 3, b"")
    records = list(tooltouch.TtvReader(tmp_path / "d.ttv"))
    assert [(r.time, r.name, r.value) for r in records] == [
        (1, "firmware_decision", {"corrected_position": 2**31 - 1, "offset": -(2**31)}),
        (2, "firmware_decision", {"corrected_position": -7}),
        (3, "firmware_decision", {}),
    ]


def test_a_force_stream_with_a_wrong_hash_is_refused(tmp_path):
    force = tooltouch.ForceSettings()
    path = tmp_path / "f.ttv"
    with tooltouch.TtvWriter(path, "events", 1000, measure_hash=0, force_hash=force.force_hash ^ 1) as w:
        w.write_force_config(0, force)
    with pytest.raises(ValueError, match="f.ttv: byte"):
        list(tooltouch.TtvReader(path))
    with pytest.raises(ValueError, match="not a firmware record kind"):
        tooltouch.TtvWriter(tmp_path / "g.ttv", "outputs", 1000, measure_hash=0).write_firmware(0, "firmware_x", {})
