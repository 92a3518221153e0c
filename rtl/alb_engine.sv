// alb_engine — the subdivision engine (docs/microarchitecture.md; docs/vp.md
// §2-§3): walks the oldest loaded face's cells from the top cell down, one
// step per cell, children top-left, top-right, bottom-left, bottom-right.  A
// step evaluates the cell's active edges E at a time (E = edge_units) and
// takes max(1, ceil(active / E)) cycles; a filled cell or a single sample
// inside is handed to the fill queue in the step's last cycle, or the engine
// stalls until the queue has room.
//
// Multiplier-free (docs/vp.md §2): an edge's h = a C + b R + c is linear, so
// over a cell of level l its corners are h_tl + {0, dA_l} + {0, dB_l}, dA_l
// the screen's increment halved min(l, LW) times (exact: dA is a multiple of
// 2^(LW+1), dB of 2^(LH+1)), and a child's h_tl is its parent's plus dA_l or
// dB_l where it lies right or below — the mean of two corners.  The engine
// holds h times 2^l (below 2^(EW-1+l): no corner or centre of the screen
// overflows EW bits, docs/vp.md §2), so a child's is twice its parent's plus
// dA or dB themselves, and the corners need no shift by the level.  It keeps,
// per level, the last cell's h_tl of every edge it evaluated (lvl_h): that
// cell is the parent of every cell popped at the next level (the walk is
// depth-first).  For the same reason at most one parent per level has
// children left, so the stack has one entry a level — which child is next and
// the parent's active edges; the parent's position is the current cell's cut
// to the parent's size.  lvl_h and the edge store are read a cycle ahead
// (block RAM on an FPGA), at addresses from the step's next state (rd_next),
// this cycle's writes forwarded.  Adders, comparators and fixed shifts only:
// no `*` (checked by yosys in tests/cosim.sh).
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
    output logic [E*6-1:0]        rd_next,      // the edges the next cycle evaluates
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
    localparam int ME = MAX_EDGES;
    localparam int EB = ME > 1 ? $clog2(ME) : 1;     // an edge's index in an address
    localparam int LB = P > 1 ? $clog2(P) : 1;       // a parent level's in an address
    localparam int HA = LB + EB;
    localparam int HW = EW + P;              // h times 2^level
    localparam logic [ME-1:0] FIRST_E = E >= ME ? {ME{1'b1}} : (ME'(1) << E) - ME'(1);

    // ---- state ----
    logic              stalled;
    // positions: below 2^LW, 2^LH (a cell's corner in the sample grid), held
    // at LW + 1, LH + 1 bits, 16 at the ports
    localparam int XB = LW + 1, YB = LH + 1;
    logic [XB-1:0]     cur_c0;
    logic [YB-1:0]     cur_r0;
    logic [4:0]        cur_lvl;
    logic              cur_dx, cur_dy;       // the cell's offset in its parent
    logic [6:0]        cur_n;                // active edges when the step began
    logic [ME-1:0]     rem;                  // edges of the step not evaluated yet
    logic              acc_out, acc_in;
    logic [ME-1:0]     acc_act;
    // the stack, one entry per parent level: whether a child is still to
    // walk, which (its offset {dy, dx} in the parent) and the parent's
    // active edges; the parent's position is the current cell's, cut to the
    // parent's size
    logic [P-1:0]      stk_pend;
    logic [1:0]        stk_next [0:P-1];
    logic [ME-1:0]     stk_act [0:P-1];
    logic [HW-1:0]     lvl_h [0:(P << EB)-1];   // per level: h_tl (x 2^level) of the last cell evaluated

    function automatic [6:0] popcount(input [ME-1:0] m);
        logic [6:0] n;
        n = 7'd0;
        for (int k = 0; k < ME; k++)
            n = n + 7'(m[k]);
        popcount = n;
    endfunction

    // a cell of level l is 2^wl x 2^hl samples; a side one sample long is not split
    function automatic [4:0] wl_of(input [4:0] l);
        wl_of = l < 5'(LW) ? 5'(LW) - l : 5'd0;
    endfunction
    function automatic [4:0] hl_of(input [4:0] l);
        hl_of = l < 5'(LH) ? 5'(LH) - l : 5'd0;
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
    wire [4:0]    wl = wl_of(lvl);
    wire [4:0]    hl = hl_of(lvl);
    wire          single = wl == 5'd0 && hl == 5'd0;
    // the cell's offset in its parent: the bit of its position at its own size
    // (the walk knows it: 0 for the screen and a top-left child, the
    // stack's offset for a child popped)
    wire          dx = start ? 1'b0 : cur_dx;
    wire          dy = start ? 1'b0 : cur_dy;
    // halvings of dA to this cell's width, of dB to its height (at most LW, LH)
    // h is held times 2^level (exact: below 2^(EW-1) unscaled, docs/vp.md
    // §2), so the increments need no shift by the level: a cell's dA is the
    // screen's halved min(level, LW) times, times 2^level.  Past LW (a grid
    // higher than wide) that is dA shifted up by level - LW.
    localparam int UA = LH > LW ? LH - LW : 0, UB = LW > LH ? LW - LH : 0;
    localparam int UAW = $clog2(UA + 1) > 0 ? $clog2(UA + 1) : 1;
    localparam int UBW = $clog2(UB + 1) > 0 ? $clog2(UB + 1) : 1;
    wire [UAW-1:0] ua = UA == 0 || lvl <= 5'(LW) ? '0 : UAW'(lvl - 5'(LW));
    wire [UBW-1:0] ub = UB == 0 || lvl <= 5'(LH) ? '0 : UBW'(lvl - 5'(LH));

    // The next E active edges, lowest index first, were picked a cycle ago
    // from the step's next state (pick_q, below), so that the edge store
    // and lvl_h are read a cycle ahead, as block RAM answers.  A face's
    // first step evaluates edges 0 .. E-1 (those it has).
    logic [E-1:0]  lane_v, pick_v, pick_vq;
    logic [5:0]    lane_e [0:E-1];
    logic [5:0]    pick_e [0:E-1];
    logic [5:0]    pick_eq [0:E-1];
    logic [ME-1:0] sel, pick_sel, pick_selq;
    always @* begin
        sel = start ? face_mask & FIRST_E : pick_selq;
        for (int j = 0; j < E; j++) begin
            lane_v[j] = start ? j < ME && face_mask[j < ME ? j : 0] : pick_vq[j];
            lane_e[j] = start ? 6'(j) : pick_eq[j];
        end
    end

    // the parent's h_tl of each lane's edge
    logic [HW-1:0] lane_par [0:E-1];

    // the edge units: each an edge's corners over the cell, by adds and shifts
    logic [HW-1:0] lane_h [0:E-1];
    logic [E-1:0]  lane_out, lane_inside, lane_centre_in;
    always @* begin
        for (int j = 0; j < E; j++) begin
            logic signed [HW-1:0] da, db, par, h, h_a, h_b, h_ab;
            logic signed [HW:0]   centre2;
            logic min_neg, max_neg;
            // the increments at this level, times 2^level: dA, dB themselves
            // (the low LW + 1 bits of dA, LH + 1 of dB are zero: the parser's
            // shifts), or shifted up past the level where a side stops splitting
            da = HW'($signed({rd_da[j*EW + LW + 1 +: EW - LW - 1], (LW + 1)'(0)})) <<< ua;
            db = HW'($signed({rd_db[j*EW + LH + 1 +: EW - LH - 1], (LH + 1)'(0)})) <<< ub;
            // level 0 is the screen: its corners come from the edge store;
            // below, twice the parent's (one level finer)
            par = lvl == 5'd0 ? HW'($signed(rd_c[j*EW +: EW])) : $signed(lane_par[j]) <<< 1;
            h = par + (dx ? da : '0) + (dy ? db : '0);
            // the corners; the least is h + min(dA, 0) + min(dB, 0), the
            // greatest h + max(dA, 0) + max(dB, 0): picked by the signs
            h_a = h + da;
            h_b = h + db;
            h_ab = h_a + db;
            min_neg = da[HW-1] ? (db[HW-1] ? h_ab[HW-1] : h_a[HW-1])
                               : (db[HW-1] ? h_b[HW-1] : h[HW-1]);
            max_neg = !da[HW-1] ? (!db[HW-1] ? h_ab[HW-1] : h_a[HW-1])   // (an
                                : (!db[HW-1] ? h_b[HW-1] : h[HW-1]);    // increment 0 adds 0)
            // the sample's centre, doubled: h + h_ab = 2 h + dA + dB
            centre2 = {h[HW-1], h} + {h_ab[HW-1], h_ab};
            lane_h[j] = h;
            lane_out[j] = lane_v[j] && max_neg;
            lane_inside[j] = lane_v[j] && !min_neg;
            lane_centre_in[j] = !lane_v[j] || !centre2[HW];
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

    // the stack's top: the deepest parent with a child left, and that child
    logic [4:0]    top_l;
    logic [1:0]    top_next;
    logic [ME-1:0] top_act;
    always @* begin
        top_l = 5'd0;
        top_next = 2'd0;
        top_act = '0;
        for (int l = 0; l < P; l++)
            if (stk_pend[l]) begin
                top_l = 5'(l);
                top_next = stk_next[l];
                top_act = stk_act[l];
            end
    end
    wire          pending = |stk_pend;
    wire          pop = advance && !split && pending;
    wire [4:0]    pwl = wl_of(top_l), phl = hl_of(top_l);
    // the child: the parent's corner (this cell's, its low bits cut) plus
    // half the parent's side where the child lies right or below
    wire [XB-1:0] pop_c0 = (c0 & ~((XB'(1) << pwl) - XB'(1)))
                         | (top_next[0] ? XB'(1) << (pwl - 5'd1) : '0);
    wire [YB-1:0] pop_r0 = (r0 & ~((YB'(1) << phl) - YB'(1)))
                         | (top_next[1] ? YB'(1) << (phl - 5'd1) : '0);
    // children after the top-right: bottom-left, bottom-right, when both sides split
    wire          top_more = pwl != 5'd0 && phl != 5'd0 && top_next != 2'd3;

    assign enq = (decided && fills && !q_full) || (busy && stalled && !q_full);
    assign enq_cell = {lvl, hl, wl, 16'(r0), 16'(c0)};
    assign face_done = advance && !split && !pending;
    assign busy_next = (start || busy) && !face_done;

    assign ev_start = start;
    assign ev_cell = decided;
    assign ev_cell_result = verdict;
    assign ev_cell_edges = n_in;
    assign ev_cell_cell = {lvl, hl, wl, 16'(r0), 16'(c0)};
    assign ev_end = face_done;
    assign ev_face = head_id;
    assign ev_slot = head_slot;

    // ---- the next state of the step ----
    // the next step's active edges, counted: a split's or the popped child's
    wire [6:0]     next_n = popcount(split ? act_now : top_act);
    logic [XB-1:0] c0_d;
    logic [YB-1:0] r0_d;
    logic [4:0]    lvl_d;
    logic          dx_d, dy_d;
    logic [6:0]    n_d;
    logic [ME-1:0] rem_d, act_d;
    logic          out_d, in_d, stalled_d;
    always @* begin
        c0_d = cur_c0;
        r0_d = cur_r0;
        lvl_d = cur_lvl;
        dx_d = cur_dx;
        dy_d = cur_dy;
        n_d = cur_n;
        rem_d = rem;
        act_d = acc_act;
        out_d = acc_out;
        in_d = acc_in;
        stalled_d = stalled;
        if (working && !last) begin
            // the step goes on: the cell stays, the next E edges
            c0_d = c0;
            r0_d = r0;
            lvl_d = lvl;
            dx_d = dx;
            dy_d = dy;
            n_d = n_in;
            rem_d = rem_after;
            out_d = out_now;
            in_d = in_now;
            act_d = act_now;
        end else if (decided && !advance) begin
            // the queue is full: hold the cell until it is handed over
            stalled_d = 1'b1;
            c0_d = c0;
            r0_d = r0;
            lvl_d = lvl;
            dx_d = dx;
            dy_d = dy;
            n_d = n_in;
        end else if (advance) begin
            stalled_d = 1'b0;
            if (split) begin
                // the top-left child is the next step
                c0_d = c0;
                r0_d = r0;
                lvl_d = lvl + 5'd1;
                dx_d = 1'b0;
                dy_d = 1'b0;
                n_d = next_n;
                rem_d = act_now;
                act_d = act_now;
            end else if (pending) begin
                c0_d = pop_c0;
                r0_d = pop_r0;
                lvl_d = top_l + 5'd1;
                dx_d = top_next[0];
                dy_d = top_next[1];
                n_d = next_n;
                rem_d = top_act;
                act_d = top_act;
            end
            out_d = 1'b0;
            in_d = 1'b1;
        end
    end

    // the next step's edges: the first E of rem_d, or a new face's 0 .. E-1
    // (only their indices then: its first step's lanes come from head_edges)
    always @* begin
        int n;
        n = 0;
        pick_sel = '0;
        for (int j = 0; j < E; j++) begin
            pick_v[j] = 1'b0;
            pick_e[j] = 6'd0;
        end
        if (E == 1) begin
            pick_sel = rem_d & (~rem_d + ME'(1));     // the lowest bit set
            pick_v[0] = rem_d != '0;
            for (int k = 0; k < ME; k++)
                if (pick_sel[k])
                    pick_e[0] = pick_e[0] | 6'(k);
        end else
        for (int k = 0; k < ME; k++)
            if (rem_d[k] && n < E) begin
                pick_v[n] = 1'b1;
                pick_e[n] = 6'(k);
                pick_sel[k] = 1'b1;
                n = n + 1;
            end
        for (int j = 0; j < E; j++)
            rd_next[j*6 +: 6] = busy_next ? pick_e[j] : 6'(j);
    end

    // lvl_h, read a cycle ahead at the next step's parent level; a value
    // written this cycle (a split's last edges, read by its first child) is
    // forwarded
    wire [LB-1:0] plvl_d = lvl_d == 5'd0 ? '0 : LB'(lvl_d - 5'd1);
    logic [HA-1:0] h_wa [0:E-1];
    logic [HA-1:0] h_ra [0:E-1];
    logic [E-1:0]  h_we;
    logic [HW-1:0] h_q [0:E-1];
    logic [HW-1:0] h_wq [0:E-1];
    logic [E*E-1:0] h_hit;                  // [j*E + k]: lane j reads what lane k wrote
    always @* begin
        for (int j = 0; j < E; j++) begin
            h_we[j] = working && lane_v[j] && 32'(lvl) < P;
            h_wa[j] = {LB'(lvl), EB'(lane_e[j])};
            h_ra[j] = {plvl_d, EB'(pick_e[j])};   // (the screen's step reads none)
        end
        for (int j = 0; j < E; j++) begin
            lane_par[j] = h_q[j];
            for (int k = 0; k < E; k++)
                if (h_hit[j*E + k])
                    lane_par[j] = h_wq[k];
        end
    end

    always_ff @(posedge clk)
        for (int j = 0; j < E; j++) begin
            if (h_we[j])
                lvl_h[h_wa[j]] <= lane_h[j];
            h_q[j] <= lvl_h[h_ra[j]];
        end

    always_ff @(posedge clk) begin
        for (int j = 0; j < E; j++) begin
            h_wq[j] <= lane_h[j];
            for (int k = 0; k < E; k++)
                h_hit[j*E + k] <= h_we[k] && h_wa[k] == h_ra[j];
            pick_eq[j] <= pick_e[j];
        end
        pick_vq <= pick_v;
        pick_selq <= pick_sel;
        if (split) begin
            // the parent's children after the top-left: top-right (or the
            // bottom-left if the sides do not split), then bottom-left, bottom-right
            stk_next[LB'(lvl)] <= wl != 5'd0 ? 2'd1 : 2'd2;
            stk_act[LB'(lvl)] <= act_now;
        end else if (pop && top_more)
            stk_next[LB'(top_l)] <= top_next + 2'd1;
        if (rst) begin
            busy <= 1'b0;
            stalled <= 1'b0;
            stk_pend <= '0;
        end else begin
            busy <= busy_next;
            stalled <= stalled_d;
            if (split)
                stk_pend[LB'(lvl)] <= 1'b1;
            else if (pop && !top_more)
                stk_pend[LB'(top_l)] <= 1'b0;
        end
        cur_c0 <= c0_d;
        cur_r0 <= r0_d;
        cur_lvl <= lvl_d;
        cur_dx <= dx_d;
        cur_dy <= dy_d;
        cur_n <= n_d;
        rem <= rem_d;
        acc_out <= out_d;
        acc_in <= in_d;
        acc_act <= act_d;
    end
endmodule
