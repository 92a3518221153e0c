// alb_pipe — the depth/shade pipeline (docs/microarchitecture.md; the
// arithmetic of docs/vp.md §4-§5 and vp/units.h): RATE lanes, L = 1 +
// DIV_LAT + SHADE_LAT stages, fully pipelined.  A sample issued in cycle t
// is depth-tested in the first stage — the depth store read and written in
// the same cycle, so later samples always see earlier ones' depths — and
// written (colour, face id, level) at the end of cycle t + L - 1 if it won.
//
// The per-sample units: the depth form at the sample and the depth store
// format; the reciprocal unit (a ROM of 2^(RB-1) quotients of the
// normalised depth); intensity (eq. 7); texture addressing and texture
// memory; the colour output stage; fog.  They are computed from the first
// stage's values and the result carried through the remaining L - 1 stage
// registers (a synthesis tool retimes them into the logic).  Multipliers
// are fine here: the form values at samples, the ratios, the colour.
`include "alb_defs.svh"

module alb_pipe #(
    parameter int RATE = 4,
    parameter int CB = 24,              // coef_bits
    parameter int LW = 5,
    parameter int LH = 5,
    parameter int DB = 24,              // depth_bits
    parameter int COLB = 8,             // colour_bits
    parameter int RB = 16,              // recip_bits
    parameter int FI = 12,              // shade_frac_bits
    parameter int DIV_LAT = 8,          // divider_latency
    parameter int SHADE_LAT = 4,        // shade_latency
    parameter int TEX_WORDS = 65536
) (
    input  logic                      clk,
    input  logic                      rst,
    // the samples issued this cycle (alb_fill)
    input  logic [RATE-1:0]           lane_v,
    input  logic [RATE*16-1:0]        lane_x,
    input  logic [RATE*16-1:0]        lane_y,
    input  logic [`SETUP_W-1:0]       setup,
    input  logic [4:0]                level,
    // the drawing frame's fog registers
    input  logic                      fog_on,
    input  logic [3*COLB-1:0]         fog_rgb,
    input  logic [31:0]               fog_near,
    input  logic [31:0]               fog_far,
    // the depth store, first stage: read (combinational) and write
    input  logic [RATE*DB-1:0]        zr_data,
    output logic [RATE-1:0]           zw_en,
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
    localparam int ROM_N = 1 << (RB - 1);
    localparam logic [16:0] ONE = 17'd1 << FI;             // intensity 1.0
    localparam logic [15:0] TOP = 16'((1 << COLB) - 1);     // the largest colour
    localparam logic [63:0] DMAX = (64'd1 << DB) - 64'd1;   // the largest depth
    // floor(x / 65025) = (x * MAGIC) >> 52 for x < 2^34: MAGIC = ceil(2^52 / 65025)
    // errs by e = MAGIC 65025 - 2^52 < 65025, and x e < 2^52 keeps the floor.
    localparam logic [63:0] MAGIC = ((64'd1 << 52) + 64'd65024) / 64'd65025;
    localparam int LD = 1 + 16 + 16 + DB + 3 * COLB;        // a lane through the stages
    // a form at a sample: |N| < 3 2^(CB-1+P) < 2^(CB+P+1) (docs/vp.md §4), with the sign
    localparam int FW = CB + P + 3;
    // a form times a reciprocal: below 2^(FW+RB), at most 64 bits by the
    // profile's constraint coef_bits + levels + recip_bits <= 60
    localparam int PW = FW + RB + 1;

    // ---- the reciprocal ROM: rm = floor(2^(2RB-1) / dm), dm in [2^(RB-1), 2^RB) ----
    logic [RB:0] recip_rom [0:ROM_N-1];
    initial begin
        for (int i = 0; i < ROM_N; i++)
            recip_rom[i] = (RB + 1)'((64'd1 << (2 * RB - 1)) / (64'(ROM_N) + 64'(i)));
    end

    // ---- texture memory ----
    logic [23:0] tex_mem [0:TEX_WORDS-1];
    always_ff @(posedge clk)
        if (tw_en)
            tex_mem[tw_addr] <= tw_data;

    // ---- the units (vp/units.h) ----
    // N of a form at sample (x, y), exact in FW bits (the form's terms, 64 bits
    // in the set-up, are below 2^(FW-1) too: the set-up's high bits are copies
    // of the sign)
    function automatic [FW-1:0] form_at(input [3*FW-1:0] f, input [15:0] x, input [15:0] y);
        logic signed [FW-1:0] o, sc, sr, cx, ry;
        {sr, sc, o} = f;
        cx = FW'($signed({1'b0, x}));
        ry = FW'($signed({1'b0, y}));
        form_at = o + cx * sc + ry * sr;
    endfunction


    // the depth store value: near/Z as unsigned 0.DB, truncated, saturated
    // (nearer than near), 0 behind the observer (docs/vp.md §4)
    function automatic [DB-1:0] depth_of(input [FW-1:0] nf, input signed [15:0] sh);
        logic signed [FW-1:0] n;
        logic [63:0] nu, v;
        n = nf;
        nu = 64'(nf);
        if (n <= 0)
            v = 64'd0;
        else if (sh >= 0) begin
            if (sh >= 16'sd62 || nu > (DMAX >> sh))
                v = DMAX;
            else
                v = nu << sh;
        end else if (-sh >= 16'sd63)
            v = 64'd0;
        else
            v = nu >> (-sh);
        if (v > DMAX)
            v = DMAX;
        depth_of = v[DB-1:0];
    endfunction

    // the number of significant bits: a priority encoder
    function automatic [6:0] bitlen(input [FW-1:0] v);
        logic [6:0] n;
        n = 7'd0;
        for (int k = 0; k < FW; k++)
            if (v[k])
                n = 7'(k + 1);
        bitlen = n;
    endfunction

    // floor(num 2^k) clamped to [0, ONE]: the intensity of eq. (7)
    function automatic [16:0] intensity_of(input [PW-1:0] pu, input signed [15:0] k);
        logic signed [PW-1:0] p;
        logic [33:0] wide;
        logic [PW-1:0] v;
        p = pu;
        if (p <= 0)
            intensity_of = 17'd0;
        else if (k >= 0) begin
            // p 2^k >= 2^17 > ONE when p or k is that large
            if (k >= 16'sd17 || pu[PW-1:17] != '0)
                intensity_of = ONE;
            else begin
                wide = 34'(pu[16:0]) << k;
                intensity_of = wide > 34'(ONE) ? ONE : wide[16:0];
            end
        end else begin
            v = -k >= 16'sd63 ? '0 : pu >> (-k);
            intensity_of = v > PW'(ONE) ? ONE : v[16:0];
        end
    endfunction

    // floor(num 2^k) mod 2^lg: a texture coordinate's fraction (units_fraction)
    function automatic [9:0] fraction_of(input [PW-1:0] pu, input signed [15:0] k, input [3:0] lg);
        logic signed [PW-1:0] p;
        logic signed [15:0] s;
        p = pu;
        s = -k > 16'sd63 ? 16'sd63 : -k;
        // only the low 10 bits of p 2^k matter, so k >= 10 gives 0
        if (k >= 16'sd10)
            fraction_of = 10'd0;
        else if (k >= 0)
            fraction_of = (pu[9:0] << k) & ((10'd1 << lg) - 10'd1);
        else
            fraction_of = 10'(p >>> s) & ((10'd1 << lg) - 10'd1);
    endfunction

    // Z/near in 24.8 through the reciprocal: floor(rm 2^k), saturating at 2^62
    function automatic [63:0] fog_distance(input [RB:0] rm, input signed [15:0] k);
        logic [63:0] r;
        r = 64'(rm);
        if (k >= 0) begin
            if (k >= 16'sd62 || r > ((64'd1 << 62) >> k))
                fog_distance = 64'd1 << 62;
            else
                fog_distance = r << k;
        end else
            fog_distance = -k >= 16'sd63 ? 64'd0 : r >> (-k);
    endfunction

    // base x texel x intensity to the frame store, round half up (units_output):
    // m < 65025 2^FI, so x = (2 m TOP + 65025 2^FI) >> (FI + 1) < 65025 2^16 < 2^34
    function automatic [COLB-1:0] colour_out(input [7:0] base, input [7:0] texel,
                                             input [16:0] inten);
        logic [32:0] m;
        logic [50:0] num;
        logic [33:0] x;
        logic [70:0] q;
        m = 33'(16'(base) * 16'(texel)) * 33'(inten);
        num = 51'(m) * 51'(TOP) * 51'd2 + (51'd65025 << FI);
        x = 34'(num >> (FI + 1));
        q = 71'(x) * 71'(MAGIC[36:0]);
        colour_out = COLB'(q >> 52);
    endfunction

    // floor(a / b) for a quotient below 2^16: fog visibility, (far - zq) 2^FI /
    // (far - near) with zq inside (near, far), by sixteen compare-subtracts
    function automatic [16:0] vis_div(input [47:0] a, input [31:0] b);
        logic [48:0] r;
        logic [16:0] q;
        r = 49'(a);
        q = '0;
        for (int k = 15; k >= 0; k--)
            if (r >= (49'(b) << k)) begin
                r = r - (49'(b) << k);
                q[k] = 1'b1;
            end
        vis_div = q;
    endfunction

    function automatic [COLB-1:0] fog_blend(input [COLB-1:0] c, input [COLB-1:0] f,
                                            input [16:0] vis);
        logic [63:0] t;
        t = 64'(c) * 64'(vis) + 64'(f) * (64'(ONE) - 64'(vis)) + (64'(ONE) >> 1);
        fog_blend = COLB'(t >> FI);
    endfunction

    // ---- the first stage ----
    wire [2:0]  flags = setup[`SU_FLAGS +: 3];
    wire [23:0] base_rgb = setup[`SU_RGB +: 24];
    wire [23:0] tbase = setup[`SU_TBASE +: 24];
    wire [3:0]  tlg = setup[`SU_TLG +: 4];
    wire [`FORM_W-1:0] fz = setup[`SU_FORM(`F_DEPTH) +: `FORM_W];
    wire [`FORM_W-1:0] fs = setup[`SU_FORM(`F_SHADE) +: `FORM_W];
    wire [`FORM_W-1:0] fu = setup[`SU_FORM(`F_TEX_U) +: `FORM_W];
    wire [`FORM_W-1:0] fv = setup[`SU_FORM(`F_TEX_V) +: `FORM_W];
    wire signed [15:0] ez = 16'($signed(fz[`FORM_EXP +: 8]));
    wire signed [15:0] es = 16'($signed(fs[`FORM_EXP +: 8]));
    wire signed [15:0] eu = 16'($signed(fu[`FORM_EXP +: 8]));
    wire signed [15:0] ev = 16'($signed(fv[`FORM_EXP +: 8]));
    wire signed [15:0] zshift = ez - $signed(16'(P)) + $signed(16'(DB));
    wire        fogged = fog_on && flags[2];
    wire [3*FW-1:0] tz = {fz[`FORM_STEP_R +: FW], fz[`FORM_STEP_C +: FW], fz[`FORM_ORIGIN +: FW]};
    wire [3*FW-1:0] ts = {fs[`FORM_STEP_R +: FW], fs[`FORM_STEP_C +: FW], fs[`FORM_ORIGIN +: FW]};
    wire [3*FW-1:0] tu = {fu[`FORM_STEP_R +: FW], fu[`FORM_STEP_C +: FW], fu[`FORM_ORIGIN +: FW]};
    wire [3*FW-1:0] tv = {fv[`FORM_STEP_R +: FW], fv[`FORM_STEP_C +: FW], fv[`FORM_ORIGIN +: FW]};
    wire unused_form_sign_copies = ^{fz[`FORM_ORIGIN+FW +: 64-FW], fz[`FORM_STEP_C+FW +: 64-FW],
                                     fz[`FORM_STEP_R+FW +: 64-FW], fs[`FORM_ORIGIN+FW +: 64-FW],
                                     fs[`FORM_STEP_C+FW +: 64-FW], fs[`FORM_STEP_R+FW +: 64-FW],
                                     fu[`FORM_ORIGIN+FW +: 64-FW], fu[`FORM_STEP_C+FW +: 64-FW],
                                     fu[`FORM_STEP_R+FW +: 64-FW], fv[`FORM_ORIGIN+FW +: 64-FW],
                                     fv[`FORM_STEP_C+FW +: 64-FW], fv[`FORM_STEP_R+FW +: 64-FW]};

    logic [RATE-1:0]        s1_win;
    logic [RATE*DB-1:0]     s1_depth;
    logic [RATE*3*COLB-1:0] s1_rgb;
    generate
        for (genvar j = 0; j < RATE; j++) begin : g_lane
            wire [15:0] x = lane_x[j*16 +: 16];
            wire [15:0] y = lane_y[j*16 +: 16];
            wire [FW-1:0] nz = form_at(tz, x, y);
            wire [DB-1:0] d = depth_of(nz, zshift);
            // the reciprocal unit: N_z normalised to RB bits, then the ROM
            wire [6:0] nb = bitlen(nz);
            wire [RB-2:0] idx = (RB - 1)'(nb > 7'(RB) ? nz >> (nb - 7'(RB)) : nz << (7'(RB) - nb));
            wire [RB:0] rm = recip_rom[idx];
            wire signed [15:0] rsh = 16'(nb) - $signed(16'(RB));
            // eq. (7): intensity = shade / depth, clamped to [0, 1]
            wire [FW-1:0] ns = form_at(ts, x, y);
            wire signed [15:0] ks = es - ez - $signed(16'(2 * RB - 1)) - rsh + $signed(16'(FI));
            wire [PW-1:0] ps = PW'($signed(ns)) * PW'(rm);
            wire [16:0] inten = flags[0] ? intensity_of(ps, ks) : ONE;
            // texture: the fractions of u and v address the nearest texel
            wire [FW-1:0] nu = form_at(tu, x, y);
            wire [FW-1:0] nv = form_at(tv, x, y);
            wire [PW-1:0] pu = PW'($signed(nu)) * PW'(rm);
            wire [PW-1:0] pv = PW'($signed(nv)) * PW'(rm);
            wire signed [15:0] kt = -ez - $signed(16'(2 * RB - 1)) - rsh + 16'(tlg);
            wire [9:0] u = fraction_of(pu, eu + kt, tlg);
            wire [9:0] v = fraction_of(pv, ev + kt, tlg);
            wire [TA-1:0] taddr = TA'(tbase + ((24'(v) << tlg) + 24'(u)));
            wire [23:0] fetched = tex_mem[taddr];
            wire [23:0] texel = flags[1] ? fetched : 24'hFFFFFF;
            // fog: the distance Z/near = 2^P / N_z in 24.8, visibility linear
            // between fog near and far, truncated
            wire [63:0] zq = fog_distance(rm, $signed(16'(P)) - ez - $signed(16'(2 * RB - 1)) - rsh
                                              + 16'sd8);
            logic [16:0] vis;
            logic [3*COLB-1:0] rgb;
            always @* begin
                if (zq <= 64'(fog_near))
                    vis = ONE;
                else if (zq >= 64'(fog_far))
                    vis = 17'd0;
                else
                    vis = vis_div(48'(32'(64'(fog_far) - zq)) << FI, fog_far - fog_near);
                for (int c = 0; c < 3; c++) begin
                    rgb[(2-c)*COLB +: COLB] = colour_out(base_rgb[(2-c)*8 +: 8],
                                                         texel[(2-c)*8 +: 8], inten);
                    if (fogged)
                        rgb[(2-c)*COLB +: COLB] = fog_blend(rgb[(2-c)*COLB +: COLB],
                                                            fog_rgb[(2-c)*COLB +: COLB], vis);
                end
            end
            // strictly nearer wins; 0 is "no surface" (docs/vp.md §4)
            assign s1_win[j] = lane_v[j] && d != '0 && d > zr_data[j*DB +: DB];
            assign s1_depth[j*DB +: DB] = d;
            assign s1_rgb[j*3*COLB +: 3*COLB] = rgb;
        end
    endgenerate
    assign zw_en = s1_win;
    assign zw_data = s1_depth;

    // ---- the remaining stages ----
    wire iss_now = |lane_v;
    logic [LD-1:0] s1_lane [0:RATE-1];
    always @*
        for (int j = 0; j < RATE; j++)
            s1_lane[j] = {s1_win[j], lane_x[j*16 +: 16], lane_y[j*16 +: 16],
                          s1_depth[j*DB +: DB], s1_rgb[j*3*COLB +: 3*COLB]};

    logic [LD-1:0] out_lane [0:RATE-1];
    logic [31:0]   out_face;
    logic [4:0]    out_level;
    generate
        if (L == 1) begin : g_one_stage
            always @*
                for (int j = 0; j < RATE; j++)
                    out_lane[j] = s1_lane[j];
            assign out_face = setup[`SU_ID +: 32];
            assign out_level = level;
            assign busy = 1'b0;
            assign busy_before_last = 1'b0;
            wire unused_one_stage = rst | iss_now;   // no stage registers to reset
        end else begin : g_stages
            // st_*[k]: the samples issued k cycles ago, in stage k + 1
            logic [LD-1:0] st_lane [0:(L-1)*RATE-1];
            logic [31:0]   st_face [1:L-1];
            logic [4:0]    st_level [1:L-1];
            logic [L-1:1]  st_iss;                          // bit k: issued k cycles ago
            wire  [L-2:0]  iss_line = (L - 1)'({st_iss, iss_now});
            always_ff @(posedge clk) begin
                for (int j = 0; j < RATE; j++)
                    st_lane[j] <= s1_lane[j];
                st_face[1] <= setup[`SU_ID +: 32];
                st_level[1] <= level;
                for (int k = 2; k < L; k++) begin
                    for (int j = 0; j < RATE; j++)
                        st_lane[(k-1)*RATE + j] <= st_lane[(k-2)*RATE + j];
                    st_face[k] <= st_face[k-1];
                    st_level[k] <= st_level[k-1];
                end
                if (rst)
                    st_iss <= '0;
                else
                    st_iss <= iss_line;
            end
            always @*
                for (int j = 0; j < RATE; j++)
                    out_lane[j] = st_lane[(L-2)*RATE + j];
            assign out_face = st_face[L-1];
            assign out_level = st_level[L-1];
            assign busy = |st_iss;
            assign busy_before_last = |iss_line;
        end
    endgenerate

    always @*
        for (int j = 0; j < RATE; j++) begin
            {cw_en[j], cw_x[j*16 +: 16], cw_y[j*16 +: 16], cw_depth[j*DB +: DB],
             cw_rgb[j*3*COLB +: 3*COLB]} = out_lane[j];
        end
    assign cw_face = out_face;
    assign cw_level = {3'd0, out_level};
endmodule
