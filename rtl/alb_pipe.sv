// alb_pipe — the depth/shade pipeline (docs/microarchitecture.md; the
// arithmetic of docs/vp.md §4-§5 and vp/units.h): RATE lanes, L = 1 +
// DIV_LAT + SHADE_LAT stages, fully pipelined.  A sample issued in cycle t
// is written (colour, face id, level) at the end of cycle t + L - 1 if it won
// the depth test.
//
// The units, as steps with a register boundary after each (alb_pipe_reg):
//
//   S1  the four linear forms at the sample (depth, shade, u, v)
//   S2  the depth store format and the depth test; the reciprocal's index
//   S3  the reciprocal ROM; the forms times the reciprocal; fog distance
//   S4  intensity (eq. 7) and the texture fractions; fog near/far and the
//       first bits of the visibility's division
//   S5  texture memory; base x texel x intensity; more division bits
//   S6  the colour output stage's scale and the first bits of its division
//   S7  the rest of both divisions
//   S8  fog blend
//
// The L - 1 boundaries the profile's latencies give are used from the first
// on (A between S1 and S2 only with ZR_REG, below), those left over are wires;
// stages the steps do not need delay the result to t + L - 1.  A boundary
// before a memory makes its read synchronous (the reciprocal ROM, texture
// memory): what a block RAM does.
//
// The depth test: with ZR_REG = 0 it is in the first stage — the depth store
// read (answered in the same cycle) and written in the cycle the sample is
// issued.  With ZR_REG = 1 (a block RAM) the read address goes out in the
// first stage, the data comes back in the second, where the sample is tested
// and written; a sample of the previous cycle's second stage written to the
// same place at the end of that cycle is forwarded (the read missed it).  In
// both, later samples see the depths of earlier ones (docs/cosim.md, "What
// an RTL may do differently").
//
// Widths follow the profile: a form's value at a sample is below
// 2^(CB + P + 1) (docs/profiles.md), so NB = CB + P + 2 signed bits hold it
// and modular arithmetic in them is exact; a form times the reciprocal needs
// NB + RB + 1.  The narrow products (a form's steps times the sample's
// LW- and LH-bit position, the fog blend, one channel of base x texel) are
// shifts and adds; the wide ones (the forms times the reciprocal, x
// intensity, two channels of base x texel) multipliers, which the UP5K's 8
// DSPs hold (docs/fpga.md, "Products as shifts and adds").
//
// Units left out (SHADE_UNIT, TEX_UNIT, FOG_UNIT 0; the parser refuses what
// would need them, E_UNIT) are not built: their generate blocks drive their
// results as constants — intensity 1.0, the white texel, no fog — and the
// stage registers that would carry their values carry zeros, which synthesis
// drops; the stages, and so L, stay as they are.  The shade form needs the
// reciprocal and a form times it, texture the u and v forms, the reciprocal,
// two products and texture memory, fog the reciprocal and the visibility's
// division; the reciprocal ROM is built if any of the three is.
`include "alb_defs.svh"

module alb_pipe #(
    parameter int RATE = 4,
    parameter int LW = 5,
    parameter int LH = 5,
    parameter int CB = 24,              // coef_bits
    parameter int DB = 24,              // depth_bits
    parameter int COLB = 8,             // colour_bits
    parameter int RB = 16,              // recip_bits
    parameter int FI = 12,              // shade_frac_bits
    parameter int DIV_LAT = 8,          // divider_latency
    parameter int SHADE_LAT = 4,        // shade_latency
    parameter int TEX_WORDS = 65536,
    parameter int ZR_REG = 0,           // 1: the depth store answers in the next cycle
    parameter int SHADE_UNIT = 1,       // 0: no Gouraud intensity (eq. 7): 1.0
    parameter int TEX_UNIT = 1,         // 0: no texture memory or addressing: white texels
    parameter int FOG_UNIT = 1          // 0: no fog distance, visibility or blend
) (
    input  logic                      clk,
    input  logic                      rst,
    // the samples issued this cycle (alb_fill)
    input  logic [RATE-1:0]           lane_v,
    input  logic [RATE*16-1:0]        lane_x,
    input  logic [RATE*16-1:0]        lane_y,
    input  logic [`SETUP_W-1:0]       setup,
    input  logic [4:0]                level,
    // the drawing frame's fog registers (constant while samples are in flight:
    // they change when a frame retires, after its last write)
    input  logic                      fog_on,
    input  logic [3*COLB-1:0]         fog_rgb,
    input  logic [31:0]               fog_near,
    input  logic [31:0]               fog_far,
    // the depth store: read at lane_x, lane_y (in this cycle, or with ZR_REG
    // answered in the next) and written at zw_x, zw_y at the end of the cycle
    input  logic [RATE*DB-1:0]        zr_data,
    output logic [RATE-1:0]           zw_en,
    output logic [RATE*16-1:0]        zw_x,
    output logic [RATE*16-1:0]        zw_y,
    output logic [RATE*DB-1:0]        zw_data,
    // the last stage: the samples that won, written at the end of the cycle
    output logic [RATE-1:0]           cw_en,
    output logic [RATE*16-1:0]        cw_x,
    output logic [RATE*16-1:0]        cw_y,
    output logic [RATE*DB-1:0]        cw_depth,
    output logic [RATE*3*COLB-1:0]    cw_rgb,
    output logic [31:0]               cw_face,
    output logic [7:0]                cw_level,
    // texture memory's write port (alb_parser)
    input  logic                      tw_en,
    input  logic [$clog2(TEX_WORDS)-1:0] tw_addr,
    input  logic [23:0]               tw_data,
    // samples in the stage registers (stages 2..L) at the start of the cycle
    output logic                      busy,
    // samples in stages 1..L-1 this cycle: written after this cycle
    output logic                      busy_before_last
);
    localparam int L = 1 + DIV_LAT + SHADE_LAT;
    localparam int P = LW > LH ? LW : LH;
    localparam int TA = $clog2(TEX_WORDS);
    localparam int NB = CB + P + 2;                 // a form at a sample, signed
    localparam int PW = NB + RB + 1;                // ... times the reciprocal
    localparam int KW = 12;                         // shift amounts, signed
    localparam int MW = 16 + FI;                    // base x texel x intensity
    localparam int XW = 17 + COLB;                  // the colour before / 65025
    localparam int ROM_N = 1 << (RB - 1);
    // base x texel: how many of the three channels' 8 x 8 products are left
    // as multipliers.  On the iCE40 UP5K (8 SB_MAC16, docs/fpga.md) the
    // wider products — the forms times the reciprocal, x intensity — take 6
    // a lane and two of base x texel fill the part; the forms at the sample
    // and the fog blend are shifts and adds, cheaper in logic than these
    localparam int BT_DSP = 2;
    localparam logic [FI:0] ONE = (FI + 1)'(1) << FI;          // intensity 1.0
    localparam logic [DB-1:0] DMAX = {DB{1'b1}};   // the largest depth (yosys 0.23 reads '1 here as 1)
    localparam logic [XW-1:0] D65025 = XW'(65025);
    // a sample's record from the depth test to the write
    localparam int WR = 1 + LW + LH + DB;
    // a form's value beside the depth store's and the reciprocal's widths
    localparam int DW = NB > DB ? NB : DB;
    localparam int DMW = NB > RB ? NB : RB;

    // ---- the stage boundaries in use (see the header) ----
    localparam int NA = L - 1;
    localparam int IB = ZR_REG != 0 ? 1 : 0;
    localparam bit ON_A = ZR_REG != 0;
    localparam bit ON_B = IB < NA;
    localparam bit ON_C = IB + 1 < NA;
    localparam bit ON_D = IB + 2 < NA;
    localparam bit ON_E = IB + 3 < NA;
    localparam bit ON_F = IB + 4 < NA;
    localparam bit ON_G = IB + 5 < NA;
    localparam int USED = (ON_A ? 1 : 0) + (ON_B ? 1 : 0) + (ON_C ? 1 : 0) + (ON_D ? 1 : 0) +
                          (ON_E ? 1 : 0) + (ON_F ? 1 : 0) + (ON_G ? 1 : 0);
    localparam int TAIL = NA - USED;
    // the visibility's division, FI quotient bits over S4..S7; the colour's,
    // COLB bits over S6 and S7
    localparam int V4 = (FI + 3) / 4, V5 = (FI + 2) / 4, V6 = (FI + 1) / 4, V7 = FI / 4;
    localparam int C6 = (COLB + 1) / 2;
    // the units built (the header); the reciprocal for any of them
    localparam bit SHADE = SHADE_UNIT != 0;
    localparam bit TEX = TEX_UNIT != 0;
    localparam bit FOG = FOG_UNIT != 0;
    localparam bit RECIP = SHADE || TEX || FOG;
    // neither shade nor texture: the parser has scaled the face's colour to
    // the frame store (alb_parser's FLAT_RGB), and the output stage's
    // product and division go too
    localparam bit FLAT_RGB = !SHADE && !TEX && 3 * COLB <= 24;

    // ---- the units (vp/units.h), at the widths of the profile ----
    // N of a form at sample (x, y): origin + x step_c + y step_r, modulo 2^NB.
    // x and y are LW and LH bits: the products as shifts and adds (a step
    // shifted by each set bit of the position), not multipliers — the same
    // bits modulo 2^NB, and no DSP for an NB x LW product
    function automatic signed [NB-1:0] form_at(input signed [NB-1:0] o, input signed [NB-1:0] sc,
                                               input signed [NB-1:0] sr, input [LW-1:0] x,
                                               input [LH-1:0] y);
        // (bits below k of a step shifted by k are 0: each add is NB - k
        // bits wide, the bits below it pass through)
        logic [NB-1:0] acc;
        acc = o;
        for (int k = 0; k < LW; k++)
            if (x[k])
                acc = ((((acc >> k) + sc) << k) | (acc & ~({NB{1'b1}} << k)));
        for (int k = 0; k < LH; k++)
            if (y[k])
                acc = ((((acc >> k) + sr) << k) | (acc & ~({NB{1'b1}} << k)));
        form_at = acc;
    endfunction

    // a x b, 8 x 8 bits, as shifts and adds: a shifted by each set bit of b
    // (DSPs are kept for the wider products)
    function automatic [15:0] mul8(input [7:0] a, input [7:0] b);
        logic [15:0] acc;
        acc = '0;
        for (int k = 0; k < 8; k++)
            if (b[k])
                acc = ((((acc >> k) + 16'(a)) << k) | (acc & ~(16'hFFFF << k)));
        mul8 = acc;
    endfunction

    // the depth store value: near/Z as unsigned 0.DB, truncated, saturated
    // (nearer than near), 0 behind the observer (docs/vp.md §4)
    function automatic [DB-1:0] depth_of(input signed [NB-1:0] n, input signed [KW-1:0] sh);
        logic [DW-1:0] s;
        if (n <= 0)
            depth_of = '0;
        else if (sh >= 0) begin
            if (sh >= KW'(DB) || DW'(n) > (DW'(DMAX) >> sh))
                depth_of = DMAX;
            else
                depth_of = DB'(DW'(n) << sh);
        end else begin
            s = DW'(n) >> (-sh);
            // (never true when DW = DB, as at up5k's widths)
            /* verilator lint_off CMPCONST */
            depth_of = s > DW'(DMAX) ? DMAX : DB'(s);
            /* verilator lint_on CMPCONST */
        end
    endfunction

    // the number of significant bits: a priority encoder
    function automatic [7:0] bitlen(input [NB-1:0] v);
        bitlen = 8'd0;
        for (int k = 0; k < NB; k++)
            if (v[k])
                bitlen = 8'(k + 1);
    endfunction

    // floor(p 2^k) clamped to [0, ONE]: the intensity of eq. (7)
    function automatic [FI:0] intensity_of(input signed [PW-1:0] p, input signed [KW-1:0] k);
        logic [PW+FI:0] wide;
        logic [PW-1:0] v;
        if (p <= 0)
            intensity_of = '0;
        else if (k > KW'(FI))
            intensity_of = ONE;
        else if (k >= 0) begin
            wide = (PW + FI + 1)'(p) << k;
            intensity_of = wide > (PW + FI + 1)'(ONE) ? ONE : wide[FI:0];
        end else begin
            v = -k >= KW'(PW) ? '0 : PW'(p) >> (-k);
            intensity_of = v > PW'(ONE) ? ONE : v[FI:0];
        end
    endfunction

    // floor(p 2^k) mod 2^lg: a texture coordinate's fraction (units_fraction)
    function automatic [9:0] fraction_of(input signed [PW-1:0] p, input signed [KW-1:0] k,
                                         input [3:0] lg);
        logic [9:0] m;
        logic signed [KW-1:0] nk;
        m = (10'd1 << lg) - 10'd1;
        nk = -k;
        if (k >= KW'(10))
            fraction_of = 10'd0;
        else if (k >= 0)
            fraction_of = 10'(p << k) & m;
        else
            fraction_of = 10'(p >>> (nk >= KW'(PW) ? KW'(PW - 1) : nk)) & m;
    endfunction

    // Z/near in 24.8 through the reciprocal, floor(rm 2^k); only its order
    // against the 32-bit fog distances matters, so it saturates at 2^32
    function automatic [32:0] fog_distance(input [RB:0] rm, input signed [KW-1:0] k);
        logic [32+RB+1:0] w;
        logic signed [KW-1:0] nk;
        nk = -k;
        if (k >= 0) begin
            if (k >= KW'(33))
                fog_distance = 33'd1 << 32;
            else begin
                w = (34 + RB)'(rm) << k;
                fog_distance = w >= ((34 + RB)'(1) << 32) ? 33'd1 << 32 : w[32:0];
            end
        end else
            fog_distance = nk >= KW'(RB + 1) ? 33'd0 : 33'(rm) >> nk;
    endfunction

    // n steps of restoring division: the remainder r (below d) doubled, d
    // taken off where it goes, the quotient bit shifted in
    function automatic [33+FI-1:0] div_steps(input [32:0] r, input [FI-1:0] q, input [31:0] d,
                                             input int n);
        logic [33:0] rr;
        logic [32:0] r2;
        logic [FI-1:0] q2;
        r2 = r;
        q2 = q;
        for (int i = 0; i < n; i++) begin
            rr = {r2, 1'b0};
            q2 = q2 << 1;
            if (rr >= 34'(d)) begin
                rr = rr - 34'(d);
                q2[0] = 1'b1;
            end
            r2 = rr[32:0];
        end
        div_steps = {r2, q2};
    endfunction

    // quotient bits hi down to lo of x / 65025 (the colour output stage)
    function automatic [XW+COLB-1:0] col_div(input [XW-1:0] x, input [COLB-1:0] q, input int hi,
                                             input int lo);
        logic [XW-1:0] r;
        logic [COLB-1:0] q2;
        r = x;
        q2 = q;
        for (int i = hi; i >= lo; i--)
            if (r >= D65025 << i) begin
                r = r - (D65025 << i);
                q2[i] = 1'b1;
            end
        col_div = {r, q2};
    endfunction

    // base x texel x intensity to the frame store, round half up
    // (units_output): floor((2 m TOP + 65025 2^FI) / 2^(FI+1)) before / 65025
    function automatic [XW-1:0] colour_scale(input [MW-1:0] m);
        logic [MW+COLB+2:0] t;
        t = ((MW + COLB + 3)'(m) << (COLB + 1)) - ((MW + COLB + 3)'(m) << 1)
          + ((MW + COLB + 3)'(65025) << FI);
        colour_scale = XW'(t >> (FI + 1));
    endfunction

    // blend toward the fog colour, round half up: (c vis + f (ONE - vis) +
    // ONE/2) >> FI, computed as (f ONE + (c - f) vis + ONE/2) >> FI.  The
    // product of the COLB + 1-bit signed difference and vis as shifts and
    // adds: vis shifted by each set bit of df, the sign bit's weight taken
    // off (two's complement), modulo 2^(COLB + FI + 4) where t is exact
    function automatic [COLB-1:0] fog_blend(input [COLB-1:0] c, input [COLB-1:0] f,
                                            input [FI:0] vis);
        logic [COLB+FI+3:0] t;
        logic [COLB:0] df;
        df = {1'b0, c} - {1'b0, f};
        t = ((COLB + FI + 4)'(f) << FI) + ((COLB + FI + 4)'(ONE) >> 1);
        for (int k = 0; k < COLB; k++)
            if (df[k])
                t = t + ((COLB + FI + 4)'(vis) << k);
        if (df[COLB])
            t = t - ((COLB + FI + 4)'(vis) << COLB);
        fog_blend = COLB'(t >> FI);
    endfunction

    // ================= S1: the forms at the sample =================
    // (a flag of a unit left out never reaches here: the parser refuses it)
    wire [2:0]  s1_flags = setup[`SU_FLAGS +: 3] & {FOG, TEX, SHADE};
    wire [`FORM_W-1:0] fz = setup[`SU_FORM(`F_DEPTH) +: `FORM_W];
    wire [`FORM_W-1:0] fs = setup[`SU_FORM(`F_SHADE) +: `FORM_W];
    wire [`FORM_W-1:0] fu = setup[`SU_FORM(`F_TEX_U) +: `FORM_W];
    wire [`FORM_W-1:0] fv = setup[`SU_FORM(`F_TEX_V) +: `FORM_W];
    wire signed [KW-1:0] ez = KW'($signed(fz[`FORM_EXP +: 8]));
    wire signed [KW-1:0] es = KW'($signed(fs[`FORM_EXP +: 8]));
    wire signed [KW-1:0] eu = KW'($signed(fu[`FORM_EXP +: 8]));
    wire signed [KW-1:0] ev = KW'($signed(fv[`FORM_EXP +: 8]));
    wire [3:0]  s1_tlg = setup[`SU_TLG +: 4];
    wire [TA-1:0] s1_tbase = setup[`SU_TBASE +: TA];
    wire [23:0] s1_rgb = setup[`SU_RGB +: 24];
    wire [36:0] s1_gid = {setup[`SU_ID +: 32], level};
    // the exponents of the shifts after the reciprocal, less its shift (S3)
    wire signed [KW-1:0] s1_zsh = ez - KW'(P) + KW'(DB);
    wire signed [KW-1:0] kt0 = -ez - KW'(2 * RB - 1) + KW'(s1_tlg);
    wire signed [KW-1:0] s1_ks0 = SHADE ? es - ez - KW'(2 * RB - 1) + KW'(FI) : '0;
    wire signed [KW-1:0] s1_ku0 = TEX ? eu + kt0 : '0;
    wire signed [KW-1:0] s1_kv0 = TEX ? ev + kt0 : '0;
    wire signed [KW-1:0] s1_kz0 = FOG ? KW'(P) - ez - KW'(2 * RB - 1) + KW'(8) : '0;

    logic [RATE*LW-1:0] s1_x;
    logic [RATE*LH-1:0] s1_y;
    logic [RATE*NB-1:0] s1_nz, s1_ns, s1_nu, s1_nv;
    always @* begin
        for (int j = 0; j < RATE; j++) begin
            s1_x[j*LW +: LW] = lane_x[j*16 +: LW];
            s1_y[j*LH +: LH] = lane_y[j*16 +: LH];
            s1_nz[j*NB +: NB] = form_at(fz[`FORM_ORIGIN +: NB], fz[`FORM_STEP_C +: NB],
                                       fz[`FORM_STEP_R +: NB], lane_x[j*16 +: LW], lane_y[j*16 +: LH]);
        end
    end
    generate
        if (SHADE) begin : g_s1_shade
            always @*
                for (int j = 0; j < RATE; j++)
                    s1_ns[j*NB +: NB] = form_at(fs[`FORM_ORIGIN +: NB], fs[`FORM_STEP_C +: NB],
                                               fs[`FORM_STEP_R +: NB], lane_x[j*16 +: LW],
                                               lane_y[j*16 +: LH]);
        end else begin : g_s1_no_shade
            assign s1_ns = '0;
        end
        if (TEX) begin : g_s1_tex
            always @*
                for (int j = 0; j < RATE; j++) begin
                    s1_nu[j*NB +: NB] = form_at(fu[`FORM_ORIGIN +: NB], fu[`FORM_STEP_C +: NB],
                                               fu[`FORM_STEP_R +: NB], lane_x[j*16 +: LW],
                                               lane_y[j*16 +: LH]);
                    s1_nv[j*NB +: NB] = form_at(fv[`FORM_ORIGIN +: NB], fv[`FORM_STEP_C +: NB],
                                               fv[`FORM_STEP_R +: NB], lane_x[j*16 +: LW],
                                               lane_y[j*16 +: LH]);
                end
        end else begin : g_s1_no_tex
            assign s1_nu = '0;
            assign s1_nv = '0;
        end
    endgenerate

    // ---- boundary A ----
    localparam int GA = 37 + 3 + 5 * KW + 4 + TA + 24;
    localparam int LA = 1 + LW + LH + 4 * NB;
    logic [36:0] s2_gid;
    logic [2:0]  s2_flags;
    logic signed [KW-1:0] s2_zsh, s2_ks0, s2_ku0, s2_kv0, s2_kz0;
    logic [3:0]  s2_tlg;
    logic [TA-1:0] s2_tbase;
    logic [23:0] s2_rgb;
    logic [RATE-1:0] s2_v;
    logic [RATE*LW-1:0] s2_x;
    logic [RATE*LH-1:0] s2_y;
    logic [RATE*NB-1:0] s2_nz, s2_ns, s2_nu, s2_nv;
    alb_pipe_reg #(.ON(ON_A), .W(GA + RATE * LA)) u_ra (.clk,
        .d({s1_gid, s1_flags, s1_zsh, s1_ks0, s1_ku0, s1_kv0, s1_kz0, s1_tlg, s1_tbase, s1_rgb,
            lane_v, s1_x, s1_y, s1_nz, s1_ns, s1_nu, s1_nv}),
        .q({s2_gid, s2_flags, s2_zsh, s2_ks0, s2_ku0, s2_kv0, s2_kz0, s2_tlg, s2_tbase, s2_rgb,
            s2_v, s2_x, s2_y, s2_nz, s2_ns, s2_nu, s2_nv}));

    // ================= S2: depth test, the reciprocal's index =================
    // the depth store's answer, with the previous cycle's writes forwarded
    logic [RATE*DB-1:0] zr_seen;
    generate
        if (ZR_REG != 0) begin : g_forward
            logic [RATE-1:0]    fw_en;
            logic [RATE*LW-1:0] fw_x;
            logic [RATE*LH-1:0] fw_y;
            logic [RATE*DB-1:0] fw_d;
            always_ff @(posedge clk) begin
                fw_en <= rst ? '0 : zw_en;
                fw_x <= s2_x;
                fw_y <= s2_y;
                fw_d <= zw_data;
            end
            always @* begin
                zr_seen = zr_data;
                for (int j = 0; j < RATE; j++)
                    for (int k = 0; k < RATE; k++)
                        if (fw_en[k] && fw_x[k*LW +: LW] == s2_x[j*LW +: LW] &&
                            fw_y[k*LH +: LH] == s2_y[j*LH +: LH])
                            zr_seen[j*DB +: DB] = fw_d[k*DB +: DB];
            end
        end else begin : g_direct
            assign zr_seen = zr_data;
        end
    endgenerate

    logic [RATE*WR-1:0]  s2_wr;
    logic [RATE*(RB-1)-1:0] s2_idx;
    logic [RATE*KW-1:0]  s2_rsh;
    logic [RATE-1:0]     s2_win;
    logic [RATE*DB-1:0]  s2_d;
    generate
        for (genvar j = 0; j < RATE; j++) begin : g_s2
            wire signed [NB-1:0] nz = s2_nz[j*NB +: NB];
            wire [DB-1:0] d = depth_of(nz, s2_zsh);
            wire [DB-1:0] zr_data_seen = zr_seen[j*DB +: DB];
            // strictly nearer wins; 0 is "no surface" (docs/vp.md §4)
            assign s2_win[j] = s2_v[j] && d != '0 && d > zr_data_seen;
            assign s2_d[j*DB +: DB] = d;
            if (RECIP) begin : g_recip_index
                // the reciprocal unit: N_z normalised to RB bits (a winner has N_z > 0)
                wire [7:0] nb = bitlen(nz);
                wire [DMW-1:0] dm = nb > 8'(RB) ? DMW'(NB'(nz)) >> (nb - 8'(RB))
                                                : DMW'(NB'(nz)) << (8'(RB) - nb);
                assign s2_idx[j*(RB-1) +: RB-1] = dm[RB-2:0];
                wire unused_dm = |dm[DMW-1:RB-1];
                assign s2_rsh[j*KW +: KW] = KW'(nb) - KW'(RB);
            end else begin : g_no_recip_index
                assign s2_idx[j*(RB-1) +: RB-1] = '0;
                assign s2_rsh[j*KW +: KW] = '0;
            end
            assign s2_wr[j*WR +: WR] = {s2_win[j], s2_x[j*LW +: LW], s2_y[j*LH +: LH], d};
        end
    endgenerate
    assign zw_en = s2_win;
    assign zw_data = s2_d;
    always @*
        for (int j = 0; j < RATE; j++) begin
            zw_x[j*16 +: 16] = 16'(s2_x[j*LW +: LW]);
            zw_y[j*16 +: 16] = 16'(s2_y[j*LH +: LH]);
        end

    // ---- boundary B (the ROM's read register) ----
    localparam int GB = 37 + 3 + 4 * KW + 4 + TA + 24;
    localparam int LB = WR + KW + 3 * NB;
    logic [36:0] s3_gid;
    logic [2:0]  s3_flags;
    logic signed [KW-1:0] s3_ks0, s3_ku0, s3_kv0, s3_kz0;
    logic [3:0]  s3_tlg;
    logic [TA-1:0] s3_tbase;
    logic [23:0] s3_rgb;
    logic [RATE*WR-1:0] s3_wr;
    logic [RATE*KW-1:0] s3_rsh;
    logic [RATE*NB-1:0] s3_ns, s3_nu, s3_nv;
    logic [RATE*(RB+1)-1:0] s3_rm;
    alb_pipe_reg #(.ON(ON_B), .W(GB + RATE * LB)) u_rb (.clk,
        .d({s2_gid, s2_flags, s2_ks0, s2_ku0, s2_kv0, s2_kz0, s2_tlg, s2_tbase, s2_rgb,
            s2_wr, s2_rsh, s2_ns, s2_nu, s2_nv}),
        .q({s3_gid, s3_flags, s3_ks0, s3_ku0, s3_kv0, s3_kz0, s3_tlg, s3_tbase, s3_rgb,
            s3_wr, s3_rsh, s3_ns, s3_nu, s3_nv}));
    // the reciprocal ROM: rm = floor(2^(2RB-1) / dm), dm in [2^(RB-1), 2^RB)
    generate
        if (RECIP) begin : g_recip
            logic [RB:0] recip_rom [0:ROM_N-1];
            initial begin
                for (int i = 0; i < ROM_N; i++)
                    recip_rom[i] = (RB + 1)'((64'd1 << (2 * RB - 1)) / (64'(ROM_N) + 64'(i)));
            end
            for (genvar j = 0; j < RATE; j++) begin : g_rom
                if (ON_B) begin : g_sync
                    always_ff @(posedge clk)
                        s3_rm[j*(RB+1) +: RB+1] <= recip_rom[s2_idx[j*(RB-1) +: RB-1]];
                end else begin : g_async
                    assign s3_rm[j*(RB+1) +: RB+1] = recip_rom[s2_idx[j*(RB-1) +: RB-1]];
                end
            end
        end else begin : g_no_recip
            assign s3_rm = '0;
            wire unused_recip = (|s2_idx) | (|s3_rsh);
        end
    endgenerate

    // ================= S3: the forms times the reciprocal =================
    logic [RATE*PW-1:0] s3_ps, s3_pu, s3_pv;
    logic [RATE*KW-1:0] s3_ks, s3_ku, s3_kv;
    logic [RATE*33-1:0] s3_zq;
    generate
        if (SHADE) begin : g_s3_shade
            always @*
                for (int j = 0; j < RATE; j++) begin
                    s3_ps[j*PW +: PW] = $signed(PW'($signed(s3_ns[j*NB +: NB])))
                                      * $signed(PW'(s3_rm[j*(RB+1) +: RB+1]));
                    s3_ks[j*KW +: KW] = s3_ks0 - s3_rsh[j*KW +: KW];
                end
        end else begin : g_s3_no_shade
            assign s3_ps = '0;
            assign s3_ks = '0;
            wire unused_shade = (|s3_ns) | (|s3_ks0);
        end
        if (TEX) begin : g_s3_tex
            always @*
                for (int j = 0; j < RATE; j++) begin
                    s3_pu[j*PW +: PW] = $signed(PW'($signed(s3_nu[j*NB +: NB])))
                                      * $signed(PW'(s3_rm[j*(RB+1) +: RB+1]));
                    s3_pv[j*PW +: PW] = $signed(PW'($signed(s3_nv[j*NB +: NB])))
                                      * $signed(PW'(s3_rm[j*(RB+1) +: RB+1]));
                    s3_ku[j*KW +: KW] = s3_ku0 - s3_rsh[j*KW +: KW];
                    s3_kv[j*KW +: KW] = s3_kv0 - s3_rsh[j*KW +: KW];
                end
        end else begin : g_s3_no_tex
            assign s3_pu = '0;
            assign s3_pv = '0;
            assign s3_ku = '0;
            assign s3_kv = '0;
            wire unused_tex = (|s3_nu) | (|s3_nv) | (|s3_ku0) | (|s3_kv0);
        end
        if (FOG) begin : g_s3_fog
            always @*
                for (int j = 0; j < RATE; j++)
                    s3_zq[j*33 +: 33] = fog_distance(s3_rm[j*(RB+1) +: RB+1],
                                                     s3_kz0 - s3_rsh[j*KW +: KW]);
        end else begin : g_s3_no_fog
            assign s3_zq = '0;
            wire unused_fog = |s3_kz0;
        end
        if (!RECIP) begin : g_s3_no_recip
            wire unused_rm = |s3_rm;
        end
    endgenerate

    // ---- boundary C ----
    localparam int GC = 37 + 3 + 4 + TA + 24;
    localparam int LC = WR + 3 * PW + 3 * KW + 33;
    logic [36:0] s4_gid;
    logic [2:0]  s4_flags;
    logic [3:0]  s4_tlg;
    logic [TA-1:0] s4_tbase;
    logic [23:0] s4_rgb;
    logic [RATE*WR-1:0] s4_wr;
    logic [RATE*PW-1:0] s4_ps, s4_pu, s4_pv;
    logic [RATE*KW-1:0] s4_ks, s4_ku, s4_kv;
    logic [RATE*33-1:0] s4_zq;
    alb_pipe_reg #(.ON(ON_C), .W(GC + RATE * LC)) u_rc (.clk,
        .d({s3_gid, s3_flags, s3_tlg, s3_tbase, s3_rgb, s3_wr, s3_ps, s3_pu, s3_pv, s3_ks, s3_ku,
            s3_kv, s3_zq}),
        .q({s4_gid, s4_flags, s4_tlg, s4_tbase, s4_rgb, s4_wr, s4_ps, s4_pu, s4_pv, s4_ks, s4_ku,
            s4_kv, s4_zq}));

    // ================= S4: intensity, texture address, fog =================
    // the visibility: 2'b10 at its nearest (ONE), 2'b01 beyond the far
    // distance (0), else 2'b00 and the division of (far - zq) 2^FI by
    // (far - near), FI quotient bits
    wire [31:0] fog_span = fog_far - fog_near;
    logic [RATE*(FI+1)-1:0] s4_inten;
    logic [RATE*TA-1:0]     s4_taddr;
    logic [RATE*2-1:0]      s4_vm;
    logic [RATE*(33+FI)-1:0] s4_vd;
    generate
        if (SHADE) begin : g_s4_shade
            // eq. (7): intensity = shade / depth, clamped to [0, 1]
            always @*
                for (int j = 0; j < RATE; j++)
                    s4_inten[j*(FI+1) +: FI+1] = s4_flags[0]
                        ? intensity_of(s4_ps[j*PW +: PW], s4_ks[j*KW +: KW]) : ONE;
        end else begin : g_s4_no_shade
            assign s4_inten = {RATE{ONE}};
            wire unused_shade = (|s4_ps) | (|s4_ks);
        end
        if (TEX) begin : g_s4_tex
            // texture: the fractions of u and v address the nearest texel
            always @*
                for (int j = 0; j < RATE; j++) begin
                    // (bits above the texture memory's address unused when it is small)
                    /* verilator lint_off UNUSEDSIGNAL */
                    logic [9:0] u, v;
                    /* verilator lint_on UNUSEDSIGNAL */
                    u = fraction_of(s4_pu[j*PW +: PW], s4_ku[j*KW +: KW], s4_tlg);
                    v = fraction_of(s4_pv[j*PW +: PW], s4_kv[j*KW +: KW], s4_tlg);
                    s4_taddr[j*TA +: TA] = TA'(s4_tbase + TA'((TA'(v) << s4_tlg) + TA'(u)));
                end
        end else begin : g_s4_no_tex
            assign s4_taddr = '0;
            wire unused_tex = (|s4_pu) | (|s4_pv) | (|s4_ku) | (|s4_kv) | (|s4_tlg) | (|s4_tbase);
        end
        if (FOG) begin : g_s4_fog
            // fog: the distance Z/near = 2^P / N_z in 24.8, visibility linear
            // between fog near and far, truncated
            always @*
                for (int j = 0; j < RATE; j++) begin
                    logic [32:0] zq;
                    zq = s4_zq[j*33 +: 33];
                    s4_vm[j*2 +: 2] = zq <= 33'(fog_near) ? 2'b10
                                    : zq >= 33'(fog_far) ? 2'b01 : 2'b00;
                    s4_vd[j*(33+FI) +: 33+FI] = div_steps(33'(fog_far) - zq, '0, fog_span, V4);
                end
        end else begin : g_s4_no_fog
            assign s4_vm = '0;
            assign s4_vd = '0;
            wire unused_fog = (|s4_zq) | (|fog_near) | (|fog_far) | (|fog_span);
        end
    endgenerate

    // ---- boundary D (texture memory's read register) ----
    localparam int GD = 37 + 3 + 24;
    localparam int LD = WR + FI + 1 + TA + 2 + 33 + FI;
    logic [36:0] s5_gid;
    logic [2:0]  s5_flags;
    logic [23:0] s5_rgb;
    logic [RATE*WR-1:0] s5_wr;
    logic [RATE*(FI+1)-1:0] s5_inten;
    logic [RATE*TA-1:0] s5_taddr;
    logic [RATE*2-1:0] s5_vm;
    logic [RATE*(33+FI)-1:0] s5_vd;
    logic [RATE*24-1:0] s5_fetched;
    alb_pipe_reg #(.ON(ON_D), .W(GD + RATE * LD)) u_rd (.clk,
        .d({s4_gid, s4_flags, s4_rgb, s4_wr, s4_inten, s4_taddr, s4_vm, s4_vd}),
        .q({s5_gid, s5_flags, s5_rgb, s5_wr, s5_inten, s5_taddr, s5_vm, s5_vd}));
    // Texture memory is written only while no face runs (TEXTURE waits for
    // retirement, docs/microarchitecture.md), so lane 0 shares one port with
    // the parser's writes: a single-port RAM.
    generate
        if (!TEX) begin : g_no_tex_mem
            assign s5_fetched = '0;
            wire unused_tex = tw_en | (|tw_addr) | (|tw_data) | (|s5_taddr);
        end else if (ON_D) begin : g_tex_sync
            logic [23:0] tex_mem [0:TEX_WORDS-1];
            wire [TA-1:0] a0 = tw_en ? tw_addr : s4_taddr[0 +: TA];
            always_ff @(posedge clk)
                if (tw_en)
                    tex_mem[a0] <= tw_data;
                else
                    s5_fetched[0 +: 24] <= tex_mem[a0];
            for (genvar j = 1; j < RATE; j++) begin : g_lane
                always_ff @(posedge clk)
                    s5_fetched[j*24 +: 24] <= tex_mem[s4_taddr[j*TA +: TA]];
            end
        end else begin : g_tex_async
            logic [23:0] tex_mem [0:TEX_WORDS-1];
            always_ff @(posedge clk)
                if (tw_en)
                    tex_mem[tw_addr] <= tw_data;
            for (genvar j = 0; j < RATE; j++) begin : g_lane
                assign s5_fetched[j*24 +: 24] = tex_mem[s5_taddr[j*TA +: TA]];
            end
        end
    endgenerate

    // ================= S5: base x texel x intensity =================
    logic [RATE*3*MW-1:0] s5_m;
    // (the base colour in frame-store units when FLAT_RGB; the cast keeps
    // the selects in range when it is not)
    wire [3*COLB-1:0] s5_flat = (3 * COLB)'(s5_rgb);
    logic [RATE*(33+FI)-1:0] s5_vd2;
    always @* begin
        for (int j = 0; j < RATE; j++) begin
            logic [23:0] texel;
            texel = s5_flags[1] ? s5_fetched[j*24 +: 24] : 24'hFFFFFF;
            for (int c = 0; c < 3; c++) begin
                logic [15:0] bt;
                // the first BT_DSP channels' products as multipliers (DSPs),
                // the others as shifts and adds; without texture the texel
                // is 255: base x 256 - base
                if (!TEX)
                    bt = (16'(s5_rgb[(2-c)*8 +: 8]) << 8) - 16'(s5_rgb[(2-c)*8 +: 8]);
                else if (c < BT_DSP)
                    bt = 16'(s5_rgb[(2-c)*8 +: 8]) * 16'(texel[(2-c)*8 +: 8]);
                else
                    bt = mul8(s5_rgb[(2-c)*8 +: 8], texel[(2-c)*8 +: 8]);
                // without Gouraud shading the intensity is 1.0: a shift;
                // flat only, the colour itself (in the quotient's place, S7)
                if (FLAT_RGB)
                    s5_m[(j*3+c)*MW +: MW] = MW'(s5_flat[(2-c)*COLB +: COLB]);
                else if (SHADE)
                    s5_m[(j*3+c)*MW +: MW] = MW'(bt) * MW'(s5_inten[j*(FI+1) +: FI+1]);
                else
                    s5_m[(j*3+c)*MW +: MW] = MW'(bt) << FI;
            end
        end
    end
    generate
        if (FOG) begin : g_s5_fog
            always @*
                for (int j = 0; j < RATE; j++)
                    s5_vd2[j*(33+FI) +: 33+FI] = div_steps(s5_vd[j*(33+FI)+FI +: 33],
                                                           s5_vd[j*(33+FI) +: FI], fog_span, V5);
        end else begin : g_s5_no_fog
            assign s5_vd2 = '0;
            wire unused_fog = |s5_vd;
        end
        if (!SHADE) begin : g_s5_no_shade
            wire unused_shade = |s5_inten;
        end
        if (!TEX) begin : g_s5_no_tex
            wire unused_tex = (|s5_fetched) | s5_flags[1];
        end
    endgenerate

    // ---- boundary E ----
    localparam int GE = 37 + 1;
    localparam int LE = WR + 3 * MW + 2 + 33 + FI;
    wire s5_fogged = fog_on && s5_flags[2];
    logic [36:0] s6_gid;
    logic        s6_fogged;
    logic [RATE*WR-1:0] s6_wr;
    logic [RATE*3*MW-1:0] s6_m;
    logic [RATE*2-1:0] s6_vm;
    logic [RATE*(33+FI)-1:0] s6_vd;
    alb_pipe_reg #(.ON(ON_E), .W(GE + RATE * LE)) u_re (.clk,
        .d({s5_gid, s5_fogged, s5_wr, s5_m, s5_vm, s5_vd2}),
        .q({s6_gid, s6_fogged, s6_wr, s6_m, s6_vm, s6_vd}));

    // ================= S6: the colour's scale, the divisions go on =================
    logic [RATE*3*(XW+COLB)-1:0] s6_cd;
    logic [RATE*(33+FI)-1:0] s6_vd2;
    always @*
        for (int j = 0; j < RATE; j++)
            for (int c = 0; c < 3; c++)
                s6_cd[(j*3+c)*(XW+COLB) +: XW+COLB] = FLAT_RGB
                    ? (XW + COLB)'(s6_m[(j*3+c)*MW +: COLB])
                    : col_div(colour_scale(s6_m[(j*3+c)*MW +: MW]), '0, COLB - 1, COLB - C6);
    generate
        if (FOG) begin : g_s6_fog
            always @*
                for (int j = 0; j < RATE; j++)
                    s6_vd2[j*(33+FI) +: 33+FI] = div_steps(s6_vd[j*(33+FI)+FI +: 33],
                                                           s6_vd[j*(33+FI) +: FI], fog_span, V6);
        end else begin : g_s6_no_fog
            assign s6_vd2 = '0;
            wire unused_fog = |s6_vd;
        end
    endgenerate

    // ---- boundary F ----
    localparam int LF = WR + 3 * (XW + COLB) + 2 + 33 + FI;
    logic [36:0] s7_gid;
    logic        s7_fogged;
    logic [RATE*WR-1:0] s7_wr;
    logic [RATE*3*(XW+COLB)-1:0] s7_cd;
    logic [RATE*2-1:0] s7_vm;
    logic [RATE*(33+FI)-1:0] s7_vd;
    alb_pipe_reg #(.ON(ON_F), .W(GE + RATE * LF)) u_rf (.clk,
        .d({s6_gid, s6_fogged, s6_wr, s6_cd, s6_vm, s6_vd2}),
        .q({s7_gid, s7_fogged, s7_wr, s7_cd, s7_vm, s7_vd}));

    // ================= S7: both divisions end =================
    logic [RATE*3*COLB-1:0] s7_rgb;
    logic [RATE*(FI+1)-1:0] s7_vis;
    logic [RATE*(33+FI)-1:0] s7_vd2;     // the remainders are not needed
    always @*
        for (int j = 0; j < RATE; j++)
            for (int c = 0; c < 3; c++) begin
                logic [XW+COLB-1:0] cd;
                cd = s7_cd[(j*3+c)*(XW+COLB) +: XW+COLB];
                if (!FLAT_RGB)
                    cd = col_div(cd[COLB +: XW], cd[COLB-1:0], COLB - C6 - 1, 0);
                s7_rgb[j*3*COLB + (2-c)*COLB +: COLB] = cd[COLB-1:0];
            end
    generate
        if (FOG) begin : g_s7_fog
            always @*
                for (int j = 0; j < RATE; j++) begin
                    s7_vd2[j*(33+FI) +: 33+FI] = div_steps(s7_vd[j*(33+FI)+FI +: 33],
                                                           s7_vd[j*(33+FI) +: FI], fog_span, V7);
                    s7_vis[j*(FI+1) +: FI+1] = s7_vm[j*2+1] ? ONE : s7_vm[j*2] ? '0
                                             : (FI + 1)'(s7_vd2[j*(33+FI) +: FI]);
                end
        end else begin : g_s7_no_fog
            assign s7_vd2 = '0;
            assign s7_vis = '0;
            wire unused_fog = (|s7_vd) | (|s7_vm) | (|s6_vm) | (|s5_vm);
        end
    endgenerate

    // ---- boundary G ----
    localparam int LG = WR + 3 * COLB + FI + 1;
    logic [36:0] s8_gid;
    logic        s8_fogged;
    logic [RATE*WR-1:0] s8_wr;
    logic [RATE*3*COLB-1:0] s8_rgb0;
    logic [RATE*(FI+1)-1:0] s8_vis;
    alb_pipe_reg #(.ON(ON_G), .W(GE + RATE * LG)) u_rg (.clk,
        .d({s7_gid, s7_fogged, s7_wr, s7_rgb, s7_vis}),
        .q({s8_gid, s8_fogged, s8_wr, s8_rgb0, s8_vis}));

    // ================= S8: fog blend =================
    logic [RATE*3*COLB-1:0] s8_rgb;
    generate
        if (FOG) begin : g_s8_fog
            always @*
                for (int j = 0; j < RATE; j++)
                    for (int c = 0; c < 3; c++) begin
                        s8_rgb[j*3*COLB + c*COLB +: COLB] = s8_rgb0[j*3*COLB + c*COLB +: COLB];
                        if (s8_fogged)
                            s8_rgb[j*3*COLB + c*COLB +: COLB] =
                                fog_blend(s8_rgb0[j*3*COLB + c*COLB +: COLB],
                                          fog_rgb[c*COLB +: COLB], s8_vis[j*(FI+1) +: FI+1]);
                    end
        end else begin : g_s8_no_fog
            assign s8_rgb = s8_rgb0;
            wire unused_fog = s8_fogged | (|s8_vis) | fog_on | (|fog_rgb);
        end
    endgenerate

    // ================= the rest of the stages: a delay =================
    localparam int LO = 37 + RATE * (WR + 3 * COLB);
    logic [LO-1:0] out;
    generate
        if (TAIL > 0) begin : g_tail
            // stage k of the delay in bits [k LO, (k + 1) LO)
            logic [TAIL*LO-1:0] dl;
            if (TAIL > 1) begin : g_long
                always_ff @(posedge clk)
                    dl <= {dl[(TAIL-1)*LO-1:0], s8_gid, s8_wr, s8_rgb};
            end else begin : g_short
                always_ff @(posedge clk)
                    dl <= {s8_gid, s8_wr, s8_rgb};
            end
            assign out = dl[(TAIL-1)*LO +: LO];
        end else begin : g_no_tail
            assign out = {s8_gid, s8_wr, s8_rgb};
        end
    endgenerate

    logic [RATE*WR-1:0] out_wr;
    logic [RATE*3*COLB-1:0] out_rgb;
    assign {cw_face, cw_level[4:0], out_wr, out_rgb} = out;
    assign cw_level[7:5] = 3'd0;
    assign cw_rgb = out_rgb;
    always @*
        for (int j = 0; j < RATE; j++) begin
            logic [WR-1:0] w;
            w = out_wr[j*WR +: WR];
            cw_en[j] = w[WR-1];
            cw_x[j*16 +: 16] = 16'(w[DB+LH +: LW]);
            cw_y[j*16 +: 16] = 16'(w[DB +: LH]);
            cw_depth[j*DB +: DB] = w[DB-1:0];
        end

    // ---- which stages hold samples (the retirement and drain tests) ----
    wire iss_now = |lane_v;
    generate
        if (L == 1) begin : g_one_stage
            assign busy = 1'b0;
            assign busy_before_last = 1'b0;
            wire unused_one_stage = rst | iss_now;   // no stage registers to reset
        end else begin : g_stages
            logic [L-1:1] st_iss;                      // bit k: issued k cycles ago
            wire  [L-2:0] iss_line = (L - 1)'({st_iss, iss_now});
            always_ff @(posedge clk)
                if (rst)
                    st_iss <= '0;
                else
                    st_iss <= iss_line;
            assign busy = |st_iss;
            assign busy_before_last = |iss_line;
        end
    endgenerate

    wire unused = |s5_taddr | (|setup) | s5_flags[0] | (|s7_vd2) | (|fz) | (|fs) | (|fu) | (|fv);
endmodule
