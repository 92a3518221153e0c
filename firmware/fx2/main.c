/* main.c — the FX2LP (CY7C68013A) side of the bridge: the portable core
 * (firmware/core.c) behind a HAL made of the FX2's endpoint FIFOs, with an
 * FPGA running the VP on the slave-FIFO bus.  Built by sdcc (fx2.mk).
 *
 * Where the bytes go:
 *
 *   host --EP2 OUT--> 8051 (core: framing, CRC, sequence) --EP4--> FPGA
 *   host <--EP6 IN--- 8051 (RESULT / STATUS / ERROR packets) <--EP8-- FPGA
 *   host <--EP1 IN--- 8051 (HID COUNTERS input reports); EP0: HID features
 *
 * EP2 (bulk OUT 0x02, 2 x 512) is in manual mode (AUTOOUT = 0): every USB
 * packet the host sends waits in the CPU's domain, where fw_rx parses it in
 * place in EP2FIFOBUF; only a protocol packet that straddles two USB packets
 * is assembled in rx_buf.  The buffer then goes back to the host side with
 * OUTPKTEND SKIP (nothing of EP2 reaches the FPGA directly).
 *
 * Checked payload reaches the FPGA through EP4, an OUT endpoint the host
 * never sees (it is in no descriptor).  It is never armed for USB, so after a
 * FIFO reset both its buffers belong to the 8051, which sources packets into
 * them (TRM "enhanced packet handling", REVCTL.ENH_PKT): vp_words copies the
 * words into EP4FIFOBUF with the autopointers and writing EP4BCH:L commits
 * the buffer to the slave FIFO, where the FPGA reads it (FIFOADR = 01,
 * 16-bit bus, FLAGA = EP4 empty).  A buffer is committed when full and at
 * the end of each EP2 packet, so a frame's last words never wait for more
 * host data.  A drained buffer returns to the USB domain, not to the 8051, so
 * after both are committed the 8051 waits for the FPGA to empty the FIFO and
 * takes them back with a FIFO reset of EP4.  While it waits it holds the EP2
 * buffers, so the host's bulk OUT is NAKed: the flow control of
 * docs/usb-protocol.md, down to the VP's pace.
 *
 * Results come back on EP8 (FIFOADR = 11, FLAGB = EP8 full), also in manual
 * mode (AUTOIN = 0): each record the FPGA ends with PKTEND waits for the
 * 8051, which reads it and drops it with INPKTEND SKIP.  A 20-byte record is
 * a RESULT payload (PROTO_RESULT_* layout) and goes to fw_frame_done; a
 * 4-byte record is the word offset of a malformed stream, for fw_vp_error.
 * The FPGA never writes EP6: every packet to the host is the 8051's, built
 * and numbered by the core, so the FPGA cannot race it for an IN buffer.
 * (Results in EP6, as first sketched, would have had to be intercepted and
 * rewrapped anyway, sharing buffers with the 8051's own ERROR and STATUS
 * packets.)
 *
 * vp_restart (RESET, RESUME) raises PA0 (VP_RESTART, active high) for the
 * FPGA to abandon its partial frame, with PA1 (VP_NEW_STREAM) high for a
 * RESET, after which a new CONFIG comes; and it empties EP4: words queued
 * there belong to the abandoned frame.
 *
 * Everything is polled from one loop, no interrupt handler, so the core is
 * only ever entered from here; the one nesting (records taken while
 * ep4_commit waits inside vp_words) is the kind core.c allows, a HAL
 * callback reporting a frame done or a stream error.  Not checked on hardware:
 * the buffer ownership rules above follow the TRM and need a bring-up test
 * (a RESET, a WORDS packet seen on the FPGA's side, a RESULT record back). */
#include "board.h"
#include "usb.h"
#include "fx2regs.h"

#include <string.h>

/* The largest payload accepted: 512 − header − CRC, so a host that fills its
 * packets sends one protocol packet per USB packet and the 8051 parses every
 * one in place; rx_buf only ever holds a straddling packet. */
#define FX2_MAX_PAYLOAD (PROTO_BULK_MAXPKT - PROTO_HEADER - PROTO_TRAILER)
#define RECORD_RESULT   PROTO_RESULT_BYTES
#define RECORD_ERROR    4u
#define EP4_SIZE        512u
#define EP4_BUFFERS     2u
#define HID_PERIOD_MS   100u   /* at most one COUNTERS input report per this */

__xdata fw_core fx2_core;
/* the FX2's 512-byte scratch RAM at 0xE000, outside the 16 KB of code+data */
static __xdata __at(0xE000) uint8_t rx_buf[PROTO_HEADER + FX2_MAX_PAYLOAD + PROTO_TRAILER];

static __xdata uint16_t ep4_fill;       /* bytes in the EP4 buffer being filled */
static __xdata uint8_t ep4_committed;   /* buffers handed to the FPGA since the last reset */
static __xdata uint32_t hid_sum;       /* CRC of the last COUNTERS input report */
static __xdata uint16_t hid_frame;
static __xdata fw_result record;        /* off the 8051's small stack */

/* Copy n bytes of external RAM with the two autopointers (one MOVX each). */
static void xcopy(uint16_t to, uint16_t from, uint16_t n)
{
    AUTOPTRSETUP = bmAPTREN | bmAPTR1INC | bmAPTR2INC;
    AUTOPTRH1 = (uint8_t)(from >> 8);
    AUTOPTRL1 = (uint8_t)from;
    AUTOPTRH2 = (uint8_t)(to >> 8);
    AUTOPTRL2 = (uint8_t)to;
    while (n--)
        XAUTODAT2 = XAUTODAT1;
}

/* ---- EP8: records from the FPGA ---- */

/* A record from the FPGA on EP8.  A RESULT record is copied as it lies:
 * fw_result is five u32 and sdcc stores them little-endian, as the record. */
static void poll_ep8(void)
{
    uint16_t n;

    if (EP2468STAT & bmEP8EMPTY)
        return;
    n = (uint16_t)EP8BCH << 8 | EP8BCL;
    if (n == RECORD_RESULT || n == RECORD_ERROR)
        xcopy((uint16_t)&record, (uint16_t)EP8FIFOBUF, n);
    else
        record.frame = 0xFFFFFFFFu;   /* no known record: an error, detail ~0 */
    INPKTEND = bmSKIP | 0x08;   /* the buffer back to the FPGA */
    SYNCDELAY;
    if (n == RECORD_RESULT)
        fw_frame_done(&fx2_core, &record);
    else   /* a stream error: the word offset is the record's first u32 */
        fw_vp_error(&fx2_core, record.frame);
}

/* ---- EP4: the 8051's packets to the FPGA ---- */

/* FIFO reset of EP4: both buffers empty and the 8051's again (TRM 15.6.5:
 * NAK all host traffic while a FIFO resets). */
static void ep4_reset(void)
{
    FIFORESET = bmNAKALL;
    SYNCDELAY;
    FIFORESET = 0x04;
    SYNCDELAY;
    FIFORESET = 0x00;
    SYNCDELAY;
    ep4_fill = 0;
    ep4_committed = 0;
}

static void ep4_commit(void)
{
    if (!ep4_fill)
        return;
    EP4BCH = (uint8_t)(ep4_fill >> 8);
    SYNCDELAY;
    EP4BCL = (uint8_t)ep4_fill;   /* commits the packet to the slave FIFO */
    SYNCDELAY;
    ep4_fill = 0;
    if (++ep4_committed == EP4_BUFFERS) {
        /* The FPGA reads at the VP's pace while the host waits on NAKs.
         * Its records keep flowing meanwhile: a VP that cannot post a
         * RESULT (EP8 holds two) may stop reading words. */
        while (!(EP2468STAT & bmEP4EMPTY))
            poll_ep8();
        ep4_reset();
    }
}

/* ---- the HAL ---- */

/* data points into EP2FIFOBUF or rx_buf, both external RAM: the generic
 * pointer's low 16 bits are the address. */
static void fx2_vp_words(void *ctx, const uint8_t *data, uint16_t len)
{
    uint16_t from = (uint16_t)(const __xdata uint8_t *)data, n;

    (void)ctx;
    while (len) {
        n = EP4_SIZE - ep4_fill;
        if (n > len)
            n = len;
        xcopy((uint16_t)(EP4FIFOBUF + ep4_fill), from, n);
        ep4_fill += n;
        from += n;
        len -= n;
        if (ep4_fill == EP4_SIZE)
            ep4_commit();
    }
}

static void fx2_vp_restart(void *ctx, uint8_t full)
{
    (void)ctx;
    PA1 = full ? 1 : 0;
    PA0 = 1;
    ep4_reset();
    PA0 = 0;
}

/* One whole packet to the host, as one short USB packet on EP6. */
static void fx2_send(void *ctx, const uint8_t *data, uint16_t len)
{
    (void)ctx;
    while (EP2468STAT & bmEP6FULL)
        ;   /* the host keeps an IN transfer pending (CONVENTIONS.md) */
    xcopy((uint16_t)EP6FIFOBUF, (uint16_t)(const __xdata uint8_t *)data, len);
    EP6BCH = (uint8_t)(len >> 8);
    SYNCDELAY;
    EP6BCL = (uint8_t)len;   /* commits the packet to USB */
    SYNCDELAY;
}

static const fw_hal fx2_hal = {0, fx2_vp_words, fx2_vp_restart, fx2_send, 0, 0};

/* ---- the main loop's work ---- */

/* A USB packet from the host: parse it where it lies, flush the words it
 * produced toward the FPGA, give the buffer back to the host side. */
static void poll_ep2(void)
{
    uint16_t n;

    if (EP2468STAT & bmEP2EMPTY)
        return;
    n = (uint16_t)EP2BCH << 8 | EP2BCL;
    fw_rx(&fx2_core, EP2FIFOBUF, n);
    ep4_commit();
    OUTPKTEND = bmSKIP | 0x02;
    SYNCDELAY;
}

/* HID COUNTERS input report on EP1 IN when the counters changed (their
 * CRC differs), at most every HID_PERIOD_MS (USB frames are 1 ms; the frame
 * number has 11 bits). */
static void poll_hid(void)
{
    uint16_t frame = (uint16_t)((uint16_t)USBFRAMEH << 8 | USBFRAMEL) & 0x7FFu;
    uint32_t sum;

    if (((frame - hid_frame) & 0x7FFu) < HID_PERIOD_MS || (EP01STAT & bmEP1INBSY))
        return;
    hid_frame = frame;
    EP1INBUF[0] = PROTO_HID_COUNTERS;
    fw_hid_get(&fx2_core, EP1INBUF);
    sum = proto_crc32(0, EP1INBUF, PROTO_HID_REPORT);
    if (sum == hid_sum)
        return;
    hid_sum = sum;
    EP1INBC = PROTO_HID_REPORT;
}

/* ---- set-up ---- */

static void fifo_init(void)
{
    REVCTL = bmDYN_OUT | bmENH_PKT;   /* Cypress's setting for slave FIFOs */
    SYNCDELAY;
    IFCONFIG = bmIFCLKSRC | bm3048MHZ | bmIFCLKOE | bmIFSLAVE;   /* 48 MHz to the FPGA, sync */
    SYNCDELAY;
    PINFLAGSAB = 0xF9;   /* FLAGB = EP8 full, FLAGA = EP4 empty */
    SYNCDELAY;
    PINFLAGSCD = 0x00;
    SYNCDELAY;
    FIFOPINPOLAR = 0x00;   /* flags and strobes active low */
    SYNCDELAY;
    EP1OUTCFG = 0x00;
    SYNCDELAY;
    EP1INCFG = bmVALID | bmTYPE_INT;
    SYNCDELAY;
    EP2CFG = bmVALID | bmTYPE_BULK | bmBUF_DOUBLE;               /* OUT 512 x2 */
    SYNCDELAY;
    EP4CFG = bmVALID | bmTYPE_BULK;                              /* OUT 512 x2, internal */
    SYNCDELAY;
    EP6CFG = bmVALID | bmDIR_IN | bmTYPE_BULK | bmBUF_DOUBLE;    /* IN 512 x2 */
    SYNCDELAY;
    EP8CFG = bmVALID | bmDIR_IN | bmTYPE_BULK;                   /* IN 512 x2, internal */
    SYNCDELAY;
    FIFORESET = bmNAKALL;
    SYNCDELAY;
    FIFORESET = 0x02;
    SYNCDELAY;
    FIFORESET = 0x04;
    SYNCDELAY;
    FIFORESET = 0x06;
    SYNCDELAY;
    FIFORESET = 0x08;
    SYNCDELAY;
    FIFORESET = 0x00;
    SYNCDELAY;
    EP2FIFOCFG = 0x00;          /* manual OUT, the 8051 reads it */
    SYNCDELAY;
    EP4FIFOCFG = bmWORDWIDE;    /* manual OUT, 16-bit toward the FPGA */
    SYNCDELAY;
    EP6FIFOCFG = 0x00;          /* manual IN, the 8051 writes it */
    SYNCDELAY;
    EP8FIFOCFG = bmWORDWIDE;    /* manual IN, 16-bit from the FPGA */
    SYNCDELAY;
    OUTPKTEND = bmSKIP | 0x02;  /* arm both EP2 buffers for the host */
    SYNCDELAY;
    OUTPKTEND = bmSKIP | 0x02;
    SYNCDELAY;
    ep4_fill = 0;
    ep4_committed = 0;
}

static void board_init(void)
{
    fw_init(&fx2_core, &fx2_hal, rx_buf, FX2_MAX_PAYLOAD);
    fx2_core.width = FX2_BOARD_WIDTH;   /* the FPGA design's frame store */
    fx2_core.height = FX2_BOARD_HEIGHT;
    fx2_core.colour_bits = FX2_BOARD_COLOUR_BITS;
    fx2_core.fw_version = 0x0100;
    fx2_core.serial = 1;
    memcpy(fx2_core.name, "FX2LP+FPGA VP", 13);
}

void main(void)
{
    CPUCS = (uint8_t)((CPUCS & ~bmCLKSPD) | bmCLKSPD48);   /* 8051 at 48 MHz */
    SYNCDELAY;
    PORTACFG = 0x00;
    PA0 = 0;
    PA1 = 0;
    OEA |= 0x03;   /* PA0: VP_RESTART, PA1: VP_NEW_STREAM to the FPGA */
    fifo_init();
    board_init();
    usb_init();
    for (;;) {
        usb_poll();
        if (!usb_configured())
            continue;
        poll_ep2();
        poll_ep8();
        poll_hid();
    }
}
