/* fx2sim.c — the FX2's USB side and FPGA bus around the firmware in s51
 * (fx2sim.h).  Register addresses from the EZ-USB TRM, chapter 15; the
 * firmware's own names for them are in firmware/fx2/fx2regs.h. */
#include "fx2sim.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* xram registers and buffers */
#define R_USBIRQ     0xE65Du
#define R_EPIRQ      0xE65Fu
#define R_OUTPKTEND  0xE649u
#define R_INPKTEND   0xE648u
#define R_USBCS      0xE680u
#define R_USBFRAMEH  0xE684u
#define R_USBFRAMEL  0xE685u
#define R_EP0BCH     0xE68Au
#define R_EP0BCL     0xE68Bu
#define R_EP1INBC    0xE68Fu
#define R_EP2BCH     0xE690u
#define R_EP4BCH     0xE694u
#define R_EP4BCL     0xE695u
#define R_EP6BCH     0xE698u
#define R_EP6BCL     0xE699u
#define R_EP8BCH     0xE69Cu
#define R_EP0CS      0xE6A0u
#define R_SETUPDAT   0xE6B8u
#define B_EP0BUF     0xE740u
#define B_EP1INBUF   0xE7C0u
#define B_EP2        0xF000u
#define B_EP4        0xF400u
#define B_EP6        0xF800u
#define B_EP8        0xFC00u
/* special function registers */
#define S_IOA        0x80u
#define S_SP         0x81u
#define S_EP2468STAT 0xAAu
#define S_EP01STAT   0xBAu
/* bits */
#define EP2EMPTY 0x01u
#define EP4EMPTY 0x04u
#define EP6EMPTY 0x10u
#define EP6FULL  0x20u
#define EP8EMPTY 0x40u
#define SUDAV    0x01u
#define URES     0x10u
#define EPSTALL  0x01u
#define HSNAK    0x80u
#define HSM      0x80u          /* USBCS: the link runs at high speed */
#define SKIP     0x80u          /* OUTPKTEND / INPKTEND */

#define TURN_LIMIT 20000000ul   /* instructions in one turn before it is a hang */
#define BOOT_LIMIT 50000000ul

static int fail(fx2_t *f, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int fail(fx2_t *f, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(f->error, sizeof f->error, fmt, ap);
    va_end(ap);
    return -1;
}

static int sim_fail(fx2_t *f, const char *what)
{
    return fail(f, "%s: %s", what, f->s.error);
}

static int push(fx2_t *f, fx2_queue *q, const char *what, const uint8_t *d, unsigned n)
{
    if (q->n == FX2_QUEUE)
        return fail(f, "more than %d %s in one step", FX2_QUEUE, what);
    if (n > sizeof q->pkt[0].data)
        return fail(f, "%s of %u bytes, more than a buffer holds", what, n);
    memcpy(q->pkt[q->n].data, d, n);
    q->pkt[q->n].len = (uint16_t)n;
    q->n++;
    return 0;
}

static int set_stat(fx2_t *f, uint8_t stat)
{
    f->stat = stat;
    return s51_write8(&f->s, "sfr", S_EP2468STAT, stat) ? sim_fail(f, "EP2468STAT") : 0;
}

/* A byte count register pair, high byte first. */
static int count16(fx2_t *f, unsigned reg, unsigned *n)
{
    uint8_t b[2];
    if (s51_read(&f->s, "xram", reg, b, 2))
        return sim_fail(f, "byte count");
    *n = (unsigned)b[0] << 8 | b[1];
    return 0;
}

#define BUF_PATTERN(i) ((uint8_t)(0x5A ^ (i) * 7))   /* s51's EP4/EP6 buffers */

static bool inside(unsigned a, unsigned n, unsigned base, unsigned size)
{
    return a >= base && a + n <= base + size;
}

/* xcopy(to, from, n): to in DPH:DPL, from and n on the stack under the
 * return address (sdcc's reentrant calling convention), as s51 shows them
 * at the stop. */
static int on_xcopy(fx2_t *f, const s51_stop *stop)
{
    uint8_t buf[1024];
    if (!stop->regs)
        return fail(f, "xcopy: s51 showed no registers");
    const uint8_t *st = stop->stack;   /* st[k] = iram[sp - k] */
    unsigned to = stop->dptr, n = (unsigned)st[4] << 8 | st[5], from = (unsigned)st[2] << 8 | st[3];
    if (n > sizeof buf || from + n > 0x10000u || to + n > 0x10000u)
        return fail(f, "xcopy(0x%04x, 0x%04x, %u): out of range", to, from, n);
    f->xcopies++;
    f->xcopy_bytes += n;
    if (!n)
        return 0;
    if (inside(from, n, B_EP2, f->ep2_len))
        memcpy(buf, f->ep2 + (from - B_EP2), n);   /* the packet we put there */
    else if (s51_read(&f->s, "xram", from, buf, n))
        return sim_fail(f, "xcopy: its source");
    if (inside(to, n, B_EP4, 512))
        memcpy(f->ep4 + (to - B_EP4), buf, n);
    else if (inside(to, n, B_EP6, 512))
        memcpy(f->ep6 + (to - B_EP6), buf, n);
    else if (s51_write(&f->s, "xram", to, buf, n))
        return sim_fail(f, "xcopy: its destination");
    return 0;
}

int fx2_check_buffers(fx2_t *f)
{
    uint8_t b[512];
    static const unsigned base[2] = {B_EP4, B_EP6};
    for (int k = 0; k < 2; k++) {
        if (s51_read(&f->s, "xram", base[k], b, sizeof b))
            return sim_fail(f, "EP buffers");
        for (unsigned i = 0; i < sizeof b; i++)
            if (b[i] != BUF_PATTERN(i))
                return fail(f, "EP%dFIFOBUF[%u] was written other than by xcopy: this model "
                               "of the chip does not see such writes", k ? 6 : 4, i);
    }
    return 0;
}

static int on_write(fx2_t *f, const s51_stop *st)
{
    unsigned n;
    uint8_t buf[512], v;

    if (!strcmp(st->space, "bits")) {   /* PA0 */
        if (s51_read8(&f->s, "sfr", S_IOA, &v))
            return sim_fail(f, "IOA");
        if ((v & 1u) && f->nrestart < FX2_QUEUE)
            f->restart[f->nrestart++] = (v >> 1) & 1u;
        return 0;
    }
    switch (st->addr) {
    case R_EP6BCL:
        if (count16(f, R_EP6BCH, &n))
            return -1;
        if (n > 512)
            return fail(f, "EP6 packet of %u bytes", n);
        return push(f, &f->in, "bulk IN packets", f->ep6, n);
    case R_EP4BCL:
        if (count16(f, R_EP4BCH, &n))
            return -1;
        if (n > 512)
            return fail(f, "EP4 packet of %u bytes", n);
        if (f->nfpga + n > f->capfpga) {
            size_t cap = f->capfpga ? f->capfpga * 2 : 65536;
            while (cap < f->nfpga + n)
                cap *= 2;
            uint8_t *p = realloc(f->fpga, cap);
            if (!p)
                return fail(f, "out of memory");
            f->fpga = p;
            f->capfpga = cap;
        }
        memcpy(f->fpga + f->nfpga, f->ep4, n);
        f->nfpga += n;
        return 0;
    case R_EP0BCL:
        if (s51_read8(&f->s, "xram", R_EP0BCL, &v))
            return sim_fail(f, "EP0BCL");
        if (!f->ctl_in) {   /* a control write arms EP0: its data arrives */
            if (f->ctl_out_len > 64)
                return fail(f, "control write of %u bytes: one packet here", f->ctl_out_len);
            if ((f->ctl_out_len && s51_write(&f->s, "xram", B_EP0BUF, f->ctl_out, f->ctl_out_len)) ||
                s51_write8(&f->s, "xram", R_EP0BCL, (uint8_t)f->ctl_out_len))
                return sim_fail(f, "EP0 OUT data");
            f->ctl_out_len = 0;
            return 0;
        }
        if (v > 64 || (v && s51_read(&f->s, "xram", B_EP0BUF, buf, v)))
            return v > 64 ? fail(f, "EP0 packet of %u bytes", v) : sim_fail(f, "EP0BUF");
        return push(f, &f->ep0, "EP0 packets", buf, v);
    case R_EP1INBC:
        if (s51_read8(&f->s, "xram", R_EP1INBC, &v))
            return sim_fail(f, "EP1INBC");
        if (v > 64 || (v && s51_read(&f->s, "xram", B_EP1INBUF, buf, v)))
            return v > 64 ? fail(f, "EP1 report of %u bytes", v) : sim_fail(f, "EP1INBUF");
        return push(f, &f->ep1, "HID input reports", buf, v);
    default:
        return fail(f, "a write to %s[0x%x] nobody watches", st->space, st->addr);
    }
}

static int stops(fx2_t *f, unsigned long limit);

/* Run until the firmware's main loop calls usb_poll() again.  The firmware
 * hands EP2's and EP8's buffers back by a skip in OUTPKTEND and INPKTEND:
 * read when the turn is over (cheaper than stopping at the writes; it
 * looks at each endpoint once a turn, so it cannot see the flag late). */
static int turn(fx2_t *f, unsigned long limit)
{
    static const uint8_t zero[2] = {0, 0};
    uint8_t pe[2];   /* INPKTEND, OUTPKTEND */
    if (s51_write(&f->s, "xram", R_INPKTEND, zero, 2))
        return sim_fail(f, "PKTEND");
    if (stops(f, limit))
        return -1;
    if (s51_read(&f->s, "xram", R_INPKTEND, pe, 2))
        return sim_fail(f, "PKTEND");
    if ((pe[0] && pe[0] != (SKIP | 0x08u)) || (pe[1] && pe[1] != (SKIP | 0x02u)))
        return fail(f, "INPKTEND = 0x%02x, OUTPKTEND = 0x%02x: not skips of EP8 and EP2", pe[0],
                    pe[1]);
    uint8_t stat = f->stat;
    if (pe[1]) {
        f->ep2_taken = true;
        stat |= EP2EMPTY;
    }
    if (pe[0]) {
        f->ep8_taken = true;
        stat |= EP8EMPTY;
    }
    return stat != f->stat ? set_stat(f, stat) : 0;
}

static int stops(fx2_t *f, unsigned long limit)
{
    s51_stop st;
    f->turn_clocks = 0;
    for (;;) {
        if (s51_run(&f->s, limit, &st))
            return sim_fail(f, "run");
        f->clocks += st.ticks;
        f->turn_clocks += st.ticks;
        if (st.kind == S51_LIMIT)
            return fail(f, "the firmware did not come back to its main loop within %lu "
                           "instructions (pc 0x%04x)", limit, st.pc);
        if (st.kind == S51_FETCH && st.pc == f->a_usb_poll)
            return 0;
        if (st.kind == S51_FETCH && st.pc == f->a_xcopy) {
            if (getenv("FX2SIM_TRACE"))
                fprintf(stderr, "  stop: xcopy\n");
            if (on_xcopy(f, &st))
                return -1;
            continue;
        }
        if (st.kind == S51_FETCH)
            return fail(f, "stopped at 0x%04x: no breakpoint of ours", st.pc);
        if (getenv("FX2SIM_TRACE"))
            fprintf(stderr, "  stop: pc 0x%04x %s[0x%x]\n", st.pc, st.space, st.addr);
        if (on_write(f, &st))
            return -1;
    }
}

void fx2_clear(fx2_t *f)
{
    f->in.n = f->ep0.n = f->ep1.n = 0;
    f->nfpga = 0;
    f->nrestart = 0;
}

static const unsigned watched[] = {R_EP6BCL, R_EP4BCL, R_EP0BCL, R_EP1INBC};

int fx2_open(fx2_t *f, const char *cpu, const char *ihx, const listing_t *l,
             const char *preload)
{
    uint8_t zero[256] = {0}, pattern[512];
    long poll = listing_addr(l, "_usb_poll"), xcopy = listing_addr(l, "_xcopy");

    memset(f, 0, sizeof *f);
    f->lst = l;
    if (poll < 0 || xcopy < 0)
        return fail(f, "the listings have no %s", poll < 0 ? "_usb_poll" : "_xcopy");
    f->a_usb_poll = (unsigned)poll;
    f->a_xcopy = (unsigned)xcopy;
    if (s51_open(&f->s, cpu, ihx, preload))
        return sim_fail(f, "s51");
    /* the registers at reset (s51 fills RAM with noise): all clear, the
     * link at high speed, every endpoint empty */
    for (unsigned i = 0; i < sizeof pattern; i++)
        pattern[i] = BUF_PATTERN(i);
    int rc = s51_write(&f->s, "xram", 0xE600, zero, sizeof zero) ||
             s51_write(&f->s, "xram", B_EP4, pattern, sizeof pattern) ||
             s51_write(&f->s, "xram", B_EP6, pattern, sizeof pattern) ||
             s51_write8(&f->s, "xram", R_USBCS, HSM) ||
             s51_write8(&f->s, "sfr", S_EP01STAT, 0);
    for (size_t i = 0; !rc && i < sizeof watched / sizeof watched[0]; i++)
        rc = s51_break_write(&f->s, "xram", watched[i]);
    if (!rc)
        rc = s51_break_write(&f->s, "bits", S_IOA) || s51_break_fetch(&f->s, f->a_usb_poll) ||
             s51_break_fetch(&f->s, f->a_xcopy);
    if (rc) {
        sim_fail(f, "set-up");
        fx2_close(f);
        return -1;
    }
    if (set_stat(f, EP2EMPTY | EP4EMPTY | EP6EMPTY | EP8EMPTY) || turn(f, BOOT_LIMIT)) {
        fx2_close(f);
        return -1;
    }
    fx2_clear(f);
    f->ep2_taken = f->ep8_taken = false;
    return 0;
}

void fx2_close(fx2_t *f)
{
    s51_close(&f->s);
    free(f->fpga);
    f->fpga = NULL;
    f->nfpga = f->capfpga = 0;
}

int fx2_bulk_out(fx2_t *f, const uint8_t *data, uint16_t len)
{
    uint8_t bc[2] = {(uint8_t)(len >> 8), (uint8_t)len};
    if (len > 512)
        return fail(f, "a USB packet of %u bytes: at most 512 at high speed", len);
    if (!(f->stat & EP2EMPTY))
        return fail(f, "EP2 still holds the last packet: the firmware did not take it");
    if ((len && s51_write(&f->s, "xram", B_EP2, data, len)) ||
        s51_write(&f->s, "xram", R_EP2BCH, bc, 2))
        return sim_fail(f, "EP2");
    memcpy(f->ep2, data, len);
    f->ep2_len = len;
    if (set_stat(f, (uint8_t)(f->stat & ~EP2EMPTY)))
        return -1;
    f->ep2_taken = false;
    return turn(f, TURN_LIMIT);
}

int fx2_control(fx2_t *f, const uint8_t setup[8], const uint8_t *out, uint16_t out_len)
{
    uint8_t irq = SUDAV;
    f->ctl_in = (setup[0] & 0x80u) != 0;
    f->ctl_out = out;
    f->ctl_out_len = f->ctl_in ? 0 : out_len;
    if (s51_write8(&f->s, "xram", R_EP0CS, 0) || s51_write(&f->s, "xram", R_SETUPDAT, setup, 8) ||
        s51_write8(&f->s, "xram", R_USBIRQ, irq))
        return sim_fail(f, "SETUP");
    if (turn(f, TURN_LIMIT))
        return -1;
    uint8_t cs;
    /* the firmware acknowledged SUDAV (write 1 to clear); the chip would
     * have cleared it: so do we, with EP0CS for the next request */
    if (s51_read8(&f->s, "xram", R_EP0CS, &cs) || s51_write8(&f->s, "xram", R_USBIRQ, 0) ||
        s51_write8(&f->s, "xram", R_EP0CS, 0))
        return sim_fail(f, "EP0CS");
    f->stalled = (cs & EPSTALL) != 0;
    f->acked = (cs & HSNAK) != 0;
    if (f->ctl_out_len)
        return fail(f, "the firmware never armed EP0 for the control write's %u bytes",
                    f->ctl_out_len);
    return 0;
}

int fx2_record(fx2_t *f, const uint8_t *data, uint16_t len)
{
    uint8_t bc[2] = {(uint8_t)(len >> 8), (uint8_t)len};
    if (len > 512)
        return fail(f, "an EP8 record of %u bytes", len);
    if ((len && s51_write(&f->s, "xram", B_EP8, data, len)) ||
        s51_write(&f->s, "xram", R_EP8BCH, bc, 2))
        return sim_fail(f, "EP8");
    if (set_stat(f, (uint8_t)(f->stat & ~EP8EMPTY)))
        return -1;
    f->ep8_taken = false;
    return turn(f, TURN_LIMIT);
}

int fx2_frame(fx2_t *f, uint16_t frame)
{
    uint8_t fr[2] = {(uint8_t)(frame >> 8 & 0x07u), (uint8_t)frame};
    if (s51_write(&f->s, "xram", R_USBFRAMEH, fr, 2))
        return sim_fail(f, "USBFRAME");
    return turn(f, TURN_LIMIT);
}

int fx2_turn(fx2_t *f) { return turn(f, TURN_LIMIT); }

int fx2_bus_reset(fx2_t *f)
{
    if (s51_write8(&f->s, "xram", R_USBIRQ, URES))
        return sim_fail(f, "USBIRQ");
    int rc = turn(f, TURN_LIMIT);
    if (!rc && s51_write8(&f->s, "xram", R_USBIRQ, 0))   /* acknowledged: the chip clears it */
        return sim_fail(f, "USBIRQ");
    return rc;
}

int fx2_peek(fx2_t *f, unsigned addr, uint8_t *out, unsigned n)
{
    return s51_read(&f->s, "xram", addr, out, n) ? sim_fail(f, "peek") : 0;
}

int fx2_patch_rom(fx2_t *f, unsigned addr, uint8_t value)
{
    return s51_write8(&f->s, "rom", addr, value) ? sim_fail(f, "patch") : 0;
}
