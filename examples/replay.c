/* replay.c — a golden vector through the model, checked frame by frame:
 *   cc replay.c $(pkg-config --cflags --libs albatros) -o replay
 *   ./replay PROFILE VECTOR/expected.stream VECTOR/expected.frames
 * (docs/cosim.md, "A C testbench in 30 lines"). */
#include <albatros/albatros.h>
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    uint32_t *w;
    size_t n;
    alb_diag d;
    alb_model *m;
    alb_model_config c;
    if (argc != 4 || alb_ws_read_file(argv[2], &w, &n, &d))
        return fprintf(stderr, "usage: replay PROFILE STREAM FRAMES\n"), 2;
    alb_model_config_default(&c);   /* cycle model, GP stage, frame events */
    if (alb_model_open(&m, argv[1], NULL, &c, &d))
        return fprintf(stderr, "%s\n", d.msg), 2;
    alb_model_push(m, w, n);
    FILE *want = fopen(argv[3], "r");
    unsigned number, bad = 0, frames = 0;
    unsigned long long cycles;
    unsigned crc;
    alb_event e;
    while (want && !alb_model_done(m)) {
        if (alb_model_run(m, ALB_EV_FRAME, UINT64_MAX, NULL))
            return fprintf(stderr, "%s\n", alb_model_error(m)), 1;
        while (alb_model_event(m, &e)) {
            int ok = fscanf(want, "%u %llu %x", &number, &cycles, &crc) == 3 &&
                     e.number == number && e.cycles == cycles && e.crc == crc;
            printf("frame %u: %llu cycles, CRC %08x%s\n", e.number,
                   (unsigned long long)e.cycles, e.crc, ok ? "" : "  MISMATCH");
            bad += !ok, frames++;
        }
    }
    alb_model_destroy(m);
    free(w);
    return bad || !frames;
}
