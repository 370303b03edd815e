// tooltouch_dpi: the golden model's DPI-C imports (host/rtl-sim/c/tooltouch_dpi.c over the C
// ABI of libtooltouch_abi). tooltouch_scoreboard uses them; a UVM predictor can too.
//
// BEGIN GENERATED signal-indexes: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
// Signal indexes (tooltouch_compare, tooltouch_expected): 0..16 the outputs in the order of
// the ports (armed contact register_now decision_position first_contact
// first_contact_position position scale_errors count last_window_count charge density_armed
// density_fired revolutions pulses confirmed faults), 17 irq, 18 mcu_rdata.
// END GENERATED signal-indexes
`timescale 1ns / 1ns

package tooltouch_dpi;
    // A model for the configuration file `tooltouch cosim config` writes; null on failure,
    // then tooltouch_error() says why. `diagnostics`: the DUT has --mcu-diagnostics.
    import "DPI-C" function chandle tooltouch_open(input string config_path, input bit diagnostics);
    import "DPI-C" function string tooltouch_error();
    import "DPI-C" function void tooltouch_close(input chandle handle);
    // The measurement configuration's hash: the DUT's CONFIG_HASH must equal it.
    import "DPI-C" function longint unsigned tooltouch_config_hash(input chandle handle);
    // Width of output `index` for the configuration, bits.
    import "DPI-C" function int unsigned tooltouch_output_width(input chandle handle, input int index);
    // One rising edge with the pins {scale_b, scale_a, fes, index, contact, arm}, or the
    // synchronous reset when `rst`; 0 on success.
    import "DPI-C" function int tooltouch_clock(input chandle handle, input byte unsigned pins, input bit rst);
    // The model's value of signal `index` after the last edge (mcu_rdata at `mcu_addr`).
    import "DPI-C" function longint unsigned tooltouch_expected(input chandle handle, input int index,
                                                               input int unsigned mcu_addr);
    // The first signal that differs from the model after the last edge, -1 if none;
    // `unknown` bit i: signal i holds X or Z.
    import "DPI-C" function int tooltouch_compare(
        input chandle handle, input int unsigned unknown, input int unsigned mcu_addr,
        input int unsigned mcu_rdata, input bit irq,
        // BEGIN GENERATED compare-outputs: hdl-gen's scoreboard_lists, cargo xtask bless-hdl
        input longint unsigned armed, input longint unsigned contact,
        input longint unsigned register_now, input longint unsigned decision_position,
        input longint unsigned first_contact, input longint unsigned first_contact_position,
        input longint unsigned position, input longint unsigned scale_errors,
        input longint unsigned count, input longint unsigned last_window_count,
        input longint unsigned charge, input longint unsigned density_armed,
        input longint unsigned density_fired, input longint unsigned revolutions,
        input longint unsigned pulses, input longint unsigned confirmed,
        input longint unsigned faults);
        // END GENERATED compare-outputs
endpackage
