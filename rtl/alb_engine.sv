// alb_engine — the subdivision engine (docs/microarchitecture.md; docs/vp.md
// §2-§3): walks the oldest loaded face's cells from the top cell down, one
// step per cell, children top-left, top-right, bottom-left, bottom-right.  A
// step evaluates the cell's active edges E at a time (E = edge_units) and
// takes max(1, ceil(active / E)) cycles; a filled cell or a single sample
// inside is handed to the fill queue in the step's last cycle, or the engine
// stalls until the queue has room.
//
// Multiplier-free (docs/vp.md §2): an edge's h = a C + b R + c is linear, so
// over a cell its corners are h_tl, h_tl + dA, h_tl + dB, h_tl + dA + dB,
// where dA, dB are the edge's increments across the screen halved once per
// level (arithmetic shifts, exact: they are multiples of 2^(levels+1)).  A
// child's top-left corner is its parent's plus half the parent's increment
// along each split side — the mean of two corners.  The engine keeps, per
// level, the last cell's h_tl of every edge it evaluated: that cell is the
// parent of every cell popped at the next level (the walk is depth-first),
// so the stack itself holds only positions and active-edge masks.  Adders,
// shifts and comparators only: no `*` (checked by yosys in tests/cosim.sh).
`include "alb_defs.svh"

module alb_engine #(
    parameter int LW = 5,               // log2 of the sample grid's width
    parameter int LH = 5,               // ... height
    parameter int EW = 27,              // edge value width
    parameter int MAX_EDGES = 64,
    parameter int E = 8                 // edge_units
) (
    input  logic                  clk,
    input  logic                  rst,
    // the oldest loaded face (alb_edge_store)
    input  logic                  head_valid,
    input  logic [15:0]           head_frame,
    input  logic [6:0]            head_edges,
    input  logic [31:0]           head_id,
    input  logic [7:0]            head_slot,
    input  logic [15:0]           frame_open,
    output logic [E*6-1:0]        rd_idx,
    input  logic [E*EW-1:0]       rd_c,
    input  logic [E*EW-1:0]       rd_da,
    input  logic [E*EW-1:0]       rd_db,
    output logic                  face_done,
    // the fill queue
    input  logic                  q_full,       // FILL_QUEUE cells held at the start of the cycle
    output logic                  enq,
    output logic [`CELL_W-1:0]    enq_cell,
    // state for the retirement and drain tests
    output logic                  busy,
    output logic                  busy_next,
    // events (docs/cosim.md)
    output logic                  ev_start,
    output logic                  ev_cell,
    output logic [2:0]            ev_cell_result,
    output logic [6:0]            ev_cell_edges,
    output logic [`CELL_W-1:0]    ev_cell_cell,
    output logic                  ev_end,
    output logic [31:0]           ev_face,
    output logic [7:0]            ev_slot
);
    localparam int P = LW > LH ? LW : LH;     // levels: the last is one sample
    localparam int DEPTH = 3 * P + 1;         // pending siblings: at most 3 a level
    localparam int SPW = $clog2(DEPTH + 1);
    localparam int AW = $clog2(DEPTH);
    localparam int ME = MAX_EDGES;

    // ---- state ----
    logic              stalled;
    // positions: below 2^LW, 2^LH (a cell's corner in the sample grid), held
    // at LW + 1, LH + 1 bits, 16 at the ports
    localparam int XB = LW + 1, YB = LH + 1;
    logic [XB-1:0]     cur_c0;
    logic [YB-1:0]     cur_r0;
    logic [4:0]        cur_lvl;
    logic [6:0]        cur_n;                // active edges when the step began
    logic [ME-1:0]     rem;                  // edges of the step not evaluated yet
    logic              acc_out, acc_in;
    logic [ME-1:0]     acc_act;
    logic [XB-1:0]     stk_c0 [0:DEPTH-1];
    logic [YB-1:0]     stk_r0 [0:DEPTH-1];
    logic [4:0]        stk_lvl [0:DEPTH-1];
    logic [ME-1:0]     stk_act [0:DEPTH-1];
    logic [SPW-1:0]    sp;
    logic [EW-1:0]     lvl_h [0:P*ME-1];     // per level: h_tl of the last cell evaluated

    function automatic [6:0] popcount(input [ME-1:0] m);
        logic [6:0] n;
        n = 7'd0;
        for (int k = 0; k < ME; k++)
            n = n + 7'(m[k]);
        popcount = n;
    endfunction

    // ---- the step this cycle ----
    wire start = !busy && head_valid && head_frame == frame_open;
    wire working = start || (busy && !stalled);
    wire [ME-1:0] face_mask = head_edges >= 7'(ME) ? {ME{1'b1}}
                                                   : (ME'(1) << head_edges) - ME'(1);
    wire [XB-1:0] c0 = start ? '0 : cur_c0;
    wire [YB-1:0] r0 = start ? '0 : cur_r0;
    wire [4:0]    lvl = start ? 5'd0 : cur_lvl;
    wire [ME-1:0] rem_in = start ? face_mask : rem;
    wire          out_in = start ? 1'b0 : acc_out;
    wire          in_in = start ? 1'b1 : acc_in;
    wire [ME-1:0] act_in = start ? face_mask : acc_act;
    wire [6:0]    n_in = start ? head_edges : cur_n;
    // a cell of level l is 2^wl x 2^hl samples; a side one sample long is not split
    wire [4:0]    wl = lvl < 5'(LW) ? 5'(LW) - lvl : 5'd0;
    wire [4:0]    hl = lvl < 5'(LH) ? 5'(LH) - lvl : 5'd0;
    wire          single = wl == 5'd0 && hl == 5'd0;
    // the cell's offset in its parent: the bit of its position at its own size
    wire          dx = lvl != 5'd0 && lvl <= 5'(LW) && (c0 & (XB'(1) << wl)) != '0;
    wire          dy = lvl != 5'd0 && lvl <= 5'(LH) && (r0 & (YB'(1) << hl)) != '0;
    wire [4:0]    sha = lvl < 5'(LW) ? lvl : 5'(LW);   // halvings of dA to this cell's width
    wire [4:0]    shb = lvl < 5'(LH) ? lvl : 5'(LH);

    // the next E active edges, lowest index first
    logic [E-1:0]  lane_v;
    logic [5:0]    lane_e [0:E-1];
    logic [ME-1:0] sel;
    always @* begin
        int n;
        n = 0;
        sel = '0;
        for (int j = 0; j < E; j++) begin
            lane_v[j] = 1'b0;
            lane_e[j] = 6'd0;
        end
        for (int k = 0; k < ME; k++)
            if (rem_in[k] && n < E) begin
                lane_v[n] = 1'b1;
                lane_e[n] = 6'(k);
                sel[k] = 1'b1;
                n = n + 1;
            end
        for (int j = 0; j < E; j++)
            rd_idx[j*6 +: 6] = lane_e[j];
    end

    // the parent's h_tl of each lane's edge
    wire [4:0] plvl = lvl == 5'd0 ? 5'd0 : lvl - 5'd1;
    logic [EW-1:0] lane_par [0:E-1];
    generate
        for (genvar j = 0; j < E; j++) begin : g_parent
            assign lane_par[j] = lvl_h[32'(plvl) * ME + 32'(lane_e[j])];
        end
    endgenerate

    // the edge units: each an edge's corners over the cell, by adds and shifts
    logic [EW-1:0] lane_h [0:E-1];
    logic [E-1:0]  lane_out, lane_inside, lane_centre_in;
    always @* begin
        for (int j = 0; j < E; j++) begin
            logic signed [EW-1:0] par, da, db, h, hmin, hmax, centre;
            // level 0 is the screen: its corners come from the edge store
            par = lvl == 5'd0 ? $signed(rd_c[j*EW +: EW]) : $signed(lane_par[j]);
            da = $signed(rd_da[j*EW +: EW]) >>> sha;
            db = $signed(rd_db[j*EW +: EW]) >>> shb;
            h = par + (dx ? da : '0) + (dy ? db : '0);
            hmin = h + (da < 0 ? da : '0) + (db < 0 ? db : '0);
            hmax = h + (da > 0 ? da : '0) + (db > 0 ? db : '0);
            centre = h + (da >>> 1) + (db >>> 1);        // the sample's centre
            lane_h[j] = h;
            lane_out[j] = lane_v[j] && hmax < 0;
            lane_inside[j] = lane_v[j] && hmin >= 0;
            lane_centre_in[j] = !lane_v[j] || centre >= 0;
        end
    end

    logic [ME-1:0] inside_mask;
    always @* begin
        inside_mask = '0;
        for (int j = 0; j < E; j++)
            if (lane_inside[j])
                inside_mask = inside_mask | ME'(1) << lane_e[j];
    end

    wire [ME-1:0] rem_after = rem_in & ~sel;
    wire          last = rem_after == '0;
    wire          out_now = out_in || |lane_out;
    wire [ME-1:0] act_now = act_in & ~inside_mask;
    wire          in_now = in_in && &lane_centre_in;
    wire [2:0]    verdict = single ? (in_now ? `R_SAMPLE_IN : `R_SAMPLE_OUT)
                          : out_now ? `R_OUT : act_now == '0 ? `R_FILL : `R_SPLIT;
    wire          fills = verdict == `R_FILL || verdict == `R_SAMPLE_IN;
    wire          decided = working && last;
    wire          split = decided && verdict == `R_SPLIT;
    // the step done: handed over (or nothing to hand over), or a stall ends
    wire          advance = (decided && !(fills && q_full)) || (busy && stalled && !q_full);

    // children
    wire [3:0]  cwl = wl != 5'd0 ? 4'(wl - 5'd1) : 4'd0;
    wire [3:0]  chl = hl != 5'd0 ? 4'(hl - 5'd1) : 4'd0;
    wire [XB-1:0] c_right = c0 + (XB'(1) << cwl);
    wire [YB-1:0] r_below = r0 + (YB'(1) << chl);
    wire [SPW-1:0] sp_top = sp - SPW'(1);
    wire [AW-1:0]  at0 = AW'(sp), at1 = AW'(sp + SPW'(1)), at2 = AW'(sp + SPW'(2)), attop = AW'(sp_top);

    assign enq = (decided && fills && !q_full) || (busy && stalled && !q_full);
    assign enq_cell = {lvl, hl, wl, 16'(r0), 16'(c0)};
    assign face_done = advance && !split && sp == '0;
    assign busy_next = (start || busy) && !face_done;

    assign ev_start = start;
    assign ev_cell = decided;
    assign ev_cell_result = verdict;
    assign ev_cell_edges = n_in;
    assign ev_cell_cell = {lvl, hl, wl, 16'(r0), 16'(c0)};
    assign ev_end = face_done;
    assign ev_face = head_id;
    assign ev_slot = head_slot;

    always_ff @(posedge clk) begin
        if (working)
            for (int j = 0; j < E; j++)
                if (lane_v[j] && 32'(lvl) < P)
                    lvl_h[32'(lvl) * ME + 32'(lane_e[j])] <= lane_h[j];
        if (split) begin
            // push the siblings, bottom-right deepest, so top-right pops next
            if (wl != 5'd0 && hl != 5'd0) begin
                stk_c0[at0] <= c_right;
                stk_r0[at0] <= r_below;
                stk_c0[at1] <= c0;
                stk_r0[at1] <= r_below;
                stk_c0[at2] <= c_right;
                stk_r0[at2] <= r0;
                stk_lvl[at0] <= lvl + 5'd1;
                stk_lvl[at1] <= lvl + 5'd1;
                stk_lvl[at2] <= lvl + 5'd1;
                stk_act[at0] <= act_now;
                stk_act[at1] <= act_now;
                stk_act[at2] <= act_now;
            end else begin
                stk_c0[at0] <= wl != 5'd0 ? c_right : c0;
                stk_r0[at0] <= wl != 5'd0 ? r0 : r_below;
                stk_lvl[at0] <= lvl + 5'd1;
                stk_act[at0] <= act_now;
            end
        end
        if (rst) begin
            busy <= 1'b0;
            stalled <= 1'b0;
            sp <= '0;
        end else begin
            busy <= busy_next;
            if (working && !last) begin
                // the step goes on: the cell stays, the next E edges
                cur_c0 <= c0;
                cur_r0 <= r0;
                cur_lvl <= lvl;
                cur_n <= n_in;
                rem <= rem_after;
                acc_out <= out_now;
                acc_in <= in_now;
                acc_act <= act_now;
            end else if (decided && !advance) begin
                // the queue is full: hold the cell until it is handed over
                stalled <= 1'b1;
                cur_c0 <= c0;
                cur_r0 <= r0;
                cur_lvl <= lvl;
                cur_n <= n_in;
            end else if (advance) begin
                stalled <= 1'b0;
                if (split) begin
                    // the top-left child is the next step
                    cur_c0 <= c0;
                    cur_r0 <= r0;
                    cur_lvl <= lvl + 5'd1;
                    cur_n <= popcount(act_now);
                    rem <= act_now;
                    acc_act <= act_now;
                    sp <= sp + (wl != 5'd0 && hl != 5'd0 ? SPW'(3) : SPW'(1));
                end else if (sp != '0) begin
                    cur_c0 <= stk_c0[attop];
                    cur_r0 <= stk_r0[attop];
                    cur_lvl <= stk_lvl[attop];
                    cur_n <= popcount(stk_act[attop]);
                    rem <= stk_act[attop];
                    acc_act <= stk_act[attop];
                    sp <= sp_top;
                end
                acc_out <= 1'b0;
                acc_in <= 1'b1;
            end
        end
    end
endmodule
