// alb_frame_store — the frame store port and the frame control
// (docs/microarchitecture.md, "Frame store" and "Frames").  Two sample stores
// in an external memory, one drawn, one displayed; the stores swap in the
// cycle a frame retires — the latest of its FRAME_END's pop, its last face's
// end and its last sample's write — and the next frame's first face may start
// in the following cycle.  The FRAME registers (background, fog) of frames
// taken while an earlier one drains wait in a queue of FRAME_QUEUE.
//
// The memory: a sample's address is {store, pixel row, pixel column,
// sub-sample row, sub-sample column} (a pixel's 4^aa samples adjacent, so the
// output stage reads a pixel at once).  Depth ports: per lane a read answered
// in the same cycle (asynchronous SRAM) and a write at the end of the cycle,
// for the pipeline's first stage (with the pipeline's ZR_REG, the read is
// answered in the next cycle and the write is the second stage's, at the
// place the pipeline gives); colour ports (R G B, face id, level) for its
// last stage.  A depth word carries the TAG_BITS low bits of the number
// of the frame that wrote it: a depth whose tag is not the drawing frame's
// reads as 0, "no surface, the frame's background" (docs/vp.md §4: nothing is
// written with depth 0).  So the drawing store needs no clear pass before a
// frame: the frame CRC unit clears the display store's depths as it scans
// them out, and where a short frame cut that scan off, the stale depths
// carry an older frame's tag (alb_frame_crc counts such scans, so tags never
// alias).
`include "alb_defs.svh"

module alb_frame_store #(
    parameter int RATE = 4,
    parameter int LW = 5,
    parameter int LH = 5,
    parameter int AA = 0,
    parameter int DB = 24,
    parameter int COLB = 8,
    parameter int TAG_BITS = 8,
    parameter int FRAME_QUEUE = 16
) (
    input  logic                     clk,
    input  logic                     rst,
    // FRAME and FRAME_END packets taken (alb_parser)
    input  logic                     fr_en,
    input  logic [23:0]              fr_number,
    input  logic [3*COLB-1:0]        fr_bg,
    input  logic                     fr_fog,
    input  logic [3*COLB-1:0]        fr_fog_rgb,
    input  logic [31:0]              fr_fog_near,
    input  logic [31:0]              fr_fog_far,
    input  logic                     end_taken,
    output logic [15:0]              frames_taken,
    output logic [15:0]              frame_open,     // the frame whose faces may run
    output logic                     frames_idle,    // every frame taken has retired
    // the state of the units after this cycle, for the retirement
    input  logic                     engine_busy_next,
    input  logic                     queue_empty_next,
    input  logic                     fill_busy_next,
    input  logic                     pipe_busy_before_last,
    input  logic                     waiting_next,   // a face of the open frame not started
    // the drawing frame's fog registers (alb_pipe)
    output logic                     fog_on,
    output logic [3*COLB-1:0]        fog_rgb,
    output logic [31:0]              fog_near,
    output logic [31:0]              fog_far,
    // the pipeline's lanes: first stage (depth) and last stage (colour)
    input  logic [RATE*16-1:0]       z_x,
    input  logic [RATE*16-1:0]       z_y,
    output logic [RATE*DB-1:0]       zr_data,
    input  logic [RATE-1:0]          zw_en,
    input  logic [RATE*16-1:0]       zw_x,
    input  logic [RATE*16-1:0]       zw_y,
    input  logic [RATE*DB-1:0]       zw_data,
    input  logic [RATE-1:0]          cw_en,
    input  logic [RATE*16-1:0]       cw_x,
    input  logic [RATE*16-1:0]       cw_y,
    input  logic [RATE*3*COLB-1:0]   cw_rgb,
    input  logic [31:0]              cw_face,
    input  logic [7:0]               cw_level,
    // the output stage (alb_frame_crc): scan-out of the display store
    output logic                     retire,
    output logic                     display_store,
    output logic [TAG_BITS-1:0]      display_tag,
    output logic [3*COLB-1:0]        retire_bg,
    output logic [23:0]              retire_number,
    input  logic                     sc_en,
    input  logic [LW+LH-2*AA-1:0]    sc_pixel,
    input  logic                     sc_store,
    // the external memory
    output logic [RATE*(1+LW+LH)-1:0] mem_zr_addr,
    input  logic [RATE*(TAG_BITS+DB)-1:0] mem_zr_data,
    output logic [RATE-1:0]          mem_zw_en,
    output logic [RATE*(1+LW+LH)-1:0] mem_zw_addr,
    output logic [RATE*(TAG_BITS+DB)-1:0] mem_zw_data,
    output logic [RATE-1:0]          mem_cw_en,
    output logic [RATE*(1+LW+LH)-1:0] mem_cw_addr,
    output logic [RATE*(3*COLB+40)-1:0] mem_cw_data,
    output logic                     mem_sc_en,
    output logic [LW+LH:0]           mem_sc_addr,
    // the cycle and the frame event (docs/cosim.md)
    output logic [63:0]              cycle,
    output logic                     ev_frame,
    output logic [23:0]              ev_frame_number,
    output logic [63:0]              ev_frame_cycles,
    output logic                     err_frames         // FRAME_QUEUE frames waiting, one more taken
);
    localparam int AW = 1 + LW + LH;
    localparam int ZW = TAG_BITS + DB;
    localparam int FQW = FRAME_QUEUE > 1 ? $clog2(FRAME_QUEUE) : 1;
    localparam int FRW = 24 + 6 * COLB + 1 + 64;

    // a sample's address in the store being drawn
    localparam logic [15:0] SUB = 16'((1 << AA) - 1);
    function automatic [AW-1:0] addr_of(input st, input [15:0] x, input [15:0] y);
        logic [31:0] xx, yy, pixel, sub;
        xx = 32'(x);
        yy = 32'(y);
        pixel = ((yy >> AA) << (LW - AA)) | (xx >> AA);
        sub = ((yy & 32'(SUB)) << AA) | (xx & 32'(SUB));
        addr_of = {st, (AW - 1)'((pixel << (2 * AA)) | sub)};
    endfunction

    logic          draw_store;
    // cycles since the previous retirement (the first frame's: since the
    // cycle before reset), counted rather than a difference of two 64-bit
    // registers: where nothing reads `cycle` (an FPGA board) it is gone
    logic [63:0]   since_retire;
    logic [15:0]   ends_taken;
    logic [FRW-1:0] fq [0:FRAME_QUEUE-1];
    logic [FQW-1:0] fq_head, fq_tail;
    logic [FQW:0]  fq_count;

    function automatic [FQW-1:0] inc(input [FQW-1:0] p);
        inc = p == FQW'(FRAME_QUEUE - 1) ? '0 : p + 1'b1;
    endfunction

    wire [FRW-1:0] head = fq[fq_head];
    wire [23:0]    head_number = head[FRW-1 -: 24];
    wire [3*COLB-1:0] head_bg = head[FRW-25 -: 3*COLB];
    assign fog_on = head[FRW-25-3*COLB];
    assign fog_rgb = head[FRW-26-3*COLB -: 3*COLB];
    assign fog_near = head[63:32];
    assign fog_far = head[31:0];

    // Retirement (docs/microarchitecture.md, "Frames"): the open frame's
    // FRAME_END taken, no face of it in the engine or waiting, the queue and
    // fill unit empty, and its last sample written by the end of this cycle.
    wire [15:0] ends_next = ends_taken + 16'(end_taken);
    assign retire = ends_next != frame_open && !engine_busy_next && queue_empty_next &&
                    !fill_busy_next && !pipe_busy_before_last && !waiting_next;
    assign frames_idle = frames_taken == frame_open && ends_taken == frame_open;
    assign display_store = draw_store;      // the store that becomes the display store
    assign retire_bg = head_bg;
    assign retire_number = head_number;
    assign ev_frame = retire;
    assign ev_frame_number = head_number;
    assign ev_frame_cycles = since_retire;
    assign err_frames = fr_en && fq_count == (FQW + 1)'(FRAME_QUEUE) && !retire;

    wire [TAG_BITS-1:0] draw_tag = frame_open[TAG_BITS-1:0];
    assign display_tag = draw_tag;
    always @* begin
        for (int j = 0; j < RATE; j++) begin
            mem_zr_addr[j*AW +: AW] = addr_of(draw_store, z_x[j*16 +: 16], z_y[j*16 +: 16]);
            mem_zw_addr[j*AW +: AW] = addr_of(draw_store, zw_x[j*16 +: 16], zw_y[j*16 +: 16]);
            mem_cw_addr[j*AW +: AW] = addr_of(draw_store, cw_x[j*16 +: 16], cw_y[j*16 +: 16]);
            mem_cw_data[j*(3*COLB+40) +: 3*COLB+40] = {cw_rgb[j*3*COLB +: 3*COLB], cw_face, cw_level};
            // another frame's depth is no surface for this one
            zr_data[j*DB +: DB] = mem_zr_data[j*ZW + DB +: TAG_BITS] == draw_tag
                                ? mem_zr_data[j*ZW +: DB] : '0;
            mem_zw_data[j*ZW +: ZW] = {draw_tag, zw_data[j*DB +: DB]};
        end
    end
    assign mem_zw_en = zw_en;
    assign mem_cw_en = cw_en;
    assign mem_sc_en = sc_en;
    assign mem_sc_addr = {sc_store, (LW + LH)'(sc_pixel) << (2 * AA)};

    always_ff @(posedge clk) begin
        if (fr_en)
            fq[fq_tail] <= {fr_number, fr_bg, fr_fog, fr_fog_rgb, fr_fog_near, fr_fog_far};
        if (rst) begin
            cycle <= '0;
            since_retire <= 64'd1;
            draw_store <= 1'b0;
            frames_taken <= '0;
            ends_taken <= '0;
            frame_open <= '0;
            fq_head <= '0;
            fq_tail <= '0;
            fq_count <= '0;
        end else begin
            cycle <= cycle + 64'd1;
            since_retire <= retire ? 64'd1 : since_retire + 64'd1;
            if (fr_en) begin
                frames_taken <= frames_taken + 16'd1;
                fq_tail <= inc(fq_tail);
            end
            ends_taken <= ends_next;
            if (retire) begin
                frame_open <= frame_open + 16'd1;
                draw_store <= !draw_store;
                fq_head <= inc(fq_head);
            end
            fq_count <= fq_count + (FQW + 1)'(fr_en) - (FQW + 1)'(retire);
        end
    end
endmodule
