// alb_pipe_reg — one boundary of alb_pipe's stages: a register when ON, a
// wire otherwise, so the same pipeline text serves every latency the profile
// allows (L = 1 + divider_latency + shade_latency, down to 1).
module alb_pipe_reg #(
    parameter bit ON = 1'b1,
    parameter int W = 1
) (
    input  logic         clk,
    input  logic [W-1:0] d,
    output logic [W-1:0] q
);
    generate
        if (ON) begin : g_reg
            // a flip-flop a bit: yosys 0.23's ice40_dsp takes a register
            // at a multiplier's input or output into the SB_MAC16 whole,
            // leaving the register's other bits undriven (the boundary
            // carries more than the product); one register a bit it cannot
            for (genvar i = 0; i < W; i++) begin : g_bit
                always_ff @(posedge clk)
                    q[i] <= d[i];
            end
        end else begin : g_wire
            assign q = d;
            wire unused_clk = clk;
        end
    endgenerate
endmodule
