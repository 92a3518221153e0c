/* dpi.c — the model through DPI-C (include/albatros/dpi.h): a handle wraps
 * an alb_model and the event a testbench is reading. */
#include "albatros/albatros.h"
#include "albatros/dpi.h"

#include <stdlib.h>
#include <string.h>

typedef struct {
    alb_model *m;
    alb_event cur;
    char error[800];
} dpi_model;

static _Thread_local char open_error[800];

const char *alb_dpi_open_error(void) { return open_error; }

void *alb_dpi_open(const char *profile, const char *sets, int producer, int events)
{
    open_error[0] = 0;
    dpi_model *h = calloc(1, sizeof *h);
    char *copy = strdup(sets ? sets : "");
    const char **list = calloc(strlen(copy) / 2 + 2, sizeof *list);
    if (!h || !copy || !list) {
        snprintf(open_error, sizeof open_error, "out of memory");
        free(h), free(copy), free(list);
        return NULL;
    }
    size_t n = 0;
    for (char *tok = strtok(copy, " \t,"); tok; tok = strtok(NULL, " \t,"))
        list[n++] = tok;
    alb_model_config c;
    alb_model_config_default(&c);
    c.producer = producer ? ALB_PRODUCER_EXTERNAL : ALB_PRODUCER_GP;
    c.events = (uint32_t)events & ALB_EV_ALL;
    c.name = "<dpi>";
    alb_diag d;
    if (alb_model_open(&h->m, profile, list, &c, &d)) {
        alb_diag_format(&d, open_error, sizeof open_error);
        free(h);
        h = NULL;
    }
    free(copy);
    free(list);
    return h;
}

void alb_dpi_close(void *p)
{
    dpi_model *h = p;
    if (h)
        alb_model_destroy(h->m);
    free(h);
}

static int failed(dpi_model *h)
{
    snprintf(h->error, sizeof h->error, "%s", alb_model_error(h->m));
    return -1;
}

int alb_dpi_push(void *p, unsigned int word)
{
    dpi_model *h = p;
    uint32_t w = word;
    if (alb_model_push(h->m, &w, 1))
        return 1;
    return alb_model_error(h->m)[0] ? failed(h) : 0;
}

int alb_dpi_push_file(void *p, const char *path)
{
    dpi_model *h = p;
    uint32_t *w = NULL;
    size_t n = 0;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_ws_read_file(path, &w, &n, &d)) {
        alb_diag_format(&d, h->error, sizeof h->error);
        return -1;
    }
    size_t k = alb_model_push(h->m, w, n);
    free(w);
    if (k != n)
        return alb_model_error(h->m)[0] ? failed(h) : (int)k;
    return (int)n;
}

int alb_dpi_step(void *p, int cycles)
{
    dpi_model *h = p;
    return alb_model_step(h->m, cycles > 0 ? (uint64_t)cycles : 0) ? failed(h) : 0;
}

int alb_dpi_run(void *p, int until, long long max_cycles)
{
    dpi_model *h = p;
    alb_stop why;
    if (alb_model_run(h->m, (uint32_t)until, max_cycles > 0 ? (uint64_t)max_cycles : 0, &why))
        return failed(h);
    return (int)why;
}

int alb_dpi_next(void *p)
{
    dpi_model *h = p;
    if (!alb_model_event(h->m, &h->cur))
        return 0;
    return (int)h->cur.kind;
}

long long alb_dpi_field(void *p, int field)
{
    const alb_event *e = &((dpi_model *)p)->cur;
    switch (field) {
    case ALB_DPI_CYCLE: return (long long)e->cycle;
    case ALB_DPI_KIND: return e->kind;
    case ALB_DPI_FACE: return e->face;
    case ALB_DPI_INDEX: return (long long)e->index;
    case ALB_DPI_WORD: return e->word;
    case ALB_DPI_SLOT: return e->slot;
    case ALB_DPI_EDGES: return e->edges;
    case ALB_DPI_X: return e->x;
    case ALB_DPI_Y: return e->y;
    case ALB_DPI_WL: return e->wl;
    case ALB_DPI_HL: return e->hl;
    case ALB_DPI_LEVEL: return e->level;
    case ALB_DPI_RESULT: return e->result;
    case ALB_DPI_DEPTH: return e->depth;
    case ALB_DPI_R: return e->rgb[0];
    case ALB_DPI_G: return e->rgb[1];
    case ALB_DPI_B: return e->rgb[2];
    case ALB_DPI_NUMBER: return e->number;
    case ALB_DPI_CYCLES: return (long long)e->cycles;
    case ALB_DPI_CRC: return e->crc;
    }
    return 0;
}

long long alb_dpi_cycle(void *p) { return (long long)alb_model_cycle(((dpi_model *)p)->m); }

int alb_dpi_done(void *p) { return alb_model_done(((dpi_model *)p)->m); }

const char *alb_dpi_error(void *p) { return ((dpi_model *)p)->error; }
