component tooltouch "The tooltouch golden model in the servo thread: contact measurement, force-controlled feed override and wear alarm, over the model's C ABI";

description """
Runs the golden model's event-level kernels (the measurement front end and the force path)
once per call, with the firmware's semantics: the pins read in one period become events,
applied in the model's canonical order, and every output is written back to a pin.
The measurement's clock ticks once per call: every event of the n-th call (from 0) is at
time n, so the FES watchdog's fes_timeout_cycles counts servo periods here.
Accept a measurement only when confirmed is high and fault is low; fault (faults != 0)
goes to the CNC's alarm input, faults names the conditions bit by bit.

Per period, in this order:
arm and contact: an event when the level differs from the last period's;
index: one event for a rising edge of *index* plus one per count that *index-counts* went up;
FES: one event for a rising edge of *fes* plus one per count that *fes-counts* went up;
scale: one x4 quadrature step per count that *scale-counts* moved (either way).
Then the force path: identify and force-control when their level changes, conditions when its
value changes, tool-changed on a rising edge, one ADC sample of the eight *adc-* codes
(clamped to 4095), and the control tick after every samples-per-tick samples.
The first call takes the counts pins as their baseline (no events).
At most max-events index, FES and scale events per period: the rest waits for the next
period (*backlog*) and the period counts as an overrun.

Load with the configuration file that `tooltouch cosim config --config settings.toml --out FILE`
writes and the measurement hash it reports (the generated Verilog's CONFIG_HASH):
loadrt tooltouch config=FILE measure_hash=HEX [force_hash=HEX].
A file that does not decode, or whose hash differs, refuses to load with both named.
uspace builds only (POSIX or Preempt-RT): the model is a static library over the C library.
See docs/linuxcnc.md of the tooltouch repository.
""";

license "MIT OR Apache-2.0";
author "tooltouch";
include "tooltouch_hal.h";
include <stdlib.h>;
include <string.h>;
include <errno.h>;

// ---- measurement inputs
pin in bit arm "CNC arm: a measurement cycle runs while high; low aborts";
pin in bit contact "tool-workpiece contact level";
pin in bit index_ "index pulse level; a rising edge is one index event";
pin in s32 index_counts "index pulses counted in hardware (an encoder in counter mode); each increase is one index event";
pin in bit fes "FES pulse level; a rising edge is one FES event";
pin in s32 fes_counts "FES pulses counted in hardware (encoder.N.counts, hm2_*.encoder.NN.rawcounts in counter mode)";
pin in s32 scale_counts "linear scale position, x4 quadrature counts (encoder.N.counts, hm2_*.encoder.NN.rawcounts)";
// ---- force-path inputs: the ADC codes of the period's sample and the CNC's commands
pin in u32 adc_speed "motor speed, 12-bit ADC code (unipolar)";
pin in u32 adc_power "drive power, 12-bit ADC code (unipolar)";
pin in u32 adc_force "dynamometer force, 12-bit ADC code (bipolar around 2048)";
pin in u32 adc_volts_u "phase voltage u, 12-bit ADC code (bipolar around 2048)";
pin in u32 adc_volts_v "phase voltage v, 12-bit ADC code (bipolar around 2048)";
pin in u32 adc_volts_w "phase voltage w, 12-bit ADC code (bipolar around 2048)";
pin in u32 adc_amps_u "phase current u, 12-bit ADC code (bipolar around 2048)";
pin in u32 adc_amps_v "phase current v, 12-bit ADC code (bipolar around 2048)";
pin in bit force_control "force control on (tool in cut) while high";
pin in bit identify "no-load identification runs while high";
pin in bit tool_changed "a rising edge: a new tool is in (clears the wear alarm)";
pin in u32 conditions "cutting-condition set of the wear monitor";

// ---- measurement outputs (the model's 17 fields)
pin out bit armed "a measurement cycle is running";
pin out bit contact_filtered "the filtered contact level";
pin out bit register_now "position reached, register now (to motion.probe-input); held until the next arm";
pin out s32 decision_position "scale position latched at the decision, counts";
pin out float latched_position "decision-position times position-scale, machine units";
pin out bit first_contact "a contact edge has been seen since arm";
pin out s32 first_contact_position "scale position latched at the first contact, counts";
pin out s32 position "live scale position in the model, counts (scale_bits, sign-extended)";
pin out u32 scale_errors "illegal scale transitions, saturating at 255";
pin out u32 count_ "contact pulses in the current window";
pin out u32 last_window_count "contact pulses in the previous window";
pin out u32 charge "density detector charge, LSBs";
pin out bit density_armed "the density detector is armed";
pin out bit density_fired "the density detector has fired since arm";
pin out u32 revolutions "index pulses since arm, saturating at 65535";
pin out u32 pulses "FES pulses since arm, wrapping at 2^32";
pin out bit confirmed "the decision was confirmed by the contact pattern after it; accept a reading only with confirmed high and fault low";
pin out u32 faults "fault conditions latched since arm, one bit each: 1 contact_at_arm, 2 pulses_lost, 4 index_missing, 8 scale_error, 16 no_decision, 32 fes_timeout, 64 unconfirmed";
pin out bit fault "a fault is latched (faults != 0): to the CNC's alarm input; retract and re-measure";
// ---- force outputs (the model's 15 fields; I32F32 values as high and low words)
pin out u32 override_pct "feed override, %";
pin out float adaptive_feed "override-pct / 100, for motion.adaptive-feed";
pin out bit saturated "the controller's demand was outside 0..255 in the last period";
pin out bit fast_estimate "the fast electrical estimate was selected";
pin out bit control_enabled "force control is on";
pin out bit identifying "no-load identification is running";
pin out bit identified "friction comes from an identification";
pin out bit wear_over "the wear monitor's power is at or above its threshold";
pin out bit wear_alarm "wear alarm latched (stop, change the tool)";
pin out bit wear_blind "the wear monitor cannot judge: its threshold is still above the conditions' own (after a lighter cut)";
pin out u32 bad_events "bad CNC commands, saturating at 255";
pin out s32 force_estimate_hi "estimated cutting force, N, I32F32 bits 63..32";
pin out u32 force_estimate_lo "estimated cutting force, I32F32 bits 31..0";
pin out s32 force_measured_hi "dynamometer force (period mean), N, I32F32 bits 63..32";
pin out u32 force_measured_lo "dynamometer force, I32F32 bits 31..0";
pin out s32 wear_power_hi "low-passed spindle power, W, I32F32 bits 63..32";
pin out u32 wear_power_lo "low-passed spindle power, I32F32 bits 31..0";
pin out s32 wear_allowed_hi "allowed power, W, I32F32 bits 63..32";
pin out u32 wear_allowed_lo "allowed power, I32F32 bits 31..0";
pin out s32 coulomb_hi "Coulomb friction in use, N*m, I32F32 bits 63..32";
pin out u32 coulomb_lo "Coulomb friction, I32F32 bits 31..0";
pin out float force_estimate "estimated cutting force, N";
pin out float wear_power "low-passed spindle power, W";
// ---- health
pin out u32 overruns "periods whose work did not fit: events carried over, or longer than the thread's period";
pin out u32 backlog "index, FES and scale events waiting for the next period";
pin out u32 count_errors "times index-counts or fes-counts went down from one period to the next (ignored)";
pin out u32 abi_errors "calls into the model that failed (never expected)";
pin out s32 exec_time "this period's run time, ns";
pin out bit rate_mismatch "the thread's period is not the configuration's ADC sample period";

param rw u32 max_events = 4096 "index, FES and scale events applied per period at most";
param rw float position_scale = 0.001 "machine units per scale count, for latched-position";
param r u32 measure_hash_hi "the loaded configuration's measure_hash, bits 63..32";
param r u32 measure_hash_lo "measure_hash, bits 31..0";
param r u32 force_hash_hi "the loaded configuration's force_hash, bits 63..32";
param r u32 force_hash_lo "force_hash, bits 31..0";
param r u32 sample_hz "ADC sample rate of the configuration, Hz (the thread's rate)";
param r u32 samples_per_tick "ADC samples per control period of the configuration";

function update "apply this period's events to the kernels and write every output";
option extra_setup yes;
option extra_cleanup yes;
;;

static char *config = 0;
RTAPI_MP_STRING(config, "the configuration file `tooltouch cosim config` writes");
static char *measure_hash = 0;
RTAPI_MP_STRING(measure_hash, "its measure_hash, 16 hex digits (required)");
static char *force_hash = 0;
RTAPI_MP_STRING(force_hash, "its force_hash, 16 hex digits (optional)");

/* The kernels and the period state of the one instance. */
static TtMeasurement *tt_meas = 0;
static TtForce *tt_force = 0;
static struct {
    int started;
    int last_arm, last_contact, last_index, last_fes, last_identify, last_control, last_tool;
    uint32_t last_conditions;
    int32_t base_index, base_fes, base_scale;
    uint32_t pend_index, pend_fes;
    int64_t pend_scale;
    unsigned phase; /* scale lines (A,B) driven into the model: 0..3 = 00 10 11 01 */
    uint64_t now; /* the measurement's clock: calls of update so far */
    uint32_t samples, spt;
    long long last_start;
} st;

static int parse_hash(const char *text, unsigned long long *out) {
    char *end = 0;
    if (!text || !*text) return -1;
    errno = 0;
    *out = strtoull(text, &end, 16);
    return (errno || *end) ? -1 : 0;
}

EXTRA_SETUP() {
    TtConfig *cfg = 0;
    unsigned long long want = 0, want_force = 0;
    uint64_t got = 0, got_force = 0;
    uint32_t hz = 0, spp = 0;
    (void)prefix; (void)extra_arg;
    if (tt_meas) {
        rtapi_print_msg(RTAPI_MSG_ERR, "tooltouch: one instance only\n");
        return -EINVAL;
    }
    if (tt_abi_version() != TT_ABI_VERSION) {
        rtapi_print_msg(RTAPI_MSG_ERR, "tooltouch: the library's ABI is version %u, tooltouch.h's %u\n",
                        tt_abi_version(), TT_ABI_VERSION);
        return -EINVAL;
    }
    if (!config || !*config) {
        rtapi_print_msg(RTAPI_MSG_ERR, "tooltouch: no config=FILE (the file `tooltouch cosim config` writes)\n");
        return -EINVAL;
    }
    if (parse_hash(measure_hash, &want)) {
        rtapi_print_msg(RTAPI_MSG_ERR, "tooltouch: measure_hash=%s is not 16 hex digits (the hash of %s that the HAL file expects)\n",
                        measure_hash ? measure_hash : "(missing)", config);
        return -EINVAL;
    }
    if (force_hash && parse_hash(force_hash, &want_force)) {
        rtapi_print_msg(RTAPI_MSG_ERR, "tooltouch: force_hash=%s is not 16 hex digits\n", force_hash);
        return -EINVAL;
    }
    if (tt_config_from_file(config, &cfg) != TT_STATUS_OK) {
        rtapi_print_msg(RTAPI_MSG_ERR, "tooltouch: configuration %s does not decode: %s (the HAL file names measure_hash=%s)\n",
                        config, tt_last_error(), measure_hash);
        return -EINVAL;
    }
    tt_config_measure_hash(cfg, &got);
    tt_config_force_hash(cfg, &got_force);
    if (got != want || (force_hash && got_force != want_force)) {
        rtapi_print_msg(RTAPI_MSG_ERR, "tooltouch: configuration mismatch: %s gives measure_hash %016llx force_hash %016llx, the HAL file names measure_hash=%s force_hash=%s\n",
                        config, (unsigned long long)got, (unsigned long long)got_force, measure_hash,
                        force_hash ? force_hash : "(any)");
        tt_config_free(cfg);
        return -EINVAL;
    }
    if (tt_config_force_rates(cfg, &hz, &spp) != TT_STATUS_OK
        || tt_measurement_new(cfg, &tt_meas) != TT_STATUS_OK
        || tt_force_new(cfg, &tt_force) != TT_STATUS_OK) {
        rtapi_print_msg(RTAPI_MSG_ERR, "tooltouch: %s: %s\n", config, tt_last_error());
        tt_config_free(cfg);
        return -EINVAL;
    }
    tt_config_free(cfg);
    measure_hash_hi = (hal_u32_t)(got >> 32);
    measure_hash_lo = (hal_u32_t)got;
    force_hash_hi = (hal_u32_t)(got_force >> 32);
    force_hash_lo = (hal_u32_t)got_force;
    sample_hz = hz;
    samples_per_tick = spp;
    memset(&st, 0, sizeof st);
    st.spt = spp ? spp : 1;
    rtapi_print_msg(RTAPI_MSG_INFO, "tooltouch: %s: measure_hash %016llx force_hash %016llx, %u Hz, tick every %u samples\n",
                    config, (unsigned long long)got, (unsigned long long)got_force, hz, spp);
    return 0;
}

EXTRA_CLEANUP() {
    tt_measurement_free(tt_meas);
    tt_force_free(tt_force);
    tt_meas = 0;
    tt_force = 0;
}

/* One measurement event at this period's time; a failure is counted (never expected: every
 * argument is valid and the time never goes backwards). */
static void measure(struct __comp_state *__comp_inst, uint8_t kind, uint8_t level, uint8_t a, uint8_t b) {
    TtMeasureEvent e = tt_hal_measure_event(kind, level, a, b, st.now);
    if (tt_measurement_apply(tt_meas, &e) != TT_STATUS_OK) abi_errors++;
}

static void force_event(struct __comp_state *__comp_inst, uint8_t kind, uint8_t on, uint8_t set) {
    uint32_t adc[8] = {adc_speed, adc_power, adc_force, adc_volts_u, adc_volts_v, adc_volts_w, adc_amps_u, adc_amps_v};
    TtForceEvent e = tt_hal_force_event(kind, on, set, adc);
    if (tt_force_apply(tt_force, &e) != TT_STATUS_OK) abi_errors++;
}

/* Count pins: the increase since the last period (a decrease is an error, ignored). */
static uint32_t rise_of(struct __comp_state *__comp_inst, int32_t now, int32_t *last) {
    int32_t d = (int32_t)((uint32_t)now - (uint32_t)*last);
    *last = now;
    if (d < 0) { count_errors++; return 0; }
    return (uint32_t)d;
}

static void split(int64_t v, hal_s32_t *hi, hal_u32_t *lo) {
    *hi = (hal_s32_t)(v >> 32);
    *lo = (hal_u32_t)((uint64_t)v & 0xffffffffu);
}

FUNCTION(update) {
    static const uint8_t line_a[4] = {0, 1, 1, 0}, line_b[4] = {0, 0, 1, 1};
    long long start = rtapi_get_time();
    uint32_t budget = max_events, late = 0;
    TtMeasureOutputs m;
    TtForceOutputs f;
    int64_t w[TT_OUTPUT_COUNT], v[TT_HAL_FORCE_WORDS];
    int now;
    if (!tt_meas || !tt_force) return;
    if (!st.started) {
        st.started = 1;
        st.base_index = index_counts;
        st.base_fes = fes_counts;
        st.base_scale = scale_counts;
    } else if (start - st.last_start > period + period / 2) {
        late = 1; /* the thread came late: the last period overran */
    }
    st.last_start = start;
    /* Measurement at time st.now: the watchdog first, then arm, contact, index, FES, scale
     * (the canonical order). */
    if (tt_measurement_observe(tt_meas, st.now) != TT_STATUS_OK) abi_errors++;
    if (arm != st.last_arm) { st.last_arm = arm; measure(__comp_inst, TT_MEASURE_EVENT_ARM, arm, 0, 0); }
    if (contact != st.last_contact) { st.last_contact = contact; measure(__comp_inst, TT_MEASURE_EVENT_CONTACT, contact, 0, 0); }
    now = index_;
    st.pend_index += (now && !st.last_index) + rise_of(__comp_inst, index_counts, &st.base_index);
    st.last_index = now;
    now = fes;
    st.pend_fes += (now && !st.last_fes) + rise_of(__comp_inst, fes_counts, &st.base_fes);
    st.last_fes = now;
    st.pend_scale += (int32_t)((uint32_t)scale_counts - (uint32_t)st.base_scale);
    st.base_scale = scale_counts;
    while (st.pend_index && budget) { measure(__comp_inst, TT_MEASURE_EVENT_INDEX, 0, 0, 0); st.pend_index--; budget--; }
    while (st.pend_fes && budget) { measure(__comp_inst, TT_MEASURE_EVENT_FES, 0, 0, 0); st.pend_fes--; budget--; }
    while (st.pend_scale && budget) {
        st.phase = (st.pend_scale > 0 ? st.phase + 1 : st.phase + 3) & 3;
        st.pend_scale += st.pend_scale > 0 ? -1 : 1;
        measure(__comp_inst, TT_MEASURE_EVENT_SCALE, 0, line_a[st.phase], line_b[st.phase]);
        budget--;
    }
    backlog = st.pend_index + st.pend_fes + (hal_u32_t)(st.pend_scale < 0 ? -st.pend_scale : st.pend_scale);
    if (backlog) late = 1;
    /* Force path: commands, the sample, the tick. */
    if (identify != st.last_identify) { st.last_identify = identify; force_event(__comp_inst, TT_FORCE_EVENT_IDENTIFY, identify, 0); }
    if (force_control != st.last_control) { st.last_control = force_control; force_event(__comp_inst, TT_FORCE_EVENT_CONTROL, force_control, 0); }
    if (conditions != st.last_conditions) {
        st.last_conditions = conditions;
        force_event(__comp_inst, TT_FORCE_EVENT_CONDITIONS, 0, conditions > 255 ? 255 : (uint8_t)conditions);
    }
    if (tool_changed && !st.last_tool) force_event(__comp_inst, TT_FORCE_EVENT_TOOL_CHANGED, 0, 0);
    st.last_tool = tool_changed;
    force_event(__comp_inst, TT_FORCE_EVENT_SAMPLE, 0, 0);
    if (++st.samples >= st.spt) { st.samples = 0; force_event(__comp_inst, TT_FORCE_EVENT_TICK, 0, 0); }
    /* Every output, at time st.now (the kernel's: observed above); the next call is a tick later. */
    st.now++;
    if (tt_measurement_outputs(tt_meas, &m) != TT_STATUS_OK || tt_force_outputs(tt_force, &f) != TT_STATUS_OK) {
        abi_errors++;
        return;
    }
    tt_hal_measure_words(&m, w);
    armed = w[0];
    contact_filtered = w[1];
    register_now = w[2];
    decision_position = w[3];
    latched_position = w[3] * position_scale;
    first_contact = w[4];
    first_contact_position = w[5];
    position = w[6];
    scale_errors = w[7];
    count_ = w[8];
    last_window_count = w[9];
    charge = w[10];
    density_armed = w[11];
    density_fired = w[12];
    revolutions = w[13];
    pulses = w[14];
    confirmed = w[15];
    faults = w[16];
    fault = w[16] != 0;
    tt_hal_force_words(&f, v);
    override_pct = v[0];
    adaptive_feed = v[0] / 100.0;
    saturated = v[1]; fast_estimate = v[2]; control_enabled = v[3];
    identifying = v[4]; identified = v[5]; wear_over = v[6];
    wear_alarm = v[7]; bad_events = v[8];
    split(v[9], &force_estimate_hi, &force_estimate_lo);
    split(v[10], &force_measured_hi, &force_measured_lo);
    split(v[11], &wear_power_hi, &wear_power_lo);
    split(v[12], &wear_allowed_hi, &wear_allowed_lo);
    split(v[13], &coulomb_hi, &coulomb_lo);
    wear_blind = v[14];
    force_estimate = v[9] / 4294967296.0;
    wear_power = v[11] / 4294967296.0;
    rate_mismatch = sample_hz == 0 || period != 1000000000L / (long)sample_hz;
    exec_time = (hal_s32_t)(rtapi_get_time() - start);
    if (exec_time > period) late = 1;
    overruns += late;
}
