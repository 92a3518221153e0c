/* listing.c — the firmware image's map from its .ihx, its .map and the
 * relocated listings (listing.h).  A listing line is fixed-column:
 *
 *       000092 85 81 0F         [24]  282 	mov	_bp,sp
 *       000090                        272 _xcopy:
 *
 * address in columns 6..11, the bytes from column 13, sdas's cycle count in
 * brackets (12-clock cycles × 12) for an instruction, the source line
 * number ending in column 38, the source from column 39. */
#include "listing.h"
#include "i8051.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define COL_ADDR   6
#define COL_BYTES  13
#define COL_NUMBER 34   /* the bytes and cycle columns end before it */
#define COL_SOURCE 39

static int fail(listing_t *l, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int fail(listing_t *l, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(l->error, sizeof l->error, fmt, ap);
    va_end(ap);
    return -1;
}

static int hexval(int c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    c = toupper(c);
    return c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

static long hexfield(const char *p, int n)
{
    long v = 0;
    for (int i = 0; i < n; i++) {
        int d = hexval((unsigned char)p[i]);
        if (d < 0)
            return -1;
        v = v * 16 + d;
    }
    return v;
}

static int add_label(listing_t *l, const char *name, unsigned addr, bool code)
{
    listing_label *p = realloc(l->labels, (l->nlabels + 1) * sizeof *p);
    if (!p)
        return fail(l, "out of memory");
    l->labels = p;
    snprintf(p[l->nlabels].name, sizeof p[0].name, "%s", name);
    p[l->nlabels].addr = addr;
    p[l->nlabels].code = code;
    l->nlabels++;
    return 0;
}

static int load_ihx(listing_t *l, const char *path)
{
    FILE *f = fopen(path, "r");
    char line[600];
    int lineno = 0;

    if (!f)
        return fail(l, "%s: %s", path, strerror(errno));
    while (fgets(line, sizeof line, f)) {
        lineno++;
        if (line[0] != ':')
            continue;
        long n = hexfield(line + 1, 2), addr = hexfield(line + 3, 4), type = hexfield(line + 7, 2);
        if (n < 0 || addr < 0 || type < 0) {
            fclose(f);
            return fail(l, "%s:%d: not an Intel-hex record", path, lineno);
        }
        if (type == 1)
            break;
        if (type != 0)
            continue;
        for (long i = 0; i < n; i++) {
            long b = hexfield(line + 9 + 2 * i, 2);
            if (b < 0 || addr + i >= (long)LISTING_CODE) {
                fclose(f);
                return fail(l, "%s:%d: bad data byte %ld", path, lineno, i);
            }
            l->rom[addr + i] = (uint8_t)b;
            l->loaded[addr + i] = true;
        }
    }
    fclose(f);
    return 0;
}

/* The start of the CONST area from the linker's map: code ends there. */
static int load_map(listing_t *l, const char *ihx)
{
    char path[4096], line[512];
    size_t n = strlen(ihx);

    if (n < 4 || n + 1 > sizeof path || strcmp(ihx + n - 4, ".ihx"))
        return fail(l, "%s: expected a .ihx file beside its .map", ihx);
    memcpy(path, ihx, n - 4);
    strcpy(path + n - 4, ".map");
    FILE *f = fopen(path, "r");
    if (!f)
        return fail(l, "%s: %s", path, strerror(errno));
    l->code_end = 0;
    long pos = ftell(f);
    for (int pass = 0; pass < 2; pass++) {   /* the CONST start, then the code symbols */
        fseek(f, pos, SEEK_SET);
        while (fgets(line, sizeof line, f)) {
            unsigned v;
            char name[64];
            if (sscanf(line, " C: %x %63s", &v, name) != 2)
                continue;
            if (pass == 0 && !strcmp(name, "s_CONST"))
                l->code_end = v;
            /* library routines have no listing: their names from here */
            if (pass == 1 && v < l->code_end && name[0] == '_' && add_label(l, name, v, true)) {
                fclose(f);
                return -1;
            }
        }
        if (!l->code_end)
            break;
    }
    fclose(f);
    return l->code_end ? 0 : fail(l, "%s: no s_CONST symbol", path);
}

/* One listing line: an instruction, data, a label, or nothing to us. */
static int parse_line(listing_t *l, const char *line, bool *covered)
{
    size_t len = strlen(line);
    if (len < COL_SOURCE || line[COL_ADDR - 1] != ' ')
        return 0;
    long addr = hexfield(line + COL_ADDR, 6);
    if (addr < 0 || addr >= (long)LISTING_CODE || line[COL_ADDR + 6] != ' ')
        return 0;
    unsigned nbytes = 0, cycles = 0;
    for (const char *p = line + COL_BYTES; p < line + COL_NUMBER;) {
        while (p < line + COL_NUMBER && *p == ' ')
            p++;
        if (p >= line + COL_NUMBER)
            break;
        if (*p == '[') {
            cycles = (unsigned)strtoul(p + 1, NULL, 10);
            break;
        }
        if (hexval((unsigned char)p[0]) < 0 || hexval((unsigned char)p[1]) < 0 || p[2] != ' ')
            break;
        nbytes++;
        p += 3;
    }
    for (unsigned i = 0; i < nbytes && addr + i < LISTING_CODE; i++)
        covered[addr + i] = true;
    if (nbytes && cycles) {
        l->insn[addr] = true;
        l->listed[addr] = (uint8_t)(cycles / 12);
        return 0;
    }
    if (nbytes)
        return 0;   /* data */
    const char *src = line + COL_SOURCE;
    while (*src == ' ' || *src == '\t')
        src++;
    size_t k = 0;
    while (isalnum((unsigned char)src[k]) || src[k] == '_')
        k++;
    if (k && k < 48 && src[k] == ':' && !isdigit((unsigned char)src[0])) {
        char name[48];
        memcpy(name, src, k);
        name[k] = 0;
        return add_label(l, name, (unsigned)addr, (unsigned)addr < l->code_end);
    }
    return 0;
}

static int load_rst(listing_t *l, const char *path, bool *covered)
{
    FILE *f = fopen(path, "r");
    char line[1024];
    if (!f)
        return fail(l, "%s: %s", path, strerror(errno));
    while (fgets(line, sizeof line, f))
        if (parse_line(l, line, covered)) {
            fclose(f);
            return -1;
        }
    fclose(f);
    return 0;
}

/* Code the listings do not cover: the startup and library routines,
 * decoded one instruction after another from the start of each gap. */
static void decode_gaps(listing_t *l, const bool *covered)
{
    unsigned a = 0;
    while (a < l->code_end) {
        if (covered[a] || !l->loaded[a]) {
            a++;
            continue;
        }
        while (a < l->code_end && !covered[a] && l->loaded[a]) {
            l->insn[a] = true;
            a += i8051_opcode(l->rom[a]).len;
        }
    }
}

static int by_addr(const void *a, const void *b)
{
    const listing_label *x = a, *y = b;
    return x->addr < y->addr ? -1 : x->addr > y->addr;
}

int listing_load(listing_t *l, const char *ihx, const char *dir)
{
    memset(l, 0, sizeof *l);
    bool *covered = calloc(LISTING_CODE, sizeof *covered);
    if (!covered)
        return fail(l, "out of memory");
    int rc = load_ihx(l, ihx);
    if (!rc)
        rc = load_map(l, ihx);
    DIR *d = rc ? NULL : opendir(dir);
    if (!rc && !d)
        rc = fail(l, "%s: %s", dir, strerror(errno));
    int files = 0;
    struct dirent *e;
    while (!rc && d && (e = readdir(d)) != NULL) {
        size_t n = strlen(e->d_name);
        if (n < 5 || strcmp(e->d_name + n - 4, ".rst"))
            continue;
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        rc = load_rst(l, path, covered);
        files++;
    }
    if (d)
        closedir(d);
    if (!rc && !files)
        rc = fail(l, "%s: no .rst listings (make firmware writes them)", dir);
    if (!rc) {
        decode_gaps(l, covered);
        qsort(l->labels, l->nlabels, sizeof *l->labels, by_addr);
    }
    free(covered);
    return rc;
}

void listing_free(listing_t *l)
{
    free(l->labels);
    l->labels = NULL;
    l->nlabels = 0;
}

long listing_addr(const listing_t *l, const char *name)
{
    for (size_t i = 0; i < l->nlabels; i++)
        if (!strcmp(l->labels[i].name, name))
            return (long)l->labels[i].addr;
    return -1;
}

const listing_label *listing_function(const listing_t *l, unsigned addr)
{
    const listing_label *best = NULL;
    for (size_t i = 0; i < l->nlabels && l->labels[i].addr <= addr; i++)
        if (l->labels[i].code)
            best = &l->labels[i];
    return best;
}
