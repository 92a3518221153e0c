// tb_vector.sv — a golden vector replayed through the model from
// SystemVerilog, over DPI-C (albatros_pkg): the vector's word stream read
// byte by byte and pushed word by word, the model run to each frame, and
// every frame's number, cycle count and CRC checked against the vector's
// expected.frames.  tests/dpi.sh builds it with Verilator and runs it on
// every vector.
//
//   +stream=DIR/expected.stream +frames=DIR/expected.frames
//   +profile=NAME +sets=key=value,key=value
module tb_vector;
  import albatros_pkg::*;

  initial begin
    string stream_path, frames_path, profile, sets;
    chandle m;
    int fd, fe, b[4], kind, stop, words, pass, fail;
    longint unsigned number, crc, cycles;
    pass = 0;
    fail = 0;
    words = 0;
    if (!$value$plusargs("stream=%s", stream_path) || !$value$plusargs("frames=%s", frames_path))
      $fatal(1, "usage: +stream=FILE +frames=FILE [+profile=NAME] [+sets=K=V,...]");
    if (!$value$plusargs("profile=%s", profile)) profile = "a512";
    if (!$value$plusargs("sets=%s", sets)) sets = "";
    m = alb_dpi_open(profile, sets, ALB_PRODUCER_GP, ALB_EV_FRAME);
    if (m == null) $fatal(1, "alb_dpi_open: %s", alb_dpi_open_error());
    fd = $fopen(stream_path, "rb");
    fe = $fopen(frames_path, "r");
    if (fd == 0 || fe == 0) $fatal(1, "cannot open %s or %s", stream_path, frames_path);
    // the stream file is little-endian 32-bit words (docs/word-format.md)
    forever begin
      int unsigned w;
      b[0] = $fgetc(fd);
      if (b[0] < 0) break;
      w = 0;
      for (int i = 0; i < 4; i++) begin
        if (i > 0) b[i] = $fgetc(fd);
        if (b[i] < 0) $fatal(1, "%s: a partial word at its end", stream_path);
        w = w | (int'(b[i]) << (8 * i));
      end
      if (alb_dpi_push(m, w) != 1)
        $fatal(1, "push refused: %s", alb_dpi_error(m));
      words++;
    end
    $fclose(fd);
    while (alb_dpi_done(m) == 0) begin
      stop = alb_dpi_run(m, ALB_EV_FRAME, 64'd1 << 40);
      if (stop < 0) $fatal(1, "model: %s", alb_dpi_error(m));
      forever begin
        kind = alb_dpi_next(m);
        if (kind == 0) break;
        if ($fscanf(fe, "%d %d %h\n", number, cycles, crc) != 3) begin
          $display("FAIL: frame %0d: no line for it in %s", alb_dpi_field(m, ALB_F_NUMBER),
                   frames_path);
          fail++;
        end else if (alb_dpi_field(m, ALB_F_NUMBER) != number ||
                     alb_dpi_field(m, ALB_F_CYCLES) != cycles ||
                     alb_dpi_field(m, ALB_F_CRC) != crc) begin
          $display("FAIL: frame %0d at cycle %0d: %0d cycles, CRC %08x; expected frame %0d, %0d cycles, CRC %08x",
                   alb_dpi_field(m, ALB_F_NUMBER), alb_dpi_field(m, ALB_F_CYCLE),
                   alb_dpi_field(m, ALB_F_CYCLES), alb_dpi_field(m, ALB_F_CRC), number, cycles,
                   crc);
          fail++;
        end else begin
          pass++;
        end
      end
    end
    if ($fscanf(fe, "%d %d %h\n", number, cycles, crc) == 3) begin
      $display("FAIL: expected frame %0d, the model ended first", number);
      fail++;
    end
    $fclose(fe);
    $display("%0d words, %0d cycles", words, alb_dpi_cycle(m));
    alb_dpi_close(m);
    $display("%0d passed, %0d failed", pass, fail);
    $finish;
  end
endmodule
