/* test_bridge.c — the USB/HID bridge end to end through the simulated board:
 * a stream whose every frame agrees with the emulator; a faulty board caught
 * with its frame and pixel; every link fault detected, reported, and
 * recovered from or failed cleanly without hanging; the host's packet
 * decoder against garbage. */
#include "t.h"
#include "../firmware/proto.h"
#include "gp_helpers.h"
#include "albatros/link.h"
#include "albatros/stream.h"
#include "albatros/sim.h"
#include "../firmware/sim/board.h"
#include "../firmware/sim/rtl_load.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    alb_ws_buf b;
    alb_stream_frame *f;
    unsigned nf;
    uint16_t *rgb[8];
} fixture;

typedef struct {
    fixture *x;
    unsigned k;
} exp_ctx;

/* The simulated board running profile a256. */
static alb_transport *sim_open(size_t payload, char *err, size_t errlen)
{
    alb_profile p;
    alb_profile_lookup("a256", &p);
    return sim_board_transport(&p, payload, err, errlen);
}

static int expect(void *ctx, const alb_frame *fr, const alb_vp_stats *vs, const alb_sim_counters *sc)
{
    (void)vs;
    exp_ctx *e = ctx;
    if (e->k >= e->x->nf || e->k >= 8)
        return 0;
    alb_stream_frame *f = &e->x->f[e->k];
    size_t npix = (size_t)fr->width * fr->height;
    f->crc = alb_link_frame_crc(fr->rgb, npix);
    f->cycles = sc->cycles;
    f->width = fr->width;
    f->height = fr->height;
    e->x->rgb[e->k] = malloc(3 * npix * sizeof(uint16_t));
    memcpy(e->x->rgb[e->k], fr->rgb, 3 * npix * sizeof(uint16_t));
    f->rgb = e->x->rgb[e->k];
    e->k++;
    return 0;
}

/* The moving-lit-object scene at 64x64 (4 frames), profile t32 resized. */
static const char scene_text[] =
    "albatros-scene 1\nnear 0.5\nlight 0.5 0.7 -0.6 ambient 0.25\nobserver at 0 0 -12 fov 50\n"
    "object gem moving yaw 10\n v 2 0 0 n 1 0 0\n v -2 0 0 n -1 0 0\n v 0 3 0 n 0 1 0\n"
    " v 0 -3 0 n 0 -1 0\n v 0 0 2 n 0 0 1\n v 0 0 -2 n 0 0 -1\n colour 230 140 40\n"
    " f 5 3 1\n f 2 3 5\n f 6 3 2\n f 1 3 6\n f 1 4 5\n f 5 4 2\n f 2 4 6\n f 6 4 1\nend\n"
    "frame\n pose gem yaw 10\nframe\n pose gem yaw 40 pitch 10\nframe\n pose gem yaw 70\n"
    "frame\n pose gem yaw 100 pitch 30\n";

static int make_fixture(fixture *x, const char *profile)
{
    memset(x, 0, sizeof *x);
    alb_profile p;
    alb_profile_lookup(profile, &p);
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_scene_parse(scene_text, strlen(scene_text), "t", &s, &d))
        return -1;
    alb_gp *gp = NULL;
    alb_ws_buf_init(&x->b);
    alb_err e = alb_gp_create(&gp, &s, &p, &d);
    if (!e)
        e = alb_gp_run(gp, &x->b, NULL, &d);
    alb_gp_destroy(gp);
    alb_scene_free(&s);
    if (e || alb_stream_frames(x->b.w, x->b.n, &x->f, &x->nf))
        return -1;
    exp_ctx ec = {x, 0};
    alb_sim_options o = {.fid = ALB_FIDELITY_TIMED, .threads = 1};
    return alb_sim_run(&p, x->b.w, x->b.n, "t", &o, expect, &ec, &d) ? -1 : 0;
}

static void free_fixture(fixture *x)
{
    for (unsigned i = 0; i < 8; i++)
        free(x->rgb[i]);
    free(x->f);
    alb_ws_buf_free(&x->b);
}

static void reset_results(fixture *x)
{
    for (unsigned i = 0; i < x->nf; i++) {
        x->f[i].have = false;
        x->f[i].resends = 0;
    }
}

/* Stream through the simulated board (taking payloads of up to
 * board_payload bytes, 0: the protocol's largest) with faults, in WORDS of
 * chunk bytes (0: as long as the board takes); returns alb_stream_run's rc. */
static int run_on(fixture *x, size_t board_payload, size_t chunk, const alb_tr_faults *faults,
                  long flip_frame, alb_stream_report *r)
{
    char err[300];
    alb_transport *t = sim_open(board_payload, err, sizeof err);
    if (!t)
        return -9;
    if (flip_frame >= 0)
        sim_board_flip(sim_board_of(t), (uint32_t)flip_frame, 5, 7, 1, 0);
    if (faults) {
        alb_transport *f = alb_transport_faulty(t, faults);
        if (!f)
            return -9;
        t = f;
    }
    alb_stream_opts o;
    alb_stream_opts_default(&o);
    o.timeout_ms = 20;
    o.chunk_bytes = chunk;
    reset_results(x);
    int rc = alb_stream_run(t, x->b.w, x->b.n, x->f, x->nf, &o, r);
    t->ops->close(t);
    return rc;
}

static int run_with(fixture *x, const alb_tr_faults *faults, long flip_frame, alb_stream_report *r)
{
    return run_on(x, 0, 256, faults, flip_frame, r);   /* many packets: faults land mid-frame */
}

TEST(bridge_stream_agrees_with_emulator)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    CHECK_EQ(x.nf, 4);
    alb_stream_report r;
    CHECK_EQ(run_with(&x, NULL, -1, &r), 0);
    CHECK_EQ(r.matched, 4);
    CHECK_EQ(r.resumes, 0);
    for (unsigned i = 0; i < x.nf; i++)
        CHECK(x.f[i].have && x.f[i].board_crc == x.f[i].crc && x.f[i].board_cycles == x.f[i].cycles &&
              x.f[i].cycles > 0);
    free_fixture(&x);
}

TEST(bridge_faulty_vp_caught_with_frame_and_pixel)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    alb_stream_report r;
    CHECK_EQ(run_with(&x, NULL, 2, &r), 1);
    CHECK_EQ(r.matched, 3);
    CHECK_EQ(r.crc_mismatch, 1);
    CHECK(x.f[2].board_crc != x.f[2].crc);
    CHECK_STR_CONTAINS(r.first_problem, "frame 2");
    CHECK_STR_CONTAINS(r.first_problem, "pixel (5, 7) channel G");
    free_fixture(&x);
}

/* Several frames differ: each readback names its own frame's first wrong
 * pixel (its line in the log), and the first problem only the first frame's. */
TEST(bridge_readback_per_frame)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    /* the board gets frame 1 wrong at (5, 7) G; the emulator's frame 2 is
     * made to disagree with the board at (9, 3) R */
    size_t npix = (size_t)x.f[2].width * x.f[2].height;
    x.rgb[2][3 * (3 * (size_t)x.f[2].width + 9)] ^= 1;
    x.f[2].crc = alb_link_frame_crc(x.rgb[2], npix);
    char err[300];
    alb_transport *t = sim_open(0, err, sizeof err);
    FILE *log = tmpfile();
    CHECK(t && log);
    if (!t || !log) {
        free_fixture(&x);
        return;
    }
    sim_board_flip(sim_board_of(t), x.f[1].number, 5, 7, 1, 0);
    alb_stream_opts o;
    alb_stream_opts_default(&o);
    o.timeout_ms = 200;
    o.log = log;
    reset_results(&x);
    alb_stream_report r;
    CHECK_EQ(alb_stream_run(t, x.b.w, x.b.n, x.f, x.nf, &o, &r), 1);
    t->ops->close(t);
    CHECK_EQ(r.crc_mismatch, 2);
    char want[120];
    snprintf(want, sizeof want, "frame %u: the board's frame CRC ", x.f[1].number);
    CHECK_STR_CONTAINS(r.first_problem, want);
    CHECK_STR_CONTAINS(r.first_problem, ": first at pixel (5, 7) channel G");
    CHECK_MSG(!strstr(r.first_problem, "(9, 3)"), "frame 2's readback in the first problem: %s",
              r.first_problem);
    char text[4096] = "";
    rewind(log);
    size_t got = fread(text, 1, sizeof text - 1, log);
    text[got] = 0;
    fclose(log);
    snprintf(want, sizeof want, "frame %u: first difference at pixel (5, 7) channel G",
             x.f[1].number);
    CHECK_STR_CONTAINS(text, want);
    snprintf(want, sizeof want, "frame %u: first difference at pixel (9, 3) channel R",
             x.f[2].number);
    CHECK_STR_CONTAINS(text, want);
    free_fixture(&x);
}

/* A fault kind given several times strikes each time: two packets dropped
 * are two gaps, each resumed from; overlapping swaps recover too. */
TEST(bridge_fault_kind_strikes_several_times)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    alb_stream_report r;
    alb_tr_faults drops = {.drop_packet = {12, 5}};
    CHECK_EQ(run_with(&x, &drops, -1, &r), 0);
    CHECK_EQ(r.board_errors[PROTO_E_SEQ_GAP], 2);
    CHECK_EQ(r.resumes, 2);
    CHECK_EQ(r.matched, x.nf);
    alb_tr_faults bytes = {.corrupt_byte = {1000, 700}};   /* any order */
    CHECK_EQ(run_with(&x, &bytes, -1, &r), 0);
    CHECK_EQ(r.board_errors[PROTO_E_BAD_CRC], 2);
    alb_tr_faults swaps = {.swap_packet = {6, 7}};
    CHECK_EQ(run_with(&x, &swaps, -1, &r), 0);
    CHECK_EQ(r.matched, x.nf);
    free_fixture(&x);
}

/* Each fault: detected (counted or reported), never a hang, and the stream
 * recovers: every frame finally matches. */
TEST(bridge_link_faults_detected_and_recovered)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    static const struct {
        const char *what;
        alb_tr_faults f;
    } cases[] = {
        {"corrupted byte", {.corrupt_byte = {700}}},
        {"dropped packet", {.drop_packet = {5}}},
        {"duplicated packet", {.duplicate_packet = {4}}},
        {"swapped packets", {.swap_packet = {6}}},
        {"corrupted reply", {.corrupt_reply = {30}}},
        {"truncated packet", {.truncate_packet = {5}}},
        {"last packet dropped", {.drop_packet = {0}}},   /* filled in below */
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        alb_tr_faults f = cases[k].f;
        if (k == 6) {
            /* the END word goes alone in the packet before the final PING:
             * count them first */
            alb_stream_report clean;
            run_with(&x, NULL, -1, &clean);
            f.drop_packet[0] = clean.packets - 1;
        }
        alb_stream_report r;
        int rc = run_with(&x, &f, -1, &r);
        CHECK_MSG(rc == 0, "%s: rc %d, %u matched: %s", cases[k].what, rc, r.matched, r.first_problem);
        uint64_t seen = r.resumes + r.queries + r.rx_crc_errors + r.rx_duplicates;
        for (int c = 1; c < 9; c++)
            seen += r.board_errors[c];
        CHECK_MSG(seen > 0, "%s: not detected", cases[k].what);
        CHECK_MSG(r.first_link_error[0], "%s: no first link error", cases[k].what);
    }
    /* what was lost is named: the 5th packet sent is sequence number 4, the
     * WORDS of the frame the host then resumes from */
    alb_stream_report r;
    alb_tr_faults drop = {.drop_packet = {5}};
    CHECK_EQ(run_with(&x, &drop, -1, &r), 0);
    CHECK_STR_CONTAINS(r.first_link_error, "board: sequence gap: packet 4 (WORDS: words ");
    CHECK_EQ(r.board_errors[PROTO_E_SEQ_GAP], 1);
    unsigned lost_in = 0;
    for (unsigned i = 0; i < x.nf; i++) {
        char name[40];
        snprintf(name, sizeof name, ", frame %u) never arrived", x.f[i].number);
        if (strstr(r.first_link_error, name))
            lost_in = x.f[i].number + 1;
    }
    CHECK_MSG(lost_in > 0, "the lost packet's frame is not named: %s", r.first_link_error);
    /* a truncated packet: its CRC fails where it lay, its number is missed */
    alb_tr_faults cut = {.truncate_packet = {5}};
    CHECK_EQ(run_with(&x, &cut, -1, &r), 0);
    CHECK_EQ(r.board_errors[PROTO_E_BAD_CRC], 1);
    CHECK_EQ(r.board_errors[PROTO_E_SEQ_GAP], 1);
    CHECK_STR_CONTAINS(r.first_link_error, "board: bad CRC at packet 4 (WORDS: words ");
    CHECK_EQ(r.matched, x.nf);
    free_fixture(&x);
}

/* The FX2 firmware takes 492-byte payloads (firmware/fx2/main.c); the host
 * reads the limit from the board's INFO report, and a stream in payloads as
 * long as the board takes (no chunk_bytes) still agrees with the emulator:
 * a longer packet would be garbage to the board (firmware/core.c), the
 * stream lost. */
TEST(bridge_board_payload_limit_from_info)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    alb_stream_report r;
    CHECK_EQ(run_on(&x, 492, 0, NULL, -1, &r), 0);
    CHECK_EQ(r.matched, x.nf);
    CHECK_EQ(r.max_payload, 492);
    CHECK_EQ(alb_stream_board_errors(&r), 0);
    CHECK_EQ(r.resumes, 0);
    /* the payload of every packet fits: bytes = packets x overhead + payloads */
    CHECK(r.bytes <= r.packets * (PROTO_HEADER + 492 + PROTO_TRAILER));
    CHECK(r.packets > (uint64_t)4 * x.b.n / 492);
    /* a chunk below the board's limit is kept; above it, the board's wins */
    CHECK_EQ(run_on(&x, 492, 256, NULL, -1, &r), 0);
    CHECK_EQ(r.max_payload, 256);
    CHECK_EQ(run_on(&x, 492, 4096, NULL, -1, &r), 0);
    CHECK_EQ(r.max_payload, 492);
    /* the default board: the protocol's largest */
    CHECK_EQ(run_on(&x, 0, 0, NULL, -1, &r), 0);
    CHECK_EQ(r.max_payload, PROTO_MAX_PAYLOAD);
    free_fixture(&x);
}

/* A board whose HID side fails (INFO unreadable) but whose bulk link works:
 * the stream goes on in payloads every board takes, and still agrees. */
static alb_tr_status (*real_hid_get)(alb_transport *, uint8_t *, size_t);

static alb_tr_status info_fails(alb_transport *t, uint8_t *buf, size_t len)
{
    if (len > 0 && buf[0] == PROTO_HID_INFO) {
        snprintf(t->error, sizeof t->error, "HID report 1: broken on purpose");
        return ALB_TR_ERROR;
    }
    return real_hid_get(t, buf, len);
}

TEST(bridge_unreadable_info_falls_back_to_the_smallest_payload)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    char err[300];
    alb_transport *t = sim_open(0, err, sizeof err);
    CHECK(t != NULL);
    if (!t) {
        free_fixture(&x);
        return;
    }
    static alb_transport_ops broken;
    broken = *t->ops;
    real_hid_get = t->ops->hid_get;
    broken.hid_get = info_fails;
    const alb_transport_ops *sim_ops = t->ops;
    t->ops = &broken;
    alb_stream_opts o;
    alb_stream_opts_default(&o);
    o.timeout_ms = 20;
    reset_results(&x);
    alb_stream_report r;
    CHECK_EQ(alb_stream_run(t, x.b.w, x.b.n, x.f, x.nf, &o, &r), 0);
    CHECK_EQ(r.matched, x.nf);
    CHECK_EQ(r.max_payload, PROTO_BULK_MAXPKT - PROTO_HEADER - PROTO_TRAILER);
    t->ops = sim_ops;
    t->ops->close(t);
    free_fixture(&x);
}

/* A stop flag (Ctrl-C) already set: the stream ends at once, marked partial,
 * and the link is left for the caller to close. */
TEST(bridge_stop_flag_ends_the_stream)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    char err[300];
    alb_transport *t = sim_open(0, err, sizeof err);
    if (!t) {
        CHECK_MSG(0, "%s", err);
        free_fixture(&x);
        return;
    }
    static volatile sig_atomic_t stop = 1;
    alb_stream_opts o;
    alb_stream_opts_default(&o);
    o.stop = &stop;
    alb_stream_report r;
    reset_results(&x);
    CHECK_EQ(alb_stream_run(t, x.b.w, x.b.n, x.f, x.nf, &o, &r), -2);
    CHECK(r.interrupted);
    CHECK_EQ(r.frames, 0);
    CHECK_EQ(r.first_problem[0], 0);
    alb_stream_tiles_frame tf = {0, 1, 1, (const uint8_t *)"\x10\x20\x30"};
    CHECK_EQ(alb_stream_tiles(t, &tf, 1, &o, &r), -2);
    CHECK(r.interrupted);
    t->ops->close(t);
    free_fixture(&x);
}

TEST(bridge_silent_board_and_disconnect_fail_cleanly)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    alb_stream_report r;
    alb_tr_faults silent = {.silence_after = 30};
    CHECK_EQ(run_with(&x, &silent, -1, &r), -1);
    CHECK_STR_CONTAINS(r.first_problem, "stopped answering");
    alb_tr_faults gone = {.disconnect_after = 1500};
    CHECK_EQ(run_with(&x, &gone, -1, &r), -1);
    CHECK_STR_CONTAINS(r.first_problem, "disconnected");
    /* a fresh link afterwards works: nothing was left behind */
    CHECK_EQ(run_with(&x, NULL, -1, &r), 0);
    free_fixture(&x);
}

/* Any one packet cut short, the last of a frame or of the stream included,
 * at the protocol's largest payload and at the FX2's 492 bytes: detected,
 * recovered, every frame confirmed.  A truncated last packet used to
 * deadlock: nothing followed to complete it, the host's one QUERY went into
 * the half-received packet and the host gave up.  Now the QUERY (and a
 * closing PING without answer) goes behind zero bytes that complete it. */
TEST(bridge_any_packet_truncated_recovers)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    static const size_t payloads[] = {0, 492};
    for (size_t k = 0; k < 2; k++) {
        alb_stream_report clean;
        CHECK_EQ(run_on(&x, payloads[k], 0, NULL, -1, &clean), 0);
        unsigned queried = 0;
        for (uint64_t n = 1; n <= clean.packets; n++) {
            alb_tr_faults cut = {.truncate_packet = {n}};
            alb_stream_report r;
            int rc = run_on(&x, payloads[k], 0, &cut, -1, &r);
            CHECK_MSG(rc == 0 && r.matched == x.nf && r.first_link_error[0],
                      "payload %zu, packet %llu of %llu cut: rc %d, %u of %u matched: %s / %s",
                      payloads[k], (unsigned long long)n, (unsigned long long)clean.packets, rc,
                      r.matched, x.nf, r.first_problem, r.first_link_error);
            queried += r.queries > 0;
        }
        /* some cuts left nothing behind them in their frame: the QUERY path */
        CHECK_MSG(queried > 0, "payload %zu: no cut needed a QUERY", payloads[k]);
    }
    free_fixture(&x);
}

/* A board that falls silent: the message gives the time the host waited,
 * measured, not the timeout (the simulated board answers at once, so its
 * reads return at once). */
TEST(bridge_silence_message_tells_the_time_waited)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    alb_stream_report r;
    alb_tr_faults silent = {.silence_after = 30};
    CHECK_EQ(run_with(&x, &silent, -1, &r), -1);
    double waited = -1;
    const char *in = strstr(r.first_problem, " in ");
    CHECK_MSG(in && sscanf(in, " in %lf s after", &waited) == 1, "%s", r.first_problem);
    CHECK_MSG(waited >= 0 && waited <= r.seconds, "waited %g s of a %g s run: %s", waited,
              r.seconds, r.first_problem);
    CHECK_STR_CONTAINS(r.first_problem, "(each read waits up to 20 ms)");
    free_fixture(&x);
}

/* Hot-plug: a board that disconnects mid-stream comes back as a fresh board
 * (another simulated one, with the same faults when `again` is set); the
 * stream starts over and every frame is confirmed once. */
typedef struct {
    const alb_tr_faults *again;
    unsigned opened;
    bool never;
} comeback;

static alb_transport *come_back(void *ctx, alb_transport *old, char *err, size_t errlen)
{
    comeback *c = ctx;
    old->ops->close(old);
    if (c->never) {
        snprintf(err, errlen, "gone for good");
        return NULL;
    }
    alb_transport *t = sim_open(0, err, errlen);
    c->opened++;
    if (t && c->again) {
        alb_transport *f = alb_transport_faulty(t, c->again);
        if (!f)
            t->ops->close(t);
        t = f;
    }
    return t;
}

static int run_reattach(fixture *x, comeback *c, alb_stream_report *r)
{
    char err[300];
    alb_transport *t = sim_open(0, err, sizeof err);
    alb_tr_faults gone = {.disconnect_after = 1500};
    alb_transport *f = t ? alb_transport_faulty(t, &gone) : NULL;
    if (!f)
        return -9;
    alb_stream_opts o;
    alb_stream_opts_default(&o);
    o.timeout_ms = 20;
    o.chunk_bytes = 256;
    o.reattach = come_back;
    o.reattach_ctx = c;
    reset_results(x);
    int rc = alb_stream_run(f, x->b.w, x->b.n, x->f, x->nf, &o, r);
    if (r->link)
        r->link->ops->close(r->link);
    return rc;
}

TEST(bridge_board_that_comes_back_gets_the_stream_again)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    alb_stream_report r;
    comeback once = {0};
    CHECK_EQ(run_reattach(&x, &once, &r), 0);
    CHECK_EQ(r.reattaches, 1);
    CHECK_EQ(once.opened, 1);
    CHECK_EQ(r.matched, x.nf);
    CHECK_EQ(r.frames, x.nf);   /* a frame confirmed twice is counted once */
    CHECK_STR_CONTAINS(r.first_link_error, "disconnected");
    /* a board that disconnects every time: three are survived, the fourth ends it */
    alb_tr_faults gone = {.disconnect_after = 1500};
    comeback flaky = {.again = &gone};
    CHECK_EQ(run_reattach(&x, &flaky, &r), -1);
    CHECK_EQ(r.reattaches, 3);
    CHECK_STR_CONTAINS(r.first_problem, "disconnected");
    /* one that never comes back */
    comeback never = {.never = true};
    CHECK_EQ(run_reattach(&x, &never, &r), -1);
    CHECK_STR_CONTAINS(r.first_problem, "did not come back: gone for good");
    CHECK_EQ(r.reattaches, 0);   /* the report would say it "came back" */
    CHECK(r.link == NULL);
    free_fixture(&x);
}

TEST(bridge_host_decoder_resyncs_after_garbage)
{
    uint8_t pkt[64], buf[400];
    uint8_t payload[20] = {1, 2, 3, 4};
    size_t n = alb_link_encode(pkt, PROTO_T_RESULT, 7, payload, 20);
    /* garbage, a corrupted copy, a fake magic, then the packet twice */
    size_t len = 0;
    memcpy(buf + len, "xyzALB1garbage", 14), len += 14;
    memcpy(buf + len, pkt, n), buf[len + 20] ^= 1, len += n;
    memcpy(buf + len, pkt, n), len += n;
    size_t n2 = alb_link_encode(buf + len, PROTO_T_STATUS, 8, NULL, 0);
    len += n2;
    alb_link_rx rx;
    alb_link_rx_init(&rx);
    alb_link_packet p;
    unsigned got = 0;
    /* fed one byte at a time */
    for (size_t i = 0; i < len; i++) {
        CHECK(alb_link_rx_feed(&rx, buf + i, 1) == 0);
        while (alb_link_rx_next(&rx, &p) == 1) {
            got++;
            CHECK(got != 1 || (p.type == PROTO_T_RESULT && p.seq == 7 && p.len == 20 &&
                               p.payload[3] == 4));
            CHECK(got != 2 || (p.type == PROTO_T_STATUS && p.seq == 8));
        }
    }
    CHECK_EQ(got, 2);
    CHECK_EQ(rx.crc_errors, 1);
    CHECK(rx.garbage >= 14);
    alb_link_rx_free(&rx);
}

/* Frames mode through the simulated board: the emulator's frames as tiles;
 * afterwards the board's display holds the last frame, pixel for pixel in
 * RGB888 (computed here: v * 255 / (2^cb - 1), round half up); each link
 * fault costs a resend of the frame, never a wrong or missing tile. */
TEST(bridge_frames_mode_displays_the_frames)
{
    fixture x;
    if (make_fixture(&x, "a256")) {
        CHECK_MSG(0, "fixture");
        return;
    }
    const size_t npix = (size_t)256 * 256;
    uint8_t *rgb = malloc(3 * npix * x.nf);
    alb_stream_tiles_frame tf[8];
    for (unsigned i = 0; i < x.nf; i++) {
        for (size_t k = 0; k < 3 * npix; k++) {
            unsigned v = x.f[i].rgb[k];   /* 8-bit frame store: 255 * v / 255 */
            rgb[3 * npix * i + k] = (uint8_t)((v * 510 + 255) / 510);
        }
        tf[i] = (alb_stream_tiles_frame){x.f[i].number, 256, 256, rgb + 3 * npix * i};
    }
    uint8_t check[3];
    alb_link_rgb888(x.f[0].rgb, 1, 8, check);   /* the library's scaling agrees */
    CHECK(check[0] == rgb[0] && check[1] == rgb[1] && check[2] == rgb[2]);
    static const struct {
        const char *what;
        alb_tr_faults f;
        bool resend;
        size_t payload;       /* the board's (0: the protocol's largest) */
    } cases[] = {
        {"clean link", {.drop_packet = {0}}, false, 0},
        {"dropped tile", {.drop_packet = {4}}, true, 0},
        {"corrupted tile", {.corrupt_byte = {20000}}, true, 0},
        {"dropped PING", {.drop_packet = {15}}, true, 0},   /* RESET, 13 tiles, PING */
        {"truncated tile", {.truncate_packet = {6}}, true, 0},
        {"492-byte payloads", {.drop_packet = {0}}, false, 492},           /* the FX2's: 160-pixel tiles */
        {"492-byte payloads, truncated tile", {.truncate_packet = {40}}, true, 492},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        char err[300];
        alb_transport *t = sim_open(cases[c].payload, err, sizeof err);
        CHECK(t != NULL);
        if (!t)
            break;
        sim_board *board = sim_board_of(t);
        alb_transport *link = alb_transport_faulty(t, &cases[c].f);
        alb_stream_opts o;
        alb_stream_opts_default(&o);
        o.timeout_ms = 20;
        alb_stream_report r;
        int rc = alb_stream_tiles(link, tf, x.nf, &o, &r);
        CHECK_MSG(rc == 0, "%s: rc %d: %s", cases[c].what, rc, r.first_problem);
        CHECK_MSG(r.frames == x.nf, "%s: %u frames shown", cases[c].what, r.frames);
        CHECK_MSG((r.resumes > 0) == cases[c].resend, "%s: %llu resends", cases[c].what,
                  (unsigned long long)r.resumes);
        uint32_t shown;
        uint64_t tiles;
        const uint8_t *d = sim_board_display(board, &shown, &tiles);
        CHECK_MSG(shown == x.f[x.nf - 1].number && !memcmp(d, tf[x.nf - 1].rgb, 3 * npix),
                  "%s: the display is not the last frame", cases[c].what);
        size_t pay = cases[c].payload ? cases[c].payload : PROTO_MAX_PAYLOAD;
        CHECK_EQ(r.max_payload, pay);
        /* strips as tall as a payload holds; narrower than the frame (two a
         * row) when one row does not fit */
        uint64_t per_frame = pay >= 12 + 3 * 256 ? (256 + (pay - 12) / 768 - 1) / ((pay - 12) / 768)
                                                 : 2 * 256;
        CHECK_MSG(tiles >= x.nf * per_frame, "%s: %llu tiles", cases[c].what,
                  (unsigned long long)tiles);
        link->ops->close(link);
    }
    /* a silent board: the frame is tried again, then a clean failure */
    char err[300];
    alb_transport *t = sim_open(0, err, sizeof err);
    alb_tr_faults silent = {.silence_after = 1};
    alb_transport *link = t ? alb_transport_faulty(t, &silent) : NULL;
    if (link) {
        alb_stream_opts o;
        alb_stream_opts_default(&o);
        o.timeout_ms = 5;
        alb_stream_report r;
        CHECK_EQ(alb_stream_tiles(link, tf, x.nf, &o, &r), -1);
        CHECK_STR_CONTAINS(r.first_problem, "stopped answering");
        link->ops->close(link);
    }
    free(rgb);
    free_fixture(&x);
}

/* An RTL board built with shading units left out (rtl/README.md: SHADE_UNIT,
 * TEX_UNIT, FOG_UNIT) still matches the profile it was built for, and the
 * units it lacks are named for the warning of --sim=rtl. */
TEST(bridge_rtl_board_units_left_out)
{
    alb_profile p;
    CHECK(alb_profile_lookup("up5k", &p) == 0);
    char want[600], have[700], why[200], units[160];
    sim_rtl_params(&p, want, sizeof want);
    snprintf(have, sizeof have, "%s MAX_EDGES=6 SHADE_UNIT=0 TEX_UNIT=0 FOG_UNIT=0", want);
    CHECK_EQ(sim_rtl_params_differ(want, have, why, sizeof why), 0);
    CHECK_EQ(sim_rtl_units_out(have, units, sizeof units), 3);
    CHECK_MSG(!strcmp(units, "the shade, texture and fog units (SHADE_UNIT=0 TEX_UNIT=0 FOG_UNIT=0)"),
              "units: %s", units);
    snprintf(have, sizeof have, "%s SHADE_UNIT=1 TEX_UNIT=0 FOG_UNIT=0", want);
    CHECK_EQ(sim_rtl_units_out(have, units, sizeof units), 2);
    CHECK_MSG(!strcmp(units, "the texture and fog units (TEX_UNIT=0 FOG_UNIT=0)"), "units: %s", units);
    snprintf(have, sizeof have, "FOG_UNIT=0 %s", want);
    CHECK_EQ(sim_rtl_units_out(have, units, sizeof units), 1);
    CHECK_MSG(!strcmp(units, "the fog unit (FOG_UNIT=0)"), "units: %s", units);
    /* every unit built: absent, 1, or a name that only ends like one */
    CHECK_EQ(sim_rtl_units_out(want, units, sizeof units), 0);
    CHECK(units[0] == 0);
    CHECK_EQ(sim_rtl_units_out("SHADE_UNIT=1 TEX_UNIT=1 XFOG_UNIT=0", units, sizeof units), 0);
    /* a profile field still differs as before */
    snprintf(have, sizeof have, "%s TEX_UNIT=0", want);
    char *w = strstr(have, "EDGE_UNITS=1");
    CHECK(w != NULL);
    if (w)
        w[11] = '2';
    CHECK_EQ(sim_rtl_params_differ(want, have, why, sizeof why), 1);
    CHECK_MSG(strstr(why, "EDGE_UNITS=2") != NULL, "why: %s", why);
}
