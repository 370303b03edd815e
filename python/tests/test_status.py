"""The measurement status: `confirmed` and `faults` in every output, the thresholds of
`[measure.checks]` in the settings, and the time the event level is told (the FES
watchdog), equal to the model's at both levels."""

import numpy as np
import pytest

import tooltouch

WATCHDOG = {"measure": {"checks": {"fes_timeout_cycles": 40}}}


def test_the_status_is_the_last_two_outputs_and_the_faults_are_named():
    assert tooltouch.OUTPUT_NAMES[-2:] == ["confirmed", "faults"]
    assert len(tooltouch.OUTPUT_NAMES) == 17
    assert tooltouch.FAULT_NAMES == [
        "contact_at_arm",
        "pulses_lost",
        "index_missing",
        "scale_error",
        "no_decision",
        "fes_timeout",
        "unconfirmed",
    ]
    bits = [
        tooltouch.FAULT_CONTACT_AT_ARM,
        tooltouch.FAULT_PULSES_LOST,
        tooltouch.FAULT_INDEX_MISSING,
        tooltouch.FAULT_SCALE_ERROR,
        tooltouch.FAULT_NO_DECISION,
        tooltouch.FAULT_FES_TIMEOUT,
        tooltouch.FAULT_UNCONFIRMED,
    ]
    assert bits == [1 << i for i in range(7)]
    widths = dict(tooltouch.Settings().output_widths)
    assert (widths["confirmed"], widths["faults"]) == (1, 7)


def test_measure_checks_are_settings_validated_and_hashed():
    table = {"measure": {"checks": {"fes_timeout_cycles": 40, "confirm_windows": 2, "probe_revs": 0}}}
    from_dict = tooltouch.Settings(table)
    text = "[measure.checks]\nfes_timeout_cycles = 40\nconfirm_windows = 2\nprobe_revs = 0\n"
    assert tooltouch.Settings.from_toml_str(text).config_hash == from_dict.config_hash
    assert from_dict.config_hash != tooltouch.Settings().config_hash
    assert "[measure.checks]" in from_dict.to_toml()
    with pytest.raises(ValueError, match="confirm_percent"):
        tooltouch.Settings({"measure": {"checks": {"confirm_percent": 0}}})
    with pytest.raises(ValueError, match="fes_timout_cycles"):
        tooltouch.Settings({"measure": {"checks": {"fes_timout_cycles": 3}}})


def test_the_event_level_watchdog_expires_at_its_tick():
    m = tooltouch.Measurement(tooltouch.Settings(WATCHDOG))
    assert m.apply(tooltouch.Event.arm(True), 100).faults == 0
    assert m.apply(tooltouch.Event.fes(), 139).faults == 0
    assert m.outputs_at(178).faults == 0
    late = m.outputs_at(179)
    assert late.faults == tooltouch.FAULT_FES_TIMEOUT
    assert late.fault_names == ["fes_timeout"]
    assert m.time == 139, "outputs_at changes nothing"
    assert m.observe(200).faults == tooltouch.FAULT_FES_TIMEOUT
    with pytest.raises(ValueError, match="time 150 is before the time already reached, 200"):
        m.apply(tooltouch.Event.fes(), 150)
    # Held after the arm falls, cleared at the next arm.
    assert m.apply(tooltouch.Event.arm(False), 201).faults == tooltouch.FAULT_FES_TIMEOUT
    assert m.apply(tooltouch.Event.arm(True), 5000).faults == 0
    assert m.outputs.as_dict()["faults"] == 0


def test_the_cycle_level_shows_the_watchdog_in_every_way_of_clocking():
    settings = tooltouch.Settings(WATCHDOG)
    arm = tooltouch.PIN_ARM
    # Armed, a few FES pulses, then the FES stops while armed.
    pins = np.array([arm] * 20 + [arm | tooltouch.PIN_FES, arm] * 5 + [arm] * 200, dtype=np.uint8)
    one_by_one = tooltouch.FrontEnd(settings)
    stepped = np.array([one_by_one.step(int(p)).faults for p in pins], dtype=np.uint8)
    batched = tooltouch.FrontEnd(settings).run(pins)
    assert np.array_equal(batched["faults"], stepped)
    expired = int(np.argmax(stepped != 0))
    assert stepped[expired] == tooltouch.FAULT_FES_TIMEOUT and expired > 30
    # Run-length: the settled tail is skipped, the expiry still lands on its clock.
    segments = tooltouch.FrontEnd(settings)
    rows = segments.run_segments(
        np.array([arm, arm | tooltouch.PIN_FES, arm], dtype=np.uint8),
        np.array([20, 1, 209], dtype=np.uint32),
    )
    assert segments.clocks == 230
    timed_out = rows["clock"][rows["faults"] != 0]
    assert len(timed_out) >= 1
    pins2 = np.array([arm] * 20 + [arm | tooltouch.PIN_FES] + [arm] * 209, dtype=np.uint8)
    want = tooltouch.FrontEnd(settings).run(pins2)["faults"]
    assert int(timed_out[0]) == int(np.argmax(want != 0))
    assert segments.outputs.faults == tooltouch.FAULT_FES_TIMEOUT
    # advance keeps the time too: the same front end advanced reads the same outputs.
    advanced = tooltouch.FrontEnd(settings)
    advanced.run(pins2[:21])
    advanced.advance(arm, 209)
    assert advanced.clocks == 230 and advanced.outputs == segments.outputs
