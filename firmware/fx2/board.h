/* board.h — the frame store the FX2's FPGA holds, as the board's INFO reply
 * states it (docs/usb-protocol.md): the iCEBreaker build of the VP, profile
 * up5k (docs/fpga.md, rtl/fpga/), 16 x 16 pixels of 4-bit channels.  Shared
 * by the firmware (main.c) and its s51 bench (test/fx2_s51.c). */
#ifndef ALB_FX2_BOARD_H
#define ALB_FX2_BOARD_H

#define FX2_BOARD_WIDTH       16
#define FX2_BOARD_HEIGHT      16
#define FX2_BOARD_COLOUR_BITS 4

#endif
