// alb_parser — the VP input parser (docs/microarchitecture.md, "VP input
// parser"): pops at most one word a cycle, when the FIFO held one at the
// start of the cycle and the word has somewhere to go — a FACE's words need
// a free edge-store slot, TEXTURE and END wait until everything earlier has
// retired, the rest are taken at once.  It validates every word as
// common/words.c does (docs/word-format.md) and does the set-up of
// docs/vp.md §2 and §4 as the words arrive: an edge's corner value and
// increments when its second word comes, a form's evaluation terms when its
// C mantissa comes — shifts and adds only, since S_W and S_H are powers of two.
// A build without a shading unit (SHADE_UNIT, TEX_UNIT, FOG_UNIT 0) refuses
// what would need it, E_UNIT, and without the texture unit has no texture
// table and writes no texture memory.
`include "alb_defs.svh"

module alb_parser #(
    parameter int F = 10,               // edge_frac_bits
    parameter int CB = 24,              // coef_bits
    parameter int COLB = 8,             // colour_bits
    parameter int LW = 5,               // log2 of the sample grid's width
    parameter int LH = 5,               // ... height
    parameter int EW = 27,              // edge value width (docs/vp.md §2)
    parameter int MAX_EDGES = 64,
    parameter int TEX_WORDS = 65536,
    parameter int TEX_IDS = 256,        // texture ids the table holds (the format has 256)
    parameter int FRAME_FACES = 16777215,
    parameter int SHADE_UNIT = 1,       // 0: no Gouraud shading; a FACE with S is refused
    parameter int TEX_UNIT = 1,         // 0: no texture; TEXTURE, and a FACE with T, refused
    parameter int FOG_UNIT = 1          // 0: no fog; a FRAME with fog on is refused
) (
    input  logic                 clk,
    input  logic                 rst,
    // the FIFO
    input  logic                 fifo_empty,
    input  logic [31:0]          fifo_head,
    output logic                 pop,
    // where words go, as held at the start of the cycle
    input  logic                 slot_free,      // the next slot to fill is free
    input  logic                 drained,        // everything earlier has retired
    input  logic                 frame_room,     // a FRAME register set is free
    input  logic [15:0]          frames_taken,   // FRAME packets taken so far
    // an edge's set-up, into the slot being filled
    output logic                 ew_en,
    output logic [5:0]           ew_idx,
    output logic [EW-1:0]        ew_c,           // h at the screen's top-left corner
    output logic [EW-1:0]        ew_da,          // h(top-right) - h(top-left)
    output logic [EW-1:0]        ew_db,          // h(bottom-left) - h(top-left)
    // the face complete: its slot is loaded
    output logic                 fc_en,
    output logic [`SETUP_W-1:0]  fc_setup,
    output logic [6:0]           fc_edges,
    output logic [15:0]          fc_frame,
    // a FRAME taken: the registers of its frame
    output logic                 fr_en,
    output logic [23:0]          fr_number,
    output logic [3*COLB-1:0]    fr_bg,          // in frame-store units, R highest
    output logic                 fr_fog,
    output logic [3*COLB-1:0]    fr_fog_rgb,
    output logic [31:0]          fr_fog_near,
    output logic [31:0]          fr_fog_far,
    output logic                 end_taken,      // a FRAME_END taken
    output logic                 ended,          // END taken
    // texture memory's write port
    output logic                 tw_en,
    output logic [$clog2(TEX_WORDS)-1:0] tw_addr,
    output logic [23:0]          tw_data,
    // the word popped (the cosim `pop` event)
    output logic [31:0]          pop_index,
    // a malformed stream: sticky, with what and where
    output logic                 err,
    output logic [7:0]           err_code,
    output logic [31:0]          err_word
);
    localparam int P = LW > LH ? LW : LH;
    localparam int TA = $clog2(TEX_WORDS);
    localparam int IW = TEX_IDS > 1 ? $clog2(TEX_IDS) : 1;
    localparam logic [31:0] ILIM = 32'd1 << (3 + F);           // intercepts below 2^(3+F)
    localparam logic signed [31:0] MLIM = (32'sd1 <<< (CB - 1)) - 32'sd1;
    // Without shade and texture units a face's colour at every sample is its
    // base colour scaled to the frame store, (2 c TOP + 255) / 510 — what
    // the output stage makes of c x 255 x 1.0 (vp_flat_colour) and what a
    // FRAME's background gets: scaled here once a face (sharing the
    // background's divider), not in the pipeline a sample
    localparam bit FLAT_RGB = SHADE_UNIT == 0 && TEX_UNIT == 0 && 3 * COLB <= 24;

    // ---- packet state ----
    logic        in_pkt;            // inside a packet: its header was taken
    logic [2:0]  kind;
    logic [20:0] wi;                // index of the next word within the packet
    logic [20:0] plen;              // words of the packet
    logic        have_config, in_frame;
    logic [23:0] faces_in_frame;
    logic [31:0] nwords;            // words popped so far

    // FACE
    logic [6:0]  f_edges;
    logic [2:0]  f_flags;
    logic [31:0] f_id;
    logic [23:0] f_rgb;
    logic [23:0] f_tbase;
    logic [3:0]  f_tlg;
    logic signed [7:0]  fm_exp;
    logic signed [CB-1:0] fm_a, fm_b;   // mantissas, checked to fit CB bits
    logic [`FORM_W-1:0] f_form [0:3];
    logic        e_u, e_r;
    logic [31:0] e_x1;
    // TEXTURE: the region being written
    logic [TA:0] t_base;
    // FRAME
    logic [23:0] fr_num_r;
    logic [3*COLB-1:0] fr_bg_r, fr_fogc_r;
    logic        fr_fog_r;
    logic [31:0] fr_near_r;
    logic [TA+1:0] alloc_ptr;           // texture memory's first free texel

    // ---- this cycle's word ----
    wire [31:0] w = fifo_head;
    wire [7:0]  op = w[31:24];
    // a TEXTURE header's id, a FACE header's texture; an id beyond the table
    // is never loaded (a TEXTURE of one: texture memory full)
    wire        tid_w_ok = 32'(w[23:16]) < TEX_IDS;
    wire        tid_f_ok = 32'(w[7:0]) < TEX_IDS;
    wire [IW-1:0] ti_w = IW'(w[23:16]);
    wire [IW-1:0] ti_f = IW'(w[7:0]);
    // the texture table's entries for those ids (below, with the texture unit)
    logic       tab_valid_w, tab_valid_f;
    logic [3:0] tab_alloc_w, tab_lg_f;
    logic [TA:0] tab_base_w, tab_base_f;

    function automatic [2:0] kind_of(input [7:0] o);
        case (o)
            8'hA5: kind_of = `K_CONFIG;
            8'hA7: kind_of = `K_TEXTURE;
            8'hF0: kind_of = `K_FRAME;
            8'hFA: kind_of = `K_FACE;
            8'hFE: kind_of = `K_FRAME_END;
            8'hFF: kind_of = `K_END;
            default: kind_of = `K_BAD;
        endcase
    endfunction

    wire [2:0] pkind = in_pkt ? kind : kind_of(op);
    // room for the word (docs/microarchitecture.md): a FACE's words wait for
    // a free slot, a FRAME's for a free set of FRAME registers, TEXTURE and
    // END for retirement
    wire room = pkind == `K_FACE ? slot_free
              : pkind == `K_FRAME ? frame_room
              : (pkind == `K_TEXTURE || pkind == `K_END) ? drained : 1'b1;
    assign pop = !ended && !err && !fifo_empty && room;
    assign pop_index = nwords;

    // 0..255 to frame-store units, round half up (vp_scale_colour8):
    // floor((2 c TOP + 255) / 510), TOP = 2^COLB - 1, the quotient below 2^COLB, by COLB steps
    // of restoring division at the numerator's width (a `/` would be a
    // 32-bit array divider)
    localparam int SNW = COLB + 10;     // 2 c TOP + 255 < 510 2^COLB <= 2^(COLB+9)
    function automatic [COLB-1:0] scale8(input [7:0] c);
        logic [SNW-1:0] r;
        logic [COLB-1:0] q;
        r = ((SNW'(c) << (COLB + 1)) - (SNW'(c) << 1)) + SNW'(255);   // 2 c TOP + 255
        q = '0;
        for (int i = COLB - 1; i >= 0; i--)
            if (r >= (SNW'(510) << i)) begin
                r = r - (SNW'(510) << i);
                q[i] = 1'b1;
            end
        scale8 = q;
    endfunction

    function automatic [3*COLB-1:0] scale_rgb(input [23:0] c);
        scale_rgb = {scale8(c[23:16]), scale8(c[15:8]), scale8(c[7:0])};
    endfunction

    // |m| <= 2^(CB-1) - 1
    function automatic mant_ok(input [31:0] m);
        mant_ok = $signed(m) <= MLIM && $signed(m) >= -MLIM;
    endfunction

    // ---- FACE layout: header, id, colour, forms of 4 words, edges of 2 ----
    wire [2:0]  nforms_of_hdr = 3'd1 + {2'd0, w[8]} + {1'b0, w[9], 1'b0};
    wire [2:0]  nforms = 3'd1 + {2'd0, f_flags[0]} + {1'b0, f_flags[1], 1'b0};
    wire [20:0] estart = 21'd3 + {16'd0, nforms, 2'd0};     // first edge word
    wire        in_forms = wi >= 21'd3 && wi < estart;
    wire [1:0]  form_no = 2'((wi - 21'd3) >> 2);           // in stream order
    wire [1:0]  form_word = wi[1:0] - 2'd3;                 // 0 exp, 1 A, 2 B, 3 C
    wire [6:0]  eoff = 7'(wi - estart);            // word within the edges
    wire [5:0]  edge_no = eoff[6:1];
    // the form's place in the set-up: depth, then shade with S, then u, v with T
    wire [1:0]  form_slot = form_no == 2'd0 ? 2'd`F_DEPTH
                          : f_flags[0] ? (form_no == 2'd1 ? 2'd`F_SHADE
                                          : form_no == 2'd2 ? 2'd`F_TEX_U : 2'd`F_TEX_V)
                          : (form_no == 2'd1 ? 2'd`F_TEX_U : 2'd`F_TEX_V);

    // A form's terms from its mantissas (vp_form_setup): sample (c, r) is at
    // X = (2c + 1 - S_W) 2^(P-LW), Y = (S_H - 2r - 1) 2^(P-LH) in units of
    // 2^-P, and N = A X + B Y + C 2^P; S_W, S_H powers of two make every
    // product a shift.
    function automatic [`FORM_W-1:0] form_terms(input signed [7:0] e, input signed [CB-1:0] a,
                                               input signed [CB-1:0] b, input signed [CB-1:0] c);
        logic signed [63:0] a64, b64, c64, origin, step_c, step_r;
        a64 = 64'(a);
        b64 = 64'(b);
        c64 = 64'(c);
        step_c = a64 <<< (P - LW + 1);
        step_r = -(b64 <<< (P - LH + 1));
        origin = (a64 <<< (P - LW)) - (a64 <<< P) + (b64 <<< P) - (b64 <<< (P - LH)) + (c64 <<< P);
        form_terms = {step_r, step_c, origin, e};
    endfunction

    // An edge's set-up (vp_edge_setup): G2(C, R) = a C + b R + c in doubled
    // sample coordinates, positive on the face's side (R folds the tie rule
    // into c); the engine needs h at the screen's top-left (C = R = 0) and
    // the increments to its top-right (C = 2 S_W) and bottom-left (R = 2 S_H).
    function automatic [3*EW-1:0] edge_terms(input u, input r, input [31:0] x1,
                                             input [31:0] x2);
        logic signed [63:0] q1, q2, alpha, beta, gamma;
        logic [EW-1:0] c;
        q1 = 64'(x1);
        q2 = 64'(x2);
        if (u) begin   // vertical: k = 2^(F + 1 + lh - lw)
            alpha = 64'sd1 <<< (F + 1 + LH - LW);
            beta = q2 - q1;
            gamma = (64'sd1 <<< (F + 1 + LH)) - (q2 <<< LH);
        end else begin // horizontal: k = 2^(F + 1 + lw - lh)
            alpha = q1 - q2;
            beta = -(64'sd1 <<< (F + 1 + LW - LH));
            gamma = (64'sd1 <<< (F + 2 + LW)) - (q1 <<< LW);
        end
        if (r) begin   // inside: G < 0, i.e. -G2 - 1 >= 0: a sample on the line is out
            alpha = -alpha;
            beta = -beta;
            c = EW'(-(gamma <<< 1) - 64'sd1);
        end else begin // inside: G >= 0: a sample on the line is in
            c = EW'(gamma <<< 1);
        end
        edge_terms = {EW'(beta <<< (LH + 1)), EW'(alpha <<< (LW + 1)), c};
    endfunction

    // ---- what the word does ----
    logic        bad;
    logic [7:0]  bad_code;
    logic        last;             // the packet's last word
    logic [20:0] len;              // the packet's length, at its header
    logic [TA:0] tex_base_new;
    // a texture's texels, up to 2^20 whatever TEX_WORDS is: sized by the
    // format, not by the memory, so a texture too large for a small memory
    // is refused (E_TEX_FULL) rather than wrapped to a size of 0
    localparam int SW = TA + 2 > 22 ? TA + 2 : 22;
    logic [SW-1:0] tex_size;
    logic        tex_alloc;        // a TEXTURE header that takes a new region

    always @* begin
        bad = 1'b0;
        bad_code = `E_NONE;
        len = plen;
        tex_size = '0;
        tex_base_new = '0;
        tex_alloc = 1'b0;
        if (!in_pkt) begin
            // a header: the grammar of docs/word-format.md, then the packet's fields
            case (kind_of(op))
                `K_CONFIG:    len = 21'd3;
                `K_TEXTURE:   len = 21'd1 + (21'd1 << {w[11:8], 1'b0});
                `K_FRAME:     len = 21'd5;
                `K_FACE:      len = 21'd3 + {16'd0, nforms_of_hdr, 2'd0} + {12'd0, w[23:16], 1'b0};
                default:      len = 21'd1;
            endcase
            if (kind_of(op) == `K_BAD) begin
                bad = 1'b1;
                bad_code = `E_OPCODE;
            end else if (!have_config ? kind_of(op) != `K_CONFIG
                         : kind_of(op) == `K_CONFIG ||
                           (in_frame ? kind_of(op) != `K_FACE && kind_of(op) != `K_FRAME_END
                                     : kind_of(op) == `K_FACE || kind_of(op) == `K_FRAME_END)) begin
                bad = 1'b1;
                bad_code = `E_GRAMMAR;
            end else begin
                case (kind_of(op))
                    `K_CONFIG:
                        if (w[23:0] != 24'h010002) begin   // version 1, length 2
                            bad = 1'b1;
                            bad_code = `E_CONFIG;
                        end
                    `K_TEXTURE: begin
                        tex_size = SW'(1) << {w[11:8], 1'b0};
                        tex_alloc = !(tab_valid_w && tab_alloc_w >= w[11:8]);
                        tex_base_new = tex_alloc ? alloc_ptr[TA:0] : tab_base_w;
                        if (w[15:8] > 8'd10) begin
                            bad = 1'b1;
                            bad_code = `E_TEXTURE;
                        end else if (w[7:0] != 8'd0) begin
                            bad = 1'b1;
                            bad_code = `E_RESERVED;
                        end else if (TEX_UNIT == 0) begin
                            bad = 1'b1;
                            bad_code = `E_UNIT;
                        end else if (!tid_w_ok || (tex_alloc && (SW + 1)'(alloc_ptr) +
                                                   (SW + 1)'(tex_size) > (SW + 1)'(TEX_WORDS))) begin
                            bad = 1'b1;
                            bad_code = `E_TEX_FULL;
                        end
                    end
                    `K_FACE:
                        if (w[15:11] != 5'd0) begin
                            bad = 1'b1;
                            bad_code = `E_RESERVED;
                        end else if ((w[8] && SHADE_UNIT == 0) || (w[9] && TEX_UNIT == 0)) begin
                            bad = 1'b1;
                            bad_code = `E_UNIT;
                        end else if (w[23:16] > 8'(MAX_EDGES)) begin
                            bad = 1'b1;
                            bad_code = `E_EDGES;
                        end else if (faces_in_frame >= 24'(FRAME_FACES)) begin
                            bad = 1'b1;
                            bad_code = `E_COUNT;
                        end else if (w[9] && !tab_valid_f) begin
                            bad = 1'b1;
                            bad_code = `E_TEXTURE;
                        end
                    `K_FRAME_END:
                        if (w[23:0] != faces_in_frame) begin
                            bad = 1'b1;
                            bad_code = `E_COUNT;
                        end
                    `K_END:
                        if (w[23:0] != 24'd0) begin
                            bad = 1'b1;
                            bad_code = `E_RESERVED;
                        end
                    default: ;
                endcase
            end
        end else begin
            case (kind)
                `K_CONFIG:
                    if (wi == 21'd1) begin
                        if (w[31:16] != 16'd0 || w[7:0] < 8'd4 || w[7:0] > 8'd27 ||
                            w[15:8] < 8'd8 || w[15:8] > 8'd30) begin
                            bad = 1'b1;
                            bad_code = `E_CONFIG;
                        end else if (w[7:0] != 8'(F) || w[15:8] != 8'(CB)) begin
                            bad = 1'b1;
                            bad_code = `E_FORMATS;
                        end
                    end else if (w[31] || w[30:23] == 8'hFF || w[30:0] == 31'd0) begin
                        // near: positive and finite binary32
                        bad = 1'b1;
                        bad_code = `E_CONFIG;
                    end
                `K_TEXTURE:
                    if (w[31:24] != 8'd0) begin
                        bad = 1'b1;
                        bad_code = `E_RESERVED;
                    end
                `K_FRAME:
                    if ((wi == 21'd1 && w[31:24] != 8'd0) || (wi == 21'd2 && w[30:24] != 7'd0)) begin
                        bad = 1'b1;
                        bad_code = `E_RESERVED;
                    end else if (wi == 21'd2 && w[31] && FOG_UNIT == 0) begin
                        bad = 1'b1;
                        bad_code = `E_UNIT;
                    end else if (wi == 21'd4 && fr_fog_r && w <= fr_near_r) begin
                        bad = 1'b1;
                        bad_code = `E_FOG;
                    end
                `K_FACE:
                    if (wi == 21'd2 && w[31:24] != 8'd0) begin
                        bad = 1'b1;
                        bad_code = `E_RESERVED;
                    end else if (in_forms) begin
                        if (form_word == 2'd0 ? ($signed(w) < -32'sd128 || $signed(w) > 32'sd127)
                                              : !mant_ok(w)) begin
                            bad = 1'b1;
                            bad_code = `E_FORM;
                        end
                    end else if (wi >= estart) begin
                        if (eoff[0] ? w >= ILIM : {2'b00, w[29:0]} >= ILIM) begin
                            bad = 1'b1;
                            bad_code = `E_INTERCEPT;
                        end
                    end
                default: ;
            endcase
        end
        last = in_pkt ? wi == plen - 21'd1 : len == 21'd1;
    end

    // ---- outputs formed from this cycle's word ----
    wire [3*EW-1:0] eterms = edge_terms(e_u, e_r, e_x1, w);
    wire take = pop && !bad;
    wire face_word = in_pkt && kind == `K_FACE;
    wire [`FORM_W-1:0] cur_form = form_terms(fm_exp, fm_a, fm_b, w[CB-1:0]);

    assign ew_en = take && face_word && wi >= estart && eoff[0];
    assign ew_idx = edge_no;
    assign ew_c = eterms[EW-1:0];
    assign ew_da = eterms[2*EW-1:EW];
    assign ew_db = eterms[3*EW-1:2*EW];

    // the set-up as it stands with this word's form in place
    logic [`FORM_W-1:0] forms_now [0:3];
    always @* begin
        for (int k = 0; k < 4; k++)
            forms_now[k] = f_form[k];
        if (in_forms && form_word == 2'd3)
            forms_now[form_slot] = cur_form;
    end
    assign fc_en = take && face_word && last;
    // (the forms of a unit left out are 0: a FACE that has them is refused)
    assign fc_setup = {TEX_UNIT != 0 ? forms_now[3] : `FORM_W'(0),
                       TEX_UNIT != 0 ? forms_now[2] : `FORM_W'(0),
                       SHADE_UNIT != 0 ? forms_now[1] : `FORM_W'(0), forms_now[0], f_tlg, f_tbase,
                       f_rgb, f_flags, f_id};
    assign fc_edges = f_edges;
    assign fc_frame = frames_taken - 16'd1;

    assign fr_en = take && in_pkt && kind == `K_FRAME && last;
    assign fr_number = fr_num_r;
    assign fr_bg = fr_bg_r;
    // (without the fog unit a FRAME with fog on is refused: fog is off, its
    // registers 0)
    assign fr_fog = FOG_UNIT != 0 && fr_fog_r;
    assign fr_fog_rgb = FOG_UNIT != 0 ? fr_fogc_r : '0;
    assign fr_fog_near = FOG_UNIT != 0 ? fr_near_r : '0;
    assign fr_fog_far = FOG_UNIT != 0 ? w : '0;
    assign end_taken = take && !in_pkt && kind_of(op) == `K_FRAME_END;

    assign tw_en = TEX_UNIT != 0 && take && in_pkt && kind == `K_TEXTURE;
    assign tw_addr = TEX_UNIT != 0 ? TA'(t_base + TA'(wi - 21'd1)) : '0;
    assign tw_data = TEX_UNIT != 0 ? w[23:0] : '0;

    // ---- the texture table: where each id's texels are ----
    generate
        if (TEX_UNIT != 0) begin : g_tex_table
            logic [TEX_IDS-1:0] tab_valid;
            logic [TA:0] tab_base [0:TEX_IDS-1];
            logic [3:0]  tab_lg [0:TEX_IDS-1];
            logic [3:0]  tab_alloc [0:TEX_IDS-1];   // log2 side the region was allocated for
            assign tab_valid_w = tid_w_ok && tab_valid[ti_w];
            assign tab_valid_f = tid_f_ok && tab_valid[ti_f];
            assign tab_alloc_w = tab_alloc[ti_w];
            assign tab_base_w = tab_base[ti_w];
            assign tab_base_f = tab_base[ti_f];
            assign tab_lg_f = tab_lg[ti_f];
            always_ff @(posedge clk)
                if (rst) begin
                    alloc_ptr <= '0;
                    tab_valid <= '0;
                end else if (take && !in_pkt && kind_of(op) == `K_TEXTURE) begin
                    t_base <= tex_base_new;
                    if (tex_alloc) begin
                        alloc_ptr <= alloc_ptr + (TA + 2)'(tex_size);
                        tab_alloc[ti_w] <= w[11:8];
                    end
                    tab_valid[ti_w] <= 1'b1;
                    tab_base[ti_w] <= tex_base_new;
                    tab_lg[ti_w] <= w[11:8];
                end
        end else begin : g_no_tex_table
            // every TEXTURE is refused: no texture was ever loaded
            assign tab_valid_w = 1'b0;
            assign tab_valid_f = 1'b0;
            assign tab_alloc_w = '0;
            assign tab_base_w = '0;
            assign tab_base_f = '0;
            assign tab_lg_f = '0;
            assign alloc_ptr = '0;
            assign t_base = '0;
            wire unused_tex = tid_w_ok | tid_f_ok | (|ti_w) | (|ti_f) | (|tex_base_new) |
                              tex_alloc | (|tex_size);
        end
    endgenerate

    always_ff @(posedge clk) begin
        if (rst) begin
            in_pkt <= 1'b0;
            kind <= `K_BAD;
            wi <= '0;
            plen <= '0;
            have_config <= 1'b0;
            in_frame <= 1'b0;
            faces_in_frame <= '0;
            nwords <= '0;
            ended <= 1'b0;
            err <= 1'b0;
            err_code <= `E_NONE;
            err_word <= '0;
        end else begin
            if (pop && bad) begin
                err <= 1'b1;
                err_code <= bad_code;
                err_word <= nwords;
            end else if (ended && !fifo_empty && !err) begin
                err <= 1'b1;
                err_code <= `E_AFTER_END;
                err_word <= nwords;
            end
            if (take) begin
                nwords <= nwords + 32'd1;
                if (!in_pkt) begin
                    kind <= kind_of(op);
                    plen <= len;
                    in_pkt <= !last;
                    wi <= 21'd1;
                    case (kind_of(op))
                        `K_FACE: begin
                            f_edges <= w[22:16];
                            // (a flag of a unit left out is refused: 0 here)
                            f_flags <= w[10:8] & {1'b1, TEX_UNIT != 0, SHADE_UNIT != 0};
                            f_tbase <= 24'(tab_base_f);
                            f_tlg <= tab_lg_f;
                            for (int k = 0; k < 4; k++)
                                f_form[k] <= '0;
                        end
                        `K_FRAME_END:
                            in_frame <= 1'b0;
                        `K_END:
                            ended <= 1'b1;
                        `K_FRAME:
                            fr_num_r <= w[23:0];
                        default: ;
                    endcase
                end else begin
                    wi <= wi + 21'd1;
                    if (last)
                        in_pkt <= 1'b0;
                    case (kind)
                        `K_CONFIG:
                            if (last)
                                have_config <= 1'b1;
                        `K_FRAME: begin
                            if (wi == 21'd1)
                                fr_bg_r <= scale_rgb(w[23:0]);
                            if (wi == 21'd2) begin
                                fr_fog_r <= w[31];
                                fr_fogc_r <= scale_rgb(w[23:0]);
                            end
                            if (wi == 21'd3)
                                fr_near_r <= w;
                            if (last) begin
                                in_frame <= 1'b1;
                                faces_in_frame <= '0;
                            end
                        end
                        `K_FACE: begin
                            if (wi == 21'd1)
                                f_id <= w;
                            if (wi == 21'd2)
                                f_rgb <= FLAT_RGB ? 24'(scale_rgb(w[23:0])) : w[23:0];
                            if (in_forms) begin
                                case (form_word)
                                    2'd0: fm_exp <= w[7:0];
                                    2'd1: fm_a <= w[CB-1:0];
                                    2'd2: fm_b <= w[CB-1:0];
                                    default: f_form[form_slot] <= cur_form;
                                endcase
                            end
                            if (wi >= estart && !eoff[0]) begin
                                e_u <= w[31];
                                e_r <= w[30];
                                e_x1 <= {2'b00, w[29:0]};
                            end
                            if (last)
                                faces_in_frame <= faces_in_frame + 24'd1;
                        end
                        default: ;
                    endcase
                end
            end
        end
    end
endmodule
