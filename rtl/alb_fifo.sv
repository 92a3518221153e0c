// alb_fifo — the GP -> VP FIFO (docs/microarchitecture.md, "FIFO"):
// DEPTH words of 32 bits, at most one push and one pop a cycle.  Both sides
// look at the occupancy at the start of the cycle: a push is taken only if
// fewer than DEPTH words were held (the producer sees `full`), a pop only
// if a word was held, so a word pushed in cycle t can be popped from t + 1.
module alb_fifo #(
    parameter int DEPTH = 512
) (
    input  logic        clk,
    input  logic        rst,
    input  logic        push,
    input  logic [31:0] push_data,
    output logic        full,        // DEPTH words held at the start of the cycle
    input  logic        pop,
    output logic [31:0] head,        // the oldest word, valid when !empty
    output logic        empty,
    output logic        overflow     // pushed while full: the word is lost
);
    localparam int PW = DEPTH > 1 ? $clog2(DEPTH) : 1;
    localparam int CW = $clog2(DEPTH + 1);

    logic [31:0]   mem [0:DEPTH-1];
    logic [PW-1:0] rd_ptr, wr_ptr;
    logic [CW-1:0] count;

    function automatic [PW-1:0] inc(input [PW-1:0] p);
        inc = p == PW'(DEPTH - 1) ? '0 : p + 1'b1;
    endfunction

    assign full = count == CW'(DEPTH);
    assign empty = count == '0;
    assign head = mem[rd_ptr];
    assign overflow = push && full;

    wire do_push = push && !full;
    wire do_pop = pop && !empty;

    always_ff @(posedge clk) begin
        if (do_push)
            mem[wr_ptr] <= push_data;
        if (rst) begin
            rd_ptr <= '0;
            wr_ptr <= '0;
            count <= '0;
        end else begin
            if (do_push)
                wr_ptr <= inc(wr_ptr);
            if (do_pop)
                rd_ptr <= inc(rd_ptr);
            count <= count + CW'(do_push) - CW'(do_pop);
        end
    end
endmodule
