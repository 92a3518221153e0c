// alb_fill — the fill unit (docs/microarchitecture.md, "Fill unit"): takes
// the oldest cell of the fill queue (from the cycle after it was queued, and
// after finishing the previous cell) and issues its samples RATE a cycle in
// raster order within the cell: a cell of n samples takes ceil(n / RATE)
// cycles, the last one issuing the rest.  The samples go to the pipeline's
// first stage in the cycle they are issued.
`include "alb_defs.svh"

module alb_fill #(
    parameter int RATE = 4,             // fill_rate
    parameter int LW = 5,               // log2 of the sample grid's width
    parameter int LH = 5                // ... height
) (
    input  logic                 clk,
    input  logic                 rst,
    input  logic                 q_empty,       // at the start of the cycle
    input  logic [`CELL_W-1:0]   q_cell,
    input  logic [`SETUP_W-1:0]  q_setup,
    output logic                 deq,
    // this cycle's samples
    output logic [RATE-1:0]      lane_v,
    output logic [RATE*16-1:0]   lane_x,
    output logic [RATE*16-1:0]   lane_y,
    output logic [`SETUP_W-1:0]  setup,
    output logic [4:0]           level,
    output logic                 busy,          // in a cur_cell at the start of the cycle
    output logic                 busy_next,
    output logic                 ev_fill,
    output logic [`CELL_W-1:0]   ev_cell
);
    logic [`CELL_W-1:0]  cell_r;
    logic [`SETUP_W-1:0] setup_r;
    // a sample's index within its cell, raster order: below 2^(LW+LH) + RATE
    localparam int NW = LW + LH + 2 + $clog2(RATE + 1);
    logic [NW-1:0]       next_r;        // index of the next sample
    localparam int IW = NW > 16 ? NW : 16;

    wire take = !busy && !q_empty;
    wire issuing = take || busy;
    wire [`CELL_W-1:0] cur_cell = take ? q_cell : cell_r;
    wire [NW-1:0] nx = take ? '0 : next_r;
    wire [15:0] c0 = cur_cell[`CELL_C0 +: 16];
    wire [15:0] r0 = cur_cell[`CELL_R0 +: 16];
    wire [4:0]  wl = cur_cell[`CELL_WL +: 5];
    wire [4:0]  hl = cur_cell[`CELL_HL +: 5];
    wire [NW-1:0] n = NW'(1) << (wl + hl);
    wire [NW-1:0] nx_after = nx + NW'(RATE);

    assign deq = take;
    assign setup = take ? q_setup : setup_r;
    assign level = cur_cell[`CELL_LEVEL +: 5];
    assign busy_next = issuing && nx_after < n;
    assign ev_fill = take;
    assign ev_cell = cur_cell;

    always @* begin
        for (int j = 0; j < RATE; j++) begin
            logic [NW-1:0] i;
            logic [IW-1:0] iw;
            i = nx + NW'(j);
            iw = IW'(i);
            lane_v[j] = issuing && i < n;
            lane_x[j*16 +: 16] = c0 + (16'(i) & ((16'd1 << wl) - 16'd1));
            lane_y[j*16 +: 16] = r0 + 16'(iw >> wl);
        end
    end

    always_ff @(posedge clk) begin
        if (take) begin
            cell_r <= q_cell;
            setup_r <= q_setup;
        end
        if (issuing)
            next_r <= nx_after;
        if (rst)
            busy <= 1'b0;
        else
            busy <= busy_next;
    end
endmodule
