/* transport.c — the transport to the simulated board in this process:
 * bytes written are the board's bulk OUT, its answers are read back as bulk
 * IN.  No USB hardware, no kernel modules: CI exercises the whole path. */
#include "board.h"
#include "../proto.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static alb_tr_status sim_write(alb_transport *t, const uint8_t *data, size_t len)
{
    sim_board_rx(t->impl, data, len);
    return ALB_TR_OK;
}

static alb_tr_status sim_flush(alb_transport *t)
{
    (void)t;
    return ALB_TR_OK;
}

static alb_tr_status sim_read(alb_transport *t, uint8_t *buf, size_t cap, size_t *got, unsigned timeout_ms)
{
    (void)timeout_ms;   /* the board answers at once or not at all */
    *got = sim_board_tx(t->impl, buf, cap);
    return *got ? ALB_TR_OK : ALB_TR_TIMEOUT;
}

static alb_tr_status sim_hid_get(alb_transport *t, uint8_t *buf, size_t len)
{
    if (sim_board_hid_get(t->impl, buf, len)) {
        snprintf(t->error, sizeof t->error, "HID report %u: the board does not have it", buf[0]);
        return ALB_TR_ERROR;
    }
    return ALB_TR_OK;
}

static alb_tr_status sim_hid_set(alb_transport *t, const uint8_t *buf, size_t len)
{
    if (sim_board_hid_set(t->impl, buf, len)) {
        snprintf(t->error, sizeof t->error, "HID report %u: the board refused it", buf[0]);
        return ALB_TR_ERROR;
    }
    return ALB_TR_OK;
}

static void sim_close(alb_transport *t)
{
    sim_board_destroy(t->impl);
    free(t);
}

static const alb_transport_ops sim_ops = {"sim", sim_write, sim_flush, sim_read, sim_hid_get,
                                      sim_hid_set, sim_close};

static alb_transport *wrap(sim_board *b, size_t max_payload, char *err, size_t errlen)
{
    alb_transport *t = b ? calloc(1, sizeof *t) : NULL;
    if (!t) {
        if (b)
            snprintf(err, errlen, "out of memory");
        sim_board_destroy(b);
        return NULL;
    }
    t->ops = &sim_ops;
    t->impl = b;
    t->max_payload = PROTO_MAX_PAYLOAD;
    if (max_payload)
        sim_board_set_max_payload(b, (uint16_t)max_payload);
    return t;
}

static int payload_ok(size_t max_payload, char *err, size_t errlen)
{
    if (max_payload > PROTO_MAX_PAYLOAD) {
        snprintf(err, errlen, "simulated board: a payload of %zu bytes is above the protocol's "
                 "%u", max_payload, PROTO_MAX_PAYLOAD);
        return -1;
    }
    return 0;
}

alb_transport *sim_board_transport_rtl(const alb_profile *p, size_t max_payload, const char *path,
                                       char *warn, size_t warnlen, char *err, size_t errlen)
{
    if (payload_ok(max_payload, err, errlen))
        return NULL;
    return wrap(sim_board_create_rtl(p, path, warn, warnlen, err, errlen), max_payload, err,
                errlen);
}

alb_transport *sim_board_transport(const alb_profile *p, size_t max_payload, char *err,
                                   size_t errlen)
{
    if (payload_ok(max_payload, err, errlen))
        return NULL;
    return wrap(sim_board_create(p, err, errlen), max_payload, err, errlen);
}

sim_board *sim_board_of(alb_transport *t)
{
    return t->ops == &sim_ops ? t->impl : NULL;
}
