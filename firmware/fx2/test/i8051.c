/* i8051.c — the 8051 opcode map by its regular layout: the low nibble
 * picks the operand (8..F: Rn, 6..7: @Ri, 5: direct, 4: A or #data), the
 * high nibble the operation; columns 0..3 hold the jumps, calls, bit and
 * MOVX/MOVC instructions.  Classic cycles from the MCS-51 instruction set;
 * FX2 cycles from the EZ-USB TRM's table (i8051.h).  Checked against sdas's
 * own cycle column in the firmware's listings (fx2_s51 --check-opcodes). */
#include "i8051.h"

static i8051_op op3(uint8_t len, uint8_t classic, uint8_t fx2)
{
    i8051_op o = {len, classic, fx2, false};
    return o;
}

/* One-byte-per-cycle instructions of the FX2: len cycles there. */
static i8051_op simple(uint8_t len, uint8_t classic) { return op3(len, classic, len); }

/* Columns 0..3: control flow, bits, MOVX/MOVC and the odd ones. */
static i8051_op column0(uint8_t hi)
{
    switch (hi) {
    case 0x0: return op3(1, 1, 1);              /* NOP */
    case 0x1: case 0x2: case 0x3:
        return op3(3, 2, 4);                    /* JBC, JB, JNB bit,rel */
    case 0x4: case 0x5: case 0x6: case 0x7:
        return op3(2, 2, 3);                    /* JC, JNC, JZ, JNZ rel */
    case 0x8: return op3(2, 2, 3);              /* SJMP */
    case 0x9: return op3(3, 2, 3);              /* MOV DPTR,#data16 */
    case 0xA: case 0xB:
        return op3(2, 2, 2);                    /* ORL/ANL C,/bit */
    case 0xC: case 0xD:
        return op3(2, 2, 2);                    /* PUSH, POP */
    default: {                                  /* MOVX A,@DPTR / @DPTR,A */
        i8051_op o = op3(1, 2, 2);
        o.movx = true;
        return o;
    }
    }
}

static i8051_op column2(uint8_t hi)
{
    switch (hi) {
    case 0x0: case 0x1: return op3(3, 2, 4);    /* LJMP, LCALL */
    case 0x2: case 0x3: return op3(1, 2, 4);    /* RET, RETI */
    case 0x4: case 0x5: case 0x6:
        return op3(2, 1, 2);                    /* ORL/ANL/XRL direct,A */
    case 0x7: case 0x8: case 0x9:
        return op3(2, 2, 2);                    /* ORL/ANL C,bit; MOV bit,C */
    case 0xA: case 0xB: case 0xC: case 0xD:
        return op3(2, 1, 2);                    /* MOV C,bit; CPL/CLR/SETB bit */
    default: {                                  /* MOVX A,@R0 / @R0,A */
        i8051_op o = op3(1, 2, 2);
        o.movx = true;
        return o;
    }
    }
}

static i8051_op column3(uint8_t hi)
{
    switch (hi) {
    case 0x0: case 0x1: case 0x2: case 0x3:
        return op3(1, 1, 1);                    /* RR, RRC, RL, RLC A */
    case 0x4: case 0x5: case 0x6:
        return op3(3, 2, 3);                    /* ORL/ANL/XRL direct,#data */
    case 0x7: return op3(1, 2, 3);              /* JMP @A+DPTR */
    case 0x8: case 0x9: return op3(1, 2, 3);    /* MOVC A,@A+PC / @A+DPTR */
    case 0xA: return op3(1, 2, 3);              /* INC DPTR */
    case 0xB: case 0xC: case 0xD:
        return op3(1, 1, 1);                    /* CPL, CLR, SETB C */
    default: {                                  /* MOVX A,@R1 / @R1,A */
        i8051_op o = op3(1, 2, 2);
        o.movx = true;
        return o;
    }
    }
}

/* Column 4: the accumulator and immediate forms. */
static i8051_op column4(uint8_t hi)
{
    switch (hi) {
    case 0x0: case 0x1: case 0xC: case 0xD: case 0xE: case 0xF:
        return op3(1, 1, 1);                    /* INC, DEC, SWAP, DA, CLR, CPL A */
    case 0x8: case 0xA: return op3(1, 4, 5);    /* DIV AB, MUL AB */
    case 0xB: return op3(3, 2, 4);              /* CJNE A,#data,rel */
    default: return simple(2, 1);               /* ADD..XRL, MOV, SUBB A,#data */
    }
}

/* Column 5: direct operands. */
static i8051_op column5(uint8_t hi)
{
    switch (hi) {
    case 0x7: case 0x8: return op3(3, 2, 3);    /* MOV direct,#data; MOV direct,direct */
    case 0xA: return op3(1, 1, 1);              /* reserved */
    case 0xB: case 0xD: return op3(3, 2, 4);    /* CJNE A,direct,rel; DJNZ direct,rel */
    default: return simple(2, 1);               /* INC/DEC/ADD..XCH/MOV with direct */
    }
}

/* Columns 6..F: @Ri (6, 7) and Rn (8..F) operands. */
static i8051_op column_reg(uint8_t hi, bool indirect)
{
    switch (hi) {
    case 0x7: return simple(2, 1);                          /* MOV @Ri/Rn,#data */
    case 0x8: return op3(2, 2, 2);                          /* MOV direct,@Ri/Rn */
    case 0xA: return op3(2, 2, 2);                          /* MOV @Ri/Rn,direct */
    case 0xB: return op3(3, 2, 4);                          /* CJNE @Ri/Rn,#data,rel */
    case 0xD: return indirect ? op3(1, 1, 1) : op3(2, 2, 3);   /* XCHD A,@Ri; DJNZ Rn,rel */
    default: return op3(1, 1, 1);                           /* the rest: one byte, one cycle */
    }
}

i8051_op i8051_opcode(uint8_t op)
{
    uint8_t hi = op >> 4, lo = op & 0xF;

    switch (lo) {
    case 0x0: return column0(hi);
    case 0x1: return op3(2, 2, 3);              /* AJMP / ACALL addr11 */
    case 0x2: return column2(hi);
    case 0x3: return column3(hi);
    case 0x4: return column4(hi);
    case 0x5: return column5(hi);
    default: return column_reg(hi, lo < 8);
    }
}

unsigned i8051_fx2_cycles(uint8_t op, unsigned stretch)
{
    i8051_op o = i8051_opcode(op);
    return o.fx2 + (o.movx ? stretch : 0u);
}
