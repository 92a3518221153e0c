// alb_fpga_top_tb — the board around alb_fpga_top for its Verilator bench
// (rtl/fpga/bench/top_bench.cpp, rtl/fpga/README.md): the FD bus as a real
// wire with two tri-state drivers, the FX2's (driven by the bench's FX2
// model) and the FPGA's (the top's non-SYNTHESIS branch), and a few of the
// top's internal signals brought out by hierarchical reference so that the
// bench can step the C model beside the VP (the words the VP takes, its
// cycle counter) and check the bus (who drives FD).  No logic of the board.
module alb_fpga_top_tb #(
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
    parameter int FILL_RATE = 1,
    parameter int FILL_QUEUE = 4,
    parameter int FRAME_QUEUE = 16,
    parameter int DIVIDER_LATENCY = 8,
    parameter int SHADE_LATENCY = 4,
    parameter int FRAME_FACES = 16777215,
    parameter int MAX_EDGES = 64,
    parameter int TEX_WORDS = 256,
    parameter int TEX_IDS = 4,
    parameter int TAG_BITS = 8,
    parameter int SHADE_UNIT = 1,
    parameter int TEX_UNIT = 1,
    parameter int FOG_UNIT = 1
) (
    input  logic        clk_vp,
    input  logic        ifclk,
    // the FX2's side of FD
    input  logic        fx2_fd_oe,
    input  logic [15:0] fx2_fd_out,
    output logic [15:0] fd_bus,        // what the wire carries (the FPGA's beat on a write)
    output logic        fpga_fd_oe,    // the FPGA drives FD
    input  logic        flaga_n,
    input  logic        flagb_n,
    output logic        slrd_n,
    output logic        slwr_n,
    output logic        sloe_n,
    output logic [1:0]  fifoadr,
    output logic        pktend_n,
    input  logic        vp_restart,
    input  logic        vp_new_stream,
    output logic [1:0]  led,           // LED_LOW 1: lit when low
    // inside the top, for the bench's checks
    output logic        vp_rst,        // the VP's reset
    output logic        rst_if,        // the FX2 side's reset
    output logic        vp_take,       // the VP's FIFO takes vp_word at this clock edge
    output logic [31:0] vp_word,
    output logic [63:0] vp_cycle,      // alb_vp's cycle counter
    output logic        vp_error,
    output logic [7:0]  vp_error_code,
    output logic [31:0] vp_error_word
);
    wire [15:0] fd;
    assign fd = fx2_fd_oe ? fx2_fd_out : 16'bz;
    assign fd_bus = fd;

    alb_fpga_top #(
        .WIDTH(WIDTH), .HEIGHT(HEIGHT), .AA(AA), .EDGE_FRAC_BITS(EDGE_FRAC_BITS),
        .COEF_BITS(COEF_BITS), .DEPTH_BITS(DEPTH_BITS), .COLOUR_BITS(COLOUR_BITS),
        .RECIP_BITS(RECIP_BITS), .SHADE_FRAC_BITS(SHADE_FRAC_BITS), .FIFO_DEPTH(FIFO_DEPTH),
        .FACE_SLOTS(FACE_SLOTS), .EDGE_UNITS(EDGE_UNITS), .FILL_RATE(FILL_RATE),
        .FILL_QUEUE(FILL_QUEUE), .FRAME_QUEUE(FRAME_QUEUE), .DIVIDER_LATENCY(DIVIDER_LATENCY),
        .SHADE_LATENCY(SHADE_LATENCY), .FRAME_FACES(FRAME_FACES), .MAX_EDGES(MAX_EDGES),
        .TEX_WORDS(TEX_WORDS), .TEX_IDS(TEX_IDS), .TAG_BITS(TAG_BITS),
        .SHADE_UNIT(SHADE_UNIT), .TEX_UNIT(TEX_UNIT), .FOG_UNIT(FOG_UNIT)
    ) u_top (
        .clk_vp, .ifclk, .fd, .flaga_n, .flagb_n, .slrd_n, .slwr_n, .sloe_n, .fifoadr,
        .pktend_n, .vp_restart, .vp_new_stream, .led
    );

    assign fpga_fd_oe = u_top.fd_oe;
    assign vp_rst = u_top.rst_vp;
    assign rst_if = u_top.rst_if;
    assign vp_take = u_top.in_valid;        // in_valid already holds !in_full
    assign vp_word = u_top.in_data;
    assign vp_cycle = u_top.u_vp.cycle;
    assign vp_error = u_top.error;
    assign vp_error_code = u_top.error_code;
    assign vp_error_word = u_top.error_word;
endmodule
