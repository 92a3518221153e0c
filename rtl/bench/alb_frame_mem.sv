// alb_frame_mem — the external frame-store memory a board would have, as the
// benches emulate it (not part of the VP): both sample stores, each sample a
// depth word {frame tag, depth} and a colour word {R G B, face id, level}.
// Depth reads are answered in the same cycle (an asynchronous SRAM), writes
// land at the end of the cycle; the scan port answers in the next cycle with
// each sample's {tag, depth != 0, R G B} and clears the depths it read
// (read-first, as a dual-port block RAM does).  Both stores start clear:
// depth 0, no surface.
module alb_frame_mem #(
    parameter int RATE = 4,
    parameter int LW = 5,
    parameter int LH = 5,
    parameter int AA = 0,
    parameter int DB = 24,
    parameter int COLB = 8,
    parameter int SCAN_PIXELS = 1,
    parameter int TAG_BITS = 8,
    parameter int AW = 1 + LW + LH,
    parameter int CWD = 3 * COLB + 40,
    parameter int ZW = TAG_BITS + DB
) (
    input  logic                     clk,
    input  logic [RATE*AW-1:0]       zr_addr,
    output logic [RATE*ZW-1:0]       zr_data,
    input  logic [RATE-1:0]          zw_en,
    input  logic [RATE*AW-1:0]       zw_addr,
    input  logic [RATE*ZW-1:0]       zw_data,
    input  logic [RATE-1:0]          cw_en,
    input  logic [RATE*AW-1:0]       cw_addr,
    input  logic [RATE*CWD-1:0]      cw_data,
    input  logic                     sc_en,
    input  logic [AW-1:0]            sc_addr,
    output logic [SCAN_PIXELS*(1<<(2*AA))*(TAG_BITS+1+3*COLB)-1:0] sc_data
);
    localparam int N = 1 << AW;
    localparam int SN = SCAN_PIXELS << (2 * AA);
    localparam int SD = TAG_BITS + 1 + 3 * COLB;

    // public: the Verilator bench reads them to dump a frame (cosim --dump)
    logic [ZW-1:0]  depth [0:N-1] /* verilator public */;
    logic [CWD-1:0] colour [0:N-1] /* verilator public */;

    initial begin
        for (int i = 0; i < N; i++) begin
            depth[i] = '0;
            colour[i] = '0;
        end
    end

    generate
        for (genvar j = 0; j < RATE; j++) begin : g_read
            assign zr_data[j*ZW +: ZW] = depth[zr_addr[j*AW +: AW]];
        end
    endgenerate

    always_ff @(posedge clk) begin
        for (int j = 0; j < RATE; j++) begin
            if (zw_en[j])
                depth[zw_addr[j*AW +: AW]] <= zw_data[j*ZW +: ZW];
            if (cw_en[j])
                colour[cw_addr[j*AW +: AW]] <= cw_data[j*CWD +: CWD];
        end
    end
    generate
        for (genvar k = 0; k < SN; k++) begin : g_scan
            always_ff @(posedge clk)
                if (sc_en) begin
                    sc_data[k*SD +: SD] <= {depth[sc_addr + AW'(k)][ZW-1 -: TAG_BITS],
                                            depth[sc_addr + AW'(k)][DB-1:0] != '0,
                                            colour[sc_addr + AW'(k)][CWD-1 -: 3*COLB]};
                    depth[sc_addr + AW'(k)] <= '0;
                end
        end
    endgenerate
endmodule
