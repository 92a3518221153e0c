/* transport_fault.c — a transport that misbehaves on purpose, for the
 * bridge's fault-injection tests: corrupted bytes either way, dropped,
 * truncated, duplicated and swapped packets, a board that falls silent, a device that
 * disconnects.  Each write call is one packet (the streamer writes so).  A
 * kind may strike several times: alb_tr_faults holds a few n for each. */
#include "albatros/transport.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct {
    alb_transport *inner;
    alb_tr_faults f;
    uint64_t bytes_out, packets_out, bytes_in;
    uint8_t *held;            /* a packet held back for a swap */
    size_t held_len;
    bool gone;
} faulty;

/* n is one of a kind's entries (0: unused, never matches: n counts from 1) */
static bool listed(const uint64_t *each, uint64_t n)
{
    for (unsigned i = 0; i < ALB_TR_FAULTS_EACH; i++)
        if (each[i] && each[i] == n)
            return true;
    return false;
}

/* Flip `mask` in every listed byte that falls in buf, bytes before..before+len. */
static void corrupt_bytes(const uint64_t *each, uint64_t before, uint8_t *buf, size_t len,
                          uint8_t mask)
{
    for (unsigned i = 0; i < ALB_TR_FAULTS_EACH; i++)
        if (each[i] > before && each[i] <= before + len)
            buf[each[i] - before - 1] ^= mask;
}

static alb_tr_status pass(alb_transport *t, faulty *z, const uint8_t *data, size_t len)
{
    alb_tr_status s = z->inner->ops->write(z->inner, data, len);
    if (s)
        snprintf(t->error, sizeof t->error, "%s", z->inner->error);
    return s;
}

static alb_tr_status f_write(alb_transport *t, const uint8_t *data, size_t len)
{
    faulty *z = t->impl;
    if (z->gone) {
        snprintf(t->error, sizeof t->error, "writing to the board: device disconnected");
        return ALB_TR_GONE;
    }
    uint64_t n = ++z->packets_out;
    uint8_t *copy = malloc(len ? len : 1);
    if (!copy)
        return ALB_TR_ERROR;
    memcpy(copy, data, len);
    corrupt_bytes(z->f.corrupt_byte, z->bytes_out, copy, len, 0x10);
    z->bytes_out += len;
    alb_tr_status s = ALB_TR_OK;
    if (z->f.disconnect_after && z->bytes_out >= z->f.disconnect_after) {
        z->gone = true;
        free(copy);
        snprintf(t->error, sizeof t->error, "writing to the board: device disconnected");
        return ALB_TR_GONE;
    }
    if (listed(z->f.drop_packet, n)) {
        /* lost on the wire */
    } else if (listed(z->f.truncate_packet, n)) {
        /* cut short: the receiver waits for the rest, takes the next
         * packet's bytes for it, fails the CRC and resynchronises */
        s = pass(t, z, copy, len / 2);
    } else if (listed(z->f.swap_packet, n) && !z->held) {
        /* held until the next packet has gone; that one is never held too,
         * so swap=N with swap=N+1 swaps N and N+1 only */
        z->held = copy;
        z->held_len = len;
        return ALB_TR_OK;
    } else {
        s = pass(t, z, copy, len);
        if (!s && listed(z->f.duplicate_packet, n))
            s = pass(t, z, copy, len);
        if (!s && z->held) {
            s = pass(t, z, z->held, z->held_len);
            free(z->held);
            z->held = NULL;
        }
    }
    free(copy);
    return s;
}

static alb_tr_status f_flush(alb_transport *t)
{
    faulty *z = t->impl;
    return z->gone ? ALB_TR_GONE : z->inner->ops->flush(z->inner);
}

static alb_tr_status f_read(alb_transport *t, uint8_t *buf, size_t cap, size_t *got, unsigned timeout_ms)
{
    faulty *z = t->impl;
    *got = 0;
    if (z->gone) {
        snprintf(t->error, sizeof t->error, "reading from the board: device disconnected");
        return ALB_TR_GONE;
    }
    if (z->f.silence_after && z->bytes_in >= z->f.silence_after) {
        /* a silent board answers nothing for as long as the host waits (a
         * signal cuts the wait short, as it does a USB read's) */
        struct timespec ts = {(time_t)(timeout_ms / 1000), (long)(timeout_ms % 1000) * 1000000L};
        nanosleep(&ts, NULL);
        return ALB_TR_TIMEOUT;
    }
    size_t room = cap;
    if (z->f.silence_after && z->bytes_in + room > z->f.silence_after)
        room = (size_t)(z->f.silence_after - z->bytes_in);
    alb_tr_status s = z->inner->ops->read(z->inner, buf, room, got, timeout_ms);
    corrupt_bytes(z->f.corrupt_reply, z->bytes_in, buf, *got, 0x04);
    z->bytes_in += *got;
    return s;
}

static alb_tr_status f_hid_get(alb_transport *t, uint8_t *buf, size_t len)
{
    faulty *z = t->impl;
    if (z->gone)
        return ALB_TR_GONE;
    alb_tr_status s = z->inner->ops->hid_get(z->inner, buf, len);
    if (s)
        snprintf(t->error, sizeof t->error, "%s", z->inner->error);
    return s;
}

static alb_tr_status f_hid_set(alb_transport *t, const uint8_t *buf, size_t len)
{
    faulty *z = t->impl;
    if (z->gone)
        return ALB_TR_GONE;
    alb_tr_status s = z->inner->ops->hid_set(z->inner, buf, len);
    if (s)
        snprintf(t->error, sizeof t->error, "%s", z->inner->error);
    return s;
}

static void f_close(alb_transport *t)
{
    faulty *z = t->impl;
    z->inner->ops->close(z->inner);
    free(z->held);
    free(z);
    free(t);
}

static const alb_transport_ops fault_ops = {"faulty", f_write, f_flush, f_read, f_hid_get, f_hid_set,
                                        f_close};

alb_transport *alb_transport_faulty(alb_transport *inner, const alb_tr_faults *f)
{
    alb_transport *t = calloc(1, sizeof *t);
    faulty *z = calloc(1, sizeof *z);
    if (!t || !z) {
        free(t);
        free(z);
        return NULL;
    }
    z->inner = inner;
    z->f = *f;
    t->ops = &fault_ops;
    t->impl = z;
    t->max_payload = inner->max_payload;
    return t;
}
