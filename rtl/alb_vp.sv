// alb_vp — the Albatros video processor, the reference RTL of the units of
// docs/microarchitecture.md, held cycle by cycle against the cycle model
// (docs/cosim.md).  The profile's fields are the parameters (rtl/profile-params.sh
// turns `albatros profiles NAME` into them); sizes the profile does not bound
// are parameters with defaults, and exceeding one is a reported error.
//
//   FIFO -> input parser -> edge store -> subdivision engine -> fill queue
//        -> fill unit -> depth/shade pipeline -> frame store (external) -> frame CRC
//
// Ports: the FIFO's write port (the GP output stage is outside: its timing is
// the bench's), the external frame-store memory, and for a bench the events
// of docs/cosim.md as strobes with their fields, valid in the cycle they
// happen (sampled at the rising edge that ends it), and an error output.
`include "alb_defs.svh"

module alb_vp #(
    // the profile (docs/profiles.md)
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
    // sizes the profile does not bound (rtl/README.md)
    parameter int MAX_EDGES = 64,       // edges a face may have (the word format's limit)
    parameter int TEX_WORDS = 65536,    // texture memory, texels
    parameter int TEX_IDS = 256,        // texture ids the parser's table holds
    parameter int FRAME_QUEUE = 16,     // FRAME register sets (profile frame_queue)
    parameter int SCAN_PIXELS = 1,      // pixels the output stage resolves a cycle
    parameter int TAG_BITS = 8,         // frame tag of a stored depth (alb_frame_store)
    parameter int ZR_REG = 0,           // 1: depth reads answered in the next cycle (block RAM)
    // the shading units built (1) or left out (0, what needs one refused: E_UNIT)
    parameter int SHADE_UNIT = 1,       // Gouraud intensity (a FACE's S flag)
    parameter int TEX_UNIT = 1,         // texture table, memory and addressing (TEXTURE, T)
    parameter int FOG_UNIT = 1,         // fog distance, visibility, blend (a FRAME's fog on)
    // derived
    parameter int LW = $clog2(WIDTH) + AA,
    parameter int LH = $clog2(HEIGHT) + AA,
    parameter int AW = 1 + LW + LH,
    parameter int CWD = 3 * COLOUR_BITS + 40,
    parameter int ZW = TAG_BITS + DEPTH_BITS
) (
    input  logic                            clk,
    input  logic                            rst,
    // the FIFO's write port
    input  logic                            in_valid,
    input  logic [31:0]                     in_data,
    output logic                            in_full,
    // the external frame-store memory
    output logic [FILL_RATE*AW-1:0]         mem_zr_addr,
    input  logic [FILL_RATE*ZW-1:0]         mem_zr_data,
    output logic [FILL_RATE-1:0]            mem_zw_en,
    output logic [FILL_RATE*AW-1:0]         mem_zw_addr,
    output logic [FILL_RATE*ZW-1:0]         mem_zw_data,
    output logic [FILL_RATE-1:0]            mem_cw_en,
    output logic [FILL_RATE*AW-1:0]         mem_cw_addr,
    output logic [FILL_RATE*CWD-1:0]        mem_cw_data,
    output logic                            mem_sc_en,
    output logic [AW-1:0]                   mem_sc_addr,
    input  logic [SCAN_PIXELS*(1<<(2*AA))*(ZW-DEPTH_BITS+1+3*COLOUR_BITS)-1:0] mem_sc_data,
    // events (docs/cosim.md)
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
    // a frame retired while the previous one was still being scanned out:
    // that frame's CRC is lost (the scan-out is untimed in the model)
    output logic                            ev_scan_overrun,
    // a FRAME_END taken this cycle (not a cosim event): its face count is
    // ev_pop_word[23:0] (a board's RESULT record, rtl/fpga/)
    output logic                            ev_frame_end,
    // a malformed stream or an exceeded size: sticky, the first error's code
    // (rtl/alb_defs.svh) and the word it was found at
    output logic                            error,
    output logic [7:0]                      error_code,
    output logic [31:0]                     error_word
);
    localparam int P = LW > LH ? LW : LH;
    // edge units' registers: |h| < 2^(F + 6 + P) (docs/vp.md §2), with the sign
    localparam int EW = EDGE_FRAC_BITS + P + 7;
    localparam int TA = $clog2(TEX_WORDS);

    // ---- FIFO ----
    logic        fifo_empty, fifo_overflow, pop;
    logic [31:0] fifo_head;
    alb_fifo #(.DEPTH(FIFO_DEPTH)) u_fifo (
        .clk, .rst, .push(in_valid), .push_data(in_data), .full(in_full), .pop,
        .head(fifo_head), .empty(fifo_empty), .overflow(fifo_overflow));

    // ---- parser ----
    logic                ew_en, fc_en, fr_en, fr_fog, end_taken, ended, tw_en, parse_err;
    logic [5:0]          ew_idx;
    logic [EW-1:0]       ew_c, ew_da, ew_db;
    logic [`SETUP_W-1:0] fc_setup;
    logic [6:0]          fc_edges;
    logic [15:0]         fc_frame, frames_taken, frame_open;
    logic [23:0]         fr_number;
    logic [3*COLOUR_BITS-1:0] fr_bg, fr_fog_rgb;
    logic [31:0]         fr_fog_near, fr_fog_far, pop_index, parse_err_word;
    logic [TA-1:0]       tw_addr;
    logic [23:0]         tw_data;
    logic [7:0]          parse_err_code;
    logic                slot_free, drained;
    // frame_queue register sets: the open frame's and the waiting ones
    wire frame_room = 16'(frames_taken - frame_open) < 16'(FRAME_QUEUE);
    alb_parser #(.F(EDGE_FRAC_BITS), .CB(COEF_BITS), .COLB(COLOUR_BITS), .LW(LW), .LH(LH),
                 .EW(EW), .MAX_EDGES(MAX_EDGES), .TEX_WORDS(TEX_WORDS), .TEX_IDS(TEX_IDS),
                 .FRAME_FACES(FRAME_FACES), .SHADE_UNIT(SHADE_UNIT), .TEX_UNIT(TEX_UNIT),
                 .FOG_UNIT(FOG_UNIT)) u_parser (
        .clk, .rst, .fifo_empty, .fifo_head, .pop, .slot_free, .drained, .frame_room,
        .frames_taken,
        .ew_en, .ew_idx, .ew_c, .ew_da, .ew_db, .fc_en, .fc_setup, .fc_edges, .fc_frame,
        .fr_en, .fr_number, .fr_bg, .fr_fog, .fr_fog_rgb, .fr_fog_near, .fr_fog_far,
        .end_taken, .ended, .tw_en, .tw_addr, .tw_data, .pop_index,
        .err(parse_err), .err_code(parse_err_code), .err_word(parse_err_word));

    // ---- edge store ----
    logic                head_valid, any_loaded, waiting_next, face_done;
    logic [15:0]         head_frame;
    logic [`SETUP_W-1:0] head_setup;
    logic [6:0]          head_edges;
    logic [7:0]          head_slot, load_slot;
    logic [EDGE_UNITS*6-1:0]  rd_next;
    logic [EDGE_UNITS*EW-1:0] rd_c, rd_da, rd_db;
    alb_edge_store #(.FACE_SLOTS(FACE_SLOTS), .MAX_EDGES(MAX_EDGES), .EW(EW),
                     .LANES(EDGE_UNITS)) u_edge_store (
        .clk, .rst, .ew_en, .ew_idx, .ew_c, .ew_da, .ew_db, .fc_en, .fc_setup, .fc_edges,
        .fc_frame, .slot_free, .load_slot, .head_valid, .head_frame, .head_setup, .head_edges,
        .head_slot, .rd_next, .rd_c, .rd_da, .rd_db, .face_done, .any_loaded, .frame_open,
        .waiting_next);

    // ---- engine ----
    logic               q_full, enq, engine_busy, engine_busy_next;
    logic [`CELL_W-1:0] enq_cell;
    alb_engine #(.LW(LW), .LH(LH), .EW(EW), .MAX_EDGES(MAX_EDGES), .E(EDGE_UNITS)) u_engine (
        .clk, .rst, .head_valid, .head_frame, .head_edges, .head_id(head_setup[`SU_ID +: 32]),
        .head_slot, .frame_open, .rd_next, .rd_c, .rd_da, .rd_db, .face_done, .q_full, .enq,
        .enq_cell, .busy(engine_busy), .busy_next(engine_busy_next), .ev_start, .ev_cell,
        .ev_cell_result, .ev_cell_edges, .ev_cell_cell, .ev_end, .ev_face(ev_engine_face),
        .ev_slot(ev_engine_slot));

    // ---- fill queue and fill unit ----
    logic                q_empty, q_empty_next, deq;
    logic [`CELL_W-1:0]  q_cell;
    logic [`SETUP_W-1:0] q_setup;
    logic [10:0]         q_count;
    alb_fill_queue #(.DEPTH(FILL_QUEUE)) u_fill_queue (
        .clk, .rst, .enq, .enq_cell, .enq_setup(head_setup), .full(q_full), .deq,
        .head_cell(q_cell), .head_setup(q_setup), .empty(q_empty), .empty_next(q_empty_next),
        .count_out(q_count));

    logic [FILL_RATE-1:0]    lane_v;
    logic [FILL_RATE*16-1:0] lane_x, lane_y;
    logic [`SETUP_W-1:0]     fill_setup;
    logic [4:0]              fill_level;
    logic                    fill_busy, fill_busy_next;
    alb_fill #(.RATE(FILL_RATE), .LW(LW), .LH(LH)) u_fill (
        .clk, .rst, .q_empty, .q_cell, .q_setup, .deq, .lane_v, .lane_x, .lane_y,
        .setup(fill_setup), .level(fill_level), .busy(fill_busy), .busy_next(fill_busy_next),
        .ev_fill, .ev_cell(ev_fill_cell));
    assign ev_fill_face = fill_setup[`SU_ID +: 32];

    // ---- depth/shade pipeline ----
    logic                         fog_on, pipe_busy, pipe_busy_before_last;
    logic [3*COLOUR_BITS-1:0]     fog_rgb;
    logic [31:0]                  fog_near, fog_far;
    logic [FILL_RATE*DEPTH_BITS-1:0] zr_data, zw_data;
    logic [FILL_RATE*16-1:0]      zw_x, zw_y;
    logic [FILL_RATE-1:0]         zw_en;
    alb_pipe #(.RATE(FILL_RATE), .LW(LW), .LH(LH), .CB(COEF_BITS), .DB(DEPTH_BITS),
               .COLB(COLOUR_BITS), .RB(RECIP_BITS), .FI(SHADE_FRAC_BITS),
               .DIV_LAT(DIVIDER_LATENCY), .SHADE_LAT(SHADE_LATENCY), .TEX_WORDS(TEX_WORDS),
               .ZR_REG(ZR_REG), .SHADE_UNIT(SHADE_UNIT), .TEX_UNIT(TEX_UNIT),
               .FOG_UNIT(FOG_UNIT)) u_pipe (
        .clk, .rst, .lane_v, .lane_x, .lane_y, .setup(fill_setup), .level(fill_level), .fog_on,
        .fog_rgb, .fog_near, .fog_far, .zr_data, .zw_en, .zw_x, .zw_y, .zw_data, .cw_en(ev_write),
        .cw_x(ev_write_x), .cw_y(ev_write_y), .cw_depth(ev_write_depth), .cw_rgb(ev_write_rgb),
        .cw_face(ev_write_face), .cw_level(ev_write_level), .tw_en, .tw_addr, .tw_data,
        .busy(pipe_busy), .busy_before_last(pipe_busy_before_last));

    // ---- frame store and frame control ----
    logic                     retire, display_store, frames_idle, err_frames;
    logic [TAG_BITS-1:0]      display_tag;
    logic [3*COLOUR_BITS-1:0] retire_bg;
    logic [23:0]              retire_number;
    logic                     sc_en, sc_store;
    logic [LW+LH-2*AA-1:0]    sc_pixel;
    alb_frame_store #(.RATE(FILL_RATE), .LW(LW), .LH(LH), .AA(AA), .DB(DEPTH_BITS),
                      .COLB(COLOUR_BITS), .TAG_BITS(TAG_BITS),
                      .FRAME_QUEUE(FRAME_QUEUE)) u_frame_store (
        .clk, .rst, .fr_en, .fr_number, .fr_bg, .fr_fog, .fr_fog_rgb, .fr_fog_near, .fr_fog_far,
        .end_taken, .frames_taken, .frame_open, .frames_idle, .engine_busy_next,
        .queue_empty_next(q_empty_next), .fill_busy_next, .pipe_busy_before_last, .waiting_next,
        .fog_on, .fog_rgb, .fog_near, .fog_far, .z_x(lane_x), .z_y(lane_y), .zr_data, .zw_en,
        .zw_x, .zw_y, .zw_data, .cw_en(ev_write), .cw_x(ev_write_x), .cw_y(ev_write_y), .cw_rgb(ev_write_rgb),
        .cw_face(ev_write_face), .cw_level(ev_write_level), .retire, .display_store, .display_tag,
        .retire_bg,
        .retire_number, .sc_en, .sc_pixel, .sc_store, .mem_zr_addr, .mem_zr_data, .mem_zw_en,
        .mem_zw_addr, .mem_zw_data, .mem_cw_en, .mem_cw_addr, .mem_cw_data, .mem_sc_en,
        .mem_sc_addr, .cycle, .ev_frame, .ev_frame_number, .ev_frame_cycles, .err_frames);

    // ---- output stage: frame CRC ----
    logic crc_busy, err_alias;
    alb_frame_crc #(.LW(LW), .LH(LH), .AA(AA), .COLB(COLOUR_BITS), .TAG_BITS(TAG_BITS),
                    .PIXELS(SCAN_PIXELS)) u_frame_crc (
        .clk, .rst, .start(retire), .start_store(display_store), .start_bg(retire_bg),
        .start_number(retire_number), .start_tag(display_tag), .sc_en, .sc_pixel, .sc_store,
        .sc_data(mem_sc_data), .ev_crc, .ev_crc_number, .ev_crc_value, .busy(crc_busy),
        .err_overrun(ev_scan_overrun), .err_alias);

    // Texture and END wait until everything earlier has retired (state at the
    // start of the cycle: docs/microarchitecture.md, "VP input parser").
    assign drained = !engine_busy && !any_loaded && q_empty && !fill_busy && !pipe_busy &&
                     frames_idle;

    // ---- events ----
    assign ev_pop = pop;
    assign ev_frame_end = end_taken;
    assign ev_pop_index = pop_index;
    assign ev_pop_word = fifo_head;
    assign ev_load = fc_en;
    assign ev_load_face = fc_setup[`SU_ID +: 32];
    assign ev_load_slot = load_slot;
    assign ev_load_edges = fc_edges;

    // ---- errors: the first one is kept ----
    wire       any_err = parse_err || fifo_overflow || err_frames || err_alias;
    wire [7:0] code_now = parse_err ? parse_err_code : fifo_overflow ? `E_OVERFLOW
                        : err_frames ? `E_FRAMES_AHEAD : `E_TAG_ALIAS;
    always_ff @(posedge clk) begin
        if (rst) begin
            error <= 1'b0;
            error_code <= `E_NONE;
            error_word <= '0;
        end else if (any_err && !error) begin
            error <= 1'b1;
            error_code <= code_now;
            error_word <= parse_err ? parse_err_word : pop_index;
        end
    end

    wire unused_top = ended | crc_busy | (|q_count) | (|head_setup[`SETUP_W-1:32]);
endmodule
