/* i8051.h — what each 8051 opcode costs: its length, its machine cycles on
 * the classic 12-clock core (what s51 counts for -t C52: 12 clocks each),
 * and its instruction cycles on the FX2's 4-clock core (EZ-USB TRM,
 * chapter 12 "Instruction Set", the high-speed core's table: most
 * instructions take one cycle per byte, MOVC and INC DPTR 3, MUL and DIV 5,
 * jumps one more than their bytes, and MOVX 2 plus the CKCON stretch, which
 * is 1 from reset).  Host code for the firmware speed figures. */
#ifndef ALBATROS_I8051_H
#define ALBATROS_I8051_H

#include <stdbool.h>
#include <stdint.h>

typedef struct {
    uint8_t len;       /* bytes */
    uint8_t classic;   /* machine cycles of 12 clocks */
    uint8_t fx2;       /* FX2 instruction cycles of 4 clocks, MOVX counted as 2 */
    bool movx;         /* the FX2 adds the CKCON stretch (MD2..0) to it */
} i8051_op;

i8051_op i8051_opcode(uint8_t op);

/* FX2 cycles of one opcode with MOVX stretch `stretch` (0..7, reset 1). */
unsigned i8051_fx2_cycles(uint8_t op, unsigned stretch);

#endif
