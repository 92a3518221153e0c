// pipe_gate_tb — alb_pipe (the RTL) beside alb_pipe_gate (its synth_ice40 -dsp
// netlist, rtl/fpga/pipe-gate-check.sh) at the up5k widths: texture memory
// filled, then CYCLES cycles of random samples, set-ups (every 16 cycles, the
// exponents near the useful range), fog and depth-store answers; every output
// compared every cycle once the stages hold samples.  SHADE_UNIT, TEX_UNIT,
// FOG_UNIT (defines, default 1) set the RTL's units as the netlist was
// synthesized (-chparam): a build with units left out.
`ifndef CYCLES
`define CYCLES 1500
`endif
`ifndef SHADE_UNIT
`define SHADE_UNIT 1
`endif
`ifndef TEX_UNIT
`define TEX_UNIT 1
`endif
`ifndef FOG_UNIT
`define FOG_UNIT 1
`endif
`include "alb_defs.svh"
module tb;
  logic clk = 0, rst = 1;
  logic lane_v; logic [15:0] lane_x, lane_y; logic [`SETUP_W-1:0] setup; logic [4:0] level;
  logic fog_on; logic [11:0] fog_rgb; logic [31:0] fog_near, fog_far; logic [15:0] zr_data;
  logic tw_en; logic [7:0] tw_addr; logic [23:0] tw_data;
  wire r_zw_en, r_cw_en, g_zw_en, g_cw_en, r_b, r_bl, g_b, g_bl;
  wire [15:0] r_zw_x, r_zw_y, r_zw_d, r_cw_x, r_cw_y, r_cw_d, g_zw_x, g_zw_y, g_zw_d, g_cw_x, g_cw_y, g_cw_d;
  wire [11:0] r_rgb, g_rgb; wire [31:0] r_face, g_face; wire [7:0] r_lvl, g_lvl;
  alb_pipe #(.RATE(1), .LW(4), .LH(4), .CB(8), .DB(16), .COLB(4), .RB(8), .FI(8), .DIV_LAT(4),
             .SHADE_LAT(4), .TEX_WORDS(256), .ZR_REG(1), .SHADE_UNIT(`SHADE_UNIT),
             .TEX_UNIT(`TEX_UNIT), .FOG_UNIT(`FOG_UNIT)) r (
    .clk, .rst, .lane_v, .lane_x, .lane_y, .setup, .level, .fog_on, .fog_rgb, .fog_near, .fog_far,
    .zr_data, .zw_en(r_zw_en), .zw_x(r_zw_x), .zw_y(r_zw_y), .zw_data(r_zw_d), .cw_en(r_cw_en),
    .cw_x(r_cw_x), .cw_y(r_cw_y), .cw_depth(r_cw_d), .cw_rgb(r_rgb), .cw_face(r_face), .cw_level(r_lvl),
    .tw_en, .tw_addr, .tw_data, .busy(r_b), .busy_before_last(r_bl));
  alb_pipe_gate g (
    .clk, .rst, .lane_v, .lane_x, .lane_y, .setup, .level, .fog_on, .fog_rgb, .fog_near, .fog_far,
    .zr_data, .zw_en(g_zw_en), .zw_x(g_zw_x), .zw_y(g_zw_y), .zw_data(g_zw_d), .cw_en(g_cw_en),
    .cw_x(g_cw_x), .cw_y(g_cw_y), .cw_depth(g_cw_d), .cw_rgb(g_rgb), .cw_face(g_face), .cw_level(g_lvl),
    .tw_en, .tw_addr, .tw_data, .busy(g_b), .busy_before_last(g_bl));
  wire [155:0] ro = {r_zw_en, r_zw_x, r_zw_y, r_zw_d, r_cw_en, r_cw_x, r_cw_y, r_cw_d, r_rgb, r_face, r_lvl, r_b, r_bl};
  wire [155:0] go = {g_zw_en, g_zw_x, g_zw_y, g_zw_d, g_cw_en, g_cw_x, g_cw_y, g_cw_d, g_rgb, g_face, g_lvl, g_b, g_bl};
  integer i, k, bad = 0, wins = 0, checked = 0;
  task tick; begin #1 clk = 1; #1 clk = 0; end endtask
  initial begin
    lane_v = 0; lane_x = 0; lane_y = 0; setup = '0; level = 0; fog_on = 0; fog_rgb = 0;
    fog_near = 0; fog_far = 1; zr_data = 0; tw_en = 0; tw_addr = 0; tw_data = 0;
    tick; tick; rst = 0;
    for (i = 0; i < 256; i++) begin tw_en = 1; tw_addr = i; tw_data = $urandom; tick; end
    tw_en = 0;
    for (i = 0; i < 12; i++) tick;
    for (i = 0; i < `CYCLES; i++) begin
      if (i % 16 == 0) begin
        for (k = 0; k < `SETUP_W; k += 32) setup[k +: 32] = $urandom;
        // exponents near the useful range, so the products matter
        for (k = 0; k < 4; k++) setup[`SU_FORM(k) +: 8] = 8'($signed(($urandom % 24) - 12));
        fog_on = $urandom; fog_rgb = $urandom; fog_near = $urandom % 4096; fog_far = fog_near + 1 + $urandom % 65536;
      end
      lane_v = $urandom; lane_x = $urandom % 16; lane_y = $urandom % 16; level = $urandom;
      zr_data = ($urandom % 4 == 0) ? 0 : $urandom;
      #0.5;
      if (i > 12) begin
        checked++;
        if (ro !== go) begin bad++; if (bad < 6) $display("cycle %0d: rtl %h gate %h", i, ro, go); end
        if (r_cw_en) wins++;
      end
      tick;
    end
    $display("checked %0d cycles, %0d writes, %0d mismatches", checked, wins, bad);
    $finish;
  end
endmodule
