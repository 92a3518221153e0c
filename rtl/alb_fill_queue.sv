// alb_fill_queue — the cells between the engine and the fill unit
// (docs/microarchitecture.md): DEPTH cells, each with its face's shading
// set-up copied so the face's slot can be refilled before its cells are
// filled.  The engine hands a cell over only if fewer than DEPTH were held at
// the start of the cycle; the fill unit takes the oldest from the cycle after
// it was queued.
`include "alb_defs.svh"

module alb_fill_queue #(
    parameter int DEPTH = 4
) (
    input  logic                 clk,
    input  logic                 rst,
    input  logic                 enq,
    input  logic [`CELL_W-1:0]   enq_cell,
    input  logic [`SETUP_W-1:0]  enq_setup,
    output logic                 full,
    input  logic                 deq,
    output logic [`CELL_W-1:0]   head_cell,
    output logic [`SETUP_W-1:0]  head_setup,
    output logic                 empty,
    output logic                 empty_next,    // after this cycle
    output logic [10:0]          count_out
);
    localparam int PW = DEPTH > 1 ? $clog2(DEPTH) : 1;
    localparam int CW = $clog2(DEPTH + 1);

    logic [`CELL_W-1:0]  q_cell [0:DEPTH-1];
    logic [`SETUP_W-1:0] q_setup [0:DEPTH-1];
    logic [PW-1:0]       rd_ptr, wr_ptr;
    logic [CW-1:0]       count;

    function automatic [PW-1:0] inc(input [PW-1:0] p);
        inc = p == PW'(DEPTH - 1) ? '0 : p + 1'b1;
    endfunction

    wire do_enq = enq && !full;
    wire do_deq = deq && !empty;
    wire [CW-1:0] count_next = count + CW'(do_enq) - CW'(do_deq);

    assign full = count == CW'(DEPTH);
    assign empty = count == '0;
    assign empty_next = count_next == '0;
    assign head_cell = q_cell[rd_ptr];
    assign head_setup = q_setup[rd_ptr];
    assign count_out = 11'(count);

    always_ff @(posedge clk) begin
        if (do_enq) begin
            q_cell[wr_ptr] <= enq_cell;
            q_setup[wr_ptr] <= enq_setup;
        end
        if (rst) begin
            rd_ptr <= '0;
            wr_ptr <= '0;
            count <= '0;
        end else begin
            if (do_enq)
                wr_ptr <= inc(wr_ptr);
            if (do_deq)
                rd_ptr <= inc(rd_ptr);
            count <= count_next;
        end
    end
endmodule
