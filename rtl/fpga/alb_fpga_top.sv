// alb_fpga_top — the VP on an FPGA board behind an FX2's slave FIFOs
// (docs/fpga.md): alb_vp with its frame store on block RAM (alb_fpga_mem),
// the FX2 interface in the FX2's IFCLK domain (alb_fx2_fifo), and two
// clock-crossing FIFOs (alb_afifo) between that and the VP's clock.
//
// What the board's firmware (firmware/fx2/main.c) expects of it:
// * the word stream on EP4, taken at the VP's pace (the FIFO fills, the FX2
//   NAKs the host: the flow control of docs/usb-protocol.md);
// * per frame a 20-byte RESULT record on EP8, five little-endian u32: frame,
//   CRC of the frame store (alb_frame_crc's, docs/usb-protocol.md), cycles
//   low, cycles high, faces (the frame's FRAME_END count); a malformed stream
//   a 4-byte record, the word offset alb_vp reports;
// * VP_RESTART (PA0) high: abandon everything; VP_NEW_STREAM (PA1) high with
//   it for a RESET (a new CONFIG follows), low for a RESUME (the host resends
//   a frame from its FRAME packet): the VP is reset and the stream's CONFIG,
//   kept from its first three words, is given to it again.  Textures loaded
//   before the RESUME are not: a resumed frame that uses one meets E_TEXTURE
//   (docs/fpga.md, what is not done).
// A frame whose scan-out was cut off by the next (ev_scan_overrun) has no
// CRC and so no RESULT: the host's QUERY then times out (rtl/README.md).
module alb_fpga_top #(
    // the profile (rtl/profile-params.sh gives them for a named profile)
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
    parameter int FILL_RATE = 1,
    parameter int FILL_QUEUE = 4,
    parameter int FRAME_QUEUE = 16,
    parameter int DIVIDER_LATENCY = 8,
    parameter int SHADE_LATENCY = 4,
    parameter int FRAME_FACES = 16777215,
    // the RTL's own sizes (rtl/README.md)
    parameter int MAX_EDGES = 64,
    parameter int TEX_WORDS = 256,
    parameter int TEX_IDS = 4,
    parameter int TAG_BITS = 8,
    // the shading units built (1) or left out (0; rtl/README.md)
    parameter int SHADE_UNIT = 1,
    parameter int TEX_UNIT = 1,
    parameter int FOG_UNIT = 1,
    // the board: 1 if its LEDs light when their pin is low (the iCEBreaker's),
    // 0 if when high (the HX8K breakout's)
    parameter int LED_LOW = 1
) (
    input  logic        clk_vp,        // the board's oscillator: the VP's clock
    input  logic        ifclk,         // from the FX2
    inout  wire  [15:0] fd,
    input  logic        flaga_n,
    input  logic        flagb_n,
    output logic        slrd_n,
    output logic        slwr_n,
    output logic        sloe_n,
    output logic [1:0]  fifoadr,
    output logic        pktend_n,
    input  logic        vp_restart,    // PA0
    input  logic        vp_new_stream, // PA1
    output logic [1:0]  led            // lit: [0] an error, a memory conflict or a record lost;
                                       // [1] the VP's clock, blinking (LED_LOW: the polarity)
);
    localparam int LW = $clog2(WIDTH) + AA;
    localparam int LH = $clog2(HEIGHT) + AA;
    localparam int AW = 1 + LW + LH;
    localparam int CWD = 3 * COLOUR_BITS + 40;
    localparam int ZW = TAG_BITS + DEPTH_BITS;
    localparam int FQ = FRAME_QUEUE < 2 ? 1 : $clog2(FRAME_QUEUE);

    // ---- resets: the restart line into each clock, and power-up in each ----
    logic [1:0] rs_if, rs_vp, ns_vp;
    logic [3:0] por = 4'd0, por_if = 4'd0;
    always_ff @(posedge ifclk) begin
        rs_if <= {rs_if[0], vp_restart};
        if (por_if != 4'hF)
            por_if <= por_if + 4'd1;
    end
    always_ff @(posedge clk_vp) begin
        rs_vp <= {rs_vp[0], vp_restart};
        ns_vp <= {ns_vp[0], vp_new_stream};
        if (por != 4'hF)
            por <= por + 4'd1;
    end
    wire pwr_if = por_if != 4'hF;        // after configuration, in IFCLK's domain
    wire pwr_vp = por != 4'hF;           // ... in the VP's
    wire rst_if = rs_if[1] || pwr_if;
    wire restart_vp = rs_vp[1] || pwr_vp;
    // After every reset both banks of the frame store are cleared (through
    // the scan-out's clear, 2^AW cycles) before the VP runs: its frame tags
    // count from 0 again, and a depth a frame of before the reset left with
    // the tag a new frame has would read as that frame's.
    logic [AW:0] clr_n;
    always_ff @(posedge clk_vp)
        if (restart_vp)
            clr_n <= '0;
        else if (!clr_n[AW])
            clr_n <= clr_n + 1'b1;
    wire clearing = !clr_n[AW];
    wire rst_vp = restart_vp || clearing;

    // ---- the FX2 side ----
    logic [15:0] fd_out;
    logic        fd_oe;
    wire  [15:0] fd_in;
`ifdef SYNTHESIS
    // iCE40 I/O cells: tri-state output, plain input
    generate
        for (genvar i = 0; i < 16; i++) begin : g_fd
            SB_IO #(.PIN_TYPE(6'b1010_01), .PULLUP(1'b0)) u_io (
                .PACKAGE_PIN(fd[i]), .OUTPUT_ENABLE(fd_oe), .D_OUT_0(fd_out[i]),
                .D_IN_0(fd_in[i]));
        end
    endgenerate
`else
    assign fd = fd_oe ? fd_out : 'z;
    assign fd_in = fd;
`endif

    logic        w_en, w_full, w_empty, w_take;
    logic [31:0] w_word, w_head;
    logic        r_empty, r_take, r_push, r_full;
    logic [16:0] r_beat, r_in;
    alb_fx2_fifo u_fx2 (
        .ifclk, .rst(rst_if), .fd_in, .fd_out, .fd_oe, .flaga_n, .flagb_n, .slrd_n, .slwr_n,
        .sloe_n, .fifoadr, .pktend_n, .word_en(w_en), .word(w_word), .word_full(w_full),
        .rec_empty(r_empty), .rec_beat(r_beat), .rec_take(r_take));
    alb_afifo #(.W(32), .DEPTH(16)) u_words (
        .wclk(ifclk), .wrst(rst_if), .wen(w_en), .wdata(w_word), .full(w_full),
        .rclk(clk_vp), .rrst(rst_vp), .ren(w_take), .rdata(w_head), .empty(w_empty));
    // records outlive a restart: one begun goes out whole (the FX2 would
    // join its first beats to the next record's), so this FIFO and the
    // record being sent are reset at power-up only
    alb_afifo #(.W(17), .DEPTH(32)) u_records (
        .wclk(clk_vp), .wrst(pwr_vp), .wen(r_push), .wdata(r_in), .full(r_full),
        .rclk(ifclk), .rrst(pwr_if), .ren(r_take), .rdata(r_beat), .empty(r_empty));

    // ---- the word stream into the VP, the CONFIG kept for a RESUME ----
    logic [31:0] cfg [0:2];
    logic [1:0]  cfg_kept, cfg_given;
    logic        in_full, in_valid;
    logic [31:0] in_data;
    wire replay = cfg_given < cfg_kept;
    always_comb begin
        in_valid = !in_full && (replay || !w_empty);
        in_data = replay ? cfg[cfg_given] : w_head;
    end
    assign w_take = !in_full && !replay;
    always_ff @(posedge clk_vp) begin
        if (rst_vp) begin
            cfg_given <= 2'd0;
            if (ns_vp[1] || por != 4'hF)
                cfg_kept <= 2'd0;            // a RESET: a new stream, a new CONFIG
        end else if (in_valid && replay)
            cfg_given <= cfg_given + 2'd1;
        else if (in_valid && cfg_kept != 2'd3) begin
            cfg[cfg_kept] <= w_head;
            cfg_kept <= cfg_kept + 2'd1;
            cfg_given <= cfg_given + 2'd1;
        end
    end

    // ---- the VP and its frame store ----
    logic [AW-1:0]  zr_addr, zw_addr, cw_addr, sc_addr;
    logic [ZW-1:0]  zr_data, zw_data;
    logic           zw_en, cw_en, sc_en, mem_conflict;
    logic [CWD-1:0] cw_data;
    logic [TAG_BITS+1+3*COLOUR_BITS-1:0] sc_data;
    logic        ev_pop, ev_frame, ev_crc, ev_frame_end, error;
    logic [31:0] ev_pop_word, ev_crc_value, error_word;
    logic [23:0] ev_frame_number, ev_crc_number;
    logic [63:0] ev_frame_cycles;
    logic [7:0]  error_code;
    /* verilator lint_off PINCONNECTEMPTY */
    alb_vp #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .AA(AA), .EDGE_FRAC_BITS(EDGE_FRAC_BITS),
             .COEF_BITS(COEF_BITS), .DEPTH_BITS(DEPTH_BITS), .COLOUR_BITS(COLOUR_BITS),
             .RECIP_BITS(RECIP_BITS), .SHADE_FRAC_BITS(SHADE_FRAC_BITS), .FIFO_DEPTH(FIFO_DEPTH),
             .FACE_SLOTS(FACE_SLOTS), .EDGE_UNITS(EDGE_UNITS), .FILL_RATE(1),
             .FILL_QUEUE(FILL_QUEUE), .FRAME_QUEUE(FRAME_QUEUE),
             .DIVIDER_LATENCY(DIVIDER_LATENCY), .SHADE_LATENCY(SHADE_LATENCY),
             .FRAME_FACES(FRAME_FACES), .MAX_EDGES(MAX_EDGES), .TEX_WORDS(TEX_WORDS),
             .TEX_IDS(TEX_IDS), .SCAN_PIXELS(1), .TAG_BITS(TAG_BITS), .ZR_REG(1),
             .SHADE_UNIT(SHADE_UNIT), .TEX_UNIT(TEX_UNIT), .FOG_UNIT(FOG_UNIT)) u_vp (
        .clk(clk_vp), .rst(rst_vp), .in_valid, .in_data, .in_full,
        .mem_zr_addr(zr_addr), .mem_zr_data(zr_data), .mem_zw_en(zw_en), .mem_zw_addr(zw_addr),
        .mem_zw_data(zw_data), .mem_cw_en(cw_en), .mem_cw_addr(cw_addr), .mem_cw_data(cw_data),
        .mem_sc_en(sc_en), .mem_sc_addr(sc_addr), .mem_sc_data(sc_data),
        .cycle(), .ev_pop, .ev_pop_index(), .ev_pop_word, .ev_load(), .ev_load_face(),
        .ev_load_slot(), .ev_load_edges(), .ev_start(), .ev_cell(), .ev_cell_result(),
        .ev_cell_edges(), .ev_cell_cell(), .ev_end(), .ev_engine_face(), .ev_engine_slot(),
        .ev_fill(), .ev_fill_face(), .ev_fill_cell(), .ev_write(), .ev_write_x(),
        .ev_write_y(), .ev_write_depth(), .ev_write_rgb(), .ev_write_face(), .ev_write_level(),
        .ev_frame, .ev_frame_number, .ev_frame_cycles, .ev_crc, .ev_crc_number, .ev_crc_value,
        .ev_scan_overrun(), .ev_frame_end, .error, .error_code, .error_word);
    /* verilator lint_on PINCONNECTEMPTY */
    alb_fpga_mem #(.LW(LW), .LH(LH), .DB(DEPTH_BITS), .COLB(COLOUR_BITS),
                   .TAG_BITS(TAG_BITS)) u_mem (
        .clk(clk_vp), .rst(restart_vp), .zr_addr, .zr_data, .zw_en, .zw_addr, .zw_data, .cw_en,
        .cw_addr, .cw_data, .sc_en(sc_en || clearing), .sc_addr(clearing ? clr_n[AW-1:0] : sc_addr),
        .sc_data, .conflict(mem_conflict));

    // ---- RESULT records ----
    // faces per frame: the FRAME_END counts, in the order the frames retire
    logic [23:0] faces_q [0:(1<<FQ)-1];
    logic [FQ:0] fq_in, fq_out;
    // the frame retired last, waiting for its CRC (a later retirement cuts
    // its scan-out off, and then its CRC never comes)
    logic [23:0] res_frame, res_faces;
    logic [63:0] res_cycles;
    logic        res_wait;
    // the record being sent, 16 bits at a time: held whole while it goes
    // out and its beats picked by number (a 160-bit shift register would
    // put a multiplexer before every flip-flop)
    logic [159:0] out_bits;
    logic [3:0]  out_left, out_beat;
    logic        err_sent, lost;
    logic [15:0] beat;
    always_comb begin
        beat = out_bits[15:0];
        for (int i = 1; i < 10; i++)
            if (out_beat == 4'(i))
                beat = out_bits[16*i +: 16];
    end
    assign r_push = out_left != 4'd0 && !r_full;
    assign r_in = {out_left == 4'd1, beat};
    // this frame's CRC: its record goes out if the one before has (all but
    // its last beat, which goes in this cycle), else it is lost
    wire crc_now = ev_crc && res_wait && ev_crc_number == res_frame;
    wire out_room = out_left == 4'd0 || (out_left == 4'd1 && r_push);
    wire load_rec = crc_now && out_room;
    wire load_err = !crc_now && error && !err_sent && out_left == 4'd0;
    always_ff @(posedge clk_vp) begin
        if (pwr_vp)
            out_left <= 4'd0;
        else begin
            if (r_push) begin
                out_beat <= out_beat + 4'd1;
                out_left <= out_left - 4'd1;
            end
            if (load_rec) begin
                out_bits <= {8'd0, res_faces, res_cycles, ev_crc_value, 8'd0, res_frame};
                out_left <= 4'd10;
                out_beat <= 4'd0;
            end else if (load_err) begin
                out_bits <= {128'd0, error_word};
                out_left <= 4'd2;
                out_beat <= 4'd0;
            end
        end
    end
    always_ff @(posedge clk_vp) begin
        if (rst_vp) begin
            fq_in <= '0;
            fq_out <= '0;
            res_wait <= 1'b0;
            err_sent <= 1'b0;
            lost <= 1'b0;
        end else begin
            if (ev_frame_end) begin
                faces_q[fq_in[FQ-1:0]] <= ev_pop_word[23:0];
                fq_in <= fq_in + 1'b1;
            end
            if (crc_now) begin
                if (!out_room)
                    lost <= 1'b1;            // the host is not reading records
                res_wait <= 1'b0;
            end else if (load_err)
                err_sent <= 1'b1;
            if (ev_frame) begin
                res_frame <= ev_frame_number;
                res_cycles <= ev_frame_cycles;
                res_faces <= faces_q[fq_out[FQ-1:0]];
                fq_out <= fq_out + 1'b1;
                res_wait <= 1'b1;
            end
        end
    end
    // out_bits: the five u32 of a RESULT from the low end (frame, CRC, cycles
    // low, cycles high, faces), so the frame's low half goes first

    logic [23:0] alive;
    always_ff @(posedge clk_vp)
        alive <= alive + 24'd1;
    wire [1:0] lit = {alive[23], lost || mem_conflict || error};
    assign led = LED_LOW != 0 ? ~lit : lit;
    // this board's frame store is one lane (alb_fpga_mem)
    wire unused = ^{ev_pop, error_code, ev_pop_word[31:24], FILL_RATE == 1};
endmodule
