/* cmd_stream.c — `albatros stream`: send a scene's word stream to a board
 * (real over USB, or the simulated one) and check, frame by frame, its CRCs
 * and cycle counts against the emulator's; `albatros board list|info|reset`
 * over HID (docs/usb-protocol.md).  Ctrl-C during a stream stops it with the
 * frames confirmed so far reported (exit 130). */
#include "cli.h"
#include "albatros/json.h"
#include "../firmware/proto.h"
#include "commands.h"
#include "albatros/sim.h"
#include "albatros/link.h"
#include "albatros/stream.h"
#include "albatros/transport.h"
#include "../firmware/sim/board.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Exit statuses of `albatros stream` (stream_help; docs/usb-protocol.md,
 * "Exit status"): as compare and cmp(1), 0 same, 1 different, 2 trouble
 * before any comparison — here anything that stops the stream before a
 * packet is sent — plus the link's own failure and Ctrl-C. */
enum {
    EXIT_AGREE = 0,            /* every frame matches (frames mode: shown) */
    EXIT_DIFFER = 1,           /* some frame differs (frames mode: the display) */
    EXIT_INPUT = 2,            /* usage, scene, stream, profile: nothing sent */
    EXIT_LINK = 3,             /* no board, or the link failed mid-stream */
    EXIT_INTERRUPTED = 130     /* 128 + SIGINT, as a shell reports a Ctrl-C */
};

/* Ctrl-C during a stream: the one global of the command, since a signal
 * handler can reach nothing else. */
static volatile sig_atomic_t stream_stop;
static void on_stop(int sig) { stream_stop = sig; }

typedef struct {
    bool sim, json, quiet, help, no_readback, frames, no_cycle_check;
    bool rtl;                 /* --sim=rtl: the RTL board (firmware/sim/rtl_vp.h) */
    const char *rtl_board;    /* --rtl-board FILE|DIR; NULL: the one built for the profile */
    sim_rtl_tally *tally;     /* what the RTL boards opened clocked, for the report */
    unsigned vid, pid, wait_ms, timeout_ms, sim_payload;
    unsigned usb_transfers;   /* 0: the transport's defaults */
    size_t usb_buffer;
    const char *serial, *stream;
    alb_tr_faults faults;
    bool any_fault;
    long flip_frame;          /* sim: a faulty VP */
    const char *cmd;
} link_args;

static int parse_num(const char *cmd, const char *name, const char *value, unsigned long long max,
                     unsigned long long *out)
{
    char *end;
    unsigned long long v = strtoull(value, &end, 0);
    if (end == value || *end || v > max) {
        fprintf(stderr, "albatros %s: --%s %s: expected a number up to %llu\n", cmd, name, value, max);
        return -1;
    }
    *out = v;
    return 0;
}

/* A USB id in hexadecimal, as lsusb prints it and as the default 1209:0001
 * is shown: "1209" and "0x1209" are the same id. */
static int parse_usb_id(const char *cmd, const char *name, const char *value, unsigned *out)
{
    const char *hex = value[0] == '0' && (value[1] == 'x' || value[1] == 'X') ? value + 2 : value;
    size_t n = strspn(hex, "0123456789abcdefABCDEF");
    unsigned long v = n && !hex[n] ? strtoul(hex, NULL, 16) : 0;
    if (!n || hex[n] || v > 0xFFFF) {
        fprintf(stderr, "albatros %s: --%s %s: expected a hexadecimal USB id, 0 to ffff (as lsusb "
                        "shows it; 0x optional)\n", cmd, name, value);
        return -1;
    }
    *out = (unsigned)v;
    return 0;
}

/* --fault KIND=N, for demonstrating and testing recovery.  Byte and packet
 * faults may be repeated (up to ALB_TR_FAULTS_EACH of a kind); silence,
 * disconnect and flip happen once. */
static int fault_opt(link_args *a, const char *value)
{
    enum { CORRUPT, DROP, DUPLICATE, SWAP, CORRUPT_REPLY, TRUNCATE, SILENCE, DISCONNECT, FLIP };
    static const char *const kinds[] = {"corrupt", "drop", "duplicate", "swap", "corrupt-reply",
                                        "truncate", "silence", "disconnect", "flip", NULL};
    const char *eq = strchr(value, '=');
    int k = -1;
    for (int i = 0; eq && kinds[i]; i++)
        if (strlen(kinds[i]) == (size_t)(eq - value) && !strncmp(value, kinds[i], (size_t)(eq - value)))
            k = i;
    unsigned long long v;
    if (k < 0 || parse_num(a->cmd, "fault", eq + 1, k == FLIP ? UINT32_MAX : 1ull << 40, &v)) {
        fprintf(stderr, "albatros %s: --fault %s: expected corrupt|drop|duplicate|swap|silence|"
                        "disconnect|corrupt-reply|truncate|flip=N\n", a->cmd, value);
        return -1;
    }
    if (v == 0 && k != FLIP) {   /* flip names a frame, and frames count from 0 */
        fprintf(stderr, "albatros %s: --fault %s: N counts from 1 (the first byte or packet)\n",
                a->cmd, value);
        return -1;
    }
    uint64_t *each[] = {a->faults.corrupt_byte, a->faults.drop_packet,
                        a->faults.duplicate_packet, a->faults.swap_packet,
                        a->faults.corrupt_reply, a->faults.truncate_packet};
    if (k < SILENCE) {
        unsigned i = 0;
        while (i < ALB_TR_FAULTS_EACH && each[k][i])
            i++;
        if (i == ALB_TR_FAULTS_EACH) {
            fprintf(stderr, "albatros %s: --fault %s: at most %u faults of one kind\n", a->cmd,
                    value, ALB_TR_FAULTS_EACH);
            return -1;
        }
        each[k][i] = v;
        a->any_fault = true;
        return 0;
    }
    uint64_t *once = k == SILENCE ? &a->faults.silence_after : &a->faults.disconnect_after;
    if (k == FLIP ? a->flip_frame >= 0 : *once != 0) {
        fprintf(stderr, "albatros %s: --fault %s: a second %s fault: %s\n", a->cmd, value, kinds[k],
                k == SILENCE ? "the board falls silent only once"
                : k == DISCONNECT ? "the device vanishes only once"
                                  : "the simulated VP gets one frame wrong");
        return -1;
    }
    if (k == FLIP) {
        a->flip_frame = (long)v;
    } else {
        *once = v;
        a->any_fault = true;
    }
    return 0;
}

static int link_opt(void *ctx, const char *name, const char *value)
{
    link_args *a = ctx;
    unsigned long long v;
    if (!strcmp(name, "sim")) {
        /* --sim and --sim=model: the C model behind the firmware core;
         * --sim=rtl: the verilated reference RTL */
        a->sim = true;
        a->rtl = value && !strcmp(value, "rtl");
        if (value && !a->rtl && strcmp(value, "model")) {
            fprintf(stderr, "albatros %s: --sim=%s: expected --sim, --sim=model (the C model) or "
                            "--sim=rtl (the verilated RTL)\n", a->cmd, value);
            return -1;
        }
    }
    else if (!strcmp(name, "rtl-board")) a->rtl_board = value;
    else if (!strcmp(name, "json")) a->json = true;
    else if (!strcmp(name, "quiet") || !strcmp(name, "q")) a->quiet = true;
    else if (!strcmp(name, "help")) a->help = true;
    else if (!strcmp(name, "no-readback")) a->no_readback = true;
    else if (!strcmp(name, "no-cycle-check")) a->no_cycle_check = true;
    else if (!strcmp(name, "frames")) a->frames = true;
    else if (!strcmp(name, "serial")) a->serial = value;
    else if (!strcmp(name, "stream")) a->stream = value;
    else if (!strcmp(name, "fault")) return fault_opt(a, value);
    else if (!strcmp(name, "vid")) return parse_usb_id(a->cmd, name, value, &a->vid);
    else if (!strcmp(name, "pid")) return parse_usb_id(a->cmd, name, value, &a->pid);
    else {
        unsigned long long max = !strcmp(name, "sim-payload") ? PROTO_MAX_PAYLOAD
                               : !strcmp(name, "usb-transfers") ? ALB_TR_USB_MAX_TRANSFERS
                               : !strcmp(name, "usb-buffer") ? ALB_TR_USB_MAX_BYTES : 600000;
        if (parse_num(a->cmd, name, value, max, &v))
            return -1;
        if ((!strcmp(name, "usb-transfers") || !strcmp(name, "usb-buffer")) && v == 0) {
            fprintf(stderr, "albatros %s: --%s 0: expected at least 1\n", a->cmd, name);
            return -1;
        }
        if (!strcmp(name, "sim-payload")) a->sim_payload = (unsigned)v;
        else if (!strcmp(name, "usb-transfers")) a->usb_transfers = (unsigned)v;
        else if (!strcmp(name, "usb-buffer")) a->usb_buffer = (size_t)v;
        else if (!strcmp(name, "wait")) a->wait_ms = (unsigned)v;
        else if (!strcmp(name, "timeout")) a->timeout_ms = (unsigned)v;
    }
    return 0;
}

/* The link the options ask for; *board (if not NULL) is the simulated board
 * behind it with --sim, else NULL.  hid_only: control only (`board`), which
 * leaves the data interface to a stream that may be running. */
static alb_transport *open_link(const link_args *a, const alb_profile *p, sim_board **board,
                              bool hid_only)
{
    char err[600];
    /* the board may NAK as long as a RESULT may take (--timeout) */
    alb_tr_usb_tuning tune = {a->usb_transfers, a->usb_buffer, a->timeout_ms};
    char warn[600] = "";
    alb_transport *t = a->sim && a->rtl ? sim_board_transport_rtl(p, a->sim_payload, a->rtl_board,
                                                                  warn, sizeof warn, err, sizeof err)
                     : a->sim ? sim_board_transport(p, a->sim_payload, err, sizeof err)
                     : hid_only ? alb_transport_hid_open((uint16_t)a->vid, (uint16_t)a->pid, a->serial,
                                                     a->wait_ms, err, sizeof err)
                                : alb_transport_usb_open_tuned((uint16_t)a->vid, (uint16_t)a->pid,
                                                           a->serial, a->wait_ms, &tune, err,
                                                           sizeof err);
    if (!t) {
        fprintf(stderr, "albatros %s: %s\n", a->cmd, err);
        return NULL;
    }
    if (warn[0])
        fprintf(stderr, "albatros %s: warning: %s\n", a->cmd, warn);
    if (a->sim && a->rtl && a->tally)
        sim_board_rtl_tally(sim_board_of(t), a->tally);
    if (board)
        *board = a->sim ? sim_board_of(t) : NULL;
    alb_transport_usb_set_stop(t, &stream_stop);   /* before a fault wrapper hides it */
    if (a->sim && a->flip_frame >= 0)
        sim_board_flip(sim_board_of(t), (uint32_t)a->flip_frame, 5, 7, 1, 0);
    if (a->any_fault) {
        alb_transport *f = alb_transport_faulty(t, &a->faults);
        if (!f) {
            t->ops->close(t);
            return NULL;
        }
        t = f;
    }
    return t;
}

/* After a disconnect (alb_stream_opts.reattach, with --wait): the old link
 * closed, the board waited for up to --wait ms and opened as at the start —
 * a new device, so without the link faults of --fault. */
typedef struct {
    const link_args *a;
    const alb_profile *p;
} reattach_ctx;

static alb_transport *reattach_link(void *ctx, alb_transport *old, char *err, size_t errlen)
{
    const reattach_ctx *c = ctx;
    old->ops->close(old);
    link_args again = *c->a;
    again.any_fault = false;
    alb_transport *t = open_link(&again, c->p, NULL, false);
    if (!t)
        snprintf(err, errlen, "not back within --wait %u ms (the reason is above)", c->a->wait_ms);
    return t;
}

/* ---- the emulator's view of each frame ---- */

typedef struct {
    alb_stream_frame *f;
    unsigned nf, k;
    uint16_t **keep;
} expect_ctx;

static int expect_frame(void *ctx, const alb_frame *fr, const alb_vp_stats *vs, const alb_sim_counters *sc)
{
    (void)vs;
    expect_ctx *e = ctx;
    if (e->k >= e->nf)
        return 0;
    alb_stream_frame *f = &e->f[e->k];
    size_t npix = (size_t)fr->width * fr->height;
    f->crc = alb_link_frame_crc(fr->rgb, npix);
    f->cycles = sc->cycles;
    f->width = fr->width;
    f->height = fr->height;
    e->keep[e->k] = malloc(3 * npix * sizeof **e->keep);
    if (e->keep[e->k])
        memcpy(e->keep[e->k], fr->rgb, 3 * npix * sizeof **e->keep);
    f->rgb = e->keep[e->k];
    e->k++;
    return 0;
}

/* ---- Ctrl-C ---- */

typedef struct {
    struct sigaction old_int, old_term;
} stop_handlers;

/* sigaction, not signal() (whose System V semantics in strict POSIX mode
 * reset the handler on delivery, so a second Ctrl-C from the shell's process
 * group would kill the report); no SA_RESTART, so a wait in poll() or
 * nanosleep() ends at once. */
static void catch_stop(stop_handlers *h)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop;
    sigemptyset(&sa.sa_mask);
    stream_stop = 0;
    sigaction(SIGINT, &sa, &h->old_int);
    sigaction(SIGTERM, &sa, &h->old_term);
}

static void release_stop(const stop_handlers *h)
{
    sigaction(SIGINT, &h->old_int, NULL);
    sigaction(SIGTERM, &h->old_term, NULL);
}

/* ---- reports ---- */


/* The link's losses as both sides counted them, every ERROR code; the same
 * numbers as link_json. */
static void link_text(const alb_stream_report *r)
{
    uint64_t be = alb_stream_board_errors(r);
    if (be || r->rx_crc_errors || r->rx_garbage || r->rx_gaps || r->rx_duplicates) {
        fprintf(stderr, "  link: board reported %llu errors", (unsigned long long)be);
        const char *sep = " (";
        for (unsigned k = 1; k <= ALB_STREAM_ERROR_CODES; k++) {   /* code 0 (unknown) last */
            unsigned c = k % ALB_STREAM_ERROR_CODES;
            if (r->board_errors[c]) {
                fprintf(stderr, "%s%s %llu", sep, alb_link_error_name(c),
                        (unsigned long long)r->board_errors[c]);
                sep = ", ";
            }
        }
        fprintf(stderr, "%s; host saw %llu bad CRCs, %llu garbage bytes, %llu gaps, %llu "
                        "duplicates\n", be ? ")" : "", (unsigned long long)r->rx_crc_errors,
                (unsigned long long)r->rx_garbage, (unsigned long long)r->rx_gaps,
                (unsigned long long)r->rx_duplicates);
    }
    if (r->first_link_error[0])
        fprintf(stderr, "  first link error: %s\n", r->first_link_error);
}

/* The link's half of a JSON report: keys of the object j is writing. */
static void link_json(alb_json *j, const alb_stream_report *r)
{
    alb_json_kv_uint(j, "max_payload", r->max_payload);
    alb_json_kv_uint(j, "board_errors", alb_stream_board_errors(r));
    alb_json_key(j, "board_error_codes");
    alb_json_begin_object(j);
    for (unsigned k = 1; k <= ALB_STREAM_ERROR_CODES; k++) {
        unsigned c = k % ALB_STREAM_ERROR_CODES;
        alb_json_kv_uint(j, alb_link_error_key(c), r->board_errors[c]);
    }
    alb_json_end_object(j);
    alb_json_kv_uint(j, "host_crc_errors", r->rx_crc_errors);
    alb_json_kv_uint(j, "host_garbage_bytes", r->rx_garbage);
    alb_json_kv_uint(j, "host_gaps", r->rx_gaps);
    alb_json_kv_uint(j, "host_duplicates", r->rx_duplicates);
    alb_json_kv_bool(j, "interrupted", r->interrupted);
    alb_json_kv_string(j, "first_link_error", r->first_link_error);
    alb_json_kv_string(j, "first_problem", r->first_problem);
}

static void hex32(alb_json *j, const char *key, uint32_t v)
{
    char h[9];
    snprintf(h, sizeof h, "%08x", v);
    alb_json_kv_string(j, key, h);
}

/* The USB link's line of the report: speed, packets, transfers, and what
 * it recovered from. */
static void usb_text(const alb_tr_usb_link *l)
{
    fprintf(stderr, "  USB: %s speed (%u Mbit/s), %u-byte bulk packets; %u transfers of %zu bytes in "
                    "flight; %llu zero-length packets", l->speed, l->speed_mbps, l->out_packet,
            l->out_transfers, l->out_bytes, (unsigned long long)l->zero_length_packets);
    if (l->halts_cleared)
        fprintf(stderr, "; %llu stall%s recovered", (unsigned long long)l->halts_cleared,
                l->halts_cleared > 1 ? "s" : "");
    if (l->out_timeouts)
        fprintf(stderr, "; %llu OUT timeout%s", (unsigned long long)l->out_timeouts,
                l->out_timeouts > 1 ? "s" : "");
    if (l->resent_bytes)
        fprintf(stderr, "; %llu bytes resent from where their transfers stopped",
                (unsigned long long)l->resent_bytes);
    if (l->in_partial)
        fprintf(stderr, "; %llu IN transfer%s ended by timeout with data",
                (unsigned long long)l->in_partial, l->in_partial > 1 ? "s" : "");
    if (l->hid_by_libusb)
        fprintf(stderr, "; HID through libusb (no hidraw node)");
    fputc('\n', stderr);
}

static void usb_json(alb_json *j, const alb_tr_usb_link *l)
{
    alb_json_key(j, "usb");
    alb_json_begin_object(j);
    alb_json_kv_string(j, "speed", l->speed);
    alb_json_kv_uint(j, "speed_mbps", l->speed_mbps);
    alb_json_kv_uint(j, "out_packet", l->out_packet);
    alb_json_kv_uint(j, "in_packet", l->in_packet);
    alb_json_kv_uint(j, "out_transfers", l->out_transfers);
    alb_json_kv_uint(j, "out_bytes", l->out_bytes);
    alb_json_kv_uint(j, "zero_length_packets", l->zero_length_packets);
    alb_json_kv_uint(j, "halts_cleared", l->halts_cleared);
    alb_json_kv_uint(j, "out_timeouts", l->out_timeouts);
    alb_json_kv_uint(j, "resent_bytes", l->resent_bytes);
    alb_json_kv_uint(j, "in_partial", l->in_partial);
    alb_json_kv_bool(j, "hid_by_libusb", l->hid_by_libusb);
    alb_json_end_object(j);
}

/* A slow link is worth a word before the stream starts. */
static void usb_note(alb_transport *t, FILE *log)
{
    alb_tr_usb_link l;
    if (log && !alb_transport_usb_link(t, &l) && l.speed_mbps < 480)
        fprintf(log, "stream: the board is on a %s-speed link (%u Mbit/s, %u-byte packets): "
                     "about %s MB/s at most\n", l.speed, l.speed_mbps, l.out_packet,
                l.speed_mbps >= 12 ? "1" : "0.1");
}

static const char *result_name(int rc, const char *ok)
{
    return rc == EXIT_AGREE ? ok : rc == EXIT_DIFFER ? "differs"
           : rc == EXIT_INTERRUPTED ? "interrupted" : "failed";
}

/* The RTL board's line: its object and how fast its RTL ran (clocks
 * evaluated, restarts included, against the time spent evaluating them). */
static void rtl_text(const sim_rtl_tally *t)
{
    fprintf(stderr, "  RTL board %s: %llu cycles clocked in %.3f s (%.0f cycles/s)\n", t->file,
            (unsigned long long)t->cycles, t->seconds, t->seconds > 0 ? t->cycles / t->seconds : 0);
}

static void rtl_json(alb_json *j, const sim_rtl_tally *t)
{
    alb_json_key(j, "rtl_board");
    alb_json_begin_object(j);
    alb_json_kv_string(j, "file", t->file);
    alb_json_kv_uint(j, "cycles", t->cycles);
    alb_json_kv_fixed(j, "seconds", t->seconds, 3);
    alb_json_kv_uint(j, "cycles_per_second",
                     (uint64_t)(t->seconds > 0 ? t->cycles / t->seconds : 0));
    alb_json_end_object(j);
}

static void report_text(const alb_stream_report *r, const alb_stream_frame *f, unsigned nf, int rc,
                        const alb_tr_usb_link *usb, const sim_rtl_tally *rtl)
{
    if (r->interrupted)
        fprintf(stderr, "stream: interrupted: %u of %u frames confirmed by the board\n", r->frames,
                nf);
    for (unsigned i = 0; i < nf; i++) {
        if (!f[i].have) {
            if (!r->interrupted)   /* else the frames not reached yet */
                fprintf(stderr, "  frame %u: no result\n", f[i].number);
        } else if (f[i].board_crc != f[i].crc ||
                   (f[i].board_cycles != f[i].cycles && !r->cycles_unchecked))
            fprintf(stderr, "  frame %u: DIFFERS: CRC %08x (emulator %08x), %llu cycles (emulator "
                            "%llu)\n", f[i].number, f[i].board_crc, f[i].crc,
                    (unsigned long long)f[i].board_cycles, (unsigned long long)f[i].cycles);
        else if (f[i].board_cycles != f[i].cycles)
            fprintf(stderr, "  frame %u: CRC %08x matches; %llu cycles (emulator %llu, not "
                            "compared: --no-cycle-check)\n", f[i].number, f[i].board_crc,
                    (unsigned long long)f[i].board_cycles, (unsigned long long)f[i].cycles);
    }
    double secs = r->seconds > 0 ? r->seconds : 1e-9;
    fprintf(stderr, "stream: %u of %u frames match the emulator (CRC%s); %llu packets "
                    "(payloads up to %zu bytes), %.2f MB in %.2f s (%.1f MB/s); %llu resumes, %llu "
                    "queries\n", r->matched, nf,
            r->cycles_unchecked ? "; cycles not compared" : " and cycles",
            (unsigned long long)r->packets, r->max_payload,
            (double)r->bytes / 1e6, r->seconds, (double)r->bytes / 1e6 / secs,
            (unsigned long long)r->resumes, (unsigned long long)r->queries);
    if (r->reattaches)
        fprintf(stderr, "  the board disconnected %u time%s and came back; the stream started "
                        "over each time\n", r->reattaches, r->reattaches > 1 ? "s" : "");
    if (usb)
        usb_text(usb);
    if (rtl)
        rtl_text(rtl);
    link_text(r);
    if (r->first_problem[0])
        fprintf(stderr, "  first problem: %s\n", r->first_problem);
    if (rc == EXIT_AGREE)
        fprintf(stderr, "  hardware agrees with the emulator\n");
}

static void report_json(const alb_stream_report *r, const alb_stream_frame *f, unsigned nf, int rc,
                        const alb_tr_usb_link *usb, const sim_rtl_tally *rtl)
{
    alb_json j;
    alb_json_init(&j, stdout);
    alb_json_begin_object(&j);
    alb_json_kv_string(&j, "result", result_name(rc, "match"));
    alb_json_key(&j, "frames");
    alb_json_begin_array(&j);
    for (unsigned i = 0; i < nf; i++) {
        alb_json_begin_object(&j);
        alb_json_kv_uint(&j, "frame", f[i].number);
        alb_json_kv_bool(&j, "have", f[i].have);
        hex32(&j, "crc", f[i].crc);
        hex32(&j, "board_crc", f[i].board_crc);
        alb_json_kv_uint(&j, "cycles", f[i].cycles);
        alb_json_kv_uint(&j, "board_cycles", f[i].board_cycles);
        alb_json_end_object(&j);
    }
    alb_json_end_array(&j);
    alb_json_kv_uint(&j, "matched", r->matched);
    alb_json_kv_bool(&j, "cycles_compared", !r->cycles_unchecked);
    alb_json_kv_uint(&j, "cycle_mismatches", r->cycle_mismatch);
    alb_json_kv_uint(&j, "confirmed", r->frames);
    alb_json_kv_uint(&j, "packets", r->packets);
    alb_json_kv_uint(&j, "bytes", r->bytes);
    alb_json_kv_fixed(&j, "seconds", r->seconds, 3);
    alb_json_kv_uint(&j, "resumes", r->resumes);
    alb_json_kv_uint(&j, "queries", r->queries);
    alb_json_kv_uint(&j, "reattaches", r->reattaches);
    if (usb)
        usb_json(&j, usb);
    if (rtl)
        rtl_json(&j, rtl);
    link_json(&j, r);
    alb_json_end_object(&j);
    alb_json_end_line(&j);
}

/* The exit status of a alb_stream_run / alb_stream_tiles result. */
static int exit_of(int rc)
{
    return rc == -2 ? EXIT_INTERRUPTED : rc < 0 ? EXIT_LINK : rc ? EXIT_DIFFER : EXIT_AGREE;
}

/* Frames mode: the emulator's frames, RGB888, as tiles to a display board;
 * with --sim the board's display is compared with the last frame. */
static int stream_frames_mode(const link_args *a, const alb_profile *p, const alb_stream_frame *f,
                              unsigned nf)
{
    size_t npix = (size_t)p->width * p->height;
    alb_stream_tiles_frame *tf = calloc(nf ? nf : 1, sizeof *tf);
    uint8_t *rgb = malloc(3 * npix * (nf ? nf : 1));
    int rc = EXIT_INPUT;   /* until the link is open */
    if (!tf || !rgb) {
        fprintf(stderr, "albatros stream: out of memory\n");
        goto out;
    }
    for (unsigned i = 0; i < nf; i++) {
        if (!f[i].rgb) {   /* expect_frame's copy failed */
            fprintf(stderr, "albatros stream: out of memory\n");
            goto out;
        }
        alb_link_rgb888(f[i].rgb, npix, p->colour_bits, rgb + 3 * npix * i);
        tf[i] = (alb_stream_tiles_frame){f[i].number, p->width, p->height, rgb + 3 * npix * i};
    }
    sim_board *board;
    rc = EXIT_LINK;
    alb_transport *t = open_link(a, p, &board, false);
    if (!t)
        goto out;
    alb_stream_opts so;
    alb_stream_opts_default(&so);
    so.timeout_ms = a->timeout_ms;
    so.log = a->quiet || a->json ? NULL : stderr;
    so.progress = so.log && cli_isatty_stderr();
    so.stop = &stream_stop;
    stop_handlers h;
    catch_stop(&h);
    if (so.log)
        fprintf(stderr, "frames: %u frames to send to %s\n", nf, a->sim ? "the simulated board" :
                "the board");
    usb_note(t, so.log);
    alb_stream_report r;
    rc = exit_of(alb_stream_tiles(t, tf, nf, &so, &r));
    alb_tr_usb_link usb;
    bool have_usb = alb_transport_usb_link(t, &usb) == 0;
    const char *display = "";
    if (!rc && board && nf) {
        uint32_t shown;
        uint64_t tiles;
        const uint8_t *d = sim_board_display(board, &shown, &tiles);
        bool same = shown == tf[nf - 1].number && !memcmp(d, tf[nf - 1].rgb, 3 * npix);
        display = same ? "identical" : "DIFFERENT";
        rc = same ? EXIT_AGREE : EXIT_DIFFER;
    }
    double secs = r.seconds > 0 ? r.seconds : 1e-9;
    t->ops->close(t);   /* cancels what is in flight, before a long report */
    if (a->json) {
        alb_json j;
        alb_json_init(&j, stdout);
        alb_json_begin_object(&j);
        alb_json_kv_string(&j, "result", result_name(rc, "shown"));
        alb_json_kv_uint(&j, "frames", nf);
        alb_json_kv_uint(&j, "shown", r.frames);
        alb_json_kv_uint(&j, "packets", r.packets);
        alb_json_kv_uint(&j, "bytes", r.bytes);
        alb_json_kv_fixed(&j, "seconds", r.seconds, 3);
        alb_json_kv_uint(&j, "resends", r.resumes);
        alb_json_kv_string(&j, "display", display);
        if (have_usb)
            usb_json(&j, &usb);
        link_json(&j, &r);
        alb_json_end_object(&j);
        alb_json_end_line(&j);
    } else if (!a->quiet || rc) {
        if (r.interrupted)
            fprintf(stderr, "frames: interrupted: %u of %u frames confirmed by the board\n",
                    r.frames, nf);
        fprintf(stderr, "frames: %u of %u frames shown; %llu packets (payloads up to %zu bytes), "
                        "%.2f MB in %.2f s (%.1f MB/s, %.1f frames/s); %llu resends\n", r.frames,
                nf, (unsigned long long)r.packets, r.max_payload, (double)r.bytes / 1e6, r.seconds,
                (double)r.bytes / 1e6 / secs, r.frames / secs, (unsigned long long)r.resumes);
        if (have_usb)
            usb_text(&usb);
        link_text(&r);
        if (r.first_problem[0])
            fprintf(stderr, "  first problem: %s\n", r.first_problem);
        if (display[0])
            fprintf(stderr, "  the simulated display shows frame %u: %s to the emulator's\n",
                    tf[nf - 1].number, display);
    }
    release_stop(&h);
out:
    free(rgb);
    free(tf);
    return rc;
}

static const char stream_help[] =
    "usage: albatros stream [SCENE] [--sim[=rtl] | --vid V --pid P --serial S --wait MS]\n"
    "                       [--stream FILE] [--timeout MS] [--json] [options]\n\n"
    "Send SCENE's word stream (or a stream FILE) to a board that runs the VP, and\n"
    "check each frame's CRC and cycle count against the emulator (timed model).\n"
    "Link errors are reported, counted and recovered from by resending frames.\n"
    "With --frames, send the emulator's finished frames instead, as tiles for a\n"
    "board that displays them (frames mode, docs/usb-protocol.md).\n\n"
    "  --sim              the simulated board in this process (no hardware), the C\n"
    "                     model behind the firmware core (also --sim=model)\n"
    "  --sim=rtl          the same board with the verilated reference RTL as its VP:\n"
    "                     the RTL's own CRCs and cycles (make rtl-board PROFILE=P\n"
    "                     builds it for a profile; Verilator)\n"
    "  --rtl-board PATH   that RTL board's shared object, or its directory (default:\n"
    "                     rtl-board/PROFILE/ beside this program); one built for\n"
    "                     other parameters is run with a warning\n"
    "  --sim-payload N    the simulated board accepts payloads up to N bytes (default\n"
    "                     16384; the FX2 firmware takes 492)\n"
    "  --vid, --pid       USB ids in hexadecimal as lsusb shows them, 0x optional\n"
    "                     (default 1209:0001, the pid.codes test PID)\n"
    "  --serial S         the board with this serial number\n"
    "  --wait MS          wait this long for the board to appear (hot-plug; default\n"
    "                     2000), and again after a disconnect: the stream then\n"
    "                     starts over (0: a disconnect ends it)\n"
    "  --timeout MS       wait this long for a frame's result, and for a board that\n"
    "                     NAKs to take data (then the transfers in flight are\n"
    "                     cancelled and their unsent bytes sent again; default 2000)\n"
    "  --usb-transfers N  bulk OUT transfers in flight (default 16, at most 64)\n"
    "  --usb-buffer BYTES each transfer's size (default 65536; whole packets)\n"
    "  --no-readback      do not fetch a differing frame to name its first wrong pixel\n"
    "  --no-cycle-check   report the board's cycle counts but match frames on their\n"
    "                     CRC alone: a real FPGA board takes the words as USB\n"
    "                     delivers them, not at the GP's pace (docs/fpga.md)\n"
    "  --frames           frames mode: the rendered frames, RGB888 tiles, to a display\n"
    "  --fault KIND=N     misbehave on purpose (N counts from 1); repeatable, up to\n"
    "                     8 of a kind, but silence, disconnect and flip once only:\n"
    "                       corrupt=N        flip a bit of the N-th byte sent\n"
    "                       corrupt-reply=N  flip a bit of the N-th byte received\n"
    "                       drop=N           lose the N-th packet sent (1 = the first\n"
    "                                        RESET; reports name packets by sequence\n"
    "                                        number, which is N - 1)\n"
    "                       truncate=N       send only the first half of the N-th packet\n"
    "                       duplicate=N      send the N-th packet twice\n"
    "                       swap=N           send packets N and N+1 in reverse order\n"
    "                       silence=N        the board falls silent after N bytes received\n"
    "                       disconnect=N     the device vanishes after N bytes sent\n"
    "                       flip=FRAME       (sim) a wrong VP bit in frame FRAME (from 0);\n"
    "                                        --sim=rtl: a bit of the frame store's RAM\n"
    "  --json             the report as JSON on stdout\n\n"
    "Payloads are as long as the board's INFO report allows.  Ctrl-C stops the\n"
    "stream and reports the frames confirmed so far.\n\n"
    "Exit status: 0 every frame matches (frames mode: every frame shown); 1 some\n"
    "differ (frames mode, --sim: the display differs); 2 nothing was sent: a usage\n"
    "error, a scene or stream FILE unreadable or malformed, a stream made for\n"
    "another profile; 3 the link failed (no board, or it stopped answering or\n"
    "went away); 130 interrupted (Ctrl-C, SIGTERM).\n\n";

int cmd_stream(int argc, char **argv)
{
    static const char *const spec[] = {"sim=?", "rtl-board=", "json", "quiet", "q", "help",
                                       "no-readback", "no-cycle-check", "vid=",
                                       "pid=", "serial=", "wait=", "timeout=", "stream=",
                                       "fault=", "frames", "sim-payload=", "usb-transfers=",
                                       "usb-buffer=", NULL};
    static sim_rtl_tally tally;   /* static: 4 KiB of path off the stack */
    link_args a = {.vid = PROTO_VID, .pid = PROTO_PID, .wait_ms = 2000, .timeout_ms = 2000,
                   .tally = &tally,
                   .flip_frame = -1, .cmd = "stream"};
    run_opts o;
    run_opts_init(&o);
    const char *pos[1];
    int npos;
    int parsed = cli_parse("stream", argc, argv, spec, link_opt, &a, &o, pos, 1, &npos);
    if (parsed)
        return parsed < 0 ? EXIT_INPUT : 0;
    if (a.help) {
        printf("%s%s", stream_help, run_opts_help);
        return 0;
    }
    if (cli_check_profile(&o.prof))
        return EXIT_INPUT;
    /* the word stream */
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    alb_diag d;
    alb_diag_init(&d, stderr);
    if (a.stream) {
        if (alb_ws_read_file(a.stream, &b.w, &b.n, &d)) {
            alb_diag_print(&d, stderr);
            return EXIT_INPUT;
        }
    } else {
        alb_scene scene;
        if (cli_load_scene(npos ? pos[0] : NULL, &o, &scene))
            return EXIT_INPUT;
        alb_gp *gp = NULL;
        alb_err e = alb_gp_create(&gp, &scene, &o.prof, &d);
        if (!e)
            e = alb_gp_run(gp, &b, NULL, &d);
        alb_gp_destroy(gp);
        alb_scene_free(&scene);
        if (e) {
            alb_diag_print(&d, stderr);
            alb_ws_buf_free(&b);
            return EXIT_INPUT;
        }
    }
    alb_stream_frame *frames = NULL;
    unsigned nf = 0;
    if (alb_stream_frames(b.w, b.n, &frames, &nf)) {
        fprintf(stderr, "albatros stream: the word stream is malformed (albatros dump says where)\n");
        alb_ws_buf_free(&b);
        return EXIT_INPUT;
    }
    /* what the emulator says */
    uint16_t **keep = calloc(nf ? nf : 1, sizeof *keep);
    expect_ctx ec = {frames, nf, 0, keep};
    alb_sim_options so = {.fid = ALB_FIDELITY_TIMED, .threads = 1};
    int rc = EXIT_INPUT;   /* the emulator's run fails on a stream made for another profile */
    alb_transport *t = NULL;
    if (!keep || alb_sim_run(&o.prof, b.w, b.n, "stream", &so, expect_frame, &ec, &d)) {
        if (!keep)
            fprintf(stderr, "albatros stream: out of memory\n");
        alb_diag_print(&d, stderr);
        goto out;
    }
    if (a.frames) {
        rc = stream_frames_mode(&a, &o.prof, frames, nf);
        goto out;
    }
    rc = EXIT_LINK;
    if (!(t = open_link(&a, &o.prof, NULL, false)))
        goto out;
    alb_stream_opts sopt;
    alb_stream_opts_default(&sopt);
    sopt.timeout_ms = a.timeout_ms;
    sopt.readback = !a.no_readback;
    sopt.cycles_unchecked = a.no_cycle_check;
    sopt.log = a.quiet || a.json ? NULL : stderr;
    sopt.progress = sopt.log && cli_isatty_stderr();
    sopt.stop = &stream_stop;
    reattach_ctx rctx = {&a, &o.prof};
    if (a.wait_ms) {   /* hot-plug: a board that goes away is waited for again */
        sopt.reattach = reattach_link;
        sopt.reattach_ctx = &rctx;
    }
    stop_handlers h;
    catch_stop(&h);
    if (sopt.log)   /* also the sign, for a test, that Ctrl-C is now caught */
        fprintf(stderr, "stream: %u frames to send to %s\n", nf, a.sim && a.rtl ? "the RTL board"
                : a.sim ? "the simulated board" :
                "the board");
    usb_note(t, sopt.log);
    alb_stream_report r;
    rc = exit_of(alb_stream_run(t, b.w, b.n, frames, nf, &sopt, &r));
    t = r.link;   /* another after a disconnect, or none if the board did not come back */
    alb_tr_usb_link usb;
    bool have_usb = t && alb_transport_usb_link(t, &usb) == 0;
    if (t)
        t->ops->close(t);   /* cancels the transfers in flight, before a long report */
    t = NULL;
    if (a.json)
        report_json(&r, frames, nf, rc, have_usb ? &usb : NULL, a.rtl ? &tally : NULL);
    else if (!a.quiet || rc)
        report_text(&r, frames, nf, rc, have_usb ? &usb : NULL, a.rtl ? &tally : NULL);
    release_stop(&h);
out:
    if (t)
        t->ops->close(t);
    for (unsigned i = 0; keep && i < nf; i++)
        free(keep[i]);
    free(keep);
    free(frames);
    alb_ws_buf_free(&b);
    return rc;
}

/* ---- albatros board ---- */

static int board_info(alb_transport *t, bool json)
{
    uint8_t rep[PROTO_HID_REPORT + 1] = {PROTO_HID_INFO};
    if (t->ops->hid_get(t, rep, PROTO_HID_REPORT)) {
        fprintf(stderr, "albatros board info: %s\n", t->error);
        return 1;
    }
    alb_link_info in;
    if (alb_link_info_decode(rep, &in)) {
        fprintf(stderr, "albatros board info: the device's INFO report lacks the ALBI magic: "
                        "not an albatros board?\n");
        return 1;
    }
    if (json) {
        alb_json j;
        alb_json_init(&j, stdout);
        alb_json_begin_object(&j);
        alb_json_kv_string(&j, "name", in.name);
        alb_json_kv_uint(&j, "protocol", in.protocol);
        alb_json_kv_uint(&j, "firmware", in.firmware);
        alb_json_kv_uint(&j, "width", in.width);
        alb_json_kv_uint(&j, "height", in.height);
        alb_json_kv_uint(&j, "colour_bits", in.colour_bits);
        alb_json_kv_uint(&j, "mode", in.mode);
        alb_json_kv_uint(&j, "serial", in.serial);
        alb_json_kv_uint(&j, "max_payload", in.max_payload);
        alb_json_end_object(&j);
        alb_json_end_line(&j);
    } else {
        printf("%s: protocol %u, firmware %u, VP %ux%u %u-bit colour, mode %u, serial %u, "
               "payloads up to %u bytes\n", in.name, in.protocol, in.firmware, in.width,
               in.height, in.colour_bits, in.mode, in.serial, in.max_payload);
    }
    return 0;
}

#define LIST_MAX 32

/* The boards with a's ids; with --wait, looked for every 100 ms (as
 * opening one does, transport_usb.c) until one is there or the time is up. */
static int list_waiting(const link_args *a, alb_tr_usb_device *d, char *err, size_t errlen)
{
    struct timespec start, now;
    clock_gettime(CLOCK_MONOTONIC, &start);
    for (;;) {
        int n = alb_transport_usb_list((uint16_t)a->vid, (uint16_t)a->pid, d, LIST_MAX, err, errlen);
        if (n != 0)
            return n;
        clock_gettime(CLOCK_MONOTONIC, &now);
        long ms = (long)(now.tv_sec - start.tv_sec) * 1000 + (now.tv_nsec - start.tv_nsec) / 1000000;
        if (ms >= (long)a->wait_ms)
            return 0;
        long nap_ms = (long)a->wait_ms - ms < 100 ? (long)a->wait_ms - ms : 100;
        struct timespec nap = {0, nap_ms * 1000000};
        nanosleep(&nap, NULL);
    }
}

static int board_list(const link_args *a, const alb_profile *p)
{
    alb_json j;
    alb_json_init(&j, stdout);
    if (a->sim) {
        if (a->json) {
            alb_json_begin_object(&j);
            alb_json_key(&j, "boards");
            alb_json_begin_array(&j);
            alb_json_begin_object(&j);
            alb_json_kv_string(&j, "id", "sim:0");
            alb_json_kv_string(&j, "kind", "sim");
            alb_json_kv_string(&j, "profile", p->name);
            alb_json_end_object(&j);
            alb_json_end_array(&j);
            alb_json_end_object(&j);
            alb_json_end_line(&j);
        } else
            printf("sim:0  simulated board (profile %s)\n", p->name);
        return 0;
    }
    alb_tr_usb_device d[LIST_MAX];
    char err[600];
    int n = list_waiting(a, d, err, sizeof err);
    if (n < 0) {
        fprintf(stderr, "albatros board list: %s\n", err);
        return 1;
    }
    if (a->json) {
        alb_json_begin_object(&j);
        alb_json_key(&j, "boards");
        alb_json_begin_array(&j);
    }
    for (int i = 0; i < n && i < LIST_MAX; i++) {
        char id[32], vid[8], pid[8];
        snprintf(id, sizeof id, "usb:%03u:%03u", d[i].bus, d[i].address);
        if (a->json) {
            snprintf(vid, sizeof vid, "%04x", d[i].vid);
            snprintf(pid, sizeof pid, "%04x", d[i].pid);
            alb_json_begin_object(&j);
            alb_json_kv_string(&j, "id", id);
            alb_json_kv_string(&j, "kind", "usb");
            alb_json_kv_string(&j, "vid", vid);
            alb_json_kv_string(&j, "pid", pid);
            alb_json_kv_string(&j, "serial", d[i].serial);
            alb_json_kv_bool(&j, "access", !d[i].no_access);
            alb_json_end_object(&j);
        } else {
            printf("%s  %04x:%04x  serial %s%s\n", id, d[i].vid, d[i].pid, d[i].serial,
                   d[i].no_access ? "  (no permission: see firmware/udev/)" : "");
        }
    }
    if (a->json) {
        alb_json_end_array(&j);
        alb_json_end_object(&j);
        alb_json_end_line(&j);
    } else if (n == 0)
        fprintf(stderr, "no board %04x:%04x on the USB bus\n", a->vid, a->pid);
    if (n > LIST_MAX)
        fprintf(stderr, "albatros board list: %d more not shown\n", n - LIST_MAX);
    return 0;
}

int cmd_board(int argc, char **argv)
{
    static const char *const spec[] = {"sim=?", "rtl-board=", "json", "help", "vid=", "pid=",
                                       "serial=", "wait=",
                                       "sim-payload=", NULL};
    link_args a = {.vid = PROTO_VID, .pid = PROTO_PID, .wait_ms = 0, .flip_frame = -1,
                   .cmd = "board"};
    run_opts o;
    run_opts_init(&o);
    const char *pos[1];
    int npos;
    int parsed = cli_parse("board", argc, argv, spec, link_opt, &a, &o, pos, 1, &npos);
    if (parsed)
        return CLI_PARSE_EXIT(parsed);
    if (a.help || npos != 1 ||
        (strcmp(pos[0], "list") && strcmp(pos[0], "info") && strcmp(pos[0], "reset"))) {
        printf("usage: albatros board list|info|reset [--sim] [--vid V --pid P --serial S] "
               "[--wait MS] [--json]\n\n"
               "  list   boards on the USB bus\n"
               "  info   the board's INFO report (HID)\n"
               "  reset  reset the board's link, VP and counters (HID)\n\n"
               "  --sim            the simulated board (--sim-payload N: it takes N-byte payloads)\n"
               "  --vid, --pid     USB ids in hexadecimal as lsusb shows them, 0x optional\n"
               "                   (default 1209:0001)\n"
               "  --wait MS        wait this long for the board to appear (hot-plug; default 0);\n"
               "                   list waits until one is on the bus (--sim: at once)\n"
               "  --json           the answer as JSON on stdout\n\n"
               "info and reset use the HID interface only, so they work while a stream runs.\n");
        return a.help ? 0 : 2;
    }
    if (!strcmp(pos[0], "list"))
        return board_list(&a, &o.prof);
    alb_transport *t = open_link(&a, &o.prof, NULL, true);
    if (!t)
        return 1;
    int rc;
    if (!strcmp(pos[0], "info")) {
        rc = board_info(t, a.json);
    } else {
        uint8_t rep[PROTO_HID_REPORT + 1] = {PROTO_HID_RESET, PROTO_RESET_ALL};
        rc = t->ops->hid_set(t, rep, PROTO_HID_REPORT) ? 1 : 0;
        if (rc)
            fprintf(stderr, "albatros board reset: %s\n", t->error);
        else if (a.json) {
            alb_json j;
            alb_json_init(&j, stdout);
            alb_json_begin_object(&j);
            alb_json_kv_string(&j, "reset", "link, VP and counters");
            alb_json_end_object(&j);
            alb_json_end_line(&j);
        }
        else
            printf("board reset\n");
    }
    t->ops->close(t);
    return rc;
}
