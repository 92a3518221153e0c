/* fx2regs.h — the Cypress EZ-USB FX2LP (CY7C68013A) registers this firmware
 * uses, nothing more, with their addresses and bits from the EZ-USB
 * Technical Reference Manual (chapter 15 "Registers"; the TRM's names).
 * sdcc only: __sfr / __sbit for the 8051 special function registers, __xdata
 * __at for the registers and buffers mapped into external data memory. */
#ifndef ALBATROS_FX2REGS_H
#define ALBATROS_FX2REGS_H

#include <stdint.h>

#define FX2_XREG(addr, name) __xdata __at(addr) volatile uint8_t name

/* ---- special function registers ---- */
__sfr __at(0x80) IOA;           /* port A pins */
__sbit __at(0x80) PA0;          /* PA0 (bit 0 of IOA) */
__sbit __at(0x81) PA1;          /* PA1 (bit 1 of IOA) */
__sfr __at(0x9A) AUTOPTRH1;     /* autopointer 1 address */
__sfr __at(0x9B) AUTOPTRL1;
__sfr __at(0x9D) AUTOPTRH2;     /* autopointer 2 address */
__sfr __at(0x9E) AUTOPTRL2;
__sfr __at(0xAA) EP2468STAT;    /* endpoint 2/4/6/8 empty and full */
__sfr __at(0xAF) AUTOPTRSETUP;
__sfr __at(0xB2) OEA;           /* port A output enables */
__sfr __at(0xBA) EP01STAT;      /* endpoint 0/1 busy */

/* EP2468STAT */
#define bmEP8EMPTY 0x40
#define bmEP6FULL  0x20
#define bmEP4EMPTY 0x04
#define bmEP2EMPTY 0x01
/* EP01STAT */
#define bmEP1INBSY 0x04
/* AUTOPTRSETUP: enable, increment pointer 1, increment pointer 2 */
#define bmAPTREN    0x01
#define bmAPTR1INC  0x02
#define bmAPTR2INC  0x04

/* ---- general configuration (TRM 15.5) ---- */
FX2_XREG(0xE600, CPUCS);
FX2_XREG(0xE601, IFCONFIG);
FX2_XREG(0xE602, PINFLAGSAB);
FX2_XREG(0xE603, PINFLAGSCD);
FX2_XREG(0xE604, FIFORESET);
FX2_XREG(0xE609, FIFOPINPOLAR);
FX2_XREG(0xE60B, REVCTL);

/* CPUCS: CLKSPD[1:0] in bits 4..3, 10 = 48 MHz */
#define bmCLKSPD   0x18
#define bmCLKSPD48 0x10
/* IFCONFIG */
#define bmIFCLKSRC  0x80        /* internal IFCLK */
#define bm3048MHZ   0x40        /* ... at 48 MHz */
#define bmIFCLKOE   0x20        /* drive IFCLK out to the FPGA */
#define bmIFSLAVE   0x03        /* IFCFG = 11: slave FIFO */
/* REVCTL (TRM: DYN_OUT, ENH_PKT) */
#define bmDYN_OUT   0x02        /* no auto-arming of OUT endpoints */
#define bmENH_PKT   0x01        /* enhanced packet handling: source, edit, skip */
/* FIFORESET */
#define bmNAKALL    0x80

/* ---- endpoint configuration (TRM 15.6) ---- */
FX2_XREG(0xE610, EP1OUTCFG);
FX2_XREG(0xE611, EP1INCFG);
FX2_XREG(0xE612, EP2CFG);
FX2_XREG(0xE613, EP4CFG);
FX2_XREG(0xE614, EP6CFG);
FX2_XREG(0xE615, EP8CFG);
FX2_XREG(0xE618, EP2FIFOCFG);
FX2_XREG(0xE619, EP4FIFOCFG);
FX2_XREG(0xE61A, EP6FIFOCFG);
FX2_XREG(0xE61B, EP8FIFOCFG);
FX2_XREG(0xE648, INPKTEND);
FX2_XREG(0xE649, OUTPKTEND);

/* EPxCFG */
#define bmVALID     0x80
#define bmDIR_IN    0x40
#define bmTYPE_BULK 0x20
#define bmTYPE_INT  0x30
#define bmBUF_DOUBLE 0x02       /* EP2/EP6 only; EP4/EP8 are always double */
/* EPxFIFOCFG */
#define bmWORDWIDE  0x01
/* INPKTEND / OUTPKTEND: bit 7 SKIP, bits 3..0 the endpoint */
#define bmSKIP      0x80

/* ---- interrupts (polled here: only the request bits are read) ---- */
FX2_XREG(0xE65D, USBIRQ);
FX2_XREG(0xE65F, EPIRQ);
#define bmHSGRANT 0x20
#define bmURES    0x10
#define bmSUSP    0x08
#define bmSUTOK   0x04
#define bmSOF     0x02
#define bmSUDAV   0x01

/* ---- I/O ---- */
FX2_XREG(0xE670, PORTACFG);
FX2_XREG(0xE67B, XAUTODAT1);    /* MOVX through autopointer 1 */
FX2_XREG(0xE67C, XAUTODAT2);    /* MOVX through autopointer 2 */

/* ---- USB control ---- */
FX2_XREG(0xE680, USBCS);
FX2_XREG(0xE683, TOGCTL);
FX2_XREG(0xE684, USBFRAMEH);
FX2_XREG(0xE685, USBFRAMEL);
/* USBCS */
#define bmHSM     0x80          /* high speed */
#define bmDISCON  0x08
#define bmRENUM   0x02          /* the firmware, not the boot ROM, answers EP0 */
/* TOGCTL: bit 4 IN, bits 3..0 endpoint, bit 5 reset the data toggle */
#define bmTOG_IO    0x10
#define bmTOG_RESET 0x20

/* ---- endpoints ---- */
FX2_XREG(0xE68A, EP0BCH);
FX2_XREG(0xE68B, EP0BCL);
FX2_XREG(0xE68F, EP1INBC);
FX2_XREG(0xE690, EP2BCH);
FX2_XREG(0xE691, EP2BCL);
FX2_XREG(0xE694, EP4BCH);
FX2_XREG(0xE695, EP4BCL);
FX2_XREG(0xE698, EP6BCH);
FX2_XREG(0xE699, EP6BCL);
FX2_XREG(0xE69C, EP8BCH);
FX2_XREG(0xE69D, EP8BCL);
FX2_XREG(0xE6A0, EP0CS);
FX2_XREG(0xE6A1, EP1OUTCS);
FX2_XREG(0xE6A2, EP1INCS);
FX2_XREG(0xE6A3, EP2CS);
FX2_XREG(0xE6A5, EP6CS);
/* EPxCS */
#define bmHSNAK   0x80          /* EP0CS: clear (write 1) to end the status stage */
#define bmEPBUSY  0x02
#define bmEPSTALL 0x01

/* SETUPDAT: the 8 bytes of the last SETUP packet */
__xdata __at(0xE6B8) volatile uint8_t SETUPDAT[8];

/* ---- buffers ----
 * Endpoint buffers are plain RAM to the 8051 while it owns them (between the
 * USB side handing one over and the firmware committing it), so they are not
 * volatile: the core parses EP2FIFOBUF in place and builds reports in
 * EP0BUF and EP1INBUF. */
__xdata __at(0xE740) uint8_t EP0BUF[64];
__xdata __at(0xE7C0) uint8_t EP1INBUF[64];
__xdata __at(0xF000) uint8_t EP2FIFOBUF[512];
__xdata __at(0xF400) uint8_t EP4FIFOBUF[512];
__xdata __at(0xF800) uint8_t EP6FIFOBUF[512];
__xdata __at(0xFC00) uint8_t EP8FIFOBUF[512];

/* TRM 15.14: some registers need a few cycles before the next access
 * (FIFO and endpoint configuration, byte counts); four NOPs cover IFCLK and
 * CPU both at 48 MHz. */
#define SYNCDELAY __asm__("nop\n\tnop\n\tnop\n\tnop")

#endif
