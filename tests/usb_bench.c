/* usb_bench.c — bulk OUT throughput of the USB transport, for
 * tests/usb-bench.sh (make usb-bench; docs/usb-protocol.md, "Throughput"):
 * RESET, then WORDS packets of the board's payload up to the amount asked
 * for, then a PING; the time from the first byte to the STATUS that answers
 * the PING, whose counters must show every packet arrived intact.  A client
 * of libalbatros's public API only, run under tests/usb_board.c --sink. */
#include "albatros/link.h"
#include "albatros/transport.h"
#include "../firmware/proto.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static unsigned long arg(int argc, char **argv, const char *name, unsigned long dflt)
{
    for (int i = 1; i + 1 < argc; i++)
        if (!strcmp(argv[i], name))
            return strtoul(argv[i + 1], NULL, 0);
    return dflt;
}

static int send(alb_transport *t, uint8_t *pkt, uint8_t type, uint32_t seq, const uint8_t *p,
                uint32_t len)
{
    size_t n = alb_link_encode(pkt, type, seq, p, len);
    if (t->ops->write(t, pkt, n)) {
        fprintf(stderr, "usb_bench: writing: %s\n", t->error);
        return -1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    alb_tr_usb_tuning tune = {(unsigned)arg(argc, argv, "--transfers", 16),
                              (size_t)arg(argc, argv, "--buffer", 65536), 5000};
    double mb = (double)arg(argc, argv, "--mb", 16);
    char err[600];
    alb_transport *t = alb_transport_usb_open_tuned(PROTO_VID, PROTO_PID, NULL, 2000, &tune, err,
                                                    sizeof err);
    if (!t) {
        fprintf(stderr, "usb_bench: %s\n", err);
        return 2;
    }
    uint8_t rep[PROTO_HID_REPORT + 1] = {PROTO_HID_INFO};
    alb_link_info info;
    if (t->ops->hid_get(t, rep, PROTO_HID_REPORT) || alb_link_info_decode(rep, &info)) {
        fprintf(stderr, "usb_bench: no INFO from the board: %s\n", t->error);
        t->ops->close(t);
        return 2;
    }
    uint32_t payload = info.max_payload & ~3u;
    uint8_t *pkt = malloc(PROTO_HEADER + PROTO_MAX_PAYLOAD + PROTO_TRAILER);
    uint8_t *words = calloc(1, PROTO_MAX_PAYLOAD);
    if (!pkt || !words)
        return 2;
    uint32_t seq = 0;
    uint64_t bytes = 0, target = (uint64_t)(mb * 1e6);
    double t0 = now();
    int rc = send(t, pkt, PROTO_T_RESET, seq++, NULL, 0);
    while (!rc && bytes < target) {
        PROTO_PUT32(words, seq);   /* not that the sink looks */
        rc = send(t, pkt, PROTO_T_WORDS, seq++, words, payload);
        bytes += PROTO_HEADER + payload + PROTO_TRAILER;
    }
    if (!rc)
        rc = send(t, pkt, PROTO_T_PING, seq++, NULL, 0);
    /* the STATUS that answers the PING: every packet counted, none damaged */
    alb_link_rx rx;
    alb_link_rx_init(&rx);
    uint32_t st[PROTO_STATUS_BYTES / 4] = {0};
    bool have = false;
    while (!rc && !have) {
        uint8_t buf[4096];
        size_t got;
        alb_tr_status s = t->ops->read(t, buf, sizeof buf, &got, 5000);
        if (s) {
            fprintf(stderr, "usb_bench: no STATUS: %s\n", s == ALB_TR_TIMEOUT ? "timeout" : t->error);
            rc = -1;
            break;
        }
        alb_link_rx_feed(&rx, buf, got);
        alb_link_packet p;
        while (alb_link_rx_next(&rx, &p) == 1)
            if (p.type == PROTO_T_STATUS && p.len >= PROTO_STATUS_BYTES) {
                for (unsigned i = 0; i < PROTO_STATUS_BYTES / 4; i++)
                    st[i] = PROTO_GET32(p.payload + 4 * i);
                have = true;
            }
    }
    double secs = now() - t0;
    alb_tr_usb_link l;
    alb_transport_usb_link(t, &l);
    t->ops->close(t);
    alb_link_rx_free(&rx);
    free(pkt);
    free(words);
    if (rc)
        return 1;
    if (st[0] != seq || st[1] || st[2] || st[3] || st[4]) {
        fprintf(stderr, "usb_bench: the board counted %u packets of %u, %u bad CRCs, %u gaps, %u "
                "duplicates, %u garbage bytes\n", st[0], seq, st[1], st[2], st[3], st[4]);
        return 1;
    }
    printf("%u,%zu,%u,%.1f,%.3f,%.1f\n", l.out_transfers, l.out_bytes, payload,
           (double)bytes / 1e6, secs, (double)bytes / 1e6 / secs);
    return 0;
}
