// albatros_pkg.sv — the golden model of the Albatros VP for SystemVerilog
// testbenches, through DPI-C (the C side is libalbatros: albatros/dpi.h).
// A chandle is one model; docs/cosim.md says what each event means, which
// cycle it carries and how to build a scoreboard on it.
//
//   import albatros_pkg::*;
//   chandle m = alb_dpi_open("t32", "edge_units=3", ALB_PRODUCER_TB, ALB_EV_ALL);
//   ... alb_dpi_push(m, word); alb_dpi_step(m, 1);
//   while ((kind = alb_dpi_next(m)) != 0) ... alb_dpi_field(m, ALB_F_CYCLE) ...
// a bench uses some of the constants below
// verilator lint_off UNUSEDPARAM
package albatros_pkg;

  // who feeds the FIFO
  localparam int ALB_PRODUCER_GP = 0;   // the model's GP output stage, with its timing
  localparam int ALB_PRODUCER_TB = 1;   // the testbench: a word a cycle at most

  // event kinds, one bit each (albatros/sim.h, ALB_EV_*)
  localparam int ALB_EV_PUSH  = 1 << 0;
  localparam int ALB_EV_POP   = 1 << 1;
  localparam int ALB_EV_LOAD  = 1 << 2;
  localparam int ALB_EV_START = 1 << 3;
  localparam int ALB_EV_CELL  = 1 << 4;
  localparam int ALB_EV_END   = 1 << 5;
  localparam int ALB_EV_FILL  = 1 << 6;
  localparam int ALB_EV_WRITE = 1 << 7;
  localparam int ALB_EV_FRAME = 1 << 8;
  localparam int ALB_EV_ALL   = 'h1ff;

  // alb_dpi_run's answer
  localparam int ALB_STOP_CYCLES = 0;
  localparam int ALB_STOP_EVENT  = 1;
  localparam int ALB_STOP_DONE   = 2;

  // fields of the current event (albatros/dpi.h, ALB_DPI_*)
  localparam int ALB_F_CYCLE  = 0;
  localparam int ALB_F_KIND   = 1;
  localparam int ALB_F_FACE   = 2;
  localparam int ALB_F_INDEX  = 3;
  localparam int ALB_F_WORD   = 4;
  localparam int ALB_F_SLOT   = 5;
  localparam int ALB_F_EDGES  = 6;
  localparam int ALB_F_X      = 7;
  localparam int ALB_F_Y      = 8;
  localparam int ALB_F_WL     = 9;
  localparam int ALB_F_HL     = 10;
  localparam int ALB_F_LEVEL  = 11;
  localparam int ALB_F_RESULT = 12;
  localparam int ALB_F_DEPTH  = 13;
  localparam int ALB_F_R      = 14;
  localparam int ALB_F_G      = 15;
  localparam int ALB_F_B      = 16;
  localparam int ALB_F_NUMBER = 17;
  localparam int ALB_F_CYCLES = 18;
  localparam int ALB_F_CRC    = 19;

  import "DPI-C" function chandle alb_dpi_open(input string profile, input string sets,
                                               input int producer, input int events);
  import "DPI-C" function string alb_dpi_open_error();
  import "DPI-C" function void alb_dpi_close(input chandle m);
  import "DPI-C" function int alb_dpi_push(input chandle m, input int unsigned word);
  import "DPI-C" function int alb_dpi_push_file(input chandle m, input string path);
  import "DPI-C" function int alb_dpi_step(input chandle m, input int cycles);
  import "DPI-C" function int alb_dpi_run(input chandle m, input int stop_on,
                                          input longint max_cycles);
  import "DPI-C" function int alb_dpi_next(input chandle m);
  import "DPI-C" function longint alb_dpi_field(input chandle m, input int field);
  import "DPI-C" function longint alb_dpi_cycle(input chandle m);
  import "DPI-C" function int alb_dpi_done(input chandle m);
  import "DPI-C" function string alb_dpi_error(input chandle m);

endpackage
// verilator lint_on UNUSEDPARAM
