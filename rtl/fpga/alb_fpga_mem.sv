// alb_fpga_mem — the frame-store memory of alb_vp (its mem_* port, rtl/README.md)
// on the FPGA's block RAM, for FILL_RATE = 1, SCAN_PIXELS = 1 and ZR_REG = 1:
// what rtl/bench/alb_frame_mem.sv emulates, built so that each RAM has one
// read and one write port (an SB_RAM40_4K's).
//
// The two sample stores are two banks (the address's top bit).  The drawing
// store is read (depth test) and written (depth, colour); the display store
// is read and cleared by the scan.  They are never the same store while both
// are busy (the scan of a store starts after it retired, drawing moves to the
// other), so each bank sees one reader and one writer a cycle: depth, read by
// the depth test or the scan, written by the depth write or the scan's clear;
// colour, written by the last stage, read by the scan.  Should both ever
// want one bank, drawing wins and `conflict` latches (a LED on the board).
//
// The scan's clear is written where the scan read one cycle before, so the
// read of a bank never meets its own clear (the bench's read-first RAM does
// both in one cycle; the result is the same).
module alb_fpga_mem #(
    parameter int LW = 5,
    parameter int LH = 5,
    parameter int DB = 16,
    parameter int COLB = 5,
    parameter int TAG_BITS = 8,
    parameter int AW = 1 + LW + LH,
    parameter int CWD = 3 * COLB + 40,
    parameter int ZW = TAG_BITS + DB
) (
    input  logic                           clk,
    input  logic                           rst,
    input  logic [AW-1:0]                  zr_addr,
    output logic [ZW-1:0]                  zr_data,   // the next cycle
    input  logic                           zw_en,
    input  logic [AW-1:0]                  zw_addr,
    input  logic [ZW-1:0]                  zw_data,
    input  logic                           cw_en,
    input  logic [AW-1:0]                  cw_addr,
    input  logic [CWD-1:0]                 cw_data,
    input  logic                           sc_en,
    input  logic [AW-1:0]                  sc_addr,
    output logic [TAG_BITS+1+3*COLB-1:0]   sc_data,   // the next cycle
    output logic                           conflict
);
    localparam int BA = AW - 1;           // address within a bank
    localparam int N = 1 << BA;
    localparam int CB3 = 3 * COLB;

    // the scan's clear, one cycle behind its read
    logic          clr_en;
    logic [AW-1:0] clr_addr;
    always_ff @(posedge clk) begin
        clr_en <= sc_en && !rst;
        clr_addr <= sc_addr;
    end

    logic [ZW-1:0]  zq [0:1];
    logic [CB3-1:0] cq [0:1];
    logic           zr_bank, sc_bank;
    logic [1:0]     clash;

    generate
        for (genvar b = 0; b < 2; b++) begin : g_bank
            logic [ZW-1:0]  depth [0:N-1];
            logic [CB3-1:0] colour [0:N-1];
            // both stores start clear: depth 0, no surface
            initial
                for (int i = 0; i < N; i++) begin
                    depth[i] = '0;
                    colour[i] = '0;
                end
            wire sc_here = sc_en && sc_addr[AW-1] == 1'(b);
            wire zw_here = zw_en && zw_addr[AW-1] == 1'(b);
            wire clr_here = clr_en && clr_addr[AW-1] == 1'(b);
            wire cw_here = cw_en && cw_addr[AW-1] == 1'(b);
            // the depth test reads every cycle (its address is don't-care
            // when no sample is issued), so the scan has the bank it scans
            wire [BA-1:0] zra = sc_here ? sc_addr[BA-1:0] : zr_addr[BA-1:0];
            wire [BA-1:0] zwa = zw_here ? zw_addr[BA-1:0] : clr_addr[BA-1:0];
            wire [ZW-1:0] zwd = zw_here ? zw_data : '0;
            always_ff @(posedge clk) begin
                zq[b] <= depth[zra];
                if (zw_here || clr_here)
                    depth[zwa] <= zwd;
                cq[b] <= colour[sc_addr[BA-1:0]];
                if (cw_here)
                    colour[cw_addr[BA-1:0]] <= cw_data[CWD-1 -: CB3];
            end
            assign clash[b] = zw_here && clr_here;
        end
    endgenerate

    always_ff @(posedge clk) begin
        zr_bank <= zr_addr[AW-1];
        sc_bank <= sc_addr[AW-1];
        if (rst)
            conflict <= 1'b0;
        else if (|clash)
            conflict <= 1'b1;
    end
    assign zr_data = zq[zr_bank];
    // {tag, depth != 0, R G B} of the sample scanned
    assign sc_data = {zq[sc_bank][ZW-1 -: TAG_BITS], zq[sc_bank][DB-1:0] != '0, cq[sc_bank]};
    wire unused_cw = ^cw_data[CWD-CB3-1:0];
endmodule
