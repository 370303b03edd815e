/* tooltouch_dpi.c: the DPI-C functions the SystemVerilog package `tooltouch_dpi`
 * (host/rtl-sim/sv/tooltouch_dpi.sv) imports, over the C ABI of tooltouch.h. Compile it with
 * the simulator's C compiler and link libtooltouch_abi.a, e.g. with Verilator:
 *
 *   verilator --binary ... host/rtl-sim/c/tooltouch_dpi.c -CFLAGS -I<repo>/host/abi/include \
 *             <target>/release/libtooltouch_abi.a -LDFLAGS "-lpthread -ldl -lm"
 *
 * Valid C and C++ (Verilator compiles it as C++; the functions have C linkage).
 * Plain C types only (no svdpi.h): chandle = void *, string = const char *, bit and
 * byte unsigned = unsigned char, int unsigned = uint32_t, longint unsigned = uint64_t.
 * One scoreboard handle holds the cycle-level model and its outputs after the last clock;
 * nothing is allocated after tooltouch_open. */
#include "tooltouch.h"
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Signal indexes of tooltouch_compare and tooltouch_expected: 0..TT_OUTPUT_COUNT-1 the
 * outputs (in tt_output_name's order), then these two. */
enum { SIGNAL_IRQ = TT_OUTPUT_COUNT, SIGNAL_MCU_RDATA = TT_OUTPUT_COUNT + 1 };
/* BEGIN GENERATED irq-source: hdl-gen's scoreboard_lists, cargo xtask bless-hdl */
/* irq is a copy of output 2, register_now (tt_frontend: `assign irq = register_now`). */
enum { IRQ_SOURCE = 2 };
/* END GENERATED irq-source */

typedef struct Scoreboard {
    TtConfig *config;
    TtFrontEnd *front_end;
    uint64_t registers[TT_OUTPUT_COUNT]; /* after the last clock */
    unsigned char diagnostics;
} Scoreboard;

static char message[768];

/* The message of the last failed tooltouch_open. */
const char *tooltouch_error(void) { return message; }

static int refresh(Scoreboard *sb) {
    return tt_frontend_registers(sb->front_end, sb->registers) == TT_STATUS_OK;
}

/* The MCU word at `addr` after the last clock (0 past the 4-bit address range). */
static uint32_t mcu_word(const Scoreboard *sb, uint32_t addr) {
    uint32_t word = 0;
    if (addr < TT_MCU_ADDRESSES) tt_frontend_mcu_read(sb->front_end, addr, sb->diagnostics != 0, &word);
    return word;
}

/* A scoreboard model for the configuration file at `config_path` (`tooltouch cosim config`
 * writes it), NULL on failure (tooltouch_error says why). `diagnostics`: the DUT was
 * generated with --mcu-diagnostics. */
void *tooltouch_open(const char *config_path, unsigned char diagnostics) {
    if (tt_abi_version() != TT_ABI_VERSION) {
        snprintf(message, sizeof message, "libtooltouch_abi has ABI version %u, tooltouch.h %u",
                 tt_abi_version(), TT_ABI_VERSION);
        return NULL;
    }
    Scoreboard *sb = (Scoreboard *)calloc(1, sizeof *sb);
    if (sb == NULL) {
        snprintf(message, sizeof message, "out of memory");
        return NULL;
    }
    sb->diagnostics = diagnostics;
    if (tt_config_from_file(config_path, &sb->config) != TT_STATUS_OK ||
        tt_frontend_new(sb->config, &sb->front_end) != TT_STATUS_OK || !refresh(sb)) {
        snprintf(message, sizeof message, "%s", tt_last_error());
        tt_config_free(sb->config);
        free(sb);
        return NULL;
    }
    return sb;
}

void tooltouch_close(void *handle) {
    Scoreboard *sb = (Scoreboard *)handle;
    if (sb == NULL) return;
    tt_frontend_free(sb->front_end);
    tt_config_free(sb->config);
    free(sb);
}

/* The measurement configuration's hash (the DUT's CONFIG_HASH must equal it). */
uint64_t tooltouch_config_hash(void *handle) {
    uint64_t hash = 0;
    if (handle != NULL) tt_config_measure_hash(((Scoreboard *)handle)->config, &hash);
    return hash;
}

/* The width of output `index` for this configuration (0 for a bad index). */
uint32_t tooltouch_output_width(void *handle, int32_t index) {
    uint32_t width = 0;
    if (handle != NULL && index >= 0)
        tt_config_output_width(((Scoreboard *)handle)->config, (uint32_t)index, &width);
    return width;
}

/* One rising edge with the pins sampled (bit 0 arm, 1 contact, 2 index, 3 FES, 4 scale A,
 * 5 scale B); with `rst`, the synchronous reset instead. 0 on success. */
int32_t tooltouch_clock(void *handle, unsigned char pins, unsigned char rst) {
    Scoreboard *sb = (Scoreboard *)handle;
    if (sb == NULL) return -1;
    TtStatus status = rst ? tt_frontend_reset(sb->front_end) : tt_frontend_clock(sb->front_end, pins);
    if (status != TT_STATUS_OK || !refresh(sb)) return -1;
    return 0;
}

/* The model's value of signal `index` (the outputs, SIGNAL_IRQ, SIGNAL_MCU_RDATA at
 * `mcu_addr`) after the last clock. */
uint64_t tooltouch_expected(void *handle, int32_t index, uint32_t mcu_addr) {
    Scoreboard *sb = (Scoreboard *)handle;
    if (sb == NULL || index < 0) return 0;
    if (index < (int32_t)TT_OUTPUT_COUNT) return sb->registers[index];
    if (index == SIGNAL_IRQ) return sb->registers[IRQ_SOURCE];
    if (index == SIGNAL_MCU_RDATA) return mcu_word(sb, mcu_addr);
    return 0;
}

/* Compares the DUT's outputs after the last clock with the model's: the index of the
 * first differing signal (as tooltouch_expected), or -1 when all agree. `unknown` has bit
 * i set when signal i holds an X or Z bit (always a mismatch). */
/* BEGIN GENERATED compare-signature: hdl-gen's scoreboard_lists, cargo xtask bless-hdl */
int32_t tooltouch_compare(void *handle, uint32_t unknown, uint32_t mcu_addr, uint32_t mcu_rdata,
                          unsigned char irq, uint64_t armed, uint64_t contact,
                          uint64_t register_now, uint64_t decision_position, uint64_t first_contact,
                          uint64_t first_contact_position, uint64_t position, uint64_t scale_errors,
                          uint64_t count, uint64_t last_window_count, uint64_t charge,
                          uint64_t density_armed, uint64_t density_fired, uint64_t revolutions,
                          uint64_t pulses, uint64_t confirmed, uint64_t faults) {
/* END GENERATED compare-signature */
    Scoreboard *sb = (Scoreboard *)handle;
    if (sb == NULL) return 0;
    /* BEGIN GENERATED compare-outputs: hdl-gen's scoreboard_lists, cargo xtask bless-hdl */
    const uint64_t got[TT_OUTPUT_COUNT] = {armed, contact, register_now, decision_position,
                                           first_contact, first_contact_position, position,
                                           scale_errors, count, last_window_count, charge,
                                           density_armed, density_fired, revolutions, pulses,
                                           confirmed, faults};
    /* END GENERATED compare-outputs */
    for (int32_t i = 0; i < (int32_t)TT_OUTPUT_COUNT; i++)
        if ((unknown >> i & 1u) || got[i] != sb->registers[i]) return i;
    if ((unknown >> SIGNAL_IRQ & 1u) || irq != sb->registers[IRQ_SOURCE]) return SIGNAL_IRQ;
    if ((unknown >> SIGNAL_MCU_RDATA & 1u) || mcu_addr >= TT_MCU_ADDRESSES ||
        mcu_rdata != mcu_word(sb, mcu_addr))
        return SIGNAL_MCU_RDATA;
    return -1;
}

#ifdef __cplusplus
}
#endif
