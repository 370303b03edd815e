/* tooltouch_vpi.c: the golden model as Icarus system functions (VPI), for the Verilog-2005
 * scoreboard host/rtl-sim/verilog/tooltouch_scoreboard.v. Build it with Icarus's tool, linking
 * the static library of the C ABI:
 *
 *   iverilog-vpi --name=tooltouch -I<repo>/host/abi/include <repo>/host/rtl-sim/c/tooltouch_vpi.c \
 *                <target>/release/libtooltouch_abi.a -lpthread -ldl -lm
 *   vvp -M . -m tooltouch sim +tooltouch_config=FILE
 *
 * Functions (32-bit integer results; a model is a small integer, -1 on failure):
 *   $tooltouch_open(path, diagnostics)           a model for the configuration file at path
 *   $tooltouch_config_hash_lo(m), _hi(m)         the measurement configuration's hash, halves
 *   $tooltouch_output_width(m, index)            width of output index, bits
 *   $tooltouch_clock(m, pins, rst)               one rising edge (or reset); 0 on success
 *   $tooltouch_compare(m, mcu_addr, mcu_rdata, irq, armed, ..., pulses)
 *                                                the first differing signal (the outputs in
 *                                                tt_output_name's order, irq, mcu_rdata), -1
 *                                                if none; X or Z in a DUT signal is a
 *                                                mismatch
 *   $tooltouch_expected(m, index, mcu_addr)      the model's value of a signal
 * At the end of the simulation each model prints `tooltouch_scoreboard OK <cycles>` (or
 * FAIL with the count of mismatching cycles, or that no clock was compared). Nothing is allocated after $tooltouch_open. */
#include "tooltouch.h"
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <vpi_user.h>

#define MAX_MODELS 16
#define SIGNALS (TT_OUTPUT_COUNT + 2)
/* BEGIN GENERATED irq-source: hdl-gen's scoreboard_lists, cargo xtask bless-hdl */
/* irq is a copy of output 2, register_now (tt_frontend: `assign irq = register_now`). */
enum { IRQ_SOURCE = 2 };
/* END GENERATED irq-source */
/* BEGIN GENERATED compare-arguments: hdl-gen's scoreboard_lists, cargo xtask bless-hdl */
#define COMPARE_ARGUMENTS "the model, mcu_addr, mcu_rdata, irq and the 17 outputs"
/* END GENERATED compare-arguments */

typedef struct Model {
    TtConfig *config;
    TtFrontEnd *front_end;
    uint64_t registers[TT_OUTPUT_COUNT];
    int diagnostics;
    uint64_t clocks;
    uint64_t mismatches;
} Model;

static Model models[MAX_MODELS];
static int model_count;

/* The current call, its arguments read in order. */
typedef struct Call {
    vpiHandle call;
    vpiHandle args;
    int count;
    int exhausted;
} Call;

static Call begin_call(void) {
    Call c;
    c.call = vpi_handle(vpiSysTfCall, NULL);
    c.args = vpi_iterate(vpiArgument, c.call);
    c.count = 0;
    c.exhausted = c.args == NULL;
    return c;
}

static vpiHandle next_arg(Call *c) {
    if (c->exhausted) return NULL;
    vpiHandle a = vpi_scan(c->args);
    if (a == NULL) c->exhausted = 1; /* the iterator is freed */
    else c->count++;
    return a;
}

static void end_call(Call *c, int32_t result) {
    if (!c->exhausted) vpi_free_object(c->args);
    s_vpi_value v;
    v.format = vpiIntVal;
    v.value.integer = result;
    vpi_put_value(c->call, &v, NULL, vpiNoDelay);
}

static void stop(const char *name, const char *why) {
    vpi_printf("tooltouch_vpi: %s: %s\n", name, why);
    vpi_control(vpiFinish, 1);
}

/* The next argument's value (up to 64 bits) and whether it holds an X or Z bit. */
static uint64_t value_of(Call *c, int *unknown) {
    vpiHandle a = next_arg(c);
    if (a == NULL) {
        *unknown = 1;
        return 0;
    }
    s_vpi_value v;
    v.format = vpiVectorVal;
    vpi_get_value(a, &v);
    int size = vpi_get(vpiSize, a);
    uint64_t value = (uint32_t)v.value.vector[0].aval;
    uint64_t xz = (uint32_t)v.value.vector[0].bval;
    if (size > 32) {
        value |= (uint64_t)(uint32_t)v.value.vector[1].aval << 32;
        xz |= (uint64_t)(uint32_t)v.value.vector[1].bval << 32;
    }
    if (size < 64) {
        uint64_t mask = (UINT64_C(1) << size) - 1;
        value &= mask;
        xz &= mask;
    }
    *unknown = xz != 0;
    return value;
}

/* The model named by the call's first argument, or NULL (the simulation stops). */
static Model *model_arg(Call *c, const char *name) {
    int unknown = 0;
    uint64_t index = value_of(c, &unknown);
    if (unknown || index >= (uint64_t)model_count) {
        stop(name, "the first argument is not a model from $tooltouch_open");
        return NULL;
    }
    return &models[index];
}

static int refresh(Model *m) {
    return tt_frontend_registers(m->front_end, m->registers) == TT_STATUS_OK;
}

static uint32_t mcu_word(const Model *m, uint64_t addr) {
    uint32_t word = 0;
    if (addr < TT_MCU_ADDRESSES)
        tt_frontend_mcu_read(m->front_end, (uint32_t)addr, m->diagnostics != 0, &word);
    return word;
}

static PLI_INT32 open_calltf(PLI_BYTE8 *name) {
    Call c = begin_call();
    vpiHandle path_arg = next_arg(&c);
    int32_t result = -1;
    char path[4096];
    path[0] = 0;
    if (path_arg != NULL) {
        s_vpi_value v;
        v.format = vpiStringVal;
        vpi_get_value(path_arg, &v);
        snprintf(path, sizeof path, "%s", v.value.str);
    }
    int unknown = 0;
    uint64_t diagnostics = value_of(&c, &unknown);
    if (tt_abi_version() != TT_ABI_VERSION) {
        vpi_printf("tooltouch_scoreboard: libtooltouch_abi has ABI version %u, tooltouch.h %u\n",
                   tt_abi_version(), TT_ABI_VERSION);
    } else if (model_count == MAX_MODELS) {
        vpi_printf("tooltouch_scoreboard: more than %d scoreboards\n", MAX_MODELS);
    } else {
        Model *m = &models[model_count];
        memset(m, 0, sizeof *m);
        m->diagnostics = diagnostics != 0;
        if (tt_config_from_file(path, &m->config) == TT_STATUS_OK &&
            tt_frontend_new(m->config, &m->front_end) == TT_STATUS_OK && refresh(m)) {
            result = model_count++;
        } else {
            vpi_printf("tooltouch_scoreboard: %s\n", tt_last_error());
            tt_config_free(m->config);
            m->config = NULL;
        }
    }
    (void)name;
    end_call(&c, result);
    return 0;
}

static PLI_INT32 hash_calltf(PLI_BYTE8 *name) {
    Call c = begin_call();
    Model *m = model_arg(&c, name);
    uint64_t hash = 0;
    if (m != NULL) tt_config_measure_hash(m->config, &hash);
    int high = strcmp(name, "$tooltouch_config_hash_hi") == 0;
    end_call(&c, (int32_t)(uint32_t)(high ? hash >> 32 : hash));
    return 0;
}

static PLI_INT32 width_calltf(PLI_BYTE8 *name) {
    Call c = begin_call();
    Model *m = model_arg(&c, name);
    int unknown = 0;
    uint64_t index = value_of(&c, &unknown);
    uint32_t width = 0;
    if (m != NULL && !unknown && index < TT_OUTPUT_COUNT)
        tt_config_output_width(m->config, (uint32_t)index, &width);
    end_call(&c, (int32_t)width);
    return 0;
}

static PLI_INT32 clock_calltf(PLI_BYTE8 *name) {
    Call c = begin_call();
    Model *m = model_arg(&c, name);
    int pins_unknown = 0, rst_unknown = 0;
    uint64_t pins = value_of(&c, &pins_unknown);
    uint64_t rst = value_of(&c, &rst_unknown);
    int32_t result = -1;
    if (m != NULL && !pins_unknown && !rst_unknown && pins <= 0x3f) {
        TtStatus s = rst ? tt_frontend_reset(m->front_end) : tt_frontend_clock(m->front_end, (uint8_t)pins);
        if (s == TT_STATUS_OK && refresh(m)) {
            m->clocks++;
            result = 0;
        }
    }
    end_call(&c, result);
    return 0;
}

static PLI_INT32 compare_calltf(PLI_BYTE8 *name) {
    Call c = begin_call();
    Model *m = model_arg(&c, name);
    int addr_unknown = 0, rdata_unknown = 0, irq_unknown = 0;
    uint64_t addr = value_of(&c, &addr_unknown);
    uint64_t rdata = value_of(&c, &rdata_unknown);
    uint64_t irq = value_of(&c, &irq_unknown);
    int32_t first = -1;
    for (int i = 0; i < (int)TT_OUTPUT_COUNT; i++) {
        int unknown = 0;
        uint64_t got = value_of(&c, &unknown);
        if (first < 0 && m != NULL && (unknown || got != m->registers[i])) first = i;
    }
    if (c.count != 4 + (int)TT_OUTPUT_COUNT) {
        stop(name, "takes " COMPARE_ARGUMENTS);
    } else if (m != NULL) {
        if (first < 0 && (irq_unknown || irq != m->registers[IRQ_SOURCE])) first = TT_OUTPUT_COUNT;
        if (first < 0 && (addr_unknown || rdata_unknown || rdata != mcu_word(m, addr)))
            first = TT_OUTPUT_COUNT + 1;
        if (first >= 0) m->mismatches++;
    }
    end_call(&c, first);
    return 0;
}

static PLI_INT32 expected_calltf(PLI_BYTE8 *name) {
    Call c = begin_call();
    Model *m = model_arg(&c, name);
    int unknown = 0, addr_unknown = 0;
    uint64_t index = value_of(&c, &unknown);
    uint64_t addr = value_of(&c, &addr_unknown);
    uint64_t value = 0;
    if (m != NULL && !unknown) {
        if (index < TT_OUTPUT_COUNT) value = m->registers[index];
        else if (index == TT_OUTPUT_COUNT) value = m->registers[IRQ_SOURCE];
        else if (index == TT_OUTPUT_COUNT + 1 && !addr_unknown) value = mcu_word(m, addr);
    }
    end_call(&c, (int32_t)(uint32_t)value);
    return 0;
}

static PLI_INT32 end_of_simulation(p_cb_data data) {
    (void)data;
    for (int i = 0; i < model_count; i++) {
        Model *m = &models[i];
        if (m->mismatches == 0 && m->clocks > 0)
            vpi_printf("tooltouch_scoreboard OK %llu\n", (unsigned long long)m->clocks);
        else if (m->mismatches == 0)
            vpi_printf("tooltouch_scoreboard: no clock compared\n");
        else
            vpi_printf("tooltouch_scoreboard FAIL %llu mismatching cycles of %llu\n",
                       (unsigned long long)m->mismatches, (unsigned long long)m->clocks);
        tt_frontend_free(m->front_end);
        tt_config_free(m->config);
        m->front_end = NULL;
        m->config = NULL;
    }
    return 0;
}

static void register_function(const char *name, PLI_INT32 (*calltf)(PLI_BYTE8 *)) {
    s_vpi_systf_data tf;
    memset(&tf, 0, sizeof tf);
    tf.type = vpiSysFunc;
    tf.sysfunctype = vpiIntFunc;
    tf.tfname = (PLI_BYTE8 *)name;
    tf.calltf = calltf;
    tf.user_data = (PLI_BYTE8 *)name;
    vpi_register_systf(&tf);
}

static void register_all(void) {
    register_function("$tooltouch_open", open_calltf);
    register_function("$tooltouch_config_hash_lo", hash_calltf);
    register_function("$tooltouch_config_hash_hi", hash_calltf);
    register_function("$tooltouch_output_width", width_calltf);
    register_function("$tooltouch_clock", clock_calltf);
    register_function("$tooltouch_compare", compare_calltf);
    register_function("$tooltouch_expected", expected_calltf);
    s_cb_data cb;
    memset(&cb, 0, sizeof cb);
    cb.reason = cbEndOfSimulation;
    cb.cb_rtn = end_of_simulation;
    vpi_register_cb(&cb);
}

void (*vlog_startup_routines[])(void) = {register_all, NULL};
