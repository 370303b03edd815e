"""Settings: validation errors name the field, the value and the range; dict and TOML
file agree; the configuration hash is the CLI's."""

import json

import pytest

import tooltouch


def test_defaults_validate_and_have_the_documented_latency():
    s = tooltouch.Settings()
    assert s.glitch_cycles == 4
    assert s.latency_cycles == 7
    assert s.clock_hz == 50_000_000
    assert [name for name, _ in s.output_widths] == tooltouch.OUTPUT_NAMES


def test_an_out_of_range_field_is_a_value_error_naming_field_value_and_range():
    with pytest.raises(ValueError) as e:
        tooltouch.Settings({"measure": {"i_def": 5000}})
    message = str(e.value)
    assert "`i_def`" in message and "5000" in message and "0..=1023" in message, message


def test_a_lathe_field_out_of_range_is_named():
    with pytest.raises(ValueError, match="`rpm`"):
        tooltouch.Settings({"lathe": {"rpm": 0.0}})


def test_unknown_fields_and_wrong_types_are_value_errors():
    with pytest.raises(ValueError, match="rmp"):
        tooltouch.Settings({"lathe": {"rmp": 1.0}})
    with pytest.raises(ValueError, match="glitch_cycles"):
        tooltouch.Settings({"measure": {"glitch_cycles": "four"}})
    with pytest.raises(ValueError, match="not a settings value"):
        tooltouch.Settings({"measure": {"glitch_cycles": object()}})


def test_a_bad_file_is_named(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[measure]\nscale_bits = 40\n")
    with pytest.raises(ValueError, match="`scale_bits` = 40 .*8..=32"):
        tooltouch.Settings.from_toml(bad)
    with pytest.raises(OSError, match="missing.toml"):
        tooltouch.Settings.from_toml(tmp_path / "missing.toml")


def test_dict_file_and_text_agree_and_round_trip(tmp_path):
    table = {
        "measure": {
            "glitch_cycles": 2,
            "method": "density",
            "charge_law": {"law": "exponential", "charge_shift": 3, "discharge_shift": 4},
        },
        "lathe": {"rpm": 600.0, "cycle": {"repeats": 3}},
    }
    from_dict = tooltouch.Settings(table)
    path = tmp_path / "s.toml"
    path.write_text(from_dict.to_toml())
    assert tooltouch.Settings.from_toml(path) == from_dict
    assert tooltouch.Settings.from_toml_str(from_dict.to_toml()).config_hash == from_dict.config_hash
    assert from_dict.config_hash != tooltouch.Settings().config_hash


def test_the_configuration_hash_is_the_clis(fast_run):
    settings, out = fast_run
    summary = json.loads((out / "summary.json").read_text())
    expected = tooltouch.Settings.from_toml(settings).config_hash
    assert f"{expected:016x}" in json.dumps(summary), "summary.json names another hash"
    assert tooltouch.TtvReader(out / "events.ttv").measure_hash == expected
