/* cmd_stream.c — `albatros stream`: send a scene's word stream to a board
 * (real over USB, or the simulated one) and check, frame by frame, its CRCs
 * and cycle counts against the emulator's; `albatros board list|info|reset`
 * over HID (docs/usb-protocol.md). */
#include "cli.h"
#include "commands.h"
#include "sim.h"
#include "bridge/link.h"
#include "bridge/stream.h"
#include "bridge/transport.h"
#include "../firmware/sim/board.h"

#include <stdlib.h>
#include <string.h>

typedef struct {
    bool sim, json, quiet, help, no_readback, frames;
    unsigned vid, pid, wait_ms, timeout_ms;
    const char *serial, *stream;
    tr_faults faults;
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

static int link_opt(void *ctx, const char *name, const char *value)
{
    link_args *a = ctx;
    unsigned long long v;
    if (!strcmp(name, "sim")) a->sim = true;
    else if (!strcmp(name, "json")) a->json = true;
    else if (!strcmp(name, "quiet") || !strcmp(name, "q")) a->quiet = true;
    else if (!strcmp(name, "help")) a->help = true;
    else if (!strcmp(name, "no-readback")) a->no_readback = true;
    else if (!strcmp(name, "frames")) a->frames = true;
    else if (!strcmp(name, "serial")) a->serial = value;
    else if (!strcmp(name, "stream")) a->stream = value;
    else if (!strcmp(name, "fault")) {
        /* KIND=N, for demonstrating and testing recovery */
        static const char *const kinds[] = {"corrupt", "drop", "duplicate", "swap", "silence",
                                            "disconnect", "corrupt-reply", "flip", NULL};
        const char *eq = strchr(value, '=');
        int k = -1;
        for (int i = 0; eq && kinds[i]; i++)
            if (strlen(kinds[i]) == (size_t)(eq - value) && !strncmp(value, kinds[i], (size_t)(eq - value)))
                k = i;
        if (k < 0 || parse_num(a->cmd, name, eq + 1, 1ull << 40, &v)) {
            fprintf(stderr, "albatros %s: --fault %s: expected corrupt|drop|duplicate|swap|silence|"
                            "disconnect|corrupt-reply|flip=N\n", a->cmd, value);
            return -1;
        }
        uint64_t *slot[] = {&a->faults.corrupt_byte, &a->faults.drop_packet,
                            &a->faults.duplicate_packet, &a->faults.swap_packet,
                            &a->faults.silence_after, &a->faults.disconnect_after,
                            &a->faults.corrupt_reply};
        if (k == 7)
            a->flip_frame = (long)v;
        else
            *slot[k] = v, a->any_fault = true;
    } else {
        unsigned long long max = !strcmp(name, "vid") || !strcmp(name, "pid") ? 0xFFFF : 600000;
        if (parse_num(a->cmd, name, value, max, &v))
            return -1;
        if (!strcmp(name, "vid")) a->vid = (unsigned)v;
        else if (!strcmp(name, "pid")) a->pid = (unsigned)v;
        else if (!strcmp(name, "wait")) a->wait_ms = (unsigned)v;
        else if (!strcmp(name, "timeout")) a->timeout_ms = (unsigned)v;
    }
    return 0;
}

/* The link the options ask for; *board (if not NULL) is the simulated board
 * behind it with --sim, else NULL. */
static transport_t *open_link(const link_args *a, const profile_t *p, sim_board **board)
{
    char err[600];
    transport_t *t = a->sim ? transport_sim_open(p->name, err, sizeof err)
                            : transport_usb_open((uint16_t)a->vid, (uint16_t)a->pid, a->serial,
                                                 a->wait_ms, err, sizeof err);
    if (!t) {
        fprintf(stderr, "albatros %s: %s\n", a->cmd, err);
        return NULL;
    }
    if (board)
        *board = a->sim ? transport_sim_board(t) : NULL;
    if (a->sim && a->flip_frame >= 0)
        sim_board_flip(transport_sim_board(t), (uint32_t)a->flip_frame, 5, 7, 1, 0);
    if (a->any_fault) {
        transport_t *f = transport_faulty(t, &a->faults);
        if (!f) {
            t->ops->close(t);
            return NULL;
        }
        t = f;
    }
    return t;
}

/* ---- the emulator's view of each frame ---- */

typedef struct {
    stream_frame *f;
    unsigned nf, k;
    uint16_t **keep;
} expect_ctx;

static int expect_frame(void *ctx, const frame_t *fr, const vp_stats *vs, const sim_counters *sc)
{
    (void)vs;
    expect_ctx *e = ctx;
    if (e->k >= e->nf)
        return 0;
    stream_frame *f = &e->f[e->k];
    size_t npix = (size_t)fr->width * fr->height;
    f->crc = link_frame_crc(fr->rgb, npix);
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

static void report_text(const stream_report *r, const stream_frame *f, unsigned nf, int rc)
{
    for (unsigned i = 0; i < nf; i++) {
        if (!f[i].have)
            fprintf(stderr, "  frame %u: no result\n", f[i].number);
        else if (f[i].board_crc != f[i].crc || f[i].board_cycles != f[i].cycles)
            fprintf(stderr, "  frame %u: DIFFERS: CRC %08x (emulator %08x), %llu cycles (emulator "
                            "%llu)\n", f[i].number, f[i].board_crc, f[i].crc,
                    (unsigned long long)f[i].board_cycles, (unsigned long long)f[i].cycles);
    }
    fprintf(stderr, "stream: %u of %u frames match the emulator (CRC and cycles); %llu packets, "
                    "%.2f MB in %.2f s; %llu resumes, %llu queries\n", r->matched, nf,
            (unsigned long long)r->packets, (double)r->bytes / 1e6, r->seconds,
            (unsigned long long)r->resumes, (unsigned long long)r->queries);
    uint64_t be = 0;
    for (int i = 1; i < 9; i++)
        be += r->board_errors[i];
    if (be || r->rx_crc_errors || r->rx_garbage || r->rx_gaps)
        fprintf(stderr, "  link: board reported %llu errors (CRC %llu, gaps %llu, duplicates %llu, "
                        "stream %llu); host saw %llu bad CRCs, %llu garbage bytes, %llu gaps\n",
                (unsigned long long)be, (unsigned long long)r->board_errors[PROTO_E_BAD_CRC],
                (unsigned long long)r->board_errors[PROTO_E_SEQ_GAP],
                (unsigned long long)r->board_errors[PROTO_E_DUPLICATE],
                (unsigned long long)r->board_errors[PROTO_E_STREAM],
                (unsigned long long)r->rx_crc_errors, (unsigned long long)r->rx_garbage,
                (unsigned long long)r->rx_gaps);
    if (r->first_problem[0])
        fprintf(stderr, "  first problem: %s\n", r->first_problem);
    if (rc == 0)
        fprintf(stderr, "  hardware agrees with the emulator\n");
}

static void report_json(const stream_report *r, const stream_frame *f, unsigned nf, int rc)
{
    printf("{\"result\": \"%s\", \"frames\": [", rc == 0 ? "match" : rc == 1 ? "differs" : "failed");
    for (unsigned i = 0; i < nf; i++)
        printf("%s{\"frame\": %u, \"have\": %s, \"crc\": \"%08x\", \"board_crc\": \"%08x\", "
               "\"cycles\": %llu, \"board_cycles\": %llu}", i ? ", " : "", f[i].number,
               f[i].have ? "true" : "false", f[i].crc, f[i].board_crc,
               (unsigned long long)f[i].cycles, (unsigned long long)f[i].board_cycles);
    printf("], \"matched\": %u, \"packets\": %llu, \"bytes\": %llu, \"resumes\": %llu, "
           "\"queries\": %llu, \"board_errors\": %llu, \"host_crc_errors\": %llu, "
           "\"first_problem\": \"", r->matched, (unsigned long long)r->packets,
           (unsigned long long)r->bytes, (unsigned long long)r->resumes,
           (unsigned long long)r->queries,
           (unsigned long long)(r->board_errors[1] + r->board_errors[2] + r->board_errors[3] +
                                r->board_errors[6]),
           (unsigned long long)r->rx_crc_errors);
    for (const char *p = r->first_problem; *p; p++)
        printf(*p == '"' || *p == '\\' ? "\\%c" : "%c", *p);
    printf("\"}\n");
}

/* Frames mode: the emulator's frames, RGB888, as tiles to a display board;
 * with --sim the board's display is compared with the last frame. */
static int stream_frames_mode(const link_args *a, const profile_t *p, const stream_frame *f,
                              unsigned nf)
{
    size_t npix = (size_t)p->width * p->height;
    stream_tiles_frame *tf = calloc(nf ? nf : 1, sizeof *tf);
    uint8_t *rgb = malloc(3 * npix * (nf ? nf : 1));
    int rc = 3;
    if (!tf || !rgb) {
        fprintf(stderr, "albatros stream: out of memory\n");
        goto out;
    }
    for (unsigned i = 0; i < nf; i++) {
        if (!f[i].rgb)
            goto out;
        link_rgb888(f[i].rgb, npix, p->colour_bits, rgb + 3 * npix * i);
        tf[i] = (stream_tiles_frame){f[i].number, p->width, p->height, rgb + 3 * npix * i};
    }
    sim_board *board;
    transport_t *t = open_link(a, p, &board);
    if (!t)
        goto out;
    stream_opts so;
    stream_opts_default(&so);
    so.timeout_ms = a->timeout_ms;
    so.log = a->quiet || a->json ? NULL : stderr;
    so.progress = so.log && cli_isatty_stderr();
    stream_report r;
    rc = stream_tiles(t, tf, nf, &so, &r) ? 3 : 0;
    const char *display = "";
    if (!rc && board && nf) {
        uint32_t shown;
        uint64_t tiles;
        const uint8_t *d = sim_board_display(board, &shown, &tiles);
        bool same = shown == tf[nf - 1].number && !memcmp(d, tf[nf - 1].rgb, 3 * npix);
        display = same ? "identical" : "DIFFERENT";
        rc = same ? 0 : 1;
    }
    double secs = r.seconds > 0 ? r.seconds : 1e-9;
    if (a->json)
        printf("{\"result\": \"%s\", \"frames\": %u, \"shown\": %u, \"packets\": %llu, "
               "\"bytes\": %llu, \"seconds\": %.3f, \"resends\": %llu, \"display\": \"%s\"}\n",
               rc == 0 ? "shown" : rc == 1 ? "differs" : "failed", nf, r.frames,
               (unsigned long long)r.packets, (unsigned long long)r.bytes, r.seconds,
               (unsigned long long)r.resumes, display);
    else if (!a->quiet || rc) {
        fprintf(stderr, "frames: %u of %u frames shown; %llu packets, %.2f MB in %.2f s "
                        "(%.1f MB/s, %.1f frames/s); %llu resends\n", r.frames, nf,
                (unsigned long long)r.packets, (double)r.bytes / 1e6, r.seconds,
                (double)r.bytes / 1e6 / secs, r.frames / secs, (unsigned long long)r.resumes);
        if (r.first_problem[0])
            fprintf(stderr, "  first problem: %s\n", r.first_problem);
        if (display[0])
            fprintf(stderr, "  the simulated display shows frame %u: %s to the emulator's\n",
                    tf[nf - 1].number, display);
    }
    t->ops->close(t);
out:
    free(rgb);
    free(tf);
    return rc;
}

static const char stream_help[] =
    "usage: albatros stream [SCENE] [--sim | --vid V --pid P --serial S --wait MS]\n"
    "                       [--stream FILE] [--timeout MS] [--json] [options]\n\n"
    "Send SCENE's word stream (or a stream FILE) to a board that runs the VP, and\n"
    "check each frame's CRC and cycle count against the emulator (timed model).\n"
    "Link errors are reported, counted and recovered from by resending frames.\n"
    "With --frames, send the emulator's finished frames instead, as tiles for a\n"
    "board that displays them (frames mode, docs/usb-protocol.md).\n\n"
    "  --sim              the simulated board in this process (no hardware)\n"
    "  --vid, --pid       USB ids (default 1209:0001, the pid.codes test PID)\n"
    "  --serial S         the board with this serial number\n"
    "  --wait MS          wait this long for the board to appear (hot-plug)\n"
    "  --timeout MS       wait this long for a frame's result (default 2000)\n"
    "  --no-readback      do not fetch a differing frame to name its first wrong pixel\n"
    "  --frames           frames mode: the rendered frames, RGB888 tiles, to a display\n"
    "  --fault KIND=N     misbehave on purpose: corrupt|drop|duplicate|swap|silence|\n"
    "                     disconnect|corrupt-reply=N, or flip=FRAME (sim: a wrong VP bit)\n"
    "  --json             the report as JSON on stdout\n\n"
    "Exit status: 0 every frame matches (frames mode: every frame shown), 1 some\n"
    "differ (frames mode, --sim: the display differs), 3 the link failed.\n\n";

int cmd_stream(int argc, char **argv)
{
    static const char *const spec[] = {"sim", "json", "quiet", "q", "help", "no-readback", "vid=",
                                       "pid=", "serial=", "wait=", "timeout=", "stream=",
                                       "fault=", "frames", NULL};
    link_args a = {.vid = PROTO_VID, .pid = PROTO_PID, .wait_ms = 2000, .timeout_ms = 2000,
                   .flip_frame = -1, .cmd = "stream"};
    run_opts o;
    run_opts_init(&o);
    const char *pos[1];
    int npos;
    if (cli_parse("stream", argc, argv, spec, link_opt, &a, &o, pos, 1, &npos))
        return 2;
    if (a.help) {
        printf("%s%s", stream_help, run_opts_help);
        return 0;
    }
    if (cli_check_profile(&o.prof))
        return 2;
    /* the word stream */
    ws_buf b;
    ws_buf_init(&b);
    diag_t d;
    diag_init(&d, stderr);
    if (a.stream) {
        if (ws_read_file(a.stream, &b.w, &b.n, &d)) {
            diag_print(&d, stderr);
            return 1;
        }
    } else {
        scene_t scene;
        if (cli_load_scene(npos ? pos[0] : NULL, &o, &scene))
            return 1;
        gp_t *gp = NULL;
        alb_err e = gp_create(&gp, &scene, &o.prof, &d);
        if (!e)
            e = gp_run(gp, &b, NULL, &d);
        gp_destroy(gp);
        scene_free(&scene);
        if (e) {
            diag_print(&d, stderr);
            ws_buf_free(&b);
            return 1;
        }
    }
    stream_frame *frames = NULL;
    unsigned nf = 0;
    if (stream_frames(b.w, b.n, &frames, &nf)) {
        fprintf(stderr, "albatros stream: the word stream is malformed (albatros dump says where)\n");
        ws_buf_free(&b);
        return 1;
    }
    /* what the emulator says */
    uint16_t **keep = calloc(nf ? nf : 1, sizeof *keep);
    expect_ctx ec = {frames, nf, 0, keep};
    sim_options so = {FIDELITY_TIMED, NULL, 0, 0, 1};
    int rc = 3;
    transport_t *t = NULL;
    if (!keep || sim_run(&o.prof, b.w, b.n, "stream", &so, expect_frame, &ec, &d)) {
        diag_print(&d, stderr);
        goto out;
    }
    if (a.frames) {
        rc = stream_frames_mode(&a, &o.prof, frames, nf);
        goto out;
    }
    if (!(t = open_link(&a, &o.prof, NULL)))
        goto out;
    stream_opts sopt;
    stream_opts_default(&sopt);
    sopt.timeout_ms = a.timeout_ms;
    sopt.readback = !a.no_readback;
    sopt.log = a.quiet || a.json ? NULL : stderr;
    sopt.progress = sopt.log && cli_isatty_stderr();
    stream_report r;
    rc = stream_run(t, b.w, b.n, frames, nf, &sopt, &r);
    rc = rc < 0 ? 3 : rc;
    if (a.json)
        report_json(&r, frames, nf, rc);
    else if (!a.quiet || rc)
        report_text(&r, frames, nf, rc);
out:
    if (t)
        t->ops->close(t);
    for (unsigned i = 0; keep && i < nf; i++)
        free(keep[i]);
    free(keep);
    free(frames);
    ws_buf_free(&b);
    return rc;
}

/* ---- albatros board ---- */

static int board_info(transport_t *t, bool json)
{
    uint8_t rep[PROTO_HID_REPORT + 1] = {PROTO_HID_INFO};
    if (t->ops->hid_get(t, rep, PROTO_HID_REPORT)) {
        fprintf(stderr, "albatros board info: %s\n", t->error);
        return 1;
    }
    if (memcmp(rep + PROTO_INFO_MAGIC, "ALBI", 4)) {
        fprintf(stderr, "albatros board info: the device's INFO report lacks the ALBI magic: "
                        "not an albatros board?\n");
        return 1;
    }
    char name[17];
    memcpy(name, rep + PROTO_INFO_NAME, 16);
    name[16] = 0;
    unsigned proto = rep[PROTO_INFO_PROTO] | rep[PROTO_INFO_PROTO + 1] << 8;
    unsigned fw = rep[PROTO_INFO_FW] | rep[PROTO_INFO_FW + 1] << 8;
    unsigned w = rep[PROTO_INFO_WIDTH] | rep[PROTO_INFO_WIDTH + 1] << 8;
    unsigned h = rep[PROTO_INFO_HEIGHT] | rep[PROTO_INFO_HEIGHT + 1] << 8;
    unsigned maxpay = rep[PROTO_INFO_MAXPAY] | rep[PROTO_INFO_MAXPAY + 1] << 8;
    if (json)
        printf("{\"name\": \"%s\", \"protocol\": %u, \"firmware\": %u, \"width\": %u, \"height\": "
               "%u, \"colour_bits\": %u, \"mode\": %u, \"serial\": %u, \"max_payload\": %u}\n",
               name, proto, fw, w, h, rep[PROTO_INFO_CBITS], rep[PROTO_INFO_MODE],
               PROTO_GET32(rep + PROTO_INFO_SERIAL), maxpay);
    else
        printf("%s: protocol %u, firmware %u, VP %ux%u %u-bit colour, mode %u, serial %u, "
               "payloads up to %u bytes\n", name, proto, fw, w, h, rep[PROTO_INFO_CBITS],
               rep[PROTO_INFO_MODE], PROTO_GET32(rep + PROTO_INFO_SERIAL), maxpay);
    return 0;
}

int cmd_board(int argc, char **argv)
{
    static const char *const spec[] = {"sim", "json", "help", "vid=", "pid=", "serial=", "wait=",
                                       NULL};
    link_args a = {.vid = PROTO_VID, .pid = PROTO_PID, .wait_ms = 0, .flip_frame = -1,
                   .cmd = "board"};
    run_opts o;
    run_opts_init(&o);
    const char *pos[1];
    int npos;
    if (cli_parse("board", argc, argv, spec, link_opt, &a, &o, pos, 1, &npos))
        return 2;
    if (a.help || npos != 1 ||
        (strcmp(pos[0], "list") && strcmp(pos[0], "info") && strcmp(pos[0], "reset"))) {
        printf("usage: albatros board list|info|reset [--sim] [--vid V --pid P --serial S] "
               "[--json]\n\n  list   boards on the USB bus\n  info   the board's INFO report "
               "(HID)\n  reset  reset the board's link, VP and counters (HID)\n");
        return a.help ? 0 : 2;
    }
    char err[600];
    if (!strcmp(pos[0], "list")) {
        if (a.sim) {
            printf("sim:0  simulated board (profile %s)\n", o.prof.name);
            return 0;
        }
        int n = transport_usb_list((uint16_t)a.vid, (uint16_t)a.pid, stdout, err, sizeof err);
        if (n < 0) {
            fprintf(stderr, "albatros board list: %s\n", err);
            return 1;
        }
        if (n == 0)
            fprintf(stderr, "no board %04x:%04x on the USB bus\n", a.vid, a.pid);
        return 0;
    }
    transport_t *t = open_link(&a, &o.prof, NULL);
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
        else
            printf("board reset\n");
    }
    t->ops->close(t);
    return rc;
}
