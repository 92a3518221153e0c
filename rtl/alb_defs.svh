// alb_defs.svh — layouts shared by the VP's units: a face's shading set-up
// as the edge store, fill queue, fill unit and pipeline carry it, and the
// codes of packet kinds, cell verdicts and stream errors.  Widths here do not
// depend on the profile, so every unit agrees on them.
`ifndef ALB_DEFS_SVH
`define ALB_DEFS_SVH

// Face set-up (vp_face_setup of vp/vp_internal.h): id, flags (S T F), base
// colour, texture base address and log2 size, and the four linear forms as
// the fill unit evaluates them, N(c, r) = origin + c step_c + r step_r with
// value N 2^(exp - P) (docs/vp.md §4).
`define SU_ID          0     // [31:0]  face id
`define SU_FLAGS       32    // [34:32] bit 0 S, bit 1 T, bit 2 F
`define SU_RGB         35    // [58:35] R G B, 8 bits each, R highest (in frame-store
                                   // units, colour_bits each, in a flat-only build: alb_parser)
`define SU_TBASE       59    // [82:59] texture base in texture memory
`define SU_TLG         83    // [86:83] log2 of the texture side
`define SU_FORM(f)     (87 + 200 * (f))   // form f: exp[7:0], origin, step_c, step_r
`define FORM_EXP       0     // [7:0]   signed exponent
`define FORM_ORIGIN    8     // [71:8]  N at sample (0, 0)
`define FORM_STEP_C    72    // [135:72] N(c + 1, r) - N(c, r)
`define FORM_STEP_R    136   // [199:136] N(c, r + 1) - N(c, r)
`define FORM_W         200
`define SETUP_W        887
`define F_DEPTH        0
`define F_SHADE        1
`define F_TEX_U        2
`define F_TEX_V        3

// A cell as the engine hands it to the fill queue: top-left sample, log2 of
// its width and height in samples, level.
`define CELL_C0        0     // [15:0]
`define CELL_R0        16    // [31:16]
`define CELL_WL        32    // [36:32]
`define CELL_HL        37    // [41:37]
`define CELL_LEVEL     42    // [46:42]
`define CELL_W         47

// Packet kinds (docs/word-format.md).
`define K_CONFIG       3'd0
`define K_TEXTURE      3'd1
`define K_FRAME        3'd2
`define K_FACE         3'd3
`define K_FRAME_END    3'd4
`define K_END          3'd5
`define K_BAD          3'd7

// Cell verdicts, as the cosim event `cell` numbers them (docs/cosim.md).
`define R_OUT          3'd1
`define R_SPLIT        3'd2
`define R_FILL         3'd3
`define R_SAMPLE_IN    3'd4
`define R_SAMPLE_OUT   3'd5

// Stream and capacity errors (error_code of alb_vp; rtl/README.md).
`define E_NONE         8'd0
`define E_OPCODE       8'd1    // not a packet opcode
`define E_GRAMMAR      8'd2    // packet out of place (before CONFIG, inside a frame, ...)
`define E_CONFIG       8'd3    // CONFIG version, length, formats or near
`define E_FORMATS      8'd4    // CONFIG formats differ from this VP's profile
`define E_RESERVED     8'd5    // reserved bits set
`define E_EDGES        8'd6    // FACE with more edges than the edge store holds
`define E_FORM         8'd7    // form exponent or mantissa out of range
`define E_INTERCEPT    8'd8    // edge intercept beyond 3.F
`define E_COUNT        8'd9    // FRAME_END count differs / too many faces in a frame
`define E_TEXTURE      8'd10   // TEXTURE size, or FACE using a texture never loaded
`define E_FOG          8'd11   // fog far not beyond fog near
`define E_TEX_FULL     8'd12   // texture memory full (TEX_WORDS)
`define E_AFTER_END    8'd13   // a word after END
`define E_OVERFLOW     8'd14   // word pushed while the FIFO was full
`define E_FRAMES_AHEAD 8'd15   // more FRAMEs taken ahead than FRAME_QUEUE holds
`define E_TAG_ALIAS    8'd16   // 2^(TAG_BITS-1) - 1 scan-outs of a store cut off in a row
`define E_UNIT         8'd17   // a packet or flag needing a unit this build leaves out

`endif
