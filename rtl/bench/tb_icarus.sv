// tb_icarus — a plain SystemVerilog bench of the VP RTL for Icarus Verilog
// (iverilog -g2012), so nothing rests on one simulator's semantics: the word
// stream and the cycle of each push from $readmemh files, the model's writes,
// frames and CRCs likewise (rtl/bench/icarus.sh makes them from the model's
// event log), each checked in its cycle.  Files by plusargs:
//   +words=F +pushes=F +writes=F +frames=F +nwords=N +nwrites=N +nframes=N
// Prints "icarus: PASS ..." or "icarus: FAIL ..." (vvp's exit status does
// not carry it).
`include "alb_defs.svh"

module tb_icarus #(
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
    parameter int SCAN_PIXELS = 8,
    parameter int SHADE_UNIT = 1,
    parameter int TEX_UNIT = 1,
    parameter int FOG_UNIT = 1,
    parameter int MAX_WORDS = 1 << 16,
    parameter int MAX_WRITES = 1 << 16,
    parameter int MAX_FRAMES = 64
);
    localparam int LW = $clog2(WIDTH) + AA;
    localparam int LH = $clog2(HEIGHT) + AA;
    localparam int AW = 1 + LW + LH;
    localparam int CWD = 3 * COLOUR_BITS + 40;
    localparam int TAG_BITS = 8;
    localparam int ZW = TAG_BITS + DEPTH_BITS;
    localparam int SCW = SCAN_PIXELS * (1 << (2 * AA)) * (TAG_BITS + 1 + 3 * COLOUR_BITS);
    localparam int CB = COLOUR_BITS;

    // stimulus and expectations
    logic [31:0]  words [0:MAX_WORDS-1];
    logic [31:0]  pushes [0:MAX_WORDS-1];     // cycle of each word's push
    // cycle, x, y, depth, r, g, b, face, level
    logic [183:0] writes [0:MAX_WRITES-1];
    // cycle, number, cycles, crc
    logic [127:0] frames [0:MAX_FRAMES-1];
    int nwords, nwrites, nframes;

    logic clk = 1'b0, rst = 1'b1, in_valid = 1'b0, in_full;
    logic [31:0] in_data = '0;
    always #5 clk = !clk;

    logic [FILL_RATE*AW-1:0]   zr_addr, zw_addr, cw_addr;
    logic [FILL_RATE*ZW-1:0]   zr_data, zw_data;
    logic [FILL_RATE-1:0]      zw_en, cw_en;
    logic [FILL_RATE*CWD-1:0]  cw_data;
    logic                      sc_en;
    logic [AW-1:0]             sc_addr;
    logic [SCW-1:0]            sc_data;
    logic [63:0]               cycle;
    logic                      ev_pop, ev_load, ev_start, ev_cell, ev_end, ev_fill, ev_frame, ev_crc;
    logic                      ev_scan_overrun, error;
    logic [31:0]               ev_pop_index, ev_pop_word, ev_load_face, ev_engine_face, ev_fill_face;
    logic [7:0]                ev_load_slot, ev_engine_slot, error_code;
    logic [6:0]                ev_load_edges, ev_cell_edges;
    logic [2:0]                ev_cell_result;
    logic [`CELL_W-1:0]        ev_cell_cell, ev_fill_cell;
    logic [FILL_RATE-1:0]      ev_write;
    logic [FILL_RATE*16-1:0]   ev_write_x, ev_write_y;
    logic [FILL_RATE*DEPTH_BITS-1:0] ev_write_depth;
    logic [FILL_RATE*3*CB-1:0] ev_write_rgb;
    logic [31:0]               ev_write_face, error_word, ev_crc_value;
    logic [7:0]                ev_write_level;
    logic [23:0]               ev_frame_number, ev_crc_number;
    logic [63:0]               ev_frame_cycles;

    alb_vp #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .AA(AA), .EDGE_FRAC_BITS(EDGE_FRAC_BITS),
             .COEF_BITS(COEF_BITS), .DEPTH_BITS(DEPTH_BITS), .COLOUR_BITS(COLOUR_BITS),
             .RECIP_BITS(RECIP_BITS), .SHADE_FRAC_BITS(SHADE_FRAC_BITS), .FIFO_DEPTH(FIFO_DEPTH),
             .FACE_SLOTS(FACE_SLOTS), .EDGE_UNITS(EDGE_UNITS), .FILL_RATE(FILL_RATE),
             .FILL_QUEUE(FILL_QUEUE), .DIVIDER_LATENCY(DIVIDER_LATENCY),
             .SHADE_LATENCY(SHADE_LATENCY), .FRAME_FACES(FRAME_FACES),
             .SCAN_PIXELS(SCAN_PIXELS), .TAG_BITS(TAG_BITS), .SHADE_UNIT(SHADE_UNIT),
             .TEX_UNIT(TEX_UNIT), .FOG_UNIT(FOG_UNIT)) dut (
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
                    .COLB(COLOUR_BITS), .SCAN_PIXELS(SCAN_PIXELS), .TAG_BITS(TAG_BITS)) mem (
        .clk, .zr_addr, .zr_data, .zw_en, .zw_addr, .zw_data, .cw_en, .cw_addr, .cw_data,
        .sc_en, .sc_addr, .sc_data);

    string f;
    int next_word = 0, next_write = 0, next_frame = 0, next_crc = 0, crcs_lost = 0;
    longint t = 0, last_cycle = 0;
    bit failed = 1'b0, done;

    task automatic fail(input string what);
        $display("icarus: FAIL cycle %0d: %s", t, what);
        failed = 1'b1;
    endtask

    initial begin
        if (!$value$plusargs("nwords=%d", nwords) || !$value$plusargs("nwrites=%d", nwrites) ||
            !$value$plusargs("nframes=%d", nframes))
            $fatal(1, "+nwords= +nwrites= +nframes= missing");
        if (nwords > MAX_WORDS || nwrites > MAX_WRITES || nframes > MAX_FRAMES)
            $fatal(1, "the stream is larger than MAX_WORDS/MAX_WRITES/MAX_FRAMES");
        if (!$value$plusargs("words=%s", f)) $fatal(1, "+words=FILE missing");
        if (nwords > 0) $readmemh(f, words, 0, nwords - 1);
        if (!$value$plusargs("pushes=%s", f)) $fatal(1, "+pushes=FILE missing");
        if (nwords > 0) $readmemh(f, pushes, 0, nwords - 1);
        if (!$value$plusargs("writes=%s", f)) $fatal(1, "+writes=FILE missing");
        if (nwrites > 0) $readmemh(f, writes, 0, nwrites - 1);
        if (!$value$plusargs("frames=%s", f)) $fatal(1, "+frames=FILE missing");
        if (nframes > 0) $readmemh(f, frames, 0, nframes - 1);
        last_cycle = nframes > 0 ? longint'(frames[nframes-1][127:96]) : 0;
        repeat (2) @(posedge clk);
        #1 rst = 1'b0;
        done = 1'b0;
        while (!failed && !done) begin
            // the producer: this cycle's push, at the model's cycle
            in_valid = next_word < nwords && longint'(pushes[next_word]) == t;
            in_data = in_valid ? words[next_word] : 32'd0;
            #8;   // the cycle's events are settled before the rising edge
            check_cycle;
            if (in_valid)
                next_word++;
            if (t > last_cycle && next_crc + crcs_lost == nframes)
                done = 1'b1;
            else if (t > last_cycle + WIDTH * HEIGHT / SCAN_PIXELS + 16)
                fail($sformatf("%0d frame CRCs never came", nframes - next_crc - crcs_lost));
            else begin
                @(posedge clk);
                #1 t++;
            end
        end
        if (!failed && (next_write != nwrites || next_frame != nframes))
            fail($sformatf("%0d of %0d writes and %0d of %0d frames came", next_write, nwrites,
                           next_frame, nframes));
        if (!failed)
            $display("icarus: PASS %0d cycles, %0d writes, %0d frames, %0d CRCs match (%0d unchecked: scan-out overrun)",
                     t + 1, nwrites, nframes, next_crc, crcs_lost);
        $finish;
    end

    task automatic check_cycle;
        logic [183:0] got;
        if (cycle != 64'(t))
            fail($sformatf("the RTL's cycle counter reads %0d", cycle));
        if (in_valid && in_full)
            fail($sformatf("the FIFO is full for word %0d", next_word));
        if (error)
            fail($sformatf("the RTL reports error %0d at word %0d", error_code, error_word));
        for (int j = 0; j < FILL_RATE; j++)
            if (ev_write[j]) begin
                got = {32'(t), ev_write_x[j*16 +: 16], ev_write_y[j*16 +: 16],
                       32'(ev_write_depth[j*DEPTH_BITS +: DEPTH_BITS]),
                       16'(ev_write_rgb[j*3*CB + 2*CB +: CB]), 16'(ev_write_rgb[j*3*CB + CB +: CB]),
                       16'(ev_write_rgb[j*3*CB +: CB]), ev_write_face, ev_write_level};
                if (next_write >= nwrites)
                    fail($sformatf("an extra write %h", got));
                else if (got != writes[next_write])
                    fail($sformatf("write %0d: expected %h, got %h", next_write,
                                   writes[next_write], got));
                next_write++;
            end
        if (next_write < nwrites && longint'(writes[next_write][183:152]) < t)
            fail($sformatf("write %0d (%h) did not come", next_write, writes[next_write]));
        if (ev_frame) begin
            if (next_frame >= nframes)
                fail("an extra frame");
            else if ({32'(t), 8'd0, ev_frame_number, ev_frame_cycles[31:0]} !=
                     frames[next_frame][127:32])
                fail($sformatf("frame %0d: expected %h, got cycle %0d number %0d cycles %0d",
                               next_frame, frames[next_frame], t, ev_frame_number,
                               ev_frame_cycles));
            next_frame++;
        end
        if (ev_scan_overrun)
            crcs_lost++;
        if (ev_crc) begin
            if (next_crc + crcs_lost >= next_frame)
                fail("a CRC before its frame");
            else if (ev_crc_value != frames[next_crc + crcs_lost][31:0])
                fail($sformatf("frame %0d: CRC expected %h, got %h", next_crc + crcs_lost,
                               frames[next_crc + crcs_lost][31:0], ev_crc_value));
            next_crc++;
        end
    endtask
endmodule
