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
            always_ff @(posedge clk)
                q <= d;
        end else begin : g_wire
            assign q = d;
            wire unused_clk = clk;
        end
    endgenerate
endmodule
