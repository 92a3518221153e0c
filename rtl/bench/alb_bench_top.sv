// alb_bench_top — the VP and its external frame-store memory, as the
// bench of rtl/bench/cosim.cpp drives them under Verilator: the FIFO's write port in,
// the events out.  The parameters the bench needs to decode the events are
// also outputs (p_*), so one C++ bench serves every parameter set.
`include "alb_defs.svh"

module alb_bench_top #(
    parameter int WIDTH = 32,
    parameter int HEIGHT = 32,
    parameter int AA = 0,
    parameter int EDGE_FRAC_BITS = 10,
    parameter int COEF_BITS = 24,
    parameter int DEPTH_BITS = 24,
    parameter int COLOUR_BITS = 8,
    parameter int RECIP_BITS = 16,
    parameter int SHADE_FRAC_BITS = 12,
    parameter int FIFO_DEPTH = 512,
    parameter int FACE_SLOTS = 2,
    parameter int EDGE_UNITS = 8,
    parameter int FILL_RATE = 4,
    parameter int FILL_QUEUE = 4,
    parameter int DIVIDER_LATENCY = 8,
    parameter int SHADE_LATENCY = 4,
    parameter int FRAME_FACES = 16777215,
    parameter int MAX_EDGES = 64,
    parameter int TEX_WORDS = 65536,
    parameter int FRAME_QUEUE = 16,
    parameter int SCAN_PIXELS = 1,
    parameter int TAG_BITS = 8,
    parameter int ZR_REG = 0,
    parameter int TEX_IDS = 256,
    parameter int SHADE_UNIT = 1,
    parameter int TEX_UNIT = 1,
    parameter int FOG_UNIT = 1
) (
    input  logic                            clk,
    input  logic                            rst,
    input  logic                            in_valid,
    input  logic [31:0]                     in_data,
    output logic                            in_full,
    output logic [31:0]                     p_width,
    output logic [31:0]                     p_height,
    output logic [31:0]                     p_aa,
    output logic [31:0]                     p_fill_rate,
    output logic [31:0]                     p_depth_bits,
    output logic [31:0]                     p_colour_bits,
    output logic [31:0]                     p_scan_pixels,
    output logic [31:0]                     p_tag_bits,
    // the retiring frame's background (frame-store units), for a dump
    output logic [3*COLOUR_BITS-1:0]        dbg_retire_bg,
    output logic [63:0]                     cycle,
    output logic                            ev_pop,
    output logic [31:0]                     ev_pop_index,
    output logic [31:0]                     ev_pop_word,
    output logic                            ev_load,
    output logic [31:0]                     ev_load_face,
    output logic [7:0]                      ev_load_slot,
    output logic [6:0]                      ev_load_edges,
    output logic                            ev_start,
    output logic                            ev_cell,
    output logic [2:0]                      ev_cell_result,
    output logic [6:0]                      ev_cell_edges,
    output logic [`CELL_W-1:0]              ev_cell_cell,
    output logic                            ev_end,
    output logic [31:0]                     ev_engine_face,
    output logic [7:0]                      ev_engine_slot,
    output logic                            ev_fill,
    output logic [31:0]                     ev_fill_face,
    output logic [`CELL_W-1:0]              ev_fill_cell,
    output logic [FILL_RATE-1:0]            ev_write,
    output logic [FILL_RATE*16-1:0]         ev_write_x,
    output logic [FILL_RATE*16-1:0]         ev_write_y,
    output logic [FILL_RATE*DEPTH_BITS-1:0] ev_write_depth,
    output logic [FILL_RATE*3*COLOUR_BITS-1:0] ev_write_rgb,
    output logic [31:0]                     ev_write_face,
    output logic [7:0]                      ev_write_level,
    output logic                            ev_frame,
    output logic [23:0]                     ev_frame_number,
    output logic [63:0]                     ev_frame_cycles,
    output logic                            ev_crc,
    output logic [23:0]                     ev_crc_number,
    output logic [31:0]                     ev_crc_value,
    output logic                            ev_scan_overrun,
    output logic                            error,
    output logic [7:0]                      error_code,
    output logic [31:0]                     error_word
);
    localparam int LW = $clog2(WIDTH) + AA;
    localparam int LH = $clog2(HEIGHT) + AA;
    localparam int AW = 1 + LW + LH;
    localparam int CWD = 3 * COLOUR_BITS + 40;
    localparam int ZW = TAG_BITS + DEPTH_BITS;
    localparam int SCW = SCAN_PIXELS * (1 << (2 * AA)) * (TAG_BITS + 1 + 3 * COLOUR_BITS);

    assign p_width = WIDTH;
    assign p_height = HEIGHT;
    assign p_aa = AA;
    assign p_fill_rate = FILL_RATE;
    assign p_depth_bits = DEPTH_BITS;
    assign p_colour_bits = COLOUR_BITS;
    assign p_scan_pixels = SCAN_PIXELS;
    assign p_tag_bits = TAG_BITS;
    assign dbg_retire_bg = u_vp.retire_bg;

    logic [FILL_RATE*AW-1:0]         zr_addr, zw_addr, cw_addr;
    logic [FILL_RATE*ZW-1:0]         zr_data, zw_data;
    logic [FILL_RATE-1:0]            zw_en, cw_en;
    logic [FILL_RATE*CWD-1:0]        cw_data;
    logic                            sc_en;
    logic [AW-1:0]                   sc_addr;
    logic [SCW-1:0]                  sc_data;

    alb_vp #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .AA(AA), .EDGE_FRAC_BITS(EDGE_FRAC_BITS),
             .COEF_BITS(COEF_BITS), .DEPTH_BITS(DEPTH_BITS), .COLOUR_BITS(COLOUR_BITS),
             .RECIP_BITS(RECIP_BITS), .SHADE_FRAC_BITS(SHADE_FRAC_BITS), .FIFO_DEPTH(FIFO_DEPTH),
             .FACE_SLOTS(FACE_SLOTS), .EDGE_UNITS(EDGE_UNITS), .FILL_RATE(FILL_RATE),
             .FILL_QUEUE(FILL_QUEUE), .DIVIDER_LATENCY(DIVIDER_LATENCY),
             .SHADE_LATENCY(SHADE_LATENCY), .FRAME_FACES(FRAME_FACES), .MAX_EDGES(MAX_EDGES),
             .TEX_WORDS(TEX_WORDS), .FRAME_QUEUE(FRAME_QUEUE), .SCAN_PIXELS(SCAN_PIXELS),
             .TAG_BITS(TAG_BITS), .ZR_REG(ZR_REG), .TEX_IDS(TEX_IDS), .SHADE_UNIT(SHADE_UNIT),
             .TEX_UNIT(TEX_UNIT), .FOG_UNIT(FOG_UNIT)) u_vp (
        .clk, .rst, .in_valid, .in_data, .in_full,
        .mem_zr_addr(zr_addr), .mem_zr_data(zr_data), .mem_zw_en(zw_en), .mem_zw_addr(zw_addr),
        .mem_zw_data(zw_data), .mem_cw_en(cw_en), .mem_cw_addr(cw_addr), .mem_cw_data(cw_data),
        .mem_sc_en(sc_en), .mem_sc_addr(sc_addr), .mem_sc_data(sc_data),
        .cycle, .ev_pop, .ev_pop_index, .ev_pop_word, .ev_load, .ev_load_face, .ev_load_slot,
        .ev_load_edges, .ev_start, .ev_cell, .ev_cell_result, .ev_cell_edges, .ev_cell_cell,
        .ev_end, .ev_engine_face, .ev_engine_slot, .ev_fill, .ev_fill_face, .ev_fill_cell,
        .ev_write, .ev_write_x, .ev_write_y, .ev_write_depth, .ev_write_rgb, .ev_write_face,
        .ev_write_level, .ev_frame, .ev_frame_number, .ev_frame_cycles, .ev_crc, .ev_crc_number,
        .ev_crc_value, .ev_scan_overrun, .ev_frame_end(), .error, .error_code, .error_word);

    alb_frame_mem #(.RATE(FILL_RATE), .LW(LW), .LH(LH), .AA(AA), .DB(DEPTH_BITS),
                    .COLB(COLOUR_BITS), .SCAN_PIXELS(SCAN_PIXELS), .TAG_BITS(TAG_BITS),
                    .ZR_REG(ZR_REG)) u_mem (
        .clk, .zr_addr, .zr_data, .zw_en, .zw_addr, .zw_data, .cw_en, .cw_addr, .cw_data,
        .sc_en, .sc_addr, .sc_data);
endmodule
