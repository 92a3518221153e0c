/* sweep.h — the stability and speed-against-accuracy sweeps of the classic
 * methods and the Albatros configurations over the stress families
 * (docs/stability.md).  Split into independent jobs (one per family, plus
 * the speed sweep) that write CSV; a report step reads the CSVs and writes
 * Markdown tables and gnuplot charts. */
#ifndef ALBATROS_SWEEP_H
#define ALBATROS_SWEEP_H

#include "albatros/profile.h"

#include <stdbool.h>
#include <stdio.h>

#define SWEEP_SEVERITIES 4

/* The families and their severities, in order of increasing severity. */
unsigned sweep_family_count(void);
const char *sweep_family(unsigned i);
const double *sweep_severities(unsigned i);

/* Where a job reports its progress: nowhere (f NULL); on a terminal (live:
 * one line redrawn per configuration); or in a log, as under make -j, GNU
 * parallel or Slurm (one line per severity, or per speed configuration). */
typedef struct {
    FILE *f;
    bool live;
} sweep_progress;

/* One family: every configuration at every severity, seeds 1..seeds;
 * CSV rows to out (with a header); the last column counts the seeds that
 * failed to render. */
int sweep_family_run(const char *family, const alb_profile *p, unsigned seeds, FILE *out,
                     const sweep_progress *progress);
/* Speed against accuracy: every configuration, the VP's three fidelities
 * and the exact reference itself on a fixed set of scenes; CSV rows to out. */
int sweep_speed_run(const alb_profile *p, FILE *out, const sweep_progress *progress);

/* Read the CSVs of dir and write stability.csv, stability.md and
 * stability.png there, and speed.md and speed.png if dir has a speed.csv
 * (*with_speed tells whether it had; charts by gnuplot, which must be
 * installed).  Returns 0, or -1 with a message on stderr. */
int sweep_report(const char *dir, bool *with_speed);

#endif
