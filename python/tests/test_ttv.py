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
