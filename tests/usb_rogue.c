/* usb_rogue.c — a host that breaks the rules tests/usb_board.c checks, one
 * per mode, so tests/usb-umockdev.sh can show that each check fires (the
 * albatros binary keeping them proves nothing without that):
 *   zlp    a bulk OUT transfer of one whole packet without a zero-length one
 *   leak   the device closed with an IN transfer still in flight
 *   halt   the halt cleared from inside the stalled transfer's callback,
 *          with the next transfer still queued behind it (run the board
 *          with --stall-out)
 * Plain libusb, nothing of albatros. */
#include <libusb.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#define EP_OUT 0x02
#define EP_IN  0x86

static int done;

static void LIBUSB_CALL finished(struct libusb_transfer *x)
{
    (void)x;
    done++;
}

/* the old transport's mistake: clear_halt synchronously in the callback */
static void LIBUSB_CALL stalled(struct libusb_transfer *x)
{
    if (x->status == LIBUSB_TRANSFER_STALL && done == 0)
        libusb_clear_halt(x->dev_handle, EP_OUT);
    done++;
}

static int fail(const char *what, int rc)
{
    fprintf(stderr, "usb_rogue: %s: %s\n", what, libusb_error_name(rc));
    return 2;
}

static void wait_for(libusb_context *ctx, int n)
{
    for (int spins = 0; done < n && spins < 500; spins++) {
        struct timeval tv = {0, 10000};
        libusb_handle_events_timeout_completed(ctx, &tv, NULL);
    }
}

int main(int argc, char **argv)
{
    const char *mode = argc > 1 ? argv[1] : "";
    libusb_context *ctx;
    int rc = libusb_init(&ctx);
    if (rc)
        return fail("libusb_init", rc);
    libusb_device_handle *h = libusb_open_device_with_vid_pid(ctx, 0x1209, 0x0001);
    if (!h)
        return fail("opening 1209:0001", LIBUSB_ERROR_NOT_FOUND);
    if ((rc = libusb_claim_interface(h, 0)))
        return fail("claiming interface 0", rc);
    static unsigned char buf[2][512];
    struct libusb_transfer *x[2] = {libusb_alloc_transfer(0), libusb_alloc_transfer(0)};
    if (!x[0] || !x[1])
        return fail("allocating transfers", LIBUSB_ERROR_NO_MEM);
    if (!strcmp(mode, "zlp")) {
        libusb_fill_bulk_transfer(x[0], h, EP_OUT, buf[0], 512, finished, NULL, 1000);
        if ((rc = libusb_submit_transfer(x[0])))
            return fail("submitting", rc);
        wait_for(ctx, 1);
    } else if (!strcmp(mode, "leak")) {
        libusb_fill_bulk_transfer(x[0], h, EP_IN, buf[0], 512, finished, NULL, 0);
        if ((rc = libusb_submit_transfer(x[0])))
            return fail("submitting", rc);
        libusb_release_interface(h, 0);
        libusb_close(h);   /* with the transfer in flight */
        _exit(0);          /* its memory stays: the leak is the point (no LeakSanitizer report) */
    } else if (!strcmp(mode, "halt")) {
        for (int i = 0; i < 2; i++) {
            libusb_fill_bulk_transfer(x[i], h, EP_OUT, buf[i], 500, stalled, NULL, 1000);
            if ((rc = libusb_submit_transfer(x[i])))
                return fail("submitting", rc);
        }
        wait_for(ctx, 2);
    } else {
        fprintf(stderr, "usage: usb_rogue zlp|leak|halt\n");
        return 2;
    }
    libusb_free_transfer(x[0]);
    libusb_free_transfer(x[1]);
    libusb_release_interface(h, 0);
    libusb_close(h);
    libusb_exit(ctx);
    return 0;
}
