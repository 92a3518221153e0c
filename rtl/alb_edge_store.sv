// alb_edge_store — the edge store (docs/microarchitecture.md): FACE_SLOTS
// slots, each a loaded face — its shading set-up and up to MAX_EDGES edges,
// each edge as the engine starts from it (h at the screen's top-left corner
// and the increments across the screen).  Slots fill round-robin from 0
// (the k-th face loaded goes to slot k % FACE_SLOTS) and drain in the same
// order: the engine's face is always the oldest loaded one.  A slot is freed
// in the cycle the engine finishes its face and can be refilled from the next.
// The edges are read a cycle ahead, registered as block RAM answers (the
// engine names its next edges), an edge written in the cycle forwarded.
`include "alb_defs.svh"

module alb_edge_store #(
    parameter int FACE_SLOTS = 2,
    parameter int MAX_EDGES = 64,
    parameter int EW = 27,
    parameter int LANES = 8            // edge_units: edges the engine reads a cycle
) (
    input  logic                       clk,
    input  logic                       rst,
    // the parser: an edge, then the face complete
    input  logic                       ew_en,
    input  logic [5:0]                 ew_idx,
    input  logic [EW-1:0]              ew_c,
    input  logic [EW-1:0]              ew_da,
    input  logic [EW-1:0]              ew_db,
    input  logic                       fc_en,
    input  logic [`SETUP_W-1:0]        fc_setup,
    input  logic [6:0]                 fc_edges,
    input  logic [15:0]                fc_frame,
    output logic                       slot_free,     // the slot to fill next is free
    output logic [7:0]                 load_slot,     // ... and its number
    // the engine: the oldest loaded face
    output logic                       head_valid,
    output logic [15:0]                head_frame,
    output logic [`SETUP_W-1:0]        head_setup,
    output logic [6:0]                 head_edges,
    output logic [7:0]                 head_slot,
    input  logic [LANES*6-1:0]         rd_next,       // edges the engine evaluates next cycle
    output logic [LANES*EW-1:0]        rd_c,
    output logic [LANES*EW-1:0]        rd_da,
    output logic [LANES*EW-1:0]        rd_db,
    input  logic                       face_done,     // the engine finished the head face
    // status
    output logic                       any_loaded,    // a face loaded and not finished
    input  logic [15:0]                frame_open,
    output logic                       waiting_next   // after this cycle a face of frame_open waits
);
    localparam int SW = FACE_SLOTS > 1 ? $clog2(FACE_SLOTS) : 1;

    localparam int CAB = 3 * EW;
    logic [CAB-1:0]      e_cab [0:(FACE_SLOTS << EB)-1];   // {db, da, c} of an edge
    logic [`SETUP_W-1:0] s_setup [0:FACE_SLOTS-1];
    logic [6:0]          s_edges [0:FACE_SLOTS-1];
    logic [15:0]         s_frame [0:FACE_SLOTS-1];
    logic [FACE_SLOTS-1:0] s_valid;
    logic [SW-1:0]       load_ptr, done_ptr;

    function automatic [SW-1:0] inc(input [SW-1:0] p);
        inc = p == SW'(FACE_SLOTS - 1) ? '0 : p + 1'b1;
    endfunction

    // an edge's address: its slot, its index (MAX_EDGES rounded up to a power of two)
    localparam int EB = MAX_EDGES > 1 ? $clog2(MAX_EDGES) : 1;
    localparam int AW = (FACE_SLOTS > 1 ? SW : 0) + EB;
    /* verilator lint_off UNUSEDSIGNAL */   // the index's bits above EB, the slot with one slot
    function automatic [AW-1:0] eaddr(input [SW-1:0] s, input [5:0] e);
        eaddr = AW'({s, EB'(e)});
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */

    assign slot_free = !s_valid[load_ptr];
    assign load_slot = 8'(load_ptr);
    assign head_valid = s_valid[done_ptr];
    assign head_frame = s_frame[done_ptr];
    assign head_setup = s_setup[done_ptr];
    assign head_edges = s_edges[done_ptr];
    assign head_slot = 8'(done_ptr);
    assign any_loaded = |s_valid;

    // Read a cycle ahead (block RAM answers a cycle after its address):
    // the head slot after this cycle and the engine's next edges.  An edge
    // written this cycle (a face's last, when the engine starts it next
    // cycle) is forwarded.
    logic [CAB-1:0]   q_cab [0:LANES-1];
    logic [LANES-1:0] fwd;
    logic [CAB-1:0]   w_cab;
    wire  [CAB-1:0]   ew_cab = {ew_db, ew_da, ew_c};
    generate
        for (genvar j = 0; j < LANES; j++) begin : g_read
            wire [CAB-1:0] cab = fwd[j] ? w_cab : q_cab[j];
            assign rd_c[j*EW +: EW] = cab[EW-1:0];
            assign rd_da[j*EW +: EW] = cab[EW +: EW];
            assign rd_db[j*EW +: EW] = cab[2*EW +: EW];
        end
    endgenerate

    // The retirement test looks at the state after this cycle
    // (docs/microarchitecture.md, "Frames"): is the oldest unfinished face
    // one of the open frame's?  A slot loaded now is never the one freed now.
    wire [SW-1:0] done_next = face_done ? inc(done_ptr) : done_ptr;
    wire          valid_next = fc_en && load_ptr == done_next ? 1'b1
                             : face_done && done_next == done_ptr ? 1'b0 : s_valid[done_next];
    wire [15:0]   frame_next = fc_en && load_ptr == done_next ? fc_frame : s_frame[done_next];
    assign waiting_next = valid_next && frame_next == frame_open;

    always_ff @(posedge clk) begin
        if (ew_en)
            e_cab[eaddr(load_ptr, ew_idx)] <= ew_cab;
        for (int j = 0; j < LANES; j++)
            q_cab[j] <= e_cab[eaddr(done_next, rd_next[j*6 +: 6])];
    end

    always_ff @(posedge clk) begin
        for (int j = 0; j < LANES; j++)
            fwd[j] <= ew_en && eaddr(load_ptr, ew_idx) == eaddr(done_next, rd_next[j*6 +: 6]);
        w_cab <= ew_cab;
        if (fc_en) begin
            s_setup[load_ptr] <= fc_setup;
            s_edges[load_ptr] <= fc_edges;
            s_frame[load_ptr] <= fc_frame;
        end
        if (rst) begin
            s_valid <= '0;
            load_ptr <= '0;
            done_ptr <= '0;
        end else begin
            if (fc_en) begin
                s_valid[load_ptr] <= 1'b1;
                load_ptr <= inc(load_ptr);
            end
            if (face_done) begin
                s_valid[done_ptr] <= 1'b0;
                done_ptr <= inc(done_ptr);
            end
        end
    end
endmodule
