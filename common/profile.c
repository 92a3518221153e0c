/* profile.c — the built-in members of the family and their overrides. */
#include "albatros/profile.h"
#include "fix.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Defaults are chosen as a 1990s team would for 50 Hz at these sizes: 24-bit
 * mantissas and depth (what a 24-bit DSP datapath carries), 8-bit colour, and
 * six bits below the pixel in edge intercepts (docs/profiles.md). */
/* The clocked parameters (docs/microarchitecture.md): a 40 MHz VP with 8
 * edge units and a 4-sample fill for 512x512, twice the clock and fill rate
 * for 1024x1024, a 512-word FIFO, two face slots, a 4-cell fill queue, the
 * registers of 16 frames, an 8-stage divider; the GP spends 24 + 6 per edge clocks per face;
 * all_units off, the host's SIMD forms on. */
#define CLOCKED(khz, fill) khz, 512, 2, 8, fill, 4, 16, 8, 4, 24, 6, 16, 16777215, 0, 1
static const alb_profile builtin[] = {
    {"a512", 512, 512, 0, 14, 24, 24, 8, 16, 12, ALB_BOUND_ALBATROS, true, CLOCKED(40000, 4)},
    {"a1024", 1024, 1024, 0, 15, 24, 24, 8, 16, 12, ALB_BOUND_ALBATROS, true, CLOCKED(80000, 8)},
    {"a1024x512", 1024, 512, 0, 15, 24, 24, 8, 16, 12, ALB_BOUND_ALBATROS, true, CLOCKED(60000, 8)},
    {"a256", 256, 256, 0, 13, 24, 24, 8, 16, 12, ALB_BOUND_ALBATROS, true, CLOCKED(20000, 4)},
    {"t32", 32, 32, 0, 10, 24, 24, 8, 16, 12, ALB_BOUND_ALBATROS, true, CLOCKED(10000, 4)},
    /* The member built for an iCE40 UP5K, the iCEBreaker (docs/fpga.md): the
     * narrowest widths the fields allow (but 16-bit depth, which the built-in
     * scene needs, and edge intercepts four bits below the pixel), a 16x16
     * screen, one edge unit, one sample a clock, a one-cell fill queue,
     * a 16-word FIFO, one face slot, two FRAME register sets, the board's
     * 12 MHz clock.  Even so the RTL is 1.7 times the part (docs/fpga.md). */
    {"up5k", 16, 16, 0, 7, 8, 16, 4, 8, 8, ALB_BOUND_ALBATROS, true,
     12000, 16, 1, 1, 1, 1, 2, 4, 4, 24, 6, 16, 4095, 0, 1},
};

static const char *const names[] = {"a512", "a1024", "a1024x512", "a256", "t32", "up5k", NULL};

const char *const *alb_profile_names(void) { return names; }

int alb_profile_lookup(const char *name, alb_profile *p)
{
    for (size_t i = 0; i < sizeof builtin / sizeof builtin[0]; i++) {
        if (strcmp(builtin[i].name, name) == 0) {
            *p = builtin[i];
            return 0;
        }
    }
    return -1;
}

const char *alb_bound_method_name(alb_bound_method m)
{
    switch (m) {
    case ALB_BOUND_NONE: return "none";
    case ALB_BOUND_ALBATROS: return "albatros";
    case ALB_BOUND_BOX: return "box";
    case ALB_BOUND_BISECTOR: return "bisector";
    }
    return "?";
}

int alb_bound_method_parse(const char *s, alb_bound_method *m)
{
    for (int i = ALB_BOUND_NONE; i <= ALB_BOUND_BISECTOR; i++) {
        if (strcmp(s, alb_bound_method_name((alb_bound_method)i)) == 0) {
            *m = (alb_bound_method)i;
            return 0;
        }
    }
    return -1;
}

/* Decimal digits only (strtoul would take a sign and spaces); -1 if not
 * such, -2 if above ALB_PROFILE_MAX_VALUE. */
static int parse_uint(const char *s, unsigned *out)
{
    char *end;
    errno = 0;
    if (*s < '0' || *s > '9')
        return -1;
    unsigned long v = strtoul(s, &end, 10);
    if (*end)
        return -1;
    if (errno == ERANGE || v > ALB_PROFILE_MAX_VALUE)
        return -2;
    *out = (unsigned)v;
    return 0;
}

typedef struct {
    const char *key;
    size_t offset;
} uint_field;

#define FIELD(f) {#f, offsetof(alb_profile, f)}
static const uint_field uint_fields[] = {
    FIELD(width), FIELD(height), {"aa", offsetof(alb_profile, aa_levels)},
    FIELD(edge_frac_bits), FIELD(coef_bits), FIELD(depth_bits),
    FIELD(colour_bits), FIELD(recip_bits), FIELD(shade_frac_bits), FIELD(clock_khz),
    FIELD(fifo_depth), FIELD(face_slots), FIELD(edge_units), FIELD(fill_rate), FIELD(fill_queue),
    FIELD(frame_queue),
    FIELD(divider_latency), FIELD(shade_latency), FIELD(gp_face_cycles), FIELD(gp_edge_cycles),
    FIELD(gp_frame_cycles), FIELD(frame_faces), FIELD(all_units), FIELD(simd),
};

int alb_profile_set(alb_profile *p, const char *assignment, char *err, size_t errlen)
{
    const char *eq = strchr(assignment, '=');
    if (!eq) {
        snprintf(err, errlen, "'%s': expected key=value", assignment);
        return -1;
    }
    size_t klen = (size_t)(eq - assignment);
    const char *val = eq + 1;
    for (size_t i = 0; i < sizeof uint_fields / sizeof uint_fields[0]; i++) {
        if (strlen(uint_fields[i].key) == klen &&
            strncmp(uint_fields[i].key, assignment, klen) == 0) {
            unsigned v;
            int bad = parse_uint(val, &v);
            if (bad) {
                if (bad == -2)
                    snprintf(err, errlen, "'%s': out of range (at most %u)", assignment,
                             ALB_PROFILE_MAX_VALUE);
                else
                    snprintf(err, errlen, "'%s': expected a non-negative integer", assignment);
                return -1;
            }
            *(unsigned *)((char *)p + uint_fields[i].offset) = v;
            return 0;
        }
    }
    if (klen == 5 && strncmp(assignment, "bound", 5) == 0) {
        if (alb_bound_method_parse(val, &p->bound)) {
            snprintf(err, errlen, "'%s': expected none, albatros, box or bisector", assignment);
            return -1;
        }
        return 0;
    }
    if (klen == 8 && strncmp(assignment, "backface", 8) == 0) {
        if (strcmp(val, "0") && strcmp(val, "1")) {
            snprintf(err, errlen, "'%s': expected 0 or 1", assignment);
            return -1;
        }
        p->cull_backfaces = val[0] == '1';
        return 0;
    }
    char known[600] = "";
    for (size_t i = 0; i < sizeof uint_fields / sizeof uint_fields[0]; i++)
        snprintf(known + strlen(known), sizeof known - strlen(known), " %s", uint_fields[i].key);
    snprintf(err, errlen, "'%.*s': unknown profile key (known:%s bound backface)", (int)klen,
             assignment, known);
    return -1;
}

unsigned alb_profile_levels(const alb_profile *p)
{
    unsigned w = fix_log2(p->width), h = fix_log2(p->height);
    return (w > h ? w : h) + p->aa_levels;
}

unsigned alb_profile_sample_shift(const alb_profile *p) { return alb_profile_levels(p); }

int alb_profile_check(const alb_profile *p, char *err, size_t errlen)
{
#define BAD(...) do { snprintf(err, errlen, __VA_ARGS__); return -1; } while (0)
    if (!fix_is_pow2(p->width) || !fix_is_pow2(p->height) || p->width < 2 ||
        p->height < 2 || p->width > ALB_PROFILE_MAX_SIDE || p->height > ALB_PROFILE_MAX_SIDE)
        BAD("screen %ux%u: width and height must be powers of two in 2..%d",
            p->width, p->height, ALB_PROFILE_MAX_SIDE);
    if (p->aa_levels > 3)
        BAD("aa=%u: at most 3 anti-aliasing levels (64 samples per pixel)", p->aa_levels);
    if (p->edge_frac_bits < EDGE_FRAC_MIN || p->edge_frac_bits > EDGE_FRAC_MAX)
        BAD("edge_frac_bits=%u: must be in %d..%d", p->edge_frac_bits,
            EDGE_FRAC_MIN, EDGE_FRAC_MAX);
    if (p->coef_bits < COEF_BITS_MIN || p->coef_bits > COEF_BITS_MAX)
        BAD("coef_bits=%u: must be in %d..%d", p->coef_bits, COEF_BITS_MIN, COEF_BITS_MAX);
    if (p->depth_bits < 8 || p->depth_bits > 32)
        BAD("depth_bits=%u: must be in 8..32", p->depth_bits);
    if (p->colour_bits < 4 || p->colour_bits > 16)
        BAD("colour_bits=%u: must be in 4..16", p->colour_bits);
    if (p->recip_bits < 8 || p->recip_bits > 24)
        BAD("recip_bits=%u: must be in 8..24", p->recip_bits);
    if (p->shade_frac_bits < 8 || p->shade_frac_bits > 16)
        BAD("shade_frac_bits=%u: must be in 8..16", p->shade_frac_bits);
    /* The edge set-up scales by 2^(F + 1 + lh - lw) and 2^(F + 1 + lw - lh). */
    if (fix_log2(p->width) > fix_log2(p->height) + p->edge_frac_bits + 1 ||
        fix_log2(p->height) > fix_log2(p->width) + p->edge_frac_bits + 1)
        BAD("screen %ux%u is too elongated for edge_frac_bits=%u", p->width, p->height,
            p->edge_frac_bits);
    /* A form evaluated at a sample is below 2^(coef_bits + levels + 1); times a
     * reciprocal of recip_bits + 1 bits it must stay inside int64
     * (docs/number-formats.md §4): the sum plus 3 at most 63. */
    if (p->coef_bits + alb_profile_levels(p) + p->recip_bits > 60)
        BAD("coef_bits + levels + recip_bits = %u: must be at most 60 (levels = %u: log2 of "
            "the larger screen side plus aa), so that the VP's form-times-reciprocal "
            "products fit 64-bit integers", p->coef_bits + alb_profile_levels(p) + p->recip_bits,
            alb_profile_levels(p));
    if (p->clock_khz < 1 || p->clock_khz > 10000000)
        BAD("clock_khz=%u: must be in 1..10000000", p->clock_khz);
    if (p->fifo_depth < 1 || p->fifo_depth > (1u << 20))
        BAD("fifo_depth=%u: must be in 1..1048576 words", p->fifo_depth);
    if (p->face_slots < 1 || p->face_slots > 64)
        BAD("face_slots=%u: must be in 1..64", p->face_slots);
    if (p->edge_units < 1 || p->edge_units > 64)
        BAD("edge_units=%u: must be in 1..64", p->edge_units);
    if (p->fill_rate < 1 || p->fill_rate > 256)
        BAD("fill_rate=%u: must be in 1..256 samples per clock", p->fill_rate);
    if (p->fill_queue < 1 || p->fill_queue > 1024)
        BAD("fill_queue=%u: must be in 1..1024 cells", p->fill_queue);
    if (p->frame_queue < 1 || p->frame_queue > 1024)
        BAD("frame_queue=%u: must be in 1..1024 frames", p->frame_queue);
    if (p->divider_latency > 1000 || p->shade_latency > 1000 || p->gp_face_cycles > 1000000 ||
        p->gp_edge_cycles > 1000000 || p->gp_frame_cycles > 1000000)
        BAD("latencies must be at most 1000 (divider, shade) and 1000000 (GP)");
    if (p->frame_faces < 1 || p->frame_faces > 16777215)
        BAD("frame_faces=%u: must be in 1..16777215 (the 24-bit face count of FRAME_END)",
            p->frame_faces);
    if (p->all_units > 1)
        BAD("all_units=%u: must be 0 (the units a face uses) or 1 (every unit)", p->all_units);
    if (p->simd > 1)
        BAD("simd=%u: must be 1 (the host's fastest forms) or 0 (the plain ones)", p->simd);
    return 0;
#undef BAD
}

void alb_profile_describe(const alb_profile *p, char *buf, size_t len)
{
    snprintf(buf, len,
             "profile=%s\nwidth=%u\nheight=%u\naa=%u\nedge_frac_bits=%u\n"
             "coef_bits=%u\ndepth_bits=%u\ncolour_bits=%u\nrecip_bits=%u\n"
             "shade_frac_bits=%u\nbound=%s\nbackface=%d\nclock_khz=%u\nfifo_depth=%u\n"
             "face_slots=%u\nedge_units=%u\nfill_rate=%u\nfill_queue=%u\nframe_queue=%u\n"
             "divider_latency=%u\nshade_latency=%u\ngp_face_cycles=%u\ngp_edge_cycles=%u\n"
             "gp_frame_cycles=%u\nframe_faces=%u\nall_units=%u\nsimd=%u\n",
             p->name, p->width, p->height, p->aa_levels, p->edge_frac_bits,
             p->coef_bits, p->depth_bits, p->colour_bits, p->recip_bits,
             p->shade_frac_bits, alb_bound_method_name(p->bound), p->cull_backfaces, p->clock_khz,
             p->fifo_depth, p->face_slots, p->edge_units, p->fill_rate, p->fill_queue, p->frame_queue,
             p->divider_latency, p->shade_latency, p->gp_face_cycles, p->gp_edge_cycles,
             p->gp_frame_cycles, p->frame_faces, p->all_units, p->simd);
}

alb_err alb_profile_open(alb_profile *p, const char *name, const char *const *sets, alb_diag *d)
{
    char msg[256];
    if (alb_profile_lookup(name ? name : "a512", p))
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "unknown profile '%s'", name);
    for (size_t i = 0; sets && sets[i]; i++)
        if (alb_profile_set(p, sets[i], msg, sizeof msg))
            return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "%s", msg);
    if (alb_profile_check(p, msg, sizeof msg))
        return alb_diag_at(d, ALB_ERR_CONFIG, "", 0, 0, "profile %s: %s", p->name, msg);
    return ALB_OK;
}
