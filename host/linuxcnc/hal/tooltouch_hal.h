/* tooltouch_hal.h: the C ABI's output structures as plain words, for tooltouch.comp.
 * halcompile defines a macro for every pin name, and many pins are named as the model's
 * fields (armed, position, wear_alarm, ...); these helpers read the fields before those
 * macros exist (the component includes this header first). */
#ifndef TOOLTOUCH_HAL_H
#define TOOLTOUCH_HAL_H

#include "tooltouch.h"

/* The 17 measurement outputs in the model's order (TT_OUTPUT_COUNT): armed contact
 * register_now decision_position first_contact first_contact_position position
 * scale_errors count last_window_count charge density_armed density_fired revolutions
 * pulses confirmed faults; flags 0/1, positions sign-extended. */
static inline void tt_hal_measure_words(const TtMeasureOutputs *m, int64_t w[TT_OUTPUT_COUNT]) {
    w[0] = m->armed;
    w[1] = m->contact;
    w[2] = m->register_now;
    w[3] = m->decision_position;
    w[4] = m->first_contact;
    w[5] = m->first_contact_position;
    w[6] = m->position;
    w[7] = m->scale_errors;
    w[8] = m->count;
    w[9] = m->last_window_count;
    w[10] = m->charge;
    w[11] = m->density_armed;
    w[12] = m->density_fired;
    w[13] = m->revolutions;
    w[14] = m->pulses;
    w[15] = m->confirmed;
    w[16] = m->faults;
}

/* Number of force output words. */
#define TT_HAL_FORCE_WORDS 15

/* The 15 force outputs: override_pct saturated fast_estimate control_enabled identifying
 * identified wear_over wear_alarm bad_events, then the I32F32 bits of force_estimate
 * force_measured wear_power wear_allowed coulomb, then wear_blind. */
static inline void tt_hal_force_words(const TtForceOutputs *f, int64_t w[TT_HAL_FORCE_WORDS]) {
    w[0] = f->override_pct;
    w[1] = f->saturated;
    w[2] = f->fast_estimate;
    w[3] = f->control_enabled;
    w[4] = f->identifying;
    w[5] = f->identified;
    w[6] = f->wear_over;
    w[7] = f->wear_alarm;
    w[8] = f->bad_events;
    w[9] = f->force_estimate;
    w[10] = f->force_measured;
    w[11] = f->wear_power;
    w[12] = f->wear_allowed;
    w[13] = f->coulomb;
    w[14] = f->wear_blind;
}

/* A force event of `kind` with `on` and the condition set `set`; for a sample the eight
 * codes `adc` in the model's channel order (speed power force volts_u volts_v volts_w
 * amps_u amps_v), each clamped to 4095. */
static inline TtForceEvent tt_hal_force_event(uint8_t kind, uint8_t on, uint8_t set, const uint32_t adc[8]) {
    TtForceEvent e;
    uint16_t c[8];
    int i;
    for (i = 0; i < 8; i++) c[i] = (uint16_t)(adc[i] > 4095 ? 4095 : adc[i]);
    e.kind = kind;
    e.on = on;
    e.conditions = set;
    e.adc.speed = c[0];
    e.adc.power = c[1];
    e.adc.force = c[2];
    e.adc.volts[0] = c[3];
    e.adc.volts[1] = c[4];
    e.adc.volts[2] = c[5];
    e.adc.amps[0] = c[6];
    e.adc.amps[1] = c[7];
    return e;
}

/* A measurement event at `time` (the component's clock: one tick per servo period). */
static inline TtMeasureEvent tt_hal_measure_event(uint8_t kind, uint8_t level, uint8_t a, uint8_t b, uint64_t time) {
    TtMeasureEvent e;
    e.kind = kind;
    e.level = level;
    e.scale_a = a;
    e.scale_b = b;
    e.pulses = 0;
    e.time = time;
    return e;
}

#endif /* TOOLTOUCH_HAL_H */
