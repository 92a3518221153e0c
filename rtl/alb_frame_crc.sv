// alb_frame_crc — the output stage (docs/vp.md §6) and the frame CRC a board
// reports (docs/usb-protocol.md, "Frame CRC"; docs/cosim.md): from the cycle
// after a frame retires it scans the display store, PIXELS pixels a cycle in
// raster order, resolves each pixel's 4^AA samples (a sample of depth 0 has
// the frame's background; colour the mean, rounded half up) and runs R, G, B
// as 16-bit little-endian values through CRC-32 (IEEE 802.3 as zlib: reflected
// 0xEDB88320, preset and final inversion).  The memory answers a scan read in
// the next cycle and clears the samples' depths as it reads them, so the store
// is clean when it is drawn again.
//
// A sample is covered if its depth is not 0 and its tag is the frame's
// (alb_frame_store).  The scan takes W H / PIXELS cycles (plus one).  The
// micro-architecture leaves the scan-out untimed ("it must fit in the next
// frame's time"); a frame that retires while the previous one is still being
// scanned out overruns it: the scan starts over on the new frame and the old
// frame's CRC is lost — reported (err_overrun), never a wrong CRC.  The store
// cut off keeps stale depths, harmless while their tags differ from every
// later frame's drawn there; after 2^(TAG_BITS-1) - 1 such scans of one store
// in a row the next could alias, and err_alias says so.
module alb_frame_crc #(
    parameter int LW = 5,
    parameter int LH = 5,
    parameter int AA = 0,
    parameter int COLB = 8,
    parameter int TAG_BITS = 8,
    parameter int PIXELS = 1            // pixels scanned a cycle, a power of two
) (
    input  logic                            clk,
    input  logic                            rst,
    input  logic                            start,       // a frame retired
    input  logic                            start_store, // its store, now the display store
    input  logic [3*COLB-1:0]               start_bg,
    input  logic [23:0]                     start_number,
    input  logic [TAG_BITS-1:0]             start_tag,
    // the scan port: PIXELS x 4^AA samples, each {tag, depth != 0, R, G, B}
    output logic                            sc_en,
    output logic [LW+LH-2*AA-1:0]           sc_pixel,
    output logic                            sc_store,
    input  logic [PIXELS*(1<<(2*AA))*(TAG_BITS+1+3*COLB)-1:0] sc_data,
    // the CRC of a frame, in frame order
    output logic                            ev_crc,
    output logic [23:0]                     ev_crc_number,
    output logic [31:0]                     ev_crc_value,
    output logic                            busy,
    output logic                            err_overrun,
    output logic                            err_alias
);
    localparam int PW = LW + LH - 2 * AA;              // pixel index bits
    localparam int NS = 1 << (2 * AA);                  // samples a pixel
    localparam int SD = TAG_BITS + 1 + 3 * COLB;
    localparam int CUT_MAX = (1 << (TAG_BITS - 1)) - 1;   // scans of a store cut off in a row
    localparam logic [PW:0] NPIX = (PW + 1)'(1) << PW;

    logic          pend;            // a scan read answered this cycle
    logic          pend_last;
    logic [PW:0]   next_pixel;
    logic [31:0]   crc;
    logic [3*COLB-1:0] bg;
    logic [23:0]   number;
    logic [TAG_BITS-1:0] tag;
    logic [TAG_BITS-1:0] cut [0:1];  // per store: scans cut off since its last whole one

    function automatic [31:0] crc_byte(input [31:0] c, input [7:0] b);
        logic [31:0] r;
        r = c ^ {24'd0, b};
        for (int k = 0; k < 8; k++)
            r = r[0] ? (r >> 1) ^ 32'hEDB88320 : r >> 1;
        crc_byte = r;
    endfunction

    // one pixel from its samples: the mean of each channel, round half up
    function automatic [47:0] resolve(input [NS*SD-1:0] s, input [3*COLB-1:0] b,
                                      input [TAG_BITS-1:0] tg);
        logic [COLB+2*AA:0] sum [0:2];
        logic [COLB-1:0] mean;
        logic [COLB-1:0] v;
        logic [15:0] ch [0:2];
        for (int c = 0; c < 3; c++)
            sum[c] = '0;
        for (int k = 0; k < NS; k++)
            for (int c = 0; c < 3; c++) begin
                v = s[k*SD + 3*COLB] && s[k*SD + 3*COLB + 1 +: TAG_BITS] == tg
                  ? s[k*SD + (2-c)*COLB +: COLB] : b[(2-c)*COLB +: COLB];
                sum[c] = sum[c] + (COLB + 2 * AA + 1)'(v);
            end
        for (int c = 0; c < 3; c++) begin
            mean = COLB'((sum[c] + (COLB + 2 * AA + 1)'(NS / 2)) >> (2 * AA));
            ch[c] = 16'(mean);
        end
        resolve = {ch[0], ch[1], ch[2]};
    endfunction

    logic [31:0] crc_after;
    always @* begin
        logic [47:0] px;
        crc_after = crc;
        for (int p = 0; p < PIXELS; p++) begin
            px = resolve(sc_data[p*NS*SD +: NS*SD], bg, tag);
            // R, G, B as 16-bit little-endian words
            crc_after = crc_byte(crc_after, px[39:32]);
            crc_after = crc_byte(crc_after, px[47:40]);
            crc_after = crc_byte(crc_after, px[23:16]);
            crc_after = crc_byte(crc_after, px[31:24]);
            crc_after = crc_byte(crc_after, px[7:0]);
            crc_after = crc_byte(crc_after, px[15:8]);
        end
    end

    assign sc_en = busy && next_pixel != NPIX;
    assign sc_pixel = next_pixel[PW-1:0];
    assign ev_crc = pend && pend_last;
    assign ev_crc_number = number;
    assign ev_crc_value = ~crc_after;
    assign err_overrun = start && busy && !ev_crc;
    assign err_alias = err_overrun && cut[sc_store] == TAG_BITS'(CUT_MAX);

    always_ff @(posedge clk) begin
        if (rst) begin
            busy <= 1'b0;
            pend <= 1'b0;
            pend_last <= 1'b0;
            cut[0] <= '0;
            cut[1] <= '0;
        end else begin
            if (ev_crc)
                cut[sc_store] <= '0;
            if (err_overrun)
                cut[sc_store] <= cut[sc_store] + 1'b1;
            pend <= sc_en;
            pend_last <= sc_en && next_pixel + (PW + 1)'(PIXELS) == NPIX;
            if (sc_en)
                next_pixel <= next_pixel + (PW + 1)'(PIXELS);
            if (pend)
                crc <= crc_after;
            if (ev_crc)
                busy <= 1'b0;
            if (start) begin
                busy <= 1'b1;
                next_pixel <= '0;
                crc <= 32'hFFFFFFFF;
                bg <= start_bg;
                number <= start_number;
                tag <= start_tag;
                sc_store <= start_store;
                pend <= 1'b0;
            end
        end
    end
endmodule
