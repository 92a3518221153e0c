// alb_fx2_fifo — the FPGA's side of the FX2's slave FIFOs, synchronous to the
// IFCLK the FX2 drives (48 MHz, firmware/fx2/main.c: IFCONFIG internal clock,
// output, synchronous slave; 16-bit bus; flags and strobes active low).
//
//   EP4 (FIFOADR 01, FLAGA = EP4 empty): the word stream, each 32-bit word as
//        two 16-bit beats, low half first (WORDS payloads are little-endian
//        words and FD[7:0] carries the first byte), to `word_*`.
//   EP8 (FIFOADR 11, FLAGB = EP8 full): the records from `rec_*`, 16-bit
//        beats, each record ended by PKTEND (20-byte RESULT, 4-byte error).
//
// A strobe takes one IFCLK edge; the flags are registered, and after each
// strobe the FSM waits three edges before it trusts them again: the FX2
// updates a flag a clock after the strobe that changes it, and one clock more
// is margin (a flag a clock later still reads right: the bench's --flag-lag
// 1).  So a beat takes four clocks: 12 M beats/s, 24 MB/s, half of what the
// VP can take at 12 MHz and 56 times a 50 Hz stream of the built-in scene.
// The strobes are high (idle) from configuration on, before any reset.  Switching between
// the endpoints leaves the bus undriven for a clock (SLOE high before the
// FPGA drives FD, the FPGA off FD before SLOE low).
module alb_fx2_fifo (
    input  logic        ifclk,
    input  logic        rst,
    // the pins (through the top's I/O cells)
    input  logic [15:0] fd_in,
    output logic [15:0] fd_out,
    output logic        fd_oe,
    input  logic        flaga_n,      // EP4 empty
    input  logic        flagb_n,      // EP8 full
    output logic        slrd_n,
    output logic        slwr_n,
    output logic        sloe_n,
    output logic [1:0]  fifoadr,
    output logic        pktend_n,
    // the word stream toward the VP
    output logic        word_en,
    output logic [31:0] word,
    input  logic        word_full,
    // records from the VP: {last beat of its record, beat}
    input  logic        rec_empty,
    input  logic [16:0] rec_beat,
    output logic        rec_take
);
    typedef enum logic [2:0] {S_IDLE, S_RD, S_RD_WAIT, S_TURN, S_WR, S_WR_WAIT, S_END} state_t;
    state_t st;
    logic [1:0]  wait_n;
    logic        half;              // the low half is held
    logic [15:0] low;
    logic        ep4_empty, ep8_full;
    logic        rec_last;

    always_ff @(posedge ifclk) begin
        ep4_empty <= !flaga_n;
        ep8_full <= !flagb_n;
    end

    // the pins' registers, at their idle values from configuration on
    // (iCE40 flip-flops power up 0: yosys inverts those that start at 1)
    logic rd_n = 1'b1, wr_n = 1'b1, oe_n = 1'b1, pe_n = 1'b1, drive = 1'b0;
    logic [1:0] adr = 2'b01;
    assign slrd_n = rd_n;
    assign slwr_n = wr_n;
    assign sloe_n = oe_n;
    assign pktend_n = pe_n;
    assign fd_oe = drive;
    assign fifoadr = adr;

    // A record begun is written out whole, whatever rst says meanwhile: a
    // reset between taking a beat (S_WR) and its strobe (S_WR_WAIT) would
    // lose it, and the FX2 join the record's first beats to the next's.
    wire writing = st == S_TURN || st == S_WR || st == S_WR_WAIT || st == S_END;
    always_ff @(posedge ifclk) begin
        word_en <= 1'b0;
        rec_take <= 1'b0;
        rd_n <= 1'b1;
        wr_n <= 1'b1;
        pe_n <= 1'b1;
        if (rst && !writing) begin
            st <= S_IDLE;
            half <= 1'b0;
            drive <= 1'b0;
            oe_n <= 1'b1;
            adr <= 2'b01;
            wait_n <= 2'd0;
        end else if (wait_n != 2'd0) begin
            wait_n <= wait_n - 2'd1;
        end else begin
            case (st)
                // records first: a VP that cannot post one may stop taking words
                S_IDLE:
                    if (!rec_empty) begin
                        oe_n <= 1'b1;
                        adr <= 2'b11;
                        st <= S_TURN;
                        wait_n <= 2'd1;
                    end else begin
                        adr <= 2'b01;
                        oe_n <= 1'b0;
                        st <= S_RD;
                        wait_n <= 2'd1;
                    end
                S_RD:
                    if (!ep4_empty && !word_full) begin
                        rd_n <= 1'b0;          // the FX2 moves on at the next edge,
                        st <= S_RD_WAIT;         // where FD is still this beat
                    end else if (!rec_empty || (!half && ep4_empty)) begin
                        oe_n <= 1'b1;
                        st <= S_IDLE;
                        wait_n <= 2'd1;
                    end
                S_RD_WAIT: begin
                    if (half) begin
                        word <= {fd_in, low};
                        word_en <= 1'b1;
                    end else
                        low <= fd_in;
                    half <= !half;
                    st <= S_RD;
                    wait_n <= 2'd2;
                end
                S_TURN: begin
                    drive <= 1'b1;
                    st <= S_WR;
                end
                S_WR:
                    if (!ep8_full && !rec_empty) begin
                        fd_out <= rec_beat[15:0];
                        rec_last <= rec_beat[16];
                        rec_take <= 1'b1;
                        st <= S_WR_WAIT;
                    end
                S_WR_WAIT: begin
                    wr_n <= 1'b0;              // FD has held the beat a clock
                    st <= rec_last ? S_END : S_WR;
                    wait_n <= 2'd2;
                end
                S_END: begin
                    pe_n <= 1'b0;            // the record is one packet
                    drive <= 1'b0;
                    st <= S_IDLE;
                    wait_n <= 2'd2;
                end
                default: st <= S_IDLE;
            endcase
        end
    end
endmodule
