/* abi_test.c: drives the tooltouch C ABI as a C program does, and prints what the model
 * computed so that tests/c_program.rs can compare it with the Rust model bit for bit.
 *
 *   abi_test CONFIG_FILE CYCLES SEED
 *
 * Output lines (hexadecimal words):
 *   hash <measure hash> <force hash> <latency>
 *   c <cycle> <pins> <17 register words> <16 MCU words, diagnostics off> <MCU 7, 8 with diagnostics>
 *   e <event index> <event time> <17 register words>
 *   w <time> <armed> <pulses> <confirmed> <faults>, read at that time (tt_measurement_outputs_at)
 *   o <time> <17 register words> after tt_measurement_observe at that time
 *   faults <the TT_FAULT_COUNT names, bit 0 first>
 *   f <event index> <override> <flags> <bad events> <5 I32F32 words>
 *   errors ok
 * Exit status 0 when every call that should succeed did and every bad call failed with
 * its status and a message; 1 otherwise (the reason on stderr). */
#include "tooltouch.h"
#include <inttypes.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

static int failures = 0;

#define CHECK(call)                                                                    \
    do {                                                                               \
        TtStatus status_ = (call);                                                     \
        if (status_ != TT_STATUS_OK) {                                                 \
            fprintf(stderr, "%s:%d: %s -> %d: %s\n", __FILE__, __LINE__, #call,        \
                    (int)status_, tt_last_error());                                    \
            exit(1);                                                                   \
        }                                                                              \
    } while (0)

/* A bad call: must fail with `expected` and leave a message containing `needle`. */
static void expect_failure(TtStatus got, TtStatus expected, const char *needle, const char *what) {
    const char *message = tt_last_error();
    if (got != expected || strstr(message, needle) == NULL) {
        fprintf(stderr, "%s: status %d (expected %d), message \"%s\" (expected \"%s\" in it)\n",
                what, (int)got, (int)expected, message, needle);
        failures++;
    }
}

static uint64_t next(uint64_t *state) {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    return *state;
}

/* The pin a random toggle hits, from `r` in 0..63: FES often, the index and arm rarely, so
 * that decisions happen. */
static uint8_t pick_pin(uint64_t r) {
    if (r == 0) return TT_PIN_ARM;
    if (r <= 6) return TT_PIN_CONTACT;
    if (r == 7) return TT_PIN_INDEX;
    if (r <= 39) return TT_PIN_FES;
    if (r <= 51) return TT_PIN_SCALE_A;
    return TT_PIN_SCALE_B;
}

int main(int argc, char **argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: abi_test CONFIG_FILE CYCLES SEED\n");
        return 2;
    }
    if (tt_abi_version() != TT_ABI_VERSION) {
        fprintf(stderr, "library ABI %u, header %u\n", tt_abi_version(), TT_ABI_VERSION);
        return 1;
    }
    uint64_t cycles = strtoull(argv[2], NULL, 10);
    uint64_t rng = strtoull(argv[3], NULL, 16);

    TtConfig *config = NULL;
    CHECK(tt_config_from_file(argv[1], &config));
    uint64_t measure_hash = 0, force_hash = 0;
    uint32_t latency = 0;
    CHECK(tt_config_measure_hash(config, &measure_hash));
    CHECK(tt_config_force_hash(config, &force_hash));
    CHECK(tt_config_latency_cycles(config, &latency));
    printf("hash %016" PRIx64 " %016" PRIx64 " %x\n", measure_hash, force_hash, latency);

    /* Cycle level: random pins, every register and MCU word after every clock. */
    TtFrontEnd *fe = NULL;
    CHECK(tt_frontend_new(config, &fe));
    uint8_t pins = 0;
    for (uint64_t k = 0; k < cycles; k++) {
        if (next(&rng) % 2 == 0) pins ^= pick_pin(next(&rng) % 64);
        CHECK(tt_frontend_clock(fe, pins));
        uint64_t regs[TT_OUTPUT_COUNT];
        CHECK(tt_frontend_registers(fe, regs));
        printf("c %" PRIx64 " %x", k, pins);
        for (unsigned i = 0; i < TT_OUTPUT_COUNT; i++) printf(" %" PRIx64, regs[i]);
        for (uint32_t a = 0; a < TT_MCU_ADDRESSES; a++) {
            uint32_t word = 0;
            CHECK(tt_frontend_mcu_read(fe, a, false, &word));
            printf(" %x", word);
        }
        for (uint32_t a = 7; a <= 8; a++) {
            uint32_t word = 0;
            CHECK(tt_frontend_mcu_read(fe, a, true, &word));
            printf(" %x", word);
        }
        printf("\n");
    }
    /* The struct and the register words agree. */
    TtMeasureOutputs o;
    uint64_t regs[TT_OUTPUT_COUNT];
    CHECK(tt_frontend_outputs(fe, &o));
    CHECK(tt_frontend_registers(fe, regs));
    if (o.pulses != regs[14] || o.count != regs[8] || o.armed != regs[0] || o.confirmed != regs[15]
        || o.faults != regs[16]) {
        fprintf(stderr, "tt_frontend_outputs and tt_frontend_registers disagree\n");
        failures++;
    }

    /* Event level: a fixed sequence at its times (kind, level, a, b, pulses, time); the
     * gap before the last FES is longer than the settings' FES watchdog. */
    TtMeasurement *m = NULL;
    CHECK(tt_measurement_new(config, &m));
    TtMeasureEvent events[] = {
        {TT_MEASURE_EVENT_ARM, 1, 0, 0, 0, 0},     {TT_MEASURE_EVENT_CONTACT, 1, 0, 0, 0, 3},
        {TT_MEASURE_EVENT_FES, 0, 0, 0, 0, 10},    {TT_MEASURE_EVENT_SCALE, 0, 1, 0, 0, 10},
        {TT_MEASURE_EVENT_SCALE, 0, 1, 1, 0, 12},  {TT_MEASURE_EVENT_INDEX, 0, 0, 0, 0, 20},
        {TT_MEASURE_EVENT_FES, 0, 0, 0, 0, 25},    {TT_MEASURE_EVENT_CONTACT, 0, 0, 0, 0, 40},
        {TT_MEASURE_EVENT_PRESET_PULSES, 0, 0, 0, 0xffffffffu, 41},
        {TT_MEASURE_EVENT_FES, 0, 0, 0, 0, 200},   {TT_MEASURE_EVENT_ARM, 0, 0, 0, 0, 201},
    };
    for (unsigned e = 0; e < sizeof events / sizeof events[0]; e++) {
        CHECK(tt_measurement_apply(m, &events[e]));
        CHECK(tt_measurement_registers(m, regs));
        printf("e %x %" PRIx64, e, events[e].time);
        for (unsigned i = 0; i < TT_OUTPUT_COUNT; i++) printf(" %" PRIx64, regs[i]);
        printf("\n");
    }
    /* A second cycle armed at 300 with no FES: the watchdog read at two later times, then
     * observed. */
    TtMeasureEvent rearm = {TT_MEASURE_EVENT_ARM, 1, 0, 0, 0, 300};
    CHECK(tt_measurement_apply(m, &rearm));
    const uint64_t reads[] = {340, 400};
    for (unsigned r = 0; r < 2; r++) {
        CHECK(tt_measurement_outputs_at(m, reads[r], &o));
        printf("w %" PRIx64 " %x %x %x %x\n", reads[r], o.armed, o.pulses, o.confirmed, o.faults);
    }
    CHECK(tt_measurement_observe(m, 400));
    CHECK(tt_measurement_registers(m, regs));
    printf("o %x", 400);
    for (unsigned i = 0; i < TT_OUTPUT_COUNT; i++) printf(" %" PRIx64, regs[i]);
    printf("\n");
    printf("faults");
    for (uint32_t b = 0; b < TT_FAULT_COUNT; b++) printf(" %s", tt_fault_name(b));
    printf("\n");

    /* Force kernel: control on, four periods of samples and ticks, a bad condition set. */
    TtForce *force = NULL;
    CHECK(tt_force_new(config, &force));
    unsigned index = 0;
    for (int period = 0; period < 6; period++) {
        TtForceEvent e;
        memset(&e, 0, sizeof e);
        if (period == 1) {
            e.kind = TT_FORCE_EVENT_CONTROL;
            e.on = 1;
        } else if (period == 5) {
            e.kind = TT_FORCE_EVENT_CONDITIONS;
            e.conditions = 200;
        } else {
            e.kind = TT_FORCE_EVENT_TICK;
        }
        for (int s = 0; s < 50; s++) {
            TtForceEvent sample;
            memset(&sample, 0, sizeof sample);
            sample.kind = TT_FORCE_EVENT_SAMPLE;
            sample.adc.speed = (uint16_t)(1200 + 10 * period);
            sample.adc.power = (uint16_t)(900 + 40 * period + s);
            sample.adc.force = (uint16_t)(2300 + 5 * s);
            sample.adc.volts[0] = 2100;
            sample.adc.volts[1] = 2000;
            sample.adc.volts[2] = 2048;
            sample.adc.amps[0] = 2060;
            sample.adc.amps[1] = 2040;
            CHECK(tt_force_apply(force, &sample));
        }
        CHECK(tt_force_apply(force, &e));
        TtForceOutputs f;
        CHECK(tt_force_outputs(force, &f));
        unsigned flags = f.saturated | f.fast_estimate << 1 | f.control_enabled << 2 |
                         f.identifying << 3 | f.identified << 4 | f.wear_over << 5 |
                         f.wear_alarm << 6 | f.wear_blind << 7;
        printf("f %x %x %x %x %" PRIx64 " %" PRIx64 " %" PRIx64 " %" PRIx64 " %" PRIx64 "\n",
               index++, f.override_pct, flags, f.bad_events, (uint64_t)f.force_estimate,
               (uint64_t)f.force_measured, (uint64_t)f.wear_power, (uint64_t)f.wear_allowed,
               (uint64_t)f.coulomb);
    }

    /* Bad calls: a status and a message naming the culprit, and the handles still work. */
    expect_failure(tt_frontend_clock(fe, 0x80), TT_STATUS_BAD_ARGUMENT, "pins 0x80", "pin 7");
    expect_failure(tt_frontend_clock(NULL, 0), TT_STATUS_NULL_POINTER, "front_end is NULL", "NULL front end");
    uint32_t word;
    expect_failure(tt_frontend_mcu_read(fe, 16, false, &word), TT_STATUS_BAD_ARGUMENT, "MCU address 16", "address 16");
    TtMeasureEvent bad = {0x55, 0, 0, 0, 0, 500};
    expect_failure(tt_measurement_apply(m, &bad), TT_STATUS_BAD_ARGUMENT, "kind 0x55", "event kind");
    TtMeasureEvent early = {TT_MEASURE_EVENT_FES, 0, 0, 0, 0, 399};
    expect_failure(tt_measurement_apply(m, &early), TT_STATUS_BAD_ARGUMENT, "before the time already reached, 400", "time backwards");
    TtConfig *none = NULL;
    const uint8_t junk[5] = {1, 2, 3, 4, 5};
    expect_failure(tt_config_from_bytes(junk, sizeof junk, &none), TT_STATUS_BAD_CONFIG, "TTFWCFG1", "junk bytes");
    expect_failure(tt_config_from_file("/nonexistent/config.ttc", &none), TT_STATUS_IO, "/nonexistent/config.ttc", "missing file");
    if (none != NULL || tt_output_name(TT_OUTPUT_COUNT) != NULL || strcmp(tt_output_name(0), "armed") != 0
        || tt_fault_name(TT_FAULT_COUNT) != NULL) {
        fprintf(stderr, "a failed call wrote its handle, or tt_output_name or tt_fault_name is wrong\n");
        failures++;
    }
    CHECK(tt_frontend_clock(fe, pins));
    printf("errors %s\n", failures == 0 ? "ok" : "failed");

    tt_force_free(force);
    tt_measurement_free(m);
    tt_frontend_free(fe);
    tt_config_free(config);
    tt_config_free(NULL);
    return failures == 0 ? 0 : 1;
}
