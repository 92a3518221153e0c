/* exr.c — frames to and from OpenEXR files through OpenEXRCore's C API (the
 * channels and attributes are listed in exr.h).  We own the file descriptor
 * and do the I/O ourselves so that errors carry errno and nothing is printed. */
#include "albatros/exr.h"
#include "albatros/file.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <half.h>
#include <openexr.h>

/* Our files have one part; OpenEXRCore numbers it 0. */
#define PART 0

#define ATTR_COLOUR "albatros.colour_bits"
#define ATTR_DEPTH  "albatros.depth_bits"
#define ATTR_AA     "albatros.aa_levels"
#define ATTR_FRAME  "albatros.frame"
#define ATTR_NEAR   "albatros.near"
#define ATTR_COLOUR_NOTE "albatros.colour"
#define ATTR_SOFTWARE "albatros.software"
#define ATTR_PROFILE  "albatros.profile"
#define ATTR_FIDELITY "albatros.fidelity"
#define ATTR_SOURCE   "albatros.source"

/* What R, G, B hold, in the file for whoever opens it (docs/vp.md, "Frames"). */
static const char colour_note[] =
    "R G B: linear light with sRGB (Rec. 709) primaries and D65 white, the frame store value "
    "v / (2^colour_bits - 1) decoded by the sRGB transfer function (IEC 61966-2-1), as a "
    "viewer shows the PNG preview; the exact store values are vp.R vp.G vp.B";

enum {
    CH_R, CH_G, CH_B, CH_A, CH_Z, CH_FACE, CH_LEVEL, CH_DEPTH,
    CH_VR, CH_VG, CH_VB, CH_COVERAGE, CH_CYCLES, CH_COUNT
};

typedef struct {
    const char *name;
    exr_pixel_type_t type;
} chan_def;

static const chan_def chans[CH_COUNT] = {
    [CH_R] = {"R", EXR_PIXEL_HALF},
    [CH_G] = {"G", EXR_PIXEL_HALF},
    [CH_B] = {"B", EXR_PIXEL_HALF},
    [CH_A] = {"A", EXR_PIXEL_HALF},
    [CH_Z] = {"Z", EXR_PIXEL_FLOAT},
    [CH_FACE] = {"face.id", EXR_PIXEL_UINT},
    [CH_LEVEL] = {"vp.level", EXR_PIXEL_UINT},
    [CH_DEPTH] = {"vp.depth", EXR_PIXEL_UINT},
    [CH_VR] = {"vp.R", EXR_PIXEL_UINT},
    [CH_VG] = {"vp.G", EXR_PIXEL_UINT},
    [CH_VB] = {"vp.B", EXR_PIXEL_UINT},
    [CH_COVERAGE] = {"vp.coverage", EXR_PIXEL_UINT},
    [CH_CYCLES] = {"vp.cycles", EXR_PIXEL_UINT},
};

static int chan_kind(const char *name, size_t len)
{
    for (int k = 0; k < CH_COUNT; k++)
        if (strlen(chans[k].name) == len && memcmp(chans[k].name, name, len) == 0)
            return k;
    return -1;
}

static size_t chan_bytes(int k)
{
    return chans[k].type == EXR_PIXEL_HALF ? 2 : 4;
}

/* ---- I/O callbacks: pread/pwrite on our descriptor ---------------------- */

typedef struct {
    int fd;
    int err;    /* errno of the first failed read or write; 0 if none */
    /* a target that takes no pwrite (a FIFO): the file is built here and
     * written in one go (OpenEXR writes its offset table last, at the start) */
    bool in_memory;
    unsigned char *mem;
    size_t mem_len, mem_cap;
} exr_io;

static int64_t io_read(exr_const_context_t c, void *user, void *buf, uint64_t size,
                       uint64_t offset, exr_stream_error_func_ptr_t report)
{
    exr_io *io = user;
    unsigned char *p = buf;
    uint64_t done = 0;
    (void)c;
    (void)report;
    /* offsets come from the file: refuse those off_t cannot hold */
    if (offset > (uint64_t)INT64_MAX - size)
        return -1;
    while (done < size) {
        ssize_t n = pread(io->fd, p + done, (size_t)(size - done), (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            if (io->err == 0)
                io->err = errno;
            return -1;
        }
        if (n == 0)
            break;   /* end of file: a short read, which the library reports */
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

static int64_t io_size(exr_const_context_t c, void *user)
{
    exr_io *io = user;
    struct stat st;
    (void)c;
    /* the library checks offsets and sizes in the header against this */
    return fstat(io->fd, &st) == 0 ? (int64_t)st.st_size : -1;
}

static int64_t mem_write(exr_io *io, const void *buf, uint64_t size, uint64_t offset)
{
    if (offset > SIZE_MAX - size) {
        io->err = io->err ? io->err : EFBIG;
        return -1;
    }
    size_t end = (size_t)(offset + size);
    if (end > io->mem_cap) {
        size_t cap = io->mem_cap ? io->mem_cap : 65536;
        while (cap < end)
            cap = cap <= SIZE_MAX / 2 ? cap * 2 : end;
        unsigned char *m = realloc(io->mem, cap);
        if (!m) {
            io->err = io->err ? io->err : ENOMEM;
            return -1;
        }
        if (cap > io->mem_len)
            memset(m + io->mem_len, 0, cap - io->mem_len);
        io->mem = m;
        io->mem_cap = cap;
    }
    memcpy(io->mem + offset, buf, size);
    if (end > io->mem_len)
        io->mem_len = end;
    return (int64_t)size;
}

static int64_t io_write(exr_const_context_t c, void *user, const void *buf, uint64_t size,
                        uint64_t offset, exr_stream_error_func_ptr_t report)
{
    exr_io *io = user;
    const unsigned char *p = buf;
    uint64_t done = 0;
    (void)c;
    (void)report;
    if (io->in_memory)
        return mem_write(io, buf, size, offset);
    while (done < size) {
        ssize_t n = pwrite(io->fd, p + done, (size_t)(size - done), (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            if (io->err == 0)
                io->err = n < 0 ? errno : ENOSPC;
            return -1;
        }
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

/* The library's default handler prints to stderr; library code must not. */
static void quiet(exr_const_context_t c, exr_result_t code, const char *msg)
{
    (void)c;
    (void)code;
    (void)msg;
}

static exr_context_initializer_t io_init(exr_io *io)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet;
    init.user_data = io;
    init.read_fn = io_read;
    init.size_fn = io_size;
    init.write_fn = io_write;
    init.max_image_width = init.max_image_height = (int)ALB_EXR_MAX_SIDE;
    /* fixed rather than the process-wide default, so output never varies */
    init.zip_level = 6;
    return init;
}

/* An OpenEXRCore failure: errno if our I/O failed, else the library's text. */
static alb_err exr_fail(alb_diag *d, const char *path, const exr_io *io, exr_result_t rv,
                        const char *what)
{
    if (io->err != 0)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "%s: %s", what, strerror(io->err));
    return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "%s: %s (OpenEXR)", what,
                   exr_get_default_error_message(rv));
}

/* ---- writing ------------------------------------------------------------- */

static alb_err check_frame(const char *path, const alb_frame *f, alb_diag *d)
{
    if (f->width < 1 || f->height < 1 || f->width > ALB_EXR_MAX_SIDE || f->height > ALB_EXR_MAX_SIDE)
        return alb_diag_at(d, ALB_ERR_CONFIG, path, 0, 0,
                       "cannot write a %ux%u frame: sides must be 1..%u", f->width,
                       f->height, ALB_EXR_MAX_SIDE);
    if (f->colour_bits < 1 || f->colour_bits > 16 || f->depth_bits < 1 ||
        f->depth_bits > 32 || f->aa_levels > 7)
        return alb_diag_at(d, ALB_ERR_CONFIG, path, 0, 0,
                       "cannot write a frame with colour_bits=%u depth_bits=%u aa=%u "
                       "(need 1..16, 1..32, 0..7)",
                       f->colour_bits, f->depth_bits, f->aa_levels);
    if (!f->rgb || !f->depth || !f->face || !f->level || !f->coverage)
        return alb_diag_at(d, ALB_ERR_CONFIG, path, 0, 0, "cannot write a frame without planes");
    return ALB_OK;
}

static void channels_of(const alb_frame *f, bool present[CH_COUNT])
{
    for (int k = 0; k < CH_COUNT; k++)
        present[k] = true;
    present[CH_A] = f->aa_levels > 0;
    present[CH_CYCLES] = f->cycles != NULL;
}

/* sRGB's transfer function (IEC 61966-2-1): encoded e in [0, 1] to linear
 * light, and back. */
static double srgb_to_linear(double e)
{
    return e <= 0.04045 ? e / 12.92 : pow((e + 0.055) / 1.055, 2.4);
}

static double linear_to_srgb(double l)
{
    return l <= 0.0031308 ? l * 12.92 : 1.055 * pow(l, 1 / 2.4) - 0.055;
}

/* A string attribute if the string is given. */
static exr_result_t set_string(exr_context_t c, const char *name, const char *v, exr_result_t rv)
{
    return rv == EXR_ERR_SUCCESS && v ? exr_attr_set_string(c, PART, name, v) : rv;
}

/* Where the frame came from: fixed strings, no dates, so the same input
 * gives the same bytes. */
static exr_result_t define_provenance(exr_context_t c, const alb_exr_options *o)
{
    exr_result_t rv = EXR_ERR_SUCCESS;
    if (!o)
        return rv;
    rv = set_string(c, ATTR_SOFTWARE, o->software, rv);
    rv = set_string(c, ATTR_PROFILE, o->profile, rv);
    rv = set_string(c, ATTR_FIDELITY, o->fidelity, rv);
    return set_string(c, ATTR_SOURCE, o->source, rv);
}

static exr_result_t define_attrs(exr_context_t c, const alb_frame *f)
{
    /* Rec. 709 / sRGB primaries and D65 white: what R G B are in */
    static const exr_attr_chromaticities_t rec709 = {0.64f, 0.33f, 0.30f, 0.60f,
                                                     0.15f, 0.06f, 0.3127f, 0.3290f};
    int32_t number;
    /* an int attribute carries the uint32 frame number's bits unchanged */
    memcpy(&number, &f->number, sizeof number);
    exr_result_t rv = exr_attr_set_int(c, PART, ATTR_COLOUR, (int32_t)f->colour_bits);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_attr_set_int(c, PART, ATTR_DEPTH, (int32_t)f->depth_bits);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_attr_set_int(c, PART, ATTR_AA, (int32_t)f->aa_levels);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_attr_set_int(c, PART, ATTR_FRAME, number);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_attr_set_float(c, PART, ATTR_NEAR, f->near);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_attr_set_chromaticities(c, PART, "chromaticities", &rec709);
    return set_string(c, ATTR_COLOUR_NOTE, colour_note, rv);
}

static exr_result_t define_header(exr_context_t c, const alb_frame *f, const bool *present,
                                  const alb_exr_options *opt)
{
    int part;
    /* no part name: a single unnamed part is written as a plain
     * (non-multipart) file that every OpenEXR reader accepts */
    exr_result_t rv = exr_add_part(c, NULL, EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS && part != PART)
        rv = EXR_ERR_INCORRECT_PART;
    /* data = display window = the screen, INCREASING_Y, ZIP (lossless) */
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(c, PART, (int32_t)f->width,
                                                 (int32_t)f->height, EXR_COMPRESSION_ZIP);
    for (int k = 0; k < CH_COUNT && rv == EXR_ERR_SUCCESS; k++) {
        /* colour is perceptual; ids, depth and counts are not */
        exr_perceptual_treatment_t pt = k <= CH_A ? EXR_PERCEPTUALLY_LOGARITHMIC
                                                  : EXR_PERCEPTUALLY_LINEAR;
        if (present[k])
            rv = exr_add_channel(c, PART, chans[k].name, chans[k].type, pt, 1, 1);
    }
    if (rv == EXR_ERR_SUCCESS)
        rv = define_attrs(c, f);
    if (rv == EXR_ERR_SUCCESS)
        rv = define_provenance(c, opt);
    return rv;
}

static uint16_t to_half(double v)
{
    return imath_float_to_half((float)v);
}

/* What every chunk's rows are made from: the frame and its HALF values,
 * converted once per frame rather than once per pixel. */
typedef struct {
    const alb_frame *f;
    uint16_t *colour_half;     /* frame store value -> HALF, 2^colour_bits entries */
    uint16_t *coverage_half;   /* covered samples -> HALF, 4^aa + 1 entries */
} row_src;

static int row_src_init(row_src *r, const alb_frame *f)
{
    size_t ncol = (size_t)1 << f->colour_bits, ncov = ((size_t)1 << (2 * f->aa_levels)) + 1;
    double cmax = (double)(ncol - 1), samples = (double)(ncov - 1);
    r->f = f;
    r->colour_half = malloc(ncol * sizeof *r->colour_half);
    r->coverage_half = malloc(ncov * sizeof *r->coverage_half);
    if (!r->colour_half || !r->coverage_half)
        return -1;
    for (size_t v = 0; v < ncol; v++)   /* linear light: docs/vp.md, "Frames" */
        r->colour_half[v] = to_half(srgb_to_linear((double)v / cmax));
    for (size_t v = 0; v < ncov; v++)
        r->coverage_half[v] = to_half((double)v / samples);
    return 0;
}

static void row_src_free(row_src *r)
{
    free(r->colour_half);
    free(r->coverage_half);
}

/* Row y of channel k in its file type (HALF: 2 bytes, else 4) into dst. */
static void fill_row(const row_src *src, int k, unsigned y, unsigned char *dst)
{
    const alb_frame *f = src->f;
    const size_t w = f->width, row = (size_t)y * w;
    uint16_t *h = (uint16_t *)(void *)dst;
    uint32_t *u = (uint32_t *)(void *)dst;
    float *z = (float *)(void *)dst;
    /* values beyond the tables cannot come from a VP; converted all the same */
    const uint32_t cmax = (1u << f->colour_bits) - 1, most = 1u << (2 * f->aa_levels);
    switch (k) {
    case CH_R: case CH_G: case CH_B:
        for (size_t x = 0; x < w; x++) {
            uint32_t v = f->rgb[3 * (row + x) + (size_t)(k - CH_R)];
            h[x] = v <= cmax ? src->colour_half[v] : to_half(srgb_to_linear((double)v / cmax));
        }
        break;
    case CH_A:
        for (size_t x = 0; x < w; x++) {
            uint32_t c = f->coverage[row + x];
            h[x] = c <= most ? src->coverage_half[c] : to_half((double)c / most);
        }
        break;
    case CH_Z:
        for (size_t x = 0; x < w; x++)
            z[x] = alb_frame_z(f, f->depth[row + x]);
        break;
    case CH_FACE: memcpy(u, f->face + row, w * 4); break;
    case CH_LEVEL:
        for (size_t x = 0; x < w; x++)
            u[x] = f->level[row + x];
        break;
    case CH_DEPTH: memcpy(u, f->depth + row, w * 4); break;
    case CH_VR: case CH_VG: case CH_VB:
        for (size_t x = 0; x < w; x++)
            u[x] = f->rgb[3 * (row + x) + (size_t)(k - CH_VR)];
        break;
    case CH_COVERAGE:
        for (size_t x = 0; x < w; x++)
            u[x] = f->coverage[row + x];
        break;
    case CH_CYCLES: memcpy(u, f->cycles + row, w * 4); break;
    default: break;
    }
}

/* Our side of a pipeline channel: planar rows of `width` pixels, `bytes` each. */
static void set_layout(exr_coding_channel_info_t *ch, int16_t bytes, exr_pixel_type_t type,
                       unsigned width)
{
    ch->user_bytes_per_element = bytes;
    ch->user_data_type = (uint16_t)type;
    ch->user_pixel_stride = bytes;
    ch->user_line_stride = (int32_t)bytes * (int32_t)width;
}

/* ---- chunks, compressed on several threads, written in order ------------
 * Each thread takes the next chunk, packs and compresses it with a pipeline
 * of its own, then waits for its turn to write: the file's chunks are in
 * increasing y and its bytes are the same on any number of threads. */

typedef struct {
    exr_context_t c;
    row_src src;
    int lines;
    unsigned chunks;
    size_t slot;               /* bytes of one channel's rows in a chunk */
    pthread_mutex_t mu;
    pthread_cond_t turn;
    unsigned next_take, next_write;
    bool failed;               /* stop: every thread leaves */
    exr_result_t rv;           /* the first failure, and its chunk */
    unsigned failed_chunk;
} chunk_writer;

typedef struct {
    chunk_writer *w;
    unsigned chunk;
    exr_result_t (*write)(exr_encode_pipeline_t *);   /* the library's */
} chunk_job;

static void fail_chunk(chunk_writer *w, unsigned chunk, exr_result_t rv)
{
    if (!w->failed || chunk < w->failed_chunk) {
        w->rv = rv;
        w->failed_chunk = chunk;
    }
    w->failed = true;
    pthread_cond_broadcast(&w->turn);
}

/* The pipeline's write step: in chunk order, one at a time. */
static exr_result_t write_in_turn(exr_encode_pipeline_t *enc)
{
    chunk_job *job = enc->encoding_user_data;
    chunk_writer *w = job->w;
    pthread_mutex_lock(&w->mu);
    while (w->next_write != job->chunk && !w->failed)
        pthread_cond_wait(&w->turn, &w->mu);
    exr_result_t rv = w->failed ? EXR_ERR_UNKNOWN : job->write(enc);
    if (rv == EXR_ERR_SUCCESS) {
        w->next_write++;
        pthread_cond_broadcast(&w->turn);
    }
    pthread_mutex_unlock(&w->mu);
    return rv;
}

static exr_result_t encode_chunk(chunk_writer *w, chunk_job *job, unsigned char *buf,
                                 exr_encode_pipeline_t *enc, bool *started)
{
    const alb_frame *f = w->src.f;
    exr_chunk_info_t ci;
    exr_result_t rv = exr_write_scanline_chunk_info(w->c, PART, (int)job->chunk * w->lines, &ci);
    if (rv == EXR_ERR_SUCCESS)
        rv = *started ? exr_encoding_update(w->c, PART, &ci, enc)
                      : exr_encoding_initialize(w->c, PART, &ci, enc);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    *started = true;
    for (int i = 0; i < enc->channel_count; i++) {
        exr_coding_channel_info_t *ch = &enc->channels[i];
        int k = chan_kind(ch->channel_name, strlen(ch->channel_name));
        if (k < 0)
            return EXR_ERR_INVALID_ARGUMENT;   /* we defined every channel */
        unsigned char *dst = buf + w->slot * (size_t)k;
        size_t bytes = chan_bytes(k);
        for (int r = 0; r < ci.height; r++)
            fill_row(&w->src, k, (unsigned)(ci.start_y + r), dst + (size_t)r * bytes * f->width);
        set_layout(ch, (int16_t)bytes, chans[k].type, f->width);
        ch->encode_from_ptr = dst;
    }
    rv = exr_encoding_choose_default_routines(w->c, PART, enc);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    job->write = enc->write_fn;
    enc->write_fn = write_in_turn;
    /* the library's wait would refuse a chunk whose turn has not come;
     * write_in_turn waits for it instead */
    enc->yield_until_ready_fn = NULL;
    enc->encoding_user_data = job;
    return exr_encoding_run(w->c, PART, enc);
}

static void *chunk_worker(void *arg)
{
    chunk_writer *w = arg;
    unsigned char *buf = malloc(w->slot * CH_COUNT);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    bool started = false;
    chunk_job job = {w, 0, NULL};
    pthread_mutex_lock(&w->mu);
    if (!buf)
        fail_chunk(w, w->next_take, EXR_ERR_OUT_OF_MEMORY);
    while (!w->failed && w->next_take < w->chunks) {
        job.chunk = w->next_take++;
        pthread_mutex_unlock(&w->mu);
        exr_result_t rv = encode_chunk(w, &job, buf, &enc, &started);
        pthread_mutex_lock(&w->mu);
        /* a chunk stopped because another failed is not a failure of its own */
        if (rv != EXR_ERR_SUCCESS && !w->failed)
            fail_chunk(w, job.chunk, rv);
    }
    pthread_mutex_unlock(&w->mu);
    if (started && exr_encoding_destroy(w->c, &enc) != EXR_ERR_SUCCESS) {
        pthread_mutex_lock(&w->mu);
        fail_chunk(w, w->chunks, EXR_ERR_UNKNOWN);
        pthread_mutex_unlock(&w->mu);
    }
    free(buf);
    return NULL;
}

static alb_err write_chunks(exr_context_t c, const alb_frame *f, unsigned threads,
                            const char *path, const exr_io *io, alb_diag *d)
{
    chunk_writer w = {.c = c};
    exr_result_t rv = exr_get_scanlines_per_chunk(c, PART, &w.lines);
    if (rv != EXR_ERR_SUCCESS || w.lines < 1)
        return exr_fail(d, path, io, rv, "cannot lay out OpenEXR chunks");
    w.chunks = (f->height + (unsigned)w.lines - 1) / (unsigned)w.lines;
    w.slot = (size_t)f->width * (size_t)w.lines * 4;
    if (row_src_init(&w.src, f)) {
        row_src_free(&w.src);
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory writing OpenEXR");
    }
    pthread_mutex_init(&w.mu, NULL);
    pthread_cond_init(&w.turn, NULL);
    threads = threads < 1 ? 1 : threads > w.chunks ? w.chunks : threads;
    pthread_t tid[ALB_EXR_MAX_THREADS];
    unsigned started = 0;
    while (started + 1 < threads && started < ALB_EXR_MAX_THREADS &&
           pthread_create(&tid[started], NULL, chunk_worker, &w) == 0)
        started++;
    chunk_worker(&w);   /* this thread works too: one thread is no thread */
    for (unsigned i = 0; i < started; i++)
        pthread_join(tid[i], NULL);
    pthread_cond_destroy(&w.turn);
    pthread_mutex_destroy(&w.mu);
    row_src_free(&w.src);
    if (!w.failed)
        return ALB_OK;
    if (w.rv == EXR_ERR_OUT_OF_MEMORY)
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory writing OpenEXR");
    if (w.failed_chunk >= w.chunks)
        return exr_fail(d, path, io, w.rv, "cannot finish encoding");
    char what[64];
    snprintf(what, sizeof what, "cannot write lines from %u", w.failed_chunk * (unsigned)w.lines);
    return exr_fail(d, path, io, w.rv, what);
}

static alb_err write_ctx(exr_context_t c, const alb_frame *f, const alb_exr_options *opt,
                         const char *path, const exr_io *io, alb_diag *d)
{
    bool present[CH_COUNT];
    channels_of(f, present);
    unsigned threads = opt ? opt->threads : 1;
    exr_result_t rv = define_header(c, f, present, opt);
    if (rv != EXR_ERR_SUCCESS)
        return exr_fail(d, path, io, rv, "cannot define the OpenEXR header");
    rv = exr_write_header(c);
    if (rv != EXR_ERR_SUCCESS)
        return exr_fail(d, path, io, rv, "cannot write the OpenEXR header");
    return write_chunks(c, f, threads, path, io, d);
}

alb_err alb_exr_write_frame(const char *path, const alb_frame *f, alb_diag *d)
{
    return alb_exr_write_frame_threads(path, f, 1, d);
}

alb_err alb_exr_write_frame_threads(const char *path, const alb_frame *f, unsigned threads, alb_diag *d)
{
    alb_exr_options opt = {.threads = threads};
    return alb_exr_write(path, f, &opt, d);
}

alb_err alb_exr_write(const char *path, const alb_frame *f, const alb_exr_options *opt, alb_diag *d)
{
    alb_err e = check_frame(path, f, d);
    if (e != ALB_OK)
        return e;
    alb_out out;
    if ((e = alb_out_open(&out, path, 0, d)) != ALB_OK)
        return e;
    exr_io io = {.fd = out.fd, .in_memory = !out.seekable};
    exr_context_initializer_t init = io_init(&io);
    exr_context_t c = NULL;
    exr_result_t rv = exr_start_write(&c, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS)
        e = exr_fail(d, path, &io, rv, "cannot start an OpenEXR file");
    else
        e = write_ctx(c, f, opt, path, &io, d);
    /* exr_finish writes the chunk offset table: its failure is ours too */
    rv = exr_finish(&c);
    if (rv != EXR_ERR_SUCCESS && e == ALB_OK)
        e = exr_fail(d, path, &io, rv, "cannot finish the OpenEXR file");
    if (e == ALB_OK && io.in_memory)
        e = alb_out_write(&out, io.mem, io.mem_len, d);
    free(io.mem);
    /* never a half-written frame under the name: the old file stays until
     * the new one is complete, and a device is never removed */
    if (e == ALB_OK)
        e = alb_out_commit(&out, d);
    else
        alb_out_abort(&out);
    return e;
}

/* ---- reading ------------------------------------------------------------- */

static alb_err read_layout(exr_const_context_t c, const char *path, const exr_io *io,
                           exr_attr_box2i_t *dw, alb_diag *d)
{
    int parts = 0;
    exr_storage_t st;
    exr_result_t rv = exr_get_count(c, &parts);
    if (rv == EXR_ERR_SUCCESS && parts < 1)
        rv = EXR_ERR_FILE_BAD_HEADER;
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_storage(c, PART, &st);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_data_window(c, PART, dw);
    if (rv != EXR_ERR_SUCCESS)
        return exr_fail(d, path, io, rv, "cannot read the OpenEXR header");
    if (st != EXR_STORAGE_SCANLINE)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0,
                       "holds a tiled or deep image; frames are scanline images");
    int64_t w = (int64_t)dw->max.x - dw->min.x + 1, h = (int64_t)dw->max.y - dw->min.y + 1;
    if (w < 1 || h < 1 || w > ALB_EXR_MAX_SIDE || h > ALB_EXR_MAX_SIDE)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0,
                       "data window is %lldx%lld; frames are 1..%u pixels a side",
                       (long long)w, (long long)h, ALB_EXR_MAX_SIDE);
    return ALB_OK;
}

static const char *type_name(exr_pixel_type_t t)
{
    return t == EXR_PIXEL_UINT ? "UINT" : t == EXR_PIXEL_HALF ? "HALF"
         : t == EXR_PIXEL_FLOAT ? "FLOAT" : "an unknown type";
}

static bool type_ok(int k, exr_pixel_type_t t)
{
    if (k <= CH_B)   /* colour is converted: HALF or FLOAT will do */
        return t == EXR_PIXEL_HALF || t == EXR_PIXEL_FLOAT;
    if (k == CH_A || k == CH_Z)   /* never read back */
        return true;
    return t == chans[k].type;   /* exact data only as stored by us */
}

static alb_err read_channels(exr_const_context_t c, const char *path, const exr_io *io,
                             bool present[CH_COUNT], alb_diag *d)
{
    const exr_attr_chlist_t *cl = NULL;
    exr_result_t rv = exr_get_channels(c, PART, &cl);
    if (rv != EXR_ERR_SUCCESS || !cl)
        return exr_fail(d, path, io, rv, "cannot read the channel list");
    for (int k = 0; k < CH_COUNT; k++)
        present[k] = false;
    for (int i = 0; i < cl->num_channels; i++) {
        const exr_attr_chlist_entry_t *e = &cl->entries[i];
        int k = chan_kind(e->name.str, (size_t)e->name.length);
        if (k < 0)
            continue;   /* another tool's channel: not ours to judge */
        if (e->x_sampling != 1 || e->y_sampling != 1)
            return alb_diag_at(d, ALB_ERR_IO, path, 0, 0,
                           "channel %s is subsampled (%d x %d); frames have one sample "
                           "per pixel", chans[k].name, (int)e->x_sampling, (int)e->y_sampling);
        if (!type_ok(k, e->pixel_type))
            return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "channel %s holds %s; expected %s",
                           chans[k].name, type_name(e->pixel_type), type_name(chans[k].type));
        present[k] = true;
    }
    if (!present[CH_R] || !present[CH_G] || !present[CH_B])
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0,
                       "not a frame: it lacks channel %s",
                       !present[CH_R] ? "R" : !present[CH_G] ? "G" : "B");
    return ALB_OK;
}

static alb_err get_int(exr_const_context_t c, const char *path, const char *name,
                       int64_t lo, int64_t hi, int32_t def, int32_t *out, alb_diag *d)
{
    int32_t v;
    exr_result_t rv = exr_attr_get_int(c, PART, name, &v);
    if (rv == EXR_ERR_NO_ATTR_BY_NAME) {
        *out = def;
        return ALB_OK;
    }
    if (rv != EXR_ERR_SUCCESS)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "attribute %s: %s (OpenEXR)", name,
                       exr_get_default_error_message(rv));
    if (v < lo || v > hi)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "attribute %s = %d is outside %lld..%lld",
                       name, (int)v, (long long)lo, (long long)hi);
    *out = v;
    return ALB_OK;
}

/* The frame's parameters from our attributes (defaults for other files). */
static alb_err read_params(exr_const_context_t c, const char *path, alb_frame *p, alb_diag *d)
{
    int32_t cb, db, aa, number;
    alb_err e = get_int(c, path, ATTR_COLOUR, 1, 16, 8, &cb, d);
    if (e == ALB_OK)
        e = get_int(c, path, ATTR_DEPTH, 1, 32, 24, &db, d);
    if (e == ALB_OK)
        e = get_int(c, path, ATTR_AA, 0, 7, 0, &aa, d);
    if (e == ALB_OK)
        e = get_int(c, path, ATTR_FRAME, INT32_MIN, INT32_MAX, 0, &number, d);
    if (e != ALB_OK)
        return e;
    exr_result_t rv = exr_attr_get_float(c, PART, ATTR_NEAR, &p->near);
    if (rv == EXR_ERR_NO_ATTR_BY_NAME)
        p->near = 1.0f;
    else if (rv != EXR_ERR_SUCCESS)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "attribute %s: %s (OpenEXR)", ATTR_NEAR,
                       exr_get_default_error_message(rv));
    p->colour_bits = (unsigned)cb;
    p->depth_bits = (unsigned)db;
    p->aa_levels = (unsigned)aa;
    memcpy(&p->number, &number, sizeof number);
    return ALB_OK;
}

/* Validate the chunk before decoding into buffers sized for `lines` rows. */
static exr_result_t check_chunk(const exr_chunk_info_t *ci, const exr_decode_pipeline_t *dec,
                                int y, int32_t lines, unsigned width)
{
    if (ci->start_y != y || ci->height < 1 || ci->height > lines || ci->width != (int32_t)width)
        return EXR_ERR_CORRUPT_CHUNK;
    for (int i = 0; i < dec->channel_count; i++)
        if (dec->channels[i].height > ci->height || dec->channels[i].width != ci->width)
            return EXR_ERR_CORRUPT_CHUNK;
    return EXR_ERR_SUCCESS;
}

static exr_result_t decode_chunk(exr_const_context_t c, int y, int32_t lines,
                                 unsigned char *buf, size_t slot, const bool *want,
                                 unsigned width, exr_decode_pipeline_t *dec, bool *started,
                                 exr_chunk_info_t *ci)
{
    exr_result_t rv = exr_read_scanline_chunk_info(c, PART, y, ci);
    if (rv == EXR_ERR_SUCCESS)
        rv = *started ? exr_decoding_update(c, PART, ci, dec)
                      : exr_decoding_initialize(c, PART, ci, dec);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    *started = true;
    rv = check_chunk(ci, dec, y, lines, width);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    for (int i = 0; i < dec->channel_count; i++) {
        exr_coding_channel_info_t *ch = &dec->channels[i];
        int k = chan_kind(ch->channel_name, strlen(ch->channel_name));
        if (k < 0 || !want[k]) {
            ch->decode_to_ptr = NULL;   /* the library skips it */
            continue;
        }
        /* everything arrives as 4 bytes: UINT stays, HALF becomes FLOAT */
        set_layout(ch, 4, chans[k].type == EXR_PIXEL_UINT ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT,
                   width);
        ch->decode_to_ptr = buf + slot * (size_t)k;
    }
    rv = exr_decoding_choose_default_routines(c, PART, dec);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_decoding_run(c, PART, dec);
    return rv;
}

/* Store one decoded value of channel k at pixel i; -1 if out of range. */
static int store_value(alb_frame *f, int k, size_t i, const unsigned char *src)
{
    uint32_t u;
    float v;
    uint32_t cmax = (1u << f->colour_bits) - 1u;
    memcpy(&u, src, 4);
    memcpy(&v, src, 4);
    switch (k) {
    case CH_R: case CH_G: case CH_B: {
        /* only when vp.R/G/B are absent (another tool's file): linear light,
         * as EXR holds it, encoded by sRGB's transfer function and rounded */
        double s = linear_to_srgb(v > 0 ? (double)v : 0) * cmax;
        s = !(s >= 0) ? 0 : s > cmax ? cmax : s;   /* NaN and negatives -> 0 */
        f->rgb[3 * i + (size_t)(k - CH_R)] = (uint16_t)floor(s + 0.5);
        return 0;
    }
    case CH_FACE: f->face[i] = u; return 0;
    case CH_DEPTH: f->depth[i] = u; return 0;
    case CH_CYCLES: f->cycles[i] = u; return 0;
    case CH_LEVEL:
        if (u > 0xFFu)
            return -1;
        f->level[i] = (uint8_t)u;
        return 0;
    case CH_VR: case CH_VG: case CH_VB:
        if (u > cmax)
            return -1;
        f->rgb[3 * i + (size_t)(k - CH_VR)] = (uint16_t)u;
        return 0;
    case CH_COVERAGE:
        if (u > (1u << (2 * f->aa_levels)))
            return -1;
        f->coverage[i] = (uint16_t)u;
        return 0;
    default:
        return 0;
    }
}

static alb_err store_rows(const char *path, alb_frame *f, const unsigned char *buf, size_t slot,
                          const bool *want, unsigned y0, unsigned rows, alb_diag *d)
{
    for (int k = 0; k < CH_COUNT; k++) {
        if (!want[k])
            continue;
        const unsigned char *src = buf + slot * (size_t)k;
        for (unsigned r = 0; r < rows; r++)
            for (unsigned x = 0; x < f->width; x++) {
                size_t j = (size_t)r * f->width + x;
                if (store_value(f, k, (size_t)(y0 + r) * f->width + x, src + 4 * j) != 0)
                    return alb_diag_at(d, ALB_ERR_IO, path, 0, 0,
                                   "channel %s at pixel (%u, %u) is out of range for this "
                                   "frame (colour_bits %u, aa %u)",
                                   chans[k].name, x, y0 + r, f->colour_bits, f->aa_levels);
            }
    }
    return ALB_OK;
}

static alb_err read_chunks(exr_const_context_t c, const char *path, const exr_io *io,
                           const exr_attr_box2i_t *dw, const bool *want, alb_frame *f,
                           alb_diag *d)
{
    int32_t lines = 0;
    exr_result_t rv = exr_get_scanlines_per_chunk(c, PART, &lines);
    if (rv != EXR_ERR_SUCCESS || lines < 1 || lines > 4096)
        return exr_fail(d, path, io, rv ? rv : EXR_ERR_FILE_BAD_HEADER,
                        "cannot lay out OpenEXR chunks");
    size_t slot = (size_t)f->width * (size_t)lines * 4;
    unsigned char *buf = malloc(slot * CH_COUNT);
    if (!buf)
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory reading OpenEXR");
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    bool started = false;
    alb_err e = ALB_OK;
    for (int64_t y = dw->min.y; y <= dw->max.y && e == ALB_OK; y += lines) {
        exr_chunk_info_t ci;
        rv = decode_chunk(c, (int)y, lines, buf, slot, want, f->width, &dec, &started, &ci);
        if (rv != EXR_ERR_SUCCESS) {
            char what[96];
            snprintf(what, sizeof what, "cannot read lines from %lld (truncated or corrupt?)",
                     (long long)(y - dw->min.y));
            e = exr_fail(d, path, io, rv, what);
        } else {
            e = store_rows(path, f, buf, slot, want, (unsigned)(y - dw->min.y),
                           (unsigned)ci.height, d);
        }
    }
    if (started)
        exr_decoding_destroy(c, &dec);   /* only frees; nothing to report */
    free(buf);
    return e;
}

static alb_err read_ctx(exr_const_context_t c, const char *path, const exr_io *io, alb_frame *f,
                        alb_diag *d)
{
    exr_attr_box2i_t dw;
    bool present[CH_COUNT], want[CH_COUNT];
    alb_frame p;
    memset(&p, 0, sizeof p);
    alb_err e = read_layout(c, path, io, &dw, d);
    if (e == ALB_OK)
        e = read_channels(c, path, io, present, d);
    if (e == ALB_OK)
        e = read_params(c, path, &p, d);
    if (e != ALB_OK)
        return e;
    unsigned w = (unsigned)(dw.max.x - dw.min.x + 1), h = (unsigned)(dw.max.y - dw.min.y + 1);
    if (alb_frame_alloc(f, w, h, present[CH_CYCLES]) != 0)
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory for a %ux%u frame", w, h);
    f->colour_bits = p.colour_bits;
    f->depth_bits = p.depth_bits;
    f->aa_levels = p.aa_levels;
    f->near = p.near;
    f->number = p.number;
    /* what an absent channel means: no face anywhere */
    for (size_t i = 0; i < (size_t)w * h; i++) {
        f->face[i] = ALB_FRAME_NO_FACE;
        f->level[i] = ALB_FRAME_NO_LEVEL;
    }
    for (int k = 0; k < CH_COUNT; k++)
        want[k] = present[k] && chans[k].type == EXR_PIXEL_UINT;
    for (int k = CH_R; k <= CH_B; k++)   /* colour only if the exact values are absent */
        want[k] = !present[CH_VR + (k - CH_R)];
    return read_chunks(c, path, io, &dw, want, f, d);
}

alb_err alb_exr_read_frame(const char *path, alb_frame *f, alb_diag *d)
{
    memset(f, 0, sizeof *f);
    exr_io io = {.fd = open(path, O_RDONLY | O_CLOEXEC)};
    if (io.fd < 0)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot open: %s", strerror(errno));
    exr_context_initializer_t init = io_init(&io);
    /* a truncated file must fail, not be patched up by guessing chunk offsets */
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    exr_context_t c = NULL;
    alb_err e;
    exr_result_t rv = exr_start_read(&c, path, &init);
    if (rv != EXR_ERR_SUCCESS)
        e = exr_fail(d, path, &io, rv, "not a readable OpenEXR file");
    else
        e = read_ctx(c, path, &io, f, d);
    exr_finish(&c);   /* a read context has nothing to flush */
    close(io.fd);     /* read-only: nothing can be lost */
    if (e != ALB_OK)
        alb_frame_free(f);
    return e;
}
