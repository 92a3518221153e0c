// alb_afifo — a FIFO between two clocks (the FX2's IFCLK and the VP's clock
// on the FPGA board, rtl/fpga/alb_fpga_top.sv): Gray-coded pointers passed
// through two flip-flops each way, so a side sees the other's pointer late,
// never wrong — it may think the FIFO fuller (writer) or emptier (reader) than
// it is, never the reverse.  DEPTH a power of two; the storage a RAM with one
// write port (wclk) and one read port (rclk), read in the next cycle.
// Each side has its own synchronous reset; both are held while the board's
// restart line is high (many cycles of either clock), so they end together.
module alb_afifo #(
    parameter int W = 32,
    parameter int DEPTH = 16
) (
    input  logic         wclk,
    input  logic         wrst,
    input  logic         wen,         // push wdata (ignored when full)
    input  logic [W-1:0] wdata,
    output logic         full,
    input  logic         rclk,
    input  logic         rrst,
    input  logic         ren,         // take rdata (ignored when empty)
    output logic [W-1:0] rdata,       // the head, valid while !empty
    output logic         empty
);
    localparam int A = $clog2(DEPTH);

    logic [W-1:0] mem [0:DEPTH-1];
    logic [A:0] wbin, wgray, rbin, rgray;
    logic [A:0] wq1, wq2, rq1, rq2;      // the other side's Gray pointer, synchronised

    function automatic [A:0] gray(input [A:0] b);
        gray = b ^ (b >> 1);
    endfunction
    function automatic [A:0] ungray(input [A:0] g);
        logic [A:0] b;
        b[A] = g[A];
        for (int k = A - 1; k >= 0; k--)
            b[k] = b[k + 1] ^ g[k];
        ungray = b;
    endfunction

    // ---- write side ----
    wire [A:0] rbin_w = ungray(rq2);
    assign full = (wbin[A] != rbin_w[A]) && (wbin[A-1:0] == rbin_w[A-1:0]);
    wire push = wen && !full;
    always_ff @(posedge wclk) begin
        if (push)
            mem[wbin[A-1:0]] <= wdata;
        if (wrst) begin
            wbin <= '0;
            wgray <= '0;
            rq1 <= '0;
            rq2 <= '0;
        end else begin
            if (push) begin
                wbin <= wbin + 1'b1;
                wgray <= gray(wbin + 1'b1);
            end
            rq1 <= rgray;
            rq2 <= rq1;
        end
    end

    // ---- read side: the head is read a cycle ahead, from the next pointer ----
    wire [A:0] wbin_r = ungray(wq2);
    wire pop = ren && !empty;
    wire [A:0] rnext = pop ? rbin + 1'b1 : rbin;
    always_ff @(posedge rclk) begin
        rdata <= mem[rnext[A-1:0]];
        if (rrst) begin
            rbin <= '0;
            rgray <= '0;
            wq1 <= '0;
            wq2 <= '0;
            empty <= 1'b1;
        end else begin
            rbin <= rnext;
            rgray <= gray(rnext);
            wq1 <= wgray;
            wq2 <= wq1;
            // rdata is mem[rnext] as of this edge; it is the head once the
            // writer's pointer, as seen, is beyond it
            empty <= rnext == wbin_r;
        end
    end
endmodule
